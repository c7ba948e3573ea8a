"""The add-on's one door to the engine: `import physik` (pybind11; python/).

Nothing else in the add-on imports physik. When the module cannot be imported (not built, or not
on Blender's sys.path), every call raises EngineUnavailable; bad input the engine finds, and a
diverged run, raise EngineError (a rig: rig_format.InputError, with the engine's message). The
operators report both as one Blender error (never a made-up result, never a traceback).

Contract (the operators rely on exactly this):
  scene   a dict in the scene file format (models/README.md "Scenes") whose "rig" is the rig
          dict itself (rig file format) instead of a path; built by scene_dict.build_scene
  Pose    (root_head_world [x, y, z], {bone name: quaternion (w, x, y, z)}): the engine's Pose,
          rotations relative to rest in the bone's rest frame (physik/model/kinematics.h);
          armature_io.apply_pose puts it on the armature
  solve(scene)                 -> (Pose, summary dict)   run until converged (IK use); the summary
                                  is `physik simulate`'s, plus "heads_world" and "tails_world"
                                  (per bone, DFS order: the engine's double-precision result)
  Live(scene); .step(n)        -> Pose                   a live simulation, n steps per call
  trajectory(scene, steps)     -> [Pose] * (steps + 1)   the start pose and one per step
  param_table()                -> physik.param_table(): presets, default preset, rows
  load_rig(path), canonical_rig(doc, source)
                               -> the engine's canonical rig (physik.Rig(...).to_dict()): bones
                                  in DFS order, snapped heads, re-orthonormalised frames
"""
from .rig_format import InputError

MISSING = ("the physik Python module is not built; see blender/README.md "
           "(build it with the project's CMake and start Blender with it on PYTHONPATH)")

NO_NUMPY = ("numpy cannot be imported in Blender's Python (%s); Debian: apt-get install "
            "python3-numpy (Blender must run the system Python, not another one found on PATH)")


class EngineError(RuntimeError):
    """The engine refused the scene or diverged; str() is one line saying why."""


class EngineUnavailable(EngineError):
    """The engine cannot be reached from Blender; str() says why and what to do."""


def module():
    """The physik module, or EngineUnavailable."""
    try:
        import physik  # noqa: F401
    except ImportError as e:
        raise EngineUnavailable(MISSING) from e
    try:
        import numpy  # noqa: F401  (physik's poses are numpy arrays)
    except ImportError as e:
        raise EngineUnavailable(NO_NUMPY % (e,)) from e
    return physik


_AVAILABLE = None  # looked up once per session (the panel asks on every redraw)


def available():
    global _AVAILABLE
    if _AVAILABLE is None:
        try:
            module()
            _AVAILABLE = True
        except EngineUnavailable:
            _AVAILABLE = False
    return _AVAILABLE


def param_table():
    """The engine's parameter table, as `physik params --json` prints it."""
    return module().param_table()


def _rig_dict(make):
    physik = module()
    try:
        return make(physik).to_dict()
    except physik.InputError as e:
        raise InputError.from_message(str(e)) from None


def load_rig(path):
    """The canonical rig of a rig file, read by the engine (the CLI's checks and messages)."""
    return _rig_dict(lambda physik: physik.Rig.load(path))


def canonical_rig(doc, source):
    """The canonical rig of a dict in the rig file format; `source` names it in messages."""
    return _rig_dict(lambda physik: physik.Rig.from_dict(doc, source=source))


def _source(scene):
    rig = scene.get("rig")
    name = rig.get("name") if isinstance(rig, dict) else None
    return "armature '%s'" % name if name else "<Blender scene>"


def _simulation(scene):
    """physik.Simulation of the scene dict; the engine's bad-input message as EngineError."""
    physik = module()
    source = _source(scene)
    # "damping": "auto" is the engine's damping_auto (physik/engine/linear_modes.h)
    try:
        return physik.Simulation(physik.Scene.from_dict(scene, source=source))
    except physik.InputError as e:
        raise EngineError(str(e)) from None


def _check(sim, source):
    """EngineError when the run diverged (the pose would be meaningless)."""
    if sim.diverged:
        s = sim.summary
        # the engine's own advice for this run (robust preset, smaller dt or less damping)
        raise EngineError("%s: the simulation diverged at step %s (%s); %s"
                          % (source, s.get("steps_run"), s.get("divergence_reason"),
                             s.get("divergence_hint", "")))


def solve(scene):
    """Run the scene until every control point is within tolerance (or the run stalls)."""
    sim = _simulation(scene)
    summary = sim.run()
    _check(sim, _source(scene))
    pose = sim.pose
    summary["heads_world"] = pose.heads.tolist()
    summary["tails_world"] = pose.tails.tolist()
    return pose.as_blender(), summary


class Live:
    """A live simulation for the modal Simulate operator (steps past the scene's count go on)."""

    def __init__(self, scene):
        self._source = _source(scene)
        self.sim = _simulation(scene)

    def step(self, n):
        """Advance n steps; return the Pose."""
        self.sim.step(n)
        _check(self.sim, self._source)
        return self.sim.pose.as_blender()


def trajectory(scene, steps):
    """The start pose and the pose after each of `steps` steps, for Bake."""
    sim = _simulation(scene)
    poses = [sim.pose.as_blender()]
    for _ in range(steps):
        sim.step(1)
        poses.append(sim.pose.as_blender())
    _check(sim, _source(scene))
    return poses
