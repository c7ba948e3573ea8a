"""The parts of a scene file (models/README.md "Scenes") that a static IK solve needs: the rig,
the control points (bone, alpha, target) and the initial pose. No Blender here."""
import math
import os

from . import rig_format
from .rig_format import InputError, _number, _vec3


def load_scene(path, rig_path=None):
    """{"rig", "rig_path", "control_points", "initial_pose", "residual_tol"} of a scene file.
    Raises InputError naming the file, the element and the field."""
    doc = rig_format.load_json(path)
    if not isinstance(doc, dict):
        raise InputError(path, "", "", "expected a JSON object")
    if rig_path is None:
        if not isinstance(doc.get("rig"), str):
            raise InputError(path, "", "rig", "missing (the rig file, relative to the scene)")
        rig_path = os.path.join(os.path.dirname(os.path.abspath(path)), doc["rig"])
    rig = rig_format.load_rig(rig_path)
    if doc.get("schedule"):
        raise InputError(path, "", "schedule", "a moving target cannot be one static IK solve")
    names = {b["name"] for b in rig["bones"]}
    cps = doc.get("control_points", [])
    if not isinstance(cps, list) or not cps:
        raise InputError(path, "", "control_points", "expected a non-empty array")
    out = []
    for i, c in enumerate(cps):
        el = "control_points[%d]" % i
        if not isinstance(c, dict):
            raise InputError(path, el, "", "expected an object")
        if c.get("bone") not in names:
            raise InputError(path, el, "bone", "unknown bone %r" % (c.get("bone"),))
        alpha = _number(c.get("alpha", 1.0), path, el, "alpha")
        if not 0.0 <= alpha <= 1.0:
            raise InputError(path, el, "alpha", "%g is outside [0, 1]" % alpha)
        if "target" not in c:
            raise InputError(path, el, "target", "missing")
        name = c.get("name") if isinstance(c.get("name"), str) else "%s@%g" % (c["bone"], alpha)
        out.append({"name": name, "bone": c["bone"], "alpha": alpha,
                    "target": _vec3(c["target"], path, el, "target")})
    return {"rig": rig, "rig_path": rig_path, "control_points": out,
            "initial_pose": _initial_pose(doc, path, names),
            "residual_tol": _tolerance(doc, path, rig)}


def _initial_pose(doc, path, names):
    ip = doc.get("initial_pose") or {}
    if not isinstance(ip, dict):
        raise InputError(path, "initial_pose", "", "expected an object")
    pose = {"root_head": None, "rotation_deg": {}}
    if ip.get("root_head") is not None:
        pose["root_head"] = _vec3(ip["root_head"], path, "initial_pose", "root_head")
    rot = ip.get("rotation_deg") or {}
    if not isinstance(rot, dict):
        raise InputError(path, "initial_pose", "rotation_deg", "expected an object")
    for bone, v in rot.items():
        if bone not in names:
            raise InputError(path, "initial_pose", "rotation_deg", "unknown bone %r" % bone)
        pose["rotation_deg"][bone] = _vec3(v, path, "initial_pose", "rotation_deg." + bone)
    return pose


def _tolerance(doc, path, rig):
    conv = doc.get("convergence") or {}
    tol = 0.0
    if isinstance(conv, dict) and conv.get("residual_tol") is not None:
        tol = _number(conv["residual_tol"], path, "convergence", "residual_tol")
    if tol > 0.0:
        return tol
    zs = [p[2] for b in rig["bones"] for p in (b["head"], b["tail"])]
    return 1e-3 * (max(zs) - min(zs))  # the engine's default: 1e-3 x rig height


def rotation_from_vector_deg(v):
    """Unit quaternion (w, x, y, z) of a rotation vector given in degrees."""
    r = [math.radians(c) for c in v]
    angle = math.sqrt(sum(c * c for c in r))
    if angle < 1e-15:
        return (1.0, 0.0, 0.0, 0.0)
    return rig_format.quat_axis_angle([c / angle for c in r], angle)
