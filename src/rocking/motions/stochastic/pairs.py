"""Synthetic bidirectional ensembles "with the statistical properties" of one record.

Each realization is a pair along the record's principal axes: the major and minor components
are simulated with their own fitted parameters and independent white noise, so the pair is
uncorrelated in the ensemble sense (RDK 2012; Penzien & Watabe 1975). Parameters are kept at
the fitted values: all variability comes from the noise (docs/equations.md, "Ensembles").

Reproducibility: one root seed; the noise of component c (0 = major, 1 = minor) of
realization r comes from ``SeedSequence(seed).spawn(2)[c].spawn(n)[r]`` (spawn key (c, r)),
so realization r is the same whatever n, and the streams are statistically independent.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, Literal

import numpy as np

from rocking._validate import positive_finite
from rocking.motions.motion import GroundMotion
from rocking.motions.stochastic.discretize import DEFAULT_FC_HZ, noise_rows, spectral, time_domain
from rocking.motions.stochastic.filter import DEFAULT_FLOOR_HZ, normalized_irf
from rocking.motions.stochastic.fit import RDKFit
from rocking.motions.stochastic.params import RDKParams

__all__ = ["DEFAULT_FC_HZ", "energy_correction", "simulate_component", "synthesize"]


def _streams(seed: int, n: int) -> list[list[np.random.SeedSequence]]:
    """[component][realization] seed sequences, spawn keys (c, r)."""
    root = np.random.SeedSequence(seed)
    return [comp.spawn(n) for comp in root.spawn(2)]


def _draw(seqs: list[np.random.SeedSequence], rows: int) -> np.ndarray:
    """(rows, n) standard normals, column r from stream r."""
    return np.column_stack([np.random.default_rng(s).standard_normal(rows) for s in seqs])


def simulate_component(
    params: RDKParams,
    dt: float,
    npts: int,
    seqs: list[np.random.SeedSequence],
    method: Literal["time", "spectral"] = "time",
    **kw: Any,
) -> np.ndarray:
    """(n, npts) unfiltered realizations of one component, realization r from ``seqs[r]``."""
    rows = noise_rows(params, dt, npts, method, kw.get("f_max_hz"))
    simulate = time_domain if method == "time" else spectral
    return simulate(params, dt, npts, _draw(seqs, rows), **kw)


def _apply_highpass(
    x: np.ndarray, dt: float, kind: str, fc_hz: float, order: int
) -> tuple[np.ndarray, dict[str, Any]]:
    """High-pass all rows of ``x`` at once with :mod:`rocking.motions.highpass` (padding kept)."""
    from rocking.motions.highpass import highpass_rows

    if kind not in ("oscillator", "butterworth"):
        raise ValueError(
            f"highpass must be True, False, 'oscillator' or 'butterworth', got {kind!r}"
        )
    out, front = highpass_rows(x, dt, kind, fc_hz, order)
    step: dict[str, Any] = {"step": "highpass", "kind": kind, "fc_hz": fc_hz}
    if kind == "butterworth":
        step["order"] = order
    step["pad_front"] = int(front)
    step["pad_end"] = int(out.shape[-1] - x.shape[-1] - front)
    return out, step


def energy_correction(
    params: RDKParams,
    dt: float,
    npts: int,
    filt: Callable[[np.ndarray], np.ndarray],
    *,
    floor_hz: float = DEFAULT_FLOOR_HZ,
    chunk: int = 512,
) -> float:
    """Deterministic factor c = √(E[Σ x̂²] / E[Σ a²]) restoring the energy a high-pass removes.

    The time-domain simulation and the filter are linear, a = L diag(q) Σ_k √s_k S_k u_k with
    iid unit normals u_k, so E[Σ a²] = Σ_k s_k Σ_i ‖L (q ⊙ S_k[:, i])‖²: the filtered
    responses to each single pulse, summed in chunks of ``chunk`` pulses. E[Σ x̂²] = Σ q²
    because every S_k has unit rows and the shares s_k sum to 1.
    One factor per component, the same for every realization: the record-to-record
    variability of Ia is kept (docs/equations.md, "Ensembles"; the Su/Broccardo toolbox
    does the same).

    Parameters
    ----------
    params : RDKParams
        Component parameters.
    dt : float
        Time step [s].
    npts : int
        Simulated samples (before padding).
    filt : callable
        The high-pass applied to a (m, npts) block of signals, returning (m, npts + pads).
    floor_hz : float
        Floor of the filter frequency [Hz].
    chunk : int
        Pulses filtered at once (memory ~ chunk × (npts + pads) doubles).

    Returns
    -------
    float
        c ≥ 1 for a high-pass [-].
    """
    t = np.arange(npts) * dt
    q = params.envelope(t)
    den = 0.0
    for share, omega, zeta in params.terms(t, floor_hz):
        s = normalized_irf(omega, zeta, dt, low=params.low).to_sparse().tocsc()
        for start in range(0, npts, chunk):
            # Pulses at i ≥ start are zero before it, and the filter is time-invariant and
            # starts at rest, so the leading zeros can be dropped without changing the energy.
            cols = (q[start:, None] * s[start:, start : start + chunk].toarray()).T
            den += share * float(np.sum(filt(cols) ** 2))
    num = float(np.sum(q[1:] ** 2))  # row 0 of S is zero
    return math.sqrt(num / den)


def synthesize(
    fit: RDKFit,
    n: int,
    seed: int,
    *,
    method: Literal["time", "spectral"] = "time",
    highpass: bool | str = True,
    fc_hz: float = DEFAULT_FC_HZ,
    order: int = 4,
    duration: float | None = None,
    axes: Literal["principal", "record"] = "principal",
    floor_hz: float = DEFAULT_FLOOR_HZ,
    f_max_hz: float | None = None,
    filter_psd: Literal["discrete", "continuous"] = "discrete",
    rescale: bool = False,
    name: str | None = None,
) -> list[GroundMotion]:
    """Simulate ``n`` bidirectional pairs with the fitted RDK parameters of a record.

    Parameters
    ----------
    fit : RDKFit
        Parameters of the major and minor principal components (:func:`fit_rdk`).
    n : int
        Number of pairs, ≥ 1.
    seed : int
        Root seed (≥ 0); see the module notes for the per-stream spawn keys.
    method : {"time", "spectral"}
        Time-domain banded discretization (default, RDK 2008) or the spectral form
        (Broccardo & Der Kiureghian 2014).
    highpass : bool or {"oscillator", "butterworth"}
        Post-processing high-pass; True means the RDK 2010 critically damped oscillator,
        which also makes the residual velocity and displacement vanish. The padding it adds
        is kept.
    fc_hz : float
        High-pass corner [Hz].
    order : int
        Order of the Butterworth filter (only for ``highpass="butterworth"``).
    duration : float or None
        Simulated length before padding [s]; default: the latest time at which the expected
        Husid function of either component reaches 99.9 % of Ia.
    axes : {"principal", "record"}
        Output along the principal axes (x = major; default) or rotated back by −angle to
        the recording axes.
    floor_hz : float
        Floor of the filter frequency [Hz].
    f_max_hz : float or None
        Highest frequency of the spectral method [Hz] (default Nyquist).
    filter_psd : {"discrete", "continuous"}
        Filter spectrum of the spectral method (see :func:`.discretize.spectral`).
    rescale : bool
        Multiply each high-passed component by the deterministic factor of
        :func:`energy_correction` so that the *expected* Arias intensity is the fitted one
        (default False: RDK 2010 did not rescale; the filter removes ~1–3 % of Ia). Only for
        ``method="time"``.
    name : str or None
        Prefix of the motion names (default: the record's name).

    Returns
    -------
    list of GroundMotion
        Accelerations [m/s²] on the record's time step; metadata holds the parameters, the
        seed, the stream ids and the processing steps.
    """
    if not isinstance(fit, RDKFit):
        raise ValueError(f"fit must be an RDKFit, got {type(fit).__name__}")
    if isinstance(n, bool) or int(n) != n or n < 1:
        raise ValueError(f"n must be a positive integer, got {n!r}")
    if isinstance(seed, bool) or int(seed) != seed or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    if axes not in ("principal", "record"):
        raise ValueError(f"axes must be 'principal' or 'record', got {axes!r}")
    if method not in ("time", "spectral"):
        raise ValueError(f"method must be 'time' or 'spectral', got {method!r}")
    n, seed, dt = int(n), int(seed), fit.dt
    if highpass is True:
        highpass = "oscillator"
    if rescale and (highpass is False or method != "time"):
        raise ValueError(
            f"rescale needs a high-pass and method='time', got highpass={highpass!r}, "
            f"method={method!r}"
        )
    if highpass is not False:
        fc_hz = positive_finite("fc_hz", fc_hz)
    if duration is None:
        duration = max(fit.major.model_duration(0.999), fit.minor.model_duration(0.999))
    duration = positive_finite("duration", duration)
    npts = int(math.ceil(duration / dt - 1e-9)) + 1

    kw: dict[str, Any] = {"floor_hz": floor_hz}
    if method == "spectral":
        kw["f_max_hz"] = f_max_hz
        kw["filter_psd"] = filter_psd
    streams = _streams(seed, n)
    comps = [
        simulate_component(p, dt, npts, s, method, **kw)
        for p, s in zip((fit.major, fit.minor), streams, strict=True)
    ]
    processing: list[dict[str, Any]] = [
        {"step": "rdk-simulation", "method": method, "npts": npts, **kw}
    ]
    if highpass is not False:
        steps = []
        for i, x in enumerate(comps):
            comps[i], step = _apply_highpass(x, dt, str(highpass), fc_hz, order)
            steps.append(step)
        processing.append(steps[0])
        if rescale:

            def filt(block: np.ndarray) -> np.ndarray:
                return _apply_highpass(block, dt, str(highpass), fc_hz, order)[0]

            factors = [
                energy_correction(p, dt, npts, filt, floor_hz=floor_hz)
                for p in (fit.major, fit.minor)
            ]
            comps = [c * f for c, f in zip(comps, factors, strict=True)]
            processing.append({"step": "energy-rescale", "factors": factors})

    base = name or f"{fit.name}-rdk"
    motions = []
    for r in range(n):
        meta = _metadata(fit, seed, r, streams, processing)
        gm = GroundMotion(comps[0][r], comps[1][r], dt, f"{base}-{r:03d}", meta)
        if axes == "record":
            from rocking.motions.principal import rotate

            gm = rotate(gm, -fit.angle)
            gm.metadata["axes"] = "record"
        motions.append(gm)
    return motions


def _metadata(fit: RDKFit, seed: int, r: int, streams, processing: list[dict]) -> dict:
    """Metadata of realization ``r``: parameters, seed, stream ids and processing steps."""
    from rocking import __version__  # here: the package imports this module while initializing

    return {
        "generator": "Rezaeian-Der Kiureghian (rocking.motions.stochastic)",
        "record": fit.name,
        "fit_method": fit.diagnostics.get("method", "counts"),
        "parameters": {"major": _params_only(fit.major), "minor": _params_only(fit.minor)},
        "rotation_deg": fit.angle,
        "principal_offset_deg": fit.diagnostics.get("principal_offset_deg"),
        "seed": seed,
        "realization": r,
        "streams": {"x": list(streams[0][r].spawn_key), "y": list(streams[1][r].spawn_key)},
        "processing": [dict(p) for p in processing],
        "axes": "principal (x = major)",
        "stand_in": False,
        "rocking_version": __version__,
    }


def _params_only(p: RDKParams) -> dict[str, float]:
    d = p.to_dict()
    d.pop("diagnostics")
    return d
