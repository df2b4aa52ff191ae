"""Resolution of the critical intensity: how far the answer moves when the scan is refined.

``python -m rocking.benchmarks resolution [--points N] [--jobs J] [--reuse]`` writes under
``results/benchmarks/``:

- ``resolution.csv`` / ``.md``: per (point, limit state) the first exceedance on scan grids of
  1, 0.5, 0.2, 0.1, 0.05 and 0.02 % from uplift, whether and where it converges, and the
  exceedance windows found below the 1 % answer on the finest grid (count, widths);
- ``resolution_accuracy.csv`` / ``.md``: the presets and the scans (fixed, adaptive, the
  window-seeking ``seek``) run as real searches, their error against the converged
  reference and their analyses per point;
- ``resolution_flag.csv`` / ``.md``: precision and recall of
  :attr:`~rocking.spectra.search.CriticalResult.unresolved` (and of the criteria it was
  chosen among) against the truth "a window below the 1 % scan's bracket";
- ``resolution_traces/``: every analysis of every point (cached, reused with ``--reuse``).

Grids. All grids are nested on one lattice I_n = I_uplift·1.01^(n/100): grid "1 %" is n ≡ 0
(mod 100) — exactly the points of the ``default`` preset's fixed scan —, 0.5 % is n ≡ 0
(mod 50), then mod 20, 10, 5 and 2. Only the lattice points of the two finest grids (n even or
a multiple of 5) are analysed, once each, from uplift up to the 1 % answer of every limit
state; every coarser grid is read off them, and one analysis serves all seven limit states
(it runs until the largest goal still open on the 1 % grid, so every goal's status is known at
every point). The 0.02 % grid (n even, not a multiple of 5) is analysed only up to the 0.05 %
answer of the goals still open on it: beyond that the 0.05 % answer cannot move any more. The
damped model (five times slower) is analysed on the 0.05 % grid only.

A point's answer *converges* when the 0.05 % and the 0.02 % answers agree within their two
steps (0.07 %); it converges *at* step s when every grid from s down agrees with the 0.02 %
answer within s + 0.02 %. Analyses use the ``default`` preset's rtol and rest criterion, as
the search does.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import os
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from .. import __version__
from ..dynamics.bodies import Cylinder
from ..dynamics.result import Status
from ..motions.motion import GroundMotion
from ..spectra.accuracy import PRESETS, Accuracy
from ..spectra.critical import MODES, make_analysis, uplift_intensity
from ..spectra.limit_states import DEFAULT_LIMIT_STATES, parse_limit_states
from ..spectra.search import Outcome, search_critical
from ._io import results_dir, write_table

LATTICE_LOG_STEP = math.log(1.01) / 100
"""ln of the ratio between neighbouring lattice points: 1 % / 100."""

GRIDS: dict[str, int] = {"1%": 100, "0.5%": 50, "0.2%": 20, "0.1%": 10, "0.05%": 5,
                         "0.02%": 2}
"""Scan grids: name → lattice period (grid points are the multiples of it)."""

STEP: dict[str, float] = {"1%": 0.01, "0.5%": 0.005, "0.2%": 0.002, "0.1%": 0.001,
                          "0.05%": 0.0005, "0.02%": 0.0002}
"""Nominal relative step of each grid [-]."""

UPPER = 20.0
"""Highest normalized intensity analysed (the study's search bound) [-]."""

MAX_TRACE = 12000
"""Safety net: analyses per point; a point that needs more is marked truncated."""

BASE = PRESETS["default"]

# (motion, mode, R [m], tan α): ordered so that any prefix mixes modes, sizes and motions
POINTS: tuple[tuple[str, str, float, float], ...] = (
    ("ec", "3d", 6.0, 0.2), ("ec", "2d-x", 2.0, 0.2), ("ec", "3d", 1.0, 0.2),
    ("ec", "2d-y", 6.0, 0.2), ("ec", "3d-damped", 4.0, 0.2), ("syn1", "3d", 4.0, 0.2),
    ("ec", "2d-x", 10.0, 0.2), ("ec", "3d", 10.0, 0.2), ("syn1", "2d-x", 2.0, 0.2),
    ("ec", "3d", 2.0, 0.1), ("corr", "3d", 2.0, 0.2), ("ec", "2d-y", 1.0, 0.2),
    ("syn2", "3d", 1.0, 0.2), ("ec", "3d", 0.5, 0.2), ("ec", "2d-x", 0.5, 0.2),
    ("ec", "3d-damped", 1.0, 0.2), ("ec", "3d", 4.0, 0.3), ("syn2", "2d-y", 4.0, 0.2),
    ("corr", "2d-x", 3.0, 0.2), ("ec", "2d-x", 6.0, 0.2), ("syn1", "3d", 10.0, 0.2),
    ("ec", "2d-y", 10.0, 0.2), ("ec", "3d", 2.0, 0.2), ("syn1", "3d-damped", 6.0, 0.2),
    ("ec", "2d-x", 4.0, 0.3), ("corr", "3d", 8.0, 0.2), ("ec", "2d-y", 3.0, 0.2),
    ("syn2", "3d", 6.0, 0.2), ("ec", "2d-x", 1.0, 0.2), ("ec", "3d", 8.0, 0.1),
    ("syn1", "2d-x", 8.0, 0.2), ("ec", "2d-y", 5.0, 0.1), ("ec", "3d", 1.0, 0.3),
    ("syn2", "2d-y", 10.0, 0.2), ("corr", "2d-x", 10.0, 0.2), ("ec", "3d-damped", 10.0, 0.2),
    ("syn1", "3d", 2.0, 0.2), ("ec", "2d-x", 3.0, 0.1), ("syn2", "2d-x", 6.0, 0.2),
    ("ec", "3d", 3.0, 0.2), ("syn1", "2d-y", 2.0, 0.2), ("corr", "2d-y", 5.0, 0.2),
    ("syn2", "3d-damped", 2.0, 0.2), ("ec", "2d-y", 8.0, 0.3),
)

MOTION_LABELS = {
    "ec": "El Centro 1940, principal axes, high-passed (the study's processing)",
    "syn1": "synthetic pair 1 of El Centro's ensemble (RDK, seed 2017)",
    "syn2": "synthetic pair 2 of El Centro's ensemble (RDK, seed 2017)",
    "corr": "Loma Prieta Corralitos, principal axes, high-passed",
}


# ---------------------------------------------------------------------------------- motions
def study_motions() -> dict[str, GroundMotion]:
    """The study's processed El Centro record and two of its synthetic pairs, and the
    processed Corralitos record (:func:`rocking.motions.build.build_ensemble`)."""
    from ..motions.build import build_ensemble
    from ..motions.records import load_record

    ec = build_ensemble(load_record("el-centro-1940"), 2, 2017).motions
    corr = build_ensemble(load_record("loma-prieta-corralitos"), 0, 1989).motions[0]
    return {"ec": ec[0], "syn1": ec[1], "syn2": ec[2], "corr": corr}


# ----------------------------------------------------------------------------------- traces
def lattice_periods(mode: str) -> tuple[int, ...]:
    """Lattice periods analysed in ``mode``: the damped model stops at the 0.05 % grid."""
    return (5,) if MODES[mode][0] == "3d-damped" else (5, 2)


def _goal_status(out: dict, taus: np.ndarray, alpha: float, states) -> tuple[np.ndarray,
                                                                            np.ndarray]:
    """(known, exceeded) per goal of one traced analysis (as the search classifies it)."""
    status = Status(out["status"])
    if status is Status.FAILED:
        return np.zeros(taus.size, bool), np.zeros(taus.size, bool)
    exc = np.array([ls.exceeded(out["theta"], out["overturned"], alpha) for ls in states])
    if status is Status.STOPPED_AT_LIMIT:
        stop = math.inf if out["stop_at"] is None else out["stop_at"]
        known = taus <= stop
        return known, (exc | known) & known
    return np.ones(taus.size, bool), exc


def trace_point(motion: GroundMotion, mode: str, R: float, tan_alpha: float) -> dict:
    """Analyse the lattice of one point from uplift up to the 1 % answer of every goal.

    Returns a JSON-serialisable dict: the point, ``lower`` (uplift intensity), and per
    analysis its lattice index ``n``, ``theta`` [rad], ``overturned``, ``status`` and
    ``stop_at`` [rad], with ``seconds`` and ``truncated``.
    """
    body = Cylinder(R, tan_alpha)
    states = parse_limit_states(DEFAULT_LIMIT_STATES)
    taus = np.array([ls.threshold(body.alpha) for ls in states])
    lower = uplift_intensity(motion, mode)
    analyze = make_analysis(body, motion, mode, rest_tilt=BASE.rest_tilt)
    rtol = BASE.rtol_for(MODES[mode][0])
    periods = lattice_periods(mode)
    finest = min(periods)
    open_1 = np.ones(taus.size, bool)  # goals not yet exceeded on the 1 % grid
    open_f = {p: np.ones(taus.size, bool) for p in periods}  # … on the analysed grids
    first_f = {p: np.full(taus.size, np.inf) for p in periods}
    rows, t0, n, truncated = [], time.perf_counter(), 0, False
    while open_1.any():
        n += 1
        intensity = lower * math.exp(n * LATTICE_LOG_STEP)
        if intensity > UPPER:
            break
        on = [p for p in periods if n % p == 0]
        if not on:
            continue
        if n % 5 != 0 and finest == 2:
            # a 0.02 %-only point: useful while a goal is open there and below the 0.05 %
            # answer (beyond it the 0.02 % grid can only agree with the 0.05 % one)
            useful = open_f[2] & (intensity < first_f[5] * (1 + STEP["0.05%"]))
            if not useful.any():
                continue
        if len(rows) >= MAX_TRACE:
            truncated = True
            break
        top = int(np.flatnonzero(open_1)[-1])
        stop_at = None if states[top].is_overturning else float(taus[top])
        out = analyze(intensity, stop_at, rtol)
        if out.status is Status.FAILED:
            out = analyze(intensity, stop_at, rtol * 0.1)
        row = {"n": n, "theta": float(out.theta_max), "overturned": bool(out.overturned),
               "status": Status(out.status).value, "stop_at": stop_at}
        rows.append(row)
        known, exc = _goal_status(row, taus, body.alpha, states)
        hit = known & exc
        for p in on:
            new = hit & open_f[p]
            first_f[p][new] = intensity
            open_f[p] &= ~hit
        if n % 100 == 0:
            open_1 &= ~hit
    return {"mode": mode, "R": R, "tan_alpha": tan_alpha, "motion": motion.name,
            "lower": lower, "limit_states": [ls.name for ls in states],
            "taus": taus.tolist(), "alpha": body.alpha, "periods": list(periods),
            "analyses": rows, "seconds": time.perf_counter() - t0, "truncated": truncated}


def _engine_digest() -> str:
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256(__version__.encode())
    for f in sorted((root / "dynamics").rglob("*.py")):
        h.update(f.read_bytes())
    h.update(json.dumps(BASE.to_dict(), sort_keys=True).encode())
    return h.hexdigest()[:12]


def _trace_path(key: tuple, digest: str) -> Path:
    m, mode, R, t = key
    folder = results_dir() / "resolution_traces"
    folder.mkdir(exist_ok=True)
    return folder / f"{m}_{mode}_R{R:g}_t{t:g}_{digest}.json"


_MOTIONS: dict[str, GroundMotion] = {}


def _trace_worker(key: tuple, digest: str) -> str:
    """Trace one point in a worker process (motions built once per process)."""
    if not _MOTIONS:
        _MOTIONS.update(study_motions())
    m, mode, R, t = key
    tr = trace_point(_MOTIONS[m], mode, R, t)
    tr["key"] = list(key)
    path = _trace_path(key, digest)
    path.write_text(json.dumps(tr))
    return (f"  {m} {mode} R={R:g} tan={t:g}: {len(tr['analyses'])} analyses, "
            f"{tr['seconds']:.0f} s{' (truncated)' if tr['truncated'] else ''}")


def traces(points, jobs: int, reuse: bool) -> list[dict]:
    """Traces of ``points``, computed (in ``jobs`` processes) or read from the cache."""
    digest = _engine_digest()
    todo = [k for k in points if not (reuse and _trace_path(k, digest).exists())]
    if todo:
        print(f"tracing {len(todo)} points in {jobs} processes", flush=True)
        if jobs > 1:
            with ProcessPoolExecutor(jobs) as pool:
                for line in pool.map(_trace_worker, todo, [digest] * len(todo)):
                    print(line, flush=True)
        else:
            for k in todo:
                print(_trace_worker(k, digest), flush=True)
    return [json.loads(_trace_path(k, digest).read_text()) for k in points]
