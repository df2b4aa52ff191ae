"""The critical-intensity search on an abstract analysis function.

For a body, a ground-motion pair and a mode, the critical normalized intensity of a limit
state is, by default, I_p = inf{s : P(s) >= p}: the lowest intensity around which a share p
of the intensities within ±w in ln s exceed it (:mod:`rocking.spectra.quantity`; I10 for
p = 0.1, w = 2 %). The smallest exceeding intensity itself does not converge: below the
first robust rise the response exceeds a goal in many windows a few hundredths of a per cent
wide, which a finer scan keeps finding.

The search runs in two kinds of analyses, all at intensities fixed by the cell's identity
(:func:`cell_seed`: motion, R, tan α, mode), so a rerun is bit-identical and two cells never
share a grid:

1. a *scan* upward from uplift on the grid I_j = I_uplift·(1 + h)^(j + u), h =
   :attr:`~rocking.spectra.accuracy.Accuracy.scan_step` and u ∈ [0, 1) drawn per cell, until
   every limit state has been exceeded at a grid point (its *first exceedance on the grid*);
2. a *local sample* around each first exceedance: one analysis at a random position in each
   stratum of width δ = :attr:`~rocking.spectra.accuracy.Accuracy.local_step` in ln I
   (jittered sampling: no alias with any periodicity of the response), from
   ``local_below`` under the candidate to ``local_above`` over it. P̂(s) is read off the local
   samples wherever its whole window lies in sampled strata; then
   - while P̂ at the lowest s the sample can judge is p/2 or more (:data:`EXTEND_SHARE`),
     the sample is extended downward by another ``local_below``: P may cross p below it,
     where only the scan looked;
   - else where P̂ reaches p, its first such s is I_p, once *confirmed*: every stratum its
     window touches gets a second analysis half a stratum from the first, and P̂ is read
     again (each stratum weighs its width, however many analyses it holds); a crossing made
     by the noise of ~2w/δ analyses moves up;
   - where P̂ stays below p, the candidate was an isolated window: the scan resumes above
     the sample for that limit state.

   With δ ≤ 0.6 % (the presets; w = 2 %, p = 0.1) a confirmed window holds more than 1/p
   analyses, so a window of exceedance narrower than half a stratum never makes an answer
   by itself. I50 is read off the same sample, extended up to :data:`I50_REACH` above I_p to
   find it. Exceeding a tilt goal implies exceeding every milder one, so the answers of the
   tilt axis are kept in order of severity.

What limits the accuracy is the scan: a stretch where P just reaches p over a few per cent
is found with a probability of about its exceeding width over h, and where the scan steps
over it the answer is the next one above (docs/performance.md, "The trade").

One analysis decides every limit state whose tilt goal lies below the largest tilt it
reached, so a single search serves all limit states of (body, motion, mode): each analysis
stops (``stop_at``) at the largest goal it is run for, and the local samples of limit states
whose candidates lie close together are shared. Below uplift the body is at rest and
exceeds no tilt goal: the local sample of a tilt goal near uplift counts the strata below
uplift as not exceeding without analysing them. A limit state a body at rest can exceed
(sliding, :attr:`~rocking.spectra.limit_states.LimitState.at_rest`) is also looked for
below uplift: the search analyses the uplift intensity first and, where it is exceeded
there, scans down the grid until it is not.

Each answer carries what the analyses up to its window (I_p·e^w, the analyses it is judged
on) saw of the validity monitors, two separate questions: ``lifts_off`` (some analysis there
left the support, N ≤ 0) and, given the support's friction coefficient μ, ``slides`` (some
analysis that did not overturn needed μ_req > μ while in contact; NaN without μ): the fall of
an overturning body needs unbounded friction as N → 0⁺, so it is not counted as sliding
(:func:`~rocking.spectra.limit_states.slides_in_contact`).

This module only sees an analysis function ``analyze(intensity, stop_at, rtol) -> Outcome``
(:func:`search_critical`); :mod:`rocking.spectra.critical` binds it to the dynamics engine.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from rocking._validate import positive_finite
from rocking.dynamics.result import Status, slid_in_contact
from rocking.spectra.accuracy import DEFAULT_UPPER, Accuracy
from rocking.spectra.limit_states import (
    MU_REQUIRED_MAX,
    NORMAL_FORCE_MIN,
    OVERTURNED,
    THETA_MAX,
    TILT_AXIS,
    LimitState,
    check_peaks,
    classify,
    parse_limit_states,
    stop_for,
)
from rocking.spectra.quantity import PLATEAU_SHARE, Quantity, local_exceedance

RETRY_RTOL_FACTOR = 0.1
"""A failed analysis is retried once with its rtol multiplied by this factor."""

MAX_ANALYSES = 2000
"""Safety net: no search of one spectrum point may run more analyses than this."""

I50_REACH = 0.06
"""How far above I_p (in ln I) the local sample is extended to find I50 [-]."""

EXTEND_SHARE = 0.5
"""A local sample is extended down while P̂ at the lowest s it can judge is at least this
share of p [-]: below a sample the scan alone has looked (one analysis per grid step), and
where P lies near p there it misses the exceedances often."""

MIN_AT_REST = 1e-3
"""Lowest intensity, over the uplift intensity, down to which the search follows a limit
state a body at rest can exceed [-]."""


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




@dataclass(frozen=True)
class Samples:
    """Every analysis a search learnt from, one row per intensity (a re-run at the same
    intensity, stopped at a higher goal, replaces the earlier one).

    Attributes
    ----------
    intensity : ndarray of float
        Normalized intensity of each analysis [-], increasing.
    exceeded : ndarray of float, shape (analyses, limit states)
        1.0 exceeded, 0.0 not exceeded, NaN where the analysis says nothing (it stopped at a
        lower goal, or failed).
    local : ndarray of bool
        The analysis belongs to a local sample (jittered strata), not to the scan grid.
    stratum : ndarray of int
        Stratum of each analysis: floor(ln(I/I_uplift)/δ), δ the local sample's step.
    """

    intensity: np.ndarray
    exceeded: np.ndarray
    local: np.ndarray
    stratum: np.ndarray | None = None

    def weights(self, known: np.ndarray) -> np.ndarray:
        """Weight of each analysis among those ``known``: 1 over the number of them in its
        stratum (each stratum weighs its width, however many analyses it holds)."""
        s = np.asarray(self.stratum)[known]
        _, inverse, counts = np.unique(s, return_inverse=True, return_counts=True)
        return 1.0 / counts[inverse]


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
        The quantity's answer, PGA/(g tan α) [-]: I_p under the default quantity, the first
        exceedance on the scan grid under ``first_exceedance``; NaN if not reached.
    i50 : ndarray of float
        I_0.5 = inf{s : P̂(s) >= 0.5} from the same local samples [-] (NaN where they do not
        reach it, and under ``first_exceedance``).
    first_exceedance : ndarray of float
        Smallest intensity of the scan grid (step :attr:`Accuracy.scan_step`) seen exceeding
        [-], whatever the quantity; NaN where none was.
    plateau : ndarray of bool
        P̂ rises near p without crossing it, more than one window below the answer (or
        anywhere when not reached): I_p is ill-conditioned there
        (:func:`rocking.spectra.quantity.exceedance_quantile`).
    not_reached : ndarray of bool
        Not exceeded (P̂ never reached p; under ``first_exceedance``: no grid point
        exceeded) up to :attr:`upper`.
    non_monotonic : ndarray of bool
        Seen exceeded at some intensity and not exceeded at a higher one.
    failed : ndarray of bool
        An analysis below the answer's window failed even after a retry with a tighter rtol,
        so an exceedance there may have been missed.
    slides : ndarray of float
        1.0 where an analysis up to the answer's window (I_p·e^w; the first exceedance
        itself under ``first_exceedance``; :attr:`upper` where not reached) that did not
        overturn needed more friction than :attr:`mu` while in contact
        (``mu_required_max`` > μ), 0.0 where none did, NaN without μ.
    lifts_off : ndarray of bool
        An analysis up to the answer's window had a normal force N ≤ 0 (the body left its
        support).
    n_analyses : int
        Analyses run (retries included), shared by all limit states.
    lower, upper : float
        Search interval [-]: uplift intensity and the highest intensity searched.
    accuracy : Accuracy
    quantity : Quantity
    evaluations : tuple of Evaluation
        Every analysis, in the order run.
    samples : Samples or None
        What the analyses decided, per intensity and limit state (:meth:`local_exceedance`).
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
    not_reached: np.ndarray
    non_monotonic: np.ndarray
    failed: np.ndarray
    n_analyses: int
    lower: float
    upper: float
    accuracy: Accuracy
    quantity: Quantity = field(default_factory=Quantity)
    i50: np.ndarray | None = None
    first_exceedance: np.ndarray | None = None
    plateau: np.ndarray | None = None
    evaluations: tuple[Evaluation, ...] = ()
    samples: Samples | None = None
    mode: str = ""
    motion: str = ""
    R: float = float("nan")
    tan_alpha: float = float("nan")
    slides: np.ndarray | None = None
    lifts_off: np.ndarray | None = None
    mu: float | None = None

    def __post_init__(self) -> None:
        n = len(self.limit_states)
        defaults = {"i50": np.full(n, np.nan), "first_exceedance": np.full(n, np.nan),
                    "plateau": np.zeros(n, dtype=bool), "lifts_off": np.zeros(n, dtype=bool),
                    "slides": np.full(n, np.nan)}  # a result built without them saw nothing
        for name, value in defaults.items():
            if getattr(self, name) is None:
                object.__setattr__(self, name, value)

    @property
    def pga_g(self) -> np.ndarray:
        """Critical PGA [g] = intensity · tan α (NaN where not reached or tan α unknown)."""
        return np.asarray(self.intensity, dtype=float) * self.tan_alpha

    @property
    def answer(self) -> str:
        """What :attr:`intensity` is, in words (the quantity, with the scan grid's step
        for the first exceedance)."""
        return self.quantity.describe(self.accuracy.scan_step)

    def __repr__(self) -> str:
        head = (f"CriticalResult(mode={self.mode!r}, motion={self.motion!r}, R={self.R:g} m, "
                f"tan_alpha={self.tan_alpha:g}, accuracy={self.accuracy.name!r}, "
                f"quantity={self.answer!r}, {self.n_analyses} analyses)")
        rows = []
        label = self.quantity.label if self.quantity.is_quantile else "first exceedance"
        for k, name in enumerate(self.limit_states):
            # slides where μ was given (NaN says nothing); lifts_off is left to the tables
            # (nearly every overturning answer carries it: a body falling leaves its support)
            flags = [f for f in ("not_reached", "plateau", "non_monotonic", "failed", "slides")
                     if getattr(self, f)[k] == 1 and not (f == "non_monotonic"
                                                          and self.quantity.is_quantile)]
            rows.append(f"  {name}: {label} = {float(self.intensity[k]):.6g} "
                        f"PGA/(g tan alpha), PGA = {float(self.pga_g[k]):.6g} g"
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
        """Answer for one limit state as a dict (intensity, quantity and flags)."""
        return self.to_records()[self.index(limit_state)]

    def local_exceedance(self, limit_state: str | LimitState, s, w: float | None = None
                         ) -> np.ndarray:
        """P̂(s) of one limit state from the search's local samples
        (:func:`rocking.spectra.quantity.local_exceedance`; ``w`` default the quantity's):
        trustworthy only around the answer, where the search sampled densely."""
        if self.samples is None:
            raise ValueError("this result carries no samples")
        k = self.index(limit_state)
        e = self.samples.exceeded[:, k]
        keep = ~np.isnan(e) & (self.samples.intensity > 0)
        return local_exceedance(self.samples.intensity[keep], e[keep] == 1.0, s,
                                self.quantity.w if w is None else w,
                                self.samples.weights(keep))

    def to_records(self) -> list[dict]:
        """One JSON-serialisable dict per limit state."""
        rows = []
        q = self.quantity
        for k, name in enumerate(self.limit_states):
            rows.append(
                {
                    "mode": self.mode,
                    "motion": self.motion,
                    "R": self.R,
                    "tan_alpha": self.tan_alpha,
                    "limit_state": name,
                    **q.columns(),
                    "intensity": float(self.intensity[k]),
                    "pga_g": float(self.pga_g[k]),
                    "i50": float(self.i50[k]),
                    "first_exceedance": float(self.first_exceedance[k]),
                    "scan_step": float(self.accuracy.scan_step),
                    "plateau": bool(self.plateau[k]),
                    "not_reached": bool(self.not_reached[k]),
                    "non_monotonic": bool(self.non_monotonic[k]),
                    "failed": bool(self.failed[k]),
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


PER_LIMIT_STATE = ("intensity", "i50", "first_exceedance", "plateau", "not_reached",
                   "non_monotonic", "failed", "slides", "lifts_off")
"""The per-limit-state arrays of a :class:`CriticalResult`."""


def _flag(value: float) -> bool | None:
    """A flag that may say nothing (NaN) as True, False or None."""
    return None if math.isnan(value) else bool(value)


def cell_seed(motion: str, R: float, tan_alpha: float, mode: str) -> int:
    """Seed of a cell's random grid offsets, from its identity alone (never from the process
    or the order of work): the same cell draws the same intensities in every run, two cells
    different ones. R and tan α enter as their shortest float repr."""
    key = f"{motion}|{float(R)!r}|{float(tan_alpha)!r}|{mode}".encode()
    return int.from_bytes(hashlib.sha256(key).digest()[:8], "little")


def scan_offset(seed: int) -> float:
    """Offset u ∈ [0, 1) of the scan grid I_j = I_uplift·(1 + h)^(j + u) of a cell."""
    return float(np.random.default_rng([seed, 0]).random())


def stratum_offset(seed: int, m: int, level: int = 0) -> float:
    """Position u ∈ [0, 1) of a local sample inside stratum ``m`` of a cell (the stratum
    [m δ, (m + 1) δ) in ln(I/I_uplift)): one draw per stratum, whatever the order in which
    strata are sampled; the second sample of a stratum (``level`` 1, where the answer is
    confirmed) lies half a stratum from the first, so the two are a jittered sample of
    step δ/2."""
    u = float(np.random.default_rng([seed, 1, m + (1 << 40)]).random())
    return u if level == 0 else (u + 0.5) % 1.0


# --------------------------------------------------------------------------------------
# The search on an abstract analysis function
# --------------------------------------------------------------------------------------

_SCAN, _LOCAL, _DONE = 0, 1, 2  # what a limit state waits for


@dataclass
class _Rows:
    """What the analyses run so far say about each limit state, one row per intensity."""

    n_states: int
    intensity: list[float] = field(default_factory=list)
    known: list[np.ndarray] = field(default_factory=list)
    exceeded: list[np.ndarray] = field(default_factory=list)
    local: list[bool] = field(default_factory=list)
    grid: list[bool] = field(default_factory=list)
    stop_at: list[float | None] = field(default_factory=list)
    # (μ_req max, N min, overturned 1.0/0.0) per analysis
    monitors: list[tuple[float, float, float]] = field(default_factory=list)
    failed_at: list[float] = field(default_factory=list)
    where: dict[float, int] = field(default_factory=dict)

    def add(self, intensity: float, known: np.ndarray, exceeded: np.ndarray,
            monitors: tuple[float, float, float], stop_at: float | None, *,
            local: bool, grid: bool) -> None:
        i = self.where.get(intensity)
        if i is None:
            self.where[intensity] = len(self.intensity)
            self.intensity.append(intensity)
            self.known.append(known)
            self.exceeded.append(exceeded)
            self.local.append(local)
            self.grid.append(grid)
            self.stop_at.append(stop_at)
            self.monitors.append(monitors)
            return
        # a re-run that ran further: it knows at least what the earlier one knew
        self.known[i], self.exceeded[i] = known, exceeded
        self.local[i] |= local
        self.grid[i] |= grid
        self.stop_at[i] = stop_at
        self.monitors[i] = monitors

    def row(self, intensity: float) -> int | None:
        return self.where.get(intensity)

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(intensity, known, exceeded) as arrays (rows in the order run)."""
        n = self.n_states
        if not self.intensity:
            return np.zeros(0), np.zeros((0, n), bool), np.zeros((0, n), bool)
        return (np.asarray(self.intensity), np.asarray(self.known, dtype=bool),
                np.asarray(self.exceeded, dtype=bool))

    def monitor_flags(self, limit: np.ndarray, mu: float | None) -> tuple[np.ndarray,
                                                                          np.ndarray]:
        """(slides, lifts_off) per limit state over the analyses at intensities up to
        ``limit`` (per limit state): slides 1.0/0.0 (NaN without ``mu``; an overturned
        analysis never counts, :func:`~rocking.spectra.limit_states.slides_in_contact`),
        lifts_off bool (N ≤ 0)."""
        n = self.n_states
        if not self.intensity:
            return (np.full(n, np.nan) if mu is None else np.zeros(n)), np.zeros(n, bool)
        up_to = np.asarray(self.intensity)[:, None] <= limit[None, :]
        mon = np.asarray(self.monitors, dtype=float)
        lifts_off = (up_to & (mon[:, 1:2] <= 0.0)).any(axis=0)
        if mu is None:
            return np.full(n, np.nan), lifts_off
        contact = slid_in_contact(mon[:, 0:1], mon[:, 2:3] != 0.0, mu)
        return (up_to & contact).any(axis=0).astype(float), lifts_off

    def non_monotonic(self) -> np.ndarray:
        """Exceeded at some I and known not exceeded at a larger I."""
        intens, known, exc = self.arrays()
        if not intens.size:
            return np.zeros(self.n_states, dtype=bool)
        intens = intens[:, None]
        first_hit = np.min(np.where(known & exc, intens, np.inf), axis=0)
        last_safe = np.max(np.where(known & ~exc, intens, -np.inf), axis=0)
        return last_safe > first_hit

    def samples(self, lower: float, delta: float) -> Samples:
        intens, known, exc = self.arrays()
        order = np.argsort(intens, kind="stable")
        e = np.where(known, exc.astype(float), np.nan)
        with np.errstate(divide="ignore", invalid="ignore"):
            stratum = np.floor(np.log(intens / lower) / delta)
        stratum = np.where(np.isfinite(stratum), stratum, -(1 << 40)).astype(np.int64)
        return Samples(intens[order], e[order], np.asarray(self.local, dtype=bool)[order]
                       if self.local else np.zeros(0, dtype=bool), stratum[order])


def _runs(strata: set[int]) -> list[tuple[int, int]]:
    """Maximal runs [a, b] (inclusive) of consecutive integers in ``strata``."""
    out: list[tuple[int, int]] = []
    for m in sorted(strata):
        if out and m == out[-1][1] + 1:
            out[-1] = (out[-1][0], m)
        else:
            out.append((m, m))
    return out


def _nested(values: np.ndarray, states) -> np.ndarray:
    """Answers of the tilt axis made non-decreasing in severity: exceeding a tilt goal (or
    overturning) implies exceeding every milder one, so P of the severer goal never exceeds
    P of the milder at any s, and neither do its quantiles; estimates from different local
    samples may cross by their noise, and the severer is lifted to the milder's (NaN, not
    reached, stays NaN and lifts the rest)."""
    out = np.asarray(values, dtype=float).copy()
    floor = -math.inf
    for k, ls in enumerate(states):  # by severity (parse_limit_states order)
        if ls.severity[0] != TILT_AXIS:
            continue
        if math.isnan(out[k]) or math.isnan(floor):
            floor = math.nan if math.isnan(out[k]) else floor
            out[k] = math.nan if math.isnan(floor) else out[k]
            continue
        out[k] = floor = max(out[k], floor)
    return out


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
    """State of one search: analyses run so far and the rules choosing the next ones."""

    def __init__(self, analyze: AnalysisFn, states, alpha: float, lower: float, upper: float,
                 acc: Accuracy, quantity: Quantity, rtol: float, seed: int):
        self.analyze = analyze
        self.rtol = rtol
        self.states = list(states)
        self.alpha = alpha
        self.lower = lower
        self.upper = upper
        self.acc = acc
        self.q = quantity
        n = len(self.states)
        self.rows = _Rows(n)
        self.evaluations: list[Evaluation] = []
        self.seed = seed
        self.u0 = scan_offset(seed)
        self.h = math.log1p(acc.scan_step)  # grid step in ln I
        self.delta = acc.local_step  # stratum width in ln I
        self.at_rest = np.array([ls.at_rest for ls in self.states], dtype=bool)
        self.state = np.full(n, _SCAN)
        self.scan_from = np.full(n, -math.inf)  # the scan looks above this intensity
        self.requested: list[set[tuple[int, int]]] = [set() for _ in range(n)]  # (m, level)
        self.covered: list[set[int]] = [set() for _ in range(n)]  # strata sampled and known
        self.tried: list[set[int]] = [set() for _ in range(n)]  # strata sampled (or failed)
        self.doubled: list[set[int]] = [set() for _ in range(n)]  # … with a second sample
        self.tried2: list[set[tuple[int, int]]] = [set() for _ in range(n)]
        self.stratum_row: dict[tuple[int, int], float] = {}  # (stratum, level) → intensity
        self.answer = np.full(n, np.nan)
        self.i50 = np.full(n, np.nan)
        self.plateau = np.zeros(n, dtype=bool)
        self.best_below = np.zeros(n)  # largest P̂ seen where it did not reach p
        self.cand_top = np.full(n, -math.inf)  # top of the last candidate's local sample

    # ------------------------------------------------------------------ analyses
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

    def run(self, intensity: float, wanted: np.ndarray, *, local: bool = False,
            grid: bool = False) -> bool:
        """Analyse at ``intensity`` for the limit states ``wanted`` (bool per state), unless
        an analysis there already decided them all. False where it failed twice."""
        i = self.rows.row(intensity)
        if i is not None:
            if not (wanted & ~self.rows.known[i]).any():
                if local:
                    self.rows.local[i] = True
                return True
            wanted = wanted | self.rows.known[i]  # the re-run must know what the first knew
        stop_at = stop_for([ls for ls, w in zip(self.states, wanted, strict=True) if w],
                           self.alpha)
        out = self._call(intensity, stop_at, self.rtol)
        if out.status is Status.FAILED:
            out = self._call(intensity, stop_at, self.rtol * RETRY_RTOL_FACTOR)
        if out.status is Status.FAILED:
            self.rows.failed_at.append(intensity)
            return False
        known, exceeded = classify(out, self.states, self.alpha, stop_at,
                                   stopped=out.status is Status.STOPPED_AT_LIMIT)
        self.rows.add(intensity, known, exceeded,
                      (*_monitors(out), float(bool(out.overturned))), stop_at,
                      local=local, grid=grid)
        return True

    def _status(self, intensity: float, k: int) -> tuple[bool, bool]:
        """(known, exceeded) of limit state k at an analysed intensity."""
        i = self.rows.row(intensity)
        if i is None:
            return False, False
        return bool(self.rows.known[i][k]), bool(self.rows.exceeded[i][k])

    # ---------------------------------------------------------------------- scan
    def grid_point(self, j: int) -> float:
        """The j-th point of the cell's scan grid (j may be negative: below uplift)."""
        return self.lower * math.exp((j + self.u0) * self.h)

    def _first_index_above(self, intensity: float) -> int:
        if not intensity > self.lower:
            return 0
        j = max(0, math.floor(math.log(intensity / self.lower) / self.h - self.u0))
        while self.grid_point(j) <= intensity:
            j += 1
        return j

    def at_rest_scan(self) -> None:
        """Limit states a body at rest can exceed: analyse uplift; where exceeded there,
        scan down the grid until they are not (below uplift their measure grows with the
        intensity), and take the lowest exceeding point as their candidate."""
        wanted = self.at_rest & (self.state == _SCAN)
        if not wanted.any() or not self.run(self.lower, wanted, grid=True):
            return
        hit = np.array([self._status(self.lower, k) == (True, True) for k in
                        range(len(self.states))]) & wanted
        lowest = np.where(hit, self.lower, np.nan)
        j = -1
        while hit.any():
            intensity = self.grid_point(j)
            if intensity <= MIN_AT_REST * self.lower or not self.run(intensity, hit, grid=True):
                break
            now = np.array([self._status(intensity, k) == (True, True)
                            for k in range(len(self.states))]) & hit
            lowest[now] = intensity
            hit = now
            j -= 1
        for k in np.flatnonzero(~np.isnan(lowest)):
            self._candidate(int(k), float(lowest[k]))

    def scan(self) -> None:
        """Step up the grid until no limit state waits for a candidate, or ``upper``."""
        while (self.state == _SCAN).any():
            waiting = self.state == _SCAN
            j = min(self._first_index_above(max(self.scan_from[k], self.lower * (1 - 1e-12)))
                    for k in np.flatnonzero(waiting))
            while (self.state == _SCAN).any():
                intensity = self.grid_point(j)
                last = intensity >= self.upper * (1.0 - 1e-9)
                if last:
                    intensity = self.upper
                wanted = (self.state == _SCAN) & (intensity > self.scan_from)
                if wanted.any() and self.run(intensity, wanted, grid=True):
                    for k in np.flatnonzero(wanted):
                        if self._status(intensity, int(k)) == (True, True):
                            self._candidate(int(k), intensity)
                if last:
                    for k in np.flatnonzero(self.state == _SCAN):
                        self.state[k] = _DONE  # not reached
                    return
                j += 1

    def _candidate(self, k: int, intensity: float) -> None:
        """Limit state k was seen exceeded at ``intensity`` on the grid: under the first
        exceedance it is answered; under I_p a local sample around it is requested."""
        if not self.q.is_quantile:
            self.answer[k] = intensity
            self.state[k] = _DONE
            return
        x = math.log(intensity / self.lower)
        lo = math.floor((x - self.acc.local_below) / self.delta)
        hi = math.ceil((x + self.acc.local_above) / self.delta) - 1
        self.requested[k].update((m, 0) for m in range(lo, hi + 1))
        self.cand_top[k] = intensity * math.exp(self.acc.local_above)
        self.state[k] = _LOCAL

    # --------------------------------------------------------------------- local
    def stratum_point(self, m: int, level: int = 0) -> float:
        """A local sample's intensity in stratum m (drawn once per cell and stratum)."""
        return self.lower * math.exp((m + stratum_offset(self.seed, m, level)) * self.delta)

    def _virtual(self, k: int) -> bool:
        """Strata below uplift count as not exceeded, unanalysed (a body at rest exceeds
        no tilt goal)."""
        return not self.at_rest[k]

    def sample(self) -> None:
        """Analyse every requested (stratum, level), each once for all limit states asking
        for it (stopped at the largest of their goals)."""
        todo: dict[tuple[int, int], np.ndarray] = {}
        n = len(self.states)
        for k in range(n):
            for m, level in self.requested[k]:
                if level == 0:
                    self.tried[k].add(m)
                if m < 0 and self._virtual(k):
                    (self.covered if level == 0 else self.doubled)[k].add(m)
                    continue
                todo.setdefault((m, level), np.zeros(n, dtype=bool))[k] = True
            self.requested[k] = set()
        for m, level in sorted(todo):
            intensity = self.stratum_point(m, level)
            if intensity > self.upper:
                continue
            wanted = todo[(m, level)]
            if self.run(intensity, wanted, local=True):
                self.stratum_row[(m, level)] = intensity
                for k in np.flatnonzero(wanted):
                    if self._status(intensity, int(k))[0]:
                        (self.covered if level == 0 else self.doubled)[int(k)].add(m)

    def _estimate(self, k: int) -> tuple[np.ndarray, np.ndarray,
                                         list[tuple[float, int, bool]]]:
        """Where P̂ of limit state k can be judged: (ln s points, P̂ there) over every run of
        covered strata, at the s whose windows lie wholly inside it, and per run (its lowest
        judged ln s, its lowest stratum, whether it can extend down)."""
        w, d = self.q.w, self.delta
        ln_lower = math.log(self.lower)
        xs, es, ms = [], [], []
        for level, strata in enumerate((self.covered[k], self.doubled[k])):
            for m in strata:
                if m < 0 and self._virtual(k):
                    xs.append(ln_lower + (m + 0.25 + 0.5 * level) * d)
                    es.append(False)
                    ms.append(m)
                    continue
                if level and m not in self.covered[k]:
                    continue  # a second sample counts where the first one does
                known, exc = self._status(self.stratum_row[(m, level)], k)
                if known:
                    xs.append(math.log(self.stratum_row[(m, level)]))
                    es.append(exc)
                    ms.append(m)
        if not xs:
            return np.zeros(0), np.zeros(0), []
        runs = _runs(self.covered[k])
        lx = np.asarray(xs)
        e = np.asarray(es, dtype=bool)
        # each stratum weighs its width, however many analyses it holds
        _, inverse, counts = np.unique(np.asarray(ms), return_inverse=True,
                                       return_counts=True)
        weight = 1.0 / counts[inverse]
        cuts = np.concatenate([lx - w, lx + w + 2e-12])
        points, edges = [], []
        for a, b in runs:
            lo = ln_lower + a * d + w
            hi = ln_lower + (b + 1) * d - w
            if hi < lo:
                continue
            inside = cuts[(cuts > lo) & (cuts <= hi)]
            points.append(np.concatenate([[lo], inside]))
            # a run starting at the bottom of the virtual strata (a tilt goal) or far below
            # uplift (a goal a body at rest can exceed) cannot extend further down
            bottom = a <= self._virtual_floor() if self._virtual(k) \
                else a * d < math.log(MIN_AT_REST)
            edges.append((lo, a, not bottom))
        if not points:
            return np.zeros(0), np.zeros(0), []
        ls = np.sort(np.concatenate(points))
        P = local_exceedance(np.exp(lx), e, np.exp(ls), w, weight)
        return ls, P, edges

    def _virtual_floor(self) -> int:
        """Lowest virtual stratum a tilt goal's sample needs: one window below uplift."""
        return -math.ceil(2.0 * self.q.w / self.delta) - 1

    def assess(self, k: int) -> None:
        """After a local sample: answer limit state k, extend its sample down, or send it
        back to the scan (its candidate was an isolated window)."""
        p, w = self.q.p, self.q.w
        ls, P, edges = self._estimate(k)
        if not math.isnan(self.answer[k]):
            self._assess_i50(k, ls, P)
            return
        reach = np.flatnonzero(P >= p - 1e-12)
        s = float(ls[reach[0]]) if reach.size else math.inf
        for lo, a, can_extend in edges:
            # P̂ at the lowest s this run can judge reaches p (I_p may lie lower) or comes
            # within EXTEND_SHARE of it (P may cross p just below, where only the scan
            # looked): the sample is extended down
            if can_extend and lo <= s + 1e-12 and \
                    float(P[np.searchsorted(ls, lo)]) >= EXTEND_SHARE * p - 1e-12:
                nb = max(1, math.ceil(self.acc.local_below / self.delta))
                while a - 1 in self.tried[k] - self.covered[k]:  # failed strata below
                    a -= 1
                new = set(range(a - nb, a)) - self.tried[k]
                if new:  # else the run below, or failures, stop it: judged as it is
                    self.requested[k] |= {(m, 0) for m in new}
                    return
        if reach.size and self.acc.confirm:
            # the crossing is confirmed on a sample twice as dense: a second analysis in
            # every stratum its window touches (P̂ of ~2w/δ analyses crosses p by chance
            # where P lies near p)
            ln_lower = math.log(self.lower)
            lo = math.floor((s - w - ln_lower) / self.delta)
            hi = math.floor((s + w - ln_lower) / self.delta)
            missing = {m for m in range(lo, hi + 1) if m in self.covered[k]
                       and (m, 1) not in self.tried2[k]}
            if missing:
                self.tried2[k] |= {(m, 1) for m in missing}
                self.requested[k] |= {(m, 1) for m in missing}
                return
        if reach.size:
            self.answer[k] = math.exp(s)
            below = P[ls < s - 2.0 * w]
            self.plateau[k] = bool(below.size and below.max() >= PLATEAU_SHARE * p)
            self._assess_i50(k, ls, P)
            return
        if P.size:
            self.best_below[k] = max(self.best_below[k], float(np.nanmax(P)))
        # an isolated window: the scan resumes above the sampled strata
        top = self.cand_top[k]
        if self.covered[k]:
            top = max(top, self.lower * math.exp((max(self.covered[k]) + 1) * self.delta))
        self.scan_from[k] = max(self.scan_from[k], top)
        self.state[k] = _SCAN

    def _assess_i50(self, k: int, ls: np.ndarray, P: np.ndarray) -> None:
        """I_p of limit state k is answered: I50 from the same sample, which is extended up
        (by ``local_above``) until P̂ reaches 0.5 or it spans :data:`I50_REACH` above I_p;
        I50 stays NaN where P̂ stays below 0.5 that far (P hovers between p and 0.5)."""
        half = np.flatnonzero((P >= 0.5 - 1e-12) & (ls >= math.log(self.answer[k]) - 1e-12))
        if half.size:
            self.i50[k] = math.exp(float(ls[half[0]]))
            self.state[k] = _DONE
            return
        top = max(m for m in self.covered[k]) if self.covered[k] else None
        cap = min(math.log(self.answer[k] / self.lower) + I50_REACH + self.q.w,
                  math.log(self.upper / self.lower))
        if top is None or (top + 1) * self.delta >= cap:
            self.state[k] = _DONE
            return
        nb = max(1, math.ceil(self.acc.local_above / self.delta))
        new = {(m, 0) for m in range(top + 1, top + 1 + nb) if m not in self.tried[k]}
        if not new:
            self.state[k] = _DONE
            return
        self.requested[k] |= new
        self.state[k] = _LOCAL

    def search(self) -> None:
        """Scan, sample, assess, until every limit state is answered or out of range."""
        if not self.lower < self.upper:
            self.state[:] = _DONE
            return
        self.at_rest_scan()
        while True:
            self.scan()
            local = np.flatnonzero(self.state == _LOCAL)
            if not local.size:
                return
            self.sample()
            for k in local:
                self.assess(int(k))

    # -------------------------------------------------------------------- result
    def result(self, mu: float | None = None) -> CriticalResult:
        n = len(self.states)
        intens, known, exc = self.rows.arrays()
        on_grid = np.asarray(self.rows.grid, dtype=bool)
        hit = known & exc & on_grid[:, None] if intens.size else np.zeros((0, n), bool)
        first = np.where(hit.any(axis=0),
                         np.min(np.where(hit, intens[:, None], np.inf), axis=0), np.nan) \
            if intens.size else np.full(n, np.nan)
        answer = _nested(self.answer, self.states)
        i50 = _nested(self.i50, self.states)
        not_reached = np.isnan(answer)
        plateau = self.plateau | (not_reached & (self.best_below >= PLATEAU_SHARE * self.q.p))
        # the answer's window (I_p is judged on the analyses up to I_p·e^w): the flags see the
        # analyses up to its top, and a failure there may hide exceedances
        reach = np.where(not_reached, np.inf,
                         answer * (math.exp(self.q.w) if self.q.is_quantile else 1.0))
        failed_at = np.asarray(self.rows.failed_at, dtype=float)
        failed = np.zeros(n, dtype=bool)
        if failed_at.size:
            failed |= (failed_at[:, None] < reach[None, :]).any(axis=0)
        slides, lifts_off = self.rows.monitor_flags(reach, mu)
        return CriticalResult(
            limit_states=tuple(ls.name for ls in self.states),
            intensity=answer,
            i50=i50,
            first_exceedance=first,
            plateau=plateau,
            not_reached=not_reached,
            non_monotonic=self.rows.non_monotonic(),
            failed=failed,
            n_analyses=len(self.evaluations),
            lower=float(self.lower),
            upper=float(self.upper),
            accuracy=self.acc,
            quantity=self.q,
            evaluations=tuple(self.evaluations),
            samples=self.rows.samples(self.lower, self.delta),
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
    quantity: str | Mapping | Quantity | None = None,
    rtol: float | None = None,
    mu: float | None = None,
    seed: int = 0,
) -> CriticalResult:
    """Critical intensity of each limit state, for any analysis function.

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
        Preset name or settings (:meth:`rocking.spectra.accuracy.Accuracy.of`).
    quantity : str, mapping, Quantity or None
        What the answer is (:class:`rocking.spectra.quantity.Quantity`; None: I10).
    rtol : float, optional
        ODE tolerance handed to ``analyze`` [-]; default ``accuracy.rtol``.
    mu : float, optional
        Support friction coefficient the ``slides`` flags compare the analyses'
        ``mu_required_max`` with [-] (None: the flags say nothing about sliding): a number
        checked where it entered (the body's ``mu``, the configuration or ``--mu``), not
        checked again here.
    seed : int
        Seed of the random grid offsets (:func:`cell_seed` of the cell's identity).

    Returns
    -------
    CriticalResult
        Without body/motion labels (the caller adds them).
    """
    states = parse_limit_states(limit_states)
    acc = Accuracy.of(accuracy)
    q = Quantity.from_value(quantity)
    alpha = positive_finite("alpha", alpha)
    upper = positive_finite("upper", upper)
    if lower != math.inf:  # inf: a component identically zero never lifts the body
        lower = positive_finite("lower", lower)
    rtol = acc.rtol if rtol is None else positive_finite("rtol", rtol)
    return run_search(analyze, states, alpha, lower, upper, acc, q, rtol, mu, int(seed))


def run_search(analyze: AnalysisFn, states: list, alpha: float, lower: float, upper: float,
               acc: Accuracy, quantity: Quantity, rtol: float, mu: float | None,
               seed: int) -> CriticalResult:
    """:func:`search_critical` on arguments already checked where they entered: parsed limit
    states (:func:`~rocking.spectra.limit_states.parse_limit_states`, by severity), the
    resolved :class:`~rocking.spectra.accuracy.Accuracy` and
    :class:`~rocking.spectra.quantity.Quantity` (resolved once, by the front end or the
    public function it called), numbers > 0 ([rad], [-], [-], [-])."""
    acc.check_window(quantity.w)
    search = _Search(analyze, states, alpha, lower, upper, acc, quantity, rtol, seed)
    search.search()
    return search.result(mu)


checked = _checked  # the public name (tilt_map uses it)
