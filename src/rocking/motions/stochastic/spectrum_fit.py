"""Spectrum-matched identification of the extended RDK model (one component).

The count-based identification (:mod:`.fit`) matches the zero-crossing and extrema rates of
a record with one filter; for broad-band records such as El Centro that filter leaves the
ensemble's 5 %-damped spectrum a factor 2–3 below the record's at 0.5–4 s. Here the filter
parameters are chosen so that the ensemble's median pseudo-acceleration spectrum matches the
record's, keeping the model family (modulated, normalized, filtered white noise with a
time-varying filter frequency, high-passed):

- the envelope (Ia, D5-95, t_mid) is the record's, exactly as before;
- the filter frequency keeps the relative drift f′/f_mid measured from the zero-level
  up-crossings (:func:`.fit.fit_frequency`);
- the spectral shape has seven parameters (:class:`~.params.RDKParams`): two filtered
  processes sharing the envelope (f_mid, ζ_f; f_mid2, ζ_f2; variance share s₂) and one
  low-frequency filter (f_low, ζ_low).

Identification, two nested problems:

1. *Energy spectrum.* E[|X(f)|²] of the model is, for a slowly varying filter,
   ∫q² dt · Σ_k s_k φ_k(f) averaged over the energy distribution in time, with φ_k the
   unit-variance spectrum of process k (:func:`~.filter.unit_psd`, closed form). Its log is
   fitted to a target by bounded least squares over log-spaced frequency bands (milliseconds
   per evaluation, several starts).
   Fitted to the record's band-averaged energy spectral density, this gives the start.
2. *Response spectrum.* An ensemble of ``n_sim`` simulations (fixed seed: common random
   numbers, so the result is deterministic) is high-passed like the final ensemble; r(T),
   the log ratio of its geometric-mean PSA to the record's, is the misfit, and the objective
   is mean(r²) plus the squared mean of r over each band of :data:`.quality.BANDS`.
   It is minimized by Gauss–Newton steps whose Jacobian comes from the energy spectrum:
   PSA(T) grows like the square root of the energy spectrum near f = 1/T (random-vibration
   theory), so r(θ) ≈ r(θ_k) + ½[ln E_θ − ln E_θk](1/T), a problem of step 1's kind. A step
   that did not lower the objective is followed by a half step. The best iterate is kept.

See docs/design.md (ground-motion ensembles).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import optimize

from rocking._validate import finite_array, positive_finite
from rocking.constants import G
from rocking.motions.response_spectrum import pseudo_acceleration
from rocking.motions.stochastic.discretize import noise_rows, time_domain
from rocking.motions.stochastic.filter import DEFAULT_FLOOR_HZ, unit_psd
from rocking.motions.stochastic.params import RDKParams
from rocking.motions.stochastic.quality import BANDS

#: Periods at which the ensemble's median PSA is matched [s] (log-spaced; the bands that
#: matter for rocking, 0.1–4 s, with a margin on both sides).
FIT_PERIODS: NDArray[np.float64] = np.geomspace(1.0 / 12.0, 5.0, 25)

#: Damping ratio of the matched response spectrum [-].
DAMPING = 0.05

#: Bounds of θ = (ln f_mid, ζ_f, ln(f_mid2/f_mid), ζ_f2, s₂, ln f_low, ζ_low): frequencies in
#: Hz; the second process is the lower-frequency one (f_mid2 ≤ f_mid), which removes the
#: symmetry of the sum.
_LOWER = np.array([math.log(0.3), 0.02, math.log(0.03), 0.02, 0.01, math.log(0.02), 0.2])
_UPPER = np.array([math.log(25.0), 0.95, 0.0, 0.95, 0.99, math.log(3.0), 0.95])

#: Starting ratios f_mid2/f_mid of the multi-start least squares (the ratio is the parameter
#: with separated local minima: which spectral peak the second process takes).
_START_RATIOS = (0.15, 0.3, 0.6)

#: Largest log misfit a Gauss–Newton step tries to remove at one period [-]: a jagged record
#: can ask for more than any smooth spectrum can give.
_MAX_STEP = 0.5

#: Time samples (equal shares of the expected energy) and sub-frequencies per band of the
#: model's energy spectrum.
_N_TIME, _N_SUB = 24, 3


def band_edges(f_centres: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Lower and upper edges [Hz] of log-spaced bands around increasing centres [Hz]."""
    f = np.asarray(f_centres, dtype=np.float64)
    if f.ndim != 1 or f.size < 2 or np.any(f <= 0) or np.any(np.diff(f) <= 0):
        raise ValueError(f"band centres must be > 0 and increasing, got {f!r}")
    mid = np.sqrt(f[1:] * f[:-1])
    return np.r_[f[0] ** 2 / mid[0], mid], np.r_[mid, f[-1] ** 2 / mid[-1]]


def record_esd(a: ArrayLike, dt: float, f_centres: ArrayLike) -> NDArray[np.float64]:
    """Energy spectral density of a record averaged over log-spaced bands [(m/s²)²·s/Hz].

    One-sided, E(f) = 2Δt²|Σ_k a_k e^(−2πifkΔt)|², so that ∫₀^(1/2Δt) E df = Σ a² Δt; the
    transform is zero-padded to ≥ 4 times the record so that every band holds several
    frequencies.
    """
    x = finite_array("a", a)
    dt = positive_finite("dt", dt)
    lo, hi = band_edges(f_centres)
    n = 1 << int(math.ceil(math.log2(4 * x.size)))
    f = np.fft.rfftfreq(n, dt)
    e = 2.0 * dt * dt * np.abs(np.fft.rfft(x, n)) ** 2
    idx = [np.flatnonzero((f >= a0) & (f < b0)) for a0, b0 in zip(lo, hi, strict=True)]
    if any(i.size == 0 for i in idx) or hi[-1] > 0.5 / dt:
        raise ValueError(f"bands [{lo[0]:.3g}, {hi[-1]:.3g}] Hz do not fit the record's "
                         f"frequency grid (dt={dt!r} s, {x.size} samples)")
    return np.array([e[i].mean() for i in idx])


def model_esd(
    params: RDKParams, dt: float, f_centres: ArrayLike, floor_hz: float = DEFAULT_FLOOR_HZ
) -> NDArray[np.float64]:
    """Expected energy spectral density of the model averaged over the same bands.

    E[|X(f)|²] ≈ ∫q² dt · Σ_k s_k ⟨φ_k(f; ω_k(t))⟩, the time average weighted by q²; the
    weight is sampled at equal shares of the expected energy (quasi-stationary
    approximation: the filter changes slowly compared with its memory).
    """
    lo, hi = band_edges(f_centres)
    u = np.linspace(0.0, 1.0, _N_SUB + 2)[1:-1]
    f = np.exp(np.log(lo)[:, None] + np.outer(np.log(hi / lo), u))
    t = params.envelope.time_at_fraction((np.arange(_N_TIME) + 0.5) / _N_TIME)
    total = 0.0
    for share, omega, zeta in params.terms(t, floor_hz):
        total = total + share * unit_psd(f.ravel(), omega, zeta, dt, params.low).mean(axis=0)
    energy = params.Ia * 2.0 * G / math.pi  # ∫q² dt = (2g/π) Ia
    return energy * np.asarray(total).reshape(f.shape).mean(axis=1)


def _with_theta(base: RDKParams, theta: NDArray[np.float64], rel_slope: float) -> RDKParams:
    f1, z1, ratio, z2, s2, f_low, z_low = theta
    f1 = math.exp(f1)
    return replace(
        base, f_mid=f1, f_slope=rel_slope * f1, zeta_f=float(z1), f_mid2=f1 * math.exp(ratio),
        zeta_f2=float(z2), share2=float(s2), f_low=math.exp(f_low), zeta_low=float(z_low),
        diagnostics={},
    )


def _solve(
    residual: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    starts: list[NDArray[np.float64]],
) -> NDArray[np.float64]:
    """Bounded least squares of ``residual`` from several starts; the best θ."""
    best = None
    for x0 in starts:
        x0 = np.clip(x0, _LOWER + 1e-9, _UPPER - 1e-9)
        sol = optimize.least_squares(residual, x0, bounds=(_LOWER, _UPPER), xtol=1e-6)
        if best is None or sol.cost < best.cost:
            best = sol
    return best.x


def _weighted(r: NDArray[np.float64], in_band: list[NDArray[np.bool_]]) -> NDArray[np.float64]:
    """Residuals of the objective: r(T)/√n at every period, then the band means of r."""
    return np.concatenate([r / math.sqrt(r.size), [r[m].mean() for m in in_band]])


def _objective(r: NDArray[np.float64], in_band: list[NDArray[np.bool_]]) -> float:
    """Mean square of the log ratio plus the squared mean of each band [-]."""
    return float(np.sum(_weighted(r, in_band) ** 2))


def fit_spectrum(
    a: ArrayLike,
    dt: float,
    base: RDKParams,
    post: Callable[[NDArray[np.float64]], NDArray[np.float64]],
    *,
    periods: ArrayLike = FIT_PERIODS,
    n_sim: int = 20,
    seed: int = 0,
    iterations: int = 2,
    floor_hz: float = DEFAULT_FLOOR_HZ,
) -> RDKParams:
    """Extended RDK parameters whose ensemble matches the record's median 5 % PSA.

    Parameters
    ----------
    a : array_like
        Record component [m/s²], 1-D, before the post-processing high-pass.
    dt : float
        Time step [s] (simulations use it).
    base : RDKParams
        Envelope (Ia, D5-95, t_mid) and zero-crossing line (f_mid, f′) of the record: only
        the relative drift f′/f_mid of the filter frequency is kept.
    post : callable
        The post-processing of the final ensemble (high-pass), applied to the record and to
        the simulations alike: (m, n) accelerations → (m, n′).
    periods : array_like
        Increasing periods of the match [s]; the energy spectrum is fitted in bands centred
        on 1/T.
    n_sim : int
        Simulations per misfit evaluation (common random numbers).
    seed : int
        Seed of their noise.
    iterations : int
        Gauss–Newton steps (0: the fit of the record's energy spectrum only); each costs
        one ensemble of ``n_sim`` simulations.
    floor_hz : float
        Floor of the filter frequencies [Hz].

    Returns
    -------
    RDKParams
        With ``diagnostics["spectrum_fit"]``: periods, log misfit r(T) of the kept iterate,
        its band means, the objective of every iterate, settings and the wall time [s].
    """
    x = finite_array("a", a)
    dt = positive_finite("dt", dt)
    T = np.asarray(periods, dtype=np.float64)
    if T.ndim != 1 or T.size < 3 or np.any(T <= 0) or np.any(np.diff(T) <= 0):
        raise ValueError(f"periods must be >= 3 increasing values > 0 [s], got {periods!r}")
    if int(n_sim) != n_sim or n_sim < 2:
        raise ValueError(f"n_sim must be an integer >= 2, got {n_sim!r}")
    if int(iterations) != iterations or iterations < 0:
        raise ValueError(f"iterations must be an integer >= 0, got {iterations!r}")
    f_centres = 1.0 / T[::-1]
    rel_slope = base.f_slope / base.f_mid

    def build(theta: NDArray[np.float64]) -> RDKParams:
        return _with_theta(base, theta, rel_slope)

    in_band = [(T >= lo) & (T <= hi) for lo, hi in BANDS]
    if any(not m.any() for m in in_band):
        raise ValueError(f"periods must reach into every band {BANDS} [s]")

    def residual_esd(target: NDArray[np.float64]):
        def residual(theta: NDArray[np.float64]) -> NDArray[np.float64]:
            ln_e = np.log(model_esd(build(theta), dt, f_centres, floor_hz))
            return 0.5 * (ln_e - target)

        return residual

    rec_psa = pseudo_acceleration(post(x[None, :])[0], dt, T, DAMPING)
    if np.any(rec_psa <= 0.0):
        raise ValueError("the record's response spectrum has zero values: is a a motion?")
    npts = int(math.ceil(base.model_duration(0.999) / dt - 1e-9)) + 1
    trial = build(0.5 * (_LOWER + _UPPER))
    noise = np.random.default_rng(seed).standard_normal((noise_rows(trial, dt, npts), n_sim))

    def misfit(theta: NDArray[np.float64]) -> NDArray[np.float64]:
        sims = time_domain(build(theta), dt, npts, noise, floor_hz=floor_hz)
        psa = pseudo_acceleration(post(sims), dt, T, DAMPING)
        return np.log(np.exp(np.log(psa).mean(axis=0)) / rec_psa)

    # Step 0: the record's energy spectrum, from several starts.
    lf = math.log(base.f_mid)
    starts = [np.array([lf + 0.4, 0.3, math.log(r), 0.3, 0.5, math.log(0.2), 0.6])
              for r in _START_RATIOS]
    theta = _solve(residual_esd(np.log(record_esd(x, dt, f_centres))), starts)
    history: list[tuple[float, NDArray[np.float64], NDArray[np.float64]]] = []
    for it in range(int(iterations) + 1):
        r = misfit(theta)
        history.append((_objective(r, in_band), theta, r))
        if it == iterations:
            break
        best_j, best_theta, best_r = min(history, key=lambda h: h[0])
        # Gauss–Newton step on the PSA misfit from the best iterate, its Jacobian taken from
        # the energy spectrum: r(θ) ≈ r_best + ½[ln E(θ) − ln E(θ_best)] at f = 1/T.
        ln_e = np.log(model_esd(build(best_theta), dt, f_centres, floor_hz))[::-1]
        step = np.clip(best_r, -_MAX_STEP, _MAX_STEP)

        def predicted(th, ln_e=ln_e, step=step):
            rp = step + 0.5 * (np.log(model_esd(build(th), dt, f_centres, floor_hz))[::-1]
                               - ln_e)
            return _weighted(rp, in_band)

        theta = _solve(predicted, [best_theta])
        if best_j < history[-1][0]:
            # The last step made things worse: the surrogate is trusted over half the step.
            theta = best_theta + 0.5 * (theta - best_theta)
    _, theta, r = min(history, key=lambda h: h[0])
    out = build(theta)
    diagnostics: dict[str, Any] = {
        "periods": T.tolist(),
        "log_ratio": r.tolist(),
        "rms_log_ratio": float(np.sqrt(np.mean(r * r))),
        "band_log_ratio": [float(r[m].mean()) for m in in_band],
        "objective_by_iteration": [h[0] for h in history],
        "n_sim": int(n_sim), "seed": int(seed), "iterations": int(iterations),
        "relative_slope_per_s": rel_slope,
    }  # fmt: skip
    # no wall-clock time here: these diagnostics are written into the ensemble's data files
    # (the comparison of a `counts` ensemble holds this fit), which a rerun must write to the
    # same bytes; the fit's time is in the ensemble's summary (timings fit_s)
    return replace(out, diagnostics={**base.diagnostics, "spectrum_fit": diagnostics})
