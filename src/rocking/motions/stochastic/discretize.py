"""The Rezaeian–Der Kiureghian process discretized, for many realizations at once.

Two discretizations of the same model (docs/equations.md, "The RDK model"):

- :func:`time_domain` (default, RDK 2008/2010): x̂ = diag(q) · S · U with the banded,
  row-normalized impulse-response matrix S (filter frequency attached to the pulse time);
  the realizations are the columns of U, so an ensemble is one sparse-band product.
- :func:`spectral` (Broccardo & Der Kiureghian 2014): a sum of K cosines and sines whose
  amplitudes follow the unit-variance evolutionary spectrum |H(ω; ω_f(t), ζ_f)|² at the
  response time t.

Both take the standard-normal noise as an argument, so the caller owns the random streams
(:mod:`rocking.motions.stochastic.pairs` draws one independent stream per component and
realization). Both give E[x̂²(t)] = q²(t) exactly and return an array of shape (m, n):
one realization per row, time along the last axis.

Parameters with a second filtered process (:class:`~rocking.motions.stochastic.params.RDKParams`)
take the noise of both processes stacked: the rows of process 1, then those of process 2
(:func:`noise_rows` gives the total), and x̂ = q (√(1 − s₂) z₁ + √s₂ z₂) with independent
unit-variance z₁, z₂.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocking._validate import positive_finite
from rocking.motions.stochastic.filter import DEFAULT_FLOOR_HZ, normalized_irf, unit_psd
from rocking.motions.stochastic.params import RDKParams

#: Corner of the post-processing high-pass used by RDK (2010) [Hz]. For the Vassiliou et al.
#: reproduction pass the Brune corner instead (``rocking.motions.highpass.brune_corner``).
DEFAULT_FC_HZ = 0.2

#: Upper bound on the number of (time × frequency) entries of one block of the spectral
#: sum: it caps the memory at ~16 MB per temporary array whatever the record length.
_SPECTRAL_BLOCK = 2_000_000


def _grid(dt: float, npts: int) -> tuple[float, int]:
    dt = positive_finite("dt", dt)
    if int(npts) != npts or npts < 3:
        raise ValueError(f"npts must be an integer >= 3, got {npts!r}")
    return dt, int(npts)


def _noise(noise: ArrayLike, rows: int, what: str) -> NDArray[np.float64]:
    u = np.asarray(noise, dtype=np.float64)
    if u.ndim == 1:
        u = u[:, None]
    if u.ndim != 2 or u.shape[0] != rows:
        raise ValueError(f"noise must have shape ({rows}, m) for {what}, got {u.shape}")
    if not np.all(np.isfinite(u)):
        raise ValueError("noise has non-finite values")
    return u


def _realizations(x: NDArray[np.float64], params: RDKParams, t: NDArray[np.float64],
                  modulate: bool) -> NDArray[np.float64]:
    """One realization per row of the (time, realization) sum ``x``, times q(t) if ``modulate``."""
    if modulate:
        x *= params.envelope(t)[:, None]
    return np.ascontiguousarray(x.T)


def noise_rows(
    params: RDKParams,
    dt: float,
    npts: int,
    method: Literal["time", "spectral"] = "time",
    f_max_hz: float | None = None,
) -> int:
    """Standard normals per realization needed by :func:`time_domain` or :func:`spectral`."""
    n_terms = 2 if params.f_mid2 is not None else 1
    if method == "time":
        return n_terms * _grid(dt, npts)[1]
    if method == "spectral":
        return n_terms * 2 * spectral_frequencies(dt, npts, f_max_hz).size
    raise ValueError(f"method must be 'time' or 'spectral', got {method!r}")


def time_domain(
    params: RDKParams,
    dt: float,
    npts: int,
    noise: ArrayLike,
    *,
    modulate: bool = True,
    floor_hz: float = DEFAULT_FLOOR_HZ,
    band_tol: float = 1e-8,
) -> NDArray[np.float64]:
    """Realizations of the time-domain discretized RDK process (Rezaeian & Der Kiureghian 2008).

    Parameters
    ----------
    params : RDKParams
        Model parameters of the component.
    dt : float
        Time step [s], > 0.
    npts : int
        Number of samples (t_k = kΔt, k = 0 … n−1).
    noise : array_like, shape (rows, m)
        Independent standard normals, one column per realization; rows = npts per filtered
        process (:func:`noise_rows`).
    modulate : bool
        False gives the unit-variance normalized process y/σ_y (q ≡ 1), used to identify ζ_f.
    floor_hz : float
        Floor of the filter frequency [Hz].
    band_tol : float
        Relative decay of the impulse response beyond which lags are dropped.

    Returns
    -------
    numpy.ndarray, shape (m, npts)
        Accelerations [m/s²] (dimensionless when ``modulate`` is False); x̂(t_0) = 0.
    """
    dt, npts = _grid(dt, npts)
    u = _noise(noise, noise_rows(params, dt, npts), "the time-domain method")
    t = np.arange(npts) * dt
    x = np.zeros((npts, u.shape[1]))
    for k, (share, omega, zeta) in enumerate(params.terms(t, floor_hz)):
        s = normalized_irf(omega, zeta, dt, band_tol, params.low)
        x += math.sqrt(share) * s.apply(u[k * npts : (k + 1) * npts])
    return _realizations(x, params, t, modulate)


def spectral_frequencies(
    dt: float, npts: int, f_max_hz: float | None = None
) -> NDArray[np.float64]:
    """Frequencies ω_j = (j − ½)Δω ≤ ω_max of the spectral method [rad/s].

    Δω = 2π/(nΔt) (the record's Fourier resolution) and ω_max = π/Δt (Nyquist) unless
    ``f_max_hz`` is lower; the sum is then periodic with 2nΔt, twice the record length.
    """
    dt, npts = _grid(dt, npts)
    w_max = math.pi / dt
    if f_max_hz is not None:
        w_max = min(w_max, 2.0 * math.pi * positive_finite("f_max_hz", f_max_hz))
    dw = 2.0 * math.pi / (npts * dt)
    k = int(math.floor(w_max / dw + 0.5))
    if k < 2:
        raise ValueError(f"f_max_hz = {f_max_hz!r} leaves fewer than 2 frequencies")
    return (np.arange(1, k + 1) - 0.5) * dw


def spectral(
    params: RDKParams,
    dt: float,
    npts: int,
    noise: ArrayLike,
    *,
    modulate: bool = True,
    floor_hz: float = DEFAULT_FLOOR_HZ,
    f_max_hz: float | None = None,
    fc_hz: float | None = None,
    filter_psd: Literal["discrete", "continuous"] = "discrete",
) -> NDArray[np.float64]:
    """Realizations of the spectral-representation form of the RDK process (Broccardo & Der
    Kiureghian 2014).

    x(t) = q(t) Σ_j a_j(t) [u_j cos ω_j t + v_j sin ω_j t],  a_j(t)² = |H_j(t)|² / Σ_i |H_i(t)|²

    which is the Broccardo–Der Kiureghian sum √(2Φ(ω_j, t)Δω) with Φ normalized so that
    2ΣΦΔω = 1 (Δω cancels). The filter frequency follows the response time t. A second
    filtered process adds its own sum, weighted by √s₂, with its own noise.

    With ``filter_psd="discrete"`` (default) |H_j|² is the spectrum of the *sampled* impulse
    response h(ℓΔt) used by :func:`time_domain`, so both methods share the same
    discrete-time process: the count of positive minima and negative maxima, from which
    ζ_f is identified at the record's Δt (Rezaeian & Der Kiureghian 2008), is then the same
    for both. The
    continuous |H(ω)|² (``"continuous"``, Broccardo & Der Kiureghian's form) lacks the
    aliased high-frequency content and gives ~25 % fewer PM+NM at Δt = 0.01 s, so an
    ensemble built with it would not reproduce the record's count.

    Parameters
    ----------
    params : RDKParams
        Model parameters of the component.
    dt : float
        Time step [s], > 0.
    npts : int
        Number of samples.
    noise : array_like, shape (rows, m)
        Independent standard normals: per filtered process, K rows of u_j then K rows of
        v_j, with K the length of :func:`spectral_frequencies` (dt, npts, f_max_hz)
        (:func:`noise_rows`).
    modulate : bool
        False gives the unit-variance process (q ≡ 1).
    floor_hz : float
        Floor of the filter frequency [Hz].
    f_max_hz : float or None
        Highest frequency of the sum [Hz]; default Nyquist.
    fc_hz : float or None
        If given, the Brune factor ω⁴/(ω² + ω_c²)² (ω_c = 2π fc_hz) multiplies |H|² before the
        normalization (the high-pass shape inside Φ; the time-domain post-filter is still
        needed for zero residual velocity).
    filter_psd : {"discrete", "continuous"}
        Spectrum of the sampled impulse response (default) or of the continuous filter.

    Returns
    -------
    numpy.ndarray, shape (m, npts)
        Accelerations [m/s²] (dimensionless when ``modulate`` is False).
    """
    dt, npts = _grid(dt, npts)
    w = spectral_frequencies(dt, npts, f_max_hz)
    nk = w.size
    u = _noise(noise, noise_rows(params, dt, npts, "spectral", f_max_hz), "the spectral method")
    brune = 1.0
    if fc_hz is not None:
        wc2 = (2.0 * math.pi * positive_finite("fc_hz", fc_hz)) ** 2
        brune = w**4 / (w * w + wc2) ** 2
    if filter_psd not in ("discrete", "continuous"):
        raise ValueError(f"filter_psd must be 'discrete' or 'continuous', got {filter_psd!r}")
    t = np.arange(npts) * dt
    x = np.zeros((npts, u.shape[1]))
    rows = max(1, _SPECTRAL_BLOCK // nk)
    for k, (share, wf, zeta) in enumerate(params.terms(t, floor_hz)):
        uk, vk = u[2 * k * nk : (2 * k + 1) * nk], u[(2 * k + 1) * nk : (2 * k + 2) * nk]
        for start in range(0, npts, rows):
            sl = slice(start, min(npts, start + rows))
            if filter_psd == "discrete":
                h2 = unit_psd(w / (2.0 * math.pi), wf[sl], zeta, dt, params.low) * brune
            else:
                h2 = _continuous_gain2(wf[sl, None], zeta, w, params.low) * brune
            amp = np.sqrt(share * h2 / h2.sum(axis=1, keepdims=True))
            phase = t[sl, None] * w
            x[sl] += (amp * np.cos(phase)) @ uk + (amp * np.sin(phase)) @ vk
    return _realizations(x, params, t, modulate)


def _continuous_gain2(wf, zeta, w, low):
    """|H(ω)|² of the continuous filter: ω_f⁴ / [(ω_f² − ω²)² + 4ζ²ω_f²ω²] × |H_low(ω)|²."""
    wf2 = wf * wf
    h2 = wf2 * wf2 / ((wf2 - w * w) ** 2 + 4.0 * zeta * zeta * wf2 * w * w)
    if low is not None:
        wl2, zl = low[0] ** 2, low[1]
        h2 = h2 * w**4 / ((wl2 - w * w) ** 2 + 4.0 * zl * zl * wl2 * w * w)
    return h2
