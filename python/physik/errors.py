"""The exceptions of the physik package.

The C++ core's errors arrive as these classes (python/bind_common.cpp translates them):
bad input is InputError, a run that diverged (when asked to raise) is DivergedError.
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
