"""Arias intensity, the Husid function and the durations read from it.

The Husid function I_a(t) = (π/2g) ∫₀ᵗ a² dτ is the cumulative Arias intensity. The times at
which it reaches fixed fractions of its final value define the significant duration
D5-95 = t_0.95 − t_0.05 and the middle of strong shaking t_mid = t_0.45 used by the
Rezaeian–Der Kiureghian ground-motion model.

All functions accept one record (1-D) or a stack of records (the time axis last), so an
ensemble of synthetic motions is processed in one call.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.integrate import cumulative_trapezoid

from rocking._validate import positive_finite
from rocking.constants import G


def _signal(name: str, a: ArrayLike, min_len: int = 2) -> NDArray[np.float64]:
    """Float array with time on the last axis; raise naming ``name`` on NaN/inf or short input."""
    x = np.asarray(a, dtype=np.float64)
    if x.ndim == 0:
        raise ValueError(f"{name} must be an array of samples, got a scalar {a!r}")
    if x.shape[-1] < min_len:
        raise ValueError(f"{name} needs at least {min_len} samples, got {x.shape[-1]}")
    if not np.all(np.isfinite(x)):
        bad = np.argwhere(~np.isfinite(x))[0]
        raise ValueError(f"{name} has a non-finite value {x[tuple(bad)]!r} at index {tuple(bad)}")
    return x


def husid(a: ArrayLike, dt: float) -> NDArray[np.float64]:
    """Cumulative Arias intensity (Husid function) by the trapezoid rule.

    Parameters
    ----------
    a : array_like
        Ground acceleration [m/s²], time on the last axis.
    dt : float
        Time step [s], > 0.

    Returns
    -------
    numpy.ndarray
        I_a(t_k) [m/s], same shape as ``a``, starting at 0.
    """
    x = _signal("a", a)
    dt = positive_finite("dt", dt)
    return (math.pi / (2.0 * G)) * cumulative_trapezoid(x * x, dx=dt, axis=-1, initial=0.0)


def arias(a: ArrayLike, dt: float) -> float | NDArray[np.float64]:
    """Total Arias intensity Ia = I_a(t_end) [m/s] (an array for a stack of records)."""
    ia = husid(a, dt)[..., -1]
    return float(ia) if ia.ndim == 0 else ia


def times_from_husid(ia_cum: ArrayLike, dt: float, p: ArrayLike) -> float | NDArray[np.float64]:
    """Times at which a Husid curve first reaches the fractions ``p`` of its final value.

    Parameters
    ----------
    ia_cum : array_like
        Non-decreasing cumulative intensity, 1-D [any unit], with a positive final value.
    dt : float
        Time step [s], > 0.
    p : float or array_like
        Fractions in [0, 1].

    Returns
    -------
    float or numpy.ndarray
        t_p [s]: the first sample with I_a ≥ p·Ia, refined by linear interpolation between
        that sample and the one before it.
    """
    h = _signal("ia_cum", ia_cum)
    if h.ndim != 1:
        raise ValueError(f"ia_cum must be one-dimensional, got shape {h.shape}")
    dt = positive_finite("dt", dt)
    p_arr = np.asarray(p, dtype=np.float64)
    if not np.all(np.isfinite(p_arr)) or np.any((p_arr < 0.0) | (p_arr > 1.0)):
        raise ValueError(f"p must be fractions in [0, 1], got {p!r}")
    total = h[-1]
    if not total > 0.0:
        raise ValueError(f"the record has no energy (final Arias intensity {total!r})")
    frac = h / total
    # First index whose fraction reaches p: searchsorted on the running maximum keeps the
    # search valid even if rounding makes the cumulative sum dip by one ulp.
    frac = np.maximum.accumulate(frac)
    k = np.searchsorted(frac, p_arr, side="left")
    k = np.clip(k, 1, h.size - 1)
    f0, f1 = frac[k - 1], frac[k]
    span = f1 - f0
    # A flat step (span 0) can only be hit when p equals its value: take the later sample.
    w = np.where(span > 0.0, (p_arr - f0) / np.where(span > 0.0, span, 1.0), 1.0)
    w = np.clip(w, 0.0, 1.0)
    t = (k - 1 + w) * dt
    t = np.where(p_arr <= frac[0], 0.0, t)
    return float(t) if t.ndim == 0 else t


def time_at_fraction(a: ArrayLike, dt: float, p: ArrayLike) -> float | NDArray[np.float64]:
    """Time t_p [s] at which the Husid function of ``a`` first reaches ``p``·Ia.

    Parameters
    ----------
    a : array_like
        Ground acceleration [m/s²], 1-D.
    dt : float
        Time step [s], > 0.
    p : float or array_like
        Fractions in [0, 1].

    Returns
    -------
    float or numpy.ndarray
        t_p [s] measured from the first sample, linearly interpolated between samples.
    """
    return times_from_husid(husid(a, dt), dt, p)


def significant_duration(a: ArrayLike, dt: float, lo: float = 0.05, hi: float = 0.95) -> float:
    """Significant duration t_hi − t_lo [s]; the default is D5-95.

    Parameters
    ----------
    a : array_like
        Ground acceleration [m/s²], 1-D.
    dt : float
        Time step [s], > 0.
    lo, hi : float
        Fractions of the total Arias intensity, 0 ≤ lo < hi ≤ 1.
    """
    if not 0.0 <= lo < hi <= 1.0:
        raise ValueError(f"need 0 <= lo < hi <= 1, got lo={lo!r}, hi={hi!r}")
    t_lo, t_hi = time_at_fraction(a, dt, [lo, hi])
    return float(t_hi - t_lo)


def t_mid(a: ArrayLike, dt: float) -> float:
    """Middle of strong shaking t_0.45 [s] (Rezaeian & Der Kiureghian), from the first sample."""
    return float(time_at_fraction(a, dt, 0.45))
