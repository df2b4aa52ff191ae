"""Time-varying filter of the Rezaeian–Der Kiureghian model and its normalized impulse response.

The filter is the pseudo-acceleration of a linear oscillator whose frequency ω_f(τ) is
attached to the time τ of the white-noise pulse:

    h(t − τ) = ω_f(τ)/√(1 − ζ²) · exp[−ζ ω_f(τ)(t − τ)] · sin[ω_f(τ) √(1 − ζ²) (t − τ)],  t ≥ τ

On a grid t_k = kΔt the discretized, normalized process is x = S u with
S[k, i] = h(t_k − t_i; ω_f(t_i)) / √(Σ_{j≤k} h²(t_k − t_j; ω_f(t_j))), lower triangular, each
column built with the frequency of its own pulse. Every row of S has unit norm, so the
process has unit variance at every sample. h decays like exp(−ζ ω_f τ), so S is stored as a
band of lags ℓ = k − i < w.

Extension (spectrum-matched identification): the oscillator may be followed by a
time-invariant low-frequency filter s²/(s² + 2ζ_low ω_low s + ω_low²) (the second filter of
Clough & Penzien, used by later models of this family), which replaces the flat long-period
plateau of the oscillator by an ω⁴ roll-off. The cascade's impulse response is a sum of two
damped complex exponentials (:func:`filter_poles`), normalized the same way.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray

from rocking._validate import finite, nonnegative_finite, positive_finite, positive_finite_array

#: Default floor of the filter frequency [Hz] (the SimCenter Dabaghi–Der Kiureghian value):
#: a linear ω_f with a negative slope would otherwise reach zero on long records.
DEFAULT_FLOOR_HZ = 0.3


def check_zeta(zeta: float) -> float:
    """Return ζ as a float or raise ValueError unless 0 < ζ < 1."""
    z = finite("zeta_f", zeta)
    if not 0.0 < z < 1.0:
        raise ValueError(f"zeta_f must be in (0, 1), got {zeta!r}")
    return z


def omega_f(
    t: ArrayLike,
    f_mid: float,
    f_slope: float,
    t_mid: float,
    hold: tuple[float, float] | None = None,
    floor_hz: float = DEFAULT_FLOOR_HZ,
) -> NDArray[np.float64]:
    """Filter frequency ω_f(t) = 2π[f_mid + f′ (t − t_mid)] with hold and floor [rad/s].

    Parameters
    ----------
    t : array_like
        Times [s].
    f_mid : float
        Filter frequency at t_mid [Hz], > 0.
    f_slope : float
        Its rate of change f′ [Hz/s].
    t_mid : float
        Reference time [s].
    hold : (float, float) or None
        (t_start, t_end) [s]: outside this window ω_f is held at its end values (the window
        over which the line was fitted, t_0.01 … t_0.99). None: no hold.
    floor_hz : float
        Lower bound of the frequency [Hz], ≥ 0.

    Returns
    -------
    numpy.ndarray
        ω_f [rad/s], same shape as ``t``.
    """
    f_mid = positive_finite("f_mid", f_mid)
    f_slope = finite("f_slope", f_slope)
    t_mid = finite("t_mid", t_mid)
    floor_hz = nonnegative_finite("floor_hz", floor_hz)
    t = np.asarray(t, dtype=np.float64)
    if hold is not None:
        t0, t1 = finite("hold[0]", hold[0]), finite("hold[1]", hold[1])
        if not t0 < t1:
            raise ValueError(f"hold must be an increasing pair of times, got {hold!r}")
        t = np.clip(t, t0, t1)
    f = np.maximum(f_mid + f_slope * (t - t_mid), floor_hz)
    if np.any(f <= 0.0):
        raise ValueError(
            f"the filter frequency reaches {f.min()!r} Hz <= 0: give a positive floor_hz"
        )
    return 2.0 * math.pi * f


def impulse_response(tau: ArrayLike, omega: ArrayLike, zeta: float) -> NDArray[np.float64]:
    """Pseudo-acceleration impulse response h(τ; ω, ζ) [rad/s] of the filter, 0 for τ < 0.

    Parameters
    ----------
    tau : array_like
        Lag t − τ [s].
    omega : array_like
        Filter frequency [rad/s] (broadcast against ``tau``).
    zeta : float
        Damping ratio, 0 < ζ < 1.
    """
    zeta = check_zeta(zeta)
    tau = np.asarray(tau, dtype=np.float64)
    omega = np.asarray(omega, dtype=np.float64)
    c = math.sqrt(1.0 - zeta * zeta)
    s = np.maximum(tau, 0.0)
    h = omega / c * np.exp(-zeta * omega * s) * np.sin(omega * c * s)
    return np.where(tau >= 0.0, h, 0.0)


def check_low(low: tuple[float, float] | None) -> tuple[float, float] | None:
    """Return the low-frequency filter (ω_low [rad/s], ζ_low) as floats, or None.

    Raises ValueError unless ω_low > 0 and 0 < ζ_low < 1 (complex poles).
    """
    if low is None:
        return None
    try:
        w_low, z_low = low
    except (TypeError, ValueError):
        raise ValueError(f"low must be None or (omega_low, zeta_low), got {low!r}") from None
    w_low = positive_finite("omega_low", w_low)
    z_low = finite("zeta_low", z_low)
    if not 0.0 < z_low < 1.0:
        raise ValueError(f"zeta_low must be in (0, 1), got {z_low!r}")
    return w_low, z_low


def filter_poles(
    omega: ArrayLike, zeta: float, low: tuple[float, float] | None = None
) -> tuple[NDArray[np.complex128], NDArray[np.complex128]]:
    """Residues c and poles p of the filter: h(τ) = 2 Re Σ_k c_k exp(p_k τ) for τ ≥ 0.

    Without ``low`` the filter is the RDK oscillator H(s) = ω_f²/(s² + 2ζω_f s + ω_f²) (one
    conjugate pole pair). With ``low = (ω_low, ζ_low)`` it is followed by the low-frequency
    (Clough–Penzien) filter s²/(s² + 2ζ_low ω_low s + ω_low²), which removes the flat
    long-period plateau of the oscillator: |H|² falls as ω⁴ below ω_low (two pole pairs).
    See docs/design.md (ground-motion ensembles).

    Parameters
    ----------
    omega : array_like, shape (n,)
        Filter frequency ω_f of each pulse [rad/s], > 0.
    zeta : float
        Filter damping ratio ζ_f, 0 < ζ_f < 1.
    low : (float, float) or None
        (ω_low [rad/s], ζ_low) of the low-frequency filter.

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        c and p, complex, shape (n, K) with K = 1 (no ``low``) or 2.
    """
    zeta = check_zeta(zeta)
    low = check_low(low)
    w = np.atleast_1d(np.asarray(omega, dtype=np.float64))
    p1 = w * (-zeta + 1j * math.sqrt(1.0 - zeta * zeta))
    if low is None:
        return (w * w / (p1 - p1.conj()))[:, None], p1[:, None]
    w_low, z_low = low
    p2 = np.full_like(p1, w_low * (-z_low + 1j * math.sqrt(1.0 - z_low * z_low)))
    if np.any(np.abs(p1 - p2) <= 1e-6 * np.abs(p1)):
        raise ValueError(
            f"the low-frequency filter (omega_low={w_low!r} rad/s, zeta_low={z_low!r}) "
            "coincides with the filter: its poles must differ"
        )
    # Partial fractions of ω_f² s² / [(s − p1)(s − p̄1)(s − p2)(s − p̄2)], with products and
    # quotients written out in real arithmetic: numpy's complex multiply and divide loops
    # use FMA on some CPUs and not on others, which changed the motions' last bits.
    ww = w * w
    c1 = _cdiv(ww * _cmul(p1, p1), _cmul(_cmul(p1 - p1.conj(), p1 - p2), p1 - p2.conj()))
    c2 = _cdiv(ww * _cmul(p2, p2), _cmul(_cmul(p2 - p2.conj(), p2 - p1), p2 - p1.conj()))
    return np.stack([c1, c2], axis=1), np.stack([p1, p2], axis=1)


def _cmul(a: NDArray[np.complex128], b: NDArray[np.complex128]) -> NDArray[np.complex128]:
    """a·b by real multiplies and adds (each one correctly rounded on every CPU)."""
    return (a.real * b.real - a.imag * b.imag) + 1j * (a.real * b.imag + a.imag * b.real)


def _cdiv(a: NDArray[np.complex128], b: NDArray[np.complex128]) -> NDArray[np.complex128]:
    """a/b = a·b̄/|b|² by real operations (see :func:`_cmul`); |b| is far from 0 and ∞ here."""
    den = b.real * b.real + b.imag * b.imag
    return ((a.real * b.real + a.imag * b.imag) / den) + 1j * ((a.imag * b.real
                                                               - a.real * b.imag) / den)


def unit_psd(
    f_hz: ArrayLike,
    omega: ArrayLike,
    zeta: float,
    dt: float,
    low: tuple[float, float] | None = None,
) -> NDArray[np.float64]:
    """One-sided power spectral density of the sampled filter's unit-variance output [1/Hz].

    For the impulse response sampled at the simulation step, h_ℓ = h(ℓΔt), the stationary
    output of white noise normalized to unit variance has the one-sided density
    φ(f) = 2Δt |Σ_ℓ h_ℓ e^(−2πifℓΔt)|² / Σ_ℓ h_ℓ², so that ∫₀^(1/2Δt) φ df = 1. Both sums are
    geometric series in the poles z = exp(pΔt) and are evaluated in closed form. This is
    the spectrum of the discrete-time process the time-domain method simulates (including
    the aliased high-frequency content of the sampled response).

    Parameters
    ----------
    f_hz : array_like, shape (m,)
        Frequencies [Hz], 0 ≤ f ≤ 1/(2Δt).
    omega : array_like, shape (n,)
        Filter frequencies ω_f [rad/s] (one spectrum per value).
    zeta : float
        Filter damping ratio.
    dt : float
        Time step [s].
    low : (float, float) or None
        Low-frequency filter (ω_low [rad/s], ζ_low), see :func:`filter_poles`.

    Returns
    -------
    numpy.ndarray, shape (n, m)
        φ(f) [1/Hz].
    """
    dt = positive_finite("dt", dt)
    c, p = filter_poles(omega, zeta, low)
    # All poles: each pair (c, p) and its conjugate, so h_ℓ = Σ_a C_a Z_a^ℓ is real.
    cc = np.concatenate([c, c.conj()], axis=1)
    zz = np.exp(np.concatenate([p, p.conj()], axis=1) * dt)
    norm = np.real(np.sum(cc[:, :, None] * cc[:, None, :]
                          / (1.0 - zz[:, :, None] * zz[:, None, :]), axis=(1, 2)))
    e = np.exp(-2j * math.pi * np.asarray(f_hz, dtype=np.float64) * dt)
    dtft = np.sum(cc[:, None, :] / (1.0 - zz[:, None, :] * e[None, :, None]), axis=2)
    return 2.0 * dt * np.abs(dtft) ** 2 / norm[:, None]


def band_width(
    omega: ArrayLike,
    zeta: float,
    dt: float,
    band_tol: float,
    npts: int,
    low: tuple[float, float] | None = None,
) -> int:
    """Number of lags w kept in the band: h has decayed to ``band_tol`` of its scale at w·Δt.

    The envelope of h decays like exp(−ζ ω τ) for each pole pair; the slowest decay is that
    of the smallest ω_f or of the low-frequency filter.
    """
    zeta = check_zeta(zeta)
    dt = positive_finite("dt", dt)
    band_tol = positive_finite("band_tol", band_tol)
    if band_tol >= 1.0:
        raise ValueError(f"band_tol must be < 1, got {band_tol!r}")
    decay = zeta * float(np.min(omega))
    low = check_low(low)
    if low is not None:
        decay = min(decay, low[0] * low[1])
    tau_max = math.log(1.0 / band_tol) / decay
    return int(min(npts, math.ceil(tau_max / dt) + 1))


@dataclass(frozen=True)
class NormalizedIRF:
    """Band storage of the normalized impulse-response matrix S (sub-diagonals of S).

    Attributes
    ----------
    diagonals : numpy.ndarray, shape (w, n)
        diagonals[ℓ, i] = S[i + ℓ, i]: the normalized response at t_{i+ℓ} to the pulse at
        t_i (0 where i + ℓ ≥ n). This is scipy's DIA layout for offsets 0, −1, …, −(w−1).
        Row k of S has unit norm for k ≥ 1; row 0 is zero (x̂(t_0) = 0 because h(0) = 0).
    dt : float
        Time step [s].
    """

    diagonals: NDArray[np.float64]
    dt: float

    @property
    def npts(self) -> int:
        """Number of time samples n."""
        return int(self.diagonals.shape[1])

    @property
    def width(self) -> int:
        """Number of lags w stored."""
        return int(self.diagonals.shape[0])

    def to_sparse(self) -> sp.dia_array:
        """S as a sparse (n, n) matrix in DIA format (no copy of the band)."""
        n, w = self.npts, self.width
        return sp.dia_array((self.diagonals, -np.arange(w)), shape=(n, n))

    def to_dense(self) -> NDArray[np.float64]:
        """S as a dense (n, n) array (for checks on short grids)."""
        return self.to_sparse().toarray()

    def apply(self, noise: ArrayLike) -> NDArray[np.float64]:
        """S @ noise for noise of shape (n,) or (n, m): one product for all realizations."""
        u = np.asarray(noise, dtype=np.float64)
        if u.shape[0] != self.npts:
            raise ValueError(f"noise must have {self.npts} rows (samples), got shape {u.shape}")
        return self.to_sparse() @ u


def normalized_irf(
    omega: ArrayLike,
    zeta: float,
    dt: float,
    band_tol: float = 1e-8,
    low: tuple[float, float] | None = None,
) -> NormalizedIRF:
    """Normalized impulse-response matrix S of the discretized RDK process, as a band.

    Parameters
    ----------
    omega : array_like, shape (n,)
        Filter frequency ω_f(t_i) at each pulse time t_i = iΔt [rad/s], > 0.
    zeta : float
        Filter damping ratio, 0 < ζ < 1.
    dt : float
        Time step [s], > 0.
    band_tol : float
        Lags where the slowest pole's decay exp(−ζ ω τ) < band_tol are dropped (the
        normalization is computed over the kept band, so rows still have exactly unit norm).
    low : (float, float) or None
        Low-frequency filter (ω_low [rad/s], ζ_low) in cascade with the oscillator, see
        :func:`filter_poles`; it is time-invariant, the oscillator follows the pulse time.

    Returns
    -------
    NormalizedIRF
    """
    omega = np.asarray(omega, dtype=np.float64)
    if omega.ndim != 1 or omega.size < 2:
        raise ValueError(f"omega must be a 1-D array of >= 2 samples, got shape {omega.shape}")
    positive_finite_array("omega", omega)
    zeta = check_zeta(zeta)
    dt = positive_finite("dt", dt)
    w = band_width(omega, zeta, dt, band_tol, omega.size, low)
    c, p = filter_poles(omega, zeta, low)
    return NormalizedIRF(_normalized_pole_diagonals(2.0 * c, np.exp(p * dt), w), dt)


@numba.njit(cache=True)
def _normalize_rows(diag):  # pragma: no cover - compiled
    """Divide the band in place by the norms of the rows of S (row k: lags ℓ of column k − ℓ)."""
    w, n = diag.shape
    s2 = np.zeros(n)
    for ell in range(w):
        for i in range(n - ell):
            s2[i + ell] += diag[ell, i] * diag[ell, i]
    inv = np.zeros(n)
    for k in range(n):
        # Row 0 is 0/0 (h(0) = 0): x̂(t_0) is defined as 0, so it stays a zero row.
        if s2[k] > 0.0:
            inv[k] = 1.0 / math.sqrt(s2[k])
    for ell in range(w):
        for i in range(n - ell):
            diag[ell, i] *= inv[i + ell]


@numba.njit(cache=True)
def _normalized_pole_diagonals(c2, z, w):  # pragma: no cover - compiled
    """diag[ℓ, i] = Re Σ_k c2[i, k] z[i, k]^ℓ / ‖row i+ℓ of S‖.

    Column i of S is the sampled impulse response of the filter of pulse i, a sum of damped
    complex exponentials z^ℓ with z = exp(pΔt) (``c2`` holds twice the residues, so the real
    part is the response). All columns advance one lag at a time (z^ℓ ← z^(ℓ−1)·z), so each
    entry costs one complex product per pole pair instead of an exp and a sin, memory is
    written contiguously, and the rounding error grows only like ℓ·eps.
    """
    n, npairs = c2.shape
    diag = np.zeros((w, n))
    pw = np.ones((n, npairs), dtype=np.complex128)
    for ell in range(1, w):
        for i in range(n - ell):
            acc = 0.0
            for k in range(npairs):
                pw[i, k] *= z[i, k]
                acc += (c2[i, k] * pw[i, k]).real
            diag[ell, i] = acc
    _normalize_rows(diag)
    return diag
