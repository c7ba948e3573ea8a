"""The add-on's one door to the engine: issue 16's `import physik` (pybind11).

Nothing else in the add-on imports physik. Until the module is built, every call raises
EngineUnavailable, which the operators report as a Blender error (never a made-up result).

Contract (for whoever plugs the module in; the operators rely on exactly this):
  scene   a dict in the scene file format (models/README.md "Scenes") whose "rig" is the rig
          dict itself (rig file format) instead of a path; built by scene_dict.build_scene
  Pose    (root_head_world [x, y, z], {bone name: quaternion (w, x, y, z)}): the engine's Pose,
          rotations relative to rest in the bone's rest frame (physik/model/kinematics.h);
          armature_io.apply_pose puts it on the armature (armature_io.local_rotations_from_world
          turns world orientations into these)
  solve(scene)                 -> (Pose, summary dict)   run until converged (IK use)
  Live(scene); .step(n)        -> Pose                   a live simulation, n steps per call
  trajectory(scene, steps)     -> [Pose] * (steps + 1)   the start pose and one per step
"""

MISSING = ("the physik Python module is not built; see blender/README.md "
           "(build it with the project's CMake and start Blender with it on PYTHONPATH)")


class EngineUnavailable(RuntimeError):
    """The engine cannot be reached from Blender; str() says why and what to do."""


def module():
    """The physik module, or EngineUnavailable."""
    try:
        import physik  # noqa: F401  (issue 16)
    except ImportError as e:
        raise EngineUnavailable(MISSING) from e
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


def _not_bridged(what):
    # the module exists but this bridge is not written yet: say so instead of guessing its API
    return EngineUnavailable("the physik module is present but the add-on's bridge '%s' is not "
                             "written yet (blender/physik_addon/engine.py)" % what)


def solve(scene):
    """Run the scene until every control point is within tolerance (or the run stalls)."""
    module()
    # plug in: physik.Scene.from_dict(scene) with convergence.stop_at_residual_tol, then
    # Simulation(s).run(); return (root head, local rotations) and .summary
    raise _not_bridged("solve")


class Live:
    """A live simulation for the modal Simulate operator."""

    def __init__(self, scene):
        module()
        # plug in: self.sim = physik.Simulation(physik.Scene.from_dict(scene))
        raise _not_bridged("Live")

    def step(self, n):
        """Advance n steps; return the Pose."""
        raise _not_bridged("Live.step")


def trajectory(scene, steps):
    """The start pose and the pose after each of `steps` steps, for Bake."""
    module()
    # plug in: sim.step(1) in a loop, reading sim.pose after each step
    raise _not_bridged("trajectory")
