"""Compilation paid once per machine: the kernels compiled into numba's on-disk cache.

The kernels are numba functions cached on disk (``cache=True``), so :func:`warm_numba_cache`
run once before any worker starts (the workflow's first step) compiles them, and every later
process, worker or rule loads them from the cache instead of compiling its own copy.
"""

from __future__ import annotations

import functools
import logging
import time
from collections.abc import Sequence

log = logging.getLogger("rocking.execution.warmup")

WARM_R = 1.0
"""Size of the warm-up cylinder [m] (tan α 0.2): small enough to rock, tail and overturn
under :func:`_warm_motion` within a few analyses."""


def _warm_motion(vertical: bool = False):
    """2 s of two half-sine pulses at 100 Hz: a cheap motion under which a search meets
    rest, rocking, the free tail after the record and overturning (``vertical``: with a
    vertical pulse too)."""
    import numpy as np

    from rocking.motions.motion import GroundMotion

    t = np.arange(201) * 0.01
    pulse = np.where(t < 1.0, np.sin(np.pi * t), 0.0)
    az = 1.0 * np.roll(pulse, 25) if vertical else None
    return GroundMotion(3.0 * pulse, 2.0 * np.roll(pulse, 50), 0.01, "warm-up", az=az)


def _warm_mode(mode: str, monitors: bool = False, vertical: bool = False,
               history: bool = False) -> float:
    """Cheap searches of ``mode`` (compile or load its kernels): the one every study runs
    (no monitors, no vertical forcing), and the kernels' variants with the monitors (a
    friction coefficient) and with the vertical forcing where asked
    (:data:`rocking.dynamics.driver.VARIANTS`, each compiled on its first call only); with
    ``history``, one analysis that keeps its history too (the kernels of the paper's Figs 4
    and 6, which trace tilts in time); seconds it took [s]."""
    from rocking.dynamics.bodies import Cylinder
    from rocking.spectra.critical import critical_intensity

    t0 = time.perf_counter()
    if history and mode in HISTORY_MODES:
        from rocking.dynamics.analysis import ground_response
        from rocking.spectra.modes import MODES

        ground_response(Cylinder(WARM_R, 0.2), _warm_motion(), model=MODES[mode][0],
                        pga_ratio=2.0, history=True)
    for mon, vert in ((False, False), (True, False), (False, True), (True, True)):
        if (mon and not monitors) or (vert and not vertical):
            continue
        critical_intensity(Cylinder(WARM_R, 0.2, mu=0.5 if mon else None),
                           _warm_motion(vert), ["tilt:0.5", "overturning"], mode,
                           accuracy="fast", upper=8.0)
    return time.perf_counter() - t0


HISTORY_MODES = ("3d", "3d-damped")
"""Modes whose history kernels a reproduction of the paper's figures calls (Figs 4, 6)."""


def histories_asked(config) -> bool:
    """Whether a configuration draws the paper's figures that trace histories (Figs 4 and
    6: a study that reproduces the paper): their kernels are then compiled once here,
    instead of by each of those figures' processes at the same time."""
    return any(isinstance(s, dict) and s.get("reproduces")
               for s in (config.get("studies") or {}).values())


def variants_asked(config) -> tuple[bool, bool]:
    """Whether a configuration may ask for the validity monitors (a ``mu`` set, a sliding
    limit state) and for the vertical forcing (``vertical: true``) anywhere: the kernels'
    variants :func:`warm_numba_cache` compiles besides the plain one (a superset is safe:
    only the warm-up takes longer)."""
    monitors = vertical = False
    stack = [config]
    while stack:
        node = stack.pop()
        if isinstance(node, dict):
            for key, value in node.items():
                monitors |= key == "mu" and value is not None
                vertical |= key == "vertical" and value is True
                stack.append(value)
        elif isinstance(node, (list, tuple)):
            stack.extend(node)
        elif isinstance(node, str):
            monitors |= node.strip().lower().startswith("sliding")
    return monitors, vertical


def warm_numba_cache(modes: Sequence[str] | None = None, processes: int = 1, *,
                     monitors: bool = False, vertical: bool = False,
                     history: bool = False) -> dict[str, float]:
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
    monitors, vertical : bool
        Also the kernels' variants with the validity monitors, with the vertical forcing
        (:func:`variants_asked` of a study's configuration); the plain one always.
    history : bool
        Also the kernels of an analysis that keeps its history (:func:`histories_asked`).

    Returns
    -------
    dict
        Seconds per mode [s]: compilation on an empty cache, loading on a warm one.
    """
    from rocking.spectra.critical import MODES

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
            warm = functools.partial(_warm_mode, monitors=monitors, vertical=vertical,
                                     history=history)
            seconds.update(zip(first, pool.map(warm, first), strict=True))
    for mode in modes:  # in this process too: loads what the others compiled
        seconds[mode] = seconds.get(mode, 0.0) + _warm_mode(mode, monitors, vertical,
                                                            history)
        log.info("numba kernels of mode %s ready in %.2f s", mode, seconds[mode])
    return seconds
