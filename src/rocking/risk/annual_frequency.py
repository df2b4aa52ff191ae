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

The occurrence of exceedances is taken as Poisson: the probability of at least one in T years
is 1 − exp(−λ_LS·T), the return period 1/λ_LS.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import special

from .hazard import HazardCurve

TAIL_DECADES_E = 40.0
"""The tails are followed until the hazard has dropped by e^−40 (or Φ by as much)."""

STEPS_PER_BETA = 40
"""Grid steps per β in ln im: the trapezoid error is ~(1/40)²/12 of the integrand's scale."""

MIN_STEPS = 4000


def _check(median_g: float, beta: float) -> tuple[float, float]:
    m, b = float(median_g), float(beta)
    if not (math.isfinite(m) and m > 0):
        raise ValueError(f"median_g must be finite and > 0 [g], got {median_g!r}")
    if not (math.isfinite(b) and b > 0):
        raise ValueError(f"beta must be finite and > 0 [-], got {beta!r}")
    return m, b


def _grid(m: float, b: float, hazard: HazardCurve) -> np.ndarray:
    # ln im from where Φ·λ is negligible below to where it is negligible above, with the
    # table's levels as nodes (the integrand has kinks there).
    lx = np.log(hazard.im_g)
    k = hazard.slope(hazard.im_g[:-1])
    k_first, k_last, k_max = float(k[0]), float(k[-1]), float(max(k.max(), 0.0))
    lm = math.log(m)
    # Below: Φ(z)·e^{−k b z} peaks near z = −k b; 12 β further down it is below e^−40.
    lo = lm - k_max * b * b - 12.0 * b
    if k_first <= 0.0:  # flat start: |dλ| = 0 below im_1
        lo = max(lo, lx[0])
    hi = max(lx[-1], lm + 12.0 * b)
    if k_last > 0.0:
        hi += TAIL_DECADES_E / k_last
    n = max(MIN_STEPS, int(math.ceil((hi - lo) / b * STEPS_PER_BETA)))
    inside = lx[(lx > lo) & (lx < hi)]
    return np.unique(np.concatenate([np.linspace(lo, hi, n + 1), inside]))


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
    u = _grid(m, b, hazard)
    im = np.exp(u)
    p = special.ndtr((u - math.log(m)) / b)
    f = p * hazard.slope(im) * hazard.rate(im)  # P(LS|im)·|dλ/d ln im|
    lx0, lxn = math.log(hazard.im_g[0]), math.log(hazard.im_g[-1])

    def part(mask: np.ndarray) -> float:
        return float(np.trapezoid(f[mask], u[mask])) if mask.sum() > 1 else 0.0

    below, inside, beyond = part(u <= lx0), part((u >= lx0) & (u <= lxn)), part(u >= lxn)
    # beyond im_n: at least P(LS|im_n)·λ(im_n) for any tail; the rest is the slope's doing
    floor = float(special.ndtr((lxn - math.log(m)) / b)) * float(hazard.annual_rate[-1])
    return {"total": below + inside + beyond, "below_first": below, "inside": inside,
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


Z_NODES = 401
"""Nodes in the standard normal variable of :func:`mean_annual_frequencies`."""


def mean_annual_frequencies(median_g, beta, hazard: HazardCurve) -> np.ndarray:
    """λ_LS of many lognormal fragilities at once (the bootstrap's resamples) [1/yr].

    The same integral as :func:`mean_annual_frequency`, integrated by parts:
    λ_LS = ∫ Φ(ln(im/θ)/β) |dλ(im)| = E[λ(C)], C = θ·e^{βZ} the lognormal capacity, Z
    standard normal; trapezoid over z from −(8 + k_max·β) to 8 (the integrand
    λ(θe^{βz})φ(z) ∝ e^{−kβz − z²/2} peaks at z = −kβ) with :data:`Z_NODES` nodes, the hazard
    interpolated and extrapolated as everywhere (:meth:`HazardCurve.rate`). NaN in, NaN out.

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
    m = np.asarray(median_g, dtype=float)
    b = np.asarray(beta, dtype=float)
    if m.shape != b.shape:
        raise ValueError(f"median_g and beta must have the same shape, got {m.shape} and "
                         f"{b.shape}")
    out = np.full(m.shape, np.nan)
    ok = np.isfinite(m) & np.isfinite(b) & (m > 0) & (b > 0)
    if not ok.any():
        return out
    k_max = float(max(hazard.slope(hazard.im_g[:-1]).max(), 0.0))
    mm, bb = m[ok], b[ok]
    lam = np.empty(mm.size)
    for start in range(0, mm.size, 200):  # chunks keep the work arrays small
        sl = slice(start, start + 200)
        lo = -(8.0 + k_max * bb[sl])
        t = np.linspace(0.0, 1.0, Z_NODES)
        z = lo[:, None] + (8.0 - lo)[:, None] * t[None, :]
        f = hazard.rate(mm[sl, None] * np.exp(bb[sl, None] * z)) * np.exp(-0.5 * z * z)
        lam[sl] = np.trapezoid(f, z, axis=1) / math.sqrt(2.0 * math.pi)
    out[ok] = lam
    return out


def annual_frequency_interval(median_g, beta, hazard: HazardCurve,
                              ci: float = 0.90) -> tuple[float, float, np.ndarray]:
    """The ``ci`` interval of λ_LS over bootstrap resamples of a fragility.

    Parameters
    ----------
    median_g, beta : array_like
        θ [g] and β [-] of each resample (:func:`rocking.spectra.fragility.bootstrap_lognormal`;
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
    if not (math.isfinite(years) and years > 0):
        raise ValueError(f"years must be finite and > 0, got {years!r}")
    return float(-np.expm1(-float(annual_frequency) * years))


def closed_form_frequencies(median_g, beta, hazard: HazardCurve) -> np.ndarray:
    """λ_LS of many lognormal fragilities, exactly for the hazard as it is interpolated [1/yr].

    The hazard is a piecewise power law in im (log-log interpolation, the end slopes
    extrapolated: :meth:`HazardCurve.rate`), so λ_LS = E[λ(C)], C = θ·e^{βZ}, is a sum over
    its segments [u_j, u_{j+1}] of ln im with λ = λ_j (im/im_j)^−k_j:

        λ_LS = Σ_j λ_j (θ/im_j)^−k_j e^{k_j²β²/2} [Φ(z_{j+1} + k_jβ) − Φ(z_j + k_jβ)],

    z = (u − ln θ)/β, the first segment open below and the last above (Cornell et al.'s
    closed form of a power law is the one-segment case). No quadrature: exact to rounding,
    vectorised over any shape; the trapezoid of :func:`annual_frequency_parts` differs from
    it by its quadrature error (measured 2e-5 to 4e-4 relative on the example hazard).
    NaN in (or θ, β ≤ 0), NaN out.

    Parameters
    ----------
    median_g, beta : array_like
        θ [g] and β [-] (same shape).
    hazard : HazardCurve

    Returns
    -------
    numpy.ndarray
        λ_LS [1/yr], the shape of ``median_g``.
    """
    m = np.asarray(median_g, dtype=float)
    b = np.asarray(beta, dtype=float)
    if m.shape != b.shape:
        raise ValueError(f"median_g and beta must have the same shape, got {m.shape} and "
                         f"{b.shape}")
    ok = np.isfinite(m) & np.isfinite(b) & (m > 0) & (b > 0)
    lx, ly = np.log(hazard.im_g), np.log(hazard.annual_rate)
    k = -np.diff(ly) / np.diff(lx)
    edges = np.concatenate([[-np.inf], lx[1:-1], [np.inf]])
    mu = np.log(np.where(ok, m, 1.0))[..., None]
    bb = np.where(ok, b, 1.0)[..., None]
    kb = k * bb
    lo, hi = (edges[:-1] - mu) / bb + kb, (edges[1:] - mu) / bb + kb
    # the difference of Φ on the side of its smaller tail keeps its digits
    upper = lo > 0.0
    diff = np.where(upper, special.ndtr(-lo) - special.ndtr(-hi),
                    special.ndtr(hi) - special.ndtr(lo))
    with np.errstate(divide="ignore"):
        terms = np.exp(ly[:-1] + k * (lx[:-1] - mu) + 0.5 * kb * kb + np.log(diff))
    return np.where(ok, terms.sum(axis=-1), np.nan)


__all__ = ["annual_frequency_interval", "annual_frequency_parts", "closed_form_frequencies",
           "mean_annual_frequencies", "mean_annual_frequency", "probability_in"]
