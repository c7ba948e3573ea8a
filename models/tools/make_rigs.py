#!/usr/bin/env python3
"""Write the shipped rigs in models/rigs/ (run once; the outputs are committed).

pinhead.json  the paper's 18-bone rig, converted from ../shared/data/pinhead_rig.json (read out of
              the paper's own Blender file): bone names from `suggested_name`, rest frames kept,
              limits only on the axes whose Blender `ik_limit` flag is set.
elbow.json    the two-bone elbow of the paper's Fig 6: the interior angle is limited to 90..180 deg,
              i.e. the forearm bends 0..90 deg from straight, about its local x axis (toward +Y).
chain3.json   three free bones of length 1 along +Z.
hand.json     a wrist with five fingers of three tightly limited phalanges each (the paper's
              Sec. 5 failure case): knuckles +-10 deg (x) and +-5 deg (y, z), the other phalanges
              0..10 deg about x and locked about y and z.
All use the original code's mass_per_length 1 and cylinder radius 0.5 unless said otherwise.
"""
import json
import math
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
RIGS = os.path.join(HERE, "..", "rigs")


def write(name, doc):
    path = os.path.join(RIGS, name)
    text = json.dumps(doc, indent=1)
    # keep number arrays on one line: [x, y, z]
    text = re.sub(r"\[\s*([-0-9.e,\s]+?)\s*\]", lambda m: "[" + ", ".join(m.group(1).split()).replace(",,", ",") + "]", text)
    with open(path, "w") as f:
        f.write(text + "\n")
    print("wrote", os.path.relpath(path))


def pinhead(source):
    src = json.load(open(source))
    by_blender = {b["blender_name"]: b["suggested_name"] for b in src["bones"]}
    bones = []
    for b in src["bones"]:
        limits = {}
        for k, axis in enumerate("xyz"):
            if b["ik_limit_xyz"][k]:
                limits[axis] = [b["ik_min_deg_xyz"][k], b["ik_max_deg_xyz"][k]]
        bone = {
            "name": b["suggested_name"],
            "parent": by_blender[b["parent"]] if b["parent"] else None,
            "head": b["head"],
            "tail": b["tail"],
            "rest_frame": b["rest_frame_columns_xyz"],
            "mass_per_length": b["mass_per_length"],
        }
        if limits:
            bone["limits_deg"] = limits
        bone["comment"] = "Blender bone " + b["blender_name"]
        bones.append(bone)
    return {
        "name": "pinhead",
        "comment": "The PhysIK paper's 18-bone test rig (Fig 4), converted by models/tools/make_rigs.py "
                   "from shared/data/pinhead_rig.json (docs/pinhead.blend of the original repository). "
                   "World Z up, character faces -Y, .L is +X. Knees/elbows 0..160 deg as in the file "
                   "(the paper's text says 0..120).",
        "defaults": {"mass_per_length": 1.0, "radius": 0.5},
        "bones": bones,
    }


def elbow():
    return {
        "name": "elbow",
        "comment": "Paper Fig 6: an elbow whose interior angle is limited to 90..180 deg. The forearm "
                   "bends 0..90 deg from straight about its local x (negative x turns it toward +Y).",
        "defaults": {"mass_per_length": 1.0, "radius": 0.5},
        "bones": [
            {"name": "upper_arm", "parent": None, "head": [0, 0, 0], "tail": [0, 0, 2]},
            {"name": "forearm", "parent": "upper_arm", "head": [0, 0, 2], "tail": [0, 0, 4],
             "limits_deg": {"x": [-90, 0], "y": [0, 0], "z": [0, 0]}},
        ],
    }


def chain3():
    return {
        "name": "chain3",
        "comment": "Three free bones of length 1 along +Z.",
        "defaults": {"mass_per_length": 1.0, "radius": 0.5},
        "bones": [
            {"name": "b0", "parent": None, "head": [0, 0, 0], "tail": [0, 0, 1]},
            {"name": "b1", "parent": "b0", "head": [0, 0, 1], "tail": [0, 0, 2]},
            {"name": "b2", "parent": "b1", "head": [0, 0, 2], "tail": [0, 0, 3]},
        ],
    }


def hand():
    bones = [{"name": "wrist", "parent": None, "head": [0, 0, 0], "tail": [0, 0, 1.0]}]
    names = ["thumb", "index", "middle", "ring", "pinky"]
    lengths = [0.45, 0.3, 0.25]
    for f, finger in enumerate(names):
        spread = math.radians(-40 + 20 * f)  # fan in the x-z plane
        d = (math.sin(spread), 0.0, math.cos(spread))
        p = [0.0, 0.0, 1.0]
        parent = "wrist"
        for k, length in enumerate(lengths):
            q = [p[i] + length * d[i] for i in range(3)]
            name = "%s.%d" % (finger, k + 1)
            limits = ({"x": [-10, 10], "y": [-5, 5], "z": [-5, 5]} if k == 0
                      else {"x": [0, 10], "y": [0, 0], "z": [0, 0]})
            bones.append({"name": name, "parent": parent, "head": [round(v, 6) for v in p],
                          "tail": [round(v, 6) for v in q], "limits_deg": limits})
            p, parent = q, name
    return {
        "name": "hand",
        "comment": "Paper Sec. 5 failure case: a wrist (root) with five fingers of three tightly "
                   "limited phalanges each.",
        "defaults": {"mass_per_length": 1.0, "radius": 0.5},
        "bones": bones,
    }


if __name__ == "__main__":
    shared = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "..", "..", "..", "shared")
    write("pinhead.json", pinhead(os.path.join(shared, "data", "pinhead_rig.json")))
    write("elbow.json", elbow())
    write("chain3.json", chain3())
    write("hand.json", hand())
