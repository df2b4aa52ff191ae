"""Compilation paid once per machine: the kernels compiled into numba's on-disk cache.

The kernels are numba functions cached on disk (``cache=True``), so :func:`warm_numba_cache`
run once before any worker starts (the workflow's first step) compiles them, and every later
process, worker or rule loads them from the cache instead of compiling its own copy.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Sequence

log = logging.getLogger("rocking.study.warmup")

WARM_R = 1.0
"""Size of the warm-up cylinder [m] (tan α 0.2): small enough to rock, tail and overturn
under :func:`_warm_motion` within a few analyses."""


def _warm_motion():
    """2 s of two half-sine pulses at 100 Hz: a cheap motion under which a search meets
    rest, rocking, the free tail after the record and overturning."""
    import numpy as np

    from ..motions.motion import GroundMotion

    t = np.arange(201) * 0.01
    pulse = np.where(t < 1.0, np.sin(np.pi * t), 0.0)
    return GroundMotion(3.0 * pulse, 2.0 * np.roll(pulse, 50), 0.01, "warm-up")


def _warm_mode(mode: str) -> float:
    """One cheap search of ``mode`` (compiles or loads its kernels); seconds it took [s]."""
    from ..dynamics.bodies import Cylinder
    from ..spectra.critical import critical_intensity

    t0 = time.perf_counter()
    critical_intensity(Cylinder(WARM_R, 0.2), _warm_motion(), ["tilt:0.5", "overturning"],
                       mode, accuracy="fast", upper=8.0)
    return time.perf_counter() - t0


def warm_numba_cache(modes: Sequence[str] | None = None, processes: int = 1) -> dict[str, float]:
    """Compile the kernels of ``modes``, or load them from numba's cache.

    One critical-intensity search per mode on a 2 s motion runs every kernel a study's
    tasks call (the search's summary-only analyses, stop at a tilt, free tail, overturning).
    Compiled code is written to numba's on-disk cache, so processes started afterwards on
    this machine (Dask workers, other rules) load it in about a second instead of compiling
    for 10–20 s each, and each kernel is compiled once instead of once per process.

    Parameters
    ----------
    modes : sequence of str, optional
        Modes of :data:`rocking.spectra.critical.MODES` (default all).
    processes : int
        Compile the dynamics models (3d, 3d-damped, 2d) in up to this many fresh processes
        at once (1: one after the other in this process). The models share few kernels, so
        on an empty cache the wall time falls from their sum towards the slowest one.

    Returns
    -------
    dict
        Seconds per mode [s]: compilation on an empty cache, loading on a warm one.
    """
    from ..spectra.critical import MODES

    modes = list(dict.fromkeys(MODES if modes is None else modes))
    if processes < 1:
        raise ValueError(f"processes must be >= 1, got {processes!r}")
    # one representative mode per dynamics model first (2d-x and 2d-y share a kernel)
    first = list({MODES[m][0]: m for m in reversed(modes)}.values())[::-1]
    seconds: dict[str, float] = {}
    if processes > 1 and len(first) > 1:
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        ctx = multiprocessing.get_context("spawn")  # fresh interpreters, nothing inherited
        with ProcessPoolExecutor(min(processes, len(first)), mp_context=ctx) as pool:
            seconds.update(zip(first, pool.map(_warm_mode, first), strict=True))
    for mode in modes:  # in this process too: loads what the others compiled
        seconds[mode] = seconds.get(mode, 0.0) + _warm_mode(mode)
        log.info("numba kernels of mode %s ready in %.2f s", mode, seconds[mode])
    return seconds
