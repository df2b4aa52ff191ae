"""Time-varying filter of the Rezaeian–Der Kiureghian model and its normalized impulse response.

The filter is the pseudo-acceleration of a linear oscillator whose frequency ω_f(τ) is
attached to the time τ of the white-noise pulse:

    h(t − τ) = ω_f(τ)/√(1 − ζ²) · exp[−ζ ω_f(τ)(t − τ)] · sin[ω_f(τ) √(1 − ζ²) (t − τ)],  t ≥ τ

On a grid t_k = kΔt the discretized, normalized process is x = S u with
S[k, i] = h(t_k − t_i; ω_f(t_i)) / √(Σ_{j≤k} h²(t_k − t_j; ω_f(t_j))), lower triangular, each
column built with the frequency of its own pulse. Every row of S has unit norm, so the
process has unit variance at every sample. h decays like exp(−ζ ω_f τ), so S is stored as a
band of lags ℓ = k − i < w.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray

from ..._validate import finite, nonnegative_finite, positive_finite

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


def band_width(omega: ArrayLike, zeta: float, dt: float, band_tol: float, npts: int) -> int:
    """Number of lags w kept in the band: h has decayed to ``band_tol`` of its scale at w·Δt.

    The envelope of h is exp(−ζ ω τ); the slowest decay is at the smallest ω_f.
    """
    zeta = check_zeta(zeta)
    dt = positive_finite("dt", dt)
    band_tol = positive_finite("band_tol", band_tol)
    if band_tol >= 1.0:
        raise ValueError(f"band_tol must be < 1, got {band_tol!r}")
    w_min = float(np.min(omega))
    tau_max = math.log(1.0 / band_tol) / (zeta * w_min)
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
    omega: ArrayLike, zeta: float, dt: float, band_tol: float = 1e-8
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
        Lags where exp(−ζ ω_f,min τ) < band_tol are dropped (the normalization is computed
        over the kept band, so rows still have exactly unit norm).

    Returns
    -------
    NormalizedIRF
    """
    omega = np.asarray(omega, dtype=np.float64)
    if omega.ndim != 1 or omega.size < 2:
        raise ValueError(f"omega must be a 1-D array of >= 2 samples, got shape {omega.shape}")
    if not np.all(np.isfinite(omega)) or np.any(omega <= 0.0):
        raise ValueError(f"omega must be positive and finite, got min {np.min(omega)!r}")
    zeta = check_zeta(zeta)
    dt = positive_finite("dt", dt)
    w = band_width(omega, zeta, dt, band_tol, omega.size)
    return NormalizedIRF(_normalized_diagonals(omega, zeta, dt, w), dt)


@numba.njit(cache=True)
def _normalized_diagonals(omega, zeta, dt, w):  # pragma: no cover - compiled
    """diag[ℓ, i] = h(ℓΔt; ω[i]) / ‖row i+ℓ of S‖.

    Column i of S is a damped sinusoid sampled on the grid: h(ℓΔt) = ω/√(1−ζ²)·Im z^ℓ with
    z = exp[(−ζω + iω√(1−ζ²))Δt]. All columns advance one lag at a time (p_i ← p_i z_i), so
    each entry costs one complex product instead of an exp and a sin, memory is written
    contiguously, and the rounding error grows only like ℓ·eps.
    """
    n = omega.size
    diag = np.zeros((w, n))
    c = math.sqrt(1.0 - zeta * zeta)
    amp = omega / c
    e = np.exp(-zeta * omega * dt)
    zr = e * np.cos(omega * c * dt)
    zi = e * np.sin(omega * c * dt)
    pr = np.ones(n)
    pi = np.zeros(n)
    for ell in range(1, w):
        for i in range(n - ell):
            r = pr[i] * zr[i] - pi[i] * zi[i]
            pi[i] = pr[i] * zi[i] + pi[i] * zr[i]
            pr[i] = r
            diag[ell, i] = amp[i] * pi[i]
    # Row norms of S: row k collects lag ℓ of the column i = k − ℓ.
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
    return diag
