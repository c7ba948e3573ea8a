"""The add-on's operators. Bad input and a missing engine become one Blender error report each
(self.report({'ERROR'}, ...), {'CANCELLED'}), never a traceback; the engine is reached only
through engine.py. Operators that change the scene are undoable (bl_options UNDO)."""
import json

import bpy
from bpy.props import FloatProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from . import armature_io, control_points, engine, rig_format, scene_dict
from .rig_format import InputError

START_POSE = "physik_start_pose"  # object property: the pose before the last Solve/Simulate/Bake


def _fail(op, err):
    op.report({'ERROR'}, str(err))
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
            rig = rig_format.load_rig(self.filepath)
            armature_io.rig_to_armature(rig, context, source=self.filepath)
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
            rig = armature_io.armature_to_rig(scene_dict.active_armature(context))
        except InputError as e:
            return _fail(self, e)
        try:
            with open(self.filepath, "w", encoding="utf-8") as f:
                json.dump(rig, f, indent=1)
        except OSError as e:
            return _fail(self, "%s: cannot write file (%s)" % (self.filepath, e.strerror or e))
        return {'FINISHED'}


class PHYSIK_OT_add_control_point(bpy.types.Operator):
    """Add an empty that pulls a bone of the active armature at alpha (the active bone by default)"""
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


class PHYSIK_OT_solve(bpy.types.Operator):
    """Run PhysIK on the active armature until the control points are met"""
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
        self.report({'INFO'}, "PhysIK: %s steps, converged %s" % (
            summary.get("steps_run", "?"), summary.get("converged", "?")))
        return {'FINISHED'}


class PHYSIK_OT_simulate(bpy.types.Operator):
    """Simulate PhysIK live on the active armature (Esc or right click stops, keeping the pose)"""
    bl_idname = "physik.simulate"
    bl_label = "Simulate"
    bl_options = {'REGISTER', 'UNDO'}
    _timer = None

    def execute(self, context):
        try:
            self._arm = scene_dict.active_armature(context)
            self._live = engine.Live(scene_dict.build_scene(context, self._arm))
        except (InputError, engine.EngineError) as e:
            return _fail(self, e)
        _save_start_pose(self._arm)
        self._steps = context.scene.physik.steps_per_frame
        fps = context.scene.render.fps / context.scene.render.fps_base
        self._timer = context.window_manager.event_timer_add(1.0 / fps, window=context.window)
        context.window_manager.modal_handler_add(self)
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        if event.type in {'ESC', 'RIGHTMOUSE'}:
            context.window_manager.event_timer_remove(self._timer)
            return {'FINISHED'}
        if event.type == 'TIMER':
            try:
                head, rotations = self._live.step(self._steps)
            except engine.EngineError as e:
                context.window_manager.event_timer_remove(self._timer)
                return _fail(self, e)
            armature_io.apply_pose(self._arm, head, rotations)
        return {'PASS_THROUGH'}


class PHYSIK_OT_bake(bpy.types.Operator):
    """Run PhysIK for the panel's steps and keyframe the pose every N steps from the current frame"""
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
        self.report({'INFO'}, "PhysIK: %d keyframes, frames %d..%d" % (len(frames), frames[0], frames[-1]))
        return {'FINISHED'}


class PHYSIK_OT_reset(bpy.types.Operator):
    """Return the active armature to the pose before the last Solve, Simulate or Bake (or to rest)"""
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
            self.report({'INFO'}, "PhysIK: no start pose saved; back to rest")
        else:
            rotations = {n: tuple(q) for n, q in start["rotations"].items() if n in arm.pose.bones}
            armature_io.apply_pose(arm, tuple(start["root_head"]), rotations)
        return {'FINISHED'}


CLASSES = (PHYSIK_OT_import_rig, PHYSIK_OT_export_rig, PHYSIK_OT_add_control_point,
           PHYSIK_OT_solve, PHYSIK_OT_simulate, PHYSIK_OT_bake, PHYSIK_OT_reset)
