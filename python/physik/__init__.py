"""PhysIK from Python: the testbed's C++ engine, its classic IK solvers, the MuJoCo reference and
the Ceres tools, with the CLI's names, files and messages.

    import physik
    scene = physik.Scene.load("models/scenes/pinhead_two_hands.json", overrides={"damping": 1})
    sim = physik.Simulation(scene)
    sim.step(10)
    sim.pose.heads            # (nbone, 3) numpy view of the state, no copy, read-only
    summary = sim.run()       # `physik simulate`'s summary.json as a dict

Names (each has its own docstring):
  Rig.load(path), Rig.chain(n), Rig.from_dict(d)            rigs (models/README.md)
  Scene.load(path, overrides, steps), Scene.from_dict(d)    scenes; Scene.update(params=...)
  param_table()                                             the parameters (`physik params --json`)
  Simulation(scene): .step(n), .run(), .pose, .summary      the engine, stepped from Python
  Simulation.run(record_every=N)                            and its trajectory as arrays
  PosingSession(scene): .set_target, .advance, .solve, .pose  the engine embedded in a tool
  solve(scene, solver)                                      `physik solve`
  export_mjcf(rig), compare_mujoco(scene, mode)             the MuJoCo reference
  tune(scene, params, objective), equilibrium(scene)        Ceres
  view(runs, path)                                          `physik view`: run folders in 3D
  Clip.load(path), clip.frames, clip.write(path)            BVH/qBVH clips as numpy arrays
  Rig.from_bvh(path or clip), rig.source_skeleton           `physik rig from-bvh`
  clip.pose(rig, frame), Clip.of_poses(rig, poses, ...)     a clip's frame as a pose, and back
  follow(clip, rig, ...), follow_scene(clip, rig, ...)      `physik follow`
  InputError (a ValueError), DivergedError                  errors
  StartContactWarning                                       a rig started into the ground or a box
  InputWarning                                              a value normalised (a quaternion)
  __version__                                               `physik --version`
  physik.sweep                                              grids of runs on Dask (python3 -m physik.sweep)

Conventions (docs/DESIGN.md "Conventions"): world Z up, rig units, kg, s, radians; arrays per
bone in DFS order (parents first); quaternions are stored (x, y, z, w), Eigen's order (as
scipy.spatial.transform.Rotation.from_quat reads them); Pose.as_blender() gives (w, x, y, z).
"""
from collections import namedtuple

from .errors import DivergedError, InputError, InputWarning, StartContactWarning, WriteBackWarning
from . import _core
from ._core import (Clip, PosingSolveResult, Rig, Scene, __version__, compare_mujoco, export_mjcf,
                    param_table, scaled_scene, solve_mode_rule, steps_mode_rule)

__all__ = ["Rig", "Scene", "param_table", "Simulation", "Pose", "Trajectory", "RunResult",
           "PosingSession", "PosingSolveResult", "solve_mode_rule", "steps_mode_rule", "SolveResult",
           "solve",
           "export_mjcf", "compare_mujoco", "scaled_scene", "tune", "equilibrium", "view", "View",
           "Clip", "follow", "follow_scene", "FollowRun", "InputError", "DivergedError",
           "InputWarning", "StartContactWarning", "WriteBackWarning", "__version__"]


class Pose:
    """A rig's pose as numpy arrays, per bone in DFS order.

    heads, tails        (nbone, 3) world positions, rig units
    orientations        (nbone, 4) world<-bone rotations, quaternions (x, y, z, w)
    local_rotations     (nbone, 4) rotations relative to rest in the bone's rest frame (the
                        engine's Pose, Blender's pose-bone rotation), quaternions (x, y, z, w)
    root_head           (3,) the root bone's head, world, rig units
    bone_names          the rig's bone names, same order
    joint_angles        (nbone, 3) each joint's angles, rad: component k is the angle about
                        the bone's rest axis k that the rig's limit on axis k bounds, as the
                        scene's scheme measures it (physik/model/joint_angles.h): the local
                        rotation's rotation vector (its log map, |angle| <= pi) for a ball and
                        for every joint in the paper's scheme; in the exact and implicit schemes
                        a hinge's or universal joint's own angles on its free axes, and on a
                        locked axis its value plus the turn off the joint there
    limit_excess        (nbone, 3) how far each angle is past its limit, rad, signed: angle - max
                        above the max, angle - min (negative) below the min, 0 within the limits
                        and on a free axis; the root's too (a pinned root's limits hold against
                        its rest frame in the world); its largest |value| is the pose's limit
                        violation (what the summaries' max_limit_violation_deg give in degrees)

    From Simulation.pose and PosingSession.pose the arrays are read-only views of the live state:
    they follow every step without being fetched again; joint_angles and limit_excess are
    computed from the state each time they are read (new arrays). From solve() and equilibrium()
    every array is a copy.
    """

    __slots__ = {
        "heads": "(nbone, 3) bone heads, world, rig units",
        "tails": "(nbone, 3) bone tails, world, rig units",
        "orientations": "(nbone, 4) world<-bone rotations, quaternions (x, y, z, w)",
        "local_rotations": "(nbone, 4) rest-relative rotations in the bone's rest frame, (x, y, z, w)",
        "root_head": "(3,) the root bone's head, world, rig units",
        "bone_names": "bone names, DFS order",
        "_angles": "(joint_angles, limit_excess), or a function that computes them now",
    }

    def __init__(self, heads, tails, orientations, local_rotations, root_head, bone_names,
                 angles=None):
        """A Pose of the given arrays (Simulation.pose, PosingSession.pose, solve() and
        equilibrium() build them); angles: (joint_angles, limit_excess), or a function returning
        them for a live pose."""
        self.heads = heads
        self.tails = tails
        self.orientations = orientations
        self.local_rotations = local_rotations
        self.root_head = root_head
        self.bone_names = bone_names
        self._angles = angles

    def _angle_arrays(self):
        if self._angles is None:
            raise AttributeError("this Pose was built without its joint angles")
        return self._angles() if callable(self._angles) else self._angles

    @property
    def joint_angles(self):
        """(nbone, 3) rotation vectors of the local rotations, rad, per rest axis x, y, z."""
        return self._angle_arrays()[0]

    @property
    def limit_excess(self):
        """(nbone, 3) signed excess of each joint angle past its limit, rad (0 within it)."""
        return self._angle_arrays()[1]

    def as_blender(self):
        """(root_head_world [x, y, z], {bone name: (w, x, y, z)}): the pose as the Blender
        add-on applies it (blender/physik_addon/engine.py), copied out of the arrays."""
        rotations = {name: (float(q[3]), float(q[0]), float(q[1]), float(q[2]))
                     for name, q in zip(self.bone_names, self.local_rotations)}
        return [float(v) for v in self.root_head], rotations

    def __repr__(self):
        return "<physik.Pose of %d bones>" % len(self.bone_names)


def _pose_from_arrays(arrays, bone_names):
    return Pose(arrays["heads"], arrays["tails"], arrays["orientations"],
                arrays["local_rotations"], arrays["root_head"], bone_names,
                (arrays["joint_angles"], arrays["limit_excess"]))


Trajectory = namedtuple("Trajectory", ["steps", "times", "kinetic_energy", "passes",
                                       "joint_mismatch", "joint_separation", "residuals",
                                       "heads", "tails"])
Trajectory.__doc__ = """Simulation.run(record_every=N)'s trajectory: `physik simulate --every N`'s
trajectory.csv as numpy arrays, one row per recorded state, in step order.

steps (rows,) int, times (rows,) s, kinetic_energy (rows,) J, passes (rows,) int (joint passes
of the step), joint_mismatch (rows,) rig units/s^2, joint_separation (rows,) rig units,
residuals (rows, ncontrol) each control point's distance to its goal target, rig units,
heads and tails (rows, nbone, 3) world, rig units. The first row is the state run() started from
(step 0 for a fresh Simulation: no step taken, so passes and joint_mismatch are 0); then every
N-th step and the scene's last step. A row with a non-finite value (a diverging state) is left
out, as the CSV leaves it out."""

RunResult = namedtuple("RunResult", ["summary", "trajectory"])
RunResult.__doc__ = """Simulation.run(record_every=N)'s result: summary (`physik simulate`'s
summary.json as a dict) and trajectory (a Trajectory)."""


class Simulation(_core.Simulation):
    __doc__ = _core.Simulation.__doc__

    def __init__(self, scene):
        """Start a run of `scene` (a physik.Scene, copied) at step 0, in its initial pose."""
        if isinstance(scene, dict):
            raise TypeError("Simulation(scene) takes a physik.Scene; use Scene.from_dict(d) for a dict")
        super().__init__(scene)
        self._bone_names = scene.rig.bone_names

    def run(self, raise_on_divergence=False, record_every=0):
        """Run to the scene's step count (or until the run stops) and return the summary.

        From a fresh Simulation this is `physik simulate SCENE`: the same summary.json keys and
        values (and final_state_hash), wall_time_s aside. Divergence is the summary's "diverged"
        flag; with raise_on_divergence it raises DivergedError instead.

        record_every=N (N >= 1) also keeps `physik simulate --every N`'s trajectory and returns
        RunResult(summary, trajectory) (see Trajectory): a row for the state the run starts from,
        then every N-th step and the scene's last. 0 (the default) keeps none and returns the
        summary alone."""
        out = self._run(raise_on_divergence, record_every)
        if not record_every:
            return out
        summary, arrays = out
        return RunResult(summary, Trajectory(**arrays))

    @property
    def pose(self):
        """The current pose as read-only numpy views of the state (a Pose; no copy).

        The views stay valid, and follow the state, for as long as they are referenced (each keeps
        this Simulation alive); writing to them raises ValueError. Orientations and local
        rotations are quaternions (x, y, z, w). Copy (numpy.array(view)) to keep a snapshot.
        joint_angles and limit_excess are computed from the state when read."""
        heads, tails, orient, local, root = self._views()
        return Pose(heads, tails, orient, local, root, self._bone_names, self._joint_angles)


class PosingSession(_core.PosingSession):
    __doc__ = _core.PosingSession.__doc__

    def __init__(self, scene, solve_mode=False):
        """Hold `scene` (a physik.Scene, copied) open in its initial pose; solve_mode=True gives
        it the solve mode's engine settings (scheme implicit, torsion_torque gradient)."""
        if isinstance(scene, dict):
            raise TypeError("PosingSession(scene) takes a physik.Scene; use Scene.from_dict(d) "
                            "for a dict")
        super().__init__(scene, solve_mode)
        self._bone_names = scene.rig.bone_names

    def set_pose(self, pose, root_head=None):
        """Put a pose in, at rest: a Pose (its local_rotations and root_head), or (nbone, 4)
        local rotations (x, y, z, w) and root_head (3,). The targets stay; each control point's
        pull starts again from its point on the new pose. A wrong shape or a rotation that is not
        a finite unit quaternion raises InputError."""
        if isinstance(pose, Pose):
            if root_head is not None:
                raise TypeError("set_pose(pose): a Pose carries its own root_head")
            self._set_pose(pose.local_rotations, pose.root_head)
        elif root_head is None:
            raise TypeError("set_pose(local_rotations, root_head): root_head is missing")
        else:
            self._set_pose(pose, root_head)

    @property
    def pose(self):
        """The session's pose as read-only numpy views of its state (a Pose; no copy), as
        Simulation.pose: they follow set_target, set_pose, advance and solve."""
        heads, tails, orient, local, root = self._views()
        return Pose(heads, tails, orient, local, root, self._bone_names, self._joint_angles)


SolveResult = namedtuple("SolveResult", ["summary", "pose"])
SolveResult.__doc__ = """physik.solve's result: summary (`physik solve`'s summary.json as a dict)
and pose (a Pose of copies: the solved pose)."""


def _make_solve():
    """physik.solve, its keywords, defaults and doc from the solve options' table
    (physik/posing/solve_options.h), as `physik solve`'s flags are."""
    import inspect
    rows = _core._solve_option_table()
    keyword = {"lambda": "lambda_"}  # `lambda` is a Python keyword
    params = [inspect.Parameter("scene", inspect.Parameter.POSITIONAL_OR_KEYWORD),
              inspect.Parameter("solver", inspect.Parameter.POSITIONAL_OR_KEYWORD, default="physik")]
    params += [inspect.Parameter(keyword.get(r["name"], r["name"]), inspect.Parameter.KEYWORD_ONLY,
                                 default=r["default"]) for r in rows if r["name"] != "solver"]
    params.append(inspect.Parameter("raise_on_divergence", inspect.Parameter.KEYWORD_ONLY,
                                    default=False))
    signature = inspect.Signature(params)

    def solve(*args, **kwargs):
        bound = signature.bind(*args, **kwargs)
        bound.apply_defaults()
        given = dict(bound.arguments)
        scene, raise_on_divergence = given.pop("scene"), given.pop("raise_on_divergence")
        options = {("lambda" if k == "lambda_" else k): v for k, v in given.items()}
        summary, arrays = _core._solve(scene, options, raise_on_divergence)
        return SolveResult(summary, _pose_from_arrays(arrays, scene.rig.bone_names))

    lines = []
    for r in rows:
        unit = " (%s)" % r["unit"] if r["unit"] not in ("", "1") else ""
        choices = ": " + "|".join(r["choices"]) if r["choices"] else ""
        lines.append("    %s%s: %s%s" % (keyword.get(r["name"], r["name"]), unit, r["doc"], choices))
    solve.__signature__ = signature
    solve.__name__ = solve.__qualname__ = "solve"
    solve.__doc__ = (
        "Solve the scene's goals (control points at their final targets, orientation targets, "
        "aims): `physik solve`.\n\n"
        "The keywords are the solve options, `physik solve`'s flags and a scene's \"solve\" keys "
        "(one table):\n" + "\n".join(lines) + "\n\n"
        "A bad option raises InputError naming the keyword. Returns SolveResult(summary, pose). The "
        "engine's divergence is the summary's flag, or DivergedError with raise_on_divergence.")
    return solve


solve = _make_solve()


def tune(scene, params="damping", objective="settle", *, bounds=None, measure="log", steps=0,
         scan_points=13, max_iterations=50, verbose=False):
    """Tune engine coefficients of the scene with Ceres: `physik tune SCENE --report`.

    params: "damping,control_k", a list of names, or a dict {name: (lo, hi) or None}; bounds:
    {name: (lo, hi)} (as --bounds name=lo:hi); objective: "settle" or "mujoco"; measure: "log" or
    "linear"; steps: steps per run (0 = the scene's). Unknown names raise InputError naming
    params (or bounds). Returns the CLI's report as a dict, plus "ceres_full" (Ceres' full
    report) and "tuned_scene" (a Scene with the tuned values).
    """
    return _core._tune(scene, params, bounds, objective, measure, steps, scan_points,
                       max_iterations, verbose)


def equilibrium(scene, *, start="initial", compare=False, with_pose=False):
    """The exact static pose of the scene (Ceres): `physik equilibrium SCENE [--start S] [--compare]`.

    start: "initial" (the scene's initial pose) or "physik" (PhysIK's final pose); compare: also run
    PhysIK and report its final-pose distance in the result's "physik" entry. Returns the CLI's
    JSON as a dict, or (dict, Pose) with with_pose. When Ceres stops short of convergence, the
    dict holds its last iterate with "converged" False (the CLI exits 4): read that flag, as
    solve()'s summary's.
    """
    doc, arrays = _core._equilibrium(scene, start, compare)
    if with_pose:
        return doc, _pose_from_arrays(arrays, scene.rig.bone_names)
    return doc


class View:
    """A page physik.view() wrote: its path and size. In Jupyter the page displays in place (an
    iframe holding the page: it needs no network and no file server)."""

    __slots__ = ("path", "size")

    def __init__(self, path, size):
        self.path = path  # the HTML file
        self.size = size  # bytes

    def _repr_html_(self):
        import html
        with open(self.path, encoding="utf-8") as f:
            page = f.read()
        return ('<iframe srcdoc="%s" style="width: 100%%; height: 820px; border: 0"></iframe>'
                % html.escape(page, quote=True))

    def __repr__(self):
        return "<physik.View %s (%d KB)>" % (self.path, self.size // 1024)


def view(runs, path=None, *, title=None, labels=None, max_frames=10000):
    """One self-contained HTML page that plays run folders in 3D: `physik view RUN_DIR...`.

    runs: a run folder (`physik simulate --out DIR`; `--reference` adds DIR/mujoco) or a list of
    them, overlaid in distinct colours (their rigs must have the same bones); path: the HTML file
    (default: view.html in the first folder); title, labels (one per run), max_frames (per run;
    a longer run is decimated to that many evenly spread rows, and the page says so) as the
    CLI's --title, --label, --max-frames. A folder that is not a run folder, an empty trajectory
    or rigs with other bones raise InputError naming the folder. Returns a View (its path;
    shown in place in Jupyter).
    """
    import os
    folders = [os.fspath(runs)] if isinstance(runs, (str, os.PathLike)) else [
        os.fspath(r) for r in runs]
    if path is None:
        path = os.path.join(folders[0], "view.html") if folders else "view.html"
    size = _core._view(folders, os.fspath(path), title or "", list(labels or []), max_frames)
    return View(os.fspath(path), size)


def _clip_pose(self, rig, frame):
    """The rig's pose of frame `frame` (from 0) of this clip, a clip of the rig's source skeleton
    (its joint names, parents, channels, OFFSETs): a Pose of copies. `physik follow`'s and an
    initial_pose {"bvh", "frame"}'s reading of a clip. A clip of another skeleton or a frame
    outside the clip raises InputError."""
    return _pose_from_arrays(self._pose(rig, frame), rig.bone_names)


def _clip_of_poses(rig, poses, frame_time=1.0 / 30.0, *, source=None, source_frames=None,
                   quaternion=False, euler_order="", own_skeleton=False):
    """A clip of `rig`'s poses on its source skeleton (the write-back of `physik bvh convert`,
    `solve --bvh`, `follow --bvh`): the source's joint names, hierarchy, channels, units, axes.

    poses: a list of Pose (or of (local_rotations (nbone, 4) (x, y, z, w), root_head (3,)));
    frame_time: seconds per frame; source: the clip the poses came from (a Clip of the source
    skeleton) and source_frames the frame each pose came from (default: pose i from frame i;
    -1 for none): what the rig cannot hold comes from that frame (the rotation of a joint with no
    bone, a stretch channel, the Euler branch), so a frame nothing moved comes back as it was;
    quaternion: qBVH channels; euler_order: every three-angle joint's order; own_skeleton: the
    rig's own skeleton (one joint per bone) instead. What the file cannot hold warns with
    WriteBackWarning."""
    import warnings
    import numpy
    rotations = numpy.array([p.local_rotations if isinstance(p, Pose) else p[0] for p in poses],
                            dtype=float).reshape(len(poses), rig.nbone, 4)
    roots = numpy.array([p.root_head if isinstance(p, Pose) else p[1] for p in poses],
                        dtype=float).reshape(len(poses), 3)
    if source is not None and source_frames is None:
        source_frames = list(range(len(poses)))
    clip, messages = _core._clip_of_poses(rig, rotations, roots, frame_time, source,
                                          list(source_frames or []), quaternion, euler_order,
                                          own_skeleton)
    for m in messages:
        warnings.warn(m, WriteBackWarning, stacklevel=2)
    return clip


Clip.pose = _clip_pose
Clip.of_poses = staticmethod(_clip_of_poses)

FollowRun = namedtuple("FollowRun", ["summary", "clip", "scene"])
FollowRun.__doc__ = """follow()'s result: summary (`physik follow`'s summary.json as a dict), clip
(the run on the rig's source skeleton, a Clip: one frame per followed clip frame, at the engine's
time per clip frame, as `physik follow --bvh` writes it) and scene (the follow scene that ran)."""


def _follow_options(clip, frames):
    first, last = (0, -1) if frames is None else frames
    return int(first), (-1 if last is None else int(last))


def follow_scene(clip, rig, *, points=None, frames=None, ground=0.0, gravity=False, params=None):
    """The scene `physik follow` runs: control points on chosen bones track the clip's joints
    frame by frame, starting at rest in the first frame's pose (physik/io/clip_follow.h).

    clip: a Clip of the rig's source skeleton; rig: a Rig made from it (Rig.from_bvh); points:
    bone names, or (bone, alpha) pairs (0 head, 1 tail; default: the root bone's tail and every
    leaf bone's tail); frames: (first, last) clip frames from 0 (None: all); ground: the floor's
    height (None: no floor); gravity: -9.81 along Z; params: {param: value} as `--set`. Bad input
    raises InputError naming the field."""
    first, last = _follow_options(clip, frames)
    pts = [(p, 1.0) if isinstance(p, str) else (str(p[0]), float(p[1])) for p in (points or [])]
    return _core._follow_scene(clip, rig, pts, first, last, ground, gravity, params)


def follow(clip, rig, *, points=None, frames=None, ground=0.0, gravity=False, params=None,
           raise_on_divergence=False):
    """Follow a clip with the PhysIK engine: `physik follow CLIP --rig RIG --bvh OUT`.

    The keywords are follow_scene's. Returns FollowRun(summary, clip, scene): the run's summary,
    the run on the rig's source skeleton as a Clip with one frame per followed clip frame at the
    engine's time per clip frame, as `--bvh` writes it (clip.write(path) writes it; what the rig
    cannot hold, the rotation of a joint with no bone and a stretch channel, comes from the clip
    frame each state stands for), and the scene. A diverged run is the summary's flag, or
    DivergedError with raise_on_divergence."""
    import numpy
    scene = follow_scene(clip, rig, points=points, frames=frames, ground=ground, gravity=gravity,
                         params=params)
    first, _ = _follow_options(clip, frames)
    sim = Simulation(scene)
    poses, followed = [], []

    def keep(frame):
        pose = sim.pose
        if numpy.all(numpy.isfinite(pose.local_rotations)) and numpy.all(
                numpy.isfinite(pose.root_head)):
            poses.append((numpy.array(pose.local_rotations), numpy.array(pose.root_head)))
            followed.append(first + frame)

    keep(0)
    while not sim.stopped and sim.step_count < scene.steps:
        sim.step(1, raise_on_divergence=raise_on_divergence)
        frame = _core._followed_frame(scene, sim.step_count)
        if frame > 0 and not sim.diverged:
            keep(frame)
    out = _clip_of_poses(rig, poses, _core._follow_frame_time(scene), source=clip,
                         source_frames=followed)
    return FollowRun(sim.summary, out, scene)


def _wrap_the_api():
    """Bad arguments to any public name raise a one-line TypeError naming the valid keywords
    (physik/_arguments.py)."""
    from . import _arguments as args
    names = globals()
    for name in ("param_table", "export_mjcf", "compare_mujoco", "solve_mode_rule", "steps_mode_rule",
                 "scaled_scene"):
        names[name] = args.compiled(getattr(_core, name), name)
    for name in ("solve", "tune", "equilibrium", "view", "follow", "follow_scene"):
        names[name] = args.python(names[name], name)
    args.wrap_class(Rig, ["load", "chain", "from_dict", "to_dict", "find_bone", "from_bvh"])
    args.wrap_class(Clip, ["load", "parse", "write", "copy", "pose", "of_poses"])
    args.wrap_class(Scene, ["load", "from_dict", "to_dict", "update", "copy"])
    args.wrap_class(_core.Simulation, ["step"])
    args.wrap_class(Simulation, ["__init__", "run"])
    args.wrap_class(_core.PosingSession, ["set_target", "advance", "solve", "residual", "summary",
                                          "set_orientation_target", "set_aim_target", "set_pin",
                                          "clear_orientation_target", "clear_aim_target",
                                          "clear_pin"])
    args.wrap_class(PosingSession, ["__init__", "set_pose"])
    args.wrap_class(Pose, ["__init__", "as_blender"])


_wrap_the_api()
