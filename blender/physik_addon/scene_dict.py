"""The Blender scene as a scene dict for the engine (models/README.md "Scenes"): the armature's
rig inline, the panel's params, the control-point empties, and the current pose as the start."""
from . import armature_io, control_points, settings
from .rig_format import InputError


def active_armature(context):
    """The active armature, or the armature of the active control-point empty; InputError if
    there is none."""
    obj = context.active_object
    if obj is not None and obj.type == 'EMPTY':
        owner = obj.get("physik_armature") or obj.get("fwik_armature")
        if owner is not None and getattr(owner, "type", None) == 'ARMATURE':
            return owner
    return armature_io.require_armature(obj)


def build_scene(context, arm, solve=False):
    """A scene dict for `arm`; raises InputError when the rig or a control point is bad, or when
    there is no control point to pull with."""
    context.view_layer.update()  # world matrices of just-moved empties
    rig = armature_io.armature_to_rig(arm)
    cps = control_points.read_control_points(context.scene, arm)
    if not cps:
        raise InputError(armature_io.armature_source(arm), "", "control points",
                         "none: add one (PhysIK panel > Add control point) before running")
    s = context.scene.physik
    scene = {"rig": rig, "params": settings.params_dict(s), "control_points": cps,
             "steps": s.max_steps, "initial_pose": armature_io.initial_pose_dict(arm)}
    if solve:
        scene["convergence"] = {"stop_at_residual_tol": True}
    return scene
