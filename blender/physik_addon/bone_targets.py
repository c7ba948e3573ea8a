"""Orientation and aim targets as empties (scene format: models/README.md "Scenes",
orientation_targets[] and aim_targets[]).

An empty is a bone target when it carries `physik_target`:
    physik_target     "orientation": the empty's world rotation is the bone's target frame
                      (world <- bone: the empty's local axes are where the bone's local axes
                      should point; +Y along the bone, Blender's convention and the rig's);
                      "aim": the empty's world location is the point the bone's axis turns to
    physik_armature   the armature object
    physik_bone       the bone's name
    physik_axis       aim only, optional: the bone-frame axis that turns (3 numbers; default
                      [0, 1, 0], along the bone)
    physik_k, physik_spring, physik_cap   optional: N m/rad, "linear" | "capped", rad
Blender holds rotations in single precision: the quaternion is normalised in double precision
before it is written (the engine takes a unit quaternion within 1e-6). Such an empty is never a
control point (control_points.py leaves out every empty with `physik_target`).
"""
import math

import bpy
from mathutils import Vector

from .control_points import _check_bone, _number, set_spring_properties, spring_fields
from .rig_format import InputError

KINDS = ("orientation", "aim")


def bone_world_matrix(context, arm, bone):
    """The posed bone's frame in the world, rotation and head: arm.matrix_world @ pose bone
    matrix (armature space), the frame the engine's rig reads (uniform object scale), after the
    view layer has taken the pose just set."""
    context.view_layer.update()
    return arm.matrix_world @ arm.pose.bones[bone].matrix


def _new_empty(context, arm, bone, kind, name, display):
    empty = bpy.data.objects.new(name or "PhysIK %s %s" % (kind, bone), None)
    empty.empty_display_type = display
    empty.empty_display_size = 0.2 * arm.pose.bones[bone].length * arm.matrix_world.median_scale
    empty["physik_target"] = kind
    empty["physik_armature"] = arm
    empty["physik_bone"] = bone
    (context.collection or context.scene.collection).objects.link(empty)
    return empty


def add_orientation_target(context, arm, bone, rotation=None, k=None, spring=None, cap=None,
                           name=None):
    """A new empty at `bone`'s head whose world rotation is the bone's target frame: `rotation`
    (a mathutils Quaternion or (w, x, y, z), world <- bone), or the bone's frame now, for the
    user to turn (R). Raises InputError on bad arguments."""
    source = "orientation target on armature '%s'" % arm.name
    _check_bone(arm, bone, source, "bone")
    frame = bone_world_matrix(context, arm, bone)
    empty = _new_empty(context, arm, bone, "orientation", name, 'ARROWS')
    set_spring_properties(empty, source, k, spring, cap)
    empty.rotation_mode = 'QUATERNION'
    q = frame.to_3x3().normalized().to_quaternion() if rotation is None else rotation
    empty.rotation_quaternion = q
    empty.location = frame.translation
    return empty


def add_aim_target(context, arm, bone, point=None, axis=None, k=None, spring=None, cap=None,
                   name=None):
    """A new empty at `point` (world) that `bone`'s axis turns toward; without a point, one bone
    length beyond its tail, straight ahead. Raises InputError on bad arguments."""
    source = "aim target on armature '%s'" % arm.name
    _check_bone(arm, bone, source, "bone")
    empty = _new_empty(context, arm, bone, "aim", name, 'SPHERE')
    set_spring_properties(empty, source, k, spring, cap)
    if axis is not None:
        a = [_number(x, source, "axis") for x in axis]
        if len(a) != 3 or not any(a):
            raise InputError(source, "", "axis", "must be 3 numbers, not all zero")
        empty["physik_axis"] = a
    if point is None:
        frame = bone_world_matrix(context, arm, bone)
        head, tail = frame.translation, arm.matrix_world @ arm.pose.bones[bone].tail
        point = tail + (tail - head)
    empty.location = Vector(point)
    return empty


def is_bone_target(obj):
    return obj.type == 'EMPTY' and "physik_target" in obj


def _read(obj, arm):
    source = "empty '%s'" % obj.name
    kind = obj["physik_target"]
    if kind not in KINDS:
        raise InputError(source, "", "physik_target",
                         "unknown target %r (orientation|aim)" % (kind,))
    if "physik_bone" not in obj or obj["physik_bone"] in ("", None):
        raise InputError(source, "", "physik_bone",
                         "no bone: set the name of the bone this target turns")
    bone = obj["physik_bone"]
    _check_bone(arm, bone, source, "physik_bone")
    out = {"name": obj.name, "bone": bone}
    m = obj.matrix_world
    if kind == "orientation":
        q = m.to_3x3().normalized().to_quaternion()
        wxyz = [float(c) for c in q]
        norm = math.sqrt(sum(c * c for c in wxyz))
        if not norm > 0.0 or not all(math.isfinite(c) for c in wxyz):
            raise InputError(source, "", "rotation", "no rotation (a zero scale?)")
        out["quaternion"] = [c / norm for c in wxyz]
    else:
        out["point"] = list(m.translation)
        if "physik_axis" in obj:
            a = [_number(x, source, "physik_axis") for x in obj["physik_axis"]]
            if len(a) != 3 or not any(a):
                raise InputError(source, "", "physik_axis", "must be 3 numbers, not all zero")
            out["axis"] = a
    return kind, spring_fields(obj, source, out)


def read_bone_targets(scene, arm):
    """The orientation and aim targets of `arm` in `scene`, in the scene format, each sorted by
    empty name: {"orientation_targets": [...], "aim_targets": [...]}, a key only where there is
    one. Raises InputError for a target empty with no armature, no bone, an invalid or unknown
    bone, an unknown kind or a bad axis/k/spring/cap. Two targets of a kind on one bone: the
    engine's scene reader takes both (each is a spring)."""
    out = {}
    for obj in sorted(scene.objects, key=lambda o: o.name):
        if not is_bone_target(obj):
            continue
        owner = obj.get("physik_armature")
        if owner is None or not isinstance(owner, bpy.types.Object) or owner.type != 'ARMATURE':
            raise InputError("empty '%s'" % obj.name, "", "physik_armature",
                             "no armature: set the armature this target belongs to, or delete "
                             "the empty")
        if owner != arm:
            continue
        kind, target = _read(obj, arm)
        out.setdefault(kind + ("_targets"), []).append(target)
    return out
