"""Elastic response spectra by the exact piecewise-linear recurrence (Nigam & Jennings 1969).

A single-degree-of-freedom oscillator of period T and damping ratio ζ, at rest at the first
sample, is driven by the ground acceleration a_g taken as linear between samples:

    ü + 2ζω u̇ + ω² u = −a_g(t),   ω = 2π/T.

Over each step the solution is exact (Chopra, *Dynamics of Structures*, §5.2):

    u_{k+1} = A u_k + B u̇_k + C p_k + D p_{k+1}
    u̇_{k+1} = A′u_k + B′u̇_k + C′p_k + D′p_{k+1},       p = −a_g

so the only error is the linear interpolation of the record. The pseudo-acceleration is
PSA = ω² max_k |u_k| over the samples given (append zeros to include free vibration after the
record). The coefficients are computed once per period and the time loop is compiled with
numba, vectorized over records and periods.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from scipy import linalg

from rocking._validate import positive_finite

_SMALL_WDT = 1e-2
"""Below this ωΔt the coefficients come from the matrix exponential."""

__all__ = [
    "foh_coefficients",
    "nigam_jennings_coefficients",
    "pseudo_acceleration",
    "sdof_response",
    "spectral_displacement",
]


def _check_damping(damping: float) -> float:
    z = float(damping)
    if not math.isfinite(z) or z < 0.0 or z >= 1.0:
        raise ValueError(f"damping must be in [0, 1) (underdamped), got {damping!r}")
    return z


def _check_periods(periods) -> np.ndarray:
    T = np.atleast_1d(np.asarray(periods, dtype=np.float64))
    if T.ndim != 1 or T.size == 0:
        raise ValueError(f"periods must be a non-empty 1-D array, got shape {T.shape}")
    bad = np.flatnonzero(~np.isfinite(T) | (T < 0.0))
    if bad.size:
        raise ValueError(f"periods must be finite and >= 0 [s], got {T[bad[0]]!r} at {bad[0]}")
    return T


def _recurrence_inputs(periods, damping: float, dt: float,
                       hint: str = "") -> tuple[np.ndarray, float, float, np.ndarray]:
    """Checked periods T > 0 [s], damping ζ [-], step Δt [s] and ω = 2π/T [rad/s]."""
    T = _check_periods(periods)
    if np.any(T <= 0.0):
        raise ValueError("periods must be > 0 for the recurrence" + hint)
    z = _check_damping(damping)
    h = positive_finite("dt", dt)
    return T, z, h, 2.0 * np.pi / T


def nigam_jennings_coefficients(periods, damping: float, dt: float) -> np.ndarray:
    """Exact recurrence coefficients for each period.

    Parameters
    ----------
    periods : array_like
        Natural periods T > 0 [s].
    damping : float
        Damping ratio ζ in [0, 1) [-].
    dt : float
        Time step [s].

    Returns
    -------
    numpy.ndarray
        Shape (len(periods), 8): A, B, C, D, A′, B′, C′, D′ of the recurrence in the module
        notes (unit mass; C, D, C′, D′ multiply the force p = −a_g).
    """
    T, z, h, w = _recurrence_inputs(periods, damping, dt, "; T = 0 is handled as PGA")
    long = w * h < _SMALL_WDT
    if np.any(long):
        # The closed form subtracts terms of size 2ζ/(ωΔt): relative rounding error about
        # eps·2ζ/(ωΔt)³ (up to 2e-10 at ωΔt = 1e-2). Longer periods take the matrix exponential.
        out = np.empty((T.size, 8))
        out[long] = foh_coefficients(T[long], z, h)
        if np.any(~long):
            out[~long] = nigam_jennings_coefficients(T[~long], z, h)
        return out
    sq = math.sqrt(1.0 - z * z)
    wd = w * sq
    e = np.exp(-z * w * h)
    s = np.sin(wd * h)
    c = np.cos(wd * h)
    k = w * w
    r = z / sq
    A = e * (r * s + c)
    B = e * s / wd
    C = (2.0 * z / (w * h) + e * (((1.0 - 2.0 * z * z) / (wd * h) - r) * s
                                    - (1.0 + 2.0 * z / (w * h)) * c)) / k
    D = (1.0 - 2.0 * z / (w * h) + e * ((2.0 * z * z - 1.0) / (wd * h) * s
                                          + 2.0 * z / (w * h) * c)) / k
    Ap = -e * (w / sq) * s
    Bp = e * (c - r * s)
    Cp = (-1.0 / h + e * ((w / sq + z / (h * sq)) * s + c / h)) / k
    Dp = (1.0 - e * (r * s + c)) / (k * h)
    return np.stack([A, B, C, D, Ap, Bp, Cp, Dp], axis=1)


def foh_coefficients(periods, damping: float, dt: float) -> np.ndarray:
    """The recurrence coefficients from one matrix exponential per period (Van Loan).

    Same result as :func:`nigam_jennings_coefficients` (the exact first-order-hold
    discretization of the oscillator), computed without closed forms; used for very long
    periods, where the closed form loses digits, and to check it.

    Parameters
    ----------
    periods : array_like
        Natural periods T > 0 [s].
    damping : float
        Damping ratio ζ in [0, 1) [-].
    dt : float
        Time step [s].

    Returns
    -------
    numpy.ndarray
        Shape (len(periods), 8), ordered like :func:`nigam_jennings_coefficients`.
    """
    T, z, h, w = _recurrence_inputs(periods, damping, dt)
    # [[A, B, 0], [0, 0, 1/h], [0, 0, 0]]·h; state (u, u̇), input p = −a_g per unit mass.
    em = np.zeros((T.size, 4, 4))
    em[:, 0, 1] = h
    em[:, 1, 0] = -w * w * h
    em[:, 1, 1] = -2.0 * z * w * h
    em[:, 1, 2] = h
    em[:, 2, 3] = 1.0
    ms = linalg.expm(em)
    phi, m12, m13 = ms[:, :2, :2], ms[:, :2, 2], ms[:, :2, 3]
    gamma0, gamma1 = m12 - m13, m13
    return np.stack(
        [phi[:, 0, 0], phi[:, 0, 1], gamma0[:, 0], gamma1[:, 0],
         phi[:, 1, 0], phi[:, 1, 1], gamma0[:, 1], gamma1[:, 1]], axis=1,
    )  # fmt: skip


@numba.njit(cache=True, nogil=True)
def _peak_displacement(acc, coef, out):  # pragma: no cover - compiled
    """out[r, j] = max_k |u_k| for record r and period j (oscillator at rest at k = 0)."""
    n_rec, n = acc.shape
    n_per = coef.shape[0]
    for r in range(n_rec):
        for j in range(n_per):
            A, B, C, D = coef[j, 0], coef[j, 1], coef[j, 2], coef[j, 3]
            Ap, Bp, Cp, Dp = coef[j, 4], coef[j, 5], coef[j, 6], coef[j, 7]
            u = 0.0
            v = 0.0
            peak = 0.0
            p0 = -acc[r, 0]
            for k in range(1, n):
                p1 = -acc[r, k]
                u_new = A * u + B * v + C * p0 + D * p1
                v = Ap * u + Bp * v + Cp * p0 + Dp * p1
                u = u_new
                p0 = p1
                if abs(u) > peak:
                    peak = abs(u)
            out[r, j] = peak


@numba.njit(cache=True, nogil=True)
def _history(acc, coef, u_out, v_out):  # pragma: no cover - compiled
    A, B, C, D = coef[0], coef[1], coef[2], coef[3]
    Ap, Bp, Cp, Dp = coef[4], coef[5], coef[6], coef[7]
    u_out[0] = 0.0
    v_out[0] = 0.0
    for k in range(1, acc.size):
        p0 = -acc[k - 1]
        p1 = -acc[k]
        u_out[k] = A * u_out[k - 1] + B * v_out[k - 1] + C * p0 + D * p1
        v_out[k] = Ap * u_out[k - 1] + Bp * v_out[k - 1] + Cp * p0 + Dp * p1


def _records(acc) -> tuple[np.ndarray, bool]:
    a = np.asarray(acc, dtype=np.float64)
    single = a.ndim == 1
    a2 = np.atleast_2d(a)
    if a2.ndim != 2 or a2.shape[1] < 2:
        raise ValueError(f"acc must be 1-D or 2-D (rows = records) with >= 2 samples, "
                         f"got shape {a.shape}")
    bad = np.argwhere(~np.isfinite(a2))
    if bad.size:
        raise ValueError(f"acc has a non-finite value at index {tuple(int(i) for i in bad[0])}")
    return np.ascontiguousarray(a2), single


def spectral_displacement(acc, dt: float, periods, damping: float = 0.05) -> np.ndarray:
    """Peak relative displacement SD(T) [m] of damped oscillators at rest at the first sample.

    Parameters
    ----------
    acc : array_like
        Ground acceleration [m/s²], 1-D or 2-D (one record per row).
    dt : float
        Time step [s].
    periods : array_like
        Periods T >= 0 [s]; T = 0 gives SD = 0 (a rigid oscillator).
    damping : float
        Damping ratio ζ in [0, 1) [-]; 0.05 is the usual 5 %.

    Returns
    -------
    numpy.ndarray
        Shape (len(periods),) for 1-D input, else (n_records, len(periods)).
    """
    a, single = _records(acc)
    h = positive_finite("dt", dt)
    T = _check_periods(periods)
    z = _check_damping(damping)
    out = np.zeros((a.shape[0], T.size))
    pos = T > 0.0
    if np.any(pos):
        coef = np.ascontiguousarray(nigam_jennings_coefficients(T[pos], z, h))
        peaks = np.empty((a.shape[0], coef.shape[0]))
        _peak_displacement(a, coef, peaks)
        out[:, pos] = peaks
    return out[0] if single else out


def pseudo_acceleration(acc, dt: float, periods, damping: float = 0.05) -> np.ndarray:
    """Pseudo-spectral acceleration PSA(T) = ω² SD(T) [m/s²].

    Parameters
    ----------
    acc : array_like
        Ground acceleration [m/s²], 1-D or 2-D (one record per row).
    dt : float
        Time step [s].
    periods : array_like
        Periods T >= 0 [s]; T = 0 returns the PGA (the T → 0 limit).
    damping : float
        Damping ratio ζ in [0, 1) [-].

    Returns
    -------
    numpy.ndarray
        Shape (len(periods),) for 1-D input, else (n_records, len(periods)) [m/s²].
    """
    a, single = _records(acc)
    T = _check_periods(periods)
    sd = spectral_displacement(a, dt, T, damping)
    w2 = np.zeros_like(T)
    pos = T > 0.0
    w2[pos] = (2.0 * np.pi / T[pos]) ** 2
    psa = sd * w2
    # A rigid oscillator moves with the ground: its peak absolute acceleration is the PGA.
    psa[:, ~pos] = np.max(np.abs(a), axis=1)[:, None]
    return psa[0] if single else psa


def sdof_response(acc, dt: float, period: float, damping: float = 0.05):
    """Relative displacement and velocity history of one oscillator [m, m/s].

    Parameters
    ----------
    acc : array_like
        Ground acceleration [m/s²], 1-D.
    dt : float
        Time step [s].
    period : float
        Natural period T > 0 [s].
    damping : float
        Damping ratio ζ in [0, 1) [-].

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        u and u̇ at the samples, starting from rest.
    """
    a, single = _records(acc)
    if not single:
        raise ValueError(f"acc must be 1-D, got shape {np.shape(acc)}")
    T = positive_finite("period", period)
    coef = np.ascontiguousarray(nigam_jennings_coefficients([T], damping, dt)[0])
    u = np.empty(a.shape[1])
    v = np.empty(a.shape[1])
    _history(a[0], coef, u, v)
    return u, v
