"""Live-simulation speed in Blender (issue 17 item 4; a benchmark, never a test).

What one frame of the Simulate operator does, timed: Live.step(n) (the engine, n steps), the
pose put on the armature (armature_io.apply_pose) and Blender's pose update (the depsgraph
evaluation that moves the posed bones: view_layer.update()). Headless (-b), so the viewport's
drawing is not counted. Pinhead with Fig 9's control points, the scene's params, from rest.

    blender -b --factory-startup --python blender/bench_live.py -- \
        --repo . --pythonpath build/python [--frames 600] [--repeat 3]
"""
import argparse
import json
import os
import sys
import time

import addon_utils
import bpy


def _args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("--repo", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    p.add_argument("--pythonpath", required=True, help="the folder holding the physik package")
    p.add_argument("--frames", type=int, default=600)
    p.add_argument("--repeat", type=int, default=3)
    return p.parse_args(argv)


ARGS = _args()
REPO = os.path.abspath(ARGS.repo)
sys.path.insert(0, os.path.abspath(ARGS.pythonpath))
sys.path.insert(0, os.path.join(REPO, "blender"))
addon_utils.enable("physik_addon", default_set=True, handle_error=None)
from physik_addon import armature_io, control_points, engine, rig_format, scene_dict  # noqa: E402


def fig9_scene():
    with open(os.path.join(REPO, "models", "scenes", "fig9_outstretched.json")) as f:
        doc = json.load(f)
    arm = armature_io.rig_to_armature(
        rig_format.load_rig(os.path.join(REPO, "models", "rigs", "pinhead.json")), bpy.context)
    for cp in doc["control_points"]:
        control_points.add_control_point(bpy.context, arm, cp["bone"], cp["alpha"], cp["target"])
    s = bpy.context.scene.physik
    s.preset, s.control_k = doc["params"]["preset"], doc["params"]["control_k"]
    bpy.context.view_layer.objects.active = arm
    return arm, scene_dict.build_scene(bpy.context, arm)


def frames_per_second(arm, scene, steps_per_frame, frames):
    """(fps, engine share of the frame time) over `frames` frames of a fresh live run."""
    live = engine.Live(scene)
    t_engine = 0.0
    t0 = time.perf_counter()
    for _ in range(frames):
        e0 = time.perf_counter()
        head, rotations = live.step(steps_per_frame)
        t_engine += time.perf_counter() - e0
        armature_io.apply_pose(arm, head, rotations)
        bpy.context.view_layer.update()
    total = time.perf_counter() - t0
    return frames / total, t_engine / total


def main():
    arm, scene = fig9_scene()
    for n in (1, 10):
        best = max(frames_per_second(arm, scene, n, ARGS.frames) for _ in range(ARGS.repeat))
        print("live pinhead (Fig 9), %2d steps per frame: %7.1f fps (engine %2.0f%% of the frame), "
              "best of %d x %d frames" % (n, best[0], 100 * best[1], ARGS.repeat, ARGS.frames))


main()
