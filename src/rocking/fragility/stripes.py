"""Multiple-stripe fragility: the share of motions exceeding a limit state at fixed intensities.

The critical-intensity search (:mod:`rocking.spectra.search`) answers "the smallest intensity
that exceeds a limit state", which in rocking depends on narrow windows of exceedance and on
where the scan falls. Multiple-stripe analysis (Jalayer 2003; Baker 2015, "Efficient
analytical fragility function fitting using dynamic structural analysis", Earthquake Spectra
31:579–599) asks a question whose answer converges instead: at each of a set of intensities
I_j (the stripes), analyse every motion of the ensemble once, count the n_j of the N_j motions
that exceed the limit state, and fit the lognormal fragility

    P(exceed | I) = Φ( ln(I/θ) / β )

by binomial maximum likelihood,

    ln L(θ, β) = Σ_j [ n_j ln p_j + (N_j − n_j) ln(1 − p_j) ],   p_j = Φ(ln(I_j/θ)/β).

θ is the intensity at which exceedance is as likely as not; a motion that overturns at 1.9
and survives 2.0 counts as exceeding at the first stripe and not at the second, exactly as
observed. One analysis per (stripe, motion), run to the largest tilt goal asked (or to its
end when overturning is asked), decides every limit state at once.

Where the likelihood has no finite maximum the fit says so with NaN and a reason rather than
a number: no motion exceeding at any stripe, every motion exceeding at every stripe, or
fractions that step from all-below to all-above between two stripes (the data separate: β → 0
and θ is anywhere between them). A median above the highest stripe or below the lowest one is
an extrapolation: it is returned, flagged.

Intensities are normalized, PGA/(g tan α) with the pair's vector PGA (as everywhere in
:mod:`rocking.spectra`), or, with ``measure`` another intensity measure of
:mod:`rocking.motions.measures` (``"sa:1.0"``, ``"pgv"``), that measure over g tan α: each
motion is then scaled so that *its* measure equals the stripe's value (the usual practice of
multiple-stripe analysis in Sa(T)), and analysed at the PGA this scale gives it.

Where the data separate, :func:`refine_stripes` adds stripes between the highest stripe with
no motion exceeding and the lowest with all exceeding (bisection in ln I) until the fit is
defined or a budget is spent; :func:`bootstrap_stripes` resamples the motions with
replacement and refits, for the spread of θ over other sets of motions.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np
from scipy import optimize, special, stats

from rocking._progress import maybe as _progress
from rocking._validate import positive_finite_array
from rocking.dynamics.bodies import Block, Cylinder
from rocking.dynamics.contact import Contact
from rocking.dynamics.result import Status
from rocking.fragility.lognormal import bootstrap_indices
from rocking.grids import grid_values
from rocking.motions.measures import DEFAULT_COMPONENT, VECTOR_PEAK
from rocking.motions.motion import GroundMotion
from rocking.spectra.accuracy import DEFAULT_UPPER, Accuracy
from rocking.spectra.critical import make_analysis, uplift_intensity
from rocking.spectra.limit_states import (
    LimitState,
    classify,
    parse_limit_states,
    stop_for,
    whole_record,
)
from rocking.spectra.modes import MODE_3D, MODES, check_mode

__all__ = ["BOOTSTRAP_SEED", "DEFAULT_BOOTSTRAP", "DEFAULT_REFINE", "DEFAULT_STRIPES",
           "EXCEEDANCE_COLUMNS", "JITTER", "MEASURE_COLUMNS", "exceedance_table", "jittered",
           "STRIPE_RANGE", "StripeFit", "StripeFragility", "bootstrap_interval",
           "bootstrap_stripes", "bracket",
           "fit_stripes", "measure_ratio", "refine_stripes",
           "refinement_point", "stripe_analyzer", "stripe_fragility", "stripe_intensities"]

DEFAULT_STRIPES = 40
"""Default number of stripes, geometric over :data:`STRIPE_RANGE` (docs/performance.md,
"Multiple-stripe fragility": the El Centro ensemble's median overturning intensity at R = 6 m
moves by less than its own standard error beyond about this many)."""

STRIPE_RANGE = (1.0, DEFAULT_UPPER)
"""Default first and last stripe, PGA/(g tan α) [-]: from uplift (2D; the body is at rest
there in 3D) to the search's default bound (:data:`rocking.spectra.accuracy.DEFAULT_UPPER`)."""

RETRY_RTOL_FACTOR = 0.1
"""A failed analysis is retried once with its rtol multiplied by this factor (as the search)."""

BETA_MAX = 5.0
"""Largest dispersion accepted from a fit [-]: beyond it the fractions show no trend with the
intensity (the likelihood grows without bound as β → ∞)."""

CONFIDENCE = 0.95
"""Level of the Wald intervals of θ and β."""

DEFAULT_REFINE = 8
"""Most stripes :func:`refine_stripes` adds to one (mode, limit state, R) by default: each
halves the gap in ln I where the fractions step from none to all, so 8 narrow a step of one
default stripe (ratio 20^(1/40) ≈ 1.08) to 1.0003, far below any spread seen."""

DEFAULT_BOOTSTRAP = 1000
"""Resamples of the motions in :func:`bootstrap_stripes` by default."""

BOOTSTRAP_SEED = 2017
"""Seed of the resampling (the same resamples for every row of the same motions)."""

MEASURE_COLUMNS = ("median_im", "median_p05", "median_p95", "bracket_lo", "bracket_hi")
"""Table columns in the unit of the stripes' measure (g for pga and sa:T, m/s for pgv)."""

BOOTSTRAP_LEVEL = 0.90
"""Level of the bootstrap interval of θ (``median_p05``, ``median_p95``)."""

JITTER = 0.02
"""Default half-width w of each analysis's jitter in ln s (:func:`jittered`): issue 45's
window of the local exceedance probability P(s)."""


def jittered(intensities, w: float, *, motion: str, mode: str, R: float,
             tan_alpha: float) -> np.ndarray:
    """The intensities one motion is analysed at: each stripe s times exp(u), u uniform in
    [−w, w].

    u is drawn from the analysis's identity (motion, mode, R, tan α and the stripe itself:
    never the process, the order of work or the other stripes), so a rerun, a resumed store
    and a refined stripe analyse the same intensity, bit for bit. Averaged over u, a motion
    exceeds at stripe s with probability P_m(s), the share of intensities within ±w of s
    in ln s that exceed: its local exceedance probability (issue 45). The share of motions
    exceeding at s is therefore an unbiased estimate of F(s) = mean over motions of
    P_m(s), the ensemble's exceedance probability, which converges as motions are added;
    the binomial fit of those shares is its lognormal.

    ``w`` = 0 returns the stripes themselves.
    """
    import hashlib

    x = np.asarray(intensities, dtype=float)
    if not 0.0 <= w < 0.5:
        raise ValueError(f"jitter must be in [0, 0.5), got {w!r}")
    if w == 0.0:
        return x
    out = np.empty_like(x)
    for i, s in enumerate(x):
        key = f"stripe|{motion}|{mode}|{float(R)!r}|{float(tan_alpha)!r}|{float(s)!r}"
        seed = int.from_bytes(hashlib.sha256(key.encode()).digest()[:8], "little")
        out[i] = s * math.exp(np.random.default_rng(seed).uniform(-w, w))
    return out


def stripe_intensities(n: int = DEFAULT_STRIPES, lower: float = STRIPE_RANGE[0],
                       upper: float = STRIPE_RANGE[1]) -> np.ndarray:
    """``n`` stripes geometric from ``lower`` to ``upper``, both included, measure/(g tan α)
    [-]: :func:`rocking.grids.grid_values`, the list a configuration's
    ``stripes.intensity: {start: lower, stop: upper, num: n, spacing: log}`` gives, to the
    bit."""
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 1:
        raise ValueError(f"number of stripes must be an integer >= 1, got {n!r}")
    lower, upper = float(lower), float(upper)
    if not (math.isfinite(lower) and math.isfinite(upper) and 0.0 < lower < upper):
        raise ValueError(f"stripes need 0 < lower < upper (finite), got lower={lower!r}, "
                         f"upper={upper!r}")
    return np.array(grid_values(lower, upper, int(n), "log"))


def _check_intensities(intensities) -> np.ndarray:
    if intensities is None:
        return stripe_intensities()
    if isinstance(intensities, int | np.integer) and not isinstance(intensities, bool):
        return stripe_intensities(int(intensities))
    x = np.asarray(intensities, dtype=float)
    if x.ndim != 1 or x.size == 0:
        raise ValueError(f"intensities must be a non-empty 1-D sequence, got shape {x.shape}")
    positive_finite_array("intensities", x)
    if np.any(np.diff(x) <= 0.0):
        i = int(np.flatnonzero(np.diff(x) <= 0.0)[0]) + 1
        raise ValueError(f"intensities must be strictly increasing, got {x[i]!r} after "
                         f"{x[i - 1]!r} at index {i}")
    return x


def measure_ratio(motion: GroundMotion, measure: str = "pga",
                  component: str = DEFAULT_COMPONENT) -> float:
    """PGA/(g tan α) of ``motion`` scaled so that its ``measure`` in ``component`` over
    (g tan α) is 1 [-].

    A stripe at the normalized measure x is the motion scaled by x g tan α / IM, i.e. analysed
    at PGA/(g tan α) = x · this ratio (every measure is linear in the scale). 1 for ``"pga"``
    in the vector peak (the spectra's own intensity).
    """
    from rocking.motions.measures import Measure

    im = Measure.of(measure)
    if im == Measure("pga") and component == VECTOR_PEAK:
        return 1.0
    value = im.of_motion(motion, component)
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"motion {motion.name!r} has {im} = {value!r}: it cannot be scaled "
                         "to a stripe of that measure")
    # the stripe x is the measure x·(g tan α) in its unit: the scale x·per_normalized/value
    return motion.pga_g * im.per_normalized(1.0) / value


# --------------------------------------------------------------------------------------
# The binomial maximum-likelihood fit
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class StripeFit:
    """Lognormal fragility fitted to stripe counts by binomial maximum likelihood.

    Attributes
    ----------
    median : float
        θ [PGA/(g tan α)]; NaN where the likelihood has no finite maximum.
    beta : float
        Dispersion β, standard deviation of ln I [-]; NaN likewise.
    median_ci, beta_ci : tuple of float
        Wald 95 % intervals from the expected (Fisher) information: θ·exp(±z·se(ln θ)) and
        β·exp(±z·se(ln β)); NaN where the fit is undefined. They treat the stripes as
        independent binomial samples, while the stripes reuse the same motions: they say
        how well the stripes pin θ for these motions, and are 3–4× narrower than the
        spread of θ over other sets of motions (docs/performance.md, "Multiple-stripe
        fragility").
    log_likelihood : float
        Maximized ln L (NaN if undefined).
    status : str
        ``"ok"``, ``"extrapolated"`` (θ outside the stripes: returned, flagged), or why no
        fit exists: ``"none-exceeded"``, ``"all-exceeded"``, ``"separated"``, ``"no-trend"``,
        ``"no-analyses"``.
    reason : str
        One sentence with the numbers behind a status other than "ok".
    """

    median: float
    beta: float
    median_ci: tuple[float, float]
    beta_ci: tuple[float, float]
    log_likelihood: float
    status: str = "ok"
    reason: str = ""

    def probability(self, intensity) -> np.ndarray:
        """P(exceed | I) = Φ(ln(I/θ)/β) at ``intensity`` [PGA/(g tan α)], > 0."""
        im = positive_finite_array("intensity", intensity)
        return stats.norm.cdf(np.log(im / self.median) / self.beta)


_NAN2 = (math.nan, math.nan)


def _undefined(status: str, reason: str) -> StripeFit:
    return StripeFit(math.nan, math.nan, _NAN2, _NAN2, math.nan, status, reason)


def binomial_neg_log_likelihood(params, log_x: np.ndarray, k: np.ndarray,
                                n: np.ndarray) -> tuple[float, np.ndarray]:
    """−ln L of (ln θ, ln β) for ``k`` of ``n`` exceeding at intensities exp(``log_x``)
    (binomial coefficients left out: they do not depend on the parameters), and its
    gradient."""
    log_median, log_beta = params
    beta = math.exp(log_beta)
    z = (log_x - log_median) / beta
    # log Φ(z) and log Φ(−z) stay finite where Φ would round to 0 or 1
    log_p, log_q = special.log_ndtr(z), special.log_ndtr(-z)
    log_phi = -0.5 * z * z - 0.5 * math.log(2.0 * math.pi)
    # ∂ ln L/∂z per stripe: k φ/Φ − (n − k) φ/(1 − Φ)
    dz = k * np.exp(log_phi - log_p) - (n - k) * np.exp(log_phi - log_q)
    grad = np.array([np.sum(dz) / beta, np.sum(dz * z)])  # −∂lnL/∂lnθ, −∂lnL/∂lnβ
    return float(-np.sum(k * log_p + (n - k) * log_q)), grad


def _check_counts(intensities, n_exceeding, n_total):
    x = _check_intensities(intensities)
    k = np.asarray(n_exceeding, dtype=float).ravel()
    n = np.asarray(n_total, dtype=float).ravel()
    for name, a in (("n_exceeding", k), ("n_total", n)):
        if a.shape != x.shape:
            raise ValueError(f"{name} must have one count per stripe ({x.size}), got {a.size}")
        if np.any(~np.isfinite(a) | (a < 0) | (a != np.round(a))):
            i = int(np.flatnonzero(~np.isfinite(a) | (a < 0) | (a != np.round(a)))[0])
            raise ValueError(f"{name} must be integers >= 0, got {a[i]!r} at stripe {i}")
    if np.any(k > n):
        i = int(np.flatnonzero(k > n)[0])
        raise ValueError(f"n_exceeding {int(k[i])} exceeds n_total {int(n[i])} at stripe {i}")
    return x, k, n


def _degenerate(x: np.ndarray, k: np.ndarray, n: np.ndarray) -> StripeFit | None:
    """The reason the likelihood has no finite maximum, or None if it has one.

    The probit likelihood has a finite maximum exactly when no intensity c separates the
    exceedances (all at I ≥ c) from the non-exceedances (all at I ≤ c).
    """
    used = n > 0
    if not used.any():
        return _undefined("no-analyses", "no stripe has an analysed motion")
    x, k, n = x[used], k[used], n[used]
    if not k.any():
        return _undefined("none-exceeded", f"no motion exceeds at any of {x.size} stripes up "
                          f"to {x[-1]:.6g}: the median lies above them")
    if np.all(k == n):
        return _undefined("all-exceeded", f"every motion exceeds at every one of {x.size} "
                          f"stripes from {x[0]:.6g}: the median lies below them")
    below = x[k < n].max()  # highest stripe with a motion not exceeding
    above = x[k > 0].min()  # lowest stripe with a motion exceeding
    if below < above:
        return _undefined("separated", f"the fractions step from none to all exceeding "
                          f"between {below:.6g} and {above:.6g}: the median lies there and "
                          "no spread is seen (beta -> 0); add stripes or motions there")
    if below == above:
        return _undefined("separated", f"only the stripe at {below:.6g} has some but not all "
                          "motions exceeding, none below it and all above: the median lies "
                          "near it and no spread is seen (beta -> 0); add stripes or motions "
                          "there")
    return None


def _start(x: np.ndarray, k: np.ndarray, n: np.ndarray) -> np.ndarray:
    """(ln θ, ln β) from a least-squares probit line through the mixed stripes."""
    f = np.clip(k / np.where(n > 0, n, 1), 0.5 / np.maximum(n, 1), 1 - 0.5 / np.maximum(n, 1))
    use = n > 0
    z = stats.norm.ppf(f[use])
    lx = np.log(x[use])
    if np.ptp(lx) > 0 and lx.size >= 2:
        slope, icpt = np.polyfit(lx, z, 1)
        if slope > 0:
            return np.array([-icpt / slope, math.log(min(1.0 / slope, BETA_MAX))])
    return np.array([float(np.mean(lx)), math.log(0.5)])


def _fisher_covariance(log_x, n, log_median, beta) -> np.ndarray:
    """Covariance of (ln θ, ln β) from the expected information of the binomial model."""
    z = (log_x - log_median) / beta
    p = np.clip(stats.norm.cdf(z), 1e-300, 1 - 1e-16)
    dens = stats.norm.pdf(z)
    # ∂p/∂lnθ = −φ(z)/β, ∂p/∂lnβ = −φ(z)·z
    g = np.stack([-dens / beta, -dens * z])
    w = n / (p * (1 - p))
    info = (g * w) @ g.T
    try:
        return np.linalg.inv(info)
    except np.linalg.LinAlgError:
        return np.full((2, 2), np.nan)


def fit_stripes(intensities, n_exceeding, n_total) -> StripeFit:
    """Binomial maximum-likelihood lognormal fragility of stripe counts.

    Parameters
    ----------
    intensities : array_like
        Stripe intensities, strictly increasing, > 0 [PGA/(g tan α)].
    n_exceeding : array_like of int
        Motions exceeding the limit state at each stripe.
    n_total : array_like of int
        Motions analysed at each stripe (a stripe with 0 is left out).

    Returns
    -------
    StripeFit
        NaN with a status and reason where the likelihood has no finite maximum.
    """
    x, k, n = _check_counts(intensities, n_exceeding, n_total)
    bad = _degenerate(x, k, n)
    if bad is not None:
        return bad
    used = n > 0
    x, k, n = x[used], k[used], n[used]
    log_x = np.log(x)
    args = (log_x, k, n)
    res = optimize.minimize(binomial_neg_log_likelihood, _start(x, k, n), args=args,
                            jac=True, method="BFGS", options={"gtol": 1e-9})
    if not res.success:
        # BFGS may stop on precision loss near the optimum; polish from a simplex search
        nm = optimize.minimize(lambda p: binomial_neg_log_likelihood(p, *args)[0], res.x,
                               method="Nelder-Mead",
                               options={"xatol": 1e-10, "fatol": 1e-12, "maxiter": 4000})
        res = nm if nm.fun <= res.fun else res
    log_median, log_beta = (float(v) for v in res.x)
    beta = math.exp(log_beta)
    if not (math.isfinite(log_median) and math.isfinite(beta)) or beta > BETA_MAX:
        return _undefined("no-trend", f"the fractions show no trend with intensity between "
                          f"{x[0]:.6g} and {x[-1]:.6g} (beta -> infinity)")
    median = math.exp(log_median)
    cov = _fisher_covariance(log_x, n, log_median, beta)
    zq = stats.norm.ppf(0.5 + CONFIDENCE / 2)
    se_m, se_b = (math.sqrt(v) if v >= 0 else math.nan for v in np.diag(cov))
    status, reason = "ok", ""
    if not x[0] <= median <= x[-1]:
        status = "extrapolated"
        reason = (f"median {median:.6g} lies outside the stripes {x[0]:.6g}–{x[-1]:.6g}: "
                  "extend them")
    return StripeFit(median, beta,
                     (median * math.exp(-zq * se_m), median * math.exp(zq * se_m)),
                     (beta * math.exp(-zq * se_b), beta * math.exp(zq * se_b)),
                     -float(res.fun), status, reason)


def bracket(intensities, n_exceeding, n_total) -> tuple[float, float]:
    """(lo, hi): the highest stripe with no motion exceeding below every exceeding one, and
    the lowest with every motion exceeding above every non-exceeding one [as intensities].

    Where the data separate, the median lies between them. 0 if no stripe below qualifies
    (every motion exceeds from the first stripe), inf if none above does (no motion exceeds).
    """
    x, k, n = _check_counts(intensities, n_exceeding, n_total)
    used = n > 0
    x, k, n = x[used], k[used], n[used]
    if x.size == 0:
        return math.nan, math.nan
    above = x[k > 0].min() if k.any() else math.inf  # lowest stripe with a motion exceeding
    below = x[k < n].max() if (k < n).any() else 0.0  # highest with a motion not exceeding
    none = x[(k == 0) & (x < above)]
    every = x[(k == n) & (x > below)]
    return (float(none.max()) if none.size else 0.0,
            float(every.min()) if every.size else math.inf)


def refinement_point(intensities, n_exceeding, n_total) -> float | None:
    """The next stripe of a separated fit: the middle in ln I of the gap that holds the step.

    Between the highest stripe with none and the lowest with all exceeding lies at most one
    stripe c with some exceeding (else the fit would be defined): the new stripe halves the
    gap without it, or the larger of the two gaps beside it (the lower on a tie). Where c is
    the first stripe (no stripe below it with none exceeding), the new one lies as far below
    c in ln I as the first stripe with all exceeding lies above it, and likewise above a
    last stripe c: the step is then looked for beyond the stripes. None where there is no
    stripe with some exceeding and no gap (every motion steps between the same two stripes
    is bisected; none or all exceeding everywhere is not) or the gap is at the resolution of
    floating point.
    """
    x, k, n = _check_counts(intensities, n_exceeding, n_total)
    lo, hi = bracket(x, k, n)
    inner = x[(n > 0) & (x > lo) & (x < hi)]
    if 0.0 < lo < hi < math.inf:
        if inner.size == 0:
            new = math.sqrt(lo * hi)
        else:
            c = float(inner[0])
            new = (math.sqrt(lo * c) if math.log(c / lo) >= math.log(hi / c)
                   else math.sqrt(c * hi))
    elif lo == 0.0 and hi < math.inf and inner.size:  # mixed at the first stripe: below it
        c = float(inner[0])
        new, lo = c * c / hi, 0.0
    elif hi == math.inf and lo > 0.0 and inner.size:  # mixed at the last stripe: above it
        c = float(inner[-1])
        new, hi = c * c / lo, math.inf
    else:
        return None
    return None if new in x or not lo < new < hi else float(new)


# --------------------------------------------------------------------------------------
# The analyses
# --------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class StripeFragility:
    """Multiple-stripe fragility of one body in one mode under an ensemble of motions.

    Attributes
    ----------
    intensities : ndarray, shape (stripes,)
        The stripes, PGA/(g tan α) [-].
    limit_states : tuple of str
        Canonical names, in the order asked.
    motions : tuple of str
    exceeded : ndarray of bool, shape (stripes, motions, limit states)
        Whether the analysis of each motion at each stripe exceeded each limit state (False
        where the analysis failed).
    failed : ndarray of bool, shape (stripes, motions)
        The analysis failed even after a retry with a tighter rtol; left out of the counts.
    n_exceeding : ndarray of int, shape (stripes, limit states)
    n_motions : ndarray of int, shape (stripes,)
        Motions analysed successfully at each stripe.
    median, beta : Mapping[str, float]
        θ [PGA/(g tan α)] and β [-] per limit state (NaN where undefined: see ``status``).
    median_ci, beta_ci : Mapping[str, tuple]
        Wald 95 % intervals.
    status, reason : Mapping[str, str]
        Per limit state, as :class:`StripeFit`.
    mode, accuracy : str
    R, tan_alpha : float
        Body size [m] and slenderness [-].
    n_analyses : int
        Analyses run (retries included).
    measure : str
        The intensity measure of the stripes (``"pga"``, ``"sa:1.0"``, …): ``intensities``
        and the medians are it over g tan α.
    n_refined : int
        Stripes :func:`refine_stripes` added (0 for the stripes as asked).
    component : str
        The horizontal component of ``measure`` (:data:`rocking.motions.measures.COMPONENTS`).
    jitter : float
        Half-width in ln s of each analysis's jitter about its stripe (:func:`jittered`;
        0: the stripes exactly).
    """

    intensities: np.ndarray
    limit_states: tuple[str, ...]
    motions: tuple[str, ...]
    exceeded: np.ndarray
    failed: np.ndarray
    fits: Mapping[str, StripeFit] = field(repr=False)
    mode: str = MODE_3D
    accuracy: str = "default"
    R: float = math.nan
    tan_alpha: float = math.nan
    n_analyses: int = 0
    measure: str = "pga"
    n_refined: int = 0
    component: str = DEFAULT_COMPONENT
    jitter: float = 0.0

    @property
    def scale(self) -> float:
        """Factor from the normalized intensities to the measure in its unit (g, m/s)."""
        from rocking.motions.measures import Measure

        return Measure.of(self.measure).per_normalized(self.tan_alpha)

    @property
    def n_exceeding(self) -> np.ndarray:
        return self.exceeded.sum(axis=1).astype(np.int64)

    @property
    def n_motions(self) -> np.ndarray:
        return (~self.failed).sum(axis=1).astype(np.int64)

    @property
    def fraction(self) -> np.ndarray:
        """Share of the analysed motions exceeding, (stripes, limit states) [-]; NaN at a
        stripe where every analysis failed."""
        n = self.n_motions[:, None]
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(n > 0, self.n_exceeding / np.maximum(n, 1), np.nan)

    def _per_state(self, attr: str) -> Mapping:
        return MappingProxyType({k: getattr(f, attr) for k, f in self.fits.items()})

    @property
    def median(self) -> Mapping[str, float]:
        return self._per_state("median")

    @property
    def beta(self) -> Mapping[str, float]:
        return self._per_state("beta")

    @property
    def median_ci(self) -> Mapping[str, tuple[float, float]]:
        return self._per_state("median_ci")

    @property
    def beta_ci(self) -> Mapping[str, tuple[float, float]]:
        return self._per_state("beta_ci")

    @property
    def status(self) -> Mapping[str, str]:
        return self._per_state("status")

    @property
    def reason(self) -> Mapping[str, str]:
        return self._per_state("reason")

    def __getitem__(self, limit_state: str | LimitState) -> StripeFit:
        """The fit of one limit state (any accepted spelling)."""
        from rocking.spectra.limit_states import match_limit_state

        return self.fits[match_limit_state(limit_state, self.limit_states)]

    @property
    def _vector_pga(self) -> bool:
        """The stripes are the spectra's PGA (vector peak): ``pga_g`` columns have values."""
        return self.measure == "pga" and self.component == VECTOR_PEAK

    def to_frame(self):
        """The stripes as a table: one row per (limit state, stripe) with ``intensity``
        [measure/(g tan α)], ``pga_g`` [g] (NaN for another measure than PGA), ``im`` [the
        measure's unit], ``n_exceeding``, ``n_motions``, ``fraction``."""
        import pandas as pd

        rows = []
        frac, k, n = self.fraction, self.n_exceeding, self.n_motions
        pga = self.tan_alpha if self._vector_pga else math.nan
        for j, name in enumerate(self.limit_states):
            for i, im in enumerate(self.intensities):
                rows.append({"limit_state": name, "intensity": float(im),
                             "pga_g": float(im) * pga, "im": float(im) * self.scale,
                             "n_exceeding": int(k[i, j]),
                             "n_motions": int(n[i]), "fraction": float(frac[i, j])})
        return pd.DataFrame(rows)

    def summary_frame(self):
        """The fits as a table: one row per limit state with ``median`` [measure/(g tan α)],
        ``median_pga_g`` [g] (NaN for another measure than PGA), ``beta`` [-], their 95 %
        intervals, ``status`` and ``reason``, then ``measure``, ``median_im`` [the
        measure's unit], ``bracket_lo``, ``bracket_hi`` [the measure's unit: the stripes
        around the step where the fit is separated or undefined, NaN where it is defined],
        ``n_refined``."""
        import pandas as pd

        rows = []
        pga = self.tan_alpha if self._vector_pga else math.nan
        for j, name in enumerate(self.limit_states):
            f = self.fits[name]
            lo = hi = math.nan
            if not math.isfinite(f.median):
                lo, hi = (v * self.scale for v in bracket(self.intensities,
                                                          self.n_exceeding[:, j],
                                                          self.n_motions))
            rows.append({"limit_state": name, "median": f.median,
                         "median_lo": f.median_ci[0], "median_hi": f.median_ci[1],
                         "median_pga_g": f.median * pga, "beta": f.beta,
                         "beta_lo": f.beta_ci[0], "beta_hi": f.beta_ci[1],
                         "status": f.status, "reason": f.reason, "measure": self.measure,
                         "component": self.component,
                         "median_im": f.median * self.scale, "bracket_lo": lo,
                         "bracket_hi": hi, "n_refined": int(self.n_refined),
                         "jitter": self.jitter})
        return pd.DataFrame(rows)

    def __repr__(self) -> str:
        head = (f"StripeFragility(mode={self.mode!r}, measure={self.measure!r}, R={self.R:g} m, "
                f"tan_alpha={self.tan_alpha:g}, {len(self.motions)} motions x "
                f"{self.intensities.size} stripes {self.intensities[0]:.4g}-"
                f"{self.intensities[-1]:.4g}, {self.n_analyses} analyses)")
        rows = []
        for name in self.limit_states:
            f = self.fits[name]
            note = "" if f.status == "ok" else f" [{f.status}: {f.reason}]"
            rows.append(f"  {name}: median {self.measure}/(g tan alpha) = {f.median:.4g} "
                        f"({100 * CONFIDENCE:g} % {f.median_ci[0]:.4g}-{f.median_ci[1]:.4g}), "
                        f"beta = {f.beta:.3g}{note}")
        return "\n".join([head, *rows])


def _check_motions(motions) -> list[GroundMotion]:
    if isinstance(motions, GroundMotion):
        motions = [motions]
    motions = list(motions)
    if not motions:
        raise ValueError("motions must hold at least one GroundMotion, got none")
    for i, m in enumerate(motions):
        if not isinstance(m, GroundMotion):
            raise ValueError(f"motions[{i}] must be a GroundMotion, got {type(m).__name__}")
        if not m.pga > 0.0:
            raise ValueError(f"motion {m.name!r} has zero PGA")
    names = [m.name for m in motions]
    dup = {n for n in names if names.count(n) > 1}
    if dup:
        raise ValueError(f"motion names must be unique, got {sorted(dup)} more than once")
    return motions


def stripe_outcomes(body: Cylinder | Block, motion: GroundMotion, states: Sequence[LimitState],
                    intensities: np.ndarray, mode: str, acc: Accuracy, *,
                    contact: Contact | None = None, progress=None, measure: str = "pga",
                    component: str = DEFAULT_COMPONENT,
                    jitter: float = 0.0) -> tuple[np.ndarray, np.ndarray, int]:
    """Analyse one motion at every stripe: (exceeded (stripes, states), failed (stripes,),
    analyses run). ``acc`` and ``contact`` (the damped model's; None: its default) come
    resolved and checked, as the entries above build them.

    ``intensities`` are ``measure``/(g tan α), each analysed at itself jittered by
    ``jitter`` in ln s (:func:`jittered`; 0: exactly): the motion is scaled so that its
    measure equals it (:func:`measure_ratio`). Each analysis stops once the largest tilt goal is
    passed (runs to its end when overturning is asked, and to the end of the record when a
    limit state watches a monitor, :func:`~rocking.spectra.limit_states.whole_record`);
    below the uplift intensity the body stays at rest and nothing is run, unless a limit
    state a body at rest can exceed is asked (sliding).
    """
    analyze = make_analysis(body, motion, mode, contact=contact,
                            rest_tilt=acc.rest_tilt, whole=whole_record(states))
    at_rest = any(ls.at_rest for ls in states)
    intensities = jittered(intensities, jitter, motion=motion.name, mode=mode, R=body.R,
                           tan_alpha=body.tan_alpha)
    ratio = measure_ratio(motion, measure, component)
    if ratio != 1.0:  # the PGA/(g tan α) each stripe of the measure gives this motion
        intensities = np.asarray(intensities, dtype=float) * ratio
    rtol = acc.rtol_for(MODES[mode][0])
    stop_at = stop_for(states, body.alpha)
    lower = uplift_intensity(motion, mode)
    exceeded = np.zeros((intensities.size, len(states)), dtype=bool)
    failed = np.zeros(intensities.size, dtype=bool)
    runs = 0
    for i, im in enumerate(intensities):
        if im > lower or at_rest:
            out = analyze(float(im), stop_at, rtol)
            runs += 1
            if out.status is Status.FAILED or not math.isfinite(out.theta_max):
                out = analyze(float(im), stop_at, rtol * RETRY_RTOL_FACTOR)
                runs += 1
            if out.status is Status.FAILED or not math.isfinite(out.theta_max):
                failed[i] = True
            else:  # a run stopped past the largest goal has passed every goal
                exceeded[i] = classify(out, states, body.alpha, stop_at,
                                       stopped=out.status is Status.STOPPED_AT_LIMIT)[1]
        if progress is not None:
            progress.update()
    return exceeded, failed, runs


def stripe_fragility(
    body: Cylinder | Block,
    motions: GroundMotion | Sequence[GroundMotion],
    limit_states=None,
    *,
    mode: str = MODE_3D,
    intensities=None,
    accuracy: str | Accuracy | dict = "default",
    omega_n: float | None = None,
    zeta: float | None = None,
    progress=False,
    measure: str = "pga",
    component: str = DEFAULT_COMPONENT,
    jitter: float = JITTER,
) -> StripeFragility:
    """Multiple-stripe fragility of a body under an ensemble of motions.

    Parameters
    ----------
    body : Cylinder or Block
        The rocking body (R [m], tan α [-]).
    motions : GroundMotion or sequence of GroundMotion
        The ensemble (unscaled; each is scaled to every stripe by its vector PGA).
    limit_states : str, sequence or None
        E.g. ``["overturning", "tilt:1/3"]``; None: the seven defaults.
    mode : {"3d", "3d-damped", "2d-x", "2d-y"}
    intensities : array_like, int or None
        The stripes, PGA/(g tan α) [-], strictly increasing, analysed exactly as given; an
        int: that many geometric stripes over :data:`STRIPE_RANGE`; None:
        :data:`DEFAULT_STRIPES` of them.
    accuracy : str, Accuracy or dict
        Preset or tolerances; only its ODE tolerances and rest tilt matter here.
    omega_n, zeta : float, optional
        Contact parameters of mode "3d-damped" [rad/s], [-].
    progress : bool or rocking._progress.Progress
        Report analyses done, rate and time left on stderr.
    measure : str
        Intensity measure of the stripes (:func:`rocking.motions.measures.parse_measure`):
        ``intensities`` are it over g tan α, and each motion is scaled so that its measure
        equals the stripe's value.
    component : str
        Horizontal component of ``measure`` (:data:`rocking.motions.measures.COMPONENTS`):
        each motion is scaled so that its measure in it equals the stripe.
    jitter : float
        Half-width w in ln s of each analysis's jitter about its stripe (:func:`jittered`,
        default :data:`JITTER`): the shares exceeding then estimate the mean over motions of
        their local exceedance probability; 0 analyses the stripes exactly.

    Returns
    -------
    StripeFragility
    """
    check_mode(mode)
    from rocking.motions.measures import Measure, parse_component

    Measure.of(measure)
    component = parse_component(component)
    motions = _check_motions(motions)
    states = parse_limit_states(limit_states, sort=False)
    for ls in states:
        ls.threshold(body.alpha)  # a tilt goal beyond π/2 fails here, before any analysis
    x = _check_intensities(intensities)
    acc = Accuracy.of(accuracy)
    contact = Contact.of(omega_n, zeta)
    bar = _progress(progress, x.size * len(motions), "stripes", unit="analysis")
    exceeded = np.zeros((x.size, len(motions), len(states)), dtype=bool)
    failed = np.zeros((x.size, len(motions)), dtype=bool)
    runs = 0
    for m, motion in enumerate(motions):
        exceeded[:, m], failed[:, m], r = stripe_outcomes(
            body, motion, states, x, mode, acc, contact=contact, progress=bar,
            measure=measure, component=component, jitter=jitter)
        runs += r
    if bar is not None and bar is not progress:
        bar.close()
    return from_outcomes(x, states, [m.name for m in motions], exceeded, failed, mode=mode,
                         accuracy=acc.name, R=float(body.R), tan_alpha=float(body.tan_alpha),
                         n_analyses=runs, measure=measure, component=component, jitter=jitter)


def from_outcomes(intensities, limit_states, motions: Sequence[str], exceeded, failed, *,
                  mode: str = MODE_3D, accuracy: str = "default", R: float = math.nan,
                  tan_alpha: float = math.nan, n_analyses: int = 0, measure: str = "pga",
                  n_refined: int = 0, component: str = DEFAULT_COMPONENT,
                  jitter: float = 0.0) -> StripeFragility:
    """A :class:`StripeFragility` (fits included) from per-analysis outcomes, e.g. read back
    from a store: ``exceeded`` (stripes, motions, limit states), ``failed`` (stripes,
    motions)."""
    x = _check_intensities(intensities)
    names = tuple(ls.name for ls in parse_limit_states(limit_states, sort=False))
    exc = np.asarray(exceeded, dtype=bool)
    fail = np.asarray(failed, dtype=bool)
    want = (x.size, len(motions), len(names))
    if exc.shape != want or fail.shape != want[:2]:
        raise ValueError(f"exceeded must have shape {want} and failed {want[:2]}, got "
                         f"{exc.shape} and {fail.shape}")
    exc = exc & ~fail[:, :, None]
    k = exc.sum(axis=1)
    n = (~fail).sum(axis=1)
    fits = {name: fit_stripes(x, k[:, j], n) for j, name in enumerate(names)}
    return StripeFragility(x, names, tuple(motions), exc, fail, MappingProxyType(fits),
                           mode, accuracy, R, tan_alpha, int(n_analyses), measure,
                           int(n_refined), component, float(jitter))


# --------------------------------------------------------------------------------------
# Refinement where the data separate, and the bootstrap over motions
# --------------------------------------------------------------------------------------


def stripe_analyzer(body: Cylinder | Block, motions: Sequence[GroundMotion], limit_states, *,
                    mode: str = MODE_3D, accuracy: str | Accuracy | dict = "default",
                    omega_n: float | None = None, zeta: float | None = None,
                    measure: str = "pga", component: str = DEFAULT_COMPONENT,
                    jitter: float = JITTER) -> Callable[[float], tuple]:
    """``analyze(x)``: every motion at one more stripe ``x`` [measure/(g tan α)], as
    :func:`stripe_fragility` analyses them; returns (exceeded (motions, limit states),
    failed (motions,), analyses run)."""
    states = parse_limit_states(limit_states, sort=False)
    acc = Accuracy.of(accuracy)
    contact = Contact.of(omega_n, zeta)

    def analyze(x: float) -> tuple[np.ndarray, np.ndarray, int]:
        exc = np.zeros((len(motions), len(states)), dtype=bool)
        fail = np.zeros(len(motions), dtype=bool)
        runs = 0
        for m, motion in enumerate(motions):
            e, f, r = stripe_outcomes(body, motion, states, np.array([float(x)]), mode, acc,
                                      contact=contact, measure=measure,
                                      component=component, jitter=jitter)
            exc[m], fail[m], runs = e[0], f[0], runs + r
        return exc, fail, runs

    return analyze


def refine_stripes(result: StripeFragility, limit_state: str,
                   analyze: Callable[[float], tuple], budget: int = DEFAULT_REFINE,
                   log: Callable[[str], None] | None = None) -> StripeFragility:
    """The fit of one limit state with stripes added where the data separate.

    While the fit is ``"separated"`` and fewer than ``budget`` stripes were added, one
    stripe is added at :func:`refinement_point` (every motion analysed there by
    ``analyze``, e.g. :func:`stripe_analyzer`) and the fit redone. Other statuses are
    returned as they are: no stripe between two others can define them.

    Parameters
    ----------
    result : StripeFragility
        The stripes as asked.
    limit_state : str
        One of ``result.limit_states``.
    analyze : callable
        ``analyze(x)`` → (exceeded (motions, limit states of ``result``), failed (motions,),
        analyses run) at the stripe x [measure/(g tan α)].
    budget : int
        Most stripes added (>= 0).
    log : callable, optional
        Receives one line per stripe added.

    Returns
    -------
    StripeFragility
        Of the one limit state, over the stripes as asked and those added
        (``n_refined``); the result itself restricted to it where nothing was added.
    """
    if isinstance(budget, bool) or not isinstance(budget, int | np.integer) or budget < 0:
        raise ValueError(f"refine budget must be an integer >= 0, got {budget!r}")
    j = result.limit_states.index(limit_state)
    x = result.intensities.copy()
    exc, fail = result.exceeded[:, :, j].copy(), result.failed.copy()
    every = result.exceeded.copy()
    runs, added = result.n_analyses, 0
    while added < budget:
        k, n = (exc & ~fail).sum(axis=1), (~fail).sum(axis=1)
        if fit_stripes(x, k, n).status != "separated":
            break
        new = refinement_point(x, k, n)
        if new is None:
            break
        e, f, r = analyze(new)
        i = int(np.searchsorted(x, new))
        x = np.insert(x, i, new)
        exc = np.insert(exc, i, np.asarray(e, dtype=bool)[:, j], axis=0)
        every = np.insert(every, i, np.asarray(e, dtype=bool), axis=0)
        fail = np.insert(fail, i, np.asarray(f, dtype=bool), axis=0)
        runs, added = runs + int(r), added + 1
        if log is not None:
            log(f"{result.mode}, {limit_state}, R = {result.R:g} m: stripe {added} of at most "
                f"{budget} added at {new * result.scale:.6g} ({result.measure}), "
                f"{int(e[:, j].sum())} of {len(result.motions)} motions exceeding")
    return from_outcomes(x, [limit_state], result.motions, every[:, :, [j]], fail,
                         mode=result.mode, accuracy=result.accuracy, R=result.R,
                         tan_alpha=result.tan_alpha, n_analyses=runs, measure=result.measure,
                         n_refined=added, component=result.component, jitter=result.jitter)


BOOT_CODES = {"ok": 0, "separated": 1, "none-exceeded": 2, "all-exceeded": 3, "no-trend": 4,
              "no-analyses": 5, "extrapolated": 6}
"""Status of each resample's fit in :func:`bootstrap_stripes` (``status`` codes)."""


def bootstrap_stripes(result: StripeFragility, resamples: int = DEFAULT_BOOTSTRAP,
                      seed: int = BOOTSTRAP_SEED) -> dict[str, dict[str, np.ndarray]]:
    """Resample the motions with replacement and refit, per limit state.

    Every resample draws as many motions as the ensemble holds (one index matrix from
    ``numpy.random.default_rng(seed)``, the same for every limit state and for every result
    of as many motions) and fits :func:`fit_stripes` to their counts at every stripe.

    Where a resample's data separate the maximum of the likelihood is at β → 0 with θ
    anywhere between the bracketing stripes (:func:`bracket`): its median is taken as their
    geometric middle and β as 0. Where no motion of the resample exceeds, its median is
    +inf; where all exceed at every stripe, 0; where no fit exists otherwise, NaN.

    Returns
    -------
    dict
        Per limit state: ``median`` [measure/(g tan α)], ``beta`` [-], ``status``
        (:data:`BOOT_CODES`), each of shape (resamples,).
    """
    if isinstance(resamples, bool) or not isinstance(resamples, int | np.integer) \
            or resamples < 1:
        raise ValueError(f"resamples must be an integer >= 1, got {resamples!r}")
    n_mot = len(result.motions)
    idx = bootstrap_indices(n_mot, int(resamples), seed)  # the draws every fragility uses
    # times each motion is drawn, per resample: the counts are weighted sums
    w = np.zeros((int(resamples), n_mot), dtype=np.int64)
    np.add.at(w, (np.arange(int(resamples))[:, None], idx), 1)
    ok = (~result.failed).astype(np.int64)  # (stripes, motions)
    n = w @ ok.T  # (resamples, stripes)
    out = {}
    for j, name in enumerate(result.limit_states):
        k = w @ (result.exceeded[:, :, j] & ~result.failed).astype(np.int64).T
        median = np.empty(int(resamples))
        beta = np.empty(int(resamples))
        code = np.empty(int(resamples), dtype=np.int8)
        seen: dict[bytes, tuple[float, float, int]] = {}
        full = result.fits[name]
        # a resample's optimum lies near the whole ensemble's: start there where it exists
        start = (np.log([full.median, full.beta]) if np.isfinite(full.median) and full.beta > 0
                 else None)
        for b in range(int(resamples)):
            key = k[b].tobytes() + n[b].tobytes()
            if key not in seen:
                seen[key] = _resample_fit(result.intensities, k[b], n[b], start)
            median[b], beta[b], code[b] = seen[key]
        out[name] = {"median": median, "beta": beta, "status": code}
    return out


def _scoring_fit(x: np.ndarray, k: np.ndarray, n: np.ndarray,
                 start: np.ndarray | None = None) -> tuple[float, float] | None:
    """(θ, β) maximizing the binomial likelihood by Fisher scoring with step halving, or
    None if it does not converge (then :func:`fit_stripes` decides). Some hundred times
    faster than :func:`fit_stripes` (no Wald intervals, no scipy optimizer): the bootstrap
    fits a thousand resamples per row."""
    used = n > 0
    log_x, k, n = np.log(x[used]), k[used].astype(float), n[used].astype(float)
    params = _start(x[used], k, n) if start is None else np.array(start, dtype=float)
    nll, grad = binomial_neg_log_likelihood(params, log_x, k, n)
    for _ in range(200):
        beta = math.exp(params[1])
        z = (log_x - params[0]) / beta
        p = np.clip(special.ndtr(z), 1e-300, 1.0 - 1e-16)
        dens = np.exp(-0.5 * z * z) / math.sqrt(2.0 * math.pi)
        g = np.stack([-dens / beta, -dens * z])
        info = (g * (n / (p * (1.0 - p)))) @ g.T
        try:
            step = -np.linalg.solve(info, grad)
        except np.linalg.LinAlgError:
            return None
        for _ in range(60):  # halve until the likelihood does not fall
            trial = params + step
            t_nll, t_grad = binomial_neg_log_likelihood(trial, log_x, k, n)
            if t_nll <= nll + 1e-12 * abs(nll):
                break
            step = step / 2.0
        else:
            return None
        params, nll, grad = trial, t_nll, t_grad
        if np.max(np.abs(step)) < 1e-11 or params[1] > math.log(10.0 * BETA_MAX):
            break
    else:
        return None
    median, beta = math.exp(params[0]), math.exp(params[1])
    if not (math.isfinite(median) and beta <= BETA_MAX and np.max(np.abs(grad)) < 1e-6):
        return None
    return median, beta


def _resample_fit(x: np.ndarray, k: np.ndarray, n: np.ndarray,
                  start: np.ndarray | None = None) -> tuple[float, float, int]:
    if _degenerate(x, k, n) is None:
        fast = _scoring_fit(x, k, n, start)
        if fast is not None:
            status = "ok" if x[n > 0][0] <= fast[0] <= x[n > 0][-1] else "extrapolated"
            return fast[0], fast[1], BOOT_CODES[status]
    f = fit_stripes(x, k, n)
    if f.status == "separated":
        lo, hi = bracket(x, k, n)
        return math.sqrt(lo * hi), 0.0, BOOT_CODES["separated"]
    if f.status == "none-exceeded":
        return math.inf, math.nan, BOOT_CODES[f.status]
    if f.status == "all-exceeded":
        return 0.0, math.nan, BOOT_CODES[f.status]
    return f.median, f.beta, BOOT_CODES[f.status]


EXCEEDANCE_COLUMNS = ("limit_state", "intensity", "im", "jitter", "n_exceeding", "n_motions",
                      "share", "share_p05", "share_p95")
"""Columns of :func:`exceedance_table` (``stripe_exceedance.csv``)."""


def exceedance_table(result: StripeFragility, resamples: int = DEFAULT_BOOTSTRAP,
                     seed: int = BOOTSTRAP_SEED, level: float = BOOTSTRAP_LEVEL):
    """The ensemble's exceedance probability at every stripe, with no lognormal assumed.

    F(s), the share of the analysed motions exceeding at stripe s, and its ``level``
    interval over ``resamples`` resamples of the motions (the draws of
    :func:`bootstrap_stripes`). With jittered stripes (:func:`jittered`) F(s) estimates the
    mean over motions of their local exceedance probability P_m(s) without bias: the
    fragility that converges as motions are added (issue 45), whatever its shape.

    Returns
    -------
    pandas.DataFrame
        :data:`EXCEEDANCE_COLUMNS`: per limit state and stripe, ``intensity``
        [measure/(g tan α)], ``im`` [the measure's unit], ``jitter``, the counts, ``share``
        and its interval (NaN where no motion was analysed).
    """
    import pandas as pd

    n_mot = len(result.motions)
    idx = bootstrap_indices(n_mot, int(resamples), seed)
    w = np.zeros((int(resamples), n_mot), dtype=np.int64)
    np.add.at(w, (np.arange(int(resamples))[:, None], idx), 1)
    ok = (~result.failed).astype(np.int64)
    n = (w @ ok.T).astype(float)  # (resamples, stripes)
    a = 100.0 * (1.0 - level) / 2.0
    rows = []
    frac = result.fraction
    for j, name in enumerate(result.limit_states):
        k = w @ (result.exceeded[:, :, j] & ~result.failed).astype(np.int64).T
        with np.errstate(invalid="ignore", divide="ignore"):
            share = np.where(n > 0, k / np.where(n > 0, n, 1.0), np.nan)
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            lo, hi = np.nanpercentile(share, [a, 100.0 - a], axis=0)
        for i, s in enumerate(result.intensities):
            rows.append({"limit_state": name, "intensity": float(s),
                         "im": float(s) * result.scale, "jitter": result.jitter,
                         "n_exceeding": int(result.n_exceeding[i, j]),
                         "n_motions": int(result.n_motions[i]), "share": float(frac[i, j]),
                         "share_p05": float(lo[i]), "share_p95": float(hi[i])})
    return pd.DataFrame(rows, columns=list(EXCEEDANCE_COLUMNS))


def bootstrap_interval(medians, level: float = BOOTSTRAP_LEVEL) -> tuple[float, float]:
    """(lower, upper) equal-tailed percentile interval of the resampled medians.

    Resamples without a median (NaN) are left out; ±inf and 0 take part (an order
    statistic, ``inverted_cdf``, so an unbounded end stays unbounded). NaN if none has one.
    """
    m = np.asarray(medians, dtype=float)
    m = m[~np.isnan(m)]
    if m.size == 0:
        return math.nan, math.nan
    a = (1.0 - level) / 2.0
    lo, hi = np.quantile(m, [a, 1.0 - a], method="inverted_cdf")
    return float(lo), float(hi)
