"""Rig files into and out of the add-on, read and checked by the engine's own reader when the
`physik` module can be imported (engine.py: physik.Rig.load, physik.Rig.from_dict: the CLI's
checks, canonical rig and messages), else by rig_format.py (held to the engine by
blender/tests/test_rig_format.py and blender/tests/test_round_trip.py).

The canonical rig gives the armature its geometry; the file's own dict comes along so that the
armature keeps the file's values and form (rig_record.py) and export gives them back.
"""
import json

from . import engine, rig_format
from .rig_format import InputError


def canonical(doc, source):
    """The canonical rig of a dict in the rig file format; InputError names what is wrong."""
    try:
        return engine.canonical_rig(doc, source)
    except engine.EngineUnavailable:
        return rig_format.parse_rig(doc, source)


def load(path):
    """(the file's own dict, its canonical rig) of a rig file; InputError names what is
    wrong."""
    try:
        rig = engine.load_rig(path)
    except engine.EngineUnavailable:
        doc = rig_format.load_json(path)
        return doc, rig_format.parse_rig(doc, path)
    return rig_format.load_json(path), rig


def save(doc, path, source):
    """Write a rig dict to `path` after the same checks as load (never a file the engine
    refuses); doubles are written in full (repr), so they read back bit for bit."""
    canonical(doc, source)
    try:
        with open(path, "w", encoding="utf-8") as f:
            json.dump(doc, f, indent=1)
            f.write("\n")
    except OSError as e:
        raise InputError(path, "", "", "cannot write file (%s)" % (e.strerror or e)) from None
