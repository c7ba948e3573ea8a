"""The project's rig files as Python dicts: validation and canonical frames (no Blender here).

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
Once `import physik` exists, physik.Rig.load can replace the checks; the dict form stays the
add-on's interchange with Blender.
"""
import json
import math

AXES = ("x", "y", "z")
TOP_KEYS = ("name", "comment", "source", "units", "defaults", "bones")
BONE_KEYS = ("name", "parent", "head", "tail", "rest_frame", "roll_deg", "limits_deg",
             "mass_per_length", "mass", "radius", "inertia_local", "comment")
DEFAULT_MASS_PER_LENGTH = 1.0  # kg per rig unit, the original code's
DEFAULT_RADIUS = 0.5           # rig units, the original code's
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


# --- validation --------------------------------------------------------------------------------

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
    return {bool: "boolean", str: "string", list: "array", dict: "object"}.get(type(value), "number")


def _only_keys(obj, known, source, element):
    for key in obj:
        if key not in known:
            raise InputError(source, element, key,
                             "unknown field (known fields: %s)" % ", ".join(known))


def _positive(obj, key, fallback, source, element):
    if obj.get(key) is None:
        return fallback
    v = _number(obj[key], source, element, key)
    if not v > 0.0:
        raise InputError(source, element, key, "must be positive")
    return v


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
            raise InputError(source, element, f, "min %g deg is greater than max %g deg" % (lo, hi))
        if lo < -180.0 or hi > 180.0:
            raise InputError(source, element, f,
                             "limits must lie within [-180, 180] deg (got [%g, %g])" % (lo, hi))
        out[axis] = [lo, hi]
    return out


def _bone_element(b, i):
    if isinstance(b, dict) and isinstance(b.get("name"), str):
        return "bones[%d] '%s'" % (i, b["name"])
    return "bones[%d]" % i


def _parse_bone(b, i, source):
    """One bone's own fields (no tree checks); returns a dict with tuples and the raw frame."""
    el = _bone_element(b, i)
    if not isinstance(b, dict):
        raise InputError(source, el, "", "expected an object")
    _only_keys(b, BONE_KEYS, source, el)
    if "name" not in b:
        raise InputError(source, el, "name", "missing required field")
    problem = bone_name_problem(b["name"])
    if problem:
        raise InputError(source, el, "name", problem)
    if "parent" not in b:
        raise InputError(source, el, "parent", "missing required field")
    parent = b["parent"]
    if parent is not None and (not isinstance(parent, str) or not parent):
        raise InputError(source, el, "parent", "expected a bone name, or null for the root")
    for key in ("head", "tail"):
        if key not in b:
            raise InputError(source, el, key, "missing required field")
    head = _vec3(b["head"], source, el, "head")
    tail = _vec3(b["tail"], source, el, "tail")
    if norm(sub(tail, head)) <= 1e-9:
        raise InputError(source, el, "tail", "zero-length bone (head and tail coincide)")
    bone = {"name": b["name"], "parent": parent, "head": head, "tail": tail}
    if "rest_frame" in b and "roll_deg" in b:
        raise InputError(source, el, "rest_frame", "give either rest_frame or roll_deg, not both")
    if "rest_frame" in b:
        f = b["rest_frame"]
        if not isinstance(f, list) or len(f) != 3:
            raise InputError(source, el, "rest_frame", "expected three axes [[x],[y],[z]]")
        bone["axes"] = tuple(_vec3(f[c], source, el, "rest_frame[%d]" % c) for c in range(3))
    else:
        roll = b.get("roll_deg", 0.0)
        roll = 0.0 if roll is None else _number(roll, source, el, "roll_deg")
        bone["axes"] = frame_from_roll(head, tail, math.radians(roll))
    bone["limits_deg"] = parse_limits(b["limits_deg"], source, el) if "limits_deg" in b else {}
    if "mass" in b and "mass_per_length" in b:
        raise InputError(source, el, "mass", "give either mass or mass_per_length, not both")
    for key in ("mass", "mass_per_length", "radius"):
        if key in b:
            bone[key] = _positive(b, key, None, source, el)
    if "inertia_local" in b:
        bone["inertia_local"] = _vec3(b["inertia_local"], source, el, "inertia_local")
    return bone


def _dfs_order(bones, source):
    """Indices in DFS order from the one root (children in file order); tree errors raise."""
    index = {}
    for i, b in enumerate(bones):
        if b["name"] in index:
            raise InputError(source, _bone_element(b, i), "name",
                             "duplicate bone name (first used by bones[%d])" % index[b["name"]])
        index[b["name"]] = i
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
            raise InputError(source, el, "parent", "unknown bone '%s'" % b["parent"])
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
        raise InputError(source, _bone_element(bones[i], i), "parent", "parent cycle: this bone's "
                         "ancestors never reach the root '%s'" % bones[root]["name"])
    return order


def _check_frame(bone, source, el):
    f = bone["axes"]
    gram = max(abs(dot(f[a], f[b]) - (1.0 if a == b else 0.0)) for a in range(3) for b in range(3))
    if gram > 1e-3 or dot(cross(f[0], f[1]), f[2]) < 0.0:
        raise InputError(source, el, "rest_frame", "not a right-handed orthonormal frame")
    if dot(f[1], normalized(sub(bone["tail"], bone["head"]))) < 1.0 - 1e-3:
        raise InputError(source, el, "rest_frame", "the frame's y axis does not run from head to tail")


def parse_rig(doc, source="<rig>"):
    """A checked rig in canonical form: bones in DFS order, heads snapped onto their parents'
    tails, frames as the engine builds them. Raises InputError."""
    if not isinstance(doc, dict):
        raise InputError(source, "", "", "expected a JSON object")
    _only_keys(doc, TOP_KEYS, source, "")
    defaults = doc.get("defaults", {})
    if not isinstance(defaults, dict):
        raise InputError(source, "defaults", "", "expected an object")
    _only_keys(defaults, ("mass_per_length", "radius"), source, "defaults")
    rig = {"name": doc.get("name") if isinstance(doc.get("name"), str) else "",
           "defaults": {"mass_per_length": _positive(defaults, "mass_per_length",
                                                     DEFAULT_MASS_PER_LENGTH, source, "defaults"),
                        "radius": _positive(defaults, "radius", DEFAULT_RADIUS, source, "defaults")}}
    if isinstance(doc.get("comment"), str):
        rig["comment"] = doc["comment"]
    if "bones" not in doc:
        raise InputError(source, "", "bones", "missing required field")
    if not isinstance(doc["bones"], list):
        raise InputError(source, "", "bones", "expected an array of bones")
    if not doc["bones"]:
        raise InputError(source, "", "bones", "the rig has no bones")
    parsed = [_parse_bone(b, i, source) for i, b in enumerate(doc["bones"])]
    for i, b in enumerate(parsed):
        _check_frame(b, source, _bone_element(b, i))
    for i, b in enumerate(doc["bones"]):
        if isinstance(b.get("comment"), str):
            parsed[i]["comment"] = b["comment"]
    out, tail_of, length_of = [], {}, {}
    for i in _dfs_order(parsed, source):
        b = dict(parsed[i])
        if b["parent"] is not None:
            gap = norm(sub(b["head"], tail_of[b["parent"]]))
            if gap > 1e-3 * length_of[b["parent"]]:
                raise InputError(source, _bone_element(b, i), "head", "does not meet the tail of its "
                                 "parent '%s' (gap %g); a joint is a parent's tail with its "
                                 "children's heads" % (b["parent"], gap))
            b["head"] = tail_of[b["parent"]]
        b["rest_frame"] = canonical_frame(b.pop("axes"), b["head"], b["tail"])
        tail_of[b["name"]] = b["tail"]
        length_of[b["name"]] = norm(sub(b["tail"], b["head"]))
        out.append(b)
    rig["bones"] = out
    return rig


def load_json(path):
    """A JSON file's contents; unreadable or malformed files raise InputError."""
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except OSError as e:
        raise InputError(path, "", "", "cannot read file (%s)" % (e.strerror or e))
    except ValueError as e:
        raise InputError(path, "", "", "not valid JSON (%s)" % e)


def load_rig(path):
    return parse_rig(load_json(path), path)


def bone_mass(rig, bone):
    """Total mass (kg) of a canonical bone: its mass, or mass per length x length."""
    if "mass" in bone:
        return bone["mass"]
    mpl = bone.get("mass_per_length", rig["defaults"]["mass_per_length"])
    return mpl * norm(sub(bone["tail"], bone["head"]))


def bone_radius(rig, bone):
    return bone.get("radius", rig["defaults"]["radius"])


def to_file_dict(rig):
    """A canonical rig back in the file format (lists, explicit rest frames)."""
    doc = {"name": rig.get("name", "")}
    if rig.get("comment"):
        doc["comment"] = rig["comment"]
    doc["defaults"] = dict(rig["defaults"])
    doc["bones"] = []
    for b in rig["bones"]:
        out = {"name": b["name"], "parent": b["parent"], "head": list(b["head"]),
               "tail": list(b["tail"]), "rest_frame": [list(a) for a in b["rest_frame"]]}
        if b.get("limits_deg"):
            out["limits_deg"] = {a: list(v) for a, v in b["limits_deg"].items()}
        for key in ("mass", "mass_per_length", "radius"):
            if key in b:
                out[key] = b[key]
        if "inertia_local" in b:
            out["inertia_local"] = list(b["inertia_local"])
        if b.get("comment"):
            out["comment"] = b["comment"]
        doc["bones"].append(out)
    return doc
