#!/usr/bin/env python3
"""A seeded mutation fuzzer over the real `physik` binary.

Seeds: the shipped rigs and scenes, BVH/qBVH files and MJCF written by the binary itself
(`rig to-bvh`, `export-mjcf`), and joint-limit files made from each rig's bone names. Generated
seeds (gen_* below) cover the input kinds the shipped files do not: scenes with bone targets
(orientation targets, aims, pins) and the command line's bone-target options; rigs with welds,
pinned, fixed and free roots, and collision_exclude, and scenes on them with self-collision and
their own exclusions; clips (a BVH clip and the rig `rig from-bvh` makes of its skeleton) with
`follow`, a scene whose initial pose is a clip's frame, and write-back onto the source skeleton
(`follow --bvh`, `simulate --bvh`, `solve --bvh`, `rig to-bvh`). Each case mutates one seed
(bytes, numbers, JSON values, BVH structure; for a clip, the clip or its rig) and runs one command
on it: `rig info`, `simulate` (short runs), `solve`, `equilibrium`, `export-mjcf`, `rig
from-bvh`, `rig to-bvh`, `bvh convert`, `rig limits`, `follow`. Every case must hold:

  no crash (signal), no hang (timeout), exit 0, 2 or 3 only (and 4 from `solve`: a solve short of
  its tolerance, never 3 from `solve --solver physik`, the equilibrium solve, or KDL's; and from
  `equilibrium`: Ceres stopped short), an exit-2 message that names the file at fault, and no
  non-finite number (nan, inf, or null where the seed's output has a number) in the files or JSON
  an exit-0 run (or an exit-4 solve or equilibrium) writes.

A case that breaks a rule is a failure (its input is kept with --keep).
The corpus (tests/fuzz/corpus) holds the robustness reproducers as regression cases with their
expected exit code and message (argv may name the case's folder, @DIR@, and a case may ask that a
viewer page's decoded frames be finite, "finite_page"). Counts by outcome are printed at the end.

usage: fuzz_cli.py PHYSIK SOURCE_DIR [--cases N] [--seed S] [--jobs J] [--timeout T]
"""
import argparse
import collections
import concurrent.futures
import json
import math
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile

NUMBER_REPLACEMENTS = ["0", "-0", "1", "-1", "0.5", "1e308", "-1e308", "1e-308", "4.9e-324",
                       "1e155", "1e200", "-1e200", "1e999", "nan", "NaN", "inf", "-inf",
                       "Infinity", "2147483647", "2147483648", "-2147483649",
                       "9223372036854775808", "1e9", "1e10", "3.0e", "0x10", "1e-30", "\"1\"",
                       "null", "true", "[]", "{}"]
ODD_BYTES = [b"\x00", b"\x0b", b"\x0c", b"\xff", b"\xc3", b"\xe2\x82", b'"', b"<", b"&", b"{",
             b"}", b",", b"\n", b"\r", b"\t", b" ", b"\\", b"\xef\xbb\xbf"]
ODD_NAMES = ["a\"b", "x<y", "a&b", "tab\tname", "new\nline", "\u00e9t\u00e9", "\u2603",
             "", " ", "a,b", "{", "}", "x" * 300, "end", "ROOT", "\x7f"]


# ---------------------------------------------------------------- seeds

def run(cmd, timeout, cwd=None, address_space=None):
    """(returncode or 'timeout', stdout, stderr) as text; returncode < 0 is a signal.
    address_space: a cap on the process's address space (bytes, RLIMIT_AS), as `ulimit -v`."""
    def cap():
        import resource
        resource.setrlimit(resource.RLIMIT_AS, (int(address_space), int(address_space)))
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=timeout,
                           cwd=cwd, preexec_fn=cap if address_space else None)
        return p.returncode, p.stdout.decode("utf-8", "replace"), p.stderr.decode("utf-8", "replace")
    except subprocess.TimeoutExpired as e:
        return "timeout", (e.stdout or b"").decode("utf-8", "replace"), (e.stderr or b"").decode("utf-8", "replace")


def make_seeds(physik, src, work):
    """{kind: [(name, bytes)]} for kinds rig, scene, bvh, limits, mjcf."""
    seeds = collections.defaultdict(list)
    rigs_dir = os.path.join(src, "models", "rigs")
    scenes_dir = os.path.join(src, "models", "scenes")
    for f in sorted(os.listdir(rigs_dir)):
        path = os.path.join(rigs_dir, f)
        data = open(path, "rb").read()
        seeds["rig"].append((f, data))
        stem = f[:-5]
        for ext, extra in ((".bvh", []), (".qbvh", []), ("_xyz.bvh", ["--order", "XYZ"])):
            out = os.path.join(work, "seed_" + stem + ext)
            rc, _, err = run([physik, "rig", "to-bvh", path, "--out", out] + extra, 60)
            if rc == 0:
                seeds["bvh"].append((os.path.basename(out), open(out, "rb").read()))
        out = os.path.join(work, "seed_" + stem + ".xml")
        if run([physik, "export-mjcf", path, "--out", out], 60)[0] == 0:
            seeds["mjcf"].append((os.path.basename(out), open(out, "rb").read()))
        doc = json.loads(data)
        names = [b["name"] for b in doc["bones"]]
        lim = {"limits_deg": {}}
        for i, n in enumerate(names):
            if i % 3 == 0:
                lim["limits_deg"][n] = {"x": [-30, 60], "z": [-10, 10]}
            elif i % 3 == 1:
                lim["limits_deg"][n] = "locked" if i % 2 else "free"
        seeds["limits"].append((stem + "_limits.json", json.dumps(lim, indent=1).encode(),
                                ) + (stem,))
    for f in sorted(os.listdir(scenes_dir)):
        seeds["scene"].append((f, open(os.path.join(scenes_dir, f), "rb").read()))
    return seeds


# ---------------------------------------------------------------- generated seeds

def gen_welded_rig(root):
    """A small figure whose hips' joint holds a spine and two pelvis halves welded to it, a
    chest welded to its parent, and the root `root` (pinned: a hinge, two locked axes); its
    thighs never collide (collision_exclude)."""
    def bone(name, parent, head, tail, **extra):
        return dict({"name": name, "parent": parent, "head": head, "tail": tail}, **extra)
    bones = [bone("hips", None, [0, 0, 1], [0, 0, 1.1]),
             bone("spine", "hips", [0, 0, 1.1], [0, 0, 1.6]),
             bone("pelvis.L", "hips", [0, 0, 1.1], [0.15, 0, 1.05], weld="spine"),
             bone("pelvis.R", "hips", [0, 0, 1.1], [-0.15, 0, 1.05], weld="spine"),
             bone("chest", "spine", [0, 0, 1.6], [0, 0, 1.9], weld="spine"),
             bone("arm.L", "chest", [0, 0, 1.9], [0.5, 0, 1.9], limits_deg={"x": [-90, 90]}),
             bone("arm.R", "chest", [0, 0, 1.9], [-0.5, 0, 1.9]),
             bone("thigh.L", "pelvis.L", [0.15, 0, 1.05], [0.15, 0, 0.55]),
             bone("shin.L", "thigh.L", [0.15, 0, 0.55], [0.15, 0, 0.1],
                  limits_deg={"x": [0, 120], "y": [0, 0], "z": [0, 0]}),
             bone("thigh.R", "pelvis.R", [-0.15, 0, 1.05], [-0.15, 0, 0.55]),
             bone("shin.R", "thigh.R", [-0.15, 0, 0.55], [-0.15, 0, 0.1])]
    if root == "pinned":
        bones[0]["limits_deg"] = {"x": [-45, 45], "y": [0, 0], "z": [0, 0]}
    return {"name": "fuzz_welded_" + root, "root": root, "defaults": {"collision_radius": 0.05},
            "collision_exclude": [["thigh.L", "thigh.R"]], "bones": bones}


def gen_bone_target_scene():
    """The pinhead with an orientation target, an aim and a pin beside two control points."""
    return {"rig": "../rigs/pinhead.json", "steps": 20, "params": {"preset": "robust"},
            "control_points": [{"bone": "hand.L", "target": [1.2, -0.6, 1.4]},
                               {"bone": "hand.R", "target": [-1.2, -0.6, 1.4], "spring": "capped"}],
            "orientation_targets": [{"bone": "forearm.L", "quaternion": [0.7071068, 0.7071068, 0, 0],
                                     "spring": "capped"}],
            "aim_targets": [{"bone": "head", "point": [2, -3, 2.5], "axis": [0, 1, 0]}],
            "pins": [{"bone": "foot.R"}, {"bone": "foot.L", "alpha": 1, "point": [0.3, 0, 0]}]}


def gen_welded_scene(root):
    """A scene on gen_welded_rig(root): self-collision with its own exclusion, a ground, gravity,
    a control point, an aim and a pin."""
    return {"rig": "../rigs/fuzz_welded_%s.json" % root, "steps": 20,
            "params": {"preset": "robust", "dt": 0.02},
            "gravity": [0, 0, -9.81], "ground": {"height": 0},
            "self_collision": True, "collision_exclude": [["arm.L", "spine"]],
            "control_points": [{"bone": "arm.R", "target": [-0.4, -0.3, 2.0]}],
            "aim_targets": [{"bone": "arm.L", "point": [1, 0, 2.5]}],
            "pins": [{"bone": "shin.R", "alpha": 1}]}


def gen_clip(frames=12, frame_time=1.0 / 30.0):
    """A walking-ish clip of a 12-joint figure in centimetres, Y up (its root with position
    channels and three children), `frames` frames of sine rotations."""
    import math
    rot = "CHANNELS 3 Zrotation Xrotation Yrotation"
    joints = []  # (name, depth, offset, end site or None)

    def add(name, depth, offset, end=None):
        joints.append((name, depth, offset, end))
    add("Hips", 0, "0 95 0")
    add("Spine", 1, "0 10 0")
    add("Chest", 2, "0 25 0")
    add("Head", 3, "0 25 0", "0 20 0")
    for side, sx in (("Left", 1), ("Right", -1)):
        add(side + "Arm", 3, "%d 20 0" % (18 * sx))
        add(side + "ForeArm", 4, "%d 0 0" % (28 * sx), "%d 0 0" % (26 * sx))
    for side, sx in (("Left", 1), ("Right", -1)):
        add(side + "UpLeg", 1, "%d -5 0" % (9 * sx))
        add(side + "Leg", 2, "0 -42 0", "0 -42 0")
    out = ["HIERARCHY"]
    stack = []
    for k, (name, depth, offset, end) in enumerate(joints):
        while len(stack) > depth:
            out.append("}")
            stack.pop()
        out += ["%s %s" % ("ROOT" if depth == 0 else "JOINT", name), "{", "OFFSET " + offset,
                ("CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation"
                 if depth == 0 else rot)]
        if end:
            out += ["End Site", "{", "OFFSET " + end, "}"]
        stack.append(name)
    out += ["}"] * len(stack)
    out += ["MOTION", "Frames: %d" % frames, "Frame Time: %.12g" % frame_time]
    step = 90.0 * min(frame_time, 0.1)  # cm a frame: 90 cm/s, slower for slower clips
    for f in range(frames):
        t = f * frame_time
        row = [0.0, 95.0 + math.sin(4 * t), step * f]
        for k in range(len(joints)):
            row += [5 * math.sin(2 * t + k), 20 * math.sin(6 * t + k), 3 * math.cos(3 * t + k)]
        out.append(" ".join("%.6g" % v for v in row))
    return ("\n".join(out) + "\n").encode()


def clip_seeds(physik, work):
    """[(clip name, clip bytes, rig bytes)]: clips at 30 and 120 fps, a qBVH one, and the rigs
    `rig from-bvh` makes of them (metres: --scale 0.01)."""
    out = []
    for name, data in (("walk30.bvh", gen_clip()), ("walk120.bvh", gen_clip(16, 1.0 / 120.0))):
        clip = os.path.join(work, "seed_" + name)
        with open(clip, "wb") as f:
            f.write(data)
        rig = clip[:-4] + "_rig.json"
        if run([physik, "rig", "from-bvh", clip, "--scale", "0.01", "--out", rig], 60)[0] == 0:
            out.append((name, data, open(rig, "rb").read()))
        # the qBVH's own rig: its source skeleton has quaternion channels
        q, qrig = clip[:-4] + ".qbvh", clip[:-4] + "_q_rig.json"
        if (run([physik, "bvh", "convert", clip, q], 60)[0] == 0 and
                run([physik, "rig", "from-bvh", q, "--scale", "0.01", "--out", qrig], 60)[0] == 0):
            out.append((name[:-4] + ".qbvh", open(q, "rb").read(), open(qrig, "rb").read()))
    return out


def add_generated_seeds(physik, work, seeds):
    """The generated seeds into `seeds` (the welded rigs, pinned, fixed and free roots, also
    into work/rigs, where the scenes on them find them)."""
    for root in ("pinned", "fixed", "free"):
        rig = json.dumps(gen_welded_rig(root), indent=1).encode()
        seeds["rig"].append(("fuzz_welded_%s.json" % root, rig))
        with open(os.path.join(work, "rigs", "fuzz_welded_%s.json" % root), "wb") as f:
            f.write(rig)
        seeds["scene"].append(("welded_%s_scene.json" % root,
                               json.dumps(gen_welded_scene(root), indent=1).encode()))
    seeds["scene"].append(("bone_targets_scene.json",
                           json.dumps(gen_bone_target_scene(), indent=1).encode()))
    seeds["clip"] = clip_seeds(physik, work)


# the command line's bone targets (simulate, solve): an option and an odd value for it
BONE_TARGET_VALUES = {
    "--orientation-target": ["forearm.L=0.7071,0.7071,0,0", "forearm.L=2,0,0,0", "forearm.L=0,0,0,0",
                             "forearm.L=nan,0,0,1", "forarm.L=1,0,0,0", "forearm.L=1,0,0",
                             "hand.L=1e155,1e155,0,0", "=1,0,0,0", "forearm.L"],
    "--aim": ["head=2,-3,2.5", "head=0,0,0", "head=1e155,0,0", "head=inf,0,0", "hed=1,1,1",
              "head=1,2", "head=", "head=1e9,1e9,1e9", "head=1e10,0,0"],
    "--pin": ["foot.R", "foot.R=0,0,0", "foot.R=nan,0,0", "foot.R=1e10,0,0", "feet=0,0,0",
              "foot.R=1,2", "torso", "head=1e-320,0,0"],
}


def bone_target_option(rng):
    """[] or [option, value]: one of the command line's bone targets, often odd"""
    if rng.random() < 0.6:
        return []
    opt = rng.choice(sorted(BONE_TARGET_VALUES))
    return [opt, rng.choice(BONE_TARGET_VALUES[opt])]


# ---------------------------------------------------------------- mutations

def mutate_bytes(rng, data):
    data = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        op = rng.randrange(6)
        if not data:
            data += rng.choice(ODD_BYTES)
            continue
        i = rng.randrange(len(data))
        if op == 0:      # flip a byte
            data[i] = rng.randrange(256)
        elif op == 1:    # insert an odd byte
            data[i:i] = rng.choice(ODD_BYTES)
        elif op == 2:    # delete a range
            del data[i:i + rng.randint(1, 40)]
        elif op == 3:    # duplicate a range
            j = min(len(data), i + rng.randint(1, 200))
            data[i:i] = data[i:j] * rng.randint(1, 3)
        elif op == 4:    # truncate
            del data[i:]
        else:            # replace a number
            nums = list(re.finditer(rb"-?\d+(\.\d+)?(e-?\d+)?", bytes(data)))
            if nums:
                m = rng.choice(nums)
                data[m.start():m.end()] = rng.choice(NUMBER_REPLACEMENTS).encode()
    return bytes(data)


def json_paths(doc, prefix=()):
    yield prefix, doc
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield from json_paths(v, prefix + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield from json_paths(v, prefix + (i,))


def set_path(doc, path, value):
    if not path:
        return value
    cur = doc
    for p in path[:-1]:
        cur = cur[p]
    cur[path[-1]] = value
    return doc


def odd_value(rng):
    r = rng.randrange(10)
    if r < 4:
        v = rng.choice(NUMBER_REPLACEMENTS)
        try:
            return json.loads(v)
        except ValueError:
            return rng.choice([1e308, -1e308, 1e155, 1e-300, 2 ** 31, -2 ** 31 - 1, 0])
    if r < 6:
        return rng.choice(ODD_NAMES)
    if r == 6:
        return [rng.choice([0, 1e200, -1, "x"]) for _ in range(rng.choice([0, 1, 2, 4]))]
    if r == 7:
        return {}
    if r == 8:
        return None
    return rng.choice([True, False, -1, 0, 1e10])


def mutate_json(rng, data, kind):
    try:
        doc = json.loads(data)
    except ValueError:
        return mutate_bytes(rng, data)
    for _ in range(rng.randint(1, 3)):
        paths = list(json_paths(doc))
        path, value = rng.choice(paths)
        op = rng.randrange(7)
        if op <= 2 and path:                        # an odd value
            doc = set_path(doc, path, odd_value(rng))
        elif op == 3 and path and isinstance(value, (int, float)) and not isinstance(value, bool):
            doc = set_path(doc, path, value * rng.choice([1e150, 1e300, -1, 0, 1e-300, 1e6]))
        elif op == 4 and isinstance(value, list) and value:   # grow or empty an array
            if rng.random() < 0.3:
                value.clear()
            else:
                item = rng.choice(value)
                value.extend([json.loads(json.dumps(item)) for _ in range(rng.choice([1, 5, 50]))])
        elif op == 5 and isinstance(value, dict) and value:   # delete or add a key
            if rng.random() < 0.5:
                del value[rng.choice(list(value))]
            else:
                value[rng.choice(["bogus", "comment", "name", "parent", "mass", "radius"])] = odd_value(rng)
        elif op == 6 and kind == "rig" and isinstance(doc, dict) and isinstance(doc.get("bones"), list):
            bones = doc["bones"]
            if bones:
                b = rng.choice(bones)
                if isinstance(b, dict):
                    b[rng.choice(["name", "parent"])] = rng.choice(ODD_NAMES + [b.get("name", "x")])
    text = json.dumps(doc, indent=1, allow_nan=True)
    if rng.random() < 0.1:
        return mutate_bytes(rng, text.encode())
    return text.encode()


def mutate_bvh(rng, data):
    lines = data.decode("latin-1").split("\n")
    op = rng.randrange(6)
    if op == 0 and len(lines) > 2:                  # an odd line between MOTION and Frames:
        try:
            i = next(k for k, l in enumerate(lines) if l.strip() == "MOTION")
            lines.insert(i + 1, rng.choice(["\x0b", "\x0c", " \x0b ", "\t", "\r"]))
        except StopIteration:
            pass
    elif op == 1 and len(lines) > 2:                # duplicate a block of lines
        i = rng.randrange(len(lines))
        j = min(len(lines), i + rng.randint(1, 12))
        lines[i:i] = lines[i:j] * rng.randint(1, 20)
    elif op == 2:                                   # an odd joint name
        idx = [k for k, l in enumerate(lines) if l.strip().startswith(("JOINT", "ROOT"))]
        if idx:
            k = rng.choice(idx)
            kw = lines[k].strip().split()[0]
            name = rng.choice(["bad\xffname", "\xc3", "a\"b", "x<y", "\x7fdel", "caf\xc3\xa9"])
            lines[k] = lines[k].split(kw)[0] + kw + " " + name
    elif op == 3:                                   # an extreme number
        idx = [k for k, l in enumerate(lines) if re.search(r"\d", l)]
        if idx:
            k = rng.choice(idx)
            words = lines[k].split(" ")
            nums = [i for i, w in enumerate(words) if re.fullmatch(r"-?[\d.]+(e-?\d+)?", w)]
            if nums:
                words[rng.choice(nums)] = rng.choice(["1e308", "-1e308", "1e200", "nan", "inf",
                                                      "1e-320", "1e9", "123456789012"])
                lines[k] = " ".join(words)
    else:
        return mutate_bytes(rng, data)
    return "\n".join(lines).encode("latin-1")


def deep_bvh(depth, siblings=1):
    """A BVH nested `depth` joints deep, or with `siblings` joints under the root."""
    out = ["HIERARCHY", "ROOT r", "{", "OFFSET 0 0 0", "CHANNELS 6 Xposition Yposition Zposition "
           "Zrotation Xrotation Yrotation"]
    nch = 6
    for i in range(depth):
        out += ["JOINT j%d" % i, "{", "OFFSET 0 1 0", "CHANNELS 3 Zrotation Xrotation Yrotation"]
        nch += 3
    out += ["End Site", "{", "OFFSET 0 1 0", "}"] + ["}"] * depth
    for i in range(siblings - 1):
        out += ["JOINT s", "{", "OFFSET 1 0 0", "End Site", "{", "OFFSET 0 1 0", "}", "}"]
    out += ["}", "MOTION", "Frames: 1", "Frame Time: 0.1", " ".join(["0"] * nch)]
    return ("\n".join(out) + "\n").encode()


# ---------------------------------------------------------------- commands

def command_for(rng, kind, path, aux, work, case_dir):
    """(command argv, files the command reads, output files to check, option kind)"""
    out = os.path.join(case_dir, "out")
    if kind == "rig":
        r = rng.randrange(6)
        if r == 0:
            return ["rig", "info", path], [path], [], None
        if r == 1:
            return ["rig", "info", "--json", path], [path], ["-"], None
        if r == 2:
            return ["export-mjcf", path, "--out", out + ".xml"], [path], [out + ".xml"], None
        if r == 3:
            ext = rng.choice([".bvh", ".qbvh"])
            extra = rng.choice([[], ["--scale", rng.choice(["inf", "1e308", "0", "nan", "-1", "2"])],
                                ["--order", rng.choice(["XYZ", "ABC", "XXY", "zyx"])]])
            return (["rig", "to-bvh", path, "--out", out + ext] + extra, [path], [out + ext],
                    extra[0] if extra else None)
        if r == 4:
            return ["rig", "limits", path, aux["limits"], "--out", out + ".json"], [path], [out + ".json"], None
        return ["rig", "info", "--json", path], [path], ["-"], None
    if kind == "scene":
        r = rng.randrange(10)
        extra = bone_target_option(rng)
        option = extra[0] if extra else None
        if r < 5:
            steps = str(rng.choice([5, 20, 40]))
            return (["simulate", path, "--steps", steps, "--quiet", "--out", out] + extra, [path],
                    [out + "/summary.json", out + "/trajectory.csv", out + "/final_pose.csv"],
                    option)
        if r < 8:
            solver = rng.choice(["fabrik", "ccd", "jt", "dls", "mass-spring", "rotation", "physik",
                                 "physik-steps", "kdl", "kdl-nr"])
            return (["solve", path, "--solver", solver, "--max-iterations", "50", "--quiet",
                     "--out", out] + extra, [path],
                    [out + "/summary.json", out + "/final_pose.csv"], option)
        return (["equilibrium", path, "--out", out + ".json"], [path], [out + ".json"], None)
    if kind == "clip":
        return clip_command(rng, path, aux, case_dir, out)
    if kind == "bvh":
        r = rng.randrange(4)
        if r <= 1:
            return ["rig", "from-bvh", path, "--out", out + ".json"], [path], [out + ".json"], None
        ext = rng.choice([".bvh", ".qbvh"])
        return ["bvh", "convert", path, out + ext], [path], [out + ext], None
    if kind == "limits":
        return (["rig", "limits", aux["rig"], path, "--out", out + ".json"], [path],
                [out + ".json"], None)
    if kind == "mjcf":
        return ["rig", "from-mjcf", path, "--out", out + ".json"], [path], [out + ".json"], None
    raise ValueError(kind)


FOLLOW_OPTIONS = [["--ground", "0"], ["--ground", "-0.05"], ["--ground", "nan"],
                  ["--ground", "-inf"], ["--ground", "-1e10"], ["--no-ground"], ["--gravity"],
                  ["--frames", "2:5"], ["--frames", "3:"], ["--frames", "0:99"],
                  ["--point", "LeftLeg"], ["--point", "Head:head"], ["--point", "Nose"],
                  ["--set", "dt=0.05"], ["--set", "dt=1e-4"], ["--set", "control_k=1e12"],
                  ["--every", "3"], ["--own-skeleton", "--bvh", "@OUT@_own.bvh"]]


def clip_command(rng, clip, aux, case_dir, out):
    """A command on a clip and its rig (aux["rig"]): follow (with options, and write-back with
    --bvh), a scene starting at a clip frame (simulate or solve, with --bvh), rig to-bvh of the
    rig's source skeleton, or bvh convert."""
    rig = aux["rig"]
    r = rng.randrange(10)
    if r < 5:
        argv = ["follow", clip, "--rig", rig, "--out", out, "--quiet"]
        outputs = [out + "/summary.json", out + "/trajectory.csv"]
        option = None
        for extra in rng.sample(FOLLOW_OPTIONS, rng.choice([0, 1, 2])):
            if extra[0] in argv:  # an option given twice is CLI11's usage error, not a case
                continue
            argv += [a.replace("@OUT@", out) for a in extra]
            option = option or extra[0]
        if rng.random() < 0.5 and "--bvh" not in argv:
            argv += ["--bvh", out + ".bvh"]
            outputs.append(out + ".bvh")
        return argv, [clip, rig], outputs, option
    if r < 8:
        scene = os.path.join(case_dir, "clip_scene.json")
        leaf = rng.choice(["LeftForeArm", "RightLeg", "Head", "Nope"])
        with open(scene, "w") as f:
            json.dump({"rig": os.path.basename(rig), "steps": 10,
                       "initial_pose": {"bvh": os.path.basename(clip),
                                        "frame": rng.choice([0, 3, 11, 12, -1])},
                       "control_points": [{"bone": leaf, "target": [0.3, -0.2, 1.2]}]}, f)
        cmd = (["simulate", scene, "--steps", "10"] if r < 7 else
               ["solve", scene, "--solver", rng.choice(["physik", "dls"]), "--max-iterations", "20"])
        return (cmd + ["--quiet", "--out", out, "--bvh", out + ".bvh"], [scene, clip, rig],
                [out + "/summary.json", out + ".bvh"], None)
    if r < 9:
        return (["rig", "to-bvh", rig, "--out", out + ".bvh"], [rig], [out + ".bvh"], None)
    return ["bvh", "convert", clip, out + ".qbvh"], [clip], [out + ".qbvh"], None


# ---------------------------------------------------------------- checks

NONFINITE_TOKEN = re.compile(r"(?<![A-Za-z_])[-+]?(nan|inf|infinity)(?![A-Za-z_])", re.I)


def number_paths(doc, prefix=""):
    """set of generic paths (arrays as []) at which doc holds a number"""
    out = set()
    for path, v in json_paths(doc):
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            out.add("/".join("[]" if isinstance(p, int) else str(p) for p in path))
    return out


def null_paths(doc):
    return {"/".join("[]" if isinstance(p, int) else str(p) for p in path)
            for path, v in json_paths(doc) if v is None}


def nonfinite_in_output(path, text, schema):
    """a description of a non-finite number in an output, or None"""
    if path.endswith(".json") or path == "-":
        try:
            doc = json.loads(text)
        except ValueError:
            return "unreadable JSON"
        for p, v in json_paths(doc):
            if isinstance(v, float) and not math.isfinite(v):
                return "non-finite at " + "/".join(map(str, p))
        bad = null_paths(doc) & schema
        if bad:
            return "null where a number belongs: " + sorted(bad)[0]
        return None
    # numbers only: not the CSV header, not the BVH joint names, not XML name attributes
    if path.endswith(".csv"):
        text = text.split("\n", 1)[1] if "\n" in text else ""
    elif path.endswith((".bvh", ".qbvh")):
        text = "\n".join(l for l in text.split("\n")
                         if not l.strip().upper().startswith(("ROOT", "JOINT")))
    elif path.endswith(".xml"):
        text = re.sub(r'(name|joint|body|class|file|model)="[^"]*"', "", text)
    m = NONFINITE_TOKEN.search(text)
    if m:
        return "'%s' in %s" % (m.group(0), os.path.basename(path))
    return None


def classify(case, rc, out, err, schema):
    """the rule a case breaks, or None"""
    if rc == "timeout":
        return "hang", "no exit within the timeout"
    if rc < 0:
        return "crash", "signal %d" % -rc
    # 4: a solve short of its tolerance, an equilibrium whose Ceres stopped short (both write
    # their last iterate, as their --help says)
    allowed = (0, 2, 3, 4) if case["cmd"] in ("solve", "equilibrium") else (0, 2, 3)
    if case["cmd"] == "solve" and "--solver" in case["argv"]:
        # the equilibrium solve and KDL never diverge: a valid scene exits 0 or 4, never 3
        if case["argv"][case["argv"].index("--solver") + 1] in ("physik", "kdl", "kdl-nr"):
            allowed = (0, 2, 4)
    if rc not in allowed:
        return "exit %d" % rc, err.strip().splitlines()[-1] if err.strip() else ""
    if rc == 2:
        lines = [l for l in err.splitlines() if l.startswith("physik: error:")]
        if not lines:
            return "message names no file", err.strip()[:200]
        named = any(os.path.basename(f) in lines[0] for f in case["reads"])
        # a bad option: its name ("--order"), or the field it sets ("field 'scale'" when the
        # scale pushes a value of the file past double range)
        opt = case["option"]
        if opt is not None and (opt in lines[0] or "'%s'" % opt.lstrip("-") in lines[0]):
            named = True
        if not named:
            return "message names no file", lines[0][:200]
    if rc in (0, 4):
        for o in case["outputs"]:
            text = out if o == "-" else (open(o, encoding="utf-8", errors="replace").read()
                                         if os.path.exists(o) else None)
            if text is None:
                continue
            key = case["cmd"] + ":" + (os.path.basename(o) if o != "-" else "-")
            bad = nonfinite_in_output(o, text, schema.get(key, set()))
            if bad:
                return "non-finite output", bad
    return None


# ---------------------------------------------------------------- one case

def run_case(args, physik, spec):
    """spec: dict with index, kind, data, name, aux; returns the case record"""
    case_dir = os.path.join(args.work, "c%05d" % spec["index"])
    os.makedirs(case_dir, exist_ok=True)
    rng = random.Random(spec["rng_seed"])
    # scenes and limit files refer to rigs by path: give every case its own copies
    path = os.path.join(case_dir, spec["name"])
    with open(path, "wb") as f:
        f.write(spec["data"])
    aux = {}
    if spec["kind"] == "scene":
        rigs = os.path.join(args.work, "rigs")
        # the scene says ../rigs/x.json: point it at the shared copies
        data = spec["data"].replace(b"../rigs/", (rigs + "/").encode())
        with open(path, "wb") as f:
            f.write(data)
    if spec["kind"] == "rig":
        aux["limits"] = os.path.join(args.work, "limits", spec["name"][:-5] + "_limits.json")
        if not os.path.exists(aux["limits"]):
            aux["limits"] = os.path.join(args.work, "limits", "pinhead_limits.json")
    if spec["kind"] == "limits":
        aux["rig"] = os.path.join(args.src, "models", "rigs", spec["aux_rig"] + ".json")
    if spec["kind"] == "clip":  # the clip's rig beside it (one of the two mutated)
        aux["rig"] = os.path.join(case_dir, spec["name"].rsplit(".", 1)[0] + "_rig.json")
        with open(aux["rig"], "wb") as f:
            f.write(spec["aux_data"])
    argv, reads, outputs, option = command_for(rng, spec["kind"], path, aux, args.work, case_dir)
    rc, out, err = run([physik] + argv, args.timeout)
    case = {"index": spec["index"], "kind": spec["kind"], "seed": spec["name"], "cmd": argv[0] if
            argv[0] != "rig" and argv[0] != "bvh" else argv[0] + " " + argv[1],
            "argv": argv, "reads": reads + list(aux.values()), "outputs": outputs,
            "option": option, "rc": rc, "file": path}
    case["cmd"] = case["cmd"]
    broken = classify(case, rc, out, err, args.schema)
    case["rule"], case["detail"] = broken if broken else (None, "")
    if case["rule"]:
        keep = os.path.join(args.failures, "case%05d_%s" % (spec["index"], spec["name"]))
        shutil.copy(path, keep)
        if "rig" in aux and spec["kind"] == "clip":
            shutil.copy(aux["rig"], keep.rsplit(".", 1)[0] + "_rig.json")
    else:
        shutil.rmtree(case_dir, ignore_errors=True)
    return case


def schema_commands(args, kind, item, d, path):
    """the commands whose outputs on the unmutated seed `item` (written at `path` in folder `d`)
    give build_schema its number paths"""
    name = item[0]
    if kind == "scene":
        return [["simulate", path, "--steps", "5", "--quiet", "--out", d + "/sim"],
                ["solve", path, "--solver", "dls", "--max-iterations", "5", "--quiet",
                 "--out", d + "/solve"],
                ["equilibrium", path, "--out", d + "/eq.json"]]
    if kind == "rig":
        return [["rig", "info", "--json", path],
                ["rig", "from-bvh", os.path.join(args.work, "seed_" + name[:-5] + ".bvh"),
                 "--out", d + "/fb.json"],
                ["rig", "limits", path, os.path.join(args.work, "limits", name[:-5] + "_limits.json"),
                 "--out", d + "/lim.json"]]
    if kind == "clip":
        rig = os.path.join(d, "rig.json")
        with open(rig, "wb") as f:
            f.write(item[2])
        return [["follow", path, "--rig", rig, "--out", d + "/fol", "--quiet"]]
    return []


def build_schema(args, physik, seeds):
    """the number paths of every command's output on the unmutated seeds"""
    schema = collections.defaultdict(set)
    rigs = os.path.join(args.work, "rigs")
    for kind, items in seeds.items():
        for item in items:
            name, data = item[0], item[1]
            d = os.path.join(args.work, "schema_" + kind + "_" + name)
            os.makedirs(d, exist_ok=True)
            path = os.path.join(d, name)
            with open(path, "wb") as f:
                f.write(data.replace(b"../rigs/", (rigs + "/").encode()) if kind == "scene" else data)
            cmds = schema_commands(args, kind, item, d, path)
            for argv in cmds:
                rc, out, _ = run([physik] + argv, 120)
                if rc != 0 and not (argv[0] == "solve" and rc == 4):  # 4: written, short of tol
                    continue
                key0 = argv[0] if argv[0] != "rig" else argv[0] + " " + argv[1]
                files = []
                if argv[0] == "simulate":
                    files = [d + "/sim/summary.json"]
                elif argv[0] == "solve":
                    files = [d + "/solve/summary.json"]
                elif argv[0] == "equilibrium":
                    files = [d + "/eq.json"]
                elif argv[0] == "follow":
                    files = [d + "/fol/summary.json"]
                elif "--out" in argv:
                    files = [argv[argv.index("--out") + 1]]
                for fpath in files:
                    try:
                        schema[key0 + ":" + os.path.basename(fpath)] |= number_paths(json.load(open(fpath)))
                    except (OSError, ValueError):
                        pass
                if argv[:2] == ["rig", "info"]:
                    schema[key0 + ":-"] |= number_paths(json.loads(out))
            shutil.rmtree(d, ignore_errors=True)
    # the same outputs under the names the cases use
    for key in list(schema):
        cmd, f = key.split(":")
        if cmd in ("rig from-bvh", "rig limits", "rig from-mjcf"):
            schema[cmd + ":out.json"] |= schema[key]
        if cmd == "equilibrium":
            schema[cmd + ":out.json"] |= schema[key]
    schema["rig from-mjcf:out.json"] |= schema.get("rig from-bvh:out.json", set())
    return dict(schema)


# ---------------------------------------------------------------- the corpus

def corpus_case(args, physik, entry, d):
    """A corpus entry's files in its folder `d` (copied, generated or inline; then made by its
    "before" commands and changed by its "edit"s), and its argv with every name expanded."""
    files = {}
    for key, spec in entry.get("files", {}).items():
        p = os.path.join(d, spec.get("as") or os.path.basename(spec.get("copy", key)))
        if "copy" in spec:
            data = open(os.path.join(args.corpus, spec["copy"]), "rb").read()
        elif "generate" in spec:
            data = generate(spec["generate"])
        else:
            data = spec["text"].encode("latin-1")
        data = data.replace(b"@SRC@", args.src.encode())
        with open(p, "wb") as f:
            f.write(data)
        files[key] = p

    def expand(argv):
        argv = [a.replace("@SRC@", args.src).replace("@OUT@", d + "/out").replace("@DIR@", d)
                for a in argv]
        return [files.get(a[1:-1], a) if a.startswith("{") and a.endswith("}") else a
                for a in argv]
    # commands that make the case's further files (a rig from a generated clip), then edits of
    # JSON files ({"file": key, "path": [...], "value": v})
    for before in entry.get("before", []):
        brc, _, berr = run([physik] + expand(before), 120)
        if brc != 0:
            raise RuntimeError("corpus %s: physik %s: %s" % (entry["name"], before, berr))
    for key, path in entry.get("made", {}).items():
        files[key] = expand([path])[0]
    for edit in entry.get("edit", []):
        doc = json.load(open(files[edit["file"]]))
        set_path(doc, tuple(edit["path"]), edit["value"])
        with open(files[edit["file"]], "w") as f:
            json.dump(doc, f)
    return expand(entry["argv"])


def run_corpus(args, physik):
    """the robustness reproducers: (name, ok, detail) per entry"""
    manifest = json.load(open(os.path.join(args.corpus, "manifest.json")))
    results = []
    for entry in manifest["cases"]:
        if entry.get("address_space") and os.environ.get("PHYSIK_SANITIZED") == "1":
            # a sanitized binary's shadow memory alone reserves terabytes: no cap can hold it
            print("corpus %s: skipped in the sanitizer build (it runs under an address-space cap)"
                  % entry["name"])
            continue
        d = os.path.join(args.work, "corpus_" + entry["name"])
        os.makedirs(d, exist_ok=True)
        argv = corpus_case(args, physik, entry, d)
        rc, out, err = run([physik] + argv, entry.get("timeout", args.timeout),
                           address_space=entry.get("address_space"))
        ok = rc in entry["exit"]
        detail = "exit %s" % rc
        for text in entry.get("stderr", []):
            if text not in err:
                ok = False
                detail += ", stderr lacks '%s'" % text
        for path, text in entry.get("absent", {}).items():
            p = path.replace("@OUT@", d + "/out")
            if os.path.exists(p) and re.search(text, open(p, errors="replace").read()):
                ok = False
                detail += ", %s holds '%s'" % (os.path.basename(p), text)
        for path in entry.get("finite_page", []):
            p = path.replace("@OUT@", d + "/out")
            bad = nonfinite_in_page(p) if os.path.exists(p) else "no page written"
            if bad:
                ok = False
                detail += ", %s: %s" % (os.path.basename(p), bad)
        if not ok:
            detail += " | " + (err.strip().splitlines() or [""])[-1][:200]
        results.append((entry["name"], ok, detail))
        shutil.rmtree(d, ignore_errors=True)
    return results


# the typed arrays of a `physik view` page's runs (viewer/view_page.h): name -> struct code
PAGE_ARRAYS = {"steps": "i", "times": "d", "kinetic_energy": "f", "max_residual": "f",
               "max_residual_point": "i", "positions": "f", "targets": "f", "limit_excess": "f"}


def nonfinite_in_page(path):
    """a description of a non-finite number in a viewer page's decoded frames, or None"""
    import base64
    import struct
    text = open(path, encoding="utf-8").read()
    m = re.search(r'<script type="application/json" id="physik-data">(.*?)</script>', text, re.S)
    if not m:
        return "no data element"
    for k, run in enumerate(json.loads(m.group(1))["runs"]):
        arrays = {n: (run.get(n), c) for n, c in PAGE_ARRAYS.items()}
        for n, c in (("start", "i"), ("bones", "i"), ("values", "f")):
            arrays["contacts." + n] = (run.get("contacts", {}).get(n), c)
        for name, (b64, code) in arrays.items():
            if b64 is None:
                continue
            raw = base64.b64decode(b64)
            size = struct.calcsize("<" + code)
            values = struct.unpack("<%d%s" % (len(raw) // size, code), raw)
            if not all(math.isfinite(v) for v in values):
                return "run %d: %s holds a non-finite number" % (k, name)
    return None


def overlapping_zigzag(spec):
    """A scene: a chain of `bones` bones of length 1 folded back and forth along x, each `dz`
    above the one before, collision radius 0.1, so every bone overlaps the ones two (and, with
    dz 0.02, four) along; under self-collision with `params` (the fuzzer's: contact_k 1e20,
    implicit_max_splits 20)."""
    bones, x, dz = [], 0.0, spec.get("dz", 0.08)
    for i in range(spec["bones"]):
        x2 = 1.0 - x
        bones.append({"name": "b%d" % i, "parent": "b%d" % (i - 1) if i else None,
                      "head": [x, 0, dz * i], "tail": [x2, 0, dz * (i + 1)]})
        x = x2
    return json.dumps({"rig": {"name": "zigzag", "defaults": {"collision_radius": 0.1},
                               "bones": bones},
                       "steps": spec.get("steps", 1), "self_collision": True,
                       "params": spec["params"]}).encode()


def many_boxes(spec):
    """A scene on a shipped rig ("rig", default elbow) with `boxes` boxes of half extent 0.5: all
    at one place ("spacing": 0) or on a line `spacing` apart."""
    boxes = [{"name": "box%d" % i, "box": {"center": [3 + spec["spacing"] * i, 0, 0],
                                          "half_extents": [0.5, 0.5, 0.5]}}
             for i in range(spec["boxes"])]
    return json.dumps({"rig": "@SRC@/models/rigs/%s.json" % spec.get("rig", "elbow"), "steps": 5,
                       "ground": {"height": -5}, "obstacles": boxes}).encode()


def generate(spec):
    """big reproducers are generated, not stored"""
    kind = spec["kind"]
    if kind == "clip":
        return gen_clip(spec.get("frames", 12), spec.get("frame_time", 1.0 / 30.0))
    if kind == "welded_rig":
        return json.dumps(gen_welded_rig(spec["root"])).encode()
    if kind == "overlapping_zigzag":
        return overlapping_zigzag(spec)
    if kind == "many_boxes":
        return many_boxes(spec)
    if kind == "bvh_deep":
        return deep_bvh(spec["depth"])
    if kind == "bvh_siblings":
        return deep_bvh(0, spec["siblings"])
    if kind == "json_deep_params":
        depth = spec["depth"]
        return ('{"rig": "@SRC@/models/rigs/elbow.json", "params": ' + "[" * depth + "]" * depth +
                "}").encode()
    if kind == "chain":
        n = spec["bones"]
        bones = ",".join('{"name": "b%d", "parent": %s, "head": [0, 0, %d], "tail": [0, 0, %d]}'
                         % (i, '"b%d"' % (i - 1) if i else "null", i, i + 1) for i in range(n))
        return ('{"bones": [%s]}' % bones).encode()
    if kind == "scene_many_points":
        n = spec["points"]
        cps = ",".join('{"bone": "forearm", "alpha": %g, "target": [0.1, 0, %g]}' % ((i % 10) / 10, 1 + i * 1e-4)
                       for i in range(n))
        return ('{"rig": "@SRC@/models/rigs/elbow.json", "steps": %d, "control_points": [%s]}'
                % (spec.get("steps", 5), cps)).encode()
    raise ValueError(kind)


# ---------------------------------------------------------------- main

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("physik")
    ap.add_argument("src")
    ap.add_argument("--cases", type=int, default=int(os.environ.get("PHYSIK_FUZZ_CASES", 2000)))
    ap.add_argument("--seed", type=int, default=int(os.environ.get("PHYSIK_FUZZ_SEED", 12)))
    ap.add_argument("--jobs", type=int, default=int(os.environ.get("PHYSIK_FUZZ_JOBS", 2)))
    ap.add_argument("--timeout", type=float, default=float(os.environ.get("PHYSIK_FUZZ_TIMEOUT", 20)))
    ap.add_argument("--keep", help="keep failing inputs in this folder")
    ap.add_argument("--no-corpus", action="store_true")
    args = ap.parse_args()
    physik = os.path.abspath(args.physik)
    args.src = os.path.abspath(args.src)
    args.corpus = os.path.join(args.src, "tests", "fuzz", "corpus")
    args.work = tempfile.mkdtemp(prefix="physik_fuzz_")
    args.failures = args.keep or os.path.join(args.work, "failures")
    os.makedirs(args.failures, exist_ok=True)
    try:
        return fuzz(args, physik)
    finally:
        if not args.keep:
            shutil.rmtree(args.work, ignore_errors=True)


def fuzz(args, physik):
    shutil.copytree(os.path.join(args.src, "models", "rigs"), os.path.join(args.work, "rigs"))
    seeds = make_seeds(physik, args.src, args.work)
    add_generated_seeds(physik, args.work, seeds)
    os.makedirs(os.path.join(args.work, "limits"))
    for name, data, _ in seeds["limits"]:
        with open(os.path.join(args.work, "limits", name), "wb") as f:
            f.write(data)
    args.schema = build_schema(args, physik, seeds)
    rng = random.Random(args.seed)
    weights = {"rig": 3, "scene": 4, "bvh": 2, "limits": 1, "mjcf": 1, "clip": 2}
    kinds = [k for k in weights for _ in range(weights[k]) if seeds.get(k)]
    specs = []
    for i in range(args.cases):
        kind = rng.choice(kinds)
        item = rng.choice(seeds[kind])
        name, data = item[0], item[1]
        aux_data = item[2] if kind == "clip" else None
        if kind == "clip" and rng.random() < 0.35:  # the clip's rig (its source skeleton)
            aux_data = mutate_json(rng, aux_data, "rig")
        elif kind in ("bvh", "clip"):
            data = mutate_bvh(rng, data)
        elif kind == "mjcf":
            data = mutate_bytes(rng, data)
        else:
            data = mutate_json(rng, data, kind) if rng.random() < 0.7 else mutate_bytes(rng, data)
        specs.append({"index": i, "kind": kind, "name": name, "data": data,
                      "rng_seed": rng.randrange(1 << 30),
                      "aux_rig": item[2] if kind == "limits" else None, "aux_data": aux_data})
    counts = collections.Counter()
    by_exit = collections.Counter()
    failures = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for case in pool.map(lambda s: run_case(args, physik, s), specs):
            by_exit[str(case["rc"])] += 1
            if case["rule"] is None:
                counts["ok exit %s" % case["rc"]] += 1
            else:
                counts["FAIL " + case["rule"]] += 1
                failures.append(case)
    print("fuzz: %d cases, seed %d" % (args.cases, args.seed))
    for k in sorted(counts):
        print("  %-34s %6d" % (k, counts[k]))
    print("  by exit code: " + ", ".join("%s: %d" % kv for kv in sorted(by_exit.items())))
    for c in failures[:25]:
        print("FAIL case %d (%s, seed %s): %s: %s\n     physik %s" %
              (c["index"], c["kind"], c["seed"], c["rule"], c["detail"][:300], " ".join(c["argv"])))
    corpus_failed = 0
    if not args.no_corpus:
        results = run_corpus(args, physik)
        corpus_failed = sum(1 for _, ok, _ in results if not ok)
        print("corpus: %d reproducers, %d passed, %d failed" %
              (len(results), len(results) - corpus_failed, corpus_failed))
        for name, ok, detail in results:
            if not ok:
                print("FAIL corpus %s: %s" % (name, detail))
    return 1 if failures or corpus_failed else 0


if __name__ == "__main__":
    sys.exit(main())
