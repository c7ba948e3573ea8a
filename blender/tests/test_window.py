"""The add-on in a real Blender window (ctest: blender_window), on a virtual display:

    blender/tests/window_runner.py --blender blender --event-simulate --result window.json \\
        blender/tests/test_window.py -- --repo . --pythonpath build/python

Background mode (-b) has no event loop: window-manager timers never fire, so the Simulate
operator's modal path, and undo as the keyboard reaches it, need a window. Keys are real events
(Window.event_simulate with --enable-event-simulate: the same path as a key press, through the
keymap). The cases run one after another from a bpy.app.timers callback, between them Blender's
event loop runs; the result goes to --result (JSON) and the exit status.

  undo_solve_ctrl_z      Solve (called as the panel's button: with an undo push), then Ctrl+Z:
                         the armature is exactly in the pose before Solve (channels and posed
                         heads/tails equal: the memfile undo restores the stored floats);
                         Shift+Ctrl+Z: exactly the solved pose again.
  simulate_max_frames    Simulate at 1 step per frame with max_frames = 12 stops by itself after
                         12 timer frames; the engine ran 12 steps and its state hash equals
                         engine.Live(scene) after 12 x step(1); the armature holds that pose
                         (root head 1e-6, rotations 1e-6: single precision); the viewport drew
                         every frame (a draw handler saw frames 1..12); Ctrl+Z: the start pose.
  simulate_esc           10 steps per frame, stopped with Esc after at least 4 frames: steps = 10
                         x frames, the state hash of Live after frames x step(10), its pose on
                         the armature; Ctrl+Z: the start pose; Shift+Ctrl+Z: the live pose.
  undo_during_simulate   Ctrl+Z while Simulate runs reverts the armature (a new Python object);
                         the operator keeps stepping on it (no traceback, no error), and after
                         Esc the counts, hash and pose are as above.
"""
import json
import math
import os
import sys
import time
import traceback

import bpy


sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_harness import clear_scene, enable_addon, script_args  # noqa: E402

ARGS = script_args((["--pythonpath"], {"required": True, "help": "the folder holding the physik package"}),
                   (["--result"], {"required": True, "help": "JSON file: passed and failed cases"}))
REPO = os.path.abspath(ARGS.repo)
bpy.context.preferences.view.show_splash = False  # its popup would take the key events
enable_addon(REPO, "test_window.py", ARGS.pythonpath)

from physik_addon import (armature_io, control_points, engine, operators,  # noqa: E402
                          rig_format, scene_dict)

POSED_TOL = 1e-6  # root head (rig units) and quaternion components: Blender's single precision
HAND_TARGET = (-2.4, -0.6, 1.5)
WAIT = 60.0       # seconds any one wait may take (a software-rendered frame takes ~0.1..0.5 s)


# --- the scene ---------------------------------------------------------------------------------



def fig9_armature(steps_per_frame):
    """pinhead with Fig 9's control points and params, active; one undo step 'set up'."""
    clear_scene()
    with open(os.path.join(REPO, "models", "scenes", "fig9_outstretched.json")) as f:
        doc = json.load(f)
    arm = armature_io.rig_to_armature(
        rig_format.load_rig(os.path.join(REPO, "models", "rigs", "pinhead.json")), bpy.context)
    for cp in doc["control_points"]:
        control_points.add_control_point(bpy.context, arm, cp["bone"], cp["alpha"], cp["target"],
                                         name=cp["name"])
    s = bpy.context.scene.physik
    s.preset, s.control_k = doc["params"]["preset"], doc["params"]["control_k"]
    s.max_steps = doc["steps"]
    s.steps_per_frame = steps_per_frame
    bpy.context.view_layer.objects.active = arm
    bpy.ops.ed.undo_push(message="set up")
    return arm.name


def snapshot(name):
    """The pose exactly: channels as stored, posed heads and tails (by name: undo re-reads)."""
    arm = bpy.data.objects[name]
    bpy.context.view_layer.update()
    channels = {pb.name: (tuple(pb.location), tuple(pb.rotation_quaternion),
                          tuple(pb.rotation_euler), tuple(pb.rotation_axis_angle))
                for pb in arm.pose.bones}
    posed = {n: (tuple(h), tuple(t)) for n, _, h, t in armature_io.posed_bones_world(arm)}
    return channels, posed


def pose_error(name, pose):
    """Largest difference between the armature's channels and an engine Pose: root head (rig
    units) and quaternion components (sign-blind)."""
    head, rotations = armature_io.read_pose(bpy.data.objects[name])
    worst = max(abs(a - b) for a, b in zip(head, pose[0]))
    for bone, q in pose[1].items():
        got = tuple(rotations[bone])
        worst = max(worst, min(max(abs(a - b) for a, b in zip(got, q)),
                               max(abs(a + b) for a, b in zip(got, q))))
    return worst


# --- the window and its events -----------------------------------------------------------------

def view3d():
    win = bpy.context.window_manager.windows[0]
    area = next(a for a in win.screen.areas if a.type == 'VIEW_3D')
    region = next(r for r in area.regions if r.type == 'WINDOW')
    return win, area, region


def call(op, *args, **props):
    """Run an operator in the 3D viewport as its button would (with an undo push)."""
    win, area, region = view3d()
    with bpy.context.temp_override(window=win, area=area, region=region):
        return op('INVOKE_DEFAULT', True, *args, **props)


def press(key, ctrl=False, shift=False):
    """A key press and release with the mouse over the viewport, modifiers held around it."""
    win, _, region = view3d()
    xy = {"x": region.x + region.width // 2, "y": region.y + region.height // 2}
    win.event_simulate(type='MOUSEMOVE', value='NOTHING', **xy)
    mods = [m for m, on in (('LEFT_CTRL', ctrl), ('LEFT_SHIFT', shift)) if on]
    for m in mods:
        win.event_simulate(type=m, value='PRESS', **xy)
    win.event_simulate(type=key, value='PRESS', ctrl=ctrl, shift=shift, **xy)
    win.event_simulate(type=key, value='RELEASE', ctrl=ctrl, shift=shift, **xy)
    for m in reversed(mods):
        win.event_simulate(type=m, value='RELEASE', **xy)


def wait_until(cond, what, timeout=WAIT):
    """Let Blender's event loop run until cond() holds (AssertionError after timeout s)."""
    t_end = time.perf_counter() + timeout
    while not cond():
        if time.perf_counter() > t_end:
            raise AssertionError("waited %g s for %s" % (timeout, what))
        yield 0.02


def check(cond, message):
    if not cond:
        raise AssertionError(message)


DRAWN = set()  # LIVE frame counts the viewport has drawn (cleared before a run)


def on_draw():
    if "frames" in operators.LIVE:
        DRAWN.add(operators.LIVE["frames"])


# --- the cases ---------------------------------------------------------------------------------

def undo_solve_ctrl_z():
    name = fig9_armature(1)
    before = snapshot(name)
    check(call(bpy.ops.physik.solve) == {'FINISHED'}, "Solve did not finish")
    solved = snapshot(name)
    hand = solved[1]["hand.R"][1]
    check(math.dist(hand, HAND_TARGET) < 5e-3, "Solve did not reach the hand target: %s" % (hand,))
    press('Z', ctrl=True)
    yield from wait_until(lambda: snapshot(name) == before, "Ctrl+Z to restore the pose before Solve")
    press('Z', ctrl=True, shift=True)
    yield from wait_until(lambda: snapshot(name) == solved, "Shift+Ctrl+Z to restore the solved pose")


def live_reference(scene, frames, steps_per_frame):
    live = engine.Live(scene)
    pose = None
    for _ in range(frames):
        pose = live.step(steps_per_frame)
    return live, pose


def check_live_run(name, scene, steps_per_frame, stopped_by):
    live = operators.LIVE
    frames = live["frames"]
    check(live["stopped_by"] == stopped_by, "stopped by %r, expected %r" % (live["stopped_by"], stopped_by))
    check(live["steps_per_frame"] == steps_per_frame, "steps per frame %r" % live["steps_per_frame"])
    check(live["steps"] == steps_per_frame * frames,
          "%d engine steps after %d frames of %d" % (live["steps"], frames, steps_per_frame))
    ref, pose = live_reference(scene, frames, steps_per_frame)
    check(ref.sim.step_count == live["steps"], "reference step count")
    check(live["final_state_hash"] == ref.sim.summary["final_state_hash"],
          "state hash %s, engine.Live after %d x step(%d): %s" % (
              live["final_state_hash"], frames, steps_per_frame, ref.sim.summary["final_state_hash"]))
    err = pose_error(name, pose)
    check(err < POSED_TOL, "the armature is %.3g from the engine's pose" % err)
    print("  %d frames x %d steps = %d steps, hash %s, armature within %.1e of the engine, "
          "%.1f frames/s in the operator's loop" % (frames, steps_per_frame, live["steps"],
                                                    live["final_state_hash"], err,
                                                    (frames - 1) / max(live["seconds"], 1e-9)))
    return frames


def simulate_max_frames():
    name = fig9_armature(1)
    before = snapshot(name)
    scene = scene_dict.build_scene(bpy.context, bpy.data.objects[name])
    operators.LIVE.clear()
    DRAWN.clear()
    check(call(bpy.ops.physik.simulate, max_frames=12) == {'RUNNING_MODAL'}, "Simulate did not start")
    check(operators.LIVE["running"], "not running")
    yield from wait_until(lambda: not operators.LIVE["running"], "Simulate to stop after 12 frames")
    check(operators.LIVE["frames"] == 12, "%d frames, expected 12" % operators.LIVE["frames"])
    check_live_run(name, scene, 1, "max_frames")
    # the last frame's redraw comes after the operator returns
    yield from wait_until(lambda: 12 in DRAWN, "the viewport to draw frame 12")
    missing = sorted(set(range(1, 13)) - DRAWN)
    check(not missing, "frames never drawn in the viewport: %s (drawn %s)" % (missing, sorted(DRAWN)))
    print("  viewport drew frames %s" % sorted(DRAWN))
    press('Z', ctrl=True)
    yield from wait_until(lambda: snapshot(name) == before, "Ctrl+Z to restore the start pose")


def simulate_esc():
    name = fig9_armature(10)
    before = snapshot(name)
    scene = scene_dict.build_scene(bpy.context, bpy.data.objects[name])
    check(call(bpy.ops.physik.simulate) == {'RUNNING_MODAL'}, "Simulate did not start")
    yield from wait_until(lambda: operators.LIVE["frames"] >= 4, "4 frames")
    press('ESC')
    yield from wait_until(lambda: not operators.LIVE["running"], "Esc to stop Simulate")
    check(operators.LIVE["frames"] >= 4, "frames %d" % operators.LIVE["frames"])
    check_live_run(name, scene, 10, "esc")
    after = snapshot(name)
    press('Z', ctrl=True)
    yield from wait_until(lambda: snapshot(name) == before, "Ctrl+Z to restore the start pose")
    press('Z', ctrl=True, shift=True)
    yield from wait_until(lambda: snapshot(name) == after, "Shift+Ctrl+Z to restore the live pose")


def undo_during_simulate():
    name = fig9_armature(1)
    scene = scene_dict.build_scene(bpy.context, bpy.data.objects[name])
    check(call(bpy.ops.physik.simulate) == {'RUNNING_MODAL'}, "Simulate did not start")
    yield from wait_until(lambda: operators.LIVE["frames"] >= 3, "3 frames")
    old = bpy.data.objects[name]
    press('Z', ctrl=True)
    yield from wait_until(lambda: _replaced(old), "Ctrl+Z to re-read the armature")
    at_undo = operators.LIVE["frames"]
    yield from wait_until(lambda: operators.LIVE["frames"] >= at_undo + 3, "3 more frames after Ctrl+Z")
    check(operators.LIVE["running"], "Simulate stopped after Ctrl+Z: %r" % operators.LIVE["stopped_by"])
    press('ESC')
    yield from wait_until(lambda: not operators.LIVE["running"], "Esc to stop Simulate")
    check_live_run(name, scene, 1, "esc")


def _replaced(obj):
    try:
        obj.name
        return False
    except ReferenceError:  # undo replaced the Python object
        return True


CASES = [undo_solve_ctrl_z, simulate_max_frames, simulate_esc, undo_during_simulate]


# --- the runner --------------------------------------------------------------------------------

def run_all():
    result = {"passed": [], "failed": [], "gpu": None, "window": None}
    import gpu
    result["gpu"] = gpu.platform.renderer_get()
    win, _, region = view3d()
    result["window"] = [win.width, win.height]
    yield 0.5
    for case in CASES:
        print("%s ..." % case.__name__, flush=True)
        t0 = time.perf_counter()
        try:
            yield from case()
            result["passed"].append(case.__name__)
            print("%s ok (%.1f s)" % (case.__name__, time.perf_counter() - t0), flush=True)
        except Exception:
            result["failed"].append({"case": case.__name__, "error": traceback.format_exc()})
            print("%s FAILED\n%s" % (case.__name__, traceback.format_exc()), flush=True)
        if operators.LIVE.get("running"):  # a failed case may leave Simulate running
            press('ESC')
            yield 0.5
    with open(ARGS.result, "w", encoding="utf-8") as f:
        json.dump(result, f, indent=1)
    print("test_window.py: %d passed, %d failed (%s, window %dx%d)" % (
        len(result["passed"]), len(result["failed"]), result["gpu"], *result["window"]), flush=True)
    sys.stdout.flush()
    os._exit(0 if not result["failed"] else 1)  # no quit.blend, and the exit status kept


RUNNER = run_all()


def tick():
    try:
        return next(RUNNER)
    except StopIteration:
        return None
    except Exception:
        traceback.print_exc()
        os._exit(1)


bpy.types.SpaceView3D.draw_handler_add(on_draw, (), 'WINDOW', 'POST_PIXEL')
bpy.app.timers.register(tick, first_interval=0.5)
