"""Live-simulation speed in Blender (a benchmark, never a test).

Pinhead with Fig 9's control points (models/scenes/fig9_outstretched.json: its params), from
rest, at each --steps (default 1 and 10 steps per frame). Two measures:

  headless   what one frame of Simulate computes, in a plain loop: Live.step(n) (the engine),
             the pose put on the armature (armature_io.apply_pose) and Blender's pose update
             (the depsgraph evaluation that moves the posed bones: view_layer.update()).
             --frames frames, best of --repeat. No drawing. Runs in background mode (-b) and in
             a window.
  window     (only with a window) the real Simulate operator: its window-manager timer, the
             modal step (engine and pose), Blender's event loop, the depsgraph update and the
             viewport redraw, for --window-frames frames (max_frames), best of --repeat. The
             scene's frame rate is raised to 1000 for the run (the timer fires every 1 ms, i.e.
             once per pass of the event loop), so the frame rate is what Blender sustains, not
             the scene's 24 fps. fps = (frames - 1) / (time from the first frame to the last);
             a draw handler on the 3D viewport counts the redraws (draws per frame ~1).
             Beside it (poses_only), the same run's poses computed beforehand and put on the
             armature by a plain timer, one per pass of the event loop: Blender's pose update
             and redraw without the engine or the operator, what this machine's drawing allows.
             (A redraw with nothing changed is no baseline: the viewport then reuses its image.)

    # headless
    blender -b --factory-startup --python blender/bench_live.py -- \\
        --repo . --pythonpath build/python [--json live_headless.json]
    # in a window on a virtual display (Xvfb; software OpenGL when there is no GPU)
    /usr/bin/python3 blender/tests/window_runner.py --blender blender --size 1280x800 \\
        blender/bench_live.py -- --repo . --pythonpath build/python --json live_window.json

Writes the numbers as JSON (--json) and prints one line per measure. The machine's load, the
window size and the OpenGL renderer go into the JSON: the viewport's cost is the renderer's.
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
    p = argparse.ArgumentParser(prog="bench_live.py", description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog=__doc__.split("\n\n", 1)[1])
    p.add_argument("--repo", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    p.add_argument("--pythonpath", required=True, help="the folder holding the physik package")
    p.add_argument("--steps", default="1,10", help="steps per frame, comma-separated")
    p.add_argument("--frames", type=int, default=600, help="headless frames per run")
    p.add_argument("--window-frames", type=int, default=120, help="frames per run in a window")
    p.add_argument("--repeat", type=int, default=3, help="runs per measure (the best is kept)")
    p.add_argument("--json", help="write the numbers here")
    p.add_argument("--result", help="(window_runner.py) a JSON file written at the end")
    return p.parse_args(argv)


ARGS = _args()
REPO = os.path.abspath(ARGS.repo)
sys.path.insert(0, os.path.abspath(ARGS.pythonpath))
sys.path.insert(0, os.path.join(REPO, "blender"))
bpy.context.preferences.view.show_splash = False
addon_utils.enable("physik_addon", default_set=True, handle_error=None)
from physik_addon import (armature_io, control_points, engine, operators,  # noqa: E402
                          rig_format, scene_dict)

STEPS = [int(s) for s in ARGS.steps.split(",")]


def fig9_scene():
    for obj in list(bpy.data.objects):  # factory startup's cube, camera and light
        bpy.data.objects.remove(obj)
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


def reset_pose(arm):
    for pb in arm.pose.bones:
        pb.location = (0.0, 0.0, 0.0)
        armature_io.set_rotation(pb, (1.0, 0.0, 0.0, 0.0))


def headless_run(arm, scene, steps_per_frame, frames):
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


def headless(arm, scene):
    rows = []
    for n in STEPS:
        fps, share = max(headless_run(arm, scene, n, ARGS.frames) for _ in range(ARGS.repeat))
        rows.append({"steps_per_frame": n, "fps": fps, "engine_share": share,
                     "frames": ARGS.frames, "repeat": ARGS.repeat})
        print("headless: pinhead (Fig 9), %2d steps per frame: %7.1f fps (engine %2.0f%% of the "
              "frame), best of %d x %d frames" % (n, fps, 100 * share, ARGS.repeat, ARGS.frames),
              flush=True)
    reset_pose(arm)
    return rows


def view3d():
    win = bpy.context.window_manager.windows[0]
    area = next(a for a in win.screen.areas if a.type == 'VIEW_3D')
    region = next(r for r in area.regions if r.type == 'WINDOW')
    return win, area, region


DRAWS = []  # viewport draw times while a window run is going


def on_draw():
    if operators.LIVE.get("running"):
        DRAWS.append(time.perf_counter())


def window_run(steps_per_frame, frames):
    """Generator: one Simulate run of `frames` frames; yields delays, returns its numbers."""
    arm = bpy.context.view_layer.objects.active
    reset_pose(arm)
    bpy.context.scene.physik.steps_per_frame = steps_per_frame
    win, area, region = view3d()
    DRAWS.clear()
    with bpy.context.temp_override(window=win, area=area, region=region):
        r = bpy.ops.physik.simulate('INVOKE_DEFAULT', max_frames=frames)
    if r != {'RUNNING_MODAL'}:
        raise RuntimeError("Simulate did not start: %s" % r)
    t_end = time.perf_counter() + 600.0
    while operators.LIVE["running"]:
        if time.perf_counter() > t_end:
            raise RuntimeError("Simulate did not finish %d frames in 600 s" % frames)
        yield 0.05
    live = dict(operators.LIVE)
    if live["stopped_by"] != "max_frames" or live["frames"] != frames:
        raise RuntimeError("Simulate stopped early: %s" % live)
    fps = (live["frames"] - 1) / live["seconds"]
    return {"fps": fps, "busy_share": live["busy_seconds"] / live["seconds"],
            "draws_per_frame": len(DRAWS) / live["frames"], "frames": live["frames"],
            "steps": live["steps"], "final_state_hash": live["final_state_hash"]}


REDRAW = {"on": False, "draws": []}


def on_draw_redraw_only():
    if REDRAW["on"]:
        REDRAW["draws"].append(time.perf_counter())


def poses_only(scene, frames):
    """Generator: the same run's poses, computed beforehand, put on the armature one per pass
    of the event loop by a plain timer (no engine, no operator); returns the frames per second
    the viewport then shows: what Blender's pose update and redraw alone allow here."""
    arm = bpy.context.view_layer.objects.active
    reset_pose(arm)
    poses = engine.trajectory(scene, frames)[1:]
    REDRAW.update(on=True, draws=[])
    k = [0]

    def put():
        if k[0] >= len(poses):
            REDRAW["on"] = False
            return None
        armature_io.apply_pose(arm, *poses[k[0]])
        k[0] += 1
        return 0.0

    bpy.app.timers.register(put, first_interval=0.0)
    t_end = time.perf_counter() + 600.0
    while REDRAW["on"] and time.perf_counter() < t_end:
        yield 0.05
    REDRAW["on"] = False
    d = REDRAW["draws"]
    return (len(d) - 1) / (d[-1] - d[0]) if len(d) > 1 else 0.0


def window():
    """Generator over the window measures; returns their rows."""
    scene = bpy.context.scene
    scene.render.fps, scene.render.fps_base = 1000, 1.0
    yield 1.0  # let the first full redraw of the new scene pass
    live_scene = scene_dict.build_scene(bpy.context, bpy.context.view_layer.objects.active)
    fps = 0.0
    for _ in range(ARGS.repeat):
        fps = max(fps, (yield from poses_only(live_scene, ARGS.window_frames)))
    print("window: the same poses put on by a plain timer (no engine, no operator): %7.1f fps, "
          "best of %d x %d frames" % (fps, ARGS.repeat, ARGS.window_frames), flush=True)
    rows = [{"steps_per_frame": 1, "poses_only": True, "fps": fps, "frames": ARGS.window_frames,
             "repeat": ARGS.repeat}]
    for n in STEPS:
        runs = []
        for _ in range(ARGS.repeat):
            runs.append((yield from window_run(n, ARGS.window_frames)))
        best = max(runs, key=lambda r: r["fps"])
        best.update(steps_per_frame=n, repeat=ARGS.repeat)
        rows.append(best)
        print("window: pinhead (Fig 9), %2d steps per frame: %7.1f fps (the operator's step %2.0f%% "
              "of the frame; %.2f viewport draws per frame), best of %d x %d frames" % (
                  n, best["fps"], 100 * best["busy_share"], best["draws_per_frame"], ARGS.repeat,
                  ARGS.window_frames), flush=True)
    return rows


def machine():
    info = {"blender": bpy.app.version_string, "background": bpy.app.background,
            "load_average": list(os.getloadavg()), "cpus": os.cpu_count()}
    if not bpy.app.background:
        import gpu
        win, area, region = view3d()
        info.update(renderer=gpu.platform.renderer_get(), window=[win.width, win.height],
                    viewport=[region.width, region.height])
    return info


def write(doc):
    if ARGS.json:
        with open(ARGS.json, "w", encoding="utf-8") as f:
            json.dump(doc, f, indent=1)
        print("wrote", ARGS.json)
    if ARGS.result:
        with open(ARGS.result, "w", encoding="utf-8") as f:
            json.dump({"passed": ["bench_live"], "failed": []}, f)


def main_window():
    """In a window: headless loop, then the real operator, then quit."""
    try:
        arm, scene = fig9_scene()
        doc = {"scene": "models/scenes/fig9_outstretched.json", "machine": None,
               "headless": headless(arm, scene)}
        doc["window"] = yield from window()
        doc["machine"] = machine()
        write(doc)
        code = 0
    except Exception:
        import traceback
        traceback.print_exc()
        code = 1
    sys.stdout.flush()
    os._exit(code)


if bpy.app.background:
    ARM, SCENE = fig9_scene()
    write({"scene": "models/scenes/fig9_outstretched.json", "machine": machine(),
           "headless": headless(ARM, SCENE)})
else:
    RUN = main_window()

    def tick():
        try:
            return next(RUN)
        except StopIteration:
            return None

    bpy.types.SpaceView3D.draw_handler_add(on_draw, (), 'WINDOW', 'POST_PIXEL')
    bpy.types.SpaceView3D.draw_handler_add(on_draw_redraw_only, (), 'WINDOW', 'POST_PIXEL')
    bpy.app.timers.register(tick, first_interval=1.0)
