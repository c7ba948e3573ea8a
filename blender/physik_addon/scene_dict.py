"""The Blender scene as a scene dict for the engine (models/README.md "Scenes"): the armature's
rig inline, the panel's params, the control-point empties, the current pose as the start, and,
with the panel's Collide on, the contacts (collision_dict)."""
import math

from . import armature_io, control_points, rig_format, settings
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
    if s.collide:
        scene.update(collision_dict(rig))
    if solve:
        scene["convergence"] = {"stop_at_residual_tol": True}
    return scene


def collision_radius(rig, bone):
    """A bone's contact capsule radius, rig units, as the engine takes it (rig.cpp): its own
    collision_radius, else the rig's default, else COLLISION_RADIUS_PER_LENGTH x its length."""
    r = bone.get("collision_radius") or (rig.get("defaults") or {}).get("collision_radius")
    return r if r else rig_format.COLLISION_RADIUS_PER_LENGTH * math.dist(bone["head"],
                                                                          bone["tail"])


def lowest_rest_point(rig):
    """The rig's lowest point along world z at rest, rig units: the bottom of the lowest end
    sphere of the bones' contact capsules (min over bones and ends of z - collision radius)."""
    return min(min(b["head"][2], b["tail"][2]) - collision_radius(rig, b) for b in rig["bones"])


def collision_dict(rig):
    """The scene's contacts for Collide: a floor through the rig's lowest rest point, facing +z
    (the rig at rest stands on it, touching, not sunk in), and self-collision. Rig units are
    Blender's world units (armature_io reads heads and tails through the object's matrix).
    The add-on has no gravity setting: the scene's gravity stays the engine's default (none)."""
    return {"ground": {"height": lowest_rest_point(rig), "normal": [0.0, 0.0, 1.0]},
            "self_collision": True}
