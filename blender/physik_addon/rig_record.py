"""What a rig file said, kept beside the armature built from it, so that export gives the file's
own values back (no Blender here; armature_io.py reads and writes the custom properties).

Why: Blender stores bone heads, tails, rolls and IK limits in single precision. A rig file's
doubles come back from an armature ~1e-7 of their size off (160 deg as 159.9999953), and the
engine's state hash of a run on the round-tripped rig differs from the original's. So at import
each pose bone keeps, as JSON text (doubles written in full, read back bit for bit) in its custom
property `physik_file`:
    "file":    the file's own head, tail, its frame in the file's form (rest_frame, roll_deg or
               neither) and its limits_deg (or none);
    "blender": what the add-on read back from the armature right after building it: world head,
               tail, rest frame (read in object mode and in edit mode, which Blender computes
               differently: 6e-7 apart on the MuJoCo humanoid, 3e-5 on a 200-bone chain) and
               limits, all in Blender's single precision.
On reading the armature (export, and the rig of every Solve, Simulate and Bake), each of head,
tail, frame and limits whose Blender value still equals the recorded one is taken from "file";
a field changed in Blender (a bone moved or rolled, a limit edited, the object moved) is taken
from Blender. "Equals" is exact for heads, tails and limits, which Blender stores and never
recomputes; a frame counts as unchanged within FRAME_TOL, because object mode's frames are
chained from the parents' and Blender recomputes every descendant's when a bone is rolled
(measured: 3e-7 on pinhead, 5e-7 on the MuJoCo humanoid, 1e-5 on a 200-bone chain). A roll
edit smaller than FRAME_TOL rad (6e-5 deg) is not seen; a descendant recomputed by more than
it gets Blender's single-precision frame, the same rig to 1e-5.

Masses, radii, moments, defaults and free text are custom properties holding doubles and
strings, read as they are; the rig's record (armature data, `physik_file`) keeps which
top-level fields the file gave, any free text that is not a string, and the file's
collision_exclude (the pairs whose bones are still there come back).
"""
import json

from .rig_format import InputError

PROP = "physik_file"
FREE_TEXT = ("comment", "source", "units")
FRAME_TOL = 1e-6  # axis components: ~8 float32 ulps of a unit vector


def bone_record(doc_bone, object_reading, edit_frame):
    """The JSON text for a bone: the file's own fields (doc_bone, as given) and Blender's values
    just after building (object_reading: a bone dict of armature_io's reading; edit_frame: its
    rest frame read in edit mode)."""
    file_part = {k: doc_bone[k] for k in ("head", "tail", "rest_frame", "roll_deg", "limits_deg")
                 if k in doc_bone}
    if "comment" in doc_bone and not isinstance(doc_bone["comment"], str):
        file_part["comment"] = doc_bone["comment"]
    blender = {"head": object_reading["head"], "tail": object_reading["tail"],
               "frame": object_reading["rest_frame"], "frame_edit": edit_frame,
               "limits": object_reading.get("limits_deg", {})}
    return json.dumps({"file": file_part, "blender": blender})


def _load(text, source, element):
    try:
        record = json.loads(text)
        return record["file"], record["blender"]
    except (TypeError, ValueError, KeyError) as e:
        raise InputError(source, element, PROP, "not the add-on's record of the rig file (%s); "
                         "delete the property to use Blender's values" % e) from None


def merge(bone, text, edit_mode, source, element):
    """The bone as the rig file had it where Blender's values are the recorded ones.

    bone: armature_io's reading (name, parent, head, tail, rest_frame, limits_deg?, masses ...);
    text: the bone's record (bone_record). Returns a new dict; the file's form of the frame
    (rest_frame, roll_deg or none) and of the limits (none, or as written) is kept."""
    file_part, blender = _load(text, source, element)
    out = {k: v for k, v in bone.items() if k not in ("rest_frame", "limits_deg")}
    for key in ("head", "tail"):
        if bone[key] == blender.get(key) and key in file_part:
            out[key] = file_part[key]
    out.update(_frame(bone, file_part, blender, "frame_edit" if edit_mode else "frame"))
    limits = bone.get("limits_deg", {})
    if limits != blender.get("limits"):
        if limits:
            out["limits_deg"] = limits
    elif "limits_deg" in file_part:
        out["limits_deg"] = file_part["limits_deg"]
    if "comment" not in out and "comment" in file_part:
        out["comment"] = file_part["comment"]
    return out


def _frame(bone, file_part, blender, key):
    recorded = blender.get(key)
    if recorded is None or max(abs(a - b) for u, v in zip(bone["rest_frame"], recorded)
                               for a, b in zip(u, v)) > FRAME_TOL:
        return {"rest_frame": bone["rest_frame"]}
    return {k: file_part[k] for k in ("rest_frame", "roll_deg") if k in file_part}


def rig_record(doc):
    """The JSON text for the rig: which top-level fields the file gave, its free text that is not
    a string (a string is a custom property the user can edit), its collision_exclude pairs and
    its source_skeleton (Blender has no place for them)."""
    extra = {k: doc[k] for k in FREE_TEXT if k in doc and not isinstance(doc[k], str)}
    for key in ("collision_exclude", "source_skeleton"):
        if key in doc:
            extra[key] = doc[key]
    return json.dumps({"keys": sorted(k for k in doc if k != "bones"), "extra": extra})


def load_rig_record(text, source):
    """(keys, extra) of a rig record."""
    try:
        record = json.loads(text)
        return set(record["keys"]), dict(record["extra"])
    except (TypeError, ValueError, KeyError) as e:
        raise InputError(source, "armature data", PROP, "not the add-on's record of the rig "
                         "file (%s); delete the property to use Blender's values" % e) from None
