"""Critical intensities of a cylinder under a scaled ground motion: the search bound to
the dynamics engine, for one spectrum point or a batch of them (one Dask task).

PGA is always the pair's vector PGA max √(ax² + ay²), also for the 2D modes (§5.4), so the
scale factor of the motion is I·g·tan α / PGA.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import replace

import numpy as np

from .._validate import positive_finite
from ..constants import G
from ..dynamics.bodies import Block, Cylinder
from ..dynamics.result import Status
from ..motions.motion import GroundMotion
from .accuracy import Accuracy, get_accuracy
from .limit_states import parse_limit_states
from .search import DEFAULT_UPPER, AnalysisFn, CriticalResult, Outcome, search_critical

MODES: dict[str, tuple[str, str | None]] = {
    "3d": ("3d", None),
    "3d-damped": ("3d-damped", None),
    "2d-x": ("2d", "x"),
    "2d-y": ("2d", "y"),
}
"""Mode → (dynamics model, component exciting the 2D model or None for the pair)."""


def check_mode(mode: str) -> str:
    """Return ``mode`` if it is one of :data:`MODES`, else raise ValueError naming it."""
    if mode not in MODES:
        raise ValueError(f"mode must be one of {list(MODES)}, got {mode!r}")
    return mode


def uplift_intensity(motion: GroundMotion, mode: str) -> float:
    """Normalized intensity below which the body stays at rest [-].

    1 for the 3D modes (the vector acceleration reaches g tan α at the vector PGA); for a
    2D mode PGA/max|a_component|, since only that component acts. ``inf`` when the
    component is identically zero.
    """
    check_mode(mode)
    component = MODES[mode][1]
    if component is None:
        return 1.0
    a = motion.ax if component == "x" else motion.ay
    peak = float(np.max(np.abs(a)))
    return math.inf if peak == 0.0 else motion.pga / peak


def _model_kwargs(mode: str, omega_n: float | None, zeta: float | None) -> dict:
    """Contact-model parameters, passed only to the damped model (ignored otherwise)."""
    if MODES[mode][0] != "3d-damped":
        return {}
    kw = {}
    if omega_n is not None:
        kw["omega_n"] = positive_finite("omega_n", omega_n)
    if zeta is not None:
        kw["zeta"] = positive_finite("zeta", zeta)
    return kw


def make_analysis(
    body: Cylinder | Block,
    motion: GroundMotion,
    mode: str = "3d",
    *,
    omega_n: float | None = None,
    zeta: float | None = None,
) -> AnalysisFn:
    """Bind :func:`rocking.dynamics.analysis.ground_response` to ``analyze(I, stop_at, rtol)``.

    The motion is scaled so that the pair's vector PGA equals I·g·tan α; the 2D modes are
    excited by one component (``motion.component``) scaled by the same factor.
    """
    from ..dynamics.analysis import ground_response  # the engine is imported only when needed

    check_mode(mode)
    model, component = MODES[mode]
    excitation = motion if component is None else motion.component(component)
    unit_scale = G * body.tan_alpha / motion.pga
    kw = _model_kwargs(mode, omega_n, zeta)

    def analyze(intensity: float, stop_at: float | None, rtol: float) -> Outcome:
        r = ground_response(body, excitation, model=model, scale=intensity * unit_scale,
                            stop_at=stop_at, rtol=rtol, history=False, **kw)
        return Outcome(float(r.theta_max), bool(r.overturned), Status(r.status), r.reason)

    return analyze


def critical_intensity(
    body: Cylinder | Block,
    motion: GroundMotion,
    limit_states=None,
    mode: str = "3d",
    *,
    accuracy: str | Accuracy | dict = "default",
    upper: float = DEFAULT_UPPER,
    omega_n: float | None = None,
    zeta: float | None = None,
) -> CriticalResult:
    """Critical normalized intensities PGA/(g tan α) of a body under a scaled motion.

    Parameters
    ----------
    body : Cylinder or Block
        The rocking body (R [m], tan α [-]).
    motion : GroundMotion
        The unscaled ground-motion pair; its vector PGA normalizes the intensity in every
        mode.
    limit_states : str, sequence or None
        E.g. ``["tilt:1/3", "overturning"]``; None: the seven defaults.
    mode : {"3d", "3d-damped", "2d-x", "2d-y"}
        Model and excitation (2D: one component of the pair).
    accuracy : str, Accuracy or dict
        ``"fast"``, ``"default"``, ``"precise"`` or custom tolerances.
    upper : float
        Highest normalized intensity searched [-].
    omega_n, zeta : float, optional
        Contact spring frequency [rad/s] and damping ratio [-] of the "3d-damped" model
        (None: the engine's defaults); ignored by the other modes.

    Returns
    -------
    CriticalResult
    """
    check_mode(mode)
    if motion.pga <= 0.0:
        raise ValueError(f"motion {motion.name!r} has zero PGA")
    lower = uplift_intensity(motion, mode)
    analyze = make_analysis(body, motion, mode, omega_n=omega_n, zeta=zeta)
    acc = get_accuracy(accuracy)
    res = search_critical(analyze, limit_states, body.alpha, lower=lower, upper=upper,
                          accuracy=acc, rtol=acc.rtol_for(MODES[mode][0]))
    return replace(res, mode=mode, motion=motion.name, R=float(body.R),
                   tan_alpha=float(body.tan_alpha))


Task = tuple[float, float, GroundMotion, str]
"""(R [m], tan α [-], motion, mode): one point of a spectrum grid."""


def critical_intensity_batch(
    tasks: Iterable[Task],
    limit_states=None,
    *,
    accuracy: str | Accuracy | dict = "default",
    upper: float = DEFAULT_UPPER,
    omega_n: float | None = None,
    zeta: float | None = None,
) -> list[CriticalResult]:
    """:func:`critical_intensity` of a cylinder for each task, in order (one Dask task).

    Parameters
    ----------
    tasks : iterable of (R, tan_alpha, motion, mode)
    limit_states, accuracy, upper, omega_n, zeta
        As in :func:`critical_intensity`, shared by all tasks.

    Returns
    -------
    list of CriticalResult
    """
    acc = get_accuracy(accuracy)
    states = parse_limit_states(limit_states)
    out = []
    for i, task in enumerate(tasks):
        try:
            R, tan_alpha, motion, mode = task
        except (TypeError, ValueError):
            raise ValueError(f"task {i} must be (R, tan_alpha, motion, mode), got {task!r}") \
                from None
        out.append(critical_intensity(Cylinder(R, tan_alpha), motion, states, mode,
                                      accuracy=acc, upper=upper, omega_n=omega_n, zeta=zeta))
    return out
