"""Control points as empties (scene format: models/README.md "Scenes", control_points[]).

An empty is a control point when it carries any of the first three custom properties:
    physik_control_point  true (the marker)
    physik_armature       the armature object
    physik_bone           the bone's name
    physik_alpha          where on the bone, 0 = head .. 1 = tail (default 1)
    physik_k, physik_spring, physik_cap   optional: N/m, "linear" | "capped", rig units
and its world location is the target (an empty with `physik_target` is an orientation or aim
target instead: bone_targets.py). The paper's own file uses the original add-on's
properties (fwik_is_control_point, fwik_armature, fwik_bone_name, fwik_bone_alpha,
fwik_spring_constant, fwik_active); those empties are read too (inactive ones are skipped).
"""
import math

import bpy
from mathutils import Vector

from .rig_format import InputError, bone_name_problem

SPRINGS = ("linear", "capped")


def attachment_point(arm, bone_name, alpha):
    """World position of the point at alpha along the posed bone (0 = head, 1 = tail)."""
    pb = arm.pose.bones[bone_name]
    return arm.matrix_world @ (pb.head.lerp(pb.tail, alpha))


def _check_bone(arm, bone, source, field):
    problem = bone_name_problem(bone)
    if problem:
        raise InputError(source, "", field, "not a valid bone name: " + problem)
    if bone not in arm.data.bones:
        raise InputError(source, "", field, "unknown bone '%s' in armature '%s'" % (bone, arm.name))


def _number(value, source, field, lo=None, hi=None):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(source, "", field, "expected a finite number (got %r)" % (value,))
    if (lo is not None and value < lo) or (hi is not None and value > hi):
        rng = "[%g, %g]" % (lo, hi) if hi is not None else ">= %g" % lo
        raise InputError(source, "", field, "%g is outside %s" % (value, rng))
    return float(value)


def add_control_point(context, arm, bone, alpha=1.0, target=None, k=None, spring=None,
                      cap=None, name=None):
    """A new empty pulling `bone` of `arm` at `alpha`; its location is `target` (world), or the
    attachment point itself when no target is given. Raises InputError on bad arguments."""
    source = "control point on armature '%s'" % arm.name
    _check_bone(arm, bone, source, "bone")
    alpha = _number(alpha, source, "alpha", 0.0, 1.0)
    empty = bpy.data.objects.new(name or "PhysIK %s" % bone, None)
    empty.empty_display_type = 'SPHERE'
    empty.empty_display_size = 0.05
    empty["physik_control_point"] = True
    empty["physik_armature"] = arm
    empty["physik_bone"] = bone
    empty["physik_alpha"] = alpha
    set_spring_properties(empty, source, k, spring, cap)
    empty.location = Vector(target) if target is not None else attachment_point(arm, bone, alpha)
    (context.collection or context.scene.collection).objects.link(empty)
    return empty


def _is_physik(obj):
    # the marker, or either of the two properties that only a control point has among the
    # empties that are not bone targets (bone_targets.py: those carry physik_target)
    return obj.type == 'EMPTY' and "physik_target" not in obj and any(
        k in obj for k in ("physik_control_point", "physik_bone", "physik_armature"))


def _is_legacy(obj):
    return obj.type == 'EMPTY' and bool(obj.get("fwik_is_control_point"))


def _read_physik(obj, arm):
    source = "empty '%s'" % obj.name
    if "physik_bone" not in obj or obj["physik_bone"] in ("", None):
        raise InputError(source, "", "physik_bone",
                         "no bone: set the name of the bone this control point pulls")
    bone = obj["physik_bone"]
    _check_bone(arm, bone, source, "physik_bone")
    cp = {"name": obj.name, "bone": bone,
          "alpha": _number(obj.get("physik_alpha", 1.0), source, "physik_alpha", 0.0, 1.0),
          "target": list(obj.matrix_world.translation)}
    return spring_fields(obj, source, cp)


def set_spring_properties(empty, source, k, spring, cap):
    """An empty's own spring, where given, as its custom properties (spring_fields reads them
    back); a bad k, law or cap raises InputError naming `source`."""
    if k is not None:
        empty["physik_k"] = _number(k, source, "k", 0.0)
    if spring is not None:
        if spring not in SPRINGS:
            raise InputError(source, "", "spring", "unknown law '%s' (linear|capped)" % spring)
        empty["physik_spring"] = spring
    if cap is not None:
        empty["physik_cap"] = _number(cap, source, "cap", 0.0)


def spring_fields(obj, source, out):
    """An empty's own spring, if it gives one (custom properties physik_k, physik_spring,
    physik_cap), into `out` as the scene's "k", "spring" and "cap": a control point's, or a bone
    target's (bone_targets.py)."""
    if "physik_k" in obj:
        out["k"] = _number(obj["physik_k"], source, "physik_k", 0.0)
    if "physik_spring" in obj:
        if obj["physik_spring"] not in SPRINGS:
            raise InputError(source, "", "physik_spring",
                             "unknown law %r (linear|capped)" % (obj["physik_spring"],))
        out["spring"] = obj["physik_spring"]
    if "physik_cap" in obj:
        out["cap"] = _number(obj["physik_cap"], source, "physik_cap", 0.0)
    return out


def _read_legacy(obj, arm):
    source = "empty '%s'" % obj.name
    bone = obj.get("fwik_bone_name")
    if not bone:
        raise InputError(source, "", "fwik_bone_name", "no bone")
    _check_bone(arm, bone, source, "fwik_bone_name")
    cp = {"name": obj.name, "bone": bone,
          "alpha": _number(obj.get("fwik_bone_alpha", 1.0), source, "fwik_bone_alpha", 0.0, 1.0),
          "target": list(obj.matrix_world.translation)}
    if "fwik_spring_constant" in obj:
        cp["k"] = _number(obj["fwik_spring_constant"], source, "fwik_spring_constant", 0.0)
    return cp


def read_control_points(scene, arm):
    """The control points of `arm` in `scene`, in the scene format, sorted by empty name.
    Raises InputError for a control-point empty with no bone, an invalid or unknown bone, a bad
    alpha/k/spring/cap, or no armature."""
    out = []
    for obj in sorted(scene.objects, key=lambda o: o.name):
        if _is_physik(obj):
            owner = obj.get("physik_armature")
            if owner is None:
                raise InputError("empty '%s'" % obj.name, "", "physik_armature",
                                 "no armature: set the armature this control point belongs to, or "
                                 "delete the empty")
            if not isinstance(owner, bpy.types.Object) or owner.type != 'ARMATURE':
                raise InputError("empty '%s'" % obj.name, "", "physik_armature", "not an armature")
            if owner == arm:
                out.append(_read_physik(obj, arm))
        elif _is_legacy(obj) and obj.get("fwik_armature") == arm and obj.get("fwik_active", True):
            out.append(_read_legacy(obj, arm))
    return out
