"""The motions the benchmarks run on: the study's two records (as recorded), or a labelled
synthetic stand-in where the records cannot be loaded, and one RDK pair fitted to a record."""

from __future__ import annotations

import numpy as np

from rocking.constants import G
from rocking.motions.motion import GroundMotion


def benchmark_records() -> dict[str, tuple[GroundMotion, str]]:
    """El Centro and the Loma Prieta stand-in, else a labelled synthetic motion."""
    try:
        from rocking.motions.catalogue import load_record

        return {
            "el-centro": (load_record("el-centro-1940"),
                          "El Centro 1940 (NGA-West2 RSN 6, as recorded)"),
            "loma-prieta": (load_record("loma-prieta-corralitos"),
                            "Loma Prieta 1989 Corralitos (RSN 753, as recorded)"),
        }
    except (ImportError, OSError, ValueError) as exc:
        print(f"records unavailable ({exc}); using a synthetic motion", flush=True)
        return {"synthetic": (synthetic_motion(), "synthetic: 1–10 Hz filtered white noise, "
                                                   "sin² envelope, seed 0")}


def synthetic_motion() -> GroundMotion:
    """30 s of band-limited noise under a sin² envelope, vector PGA 0.3 g (seeded)."""
    from scipy.signal import butter, sosfiltfilt

    dt, n = 0.01, 3001
    rng = np.random.default_rng(0)
    sos = butter(4, (1.0, 10.0), btype="bandpass", fs=1.0 / dt, output="sos")
    env = np.sin(np.pi * np.arange(n) / (n - 1)) ** 2
    ax, ay = (sosfiltfilt(sos, rng.standard_normal(n)) * env for _ in range(2))
    m = GroundMotion(ax, ay, dt, "synthetic")
    return m.scaled(0.3 * G / m.pga)


def with_synthetic(record: GroundMotion) -> list[GroundMotion]:
    """The record and one RDK pair fitted to it (seed 2017), as a study ensemble holds."""
    from rocking.motions.stochastic.fit import fit_rdk
    from rocking.motions.stochastic.pairs import synthesize

    try:
        return [record, synthesize(fit_rdk(record), 1, seed=2017)[0]]
    except ValueError as exc:  # e.g. a motion the RDK fit cannot describe
        print(f"no synthetic pair of {record.name} ({exc})", flush=True)
        return [record]
