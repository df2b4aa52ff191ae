"""Return codes of the compiled driver and what each one means for a :class:`Response`.

The driver (:mod:`.driver`) ends every run with one of these integers; the compiled code
compares against the module constants and the Python side (:mod:`.analysis`) turns them into
a :class:`~rocking.dynamics.result.Status` and a reason with :func:`status_of`. Nothing else
compares codes as bare integers.
"""

from __future__ import annotations

from rocking.dynamics.result import Status

OK = 0
"""Reached the end time."""
OVERTURNED = 1
"""The tilt reached π/2."""
STOPPED = 2
"""The tilt exceeded the requested ``stop_at`` level."""
AT_REST = 3
"""Back at rest: the rocking energy at a tilt minimum (3D) or after an impact (2D) fell below
the rest criterion (docs/equations.md, "Back at rest")."""
AT_PEAK = 4
"""Stopped at the first tilt maximum (asked for by the free tail)."""
DECIDED = 5
"""Stopped at a tilt minimum (3D) or an impact (2D) once the rest of the motion provably
cannot raise the peak tilt: every ground acceleration left is below uplift and the energy it
can still feed in keeps the body below its peak so far (:func:`rocking.dynamics.driver.decided`)."""
UNDERFLOW = -1
"""The step size fell below its floor while the error stayed too large."""
NEGATIVE_TILT = -2
"""3D: every step shorter than the floor still ends with θ ≤ 0 (planar motion)."""
NONFINITE = -3
"""A step produced NaN or inf at every step size down to the floor."""
TOO_MANY_STEPS = -4
"""The budget of accepted plus rejected steps ran out."""

FAILURES: dict[int, str] = {
    UNDERFLOW: "step-size underflow (the error could not be controlled)",
    NEGATIVE_TILT: "the tilt reached zero: theta <= 0 (nearly planar 3D motion; use model='2d')",
    NONFINITE: "non-finite state (NaN or inf)",
    TOO_MANY_STEPS: "too many integration steps",
}
"""Message of each failure code."""


def status_of(code: int, t_stop: float) -> tuple[Status, str]:
    """The :class:`Status` and the reason of a run that ended with ``code`` at ``t_stop`` [s].

    Raises
    ------
    ValueError
        For an integer that is not a code of this module.
    """
    if code < 0:
        if code not in FAILURES:
            raise ValueError(f"unknown kernel code {code!r}")
        return Status.FAILED, f"{FAILURES[code]} at t = {t_stop:.9g} s"
    if code == OVERTURNED:
        return Status.OVERTURNED, ""
    if code == STOPPED:
        return Status.STOPPED_AT_LIMIT, ""
    if code == AT_REST:
        return Status.OK, f"came back to rest at t = {t_stop:.9g} s"
    if code in (OK, AT_PEAK, DECIDED):
        return Status.OK, ""
    raise ValueError(f"unknown kernel code {code!r}")
