"""The Blender scene as a scene dict for the engine (models/README.md "Scenes"): the armature's
rig inline, the panel's params, the control-point empties, the orientation- and aim-target
empties (bone_targets.py), the current pose as the start, and,
with the panel's Collide on, the contacts (collision_dict): a floor, self-collision, and the mesh
objects of the collection "PhysIK Obstacles" as box obstacles (obstacle_box)."""
import math

import bpy
from mathutils import Vector

from . import armature_io, bone_targets, control_points, rig_format, settings
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
    """A scene dict for `arm`; raises InputError when the rig, a control point or a bone target
    is bad, or when there is no control point to pull with."""
    context.view_layer.update()  # world matrices of just-moved empties
    rig = armature_io.armature_to_rig(arm)
    cps = control_points.read_control_points(context.scene, arm)
    if not cps:
        raise InputError(armature_io.armature_source(arm), "", "control points",
                         "none: add one (PhysIK panel > Add control point) before running")
    s = context.scene.physik
    scene = {"rig": rig, "params": settings.params_dict(s), "control_points": cps,
             "steps": s.max_steps, "initial_pose": armature_io.initial_pose_dict(arm)}
    scene.update(bone_targets.read_bone_targets(context.scene, arm))
    if s.collide:
        scene.update(collision_dict(rig, obstacle_boxes(context)))
    if solve:
        # the engine's residual rule reads the control points and the orientation and aim
        # targets' arcs (physik/engine/measures.h, the goal residual): a Solve stops once all
        # are met
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


def collision_dict(rig, obstacles=()):
    """The scene's contacts for Collide: a floor through the rig's lowest rest point, facing +z
    (the rig at rest stands on it, touching, not sunk in), self-collision, and the `obstacles`
    (scene entries, obstacle_boxes) where there are any. Rig units are Blender's world units
    (armature_io reads heads and tails through the object's matrix). The add-on has no gravity
    setting: the scene's gravity stays the engine's default (none)."""
    out = {"ground": {"height": lowest_rest_point(rig), "normal": [0.0, 0.0, 1.0]},
           "self_collision": True}
    if obstacles:
        out["obstacles"] = list(obstacles)
    return out


OBSTACLES_COLLECTION = "PhysIK Obstacles"
AXIS_NAMES = "xyz"
SHEAR_TOL = 1e-5  # |cos| between two of the object's axes: Blender's matrices are single precision


def obstacle_source(obj):
    return "obstacle '%s' (collection '%s')" % (obj.name, OBSTACLES_COLLECTION)


def obstacle_boxes(context):
    """The scene entries of the mesh objects in the collection "PhysIK Obstacles" (its child
    collections' too) that are in the context's scene, by object name; other objects there
    (empties, lights: a parent that groups the boxes) are left out; none without the collection."""
    coll = bpy.data.collections.get(OBSTACLES_COLLECTION)
    if coll is None:
        return []
    in_scene = context.scene.objects
    meshes = [o for o in coll.all_objects if o.type == 'MESH' and in_scene.get(o.name) == o]
    return [{"name": o.name, "box": obstacle_box(o)} for o in sorted(meshes, key=lambda o: o.name)]


def obstacle_box(obj):
    """A mesh object as a box obstacle (models/README.md "Scenes", `obstacles`): the oriented box
    of its mesh's bounds (Object.bound_box: the evaluated mesh's axis-aligned box in the object's
    own axes, lo to hi) carried into the world by the object's world matrix M = [A t]:
        center       = M (lo + hi) / 2                      world, rig units
        half_extents = s_i (hi_i - lo_i) / 2,  s_i = |A e_i|  along the box's own axes
        rotation_deg = the rotation vector of R = [A e_1 / s_1, A e_2 / s_2, A e_3 / s_3], deg
    Rig units and axes are Blender's world units and axes, as for the bones. A mirrored object
    (det A < 0) has its first axis turned back (a box is its own mirror image). InputError
    naming the object: sheared axes (a parent scaled unevenly under a rotation: no box), or no
    thickness along an axis (a plane, a zero scale: the engine's half extents are > 0)."""
    src = obstacle_source(obj)
    corners = [tuple(c) for c in obj.bound_box]
    lo = [min(c[i] for c in corners) for i in range(3)]
    hi = [max(c[i] for c in corners) for i in range(3)]
    m = obj.matrix_world
    a = m.to_3x3()
    cols = [a.col[i].copy() for i in range(3)]
    scale = [c.length for c in cols]
    half = [scale[i] * (hi[i] - lo[i]) / 2.0 for i in range(3)]
    for i in range(3):
        if not half[i] > 0.0:
            raise InputError(src, "", "dimensions",
                             "no thickness along its local %s axis (a plane, or a zero scale): a "
                             "box obstacle needs all three (give it some: Solidify, or Scale)"
                             % AXIS_NAMES[i])
    for i, j in ((0, 1), (0, 2), (1, 2)):
        if abs(cols[i].dot(cols[j])) > SHEAR_TOL * scale[i] * scale[j]:
            raise InputError(src, "", "scale",
                             "its axes are sheared (a parent's uneven scale under a rotation): "
                             "it has no oriented box; apply the parent's scale first "
                             "(Object > Apply > Scale)")
    r = a.copy()
    for i in range(3):
        r.col[i] = cols[i] / scale[i]
    if r.determinant() < 0.0:
        r.col[0] = -r.col[0]
    axis, angle = r.to_quaternion().to_axis_angle()
    center = m @ Vector([(lo[i] + hi[i]) / 2.0 for i in range(3)])
    return {"center": list(center), "half_extents": half,
            "rotation_deg": [math.degrees(angle) * x for x in axis]}
