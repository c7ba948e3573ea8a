"""The project's rig files as Python dicts: validation and canonical frames, with no Blender
and no engine here: the add-on's reader when the `physik` module cannot be imported (rig_io.py
uses physik.Rig when it can; Blender's iTaSC script, which the fig9 experiment runs from a
CLI-only build, always uses this one).

Format: models/README.md "Rigs". Conventions (physik/model/rig.h, physik/model/kinematics.h):
world Z up; a bone's local +Y runs head -> tail; `rest_frame` lists the bone's x, y, z axes in
world coordinates; `limits_deg` are intervals (deg) on the components of the rotation vector of
the bone's rotation relative to rest, about its local x, y, z axes; an absent axis is free.

The checks and the canonical frame follow the C++ loader (physik/io/rig_io.cpp, build_rig in
physik/model/rig.cpp) so a file the add-on accepts is one the engine accepts, with the same
one-line messages "<file>: <element>: field '<field>': <reason>":
  - a child's head is snapped onto its parent's tail (files carry 4 decimals);
  - a given frame is turned into a unit quaternion (Shoemake's trace method, as Eigen) and then
    rotated by the minimal rotation that puts its y axis exactly on the bone;
  - a roll gives Blender's frame: the minimal rotation taking +Y to the bone, then the roll
    about the bone (rest_frame_from_roll).
blender/tests/test_rig_format.py holds it to the engine: the same canonical rig for every
shipped rig, the same message for each bad file; blender/tests/test_round_trip.py builds the
same armatures from it as from physik.Rig. Blender's own limits on bone names (63 bytes; no
character the add-on's bones CSV cannot hold) are armature_io's, not the format's.
"""
import json
import math

AXES = ("x", "y", "z")
TOP_KEYS = ("name", "comment", "source", "units", "root", "defaults", "bones",
            "collision_exclude", "source_skeleton")
BONE_KEYS = ("name", "parent", "head", "tail", "rest_frame", "roll_deg", "limits_deg",
             "mass_per_length", "mass", "radius", "inertia_local", "collision_radius", "weld",
             "segment", "forward", "comment")
ROOT_JOINTS = ("free", "pinned", "fixed")  # rig.h RootJoint
DEFAULT_MASS_PER_LENGTH = 1.0  # kg per rig unit, the original code's
DEFAULT_RADIUS = 0.5           # rig units, the original code's
COLLISION_RADIUS_PER_LENGTH = 0.06  # rig.h kCollisionRadiusPerLength: the default contact capsule
MAX_NAME_BYTES = 63            # Blender's bone names hold 63 bytes (MAXBONENAME 64 with the NUL)


class InputError(ValueError):
    """Bad input; str() is one line naming the file, the element and the field."""

    def __init__(self, source, element, field, reason):
        parts = [source] if source else []
        if element:
            parts.append(element)
        if field:
            parts.append("field '%s'" % field)
        parts.append(reason)
        super().__init__(": ".join(parts))

    @classmethod
    def from_message(cls, message):
        """An InputError whose text is `message` as it stands (the engine's: already one line
        naming the file, the element and the field)."""
        err = cls.__new__(cls)
        ValueError.__init__(err, message)
        return err



def _edit_distance(a, b):
    """Levenshtein distance between two short names (names.cpp edit_distance)"""
    prev = list(range(len(b) + 1))
    for i in range(1, len(a) + 1):
        cur = [i] + [0] * len(b)
        for j in range(1, len(b) + 1):
            cur[j] = min(prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1]))
        prev = cur
    return prev[len(b)]


def _unknown_bone(name, known):
    """The engine's message for a bone name that is not in `known` (names.cpp unknown_bone): the
    nearest known name, the first of the closest, when it is a typo (at most a third of its
    letters, two at least)"""
    best, best_d = "", None
    for k in known:
        d = _edit_distance(name, k)
        if best_d is None or d < best_d:
            best, best_d = k, d
    hint = " (did you mean '%s'?)" % best if best_d is not None and best_d <= max(
        2, len(best) // 3) else ""
    return "unknown bone '%s'%s" % (name, hint)

def bone_name_problem(name):
    """Why `name` cannot be a bone name here, or None.

    Blender truncates names past 63 bytes (two bones could then collide); the bones CSV
    (physik/io/pose_io.h) writes names unquoted, so a comma, a quote or a line break breaks it.
    """
    if not isinstance(name, str):
        return "expected a string, got %s" % type(name).__name__
    if not name:
        return "empty bone name"
    if len(name.encode("utf-8")) > MAX_NAME_BYTES:
        return "longer than Blender's %d bytes" % MAX_NAME_BYTES
    bad = [c for c in name if c in ',"\n\r']
    if bad:
        return "contains %r, which the bones CSV cannot hold" % bad[0]
    return None


# --- small vector and quaternion helpers (tuples; quaternions are (w, x, y, z)) ------------------

def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    return math.sqrt(dot(a, a))


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def normalized(a):
    return scale(a, 1.0 / norm(a))


def quat_normalized(q):
    n = math.sqrt(sum(c * c for c in q))
    return tuple(c / n for c in q)


def quat_mul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw)


def quat_from_axes(axes):
    """Unit quaternion of the matrix whose columns are `axes` (x, y, z): Shoemake's method."""
    m = [[axes[c][r] for c in range(3)] for r in range(3)]  # m[row][col]
    t = m[0][0] + m[1][1] + m[2][2]
    q = [0.0, 0.0, 0.0, 0.0]  # w, x, y, z
    if t > 0.0:
        t = math.sqrt(t + 1.0)
        q[0] = 0.5 * t
        t = 0.5 / t
        q[1] = (m[2][1] - m[1][2]) * t
        q[2] = (m[0][2] - m[2][0]) * t
        q[3] = (m[1][0] - m[0][1]) * t
    else:
        i = 0
        if m[1][1] > m[0][0]:
            i = 1
        if m[2][2] > m[i][i]:
            i = 2
        j, k = (i + 1) % 3, (i + 2) % 3
        t = math.sqrt(m[i][i] - m[j][j] - m[k][k] + 1.0)
        q[1 + i] = 0.5 * t
        t = 0.5 / t
        q[0] = (m[k][j] - m[j][k]) * t
        q[1 + j] = (m[j][i] + m[i][j]) * t
        q[1 + k] = (m[k][i] + m[i][k]) * t
    return quat_normalized(tuple(q))


def quat_axes(q):
    """The columns (x, y, z axes) of the rotation matrix of unit quaternion q."""
    w, x, y, z = q
    return ((1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)),
            (2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)),
            (2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)))


def quat_between(a, b):
    """Minimal rotation taking direction a to direction b (not antiparallel)."""
    a, b = normalized(a), normalized(b)
    c = dot(a, b)
    s = math.sqrt((1.0 + c) * 2.0)
    axis = scale(cross(a, b), 1.0 / s)
    return (0.5 * s,) + axis


def quat_axis_angle(axis, angle):
    s = math.sin(0.5 * angle)
    return (math.cos(0.5 * angle), axis[0] * s, axis[1] * s, axis[2] * s)


def rotation_vector(q):
    """Rotation vector (rad) of a unit quaternion, angle in [0, pi] (kinematics.cpp)."""
    if q[0] < 0.0:
        q = tuple(-c for c in q)
    v = q[1:]
    s = norm(v)
    if s < 1e-12:
        return scale(v, 2.0)
    return scale(v, 2.0 * math.atan2(s, q[0]) / s)


def frame_from_roll(head, tail, roll):
    """Blender's rest frame (axes x, y, z) from head, tail and roll (rad): rig.cpp's rule."""
    d = normalized(sub(tail, head))
    if dot(d, (0.0, 1.0, 0.0)) < -1.0 + 1e-12:
        align = quat_axis_angle((0.0, 0.0, 1.0), math.pi)  # antiparallel: 180 deg about Z
    else:
        align = quat_between((0.0, 1.0, 0.0), d)
    return quat_axes(quat_mul(align, quat_axis_angle((0.0, 1.0, 0.0), roll)))


def canonical_frame(axes, head, tail):
    """The engine's frame for a file's axes: orthonormalised, its y exactly on the bone."""
    q = quat_from_axes(axes)
    y = quat_axes(q)[1]
    q = quat_normalized(quat_mul(quat_between(y, sub(tail, head)), q))
    return quat_axes(q)


# --- validation: the engine's checks and messages (physik/io/rig_io.cpp, physik/model/rig.cpp) --

MAX_BONES = 1000000          # rig.h kMaxBones
MAX_COORDINATE = 1e9         # rig.h kMaxCoordinate, rig units
MIN_SCALE, MAX_SCALE = 1e-9, 1e9  # rig.h kMinScale, kMaxScale: mass (kg) and radius (rig units)
MAX_JSON_DEPTH = 256         # json_fields.h kMaxJsonDepth


def _number(value, source, element, field):
    # bool is an int in Python; JSON true is not a number
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(source, element, field, "expected a number, got %s" % _json_type(value))
    if not math.isfinite(value):
        raise InputError(source, element, field, "not a finite number")
    return float(value)


def _vec3(value, source, element, field):
    if not isinstance(value, list) or len(value) != 3:
        raise InputError(source, element, field, "expected an array of 3 numbers")
    return tuple(_number(v, source, element, "%s[%d]" % (field, k)) for k, v in enumerate(value))


def _json_type(value):
    if value is None:
        return "null"
    return {bool: "boolean", str: "string", list: "array", dict: "object"}.get(type(value),
                                                                              "number")


def _only_keys(obj, known, source, element):
    for key in obj:
        if key not in known:
            raise InputError(source, element, key,
                             "unknown field (known fields: %s)" % ", ".join(known))


def _number_or(obj, key, fallback, source, element):
    """The engine's number_or: an absent or null field is the fallback."""
    return fallback if obj.get(key) is None else _number(obj[key], source, element, key)


def parse_limits(value, source, element, field="limits_deg"):
    """{"x": [min, max], ...} in degrees, checked as axis_limits.cpp does."""
    if not isinstance(value, dict):
        raise InputError(source, element, field, 'expected an object {"x": [min, max], ...}')
    out = {}
    for axis, pair in value.items():
        f = "%s.%s" % (field, axis)
        if axis not in AXES:
            raise InputError(source, element, f, "unknown axis (expected x, y or z)")
        if not isinstance(pair, list) or len(pair) != 2:
            raise InputError(source, element, f, "expected [min, max] in degrees")
        lo = _number(pair[0], source, element, f + "[0]")
        hi = _number(pair[1], source, element, f + "[1]")
        if lo > hi:
            raise InputError(source, element, f,
                             "min %g deg is greater than max %g deg" % (lo, hi))
        if lo < -180.0 or hi > 180.0:
            raise InputError(source, element, f,
                             "limits must lie within [-180, 180] deg (got [%g, %g])" % (lo, hi))
        out[axis] = [lo, hi]
    return out


def _bone_element(b, i):
    if isinstance(b, dict) and isinstance(b.get("name"), str):
        return "bones[%d] '%s'" % (i, b["name"])
    return "bones[%d]" % i


def engine_name_problem(name):
    """names.cpp name_problem for a name read from JSON (so valid UTF-8): the first control
    character and its byte offset, or None."""
    for i, c in enumerate(name.encode("utf-8")):
        if c < 0x20 or c == 0x7F:
            return "control character 0x%02x at offset %d" % (c, i)
    return None


def _parse_frame(b, head, tail, source, el):
    """The bone's axes as given (rest_frame), or Blender's frame for its roll."""
    if "rest_frame" in b and "roll_deg" in b:
        raise InputError(source, el, "rest_frame", "give either rest_frame or roll_deg, not both")
    if "rest_frame" in b:
        f = b["rest_frame"]
        if not isinstance(f, list) or len(f) != 3:
            raise InputError(source, el, "rest_frame", "expected three axes [[x],[y],[z]]")
        return tuple(_vec3(f[c], source, el, "rest_frame[%d]" % c) for c in range(3))
    roll = _number_or(b, "roll_deg", 0.0, source, el)
    return frame_from_roll(head, tail, math.radians(roll))


def _parse_mass(b, bone, defaults, source, el):
    """Mass (given, or mass per length x length), radius and explicit moments, as rig_io.cpp
    reads them; keeps which of mass and mass_per_length the file gave."""
    if "mass" in b and "mass_per_length" in b:
        raise InputError(source, el, "mass", "give either mass or mass_per_length, not both")
    length = norm(sub(bone["tail"], bone["head"]))
    if "mass" in b:
        bone["mass"] = _number(b["mass"], source, el, "mass")
        if not bone["mass"] > 0.0:
            raise InputError(source, el, "mass", "must be positive")
        total = bone["mass"]
    else:
        mpl = _number_or(b, "mass_per_length", defaults["mass_per_length"], source, el)
        if not mpl > 0.0:
            raise InputError(source, el, "mass_per_length", "must be positive")
        if b.get("mass_per_length") is not None:
            bone["mass_per_length"] = mpl
        total = mpl * length
    radius = _number_or(b, "radius", defaults["radius"], source, el)
    if not radius > 0.0:
        raise InputError(source, el, "radius", "must be positive")
    if b.get("radius") is not None:
        bone["radius"] = radius
    if "inertia_local" in b:
        bone["inertia_local"] = _vec3(b["inertia_local"], source, el, "inertia_local")
        if not min(bone["inertia_local"]) > 0.0:
            raise InputError(source, el, "inertia_local", "moments must be positive")
    _parse_collision_radius(b, bone, source, el)
    return total, radius


def _parse_collision_radius(obj, out, source, el):
    """The contact capsule's radius where given (rig_io.cpp read_collision_radius): positive."""
    if obj.get("collision_radius") is None:
        return
    out["collision_radius"] = _number(obj["collision_radius"], source, el, "collision_radius")
    if not out["collision_radius"] > 0.0:
        raise InputError(source, el, "collision_radius", "must be positive")


def _parse_bone(b, i, source, defaults):
    """One bone's own fields (rig_io.cpp bone_from_json); returns a dict with tuples, the raw
    frame ("axes"), and the total mass and radius for the range checks."""
    el = _bone_element(b, i)
    if not isinstance(b, dict):
        raise InputError(source, el, "", "expected a JSON object")
    _only_keys(b, BONE_KEYS, source, el)
    if "name" not in b:
        raise InputError(source, el, "name", "missing required field")
    if not isinstance(b["name"], str):
        raise InputError(source, el, "name", "expected a string, got %s" % _json_type(b["name"]))
    if "parent" not in b:
        raise InputError(source, el, "parent", "missing required field")
    parent = b["parent"]
    if isinstance(parent, str) and not parent:
        raise InputError(source, el, "parent", "empty name (use null for the root)")
    if parent is not None and not isinstance(parent, str):
        raise InputError(source, el, "parent", "expected a bone name or null")
    for key in ("head", "tail"):
        if key not in b:
            raise InputError(source, el, key, "missing required field")
    head = _vec3(b["head"], source, el, "head")
    tail = _vec3(b["tail"], source, el, "tail")
    if norm(sub(tail, head)) <= 1e-9:
        raise InputError(source, el, "tail", "zero-length bone (head and tail coincide)")
    bone = {"name": b["name"], "parent": parent, "head": head, "tail": tail,
            "axes": _parse_frame(b, head, tail, source, el)}
    bone["limits_deg"] = parse_limits(b["limits_deg"], source, el) if "limits_deg" in b else {}
    if "weld" in b:
        if not isinstance(b["weld"], str):
            raise InputError(source, el, "weld", "expected a string, got %s" % _json_type(b["weld"]))
        if not b["weld"]:
            raise InputError(source, el, "weld",
                             "empty name (leave the key out for a bone that turns)")
        bone["weld"] = b["weld"]
    bone["_mass"], bone["_radius"] = _parse_mass(b, bone, defaults, source, el)
    if isinstance(b.get("comment"), str):
        bone["comment"] = b["comment"]
    return bone


def _check_names(bones, source):
    """rig.cpp stage 1: names non-empty, UTF-8 without control characters, unique."""
    index = {}
    for i, b in enumerate(bones):
        if not b["name"]:
            raise InputError(source, _bone_element(b, i), "name", "empty bone name")
        problem = engine_name_problem(b["name"])
        if problem:  # the element leaves the name out, as the engine's does
            raise InputError(source, "bones[%d]" % i, "name", problem)
        if b["name"] in index:
            raise InputError(source, _bone_element(b, i), "name",
                             "duplicate bone name (first used by bones[%d])" % index[b["name"]])
        index[b["name"]] = i
    return index


def _dfs_order(bones, source):
    """Indices in DFS order from the one root (children in file order); tree errors raise."""
    index = _check_names(bones, source)
    children = [[] for _ in bones]
    root = None
    for i, b in enumerate(bones):
        el = _bone_element(b, i)
        if b["parent"] is None:
            if root is not None:
                raise InputError(source, el, "parent", "a second root (bone '%s' is already the "
                                 "root; a rig has exactly one)" % bones[root]["name"])
            root = i
        elif b["parent"] == b["name"]:
            raise InputError(source, el, "parent", "a bone cannot be its own parent")
        elif b["parent"] not in index:
            raise InputError(source, el, "parent",
                             _unknown_bone(b["parent"], [x["name"] for x in bones]))
        else:
            children[index[b["parent"]]].append(i)
    if root is None:
        raise InputError(source, "", "parent",
                         "no root bone (every bone has a parent, so the parents form a cycle)")
    order, stack = [], [root]
    while stack:
        i = stack.pop()
        order.append(i)
        stack.extend(reversed(children[i]))
    if len(order) != len(bones):
        seen = set(order)
        i = next(k for k in range(len(bones)) if k not in seen)
        raise InputError(source, _bone_element(bones[i], i), "parent", "parent cycle: this "
                         "bone's ancestors never reach the root '%s'" % bones[root]["name"])
    return order


def _limited(bone):
    return any(bone.get("limits_deg", {}).get(a) for a in AXES)


def _check_welds(bones, source, root_joint):
    """rig.cpp stage 2b (check_welds): a weld names the bone's parent or a sibling listed before
    it, forms no cycle, and sits on a bone without limits below the root; then no limits on a
    free or fixed root."""
    index = {b["name"]: i for i, b in enumerate(bones)}
    target = {}
    for i, b in enumerate(bones):
        weld = b.get("weld")
        if weld is None:
            continue
        el = _bone_element(b, i)
        if b["parent"] is None:
            raise InputError(source, el, "weld", "the root has no parent to weld to (a root held "
                             "to the world is the rig's \"root\": \"fixed\")")
        if weld == b["name"]:
            raise InputError(source, el, "weld", "a bone cannot weld to itself")
        if weld not in index:
            raise InputError(source, el, "weld",
                             _unknown_bone(weld, [x["name"] for x in bones]))
        if weld != b["parent"] and bones[index[weld]]["parent"] != b["parent"]:
            raise InputError(source, el, "weld", "'%s' is neither this bone's parent '%s' nor a "
                             "sibling of it (a bone welds to its parent, or to a bone with the "
                             "same parent)" % (weld, b["parent"]))
        if _limited(b):
            raise InputError(source, el, "limits_deg", "a welded bone has no degree of freedom "
                             "to limit (welded to '%s')" % weld)
        target[i] = index[weld]
    for i, b in enumerate(bones):
        path, k, steps = b["name"], i, 0
        while k in target and bones[k].get("weld") != bones[k]["parent"]:
            k = target[k]
            path += " -> " + bones[k]["name"]
            steps += 1
            if k == i or steps > len(bones):
                raise InputError(source, _bone_element(b, i), "weld", "weld cycle " + path)
    for i, b in enumerate(bones):
        if i not in target or b["weld"] == b["parent"]:
            continue
        siblings = [k for k, c in enumerate(bones) if c["parent"] == b["parent"]]
        if siblings.index(target[i]) > siblings.index(i):
            raise InputError(source, _bone_element(b, i), "weld", "the sibling '%s' it welds to "
                             "must come before it among the children of '%s'"
                             % (b["weld"], b["parent"]))
    if root_joint != "pinned":
        i = next(k for k, b in enumerate(bones) if b["parent"] is None)
        if _limited(bones[i]):
            raise InputError(source, _bone_element(bones[i], i), "limits_deg",
                             "a free root has nothing to limit its turn against (limits on the "
                             "root need the rig's \"root\": \"pinned\")" if root_joint == "free"
                             else "a fixed root does not turn: it has nothing to limit")


def _check_geometry(bone, source, el):
    """rig.cpp stage 4a: coordinates within range; a right-handed orthonormal frame along the
    bone."""
    for field in ("head", "tail"):
        big = max(abs(c) for c in bone[field])
        if big > MAX_COORDINATE:
            raise InputError(source, el, field, "coordinate %g is beyond +-%g rig units "
                             "(rig.h kMaxCoordinate)" % (big, MAX_COORDINATE))
    f = bone["axes"]
    gram = math.sqrt(sum((dot(f[a], f[b]) - (1.0 if a == b else 0.0)) ** 2
                         for a in range(3) for b in range(3)))
    if gram > 1e-3 or dot(cross(f[0], f[1]), f[2]) < 0.0:
        raise InputError(source, el, "rest_frame", "not a right-handed orthonormal frame")
    if dot(f[1], normalized(sub(bone["tail"], bone["head"]))) < 1.0 - 1e-3:
        raise InputError(source, el, "rest_frame",
                         "the frame's y axis does not run from head to tail")


def _check_mass(bone, source, el):
    """rig.cpp stage 4c: mass, radius and explicit moments within the engine's ranges."""
    rng = " (rig.h: [%g, %g])" % (MIN_SCALE, MAX_SCALE)
    if not MIN_SCALE <= bone["_mass"] <= MAX_SCALE:
        raise InputError(source, el, "mass", "mass %g kg is out of range%s" % (bone["_mass"], rng))
    if not MIN_SCALE <= bone["_radius"] <= MAX_SCALE:
        raise InputError(source, el, "radius",
                         "radius %g rig units is out of range%s" % (bone["_radius"], rng))
    m = bone.get("inertia_local")
    if m is None or max(abs(c) for c in m) <= 1e-12:
        return  # the engine reads moments all within Eigen's isZero() as none given
    lo, hi = MIN_SCALE ** 3, MAX_SCALE ** 3
    if min(m) < lo or max(m) > hi:
        raise InputError(source, el, "inertia_local",
                         "moments must lie in [%g, %g] kg m^2" % (lo, hi))
    tol = 1 - 1e-9
    if m[0] + m[1] < m[2] * tol or m[1] + m[2] < m[0] * tol or m[2] + m[0] < m[1] * tol:
        raise InputError(source, el, "inertia_local",
                         "moments break the triangle inequality (no real body has them)")


def _parse_top(doc, source):
    """The rig's name, comment and defaults (rig_io.cpp rig_from_json)."""
    if not isinstance(doc, dict):
        raise InputError(source, "", "", "expected a JSON object")
    _only_keys(doc, TOP_KEYS, source, "")
    root = doc.get("root", "free")
    if not isinstance(root, str):
        raise InputError(source, "", "root", "expected a string, got %s" % _json_type(root))
    if root not in ROOT_JOINTS:
        raise InputError(source, "", "root",
                         'expected "free", "pinned" or "fixed", got "%s"' % root)
    defaults = doc.get("defaults", {})
    if not isinstance(defaults, dict):
        raise InputError(source, "defaults", "defaults", "expected a JSON object")
    _only_keys(defaults, ("mass_per_length", "radius", "collision_radius"), source, "defaults")
    d = {"mass_per_length": _number_or(defaults, "mass_per_length", DEFAULT_MASS_PER_LENGTH,
                                       source, "defaults"),
         "radius": _number_or(defaults, "radius", DEFAULT_RADIUS, source, "defaults")}
    for key, value in d.items():
        if not value > 0.0:
            raise InputError(source, "defaults", key, "must be positive")
    _parse_collision_radius(defaults, d, source, "defaults")
    if "bones" not in doc:
        raise InputError(source, "", "bones", "missing required field")
    if not isinstance(doc["bones"], list):
        raise InputError(source, "", "bones", "expected an array of bones")
    name = doc.get("name")
    if name is not None and not isinstance(name, str):
        raise InputError(source, "", "name", "expected a string, got %s" % _json_type(name))
    rig = {"name": name or "", "defaults": d, "root": root}
    if isinstance(doc.get("comment"), str):
        rig["comment"] = doc["comment"]
    return rig


def _parse_source(doc, source):
    """source: one note or a list of notes (rig_io.cpp read_notes)."""
    notes = doc.get("source")
    if notes is None or isinstance(notes, str):
        return
    if not isinstance(notes, list):
        raise InputError(source, "", "source", "expected a note or a list of notes (strings)")
    for i, n in enumerate(notes):
        if not isinstance(n, str):
            raise InputError(source, "", "source[%d]" % i, "expected a string")


def _parse_collision_exclude(doc, names, source):
    """collision_exclude: pairs of two different known bones (rig_io.cpp read_collision_exclude,
    rig.cpp set_collision_exclude), as [[a, b], ...] in the file's order."""
    pairs = doc.get("collision_exclude")
    if pairs is None:
        return []
    if not isinstance(pairs, list):
        raise InputError(source, "", "collision_exclude", "expected an array of [bone, bone] pairs")
    for i, e in enumerate(pairs):
        if not (isinstance(e, list) and len(e) == 2 and all(isinstance(n, str) for n in e)):
            raise InputError(source, "", "collision_exclude[%d]" % i,
                             'expected a pair of bone names ["a", "b"]')
    for i, e in enumerate(pairs):
        for n in e:
            if n not in names:
                raise InputError(source, "", "collision_exclude[%d]" % i,
                                 _unknown_bone(n, list(names)))
        if e[0] == e[1]:
            raise InputError(source, "", "collision_exclude[%d]" % i, "bone '%s' is paired with "
                             "itself (an exclusion names two different bones)" % e[0])
    return [list(e) for e in pairs]


def parse_rig(doc, source="<rig>"):
    """A checked rig in canonical form: bones in DFS order, heads snapped onto their parents'
    tails, frames as the engine builds them. Raises InputError with the engine's message."""
    rig = _parse_top(doc, source)
    parsed = [_parse_bone(b, i, source, rig["defaults"]) for i, b in enumerate(doc["bones"])]
    if not parsed:
        raise InputError(source, "", "bones", "the rig has no bones")
    if len(parsed) > MAX_BONES:
        raise InputError(source, "", "bones", "%d bones, more than the %d a rig may have "
                         "(rig.h kMaxBones)" % (len(parsed), MAX_BONES))
    order = _dfs_order(parsed, source)
    _check_welds(parsed, source, rig["root"])
    for i, b in enumerate(parsed):
        _check_geometry(b, source, _bone_element(b, i))
    for i, b in enumerate(parsed):
        _check_mass(b, source, _bone_element(b, i))
    out, tail_of, length_of = [], {}, {}
    for i in order:
        b = {k: v for k, v in parsed[i].items() if not k.startswith("_")}
        b["total_mass"] = parsed[i]["_mass"]  # from the file's head, as the engine's
        if b["parent"] is not None:
            gap = norm(sub(b["head"], tail_of[b["parent"]]))
            if gap > 1e-3 * length_of[b["parent"]]:
                raise InputError(source, _bone_element(b, i), "head", "does not meet the tail of "
                                 "its parent '%s' (gap %g); a joint is a parent's tail with its "
                                 "children's heads" % (b["parent"], gap))
            b["head"] = tail_of[b["parent"]]
        b["rest_frame"] = canonical_frame(b.pop("axes"), b["head"], b["tail"])
        tail_of[b["name"]] = b["tail"]
        length_of[b["name"]] = norm(sub(b["tail"], b["head"]))
        out.append(b)
    rig["bones"] = out
    _parse_source(doc, source)
    pairs = _parse_collision_exclude(doc, tail_of, source)
    if pairs:  # as the engine keeps them: each pair in DFS order, sorted, once
        index = {b["name"]: k for k, b in enumerate(out)}
        keyed = sorted({tuple(sorted(p, key=index.get)) for p in pairs},
                       key=lambda p: (index[p[0]], index[p[1]]))
        rig["collision_exclude"] = [list(p) for p in keyed]
    if "source_skeleton" in doc:  # passed through: the engine checks it against the bones
        rig["source_skeleton"] = doc["source_skeleton"]
    return rig


def _check_json_depth(text, source):
    """json_fields.cpp check_json_depth: brackets outside strings, at most MAX_JSON_DEPTH."""
    depth, line, in_string, escaped = 0, 1, False, False
    for c in text:
        if c == "\n":
            line += 1
        if in_string:
            if escaped:
                escaped = False
            elif c == "\\":
                escaped = True
            elif c == '"':
                in_string = False
        elif c == '"':
            in_string = True
        elif c in "[{":
            depth += 1
            if depth > MAX_JSON_DEPTH:
                raise InputError(source, "line %d" % line, "", "JSON nested deeper than %d "
                                 "levels (json_fields.h kMaxJsonDepth)" % MAX_JSON_DEPTH)
        elif c in "]}":
            depth -= 1


def _refuse_constant(name):
    raise ValueError("%s is not a JSON number" % name)


def load_json(path):
    """A JSON file's contents; an unreadable, malformed (bytes that are not UTF-8 included) or
    too deeply nested file raises InputError (the engine's words: "cannot open file",
    "invalid JSON: ..."; the parser's own details differ)."""
    try:
        with open(path, "rb") as f:
            raw = f.read()
    except OSError:
        raise InputError(path, "", "", "cannot open file") from None
    try:
        text = raw.decode("utf-8-sig")  # a byte order mark is skipped, as nlohmann does
    except UnicodeDecodeError as e:
        raise InputError(path, "", "", "invalid JSON: %s" % e) from None
    _check_json_depth(text, path)
    try:
        return json.loads(text, parse_constant=_refuse_constant)
    except ValueError as e:
        raise InputError(path, "", "", "invalid JSON: %s" % e) from None


def load_rig(path):
    return parse_rig(load_json(path), path)


def bone_mass(bone):
    """Total mass (kg) of a canonical bone: its mass, or mass per length x the length from the
    file's head (before the head is snapped onto the parent's tail: the engine's rule)."""
    return bone["total_mass"]


def bone_radius(rig, bone):
    return bone.get("radius", rig["defaults"]["radius"])
