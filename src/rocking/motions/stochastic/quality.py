"""How well an ensemble's elastic spectrum matches its record's, per component and band.

For each principal component: the ratio of the ensemble's geometric-mean 5 %-damped
pseudo-acceleration to the record's, averaged in log over the period bands that matter for
rocking, its extremes over the periods, and the fraction of periods at which the record lies
inside the ensemble's 5–95 % range. A single record's spectrum is jagged, so the band means
say how well the ensemble is centred and the extremes how far the record strays from it.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rocking.motions.motion import GroundMotion
from rocking.motions.response_spectrum import pseudo_acceleration

BANDS: tuple[tuple[float, float], ...] = ((0.1, 0.3), (0.3, 1.0), (1.0, 4.0))
"""Period bands of the fit-quality report [s]."""

PERIODS: NDArray[np.float64] = np.geomspace(0.1, 4.0, 40)
"""Periods of the fit-quality report [s] (log-spaced over the bands)."""

DAMPING = 0.05
"""Damping ratio of the compared spectra [-]."""

COMPONENTS = {"x": "ax", "y": "ay"}
"""Component key → GroundMotion attribute (x = major, y = minor principal axis)."""


def band_key(band: tuple[float, float]) -> str:
    """Label of a band, e.g. ``"0.1-0.3 s"``."""
    return f"{band[0]:g}-{band[1]:g} s"


def spectrum_match(
    record_psa: ArrayLike, synthetic_psa: ArrayLike, periods: ArrayLike
) -> dict[str, Any]:
    """Fit quality of one component from its spectra.

    Parameters
    ----------
    record_psa : array_like, shape (p,)
        The record's PSA at ``periods`` [any unit > 0].
    synthetic_psa : array_like, shape (n, p)
        The synthetic motions' PSA, same unit.
    periods : array_like, shape (p,)
        Periods [s], covering every band of :data:`BANDS`.

    Returns
    -------
    dict
        ``band_ratio`` {band label: exp(mean over the band of ln(gm/record))} [-],
        ``ratio_min``, ``ratio_max`` over all periods [-], ``inside_5_95`` (fraction of
        periods with the record inside the ensemble's 5–95 % range) [-] and ``n``.
    """
    T = np.asarray(periods, dtype=np.float64)
    rec = np.asarray(record_psa, dtype=np.float64)
    syn = np.atleast_2d(np.asarray(synthetic_psa, dtype=np.float64))
    if rec.shape != T.shape or syn.shape[1:] != T.shape:
        raise ValueError(f"spectra must have {T.size} periods, got record {rec.shape}, "
                         f"synthetics {syn.shape}")
    if syn.shape[0] < 2:
        raise ValueError(f"need >= 2 synthetic motions for a range, got {syn.shape[0]}")
    if not (np.all(np.isfinite(rec)) and np.all(rec > 0) and np.all(np.isfinite(syn))
            and np.all(syn > 0)):
        raise ValueError("spectra must be finite and > 0")
    log_ratio = np.log(syn).mean(axis=0) - np.log(rec)
    lo, hi = np.percentile(syn, [5.0, 95.0], axis=0)
    bands = {}
    for band in BANDS:
        sel = (T >= band[0]) & (T <= band[1])
        if not sel.any():
            raise ValueError(f"no period in the band {band} s")
        bands[band_key(band)] = float(np.exp(log_ratio[sel].mean()))
    return {
        "band_ratio": bands,
        "ratio_min": float(np.exp(log_ratio.min())),
        "ratio_max": float(np.exp(log_ratio.max())),
        "inside_5_95": float(np.mean((lo <= rec) & (rec <= hi))),
        "n": int(syn.shape[0]),
    }


def ensemble_quality(
    motions: Sequence[GroundMotion], periods: ArrayLike = PERIODS
) -> dict[str, Any]:
    """Fit quality of an ensemble: the record first, then its synthetic pairs.

    Parameters
    ----------
    motions : sequence of GroundMotion
        The processed record, then ≥ 2 synthetic pairs on the same axes [m/s²].
    periods : array_like
        Periods of the comparison [s].

    Returns
    -------
    dict
        ``x`` and ``y``: :func:`spectrum_match` of each component; ``periods`` (first, last,
        count) [s] and ``damping`` [-].
    """
    motions = list(motions)
    if len(motions) < 3:
        raise ValueError(f"need the record and >= 2 synthetic pairs, got {len(motions)} motions")
    T = np.asarray(periods, dtype=np.float64)
    out: dict[str, Any] = {"periods": [float(T[0]), float(T[-1]), int(T.size)],
                           "damping": DAMPING}
    for key, attr in COMPONENTS.items():
        rec = pseudo_acceleration(getattr(motions[0], attr), motions[0].dt, T, DAMPING)
        syn = np.vstack([pseudo_acceleration(getattr(m, attr), m.dt, T, DAMPING)
                         for m in motions[1:]])
        out[key] = spectrum_match(rec, syn, T)
    return out


def format_quality(quality: dict[str, Any], title: str = "") -> list[str]:
    """Text lines of a fit-quality summary (one line per component)."""
    lines = [title] if title else []
    for key, name in (("x", "x (major)"), ("y", "y (minor)")):
        q = quality[key]
        bands = ", ".join(f"{b} {r:.2f}" for b, r in q["band_ratio"].items())
        lines.append(
            f"  {name}: median PSA / record {bands}; range {q['ratio_min']:.2f}–"
            f"{q['ratio_max']:.2f}; record inside 5–95 % at {100 * q['inside_5_95']:.0f} % "
            f"of periods (n = {q['n']})"
        )
    return lines
