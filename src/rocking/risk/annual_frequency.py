"""Mean annual frequency of a limit state: a lognormal fragility integrated against a hazard curve.

    λ_LS = ∫ P(LS | im) |dλ(im)| = ∫ Φ(ln(im/θ)/β) · k(im) · λ(im) d ln im,

θ the median capacity [g], β the dispersion, λ the hazard curve and k = −d ln λ/d ln im its
local log-log slope. For a power law λ = k0·im^−k the integral is closed-form,
λ_LS = k0·θ^−k·exp(k²β²/2) (Cornell et al. 2002), which the tests check.

Ends of the hazard curve (a table from im_1 to im_n):

- **inside** [im_1, im_n]: log-log interpolation (a piecewise power law);
- **beyond im_n**: the last segment's log-log slope is extrapolated. Truncating instead
  (λ = 0 beyond im_n) would count the motions stronger than im_n as never exceeding the
  limit state, and would underestimate λ_LS by up to λ(im_n) whenever the capacity sits near
  or above im_n — the case of large columns, whose overturning PGA can exceed the levels of
  a hazard model. Whatever the tail's shape, the part beyond im_n lies between
  P(LS | im_n)·λ(im_n) (all those motions just above im_n) and λ(im_n) (all exceeding);
  what the extrapolated slope decides is the excess over the lower bound, returned by
  :func:`annual_frequency_parts` as ``extrapolated`` so a reader sees how much of λ_LS rests
  on it;
- **below im_1**: the first slope is extrapolated too, for symmetry (a power law is then
  reproduced exactly); P(LS | im) is negligible there for any capacity well above im_1, and
  the share is returned as ``below_first``.

The integral is evaluated exactly, without quadrature: the hazard as interpolated is a
power law on each segment [im_j, im_{j+1}] (λ = λ_j (im/im_j)^−k_j, the end segments open),
and on each, with C = θ·e^{βZ} the lognormal capacity, λ_LS = E[λ(C)] gives Cornell's closed
form cut to the segment:

    λ_LS = Σ_j λ_j (θ/im_j)^−k_j e^{k_j²β²/2} [Φ(z_{j+1} + k_jβ) − Φ(z_j + k_jβ)],
    z_j = ln(im_j/θ)/β,

(:func:`segment_rates`; for a power law, the one-segment case, λ_LS = k0·θ^−k·e^{k²β²/2}
to rounding). One function serves one fragility and many (the bootstrap's resamples, a
portfolio's columns); it replaced two trapezoid rules that differed from it by their
quadrature errors (up to 4e-4 and 5e-6 relative on the example hazard).

The occurrence of exceedances is taken as Poisson: the probability of at least one in T years
is 1 − exp(−λ_LS·T), the return period 1/λ_LS.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import special

from rocking._validate import positive_finite
from rocking.risk.hazard import HazardCurve


def _check(median_g: float, beta: float) -> tuple[float, float]:
    return positive_finite("median_g [g]", median_g), positive_finite("beta", beta)


def segment_rates(median_g, beta, hazard: HazardCurve) -> np.ndarray:
    """The part of λ_LS from each segment of the hazard, exactly [1/yr].

    Segments: below the first level (the first slope extrapolated), between each pair of
    levels, beyond the last (the last slope extrapolated): ``n + 1`` for ``n`` levels, along
    a new last axis; their sum is λ_LS (module docstring). θ or β not finite or ≤ 0: NaN.

    Parameters
    ----------
    median_g, beta : array_like
        θ [g] and β [-] (same shape).
    hazard : HazardCurve

    Returns
    -------
    numpy.ndarray
        Shape ``median_g.shape + (n + 1,)`` [1/yr].
    """
    m = np.asarray(median_g, dtype=float)
    b = np.asarray(beta, dtype=float)
    if m.shape != b.shape:
        raise ValueError(f"median_g and beta must have the same shape, got {m.shape} and "
                         f"{b.shape}")
    ok = np.isfinite(m) & np.isfinite(b) & (m > 0) & (b > 0)
    lx, ly = np.log(hazard.im_g), np.log(hazard.annual_rate)
    k = -np.diff(ly) / np.diff(lx)
    # segment s runs from edges[s] to edges[s + 1] on the power law through level ref[s]
    k = np.concatenate([k[:1], k, k[-1:]])
    ref = np.concatenate([[0], np.arange(lx.size - 1), [lx.size - 2]])
    edges = np.concatenate([[-np.inf], lx, [np.inf]])
    mu = np.log(np.where(ok, m, 1.0))[..., None]
    bb = np.where(ok, b, 1.0)[..., None]
    kb = k * bb
    lo, hi = (edges[:-1] - mu) / bb + kb, (edges[1:] - mu) / bb + kb
    # the difference of Φ taken on the side of its smaller tail keeps its digits
    diff = np.where(lo > 0.0, special.ndtr(-lo) - special.ndtr(-hi),
                    special.ndtr(hi) - special.ndtr(lo))
    with np.errstate(divide="ignore"):
        terms = np.exp(ly[ref] + k * (lx[ref] - mu) + 0.5 * kb * kb + np.log(diff))
    return np.where(ok[..., None], terms, np.nan)


def annual_frequency_parts(median_g: float, beta: float, hazard: HazardCurve) -> dict:
    """λ_LS and the parts of it from below, inside and beyond the hazard table.

    Parameters
    ----------
    median_g : float
        Median PGA capacity θ of the lognormal fragility [g].
    beta : float
        Its dispersion β (standard deviation of ln capacity) [-].
    hazard : HazardCurve
        Annual rate of exceedance of PGA at the site.

    Returns
    -------
    dict
        ``total``, ``below_first``, ``inside``, ``beyond_last`` [1/yr], and
        ``extrapolated``: the part of ``beyond_last`` above P(LS | im_n)·λ(im_n), which the
        extrapolated last slope decides [1/yr].
    """
    m, b = _check(median_g, beta)
    terms = segment_rates(m, b, hazard)
    # segment_rates splits λ_LS = E[λ(C)] by where the capacity C lies; the parts here are
    # by where the intensity lies, ∫ P(LS|im) |dλ| over each range. By parts,
    # ∫_a^b Φ |dλ| = ∫_a^b λ φ d ln im / β + Φ(a)λ(a) − Φ(b)λ(b): the boundary terms move
    # P(LS | im_1)·λ(im_1) and P(LS | im_n)·λ(im_n) between the ranges.
    p = special.ndtr((np.log(hazard.im_g[[0, -1]]) - math.log(m)) / b)
    first = float(p[0] * hazard.annual_rate[0])
    floor = float(p[1] * hazard.annual_rate[-1])  # beyond im_n: at least this, any tail
    below = max(float(terms[0]) - first, 0.0)
    inside = float(terms[1:-1].sum()) + first - floor
    beyond = float(terms[-1]) + floor
    return {"total": float(terms.sum()), "below_first": below, "inside": inside,
            "beyond_last": beyond, "extrapolated": max(beyond - floor, 0.0)}


def mean_annual_frequency(median_g: float, beta: float, hazard: HazardCurve) -> float:
    """Mean annual frequency λ_LS of exceeding a limit state with a lognormal fragility [1/yr].

    λ_LS = ∫ Φ(ln(im/θ)/β) |dλ(im)|, the hazard interpolated log-log inside its table and
    extrapolated with its end slopes outside (module docstring: why, and how much of λ_LS the
    ends carry, :func:`annual_frequency_parts`).

    Parameters
    ----------
    median_g : float
        Median PGA capacity θ [g], > 0.
    beta : float
        Dispersion β [-], > 0.
    hazard : HazardCurve
        Annual rate of exceedance of PGA [1/yr].

    Returns
    -------
    float
        λ_LS [1/yr].

    Examples
    --------
    >>> import math, rocking
    >>> h = rocking.HazardCurve.from_power_law(k0=1e-4, k=2.5)
    >>> round(rocking.mean_annual_frequency(0.5, 0.4, h) / (1e-4 * 0.5**-2.5
    ...       * math.exp(2.5**2 * 0.4**2 / 2)), 4)
    1.0
    """
    return annual_frequency_parts(median_g, beta, hazard)["total"]


def mean_annual_frequencies(median_g, beta, hazard: HazardCurve) -> np.ndarray:
    """λ_LS of many lognormal fragilities at once (the bootstrap's resamples, a portfolio's
    columns) [1/yr]: the sum of :func:`segment_rates`, exactly as
    :func:`mean_annual_frequency` one at a time. NaN in (or θ, β ≤ 0), NaN out.

    Parameters
    ----------
    median_g, beta : array_like
        θ [g] and β [-] of each fragility (same shape).
    hazard : HazardCurve

    Returns
    -------
    numpy.ndarray
        λ_LS [1/yr], the shape of ``median_g``.
    """
    return segment_rates(median_g, beta, hazard).sum(axis=-1)


def annual_frequency_interval(median_g, beta, hazard: HazardCurve,
                              ci: float = 0.90) -> tuple[float, float, np.ndarray]:
    """The ``ci`` interval of λ_LS over bootstrap resamples of a fragility.

    Parameters
    ----------
    median_g, beta : array_like
        θ [g] and β [-] of each resample (:func:`rocking.fragility.lognormal.bootstrap_lognormal`;
        NaN where a resample has no fit).
    hazard : HazardCurve
    ci : float
        Central probability of the interval (0.90: the 5th and 95th percentiles).

    Returns
    -------
    (float, float, numpy.ndarray)
        Lower and upper end [1/yr] over the resamples with a fit (NaN if none), and λ_LS
        of every resample.
    """
    if not 0.0 < ci < 1.0:
        raise ValueError(f"ci must be in (0, 1), got {ci!r}")
    lam = mean_annual_frequencies(median_g, beta, hazard)
    fin = lam[np.isfinite(lam)]
    if fin.size == 0:
        return math.nan, math.nan, lam
    q = 100.0 * (1.0 - ci) / 2.0
    return float(np.percentile(fin, q)), float(np.percentile(fin, 100.0 - q)), lam


def probability_in(annual_frequency: float, years: float) -> float:
    """Probability of at least one exceedance in ``years`` (Poisson): 1 − exp(−λT) [-]."""
    years = positive_finite("years", years)
    return float(-np.expm1(-float(annual_frequency) * years))


__all__ = ["annual_frequency_interval", "annual_frequency_parts", "mean_annual_frequencies",
           "mean_annual_frequency", "probability_in", "segment_rates"]
