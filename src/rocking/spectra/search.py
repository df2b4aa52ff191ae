"""The critical-intensity search on an abstract analysis function.

For a body, a ground-motion pair and a mode, the critical normalized intensity of a limit
state is the smallest I = PGA/(g tan α) in [I_uplift, upper] at which an analysis of the
motion scaled to intensity I exceeds it (paper §5.2).

The response is not monotonic in I: a body overturned at I₁ may survive I₂ > I₁. The search
therefore scans upward from uplift in steps and bisects inside the first bracket (last
intensity not exceeding, first exceeding]; it flags ``non_monotonic`` when it saw a limit state
exceeded at a lower intensity and not exceeded at a higher one, and reports the smallest
exceeding intensity it found.

One analysis decides every limit state whose tilt goal lies below the largest tilt it
reached, so a single search serves all limit states of (body, motion, mode): each analysis
stops (``stop_at``) at the largest goal still undecided at its intensity, the cheapest run
that still answers every open question. A limit state a body at rest can exceed (sliding,
:attr:`~rocking.spectra.limit_states.LimitState.at_rest`) is also looked for below uplift:
the search analyses the uplift intensity first and, if it is exceeded there, bisects
between 0 and it.

Each answer carries what the analyses up to it saw of the validity monitors, two separate
questions: ``lifts_off`` (some analysis at or below the answer left the support, N ≤ 0) and,
given the support's friction coefficient μ, ``slides`` (some analysis that did not overturn
needed μ_req > μ while in contact; NaN without μ): the fall of an overturning body needs
unbounded friction as N → 0⁺, so it is not counted as sliding
(:func:`~rocking.spectra.limit_states.slides_in_contact`).


This module only sees an analysis function ``analyze(intensity, stop_at, rtol) -> Outcome``
(:func:`search_critical`); :mod:`rocking.spectra.critical` binds it to the dynamics engine.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from rocking._validate import positive_finite
from rocking.dynamics.result import Status, slid_in_contact
from rocking.spectra.accuracy import Accuracy, get_accuracy
from rocking.spectra.limit_states import (
    MU_REQUIRED_MAX,
    NORMAL_FORCE_MIN,
    OVERTURNED,
    THETA_MAX,
    LimitState,
    check_peaks,
    classify,
    parse_limit_states,
    stop_for,
)

DEFAULT_UPPER = 20.0
"""Default highest normalized intensity searched, PGA/(g tan α) [-]."""

RETRY_RTOL_FACTOR = 0.1
"""A failed analysis is retried once with its rtol multiplied by this factor."""

MAX_ANALYSES = 2000
"""Safety net: no search of one spectrum point may run more analyses than this."""


@dataclass(frozen=True)
class Outcome:
    """What the search needs from one analysis.

    Attributes
    ----------
    theta_max : float
        Largest |θ| reached [rad].
    overturned : bool
        θ reached π/2.
    status : Status
    reason : str
        Why the analysis failed, if it did.
    other_peaks : mapping of str to float
        Further named peaks the analysis reports (names of
        :data:`~rocking.spectra.limit_states.QUANTITIES`), for the limit states that watch
        them.
    """

    theta_max: float
    overturned: bool
    status: Status
    reason: str = ""
    other_peaks: Mapping[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        check_peaks(self.other_peaks)

    @property
    def peaks(self) -> dict[str, float]:
        """Every peak by name, what limit states read
        (:meth:`~rocking.spectra.limit_states.LimitState.exceeded`)."""
        return {**self.other_peaks, THETA_MAX: self.theta_max, OVERTURNED: self.overturned}


AnalysisFn = Callable[[float, float | None, float], Outcome]
"""``analyze(intensity, stop_at, rtol) -> Outcome``: one analysis at normalized intensity
``intensity`` [-], ending once |θ| > ``stop_at`` [rad] (None: run to the end)."""


@dataclass(frozen=True)
class Evaluation:
    """One analysis run by the search (the retry of a failure is its own record).

    Attributes
    ----------
    intensity : float
        Normalized intensity I [-].
    stop_at : float or None
        Tilt at which the analysis was allowed to stop [rad].
    rtol : float
        ODE relative tolerance used [-].
    theta_max : float
        Largest tilt reached [rad].
    overturned : bool
    status : str
        :class:`~rocking.dynamics.result.Status` value.
    reason : str
    mu_required_max, normal_force_min : float
        The analysis's validity monitors [-] (NaN where it did not report them).
    """

    intensity: float
    stop_at: float | None
    rtol: float
    theta_max: float
    overturned: bool
    status: str
    reason: str = ""
    mu_required_max: float = float("nan")
    normal_force_min: float = float("nan")


@dataclass(frozen=True, eq=False)
class CriticalResult:
    """Critical intensities of several limit states for one (body, motion, mode).

    Arrays are indexed like :attr:`limit_states`: in the order asked for results of
    :func:`rocking.spectra.critical.critical_intensity`, by increasing tilt goal for
    :func:`search_critical`. ``repr`` is one short line per limit state.

    Attributes
    ----------
    limit_states : tuple of str
    intensity : ndarray of float
        Smallest exceeding normalized intensity found, PGA/(g tan α) [-]; NaN if not reached.
    bracket_lo, bracket_hi : ndarray of float
        Last intensity known not to exceed below the answer, and the answer itself [-].
    not_reached : ndarray of bool
        Not exceeded at any intensity up to :attr:`upper`.
    non_monotonic : ndarray of bool
        Seen exceeded at some intensity and not exceeded at a higher one.
    failed : ndarray of bool
        An analysis below the answer failed even after a retry with a tighter rtol, so an
        exceedance there may have been missed.
    unresolved : ndarray of bool
        Windows of exceedance narrower than the scan step may lie below this answer: below
        its first exceeding scan point the peak tilt came close to the goal and fell back,
        or spiked (:func:`window_warning`). A finer scan may answer lower. Never set for a
        limit state that does not watch the tilt (sliding). With a refining preset
        (``refine_budget`` > 0) the near misses whose neighbourhood was re-examined are
        cleared, and the flag stays only where the budget ran out first.
    budget_spent : ndarray of bool
        ``unresolved`` because the preset's refinement budget ran out before every near
        miss below the answer was re-examined (never set by a preset that does not refine).
    slides : ndarray of float
        1.0 where an analysis at or below the answer (up to :attr:`upper` where not
        reached) that did not overturn needed more friction than :attr:`mu` while in
        contact (``mu_required_max`` > μ), 0.0 where none did, NaN without μ: the answer
        then says nothing about sliding.
    lifts_off : ndarray of bool
        An analysis at or below the answer had a normal force N ≤ 0 (the body left its
        support).
    n_analyses : int
        Analyses run (retries included), shared by all limit states.
    lower, upper : float
        Search interval [-]: uplift intensity and the highest intensity searched.
    accuracy : Accuracy
    evaluations : tuple of Evaluation
        Every analysis, in the order run.
    mode, motion : str
    R, tan_alpha : float
        Body size [m] and slenderness [-] (NaN when the search ran on a bare function).
    mu : float or None
        Support friction coefficient the ``slides`` flags compare with [-].

    The flags see each analysis as far as it was monitored: an analysis ended at a tilt
    goal is monitored up to there; with μ or a limit state that needs the whole record
    (sliding), no analysis ends early once its tilt is decided.
    """

    limit_states: tuple[str, ...]
    intensity: np.ndarray
    bracket_lo: np.ndarray
    bracket_hi: np.ndarray
    not_reached: np.ndarray
    non_monotonic: np.ndarray
    failed: np.ndarray
    n_analyses: int
    lower: float
    upper: float
    accuracy: Accuracy
    evaluations: tuple[Evaluation, ...] = ()
    unresolved: np.ndarray | None = None
    mode: str = ""
    motion: str = ""
    R: float = float("nan")
    tan_alpha: float = float("nan")
    slides: np.ndarray | None = None
    lifts_off: np.ndarray | None = None
    mu: float | None = None
    budget_spent: np.ndarray | None = None

    def __post_init__(self) -> None:
        n = len(self.limit_states)
        if self.unresolved is None:  # a result built without the flag: nothing was seen
            object.__setattr__(self, "unresolved", np.zeros(n, dtype=bool))
        if self.budget_spent is None:  # built without refinement: no budget was spent
            object.__setattr__(self, "budget_spent", np.zeros(n, dtype=bool))
        if self.lifts_off is None:  # built without monitors: nothing was seen
            object.__setattr__(self, "lifts_off", np.zeros(n, dtype=bool))
        if self.slides is None:  # nothing to say about sliding
            object.__setattr__(self, "slides", np.full(n, np.nan))

    @property
    def pga_g(self) -> np.ndarray:
        """Critical PGA [g] = intensity · tan α (NaN where not reached or tan α unknown)."""
        return np.asarray(self.intensity, dtype=float) * self.tan_alpha

    def __repr__(self) -> str:
        head = (f"CriticalResult(mode={self.mode!r}, motion={self.motion!r}, R={self.R:g} m, "
                f"tan_alpha={self.tan_alpha:g}, accuracy={self.accuracy.name!r}, "
                f"{self.n_analyses} analyses)")
        rows = []
        for k, name in enumerate(self.limit_states):
            # slides where μ was given (NaN says nothing); lifts_off is left to the tables
            # (nearly every overturning answer carries it: a body falling leaves its support)
            flags = [f for f in ("not_reached", "non_monotonic", "failed", "unresolved",
                                 "budget_spent", "slides")
                     if getattr(self, f)[k] == 1]
            rows.append(f"  {name}: PGA/(g tan alpha) = {float(self.intensity[k]):.6g}, "
                        f"PGA = {float(self.pga_g[k]):.6g} g"
                        + (f" [{', '.join(flags)}]" if flags else ""))
        return "\n".join([head, *rows])

    def index(self, limit_state: str | LimitState) -> int:
        """Position of ``limit_state`` in the arrays (any accepted spelling)."""
        from rocking.spectra.limit_states import match_limit_state

        try:
            return self.limit_states.index(match_limit_state(limit_state,
                                                             self.limit_states))
        except KeyError as exc:
            raise ValueError(exc.args[0]) from None

    def __getitem__(self, limit_state: str | LimitState) -> dict:
        """Answer for one limit state as a dict (intensity, bracket and flags)."""
        return self.to_records()[self.index(limit_state)]

    def to_records(self) -> list[dict]:
        """One JSON-serialisable dict per limit state."""
        rows = []
        for k, name in enumerate(self.limit_states):
            rows.append(
                {
                    "mode": self.mode,
                    "motion": self.motion,
                    "R": self.R,
                    "tan_alpha": self.tan_alpha,
                    "limit_state": name,
                    "intensity": float(self.intensity[k]),
                    "pga_g": float(self.pga_g[k]),
                    "bracket_lo": float(self.bracket_lo[k]),
                    "bracket_hi": float(self.bracket_hi[k]),
                    "not_reached": bool(self.not_reached[k]),
                    "non_monotonic": bool(self.non_monotonic[k]),
                    "failed": bool(self.failed[k]),
                    "unresolved": bool(self.unresolved[k]),
                    "budget_spent": bool(self.budget_spent[k]),
                    "slides": _flag(self.slides[k]),
                    "lifts_off": bool(self.lifts_off[k]),
                    "mu": self.mu,
                    "n_analyses": int(self.n_analyses),
                    "lower": float(self.lower),
                    "upper": float(self.upper),
                    "accuracy": self.accuracy.name,
                }
            )
        return rows

    def to_frame(self) -> pd.DataFrame:
        """:meth:`to_records` as a table."""
        return pd.DataFrame(self.to_records())


def _flag(value: float) -> bool | None:
    """A flag that may say nothing (NaN) as True, False or None."""
    return None if math.isnan(value) else bool(value)


# --------------------------------------------------------------------------------------
# The search on an abstract analysis function
# --------------------------------------------------------------------------------------


@dataclass
class _Knowledge:
    """What the analyses run so far say about each limit state (rows: analyses)."""

    tau: np.ndarray
    lower: np.ndarray  # per limit state: the intensity below which it is known not exceeded
    intensities: list[float] = field(default_factory=list)
    known: list[np.ndarray] = field(default_factory=list)
    exceeded: list[np.ndarray] = field(default_factory=list)
    measures: list[np.ndarray] = field(default_factory=list)  # LimitState.measure per state
    # (μ_req max, N min, overturned 1.0/0.0) per analysis
    monitors: list[tuple[float, float, float]] = field(default_factory=list)
    failed_at: list[float] = field(default_factory=list)
    # brackets() of the analyses so far: asked two or three times per analysis, and each
    # call rereads every row, so it is kept until the next add()
    _brackets: tuple[np.ndarray, np.ndarray] | None = field(default=None, repr=False)

    def add(self, intensity: float, known: np.ndarray, exceeded: np.ndarray,
            measures: np.ndarray, monitors: tuple[float, float, float]) -> None:
        self.intensities.append(intensity)
        self.known.append(known)
        self.exceeded.append(exceeded)
        self.measures.append(measures)
        self.monitors.append(monitors)
        self._brackets = None

    def brackets(self) -> tuple[np.ndarray, np.ndarray]:
        """(lo, hi) per limit state: hi = smallest exceeding I seen (NaN if none), lo = the
        largest I below hi seen not exceeding (at least the uplift intensity)."""
        if self._brackets is None:
            self._brackets = self._compute_brackets()
        lo, hi = self._brackets
        return lo.copy(), hi.copy()  # callers may modify what they get

    def _compute_brackets(self) -> tuple[np.ndarray, np.ndarray]:
        n = self.tau.size
        hi = np.full(n, np.nan)
        lo = self.lower.copy()
        if not self.intensities:
            return lo, hi
        intens = np.asarray(self.intensities)[:, None]
        known = np.asarray(self.known)
        exc = np.asarray(self.exceeded)
        hit = known & exc
        hi = np.where(hit.any(axis=0), np.min(np.where(hit, intens, np.inf), axis=0), np.nan)
        below = known & ~exc & ((intens < hi) | np.isnan(hi))
        lo = np.maximum(self.lower, np.max(np.where(below, intens, -np.inf), axis=0))
        return lo, hi

    def monitor_flags(self, limit: np.ndarray, mu: float | None) -> tuple[np.ndarray,
                                                                          np.ndarray]:
        """(slides, lifts_off) per limit state over the analyses at intensities up to
        ``limit`` (per limit state): slides 1.0/0.0 (NaN without ``mu``; an overturned
        analysis never counts, :func:`~rocking.spectra.limit_states.slides_in_contact`),
        lifts_off bool (N ≤ 0)."""
        n = self.tau.size
        if not self.intensities:
            return (np.full(n, np.nan) if mu is None else np.zeros(n)), np.zeros(n, bool)
        up_to = np.asarray(self.intensities)[:, None] <= limit[None, :]
        mon = np.asarray(self.monitors, dtype=float)
        lifts_off = (up_to & (mon[:, 1:2] <= 0.0)).any(axis=0)
        if mu is None:
            return np.full(n, np.nan), lifts_off
        contact = slid_in_contact(mon[:, 0:1], mon[:, 2:3] != 0.0, mu)
        return (up_to & contact).any(axis=0).astype(float), lifts_off

    def non_monotonic(self) -> np.ndarray:
        """Exceeded at some I and known not exceeded at a larger I."""
        n = self.tau.size
        if not self.intensities:
            return np.zeros(n, dtype=bool)
        intens = np.asarray(self.intensities)[:, None]
        known = np.asarray(self.known)
        exc = np.asarray(self.exceeded)
        first_hit = np.min(np.where(known & exc, intens, np.inf), axis=0)
        last_safe = np.max(np.where(known & ~exc, intens, -np.inf), axis=0)
        return last_safe > first_hit

    def informative(self, intensity: float) -> np.ndarray:
        """Limit states whose answer an analysis at ``intensity`` could change."""
        lo, hi = self.brackets()
        open_above = np.isnan(hi) & (intensity > lo)
        inside = (lo < intensity) & (intensity < hi)
        return open_above | inside


UNRESOLVED_CLOSENESS = 0.5
"""Closeness θmax/goal of a peak of the scanned response at and above which
:func:`window_warning` fires when the next scan point falls back [-] (chosen on the
resolution benchmark, docs/performance.md)."""

UNRESOLVED_DROP = 3.0
"""Fall of the peak tilt between neighbouring scan points (θ_j/θ_{j+1}) at and above which
:func:`window_warning` fires whatever the closeness to the goal [-] (same benchmark)."""


def window_warning(closeness: np.ndarray, threshold: float = UNRESOLVED_CLOSENESS,
                   drop: float = UNRESOLVED_DROP) -> bool:
    """Whether windows of exceedance narrower than the scan step may hide among scan points.

    Near a goal the peak tilt jumps with the intensity and exceeds the goal in windows
    0.02–0.2 % wide; a scan sees their shoulders: the response comes close to the goal at
    one point and falls back at the next, or it spikes (θmax falls by a factor ``drop`` or
    more at the next point), the mark of the sensitive regime where such windows open. A
    response growing monotonically up to its first exceedance shows neither.

    Parameters
    ----------
    closeness : ndarray
        θmax/goal at the scan points below the first exceeding one, by increasing intensity
        [-] (the goal of overturning and of tilts above α is α: nothing beyond α is reached
        without passing it).
    threshold : float
        Closeness of a peak that counts whatever the fall [-].
    drop : float
        Fall θ_j/θ_{j+1} that counts whatever the closeness [-].

    Returns
    -------
    bool
        Some scan point but the last is followed by a lower one, and it was within
        ``threshold`` of the goal or the next is ``drop`` times lower.
    """
    return bool(window_points(closeness, threshold, drop).any())


def window_points(closeness: np.ndarray, threshold: float = UNRESOLVED_CLOSENESS,
                  drop: float = UNRESOLVED_DROP) -> np.ndarray:
    """Which scan points :func:`window_warning` fires on (bool per point, the last never):
    followed by a lower one, and within ``threshold`` of the goal or ``drop`` times above
    the next."""
    r = np.asarray(closeness, dtype=float)
    out = np.zeros(r.size, dtype=bool)
    if r.size < 2:
        return out
    here, after = r[:-1], r[1:]
    out[:-1] = (after < here) & ((here >= threshold) | (here >= drop * after))
    return out


@dataclass(frozen=True)
class NearMiss:
    """A scan point below an answer where windows of exceedance may hide.

    Attributes
    ----------
    state : int
        Index of the limit state.
    closeness : float
        Its measure over the scan goal there (θmax/τ) [-].
    lo, hi : float
        Its neighbourhood: the neighbouring scan points below and above [-].
    """

    state: int
    closeness: float
    lo: float
    hi: float


def _checked(out: Outcome) -> Outcome:
    """Turn a non-finite θ_max of a supposedly successful run into an explicit failure."""
    if out.status is not Status.FAILED and not math.isfinite(out.theta_max):
        return Outcome(out.theta_max, out.overturned, Status.FAILED,
                       f"non-finite theta_max {out.theta_max!r} with status {out.status.value}",
                       out.other_peaks)
    return out


def _monitors(out: Outcome) -> tuple[float, float]:
    """(μ_req max, N min) of an analysis [-], NaN where it did not report them."""
    return (float(out.other_peaks.get(MU_REQUIRED_MAX, math.nan)),
            float(out.other_peaks.get(NORMAL_FORCE_MIN, math.nan)))


class _Search:
    """State of one search: analyses run so far and the rules choosing the next one."""

    def __init__(self, analyze: AnalysisFn, states, alpha, lower, upper, acc: Accuracy,
                 rtol: float):
        self.analyze = analyze
        self.rtol = rtol
        self.states = states
        self.alpha = alpha
        self.tau = np.array([ls.threshold(alpha) for ls in states])
        self.goal = np.array([ls.scan_goal(alpha) for ls in states])  # closeness measure
        self.lower = lower
        self.upper = upper
        self.acc = acc
        # a limit state a body at rest can exceed is looked for from 0, the others from uplift
        at_rest = np.array([ls.at_rest for ls in states], dtype=bool) & math.isfinite(lower)
        self.know = _Knowledge(self.tau, np.where(at_rest, 0.0, lower))
        self.evaluations: list[Evaluation] = []
        self.stuck = np.zeros(len(states), dtype=bool)  # a failure blocks the bracket
        self.resolved = np.zeros(len(states), dtype=bool)  # bracket at float resolution
        self.scan_rows = 0  # the first scan_rows analyses known are the scan's
        self.pending: list[NearMiss] | None = None  # near misses refine() left uncleared

    def _call(self, intensity: float, stop_at: float | None, rtol: float) -> Outcome:
        if len(self.evaluations) >= MAX_ANALYSES:
            raise RuntimeError(f"critical-intensity search exceeded {MAX_ANALYSES} analyses")
        out = _checked(self.analyze(intensity, stop_at, rtol))
        self.evaluations.append(
            Evaluation(float(intensity), stop_at, float(rtol), float(out.theta_max),
                       bool(out.overturned), Status(out.status).value, out.reason,
                       *_monitors(out))
        )
        return out

    def run(self, intensity: float, below_answer: bool = False) -> np.ndarray:
        """Analyse at ``intensity`` if it can teach anything.

        ``below_answer``: also where it lies below a bracket (the refinement looks there for
        windows the scan stepped over), i.e. for every limit state not known exceeded at or
        below ``intensity``.

        Returns :meth:`LimitState.measure` of each limit state (the peak tilt [rad] for the
        tilt goals): 0.0 if no analysis was needed, NaN if it failed twice (nothing was
        learnt there).
        """
        if below_answer:
            _, hi = self.know.brackets()
            informative = np.isnan(hi) | (intensity < hi)
        else:
            informative = self.know.informative(intensity)
        if not informative.any():
            return np.zeros(len(self.states))
        # the highest goal still undecided decides where the analysis may stop
        stop_at = stop_for([ls for ls, i in zip(self.states, informative, strict=True) if i],
                           self.alpha)
        out = self._call(intensity, stop_at, self.rtol)
        if out.status is Status.FAILED:
            out = self._call(intensity, stop_at, self.rtol * RETRY_RTOL_FACTOR)
        if out.status is Status.FAILED:
            self.know.failed_at.append(intensity)
            return np.full(len(self.states), np.nan)
        known, exceeded = classify(out, self.states, self.alpha, stop_at,
                                   stopped=out.status is Status.STOPPED_AT_LIMIT)
        peaks = out.peaks
        measures = np.array([ls.measure(peaks) for ls in self.states], dtype=float)
        self.know.add(intensity, known, exceeded, measures,
                      (*_monitors(out), float(bool(out.overturned))))
        return measures

    def _next_scan_point(self, previous: float, j: int, measures: np.ndarray) -> float:
        """Scan point after ``previous`` (the j-th), given the measures of each limit state
        there (:meth:`run`: 0 at uplift, NaN after a failure)."""
        if self.acc.scan == "fixed":
            return self.acc.scan_point(self.lower, j)
        _, hi = self.know.brackets()
        # the state not yet exceeded closest to its scan goal (LimitState.scan_goal): for
        # tilt goals the mildest, whose goal is the smallest
        open_ = np.flatnonzero(np.isnan(hi))
        closeness = measures[open_] / self.goal[open_]
        k = int(open_[0] if np.isnan(closeness).any() else open_[np.argmax(closeness)])
        value, goal = float(measures[k]), float(self.goal[k])
        if self.acc.scan == "seek":
            return previous * (1.0 + self.acc.seek_step(value, goal))
        return previous * (1.0 + self.acc.adaptive_step(value, goal))

    def scan(self) -> None:
        """Step upward from uplift until every limit state is exceeded or ``upper`` is done
        (first the uplift intensity itself, for limit states a body at rest can exceed)."""
        j, intensity = 1, self.lower
        measures = np.zeros(len(self.states))
        if (self.know.lower < self.lower).any():
            measures = self.run(self.lower)
        while self.lower < self.upper:
            _, hi = self.know.brackets()
            if not np.isnan(hi).any():
                return
            intensity = self._next_scan_point(intensity, j, measures)
            last = intensity >= self.upper * (1.0 - 1e-9)
            measures = self.run(self.upper if last else intensity)
            if last:
                return
            j += 1

    def bisect(self) -> None:
        """Halve the open brackets, lowest limit state first, until all are narrow enough."""
        tol = self.acc.bisection_tol
        while True:
            lo, hi = self.know.brackets()
            open_ = ~np.isnan(hi) & (hi - lo > tol * hi) & ~self.stuck & ~self.resolved
            if not open_.any():
                return
            k = int(np.flatnonzero(open_)[0])
            mid = float(0.5 * (lo[k] + hi[k]))
            if not lo[k] < mid < hi[k]:  # float resolution reached: nothing left to halve
                self.resolved[k] = True
                continue
            if np.isnan(self.run(mid)).all():
                # Cannot learn anything here: stop refining every bracket around this point.
                self.stuck |= (lo < mid) & (mid < hi)
                continue
            if not self.know.known[-1][k]:
                # The analysis says nothing about this limit state (sliding where it
                # overturned, LimitState.decides): halving again would repeat it; the
                # bracket stays as wide as it is.
                self.resolved[k] = True

    def near_misses(self) -> list[NearMiss]:
        """The scan's near misses of every limit state that warns of windows: scan points
        below its first exceeding scan point (all of them where it was not reached) that
        :func:`window_warning` marks, each with the neighbourhood between its neighbouring
        scan points (uplift below the first)."""
        n = self.scan_rows
        out: list[NearMiss] = []
        if n == 0:
            return out
        intens = np.asarray(self.know.intensities[:n])
        known = np.asarray(self.know.known[:n])
        exc = np.asarray(self.know.exceeded[:n])
        measures = np.asarray(self.know.measures[:n])
        order = np.argsort(intens, kind="stable")
        for k in range(self.tau.size):
            if not self.states[k].warns_of_windows:
                continue
            hit = known[:, k] & exc[:, k]
            first = np.min(intens[hit]) if hit.any() else np.inf
            below = [i for i in order if intens[i] < first and known[i, k]]
            r = measures[below, k] / self.goal[k]
            for j in np.flatnonzero(window_points(r)):
                # below the first scan point: from uplift (never from 0, where the
                # relative steps of the re-examination would not move)
                lo = float(intens[below[j - 1]]) if j > 0 else float(self.lower)
                out.append(NearMiss(k, float(r[j]), lo, float(intens[below[j + 1]])))
        return out

    def refine(self) -> None:
        """Re-examine the near misses (:meth:`near_misses`), lowest first.

        Each near miss's neighbourhood is scanned upward from its lower neighbour with the
        step :meth:`~rocking.spectra.accuracy.Accuracy.refine_step_at` (fine where the peak
        tilt comes close to the goal) until its upper neighbour or the limit state's first
        exceedance, whichever is lower: a window found there becomes the new first
        exceedance (the bisection then narrows its bracket), and the neighbourhood is
        cleared. The search (one spectrum point, all its limit states: one analysis serves
        them all) may run ``refine_budget`` analyses so; a near miss left when it is spent
        stays uncleared (:attr:`pending`). Near misses at or above their limit state's
        answer no longer matter.
        """
        budget = self.acc.refine_budget
        # lowest first: the lowest window found makes every near miss above it moot, so the
        # budget goes where it can still move the answer (closest-first, tried on the
        # resolution traces, flagged more answers that were right: docs/performance.md)
        misses = sorted(self.near_misses(), key=lambda m: (m.lo, -m.closeness))
        spent = 0
        self.pending = []
        covered = -math.inf  # re-examined contiguously up to here (neighbourhoods overlap)
        for miss in misses:
            k = miss.state
            _, hi = self.know.brackets()
            top = min(miss.hi, hi[k]) if not np.isnan(hi[k]) else miss.hi
            if max(miss.lo, covered) >= top:
                continue
            if spent >= budget:
                self.pending.append(miss)
                continue
            intensity = max(miss.lo, covered)
            theta = self._measure_at(intensity, k)
            cleared = True
            while True:
                intensity *= 1.0 + self.acc.refine_step_at(theta, float(self.goal[k]))
                _, hi = self.know.brackets()
                top = min(miss.hi, hi[k]) if not np.isnan(hi[k]) else miss.hi
                if intensity >= top * (1.0 - 1e-12):
                    break
                if spent >= budget:
                    cleared = False
                    break
                before = len(self.evaluations)
                measures = self.run(intensity, below_answer=True)
                spent += len(self.evaluations) - before
                theta = float(measures[k])
                covered = intensity
            if cleared:
                covered = max(covered, top)
            else:
                self.pending.append(miss)

    def _measure_at(self, intensity: float, k: int) -> float:
        """Measure of limit state ``k`` at an analysed intensity (0 where none was run
        there, e.g. at uplift: at rest)."""
        for i in range(len(self.know.intensities) - 1, -1, -1):
            if self.know.intensities[i] == intensity:
                return float(self.know.measures[i][k])
        return 0.0

    def unresolved(self) -> tuple[np.ndarray, np.ndarray]:
        """(unresolved, budget_spent) per limit state: near misses below its answer left
        uncleared (without refinement: every near miss), and those of them left because
        the refinement budget ran out."""
        _, hi = self.know.brackets()
        limit = np.where(np.isnan(hi), np.inf, hi)
        pending = self.near_misses() if self.pending is None else self.pending
        out = np.zeros(self.tau.size, dtype=bool)
        for miss in pending:
            out[miss.state] |= miss.lo < limit[miss.state]
        spent = out & (self.acc.refine_budget > 0)
        return out, spent

    def result(self, mu: float | None = None) -> CriticalResult:
        lo, hi = self.know.brackets()
        not_reached = np.isnan(hi)
        failed_at = np.asarray(self.know.failed_at, dtype=float)
        failed = self.stuck.copy()
        limit = np.where(not_reached, np.inf, hi)
        if failed_at.size:
            failed |= (failed_at[:, None] < limit[None, :]).any(axis=0)
        slides, lifts_off = self.know.monitor_flags(limit, mu)
        unresolved, budget_spent = self.unresolved()
        return CriticalResult(
            limit_states=tuple(ls.name for ls in self.states),
            intensity=hi.copy(),
            bracket_lo=lo,
            bracket_hi=hi,
            not_reached=not_reached,
            non_monotonic=self.know.non_monotonic(),
            failed=failed,
            unresolved=unresolved,
            budget_spent=budget_spent,
            n_analyses=len(self.evaluations),
            lower=float(self.lower),
            upper=float(self.upper),
            accuracy=self.acc,
            evaluations=tuple(self.evaluations),
            slides=slides,
            lifts_off=lifts_off,
            mu=mu,
        )


def search_critical(
    analyze: AnalysisFn,
    limit_states,
    alpha: float,
    *,
    lower: float,
    upper: float = DEFAULT_UPPER,
    accuracy: str | Accuracy | dict = "default",
    rtol: float | None = None,
    mu: float | None = None,
) -> CriticalResult:
    """Smallest exceeding intensity of each limit state, for any analysis function.

    Parameters
    ----------
    analyze : callable
        ``analyze(intensity, stop_at, rtol) -> Outcome`` (see :data:`AnalysisFn`).
    limit_states : str or sequence
        Parsed by :func:`rocking.spectra.limit_states.parse_limit_states`.
    alpha : float
        Slenderness angle of the body [rad] (tilt goals are r·α).
    lower : float
        Highest intensity known to leave the body at rest (uplift) [-]; may be ``inf``.
    upper : float
        Highest intensity searched [-].
    accuracy : str, Accuracy or dict
        Preset name or tolerances (:func:`rocking.spectra.accuracy.get_accuracy`).
    rtol : float, optional
        ODE tolerance handed to ``analyze`` [-]; default ``accuracy.rtol``.
    mu : float, optional
        Support friction coefficient the ``slides`` flags compare the analyses'
        ``mu_required_max`` with [-] (None: the flags say nothing about sliding): a number
        checked where it entered (the body's ``mu``, the configuration or ``--mu``), not
        checked again here.

    Returns
    -------
    CriticalResult
        Without body/motion labels (the caller adds them).
    """
    states = parse_limit_states(limit_states)
    acc = get_accuracy(accuracy)
    alpha = positive_finite("alpha", alpha)
    upper = positive_finite("upper", upper)
    lower = positive_finite("lower", lower)
    rtol = acc.rtol if rtol is None else positive_finite("rtol", rtol)
    return run_search(analyze, states, alpha, lower, upper, acc, rtol, mu)


def run_search(analyze: AnalysisFn, states: list, alpha: float, lower: float, upper: float,
               acc: Accuracy, rtol: float, mu: float | None) -> CriticalResult:
    """:func:`search_critical` on arguments already checked where they entered: parsed limit
    states (:func:`~rocking.spectra.limit_states.parse_limit_states`, by severity), the
    resolved :class:`~rocking.spectra.accuracy.Accuracy` (a preset is resolved once, by the
    front end or the public function it called), numbers > 0 ([rad], [-], [-], [-])."""
    search = _Search(analyze, states, alpha, lower, upper, acc, rtol)
    search.scan()
    search.scan_rows = len(search.know.intensities)
    if acc.refine_budget > 0:
        search.refine()
    search.bisect()
    return search.result(mu)


checked = _checked  # the public name (tilt_map uses it)
