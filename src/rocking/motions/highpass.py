"""High-pass filters for ground accelerations, the Brune corner frequency and residual checks.

Oscillator filter (Rezaeian & Der Kiureghian 2010)
    The acceleration x̂ drives a critically damped oscillator from rest,
    z̈ + 2ω_c ż + ω_c² z = x̂, and the output is a = z̈ = x̂ − 2ω_c ż − ω_c² z. The output's
    velocity and displacement are then exactly ż and z, which decay as (1 + ω_c t)e^(−ω_c t)
    once the input has ended, so zero padding of ≥ 25/ω_c after the record drives both
    residuals to zero. |a/x̂| = ω²/(ω² + ω_c²): the low-frequency shape of Brune's ω² source
    spectrum, which is why this is "the high-pass filter based on Brune's source model".
    The input is taken as linear between samples (first-order hold), and the exact
    discretization is applied with :func:`scipy.signal.lfilter` (batched over rows).

Acausal Butterworth
    Zero-phase :func:`scipy.signal.sosfiltfilt` of order 2N (the forward-backward pass squares
    the magnitude) after zero padding of 1.5·n/f_c in total, half on each side (Boore & Bommer
    2005), with n = 2N the order of the forward-backward cascade; the pads are kept. With
    n = N instead, El Centro filtered at 0.2 Hz keeps a residual displacement of 1.7 % of PGD;
    with n = 2N it is 3e-6.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from rocking._validate import positive_finite
from rocking.motions.motion import GroundMotion

__all__ = [
    "Residuals",
    "brune_corner",
    "butterworth_acausal",
    "butterworth_pad",
    "highpass_motion",
    "highpass_rows",
    "oscillator",
    "oscillator_pad",
    "oscillator_transfer",
    "residuals",
]


def brune_corner(mw: float, stress_bar: float = 50.0, beta_kms: float = 3.5) -> float:
    """Brune (1970) source corner frequency [Hz].

    f_c = 4.906·10⁶ β (Δσ/M₀)^(1/3) with M₀ = 10^(1.5 Mw + 16.05) dyne·cm.

    Parameters
    ----------
    mw : float
        Moment magnitude [-].
    stress_bar : float
        Stress drop Δσ [bar].
    beta_kms : float
        Shear-wave velocity at the source β [km/s].

    Returns
    -------
    float
        Corner frequency [Hz] (Imperial Valley 1940, Mw 6.95, 50 bar, 3.5 km/s: ≈ 0.095 Hz).
    """
    if not math.isfinite(float(mw)):
        raise ValueError(f"mw must be a finite number, got {mw!r}")
    dsigma = positive_finite("stress_bar", stress_bar)
    beta = positive_finite("beta_kms", beta_kms)
    m0 = 10.0 ** (1.5 * float(mw) + 16.05)
    return 4.906e6 * beta * (dsigma / m0) ** (1.0 / 3.0)


def oscillator_pad(fc_hz: float) -> float:
    """Default zero padding after the record for the oscillator filter, 25/ω_c [s]."""
    return 25.0 / (2.0 * math.pi * positive_finite("fc_hz", fc_hz))


def butterworth_pad(fc_hz: float, order: int) -> float:
    """Total zero padding for the acausal Butterworth filter of design order N, 3N/f_c [s].

    Boore & Bommer's 1.5·n/f_c with n = 2N, the order after the forward-backward pass.
    """
    return 1.5 * 2 * int(order) / positive_finite("fc_hz", fc_hz)


def oscillator_transfer(f_hz, fc_hz: float) -> np.ndarray:
    """Frequency response of the oscillator filter, H = (iω)²/(iω + ω_c)² [-].

    Parameters
    ----------
    f_hz : array_like
        Frequencies [Hz].
    fc_hz : float
        Corner frequency [Hz].

    Returns
    -------
    numpy.ndarray
        Complex response; |H| = ω²/(ω² + ω_c²).
    """
    wc = 2.0 * math.pi * positive_finite("fc_hz", fc_hz)
    s = 2j * math.pi * np.asarray(f_hz, dtype=np.float64)
    return s**2 / (s + wc) ** 2


def _as_signal(name: str, a) -> np.ndarray:
    x = np.asarray(a, dtype=np.float64)
    if x.ndim not in (1, 2) or x.shape[-1] < 2:
        raise ValueError(f"{name} must be 1-D or 2-D (rows = signals) with >= 2 samples, "
                         f"got shape {x.shape}")
    bad = np.argwhere(~np.isfinite(x))
    if bad.size:
        raise ValueError(f"{name} has a non-finite value at index {tuple(int(i) for i in bad[0])}")
    return x


def _below_nyquist(fc_hz: float, dt: float) -> float:
    """``fc_hz`` if it lies below the Nyquist frequency 1/(2 dt), else a ValueError naming it.

    At or above Nyquist no sampled frequency lies below the corner: the filter would
    remove (Butterworth) or reshape (oscillator) the whole record while looking like a
    high-pass, so the corner is refused for both kinds, before any filtering.
    """
    fc = positive_finite("fc_hz", fc_hz)
    nyquist = 0.5 / dt
    if fc >= nyquist:
        raise ValueError(f"fc_hz={fc_hz!r} must be below the Nyquist frequency {nyquist:g} Hz "
                         f"(time step {dt:g} s)")
    return fc


def _pad_seconds(pad: float | None, default: float) -> float:
    """Zero padding [s]: ``pad``, or the filter's ``default`` when None; finite and >= 0."""
    pad_s = default if pad is None else float(pad)
    if not math.isfinite(pad_s) or pad_s < 0.0:
        raise ValueError(f"pad must be a finite number >= 0 [s], got {pad!r}")
    return pad_s


def _foh_oscillator(dt: float, wc: float):
    """Exact first-order-hold discretization of the oscillator filter.

    State x = (z, ż). With a linear input between samples,
    x[k+1] = Φ x[k] + Γ₀ u[k] + Γ₁ u[k+1] (Φ, Γ₀, Γ₁ from one matrix exponential). The
    shifted state w = x − Γ₁u gives the standard form w[k+1] = Φ w[k] + (ΦΓ₁ + Γ₀ ) u[k],
    a[k] = C w[k] + (CΓ₁ + 1) u[k], which :func:`scipy.signal.lfilter` runs as b/a.
    """
    from scipy import linalg, signal  # imported when filtering: a dry run never is
    a_mat = np.array([[0.0, 1.0], [-wc * wc, -2.0 * wc]])
    b_vec = np.array([[0.0], [1.0]])
    c_vec = np.array([[-wc * wc, -2.0 * wc]])
    # Van Loan block exponential: [[A, B, 0], [0, 0, I/dt], [0, 0, 0]] * dt.
    em = np.zeros((4, 4))
    em[:2, :2] = a_mat * dt
    em[:2, 2:3] = b_vec * dt
    em[2, 3] = 1.0
    ms = linalg.expm(em)
    phi, m12, m13 = ms[:2, :2], ms[:2, 2:3], ms[:2, 3:4]
    gamma1 = m13
    gamma0 = m12 - m13
    bd = phi @ gamma1 + gamma0
    dd = c_vec @ gamma1 + 1.0
    num, den = signal.ss2tf(phi, bd, c_vec, dd)
    return num[0], den, phi, gamma1, c_vec


def oscillator(a, dt: float, fc_hz: float, pad: float | None = None) -> np.ndarray:
    """Critically damped oscillator high-pass (RDK 2010), zero padding kept.

    Parameters
    ----------
    a : array_like
        Acceleration(s) [m/s²], 1-D or 2-D with one signal per row.
    dt : float
        Time step [s].
    fc_hz : float
        Corner frequency f_c = ω_c/2π [Hz], below the Nyquist frequency 1/(2 dt).
    pad : float, optional
        Zero padding appended before filtering [s]; default 25/ω_c (residual velocity and
        displacement relative to PGV/PGD below 1e-8). 0 disables it.

    Returns
    -------
    numpy.ndarray
        Filtered acceleration [m/s²] with ``round(pad/dt)`` extra samples at the end. The
        oscillator starts from rest at the first sample (z = ż = 0 there).
    """
    from scipy import signal
    x = _as_signal("a", a)
    step = positive_finite("dt", dt)
    wc = 2.0 * math.pi * _below_nyquist(fc_hz, step)
    pad_s = _pad_seconds(pad, oscillator_pad(fc_hz))
    npad = int(round(pad_s / step))
    u = np.concatenate([x, np.zeros(x.shape[:-1] + (npad,))], axis=-1)
    num, den, phi, gamma1, c_vec = _foh_oscillator(step, wc)
    out = signal.lfilter(num, den, u, axis=-1)
    # lfilter starts from w = 0, i.e. x(0) = Γ₁u[0]; the oscillator starts from rest, x(0) = 0.
    # Add the free response of the 2-state system from w(0) = −Γ₁u[0]. Φ^k = e^(Ak·dt), and
    # for the double eigenvalue −ω_c: e^(At) = e^(−ω_c t)[I + (A + ω_c I)t].
    u0 = u[..., 0]
    if np.any(u0 != 0.0):
        t = np.arange(u.shape[-1]) * step
        a_shift = np.array([[wc, 1.0], [-wc * wc, -wc]])  # A + ω_c I
        w0 = -gamma1[:, 0]
        # two-term sums in Python, not ``@``: BLAS kernels (FMA or not) round them
        # differently, and these two numbers reach every sample
        c, aw0 = c_vec[0].tolist(), [math.fsum(r) for r in (a_shift * w0).tolist()]
        cw0 = math.fsum(ci * wi for ci, wi in zip(c, w0.tolist(), strict=True))
        caw0 = math.fsum(ci * wi for ci, wi in zip(c, aw0, strict=True))
        free = np.exp(-wc * t) * (cw0 + caw0 * t)
        out = out + u0[..., None] * free
    return out


def butterworth_acausal(
    a, dt: float, fc_hz: float, order: int = 4, pad: float | None = None
) -> tuple[np.ndarray, int]:
    """Zero-phase Butterworth high-pass with zero padding on both sides (kept).

    Parameters
    ----------
    a : array_like
        Acceleration(s) [m/s²], 1-D or 2-D with one signal per row.
    dt : float
        Time step [s].
    fc_hz : float
        Corner frequency [Hz] (−6 dB after the forward-backward pass).
    order : int
        Order N of the Butterworth design; the zero-phase result has order 2N.
    pad : float, optional
        Total zero padding [s], half before and half after; default 3N/f_c
        (:func:`butterworth_pad`).

    Returns
    -------
    (numpy.ndarray, int)
        Filtered acceleration (longer by the padding) and the number of samples added at the
        front (the original first sample sits at that index).
    """
    from scipy import signal
    x = _as_signal("a", a)
    step = positive_finite("dt", dt)
    fc = _below_nyquist(fc_hz, step)
    if int(order) != order or order < 1:
        raise ValueError(f"order must be a positive integer, got {order!r}")
    pad_s = _pad_seconds(pad, butterworth_pad(fc, int(order)))
    half = int(round(0.5 * pad_s / step))
    widths = [(0, 0)] * (x.ndim - 1) + [(half, half)]
    u = np.pad(x, widths)
    sos = signal.butter(int(order), fc, btype="highpass", fs=1.0 / step, output="sos")
    # padtype=None: the zero pads are the padding; odd extension would invent motion.
    return signal.sosfiltfilt(sos, u, axis=-1, padtype=None), half


class Residuals(NamedTuple):
    """End-of-record velocity and displacement of an acceleration (trapezoid rule).

    Attributes
    ----------
    v_end : float
        Final velocity [m/s].
    d_end : float
        Final displacement [m].
    pgv : float
        Peak |velocity| [m/s].
    pgd : float
        Peak |displacement| [m].
    """

    v_end: float
    d_end: float
    pgv: float
    pgd: float

    @property
    def v_rel(self) -> float:
        """|v_end| / PGV [-]."""
        return abs(self.v_end) / self.pgv if self.pgv > 0 else 0.0

    @property
    def d_rel(self) -> float:
        """|d_end| / PGD [-]."""
        return abs(self.d_end) / self.pgd if self.pgd > 0 else 0.0


def residuals(a, dt: float) -> Residuals:
    """Residual velocity and displacement of a 1-D acceleration from rest [m/s, m].

    Parameters
    ----------
    a : array_like
        Acceleration [m/s²].
    dt : float
        Time step [s].

    Returns
    -------
    Residuals
        v_end, d_end, PGV, PGD (trapezoid integration, starting from rest).
    """
    from scipy import integrate
    x = _as_signal("a", a)
    if x.ndim != 1:
        raise ValueError(f"a must be 1-D, got shape {x.shape}")
    step = positive_finite("dt", dt)
    v = integrate.cumulative_trapezoid(x, dx=step, initial=0.0)
    d = integrate.cumulative_trapezoid(v, dx=step, initial=0.0)
    return Residuals(float(v[-1]), float(d[-1]), float(np.max(np.abs(v))),
                     float(np.max(np.abs(d))))


def highpass_rows(
    a, dt: float, kind: str, fc_hz: float, order: int = 4, pad: float | None = None
) -> tuple[np.ndarray, int]:
    """High-pass every row of ``a`` with the filter named by ``kind``; the padding is kept.

    Parameters
    ----------
    a : array_like
        Acceleration(s) [m/s²], 1-D or one signal per row.
    dt : float
        Time step [s].
    kind : {"oscillator", "butterworth"}
        :func:`oscillator` (padding at the end) or :func:`butterworth_acausal` (both ends).
    fc_hz : float
        Corner frequency [Hz].
    order : int
        Butterworth order N (ignored by the oscillator).
    pad : float, optional
        Padding [s] (each filter's default when None).

    Returns
    -------
    (numpy.ndarray, int)
        Filtered signals and the number of samples added at the front.
    """
    if kind == "oscillator":
        return oscillator(a, dt, fc_hz, pad), 0
    if kind == "butterworth":
        return butterworth_acausal(a, dt, fc_hz, order, pad)
    raise ValueError(f"kind must be 'oscillator' or 'butterworth', got {kind!r}")


def highpass_motion(
    motion: GroundMotion,
    kind: str = "oscillator",
    fc_hz: float | None = None,
    order: int = 4,
    pad: float | None = None,
) -> GroundMotion:
    """High-pass both components of a motion (and the vertical one, alike, if present); the
    padding is kept.

    Parameters
    ----------
    motion : GroundMotion
        Input pair.
    kind : {"oscillator", "butterworth"}
        Filter type (see the module notes).
    fc_hz : float
        Corner frequency [Hz] (e.g. :func:`brune_corner`).
    order : int
        Butterworth order N (ignored by the oscillator).
    pad : float, optional
        Padding [s]; defaults 25/ω_c (oscillator, at the end) and 3N/f_c (Butterworth,
        half at each end).

    Returns
    -------
    GroundMotion
        Filtered pair; metadata gets a ``highpass`` processing step (kind, fc_hz, order,
        pad samples before/after, residual velocity and displacement of each component).
    """
    if fc_hz is None:
        raise ValueError("fc_hz is required (e.g. rocking.motions.highpass.brune_corner(mw))")
    rows = [motion.ax, motion.ay] + ([] if motion.az is None else [motion.az])
    out, front = highpass_rows(np.vstack(rows), motion.dt, kind, fc_hz, order, pad)
    info_order = int(order) if kind == "butterworth" else None
    res = [residuals(row, motion.dt) for row in out]
    step: dict[str, Any] = {
        "step": "highpass",
        "kind": kind,
        "fc_hz": float(fc_hz),
        "order": info_order,
        "pad_front": int(front),
        "pad_end": int(out.shape[-1] - motion.npts - front),
        "v_end": [r.v_end for r in res],
        "d_end": [r.d_end for r in res],
    }
    meta = dict(motion.metadata)
    meta["processing"] = [*meta.get("processing", []), step]
    meta["highpass"] = {k: step[k] for k in ("kind", "fc_hz", "order")}
    return GroundMotion(out[0], out[1], motion.dt, motion.name, meta,
                        None if motion.az is None else out[2])
