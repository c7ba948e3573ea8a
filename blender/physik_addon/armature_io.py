"""Blender armatures <-> the project's rigs, and poses on them.

Reading (armature_to_rig): bones in DFS order from the one root; world heads, tails and rest
frames from the bones' armature-space matrices (the edit bones' matrices: roll included; in edit
mode the edit bones themselves) and the object's matrix; per-axis limits from the pose bones:
    lock_ik_<a>                      -> [0, 0] (locked)
    use_ik_limit_<a>, ik_min/max_<a> -> [deg(min), deg(max)]
    neither                          -> absent (free)
which is what models/tools/make_rigs.py does with shared/data/pinhead_rig.json (it keeps the axes
whose `ik_limit` flag is set, and the paper's file locks no axis). Blender's own IK reads these
numbers with its own joint parametrisation; the project reads them as rotation-vector components.
Mass: pose-bone properties `physik_mass` (kg) or `physik_mass_per_length` (kg per rig unit), else
the original add-on's `fwik_mass` (per length: its final wrappers.py, FWIKBone.get_mass, returns
fwik_mass x length), else the armature's `physik_mass_per_length` default; radius likewise from
`physik_radius`, the contact capsule's from `physik_collision_radius` (rig units); explicit
moments from `physik_inertia_local` (3 numbers, kg m^2); free text from `physik_comment` (bones
and armature data), `physik_source`, `physik_units`; the rig's name from `physik_rig_name`;
a weld (models/README.md "Welded bones and the root's joint") from the pose bone's
`physik_weld` (the bone it is welded to), the root's joint from the armature's `physik_root`.
Absent = the rig defaults (1 kg per unit, radius 0.5; the contact capsule 0.06 x the length).

Writing (rig_to_armature): one edit bone per rig bone, connected to its parent, its roll set so
that the bone's z axis is the rig frame's z (EditBone.align_roll); limits back as above ([0, 0]
sets lock_ik and a zero-width limit). Blender only holds min <= 0 <= max (ik_min in [-180, 0],
ik_max in [0, 180]): other limits are refused, not clamped.

Blender stores bones and limits in single precision: its own values come back to ~1e-7 of their
size (limits to ~1e-7 rad). An armature imported from a rig file keeps the file's doubles beside
them (rig_record.py), and reading it gives those back wherever Blender's values are unchanged:
export then reproduces the file, and a run on it is the run on the file. Custom properties hold
doubles, so masses, radii, moments and defaults are exact either way.
"""
import math

import bpy
from mathutils import Quaternion, Vector

from . import rig_format, rig_record
from .rig_format import AXES, InputError


def armature_source(obj):
    return "armature '%s'" % obj.name


def _world_similarity(obj):
    """The object's 3x3 matrix and its uniform scale; shear, non-uniform or negative scale raise."""
    m = obj.matrix_world.to_3x3()
    det = m.determinant()
    if not det > 0.0:
        raise InputError(armature_source(obj), "", "scale",
                         "negative or zero object scale; apply it first (Object > Apply > Scale)")
    s = det ** (1.0 / 3.0)
    gram = (m.transposed() @ m) * (1.0 / (s * s))
    if max(abs(gram[r][c] - (1.0 if r == c else 0.0)) for r in range(3) for c in range(3)) > 1e-5:
        raise InputError(armature_source(obj), "", "scale", "non-uniform object scale or "
                         "shear; apply it first (Object > Apply > Scale)")
    return m, s


def _bone_records(obj):
    """(name, parent name or None, head, tail, 3x3 rest matrix) in armature space, edit bones in
    edit mode (where they may differ from the saved bones), the saved bones otherwise."""
    if obj.mode == 'EDIT':
        bones = obj.data.edit_bones  # live in edit mode (leaving it would drop zero-length bones)
        return [(b.name, b.parent.name if b.parent else None, Vector(b.head), Vector(b.tail),
                 b.matrix.to_3x3()) for b in bones]
    return [(b.name, b.parent.name if b.parent else None, Vector(b.head_local),
             Vector(b.tail_local), b.matrix_local.to_3x3()) for b in obj.data.bones]


def _dfs(records, source):
    """Records in DFS order from the one root, children in Blender's order."""
    roots = [r for r in records if r[1] is None]
    if not roots:
        raise InputError(source, "", "bones", "the armature has no bones")
    if len(roots) > 1:
        raise InputError(source, "bone '%s'" % roots[1][0], "parent", "a second root (bone '%s' is "
                         "already the root; a rig has exactly one): parent it" % roots[0][0])
    children = {}
    for r in records:
        children.setdefault(r[1], []).append(r)
    order, stack = [], [roots[0]]
    while stack:
        r = stack.pop()
        order.append(r)
        stack.extend(reversed(children.get(r[0], [])))
    return order


def _limits_of(pb):
    out = {}
    for a in AXES:
        if getattr(pb, "lock_ik_" + a):
            out[a] = [0.0, 0.0]
        elif getattr(pb, "use_ik_limit_" + a):
            out[a] = [math.degrees(getattr(pb, "ik_min_" + a)),
                      math.degrees(getattr(pb, "ik_max_" + a))]
    return out


def _positive_prop(holder, key, source, element):
    v = holder.get(key)
    if v is None:
        return None
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
        raise InputError(source, element, key, "must be a positive number (got %r)" % (v,))
    return float(v)


def _mass_fields(pb, source, element):
    out = {}
    mass = _positive_prop(pb, "physik_mass", source, element)
    mpl = _positive_prop(pb, "physik_mass_per_length", source, element)
    if mass is not None and mpl is not None:
        raise InputError(source, element, "physik_mass",
                         "give either physik_mass or physik_mass_per_length, not both")
    if mass is not None:
        out["mass"] = mass
    elif mpl is not None:
        out["mass_per_length"] = mpl
    else:
        legacy = _positive_prop(pb, "fwik_mass", source, element)  # the paper's add-on
        if legacy is not None:
            out["mass_per_length"] = legacy
    for key in ("radius", "collision_radius"):
        value = _positive_prop(pb, "physik_" + key, source, element)
        if value is not None:
            out[key] = value
    return out


def _bone_props(pb, source, element):
    """The rig fields a pose bone holds as custom properties: masses, radius, moments,
    comment."""
    out = _mass_fields(pb, source, element)
    moments = pb.get("physik_inertia_local")
    if moments is not None:
        values = list(moments) if hasattr(moments, "__len__") else None
        if values is None or len(values) != 3 or not all(
                isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
                and v > 0 for v in values):
            raise InputError(source, element, "physik_inertia_local",
                             "must be 3 positive numbers (got %r)" % (values or moments,))
        out["inertia_local"] = [float(v) for v in values]
    if isinstance(pb.get("physik_comment"), str):
        out["comment"] = pb["physik_comment"]
    if isinstance(pb.get("physik_weld"), str):  # welded to its parent or a sibling (rig.h)
        out["weld"] = pb["physik_weld"]
    return out


def require_armature(obj, what="an armature"):
    """obj if it is an armature object; a clear InputError otherwise."""
    if obj is None:
        raise InputError("", "", "", "no armature selected: select %s first" % what)
    if obj.type != 'ARMATURE':
        raise InputError("", "", "", "no armature selected: the active object '%s' is a %s, not "
                         "an armature" % (obj.name, obj.type.lower()))
    return obj


def _world_bone(m3, s, mw, head, tail, rest):
    """World head, tail and rest frame (x, y, z axes) of an armature-space bone."""
    axes = [(m3 @ rest.col[c]) / s for c in range(3)]
    return list(mw @ head), list(mw @ tail), [list(a.normalized()) for a in axes]


def _read_bones(obj, source):
    """Blender's own values of every bone, world, DFS: dicts with name, parent, head, tail,
    rest_frame, limits_deg (when any), masses and radius, inertia_local, comment. Raises
    InputError as armature_to_rig does."""
    m3, s = _world_similarity(obj)
    tails, lengths, bones = {}, {}, []
    for name, parent, head, tail, rest in _dfs(_bone_records(obj), source):
        el = "bone '%s'" % name
        problem = rig_format.bone_name_problem(name)
        if problem:
            raise InputError(source, el, "name", problem)
        hw, tw, frame = _world_bone(m3, s, obj.matrix_world, head, tail, rest)
        length = (Vector(tw) - Vector(hw)).length
        if not length > 1e-9:
            raise InputError(source, el, "tail", "zero-length bone (head and tail coincide)")
        if parent is not None:
            gap = (Vector(hw) - Vector(tails[parent])).length
            if gap > 1e-3 * lengths[parent]:
                raise InputError(source, el, "head", "does not meet the tail of its parent '%s' "
                                 "(gap %.6g); PhysIK joints are a parent's tail with its "
                                 "children's heads: connect the bone" % (parent, gap))
        tails[name], lengths[name] = tw, length
        bone = {"name": name, "parent": parent, "head": hw, "tail": tw, "rest_frame": frame}
        pb = obj.pose.bones.get(name) if obj.pose else None
        if pb is not None:
            limits = _limits_of(pb)
            if limits:
                bone["limits_deg"] = limits
            bone.update(_bone_props(pb, source, el))
        bones.append(bone)
    return bones


def _rig_fields(obj, source):
    """The rig's top-level fields but bones: from the armature data's custom properties and,
    for an armature imported from a file, its record (rig_record.py)."""
    data = obj.data
    text = data.get(rig_record.PROP)
    keys, extra = rig_record.load_rig_record(text, source) if text is not None else (None, {})
    out = {}
    name = data.get("physik_rig_name")
    if isinstance(name, str):
        out["name"] = name
    elif keys is None:
        out["name"] = obj.name
    for key in rig_record.FREE_TEXT:
        value = data.get("physik_" + key)
        if isinstance(value, str):
            out[key] = value
        elif key in extra:
            out[key] = extra[key]
    if keys is None and "comment" not in out:
        out["comment"] = "read from Blender armature '%s' by physik_addon" % obj.name
    if isinstance(data.get("physik_root"), str):  # the root's joint to the world (rig.h)
        out["root"] = data["physik_root"]
    if "collision_exclude" in extra:
        out["collision_exclude"] = extra["collision_exclude"]
    if "source_skeleton" in extra:  # the engine checks its bones when it reads the file
        out["source_skeleton"] = extra["source_skeleton"]
    defaults = {} if keys is not None else {
        "mass_per_length": rig_format.DEFAULT_MASS_PER_LENGTH,
        "radius": rig_format.DEFAULT_RADIUS}
    for key in ("mass_per_length", "radius", "collision_radius"):
        v = _positive_prop(data, "physik_" + key, source, "armature data")
        if v is not None:
            defaults[key] = v
    if defaults or (keys is not None and "defaults" in keys):
        out["defaults"] = defaults
    return out


def armature_to_rig(obj):
    """The rig of an armature object, as a dict in the rig file format (see the module doc).

    An armature imported from a rig file gives the file's own values for every field Blender
    still holds as imported (rig_record.py), so an unchanged rig comes back as the file was.
    Raises InputError: not an armature, no bones or two roots, a bone name the project cannot
    carry, a zero-length bone (edit mode), a child head away from its parent's tail, a bad mass,
    radius or moments property, a sheared or mirrored object.
    """
    require_armature(obj)
    source = armature_source(obj)
    rig = _rig_fields(obj, source)
    bones = []
    for bone in _read_bones(obj, source):
        pb = obj.pose.bones.get(bone["name"]) if obj.pose else None
        text = pb.get(rig_record.PROP) if pb is not None else None
        if text is not None:
            bone = rig_record.merge(bone, text, obj.mode == 'EDIT', source,
                                    "bone '%s'" % bone["name"])
        bones.append(bone)
    rig["bones"] = bones
    if "collision_exclude" in rig:  # the file's pairs whose bones the armature still has
        names = {b["name"] for b in bones}
        rig["collision_exclude"] = [p for p in rig["collision_exclude"]
                                    if p[0] in names and p[1] in names]
    return rig


def check_blender_limits(rig, source):
    """Blender's IK limits hold min <= 0 <= max per axis; refuse the rest before building."""
    for i, b in enumerate(rig["bones"]):
        for a, (lo, hi) in b.get("limits_deg", {}).items():
            if lo > 0.0 or hi < 0.0:
                raise InputError(source, "bones[%d] '%s'" % (i, b["name"]), "limits_deg." + a,
                                 "[%g, %g] deg cannot be a Blender IK limit (Blender holds "
                                 "min <= 0 <= max)" % (lo, hi))


def check_blender_names(rig, source):
    """Bone names Blender and the add-on's bones CSV can hold (rig_format.bone_name_problem)."""
    for i, b in enumerate(rig["bones"]):
        problem = rig_format.bone_name_problem(b["name"])
        if problem:
            raise InputError(source, "bones[%d] '%s'" % (i, b["name"]), "name", problem)


def _set_limits(pb, limits):
    for a in AXES:
        lim = limits.get(a)
        setattr(pb, "use_ik_limit_" + a, lim is not None)
        setattr(pb, "lock_ik_" + a, lim is not None and lim[0] == 0.0 and lim[1] == 0.0)
        if lim is not None:
            setattr(pb, "ik_min_" + a, math.radians(lim[0]))
            setattr(pb, "ik_max_" + a, math.radians(lim[1]))


def _enter_object_mode(context):
    if context.object is not None and context.object.mode != 'OBJECT':
        bpy.ops.object.mode_set(mode='OBJECT')


def _new_armature_object(context, name, origin):
    """An empty armature object at `origin`, linked, selected and active, in edit mode."""
    data = bpy.data.armatures.new(name)
    obj = bpy.data.objects.new(name, data)
    obj.location = origin
    (context.collection or context.scene.collection).objects.link(obj)
    for o in context.selected_objects:
        o.select_set(False)
    obj.select_set(True)
    context.view_layer.objects.active = obj
    context.view_layer.update()  # the object's world matrix, for the edit-mode reading
    bpy.ops.object.mode_set(mode='EDIT')
    return obj


def _edit_frames(obj):
    """{bone: rest frame} read in edit mode, as _read_bones reads it there."""
    m3, s = _world_similarity(obj)
    return {name: _world_bone(m3, s, obj.matrix_world, head, tail, rest)[2]
            for name, _, head, tail, rest in _bone_records(obj)}


def _build_bones(obj, rig, origin):
    """The edit bones of a canonical rig (in edit mode); returns their frames read there."""
    edit = {}
    for b in rig["bones"]:
        eb = obj.data.edit_bones.new(b["name"])
        eb.head, eb.tail = Vector(b["head"]) - origin, Vector(b["tail"]) - origin
        eb.align_roll(Vector(b["rest_frame"][2]))  # the roll that puts z on the rig's z
        if b["parent"] is not None:
            eb.parent = edit[b["parent"]]
            eb.use_connect = True  # heads are already on their parents' tails
        edit[b["name"]] = eb
    return _edit_frames(obj)


def _put_bone_fields(pb, b):
    """A file bone's masses, radii, moments and comment as the pose bone's properties."""
    for key in ("mass", "mass_per_length", "radius", "collision_radius"):
        if b.get(key) is not None:
            pb["physik_" + key] = float(b[key])
    if b.get("inertia_local") is not None:
        pb["physik_inertia_local"] = [float(v) for v in b["inertia_local"]]
    if isinstance(b.get("comment"), str):
        pb["physik_comment"] = b["comment"]
    if isinstance(b.get("weld"), str):
        pb["physik_weld"] = b["weld"]


def _put_rig_fields(data, doc):
    """The file's top-level fields as the armature data's properties and record."""
    if isinstance(doc.get("name"), str):
        data["physik_rig_name"] = doc["name"]
    if isinstance(doc.get("root"), str):
        data["physik_root"] = doc["root"]
    for key in rig_record.FREE_TEXT:
        if isinstance(doc.get(key), str):
            data["physik_" + key] = doc[key]
    given = doc.get("defaults") if isinstance(doc.get("defaults"), dict) else {}
    for key in ("mass_per_length", "radius", "collision_radius"):
        if given.get(key) is not None:
            data["physik_" + key] = float(given[key])
    data[rig_record.PROP] = rig_record.rig_record(doc)


def rig_to_armature(rig, context, name=None, source="<rig>", origin=(0.0, 0.0, 0.0),
                    doc=None):
    """A new armature object for a canonical rig (rig_io.load, rig_format.parse_rig), in the
    active collection, selected and active, in object mode. The object sits at `origin`
    (world) and the bones keep their world rest positions. `doc`, the rig file's own dict
    (default: `rig` itself), gives the masses, radii, moments, defaults and free text, and each
    bone's record (rig_record.py), so armature_to_rig gives the file's values back. Raises
    InputError before creating anything when a bone name or a limit cannot be held by Blender.
    """
    check_blender_names(rig, source)
    check_blender_limits(rig, source)
    doc = rig if doc is None else doc
    _enter_object_mode(context)
    obj = _new_armature_object(context, name or rig.get("name") or "rig", Vector(origin))
    try:
        edit_frames = _build_bones(obj, rig, Vector(origin))
    finally:
        bpy.ops.object.mode_set(mode='OBJECT')
    doc_bones = {b["name"]: b for b in doc["bones"]}
    for b in rig["bones"]:
        pb = obj.pose.bones[b["name"]]
        pb.rotation_mode = 'QUATERNION'
        _set_limits(pb, b.get("limits_deg", {}))
        _put_bone_fields(pb, doc_bones[b["name"]])
    _put_rig_fields(obj.data, doc)
    context.view_layer.update()  # evaluate the pose so pose-bone heads and tails are current
    for bone in _read_bones(obj, source):
        obj.pose.bones[bone["name"]][rig_record.PROP] = rig_record.bone_record(
            doc_bones[bone["name"]], bone, edit_frames[bone["name"]])
    return obj


# --- poses ---------------------------------------------------------------------------------------

def pose_bones_dfs(obj):
    """Pose bones in the rig's DFS order (parents first, children in Blender's order)."""
    roots = [pb for pb in obj.pose.bones if pb.parent is None]
    order, stack = [], list(reversed(roots))
    while stack:
        pb = stack.pop()
        order.append(pb)
        stack.extend(reversed(pb.children))
    return order


def _rest_world_rotation(obj, bone):
    m3, _ = _world_similarity(obj)
    return (m3 @ bone.matrix_local.to_3x3()).normalized().to_quaternion()


def read_pose(obj):
    """(root head in world, {bone: rotation relative to rest in its rest frame}) of the pose as
    set on the channels (Blender's matrix_basis; constraints not applied)."""
    root = pose_bones_dfs(obj)[0]
    m = obj.matrix_world
    rest = root.bone.matrix_local.to_3x3()
    head_arm = root.bone.head_local + rest @ root.matrix_basis.to_translation()
    return m @ head_arm, {pb.name: pb.matrix_basis.to_quaternion() for pb in obj.pose.bones}


def initial_pose_dict(obj):
    """The current channel pose as a scene file's `initial_pose` (degrees, rotation vectors).
    A root channel that has not moved gives no root_head: the engine then starts from the rig's
    own root head (the file's double, not Blender's single-precision copy of it)."""
    head, rotations = read_pose(obj)
    rot = {}
    for name, q in rotations.items():
        v = rig_format.rotation_vector(tuple(q))
        if any(abs(c) > 0.0 for c in v):
            rot[name] = [math.degrees(c) for c in v]
    out = {"rotation_deg": rot}
    if any(c != 0.0 for c in pose_bones_dfs(obj)[0].location):
        out["root_head"] = list(head)
    return out


def set_rotation(pb, q):
    """Set a pose bone's rotation from a quaternion, in whatever rotation mode it uses."""
    q = Quaternion(q)
    if pb.rotation_mode == 'QUATERNION':
        pb.rotation_quaternion = q
    elif pb.rotation_mode == 'AXIS_ANGLE':
        axis, angle = q.to_axis_angle()
        pb.rotation_axis_angle = (angle, axis.x, axis.y, axis.z)
    else:
        pb.rotation_euler = q.to_euler(pb.rotation_mode)


def apply_pose(obj, root_head_world, rotations):
    """Set the channels: the root moves so its head is at root_head_world; every named bone
    turns by its rest-relative rotation (what the engine's Pose holds)."""
    root = pose_bones_dfs(obj)[0]
    head_arm = obj.matrix_world.inverted() @ Vector(root_head_world)
    # an unparented bone's pose head is head_local + R_rest @ location
    root.location = root.bone.matrix_local.to_3x3().transposed() @ (head_arm - root.bone.head_local)
    for name, q in rotations.items():
        set_rotation(obj.pose.bones[name], q)


def local_rotations_from_world(obj, orient_world):
    """Rest-relative rotations from world orientations {bone: quaternion world<-bone}:
    q_i = Rrest_i^-1 Rrest_parent R_parent^-1 R_i (the root: Rrest^-1 R), kinematics.cpp's rule."""
    out = {}
    for pb in pose_bones_dfs(obj):
        r_i = Quaternion(orient_world[pb.name])
        rest_i = _rest_world_rotation(obj, pb.bone)
        if pb.parent is None:
            out[pb.name] = rest_i.inverted() @ r_i
        else:
            rest_p = _rest_world_rotation(obj, pb.parent.bone)
            r_p = Quaternion(orient_world[pb.parent.name])
            out[pb.name] = rest_i.inverted() @ rest_p @ r_p.inverted() @ r_i
    return out


def posed_bones_world(obj):
    """[(name, parent, head, tail)] of the evaluated pose (constraints applied), world, DFS.
    Call context.view_layer.update() after changing the pose."""
    m = obj.matrix_world
    return [(pb.name, pb.parent.name if pb.parent else "", m @ pb.head, m @ pb.tail)
            for pb in pose_bones_dfs(obj)]


def write_bones_csv(path, rows):
    """The project's bones table (physik/io/pose_io.h): bone,parent,head_x..z,tail_x..z."""
    with open(path, "w", encoding="utf-8", newline="") as f:
        f.write("bone,parent,head_x,head_y,head_z,tail_x,tail_y,tail_z\n")
        for name, parent, head, tail in rows:
            numbers = ["%.10g" % c for c in list(head) + list(tail)]
            f.write(",".join([name, parent] + numbers) + "\n")


def bake_keyframes(obj, poses, frame_start=1, every=1):
    """Keyframe a trajectory: poses[s] = (root head world, {bone: rotation}) after step s
    (s = 0 is the start). Keys at steps 0, every, 2 every, ... and the last step, on frames
    frame_start + s / every (the last one rounded up). Returns the keyed frames."""
    if every < 1:
        raise InputError("", "", "bake every", "must be at least 1 step (got %r)" % (every,))
    steps = [s for s in range(0, len(poses), every)]
    if poses and steps[-1] != len(poses) - 1:
        steps.append(len(poses) - 1)
    root = pose_bones_dfs(obj)[0]
    previous, frames = {}, []
    for s in steps:
        head, rotations = poses[s]
        # keep consecutive quaternions in one hemisphere so the keys interpolate the short way
        fixed = {}
        for name, q in rotations.items():
            q = Quaternion(q)
            if name in previous and previous[name].dot(q) < 0.0:
                q.negate()
            fixed[name] = previous[name] = q
        apply_pose(obj, head, fixed)
        frame = frame_start + -(-s // every)
        root.keyframe_insert("location", frame=frame, group=root.name)
        for name in fixed:
            pb = obj.pose.bones[name]
            path = {"QUATERNION": "rotation_quaternion", "AXIS_ANGLE": "rotation_axis_angle"}.get(
                pb.rotation_mode, "rotation_euler")
            pb.keyframe_insert(path, frame=frame, group=name)
        frames.append(frame)
    return frames
