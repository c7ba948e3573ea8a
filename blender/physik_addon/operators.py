"""The add-on's operators. Bad input, a missing engine and a diverged run become one Blender
error report each (self.report({'ERROR'}, ...), {'CANCELLED'}, nothing changed), never a
traceback; a Solve that stops short of its targets applies the pose it reached with a WARNING
giving the residual. The engine is reached only through engine.py, rig files through rig_io.py.
Operators that change the scene are undoable (bl_options UNDO)."""
import time

import bpy
from bpy.props import FloatProperty, IntProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from . import armature_io, bone_targets, control_points, engine, rig_io, scene_dict
from .rig_format import InputError

START_POSE = "physik_start_pose"  # object property: the pose before the last Solve/Simulate/Bake

# The last report an operator made, {"level": 'INFO' | 'WARNING' | 'ERROR', "text": ...}: Blender
# keeps reports in its window manager, which Python cannot read; the tests read this.
LAST_REPORT = {}


def _report(op, level, text):
    LAST_REPORT.clear()
    LAST_REPORT.update(level=level, text=text)
    op.report({level}, text)


def _fail(op, err):
    _report(op, 'ERROR', str(err))
    return {'CANCELLED'}


def _save_start_pose(arm):
    head, rotations = armature_io.read_pose(arm)
    arm[START_POSE] = {"root_head": list(head),
                       "rotations": {n: list(q) for n, q in rotations.items()}}


class PHYSIK_OT_import_rig(bpy.types.Operator, ImportHelper):
    """Create an armature from a PhysIK rig file (JSON)"""
    bl_idname = "physik.import_rig"
    bl_label = "Import PhysIK rig"
    bl_options = {'REGISTER', 'UNDO'}
    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={'HIDDEN'})

    def execute(self, context):
        try:
            doc, rig = rig_io.load(self.filepath)
            armature_io.rig_to_armature(rig, context, source=self.filepath, doc=doc)
        except InputError as e:
            return _fail(self, e)
        return {'FINISHED'}


class PHYSIK_OT_export_rig(bpy.types.Operator, ExportHelper):
    """Write the active armature as a PhysIK rig file (JSON)"""
    bl_idname = "physik.export_rig"
    bl_label = "Export PhysIK rig"
    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={'HIDDEN'})

    def execute(self, context):
        try:
            arm = scene_dict.active_armature(context)
            rig = armature_io.armature_to_rig(arm)
            rig_io.save(rig, self.filepath, armature_io.armature_source(arm))
        except InputError as e:
            return _fail(self, e)
        return {'FINISHED'}


class PHYSIK_OT_add_control_point(bpy.types.Operator):
    """Add an empty pulling a bone of the active armature at alpha (default: the active bone)"""
    bl_idname = "physik.add_control_point"
    bl_label = "Add control point"
    bl_options = {'REGISTER', 'UNDO'}
    bone: StringProperty(name="Bone", description="bone name; empty = the active bone")
    alpha: FloatProperty(name="Alpha", default=1.0, min=0.0, max=1.0,
                         description="where on the bone: 0 = head, 1 = tail")

    def execute(self, context):
        try:
            arm = scene_dict.active_armature(context)
            bone = self.bone
            if not bone and arm.data.bones.active is not None:
                bone = arm.data.bones.active.name
            if not bone:
                raise InputError("armature '%s'" % arm.name, "", "bone",
                                 "no bone given and no active bone")
            control_points.add_control_point(context, arm, bone, self.alpha)
        except InputError as e:
            return _fail(self, e)
        return {'FINISHED'}


def _active_bone(self, arm):
    bone = self.bone
    if not bone and arm.data.bones.active is not None:
        bone = arm.data.bones.active.name
    if not bone:
        raise InputError("armature '%s'" % arm.name, "", "bone", "no bone given and no active bone")
    return bone


class PHYSIK_OT_add_orientation_target(bpy.types.Operator):
    """Add an empty at a bone's head whose rotation is the bone's target frame (default: the
    active bone, its frame now): turn the empty (R) to turn the bone"""
    bl_idname = "physik.add_orientation_target"
    bl_label = "Add orientation target"
    bl_options = {'REGISTER', 'UNDO'}
    bone: StringProperty(name="Bone", description="bone name; empty = the active bone")

    def execute(self, context):
        try:
            arm = scene_dict.active_armature(context)
            bone_targets.add_orientation_target(context, arm, _active_bone(self, arm))
        except InputError as e:
            return _fail(self, e)
        return {'FINISHED'}


class PHYSIK_OT_add_aim_target(bpy.types.Operator):
    """Add an empty that a bone's axis turns toward (default: the active bone; the empty one
    bone length beyond its tail): move the empty (G) to aim the bone"""
    bl_idname = "physik.add_aim_target"
    bl_label = "Add aim target"
    bl_options = {'REGISTER', 'UNDO'}
    bone: StringProperty(name="Bone", description="bone name; empty = the active bone")

    def execute(self, context):
        try:
            arm = scene_dict.active_armature(context)
            bone_targets.add_aim_target(context, arm, _active_bone(self, arm))
        except InputError as e:
            return _fail(self, e)
        return {'FINISHED'}


class PHYSIK_OT_solve(bpy.types.Operator):
    """Run PhysIK on the active armature until its control points and bone targets are met"""
    bl_idname = "physik.solve"
    bl_label = "Solve"
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        try:
            arm = scene_dict.active_armature(context)
            scene = scene_dict.build_scene(context, arm, solve=True)
            (head, rotations), summary = engine.solve(scene)
        except (InputError, engine.EngineError) as e:
            return _fail(self, e)
        _save_start_pose(arm)
        armature_io.apply_pose(arm, head, rotations)
        _report(self, *solve_report(summary))
        return {'FINISHED'}


def solve_report(summary):
    """(level, text) of a Solve that did not diverge: INFO when every control point is within
    the tolerance, else WARNING (the run stopped at its step count, or stalled short)."""
    residuals = summary["final_residuals"]
    if isinstance(residuals, dict):
        residuals = list(residuals.values())
    worst = max(residuals) if residuals else 0.0
    facts = "%d steps, largest residual %.3g (tolerance %.3g)" % (
        summary["steps_run"], worst, summary["residual_tol"])
    if summary["converged"]:
        return 'INFO', "PhysIK: converged: " + facts
    return 'WARNING', ("PhysIK: not converged: %s; the pose reached is applied (more steps, "
                       "or targets the rig can reach)" % facts)


# The running or last Simulate, for tests and blender/bench_live.py (one at a time is shown):
#   running, frames (timer events stepped), steps_per_frame, steps (the engine's step count),
#   seconds (first to last frame), busy_seconds (in the operator: engine and pose),
#   final_state_hash (the engine's, once stopped), stopped_by ('esc', 'max_frames', 'error',
#   'cancel')
LIVE = {}


class PHYSIK_OT_simulate(bpy.types.Operator):
    """Simulate PhysIK live on the active armature (Esc or right click stops, keeping the pose)"""
    bl_idname = "physik.simulate"
    bl_label = "Simulate"
    bl_options = {'REGISTER', 'UNDO'}
    max_frames: IntProperty(name="Frames", default=0, min=0, options={'SKIP_SAVE'},
                            description="stop after this many frames (0: run until Esc)")
    _timer = None

    def execute(self, context):
        try:
            arm = scene_dict.active_armature(context)
            self._live = engine.Live(scene_dict.build_scene(context, arm))
        except (InputError, engine.EngineError) as e:
            return _fail(self, e)
        if context.window is None or bpy.app.background:
            return _fail(self, "Simulate runs in Blender's window (a timer steps it every frame, "
                               "and timers do not run in background mode); use Bake or Solve")
        _save_start_pose(arm)
        self._arm_name = arm.name  # looked up every frame: an undo replaces the object
        self._steps = context.scene.physik.steps_per_frame
        self._last_duration = None
        LIVE.clear()
        LIVE.update(running=True, frames=0, steps_per_frame=self._steps, steps=0, seconds=0.0,
                    busy_seconds=0.0, final_state_hash=None, stopped_by=None)
        fps = context.scene.render.fps / context.scene.render.fps_base
        self._timer = context.window_manager.event_timer_add(1.0 / fps, window=context.window)
        context.window_manager.modal_handler_add(self)
        return {'RUNNING_MODAL'}

    def _stop(self, context, why):
        if self._timer is not None:
            context.window_manager.event_timer_remove(self._timer)
            self._timer = None
        LIVE.update(running=False, stopped_by=why, steps=self._live.sim.step_count,
                    final_state_hash=self._live.sim.summary["final_state_hash"])

    def modal(self, context, event):
        if event.type in {'ESC', 'RIGHTMOUSE'}:
            self._stop(context, "esc")
            _report(self, 'INFO', "PhysIK: live run stopped after %d frames (%d steps)"
                    % (LIVE["frames"], LIVE["steps"]))
            return {'FINISHED'}
        # other timers of the window send TIMER events too: step only on this one's
        if event.type != 'TIMER' or self._timer.time_duration == self._last_duration:
            return {'PASS_THROUGH'}
        self._last_duration = self._timer.time_duration
        t0 = time.perf_counter()
        arm = bpy.data.objects.get(self._arm_name)
        if arm is None or arm.type != 'ARMATURE':
            self._stop(context, "error")
            return _fail(self, "armature '%s' is gone; the live simulation stopped"
                         % self._arm_name)
        try:
            head, rotations = self._live.step(self._steps)
        except engine.EngineError as e:
            self._stop(context, "error")
            return _fail(self, e)
        armature_io.apply_pose(arm, head, rotations)
        t1 = time.perf_counter()
        if LIVE["frames"] == 0:
            self._t_first = t1
        LIVE["frames"] += 1
        LIVE["seconds"] = t1 - self._t_first
        LIVE["busy_seconds"] += t1 - t0
        if self.max_frames and LIVE["frames"] >= self.max_frames:
            self._stop(context, "max_frames")
            return {'FINISHED'}
        return {'PASS_THROUGH'}

    def cancel(self, context):
        """Blender ends the operator (a file is loaded, the window closes)."""
        self._stop(context, "cancel")


class PHYSIK_OT_bake(bpy.types.Operator):
    """Run PhysIK for the panel's steps; keyframe the pose every N steps from the current frame"""
    bl_idname = "physik.bake"
    bl_label = "Bake"
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        s = context.scene.physik
        try:
            arm = scene_dict.active_armature(context)
            poses = engine.trajectory(scene_dict.build_scene(context, arm), s.max_steps)
        except (InputError, engine.EngineError) as e:
            return _fail(self, e)
        _save_start_pose(arm)
        frame = context.scene.frame_current
        frames = armature_io.bake_keyframes(arm, poses, frame, s.bake_every)
        # show the keyed pose of the current frame (the channels hold the last key's until then)
        context.scene.frame_set(frame)
        _report(self, 'INFO', "PhysIK: %d keyframes, frames %d..%d"
                % (len(frames), frames[0], frames[-1]))
        return {'FINISHED'}


class PHYSIK_OT_reset(bpy.types.Operator):
    """Return the armature to the pose before the last Solve, Simulate or Bake (or to rest)"""
    bl_idname = "physik.reset"
    bl_label = "Reset"
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        try:
            arm = scene_dict.active_armature(context)
        except InputError as e:
            return _fail(self, e)
        start = arm.get(START_POSE)
        if start is None:
            for pb in arm.pose.bones:
                pb.location = (0.0, 0.0, 0.0)
                armature_io.set_rotation(pb, (1.0, 0.0, 0.0, 0.0))
            _report(self, 'INFO', "PhysIK: no start pose saved; back to rest")
        else:
            rotations = {n: tuple(q) for n, q in start["rotations"].items() if n in arm.pose.bones}
            armature_io.apply_pose(arm, tuple(start["root_head"]), rotations)
        return {'FINISHED'}


CLASSES = (PHYSIK_OT_import_rig, PHYSIK_OT_export_rig, PHYSIK_OT_add_control_point,
           PHYSIK_OT_add_orientation_target, PHYSIK_OT_add_aim_target, PHYSIK_OT_solve, PHYSIK_OT_simulate, PHYSIK_OT_bake, PHYSIK_OT_reset)
