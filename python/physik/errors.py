"""The exceptions and warnings of the physik package.

The C++ core's errors arrive as these classes (python/bind_common.cpp translates them):
bad input is InputError, a run that diverged (when asked to raise) is DivergedError. A run that
starts with a bone into the ground or a box warns with StartContactWarning; a value normalised
rather than refused (a quaternion within 1e-3 of unit) with InputWarning.
"""


class InputError(ValueError):
    """Bad input: a malformed or contradictory file, dict or argument.

    str(error) is the CLI's one-line message, "<file>: <element>: field '<field>': <reason>"
    (the same text `physik` prints after "physik: error: " before it exits with status 2), with
    an option named by its Python keyword where the CLI names its flag ("tol: ..." for
    "--tol: ...", "overrides: ..." for "--set: ...").
    """


class DivergedError(RuntimeError):
    """A run diverged (a non-finite state, or kinetic energy past the scene's bound).

    Raised only on request (raise_on_divergence=True); otherwise divergence is the summary's
    "diverged" flag, as `physik simulate` exits 3 and still writes summary.json. str(error) is the
    divergence reason.
    """


class StartContactWarning(UserWarning):
    """A rig that starts into the ground or an obstacle (physik/engine/start_contacts.h).

    Issued (warnings.warn) when a Simulation, a PosingSession, solve() with an engine solver,
    run_scene() or tune() starts from a pose whose deepest contact with the ground or a box is
    more than 5% of the bone's collision radius and no more than that radius: the run begins by
    pushing the bone out. str(warning) is the CLI's warning text after "physik: warning: ". A
    bone started past the surface (deeper than its radius) is an InputError instead, as the CLI's
    exit 2.
    """


class InputWarning(UserWarning):
    """A value the reader changed rather than refused: a quaternion whose norm is within 1e-3 of
    1 (a value a person types, (0.7071, 0.7071, 0, 0)), normalised (Scene.load, Scene.from_dict,
    PosingSession.set_orientation_target). str(warning) is the CLI's warning text after
    "physik: warning: ", naming the file or method, the element and the field.
    """


class WriteBackWarning(UserWarning):
    """What a clip written from a rig's poses cannot hold (Clip.of_poses, follow()): a root moved
    along an axis it has no position channel for, a turn about an axis a joint has no rotation
    channel for. str(warning) is the CLI's warning text after "physik: warning: <file>: ".
    """
