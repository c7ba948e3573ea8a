"""Solve a scene's control points with Blender's own iTaSC IK, on the same rig and limits (the
paper's Fig 9 peer), and write the posed bones as the project's bones CSV.

    blender -b --factory-startup --python-exit-code 1 --python blender/itasc_solve.py -- \
        --scene models/scenes/fig9_outstretched.json --out itasc_final.csv [--report itasc.json] \
        [--pose itasc_pose.json]

Exit status: 0 solved (whether or not the pose meets the targets: see the report's
"meets_control_points"), 2 bad input (one line naming the file, the element and the field).

How the solve is set up, and why:
  rig      the scene's rig file, built as an armature by the add-on (rest frames via roll, the
           rig's per-axis limits as Blender IK limits, [0, 0] as a locked axis). The armature
           object sits at the root bone's head: Blender 3.4.1's iTaSC solves as if the root
           bone's head were at the object's origin when the root bone is in a chain (measured:
           a two-bone chain whose root head is 1 above the origin is solved 1 too low), so the
           origin is put where the root head is, which leaves every world position unchanged.
  targets  one empty per control point at its target; one IK constraint per control point on
           its bone, weight 1 (PhysIK's spring constants have no iTaSC counterpart; Fig 9's are
           all equal). alpha = 1 targets the bone's tail (use_tail), alpha = 0 its head; another
           alpha adds a locked helper bone from the bone's head to that point and targets its tail.
  chains   --chain root (default): every chain runs up to the root bone (chain_count 0), so
           iTaSC may move every bone that PhysIK and the project's DLS can move for these points,
           as one tree solving all targets together. The root bone can only turn about its head:
           iTaSC has no translation joint (as the project's DLS, which anchors the root's head);
           PhysIK's root translates freely. --chain fixed stops each chain below the first bone
           whose three axes are all locked (0 DOF), the usual animator's setup (shown for
           comparison; the locked bones would not move anyway, but the bones above them then
           belong to no chain).
  mode     ANIMATION: stateless, starts from the channel pose (the scene's initial pose, or
           rest) and reiterates until the largest joint or end-effector change per iteration is
           below --precision, at most --iterations times: one IK solve, no frame history.
           Blender 3.4.1 raises a precision below 1e-4 to 1e-4 (measured: 1e-5 reads back as
           1e-4), so 1e-4 is the default and the tightest; the report holds the value used.
           SIMULATION would make the pose depend on previous frames and on velocity limits, which
           an IK comparison must not.
  solver   --solver SDLS (Blender's default; selective damping per singular value) or DLS
           (damping up to damping_max below damping_epsilon; Blender's defaults 0.5, 0.15).
  check    residual = distance from each attachment point (alpha along the posed bone) to its
           target; the pose meets the control points when every residual is within the scene's
           residual tolerance (convergence.residual_tol, 0 or absent = 1e-3 x rig height, as the
           engine). The pose is also measured against the rig's limits in the project's
           convention (rotation-vector components relative to rest): iTaSC enforces the same
           numbers on its own joint parametrisation (Euler angle for 1 DOF, swing + twist for 3).
  pose     --pose writes the solved pose in the scene file's `initial_pose` form (root head, and
           every bone's rotation relative to rest as a rotation vector in degrees, the project's
           convention), so the C++ side rebuilds the full pose (rolls included, which heads and
           tails do not show) with its own forward kinematics: the fig9 experiment measures
           iTaSC's pose with the same functions as PhysIK's and DLS's.
"""
import argparse
import json
import math
import os
import sys
import time

import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from physik_addon import armature_io, rig_format  # noqa: E402
from physik_addon.rig_format import InputError  # noqa: E402
from physik_addon.scene_format import load_scene, rotation_from_vector_deg  # noqa: E402


def parse_args(argv):
    p = argparse.ArgumentParser(prog="itasc_solve.py", description=__doc__.split("\n\n")[0])
    p.add_argument("--scene", required=True, help="scene file (models/README.md)")
    p.add_argument("--rig", help="rig file instead of the scene's")
    p.add_argument("--out", required=True, help="bones CSV of the solved pose")
    p.add_argument("--report", help="JSON report: settings, chains, residuals, limits")
    p.add_argument("--pose", help="JSON {\"initial_pose\": ...}: the solved pose in the scene format")
    p.add_argument("--chain", choices=("root", "fixed"), default="root")
    p.add_argument("--solver", choices=("SDLS", "DLS"), default="SDLS")
    p.add_argument("--iterations", type=int, default=1000, help="at most (Blender: 0..1000)")
    p.add_argument("--precision", type=float, default=1e-4,
                   help="stop when a joint or end effector moves less per iteration (Blender 3.4.1 "
                        "keeps it within 1e-4..0.1)")
    p.add_argument("--save-blend", help="also save the solved scene as this .blend")
    return p.parse_args(argv)


def fully_locked(rig_bone):
    lim = rig_bone.get("limits_deg", {})
    return all(a in lim and lim[a][0] == 0.0 and lim[a][1] == 0.0 for a in "xyz")


def chain_of(rig, bone, mode):
    """Bones from `bone` up the tree that the chain holds: to the root, or (fixed) up to but not
    including the first fully locked bone."""
    by_name = {b["name"]: b for b in rig["bones"]}
    chain, name = [], bone
    while name is not None:
        if mode == "fixed" and fully_locked(by_name[name]) and chain:
            break
        chain.append(name)
        name = by_name[name]["parent"]
    return chain


def add_target(context, obj, rig, cp, mode, helpers):
    """An empty at the target and an IK constraint pulling the attachment point; returns the
    chain of rig bones it moves."""
    empty = bpy.data.objects.new("target " + cp["name"], None)
    empty.location = cp["target"]
    context.scene.collection.objects.link(empty)
    chain = chain_of(rig, cp["bone"], mode)
    owner, use_tail, count = cp["bone"], True, len(chain)
    if cp["alpha"] == 0.0:
        use_tail = False  # the head: the chain starts at the parent
        chain = chain[1:] or chain
        count = len(chain)
    elif cp["alpha"] != 1.0:
        owner = helpers[(cp["bone"], cp["alpha"])]
        count += 1
    con = obj.pose.bones[owner].constraints.new('IK')
    con.name = "physik " + cp["name"]
    con.target = empty
    con.use_tail = use_tail
    con.chain_count = 0 if mode == "root" else count
    con.weight = 1.0
    return con, chain


def add_helpers(context, obj, rig, cps):
    """A locked child bone from a bone's head to its alpha point, for 0 < alpha < 1."""
    wanted = sorted({(c["bone"], c["alpha"]) for c in cps if 0.0 < c["alpha"] < 1.0})
    if not wanted:
        return {}
    by_name = {b["name"]: b for b in rig["bones"]}
    names = {}
    bpy.ops.object.mode_set(mode='EDIT')
    origin = obj.location.copy()
    for k, (bone, alpha) in enumerate(wanted):
        b = by_name[bone]
        eb = obj.data.edit_bones.new("physik_helper_%d" % k)
        head = Vector(b["head"])
        eb.head = head - origin
        eb.tail = head.lerp(Vector(b["tail"]), alpha) - origin
        eb.align_roll(Vector(b["rest_frame"][2]))
        eb.parent = obj.data.edit_bones[bone]
        names[(bone, alpha)] = eb.name
    bpy.ops.object.mode_set(mode='OBJECT')
    for name in names.values():
        pb = obj.pose.bones[name]
        pb.lock_ik_x = pb.lock_ik_y = pb.lock_ik_z = True
    return names


def apply_initial_pose(obj, pose):
    """The scene's start: the object (whose origin is the root head) moves to the initial root
    head; the channels take the initial rotations, from which ANIMATION mode starts."""
    if pose["root_head"] is not None:
        obj.location = pose["root_head"]
    for bone, v in pose["rotation_deg"].items():
        armature_io.set_rotation(obj.pose.bones[bone], rotation_from_vector_deg(v))


def posed(obj, rig):
    """{bone: (head, tail, world rotation)} of the evaluated pose, rig bones only."""
    m = obj.matrix_world
    r = m.to_3x3().normalized()
    out = {}
    for b in rig["bones"]:
        pb = obj.pose.bones[b["name"]]
        out[b["name"]] = (m @ pb.head, m @ pb.tail, (r @ pb.matrix.to_3x3()).normalized().to_quaternion())
    return out


def local_rotations(rig, pose):
    """{bone: rotation relative to rest in its rest frame} in the project's convention
    (kinematics.h): q = Rrest^-1 Rrest_parent R_parent^-1 R, the root's Rrest^-1 R."""
    rest = {b["name"]: matrix_from_axes(b["rest_frame"]).to_quaternion() for b in rig["bones"]}
    out = {}
    for b in rig["bones"]:
        p = b["parent"]
        if p is None:
            out[b["name"]] = rest[b["name"]].inverted() @ pose[b["name"]][2]
        else:
            out[b["name"]] = (rest[b["name"]].inverted() @ rest[p] @ pose[p][2].inverted()
                              @ pose[b["name"]][2])
    return out


def pose_dict(rig, pose):
    """The scene format's initial_pose of the solved pose (rotation vectors in degrees)."""
    rot = {name: [math.degrees(a) for a in rig_format.rotation_vector(tuple(q))]
           for name, q in local_rotations(rig, pose).items()}
    return {"root_head": list(pose[rig["bones"][0]["name"]][0]), "rotation_deg": rot}


def limit_violations(rig, pose):
    """Largest amount (deg) by which each limited axis is outside its range, in the project's
    convention: the rotation vector of the local rotation (local_rotations)."""
    local = local_rotations(rig, pose)
    worst = {"deg": 0.0, "bone": None, "axis": None}
    for b in rig["bones"][1:]:
        angles = [math.degrees(a) for a in rig_format.rotation_vector(tuple(local[b["name"]]))]
        for k, axis in enumerate("xyz"):
            lim = b.get("limits_deg", {}).get(axis)
            if lim is None:
                continue
            over = max(lim[0] - angles[k], angles[k] - lim[1], 0.0)
            if over > worst["deg"]:
                worst = {"deg": over, "bone": b["name"], "axis": axis}
    return worst


def matrix_from_axes(axes):
    """The 3x3 matrix whose columns are the given x, y, z axes."""
    return Matrix([[axes[c][r] for c in range(3)] for r in range(3)])


def solve(args):
    scene = load_scene(args.scene, args.rig)
    rig = scene["rig"]
    armature_io.check_blender_limits(rig, scene["rig_path"])
    context = bpy.context
    for obj in list(bpy.data.objects):  # factory startup's cube, camera and light
        bpy.data.objects.remove(obj)
    obj = armature_io.rig_to_armature(rig, context, origin=rig["bones"][0]["head"])
    helpers = add_helpers(context, obj, rig, scene["control_points"])
    apply_initial_pose(obj, scene["initial_pose"])
    obj.pose.ik_solver = 'ITASC'
    ik = obj.pose.ik_param
    ik.mode = 'ANIMATION'
    ik.solver = args.solver
    ik.iterations = args.iterations
    ik.precision = args.precision
    if abs(ik.precision - args.precision) > 1e-6 * args.precision:
        print("itasc_solve.py: Blender keeps precision at %.3g (asked %.3g)"
              % (ik.precision, args.precision), file=sys.stderr)
    constraints, chains = [], {}
    for cp in scene["control_points"]:
        con, chain = add_target(context, obj, rig, cp, args.chain, helpers)
        constraints.append(con)
        chains[cp["name"]] = chain
    t0 = time.perf_counter()
    context.view_layer.update()
    seconds = time.perf_counter() - t0
    pose = posed(obj, rig)
    residuals = {}
    for cp in scene["control_points"]:
        head, tail, _ = pose[cp["bone"]]
        residuals[cp["name"]] = (head.lerp(tail, cp["alpha"]) - Vector(cp["target"])).length
    armature_io.write_bones_csv(args.out, [(b["name"], b["parent"] or "", pose[b["name"]][0],
                                            pose[b["name"]][1]) for b in rig["bones"]])
    worst = max(residuals.values())
    report = {
        "scene": os.path.abspath(args.scene), "rig": os.path.abspath(scene["rig_path"]),
        "blender": bpy.app.version_string,
        "itasc": {"mode": ik.mode, "solver": ik.solver, "iterations": ik.iterations,
                  "precision": ik.precision, "damping_max": ik.damping_max,
                  "damping_epsilon": ik.damping_epsilon, "chain": args.chain,
                  "root": "turns about its head only (no translation joint)"},
        "chains": chains,
        "residuals": residuals, "max_residual": worst, "residual_tol": scene["residual_tol"],
        "meets_control_points": worst <= scene["residual_tol"],
        "blender_error_location": {c.name: c.error_location for c in constraints},
        "max_limit_violation": limit_violations(rig, pose),
        "solve_seconds": seconds, "bones_csv": os.path.abspath(args.out),
    }
    if args.report:
        with open(args.report, "w", encoding="utf-8") as f:
            json.dump(report, f, indent=1)
    if args.pose:
        with open(args.pose, "w", encoding="utf-8") as f:
            json.dump({"initial_pose": pose_dict(rig, pose)}, f, indent=1)
    if args.save_blend:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.save_blend))
    return report


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    args = parse_args(argv)
    try:
        report = solve(args)
    except InputError as e:
        print("itasc_solve.py: %s" % e, file=sys.stderr)
        sys.exit(2)
    print("itasc: %s %s, chains to %s: max residual %.3g (tolerance %.3g, %s), worst limit "
          "excess %.3g deg, %.3f s" % (
              report["itasc"]["mode"], report["itasc"]["solver"], args.chain, report["max_residual"],
              report["residual_tol"], "met" if report["meets_control_points"] else "NOT met",
              report["max_limit_violation"]["deg"], report["solve_seconds"]))
    if not report["meets_control_points"]:
        print("itasc_solve.py: warning: the iTaSC pose does not meet the control points",
              file=sys.stderr)


if __name__ == "__main__":
    main()
