"""Critical intensities of a cylinder under a scaled ground motion: the search bound to
the dynamics engine, for one spectrum point or a batch of them (one Dask task).

PGA is always the pair's vector PGA max √(ax² + ay²), also for the 2D modes (§5.4), so the
scale factor of the motion is I·g·tan α / PGA.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import replace

import numpy as np

from rocking._progress import maybe as _progress
from rocking._validate import positive_finite
from rocking.constants import G
from rocking.dynamics.bodies import Block, Cylinder
from rocking.dynamics.contact import Contact
from rocking.dynamics.result import Status
from rocking.motions.motion import GroundMotion
from rocking.spectra.accuracy import DEFAULT_UPPER, Accuracy
from rocking.spectra.limit_states import (
    MU_REQUIRED_MAX,
    NORMAL_FORCE_MIN,
    parse_limit_states,
    whole_record,
)
from rocking.spectra.modes import MODE_3D, MODES, check_mode, excitation, is_damped
from rocking.spectra.quantity import Quantity
from rocking.spectra.search import (
    PER_LIMIT_STATE,
    AnalysisFn,
    CriticalResult,
    Outcome,
    cell_seed,
    run_search,
)

__all__ = ["MODES", "check_mode", "critical_intensity", "critical_intensity_batch",
           "make_analysis", "uplift_intensity"]


def uplift_intensity(motion: GroundMotion, mode: str) -> float:
    """Normalized intensity below which the body stays at rest [-].

    1 for the modes under both components (the vector acceleration reaches g tan α at the
    vector PGA); for a mode under one component (3D or 2D) PGA/max|a_component|, since only
    that component acts. ``inf`` when the component is identically zero.
    """
    check_mode(mode)
    component = MODES[mode][1]
    if component is None:
        return 1.0
    a = motion.ax if component == "x" else motion.ay
    peak = float(np.max(np.abs(a)))
    return math.inf if peak == 0.0 else motion.pga / peak


def make_analysis(
    body: Cylinder | Block,
    motion: GroundMotion,
    mode: str = MODE_3D,
    *,
    contact: Contact | None = None,
    rest_tilt: float | None = None,
    whole: bool = False,
    spin: float | None = None,
) -> AnalysisFn:
    """Bind :func:`rocking.dynamics.analysis.ground_response` to ``analyze(I, stop_at, rtol)``.

    The motion is scaled so that the pair's vector PGA equals I·g·tan α; the modes under one
    component are excited by it alone (``motion.component``) scaled by the same factor, the 3D
    ones with a spin at uplift (:func:`rocking.spectra.modes.excitation`; ``spin`` [rad/s]
    overrides the mode's);
    ``contact`` is the damped model's (:class:`~rocking.dynamics.contact.Contact`, checked
    where its numbers entered; None: the model's default), handed to the damped modes only;
    ``rest_tilt`` [rad] is the engine's (None: its default per model, 0: exact).
    ``whole`` runs the validity monitors over the whole record (no early end once the peak
    tilt is decided, ``stop_when_decided=False``), as a limit state watching a monitor
    (:func:`rocking.spectra.limit_states.whole_record`) or an exact ``slides`` flag needs;
    the outcome then carries ``mu_required_max`` and ``normal_force_min`` in its
    ``other_peaks``. Without ``whole`` the kernels run their variant without the monitors
    (the same θmax, status and steps to the bit, for less work: no other answer reads them)
    and ``other_peaks`` is empty.
    """
    from rocking.dynamics.analysis import ground_response  # the engine is imported only when needed

    excited, start = excitation(mode, motion, spin)
    model = MODES[mode].model
    unit_scale = G * body.tan_alpha / motion.pga
    kw = ({} if contact is None or not is_damped(mode) else
          {"omega_n": contact.omega_n, "zeta": contact.zeta})

    def analyze(intensity: float, stop_at: float | None, rtol: float) -> Outcome:
        r = ground_response(body, excited, model=model, scale=intensity * unit_scale,
                            stop_at=stop_at, rtol=rtol, history=False,
                            rest_tilt=rest_tilt, stop_when_decided=not whole,
                            monitors=whole, **start, **kw)
        peaks = ({MU_REQUIRED_MAX: float(r.mu_required_max),
                  NORMAL_FORCE_MIN: float(r.normal_force_min)} if whole else {})
        return Outcome(float(r.theta_max), bool(r.overturned), Status(r.status), r.reason,
                       peaks)

    return analyze


def critical_intensity(
    body: Cylinder | Block,
    motion: GroundMotion,
    limit_states=None,
    mode: str = MODE_3D,
    *,
    accuracy: str | Accuracy | dict = "default",
    quantity: str | Mapping | Quantity | None = None,
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
        E.g. ``["overturning", "tilt:1/3"]``; None: the seven defaults. The result lists
        them in this order (canonical names, duplicates dropped).
    mode : {"3d", "3d-damped", "3d-x", "3d-y", "2d-x", "2d-y"}
        Model and excitation (:data:`rocking.spectra.modes.MODES`: "3d-x"/"3d-y" the 3D
        model, "2d-x"/"2d-y" the 2D one under one component of the pair).
    accuracy : str, Accuracy or dict
        ``"fast"``, ``"default"``, ``"precise"`` or custom settings.
    quantity : str, mapping, Quantity or None
        What the answer is (:class:`rocking.spectra.quantity.Quantity`): None, I10 =
        inf{s : P(s) >= 0.1} with P over ±2 % in ln s; ``"first_exceedance"`` the smallest
        exceeding intensity on the scan grid.
    upper : float
        Highest normalized intensity searched [-].
    omega_n, zeta : float, optional
        Contact spring frequency [rad/s] and damping ratio [-] of the "3d-damped" model
        (None: the engine's defaults); ignored by the other modes.

    Returns
    -------
    CriticalResult
        Per limit state, in the order asked: ``intensity`` = the quantity's answer in
        PGA/(g tan α) [-] and ``pga_g`` = PGA [g], with ``i50``, ``first_exceedance`` and
        the search's flags;
        ``slides`` compares the analyses up to each answer with ``body.mu`` (NaN without
        it), ``lifts_off`` says whether one had N < 0 (False where nothing ran the
        monitors).

    With ``body.mu`` or a limit state watching a monitor (``"sliding:<mu>"``) every analysis
    runs the validity monitors to the end of the record (no early end once its peak tilt is
    decided); otherwise none runs them (:func:`make_analysis`).
    """
    return _critical_point(body, motion, parse_limit_states(limit_states, sort=False), mode,
                           Accuracy.of(accuracy), Quantity.from_value(quantity),
                           positive_finite("upper", upper), Contact.of(omega_n, zeta))


def _critical_point(body: Cylinder | Block, motion: GroundMotion, asked: list, mode: str,
                    acc: Accuracy, quantity: Quantity, upper: float,
                    contact: Contact) -> CriticalResult:
    """:func:`critical_intensity` on parsed limit states, a resolved accuracy and quantity,
    a checked ``upper`` and contact (the batch resolves and checks them once for every
    point). The grid offsets are drawn from the cell's identity
    (:func:`~rocking.spectra.search.cell_seed`: the motion's name, R, tan α, the mode)."""
    check_mode(mode)
    if motion.pga <= 0.0:
        raise ValueError(f"motion {motion.name!r} has zero PGA")
    lower = uplift_intensity(motion, mode)
    mu = body.mu
    analyze = make_analysis(body, motion, mode, contact=contact,
                            rest_tilt=acc.rest_tilt,
                            whole=whole_record(asked) or mu is not None)
    res = run_search(analyze, tuple(sorted(asked, key=lambda ls: ls.severity)), body.alpha, lower,
                     upper, acc, quantity, acc.rtol_for(MODES[mode][0]), mu,
                     cell_seed(motion.name, body.R, body.tan_alpha, mode))
    res = _in_order(res, [ls.name for ls in asked])
    return replace(res, mode=mode, motion=motion.name, R=float(body.R),
                   tan_alpha=float(body.tan_alpha))


def _in_order(res: CriticalResult, names: list[str]) -> CriticalResult:
    """``res`` with its per-limit-state arrays in the order of ``names``.

    The search orders limit states by tilt goal; a caller indexing ``res.intensity[0]``
    means the first limit state it asked for.
    """
    idx = [res.limit_states.index(n) for n in names]
    samples = res.samples
    if samples is not None:
        samples = replace(samples, exceeded=samples.exceeded[:, idx])
    return replace(res, limit_states=tuple(names), samples=samples,
                   **{k: np.asarray(getattr(res, k))[idx] for k in PER_LIMIT_STATE})


Task = tuple[float, float, GroundMotion, str]
"""(R [m], tan α [-], motion, mode): one point of a spectrum grid."""


def critical_intensity_batch(
    tasks: Iterable[Task],
    limit_states=None,
    *,
    accuracy: str | Accuracy | dict = "default",
    quantity: str | Mapping | Quantity | None = None,
    upper: float = DEFAULT_UPPER,
    omega_n: float | None = None,
    zeta: float | None = None,
    mu: float | None = None,
    progress=False,
) -> list[CriticalResult]:
    """:func:`critical_intensity` of a cylinder for each task, in order (one Dask task).

    Parameters
    ----------
    tasks : iterable of (R, tan_alpha, motion, mode)
    limit_states, accuracy, quantity, upper, omega_n, zeta
        As in :func:`critical_intensity`, shared by all tasks.
    mu : float, optional
        Support friction coefficient of every body [-] (``Cylinder(..., mu=)``: the
        ``slides`` flags).
    progress : bool or rocking._progress.Progress
        True: report points done / total, rate and ETA on stderr (a live bar on a
        terminal, a line every few seconds otherwise).

    Returns
    -------
    list of CriticalResult
    """
    acc = Accuracy.of(accuracy)
    q = Quantity.from_value(quantity)
    upper = positive_finite("upper", upper)
    contact = Contact.of(omega_n, zeta)
    states = parse_limit_states(limit_states, sort=False)
    tasks = list(tasks)
    for i, task in enumerate(tasks):
        if not isinstance(task, tuple | list) or len(task) != 4:
            raise ValueError(f"task {i} must be (R, tan_alpha, motion, mode), got {task!r}")
    bar = _progress(progress, len(tasks), "spectra")
    out = []
    for R, tan_alpha, motion, mode in tasks:
        out.append(_critical_point(Cylinder(R, tan_alpha, mu=mu), motion, states, mode, acc,
                                   q, upper, contact))
        if bar is not None:
            bar.update()
    if bar is not None and bar is not progress:
        bar.close()
    return out
