"""Resolution of the critical intensity: the search's answers against I10 of a fine lattice.

``python -m benchmarks resolution [--points N] [--jobs J] [--stage …]`` writes under
``results/benchmarks/``:

- ``resolution_reference.csv`` / ``.md``: per (point, limit state) the reference I10 of a
  0.02 % lattice, its convergence against a 0.01 % lattice, I50, the plateau flag, the
  first exceedance on grids of 1, 0.5, 0.2 and 0.1 % (read off the lattices) and how it
  sits against I10;
- ``resolution_trade_sim.csv`` / ``.md``: search settings simulated on the lattices (the
  library's search, its analyses answered by the nearest lattice point) over many random
  offsets per point: share of answers within 2 % and 5 % of I10, median and 90th
  percentile error, analyses and (lattice-timed) CPU seconds per point — the trade;
- ``resolution_trade.csv`` / ``.md``: the presets, run as real searches, and the ``default``
  before issue 45 (:data:`BASELINE`, the code of that commit run in a subprocess in the same
  run): the same columns with real CPU seconds, per preset and goal set;
- ``resolution_paper.csv`` / ``.md``: analyses and CPU seconds per point per paper mode
  and goal set with the chosen ``default``, on a sample of config/paper.yaml's points, and
  the paper run's searches estimated from them;
- ``resolution_lattice/``: every lattice analysis of every point (one ``.npz`` per point,
  reused whenever the engine and the lattice plan are unchanged).

The lattice. Points are analysed on I_n = I_uplift·exp(n·10⁻⁴) (a 0.01 % lattice); the 0.02 %
lattice is its even n, the 0.1 % lattice n ≡ 0 (mod 10). Per point:

1. the 0.1 % lattice from uplift until every limit state exceeds at 60 % of the last ±2 %
   (or the bound 20): the global view of P(s) (40 analyses per window), and I10's first
   estimate;
2. the 0.02 % lattice from 6 % below to 5 % above that estimate, per limit state (extended
   down while P̂ >= 0.1 at its lowest judged s, up while P̂ never reaches 0.1): the
   *reference* I10 = inf{s : P̂(s) >= 0.1} over the s whose window lies inside it;
3. the 0.01 % lattice from 3 % below to 3 % above the reference: the convergence check.

Below the fine lattice only the 0.1 % lattice has looked (the reference is the lowest
crossing of P̂ there or, failing that, in the fine lattice): "I10 on the 0.1 % lattice"
beside it says whether the two views agree. Below uplift a body is at rest and exceeds no
tilt goal (the lattice counts those intensities as not exceeding). Analyses use the
``default`` preset's rtol and rest criterion (as the searches do); each runs until the
largest goal it is needed for.
"""

from __future__ import annotations

import argparse
import ast
import hashlib
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from benchmarks._io import results_dir, write_table
from benchmarks.study_motions import MOTION_LABELS
from rocking.dynamics.bodies import Cylinder
from rocking.dynamics.result import Status
from rocking.motions.motion import GroundMotion
from rocking.spectra.accuracy import PRESETS, Accuracy
from rocking.spectra.critical import MODES, make_analysis, uplift_intensity
from rocking.spectra.limit_states import (
    DEFAULT_LIMIT_STATES,
    OVERTURNED,
    THETA_MAX,
    classify,
    parse_limit_states,
    stop_for,
)
from rocking.spectra.modes import MODE_2D_X, MODE_2D_Y, MODE_3D, MODE_3D_DAMPED
from rocking.spectra.quantity import Quantity, exceedance_quantile, local_exceedance
from rocking.spectra.search import RETRY_RTOL_FACTOR, Outcome, cell_seed, search_critical

STEP = 1e-4
"""ln of the ratio between neighbouring lattice points (the 0.01 % lattice)."""

COARSE, FINE, FINEST = 10, 2, 1
"""Lattice periods: 0.1 %, 0.02 % (the reference) and 0.01 % (its convergence)."""

GRIDS = {"1%": 100, "0.5%": 50, "0.2%": 20, "0.1%": 10}
"""First-exceedance grids read off the lattice (period in lattice steps)."""

Q = Quantity()
"""The quantity of the benchmark: I10, w = 2 %."""

UPPER = 20.0
"""Highest normalized intensity analysed (the study's search bound) [-]."""

BASE = PRESETS["default"]
"""Whose rtol and rest criterion the lattice analyses use."""

FINE_BELOW, FINE_ABOVE = 0.06, 0.05
"""Reach of the 0.02 % lattice below and above the first estimate of I10 [ln I]."""

FINEST_REACH = 0.03
"""Reach of the 0.01 % lattice around the reference [ln I]."""

MAX_LATTICE = 12000
"""Safety net: analyses per point."""

GOALS_2 = ("overturning", "tilt:1/3")
"""The limit states of Figs 9, 11 and 12 (most of the paper's spectrum points)."""

GOALS_7 = tuple(DEFAULT_LIMIT_STATES)
"""The seven goals of Fig 10."""

# (motion, mode, R [m], tan α, goals): any prefix mixes modes, sizes and motions
POINTS: tuple[tuple[str, str, float, float, tuple[str, ...]], ...] = (
    ("ec", MODE_3D, 6.0, 0.2, GOALS_7), ("ec", MODE_2D_X, 2.0, 0.2, GOALS_2),
    ("syn0", MODE_3D, 4.0, 0.2, GOALS_2), ("ec", MODE_2D_Y, 6.0, 0.2, GOALS_2),
    ("ec", MODE_3D, 10.0, 0.2, GOALS_7), ("lp", MODE_3D, 2.0, 0.2, GOALS_2),
    ("syn1", MODE_2D_X, 4.0, 0.2, GOALS_2), ("ec", MODE_3D, 1.0, 0.2, GOALS_2),
    ("ec", MODE_3D_DAMPED, 4.0, 0.2, GOALS_2), ("syn2", MODE_3D, 8.0, 0.2, GOALS_2),
    ("lp", MODE_2D_Y, 5.0, 0.2, GOALS_2), ("ec", MODE_3D, 2.0, 0.2, GOALS_7),
    ("syn0", MODE_2D_Y, 8.0, 0.2, GOALS_2), ("ec", MODE_3D, 5.0, 0.1, GOALS_2),
    ("syn3", MODE_3D, 6.0, 0.2, GOALS_2), ("ec", MODE_2D_X, 10.0, 0.2, GOALS_2),
    ("lp", MODE_3D, 10.0, 0.2, GOALS_2), ("syn1", MODE_3D, 2.0, 0.2, GOALS_2),
    ("ec", MODE_3D_DAMPED, 8.0, 0.2, GOALS_2), ("lp", MODE_2D_X, 3.0, 0.2, GOALS_2),
    ("ec", MODE_3D, 4.0, 0.3, GOALS_2), ("syn2", MODE_2D_X, 6.0, 0.2, GOALS_2),
    ("syn4", MODE_3D, 10.0, 0.2, GOALS_2), ("ec", MODE_2D_Y, 1.0, 0.2, GOALS_2),
    ("lp", MODE_3D, 6.0, 0.2, GOALS_2), ("syn3", MODE_2D_Y, 3.0, 0.2, GOALS_2),
    ("ec", MODE_3D, 8.0, 0.2, GOALS_2), ("syn0", MODE_3D_DAMPED, 2.0, 0.2, GOALS_2),
    ("syn1", MODE_3D, 7.0, 0.3, GOALS_2), ("ec", MODE_2D_X, 6.0, 0.2, GOALS_2),
    ("lp", MODE_2D_X, 9.0, 0.2, GOALS_2), ("syn4", MODE_3D, 3.0, 0.1, GOALS_2),
    ("ec", MODE_2D_Y, 4.0, 0.2, GOALS_2), ("syn2", MODE_3D, 5.0, 0.2, GOALS_2),
)

# ---------------------------------------------------------------------------------- motions
_MOTIONS: dict[str, GroundMotion] = {}


def motions() -> dict[str, GroundMotion]:
    """:func:`benchmarks.study_motions.study_motions`, built once per process."""
    from benchmarks.study_motions import study_motions

    if not _MOTIONS:
        _MOTIONS.update(study_motions())
    return _MOTIONS


# ---------------------------------------------------------------------------------- lattice
@dataclass
class Lattice:
    """The analysed lattice points of one spectrum point (rows in the order run)."""

    key: tuple
    lower: float
    alpha: float
    states: list
    n: list[int]
    theta: list[float]
    overturned: list[bool]
    status: list[str]
    stop_at: list[float]  # NaN: run to the end
    seconds: list[float]

    def intensity(self, n) -> np.ndarray:
        return self.lower * np.exp(np.asarray(n, dtype=float) * STEP)

    def decided(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(n, known, exceeded) per row and limit state, a failed row knowing nothing."""
        k = len(self.states)
        known = np.zeros((len(self.n), k), bool)
        exc = np.zeros((len(self.n), k), bool)
        for i in range(len(self.n)):
            st = Status(self.status[i])
            if st is Status.FAILED:
                continue
            stop = None if math.isnan(self.stop_at[i]) else self.stop_at[i]
            known[i], exc[i] = classify({THETA_MAX: self.theta[i],
                                         OVERTURNED: self.overturned[i]}, self.states,
                                        self.alpha, stop, stopped=st is Status.STOPPED_AT_LIMIT)
        return np.asarray(self.n, dtype=int), known, exc

    def save(self, path: Path) -> None:
        np.savez_compressed(path, n=np.asarray(self.n, dtype=np.int64),
                            theta=np.asarray(self.theta), overturned=np.asarray(self.overturned),
                            status=np.asarray(self.status, dtype=str),
                            stop_at=np.asarray(self.stop_at), seconds=np.asarray(self.seconds),
                            meta=json.dumps({"key": list(self.key), "lower": self.lower,
                                             "alpha": self.alpha}))

    @classmethod
    def load(cls, path: Path) -> Lattice:
        d = np.load(path)
        meta = json.loads(str(d["meta"]))
        key = tuple(meta["key"][:4]) + (tuple(meta["key"][4]),)
        return cls(key, meta["lower"], meta["alpha"], parse_limit_states(key[4]),
                   d["n"].tolist(), d["theta"].tolist(), d["overturned"].tolist(),
                   d["status"].tolist(), d["stop_at"].tolist(), d["seconds"].tolist())


class _Builder:
    """Analyses one point's lattice, once per lattice index (a re-run with a higher goal
    replaces the row)."""

    def __init__(self, key: tuple):
        m, mode, R, tan_alpha, goals = key
        self.key = key
        self.motion = motions()[m]
        self.body = Cylinder(R, tan_alpha)
        self.states = parse_limit_states(goals)
        self.lower = uplift_intensity(self.motion, mode)
        self.analyze = make_analysis(self.body, self.motion, mode, rest_tilt=BASE.rest_tilt)
        self.rtol = BASE.rtol_for(MODES[mode][0])
        self.lat = Lattice(key, self.lower, self.body.alpha, self.states, [], [], [], [], [],
                           [])
        self.row: dict[int, int] = {}
        self.known: dict[int, np.ndarray] = {}
        self.exc: dict[int, np.ndarray] = {}

    def run(self, n: int, wanted: np.ndarray) -> None:
        """Analyse lattice point n for the limit states ``wanted`` (unless done)."""
        if n <= 0:
            return
        if n in self.row and not (wanted & ~self.known[n]).any():
            return
        if len(self.lat.n) >= MAX_LATTICE:
            raise RuntimeError(f"{self.key}: more than {MAX_LATTICE} lattice analyses")
        if n in self.row:
            wanted = wanted | self.known[n]
        stop = stop_for([s for s, w in zip(self.states, wanted, strict=True) if w],
                        self.body.alpha)
        intensity = self.lower * math.exp(n * STEP)
        t0 = time.process_time()
        out = self.analyze(intensity, stop, self.rtol)
        if out.status is Status.FAILED:
            out = self.analyze(intensity, stop, self.rtol * RETRY_RTOL_FACTOR)
        sec = time.process_time() - t0
        values = (float(out.theta_max), bool(out.overturned), Status(out.status).value,
                  math.nan if stop is None else float(stop), sec)
        if n in self.row:
            i = self.row[n]
            for lst, v in zip((self.lat.theta, self.lat.overturned, self.lat.status,
                               self.lat.stop_at, self.lat.seconds), values, strict=True):
                lst[i] = v
        else:
            self.row[n] = len(self.lat.n)
            self.lat.n.append(n)
            for lst, v in zip((self.lat.theta, self.lat.overturned, self.lat.status,
                               self.lat.stop_at, self.lat.seconds), values, strict=True):
                lst.append(v)
        if out.status is Status.FAILED:
            self.known[n] = np.zeros(len(self.states), bool)
            self.exc[n] = np.zeros(len(self.states), bool)
        else:
            self.known[n], self.exc[n] = classify(
                out, self.states, self.body.alpha, stop,
                stopped=out.status is Status.STOPPED_AT_LIMIT)

    def coarse(self) -> None:
        """Stage 1: the 0.1 % lattice until every goal exceeds at 60 % of its last window."""
        k = len(self.states)
        window = int(round(2 * Q.w / (COARSE * STEP)))
        recent: list[list[bool]] = [[] for _ in range(k)]
        open_ = np.ones(k, bool)
        n = COARSE
        while open_.any() and self.lower * math.exp(n * STEP) <= UPPER:
            self.run(n, open_)
            for j in np.flatnonzero(open_):
                recent[j].append(bool(self.known[n][j] and self.exc[n][j]))
                last = recent[j][-window:]
                if len(last) == window and np.mean(last) >= 0.6:
                    open_[j] = False
            n += COARSE

    def samples(self, j: int, period: int, lo: int, hi: int) -> tuple[np.ndarray, np.ndarray]:
        """(intensities, exceeded) of goal j on the lattice of ``period`` between indices
        lo and hi (inclusive), uplift and below counted as not exceeding."""
        ns, es = [], []
        for n in range(lo - lo % period, hi + 1, period):
            if n < lo:
                continue
            if n <= 0:
                ns.append(n)
                es.append(False)
            elif n in self.row and self.known[n][j]:
                ns.append(n)
                es.append(bool(self.exc[n][j]))
        return self.lower * np.exp(np.asarray(ns, float) * STEP), np.asarray(es, bool)

    def fine(self, period: int, first: Sequence[float], below: float, above: float
             ) -> list[float]:
        """Stages 2 and 3: per goal, the lattice of ``period`` around ``first`` (an estimate
        of I10), extended until I10 is judged inside it; returns I10 per goal (NaN where
        ``first`` is)."""
        out = []
        w = Q.w
        for j, guess in enumerate(first):
            if not math.isfinite(guess):
                out.append(math.nan)
                continue
            x = math.log(guess / self.lower) / STEP
            lo, hi = int(math.floor(x - below / STEP)), int(math.ceil(x + above / STEP))
            wanted = np.zeros(len(self.states), bool)
            wanted[j] = True
            ans = math.nan
            for _ in range(20):
                for n in range(max(lo, 1), hi + 1):
                    if n % period == 0:
                        self.run(n, wanted)
                ans, edge = judged_quantile(*self.samples(j, period, lo, hi),
                                            self.lower * math.exp(lo * STEP),
                                            self.lower * math.exp(hi * STEP))
                if edge == "low" and lo > -int(2 * w / STEP) - 2:
                    lo -= int(below / STEP)
                elif edge == "none":
                    if self.lower * math.exp(hi * STEP) > UPPER:
                        break
                    hi += int(above / STEP)
                else:
                    break
            out.append(ans)
        return out


def judged_quantile(x: np.ndarray, e: np.ndarray, lo: float, hi: float,
                    q: Quantity = Q) -> tuple[float, str]:
    """I_p of the sample (x, e) over the s whose window lies inside [lo, hi], and where it
    sits: "ok", "low" (P̂ >= p already at the lowest judged s: it may lie lower) or "none"
    (P̂ < p throughout: above the sample)."""
    a, b = math.log(lo) + q.w, math.log(hi) - q.w
    if b <= a or not x.size:
        return math.nan, "none"
    lx = np.log(x)
    cuts = np.concatenate([lx - q.w, lx + q.w + 2e-12])
    s = np.sort(np.concatenate([[a], cuts[(cuts > a) & (cuts <= b)]]))
    P = local_exceedance(x, e, np.exp(s), q.w)
    hit = np.flatnonzero(P >= q.p - 1e-12)
    if not hit.size:
        return math.nan, "none"
    return float(math.exp(s[hit[0]])), ("low" if hit[0] == 0 else "ok")


def build_lattice(key: tuple) -> Lattice:
    """Stages 1–3 of one point (see the module's docstring)."""
    b = _Builder(key)
    b.coarse()
    k = len(b.states)
    guess = []
    for j in range(k):
        x, e = b.samples(j, COARSE, -10 ** 6, 10 ** 7)
        guess.append(exceedance_quantile(x, e, Q.p, Q.w)[0])
    ref = b.fine(FINE, guess, FINE_BELOW, FINE_ABOVE)
    b.fine(FINEST, ref, FINEST_REACH, FINEST_REACH)
    return b.lat


def _code(path: Path) -> bytes:
    """A module's code without its docstrings and comments (what runs)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list):  # docstrings of modules, classes, functions, attributes
            node.body = [s for s in body if not (isinstance(s, ast.Expr) and isinstance(
                s.value, ast.Constant) and isinstance(s.value.value, str))] or [ast.Pass()]
    return ast.dump(tree, include_attributes=False).encode()


def _engine_digest() -> str:
    """What the lattice depends on: the dynamics code (docstrings and comments aside), the
    analyses' rtol and rest criterion, and the lattice plan."""
    root = Path(__file__).resolve().parents[1] / "src" / "rocking"
    h = hashlib.sha256()
    for f in sorted((root / "dynamics").rglob("*.py")):
        h.update(_code(f))
    h.update(json.dumps({k: BASE.to_dict()[k] for k in ("rtol", "rtol_damped", "rest_tilt")}
                        | {"plan": [STEP, COARSE, FINE, FINEST, FINE_BELOW, FINE_ABOVE,
                                    FINEST_REACH, UPPER]}, sort_keys=True).encode())
    return h.hexdigest()[:12]


def _key_name(key: tuple) -> str:
    m, mode, R, t, goals = key
    return f"{m}_{mode}_R{R:g}_t{t:g}_g{len(goals)}"


def _lattice_path(key: tuple, digest: str) -> Path:
    folder = results_dir() / "resolution_lattice"
    folder.mkdir(exist_ok=True)
    return folder / f"{_key_name(key)}_{digest}.npz"


def _lattice_worker(key: tuple, digest: str) -> str:
    t0 = time.process_time()
    lat = build_lattice(key)
    lat.save(_lattice_path(key, digest))
    return (f"  {_key_name(key)}: {len(lat.n)} analyses, {time.process_time() - t0:.0f} s "
            f"CPU")


def lattices(points, jobs: int) -> list[Lattice]:
    """The lattices of ``points``, computed (in ``jobs`` processes) or read from the cache."""
    digest = _engine_digest()
    todo = [k for k in points if not _lattice_path(k, digest).exists()]
    if todo:
        print(f"lattices of {len(todo)} points in {jobs} process(es)", flush=True)
        if jobs > 1:
            with ProcessPoolExecutor(jobs) as pool:
                for line in pool.map(_lattice_worker, todo, [digest] * len(todo)):
                    print(line, flush=True)
        else:
            for k in todo:
                print(_lattice_worker(k, digest), flush=True)
    return [Lattice.load(_lattice_path(k, digest)) for k in points]


# -------------------------------------------------------------------------------- reference
def _runs(ns: np.ndarray, gap: int) -> list[tuple[int, int]]:
    """Maximal runs [a, b] of sorted lattice indices whose neighbours lie at most ``gap``
    apart."""
    out: list[tuple[int, int]] = []
    for n in np.sort(ns):
        if out and n - out[-1][1] <= gap:
            out[-1] = (out[-1][0], int(n))
        else:
            out.append((int(n), int(n)))
    return out


def lattice_i10(lat: Lattice, j: int, period: int, own: np.ndarray, gap: int,
                q: Quantity = Q) -> tuple[float, float]:
    """I_p of limit state j on the lattice of ``period`` over the runs of the indices ``own``
    (that lattice's own analyses), each judged where its windows lie inside it; and the
    largest P̂ more than a window below it (the plateau's measure)."""
    n, known, exc = lat.decided()
    sel = (n % period == 0) & known[:, j]
    virtual = np.arange(-int(2 * q.w / STEP) - 2, 1)
    virtual = virtual[virtual % period == 0]
    x = lat.intensity(np.concatenate([virtual, n[sel]]))
    e = np.concatenate([np.zeros(virtual.size, bool), exc[sel, j]])
    own = np.concatenate([own, virtual]) if own.size and own.min() <= 2 * q.w / STEP + gap \
        else own
    best, below = math.nan, []
    profile = []
    for a, b in _runs(own, gap):
        lo, hi = lat.intensity(a - period), lat.intensity(b + period)
        ip, _ = judged_quantile(x, e, lo, hi, q)
        if math.isfinite(ip) and not ip >= best:
            best = ip
        s = np.exp(np.linspace(math.log(lo) + q.w, math.log(hi) - q.w, 200))
        if s.size and s[0] < s[-1]:
            profile.append((s, local_exceedance(x, e, s, q.w)))
    if math.isfinite(best):
        for s, P in profile:
            below += list(P[s < best * math.exp(-2 * q.w)])
    top = float(np.nanmax(below)) if below else 0.0
    return best, top


def reference_rows(lat: Lattice) -> list[dict]:
    """Per limit state: reference I10 (0.02 %), its 0.01 % value, I50, plateau, the 0.1 %
    lattice's I10 and the first exceedance on coarser grids."""
    n, known, exc = lat.decided()
    rows = []
    m, mode, R, t, goals = lat.key
    for j, ls in enumerate(lat.states):
        row = {"motion": m, "mode": mode, "R": R, "tan_alpha": t, "goals": len(goals),
               "limit_state": ls.name}
        fine = n[(n % FINE == 0) & (n % COARSE != 0) & known[:, j]]
        finest = n[(n % FINE != 0) & known[:, j]]
        if not fine.size:
            row.update(reference=math.nan, converged=False)
            rows.append(row)
            continue
        ref, top = lattice_i10(lat, j, FINE, fine, 2 * FINE)
        half, _ = lattice_i10(lat, j, FINE, fine, 2 * FINE, Quantity(p=0.5))
        ref01 = lattice_i10(lat, j, FINEST, finest, 2)[0] if finest.size else math.nan
        coarse, _ = lattice_i10(lat, j, COARSE, n[(n % COARSE == 0) & known[:, j]], COARSE)
        firsts = {}
        for g, period in GRIDS.items():
            sel = (n % period == 0) & known[:, j] & exc[:, j]
            firsts[f"first_{g}"] = float(lat.intensity(n[sel].min())) if sel.any() else math.nan
        row.update(reference=ref, i10_001=ref01,
                   conv_001=ref01 / ref - 1.0 if math.isfinite(ref01) else math.nan,
                   converged=bool(math.isfinite(ref01) and abs(ref01 / ref - 1) <= 0.01),
                   i10_coarse=coarse, i50=half, plateau=bool(top >= 0.5 * Q.p),
                   **firsts, **{f"ratio_{g}": firsts[f"first_{g}"] / ref for g in GRIDS},
                   lattice_analyses=len(lat.n), lattice_cpu_s=float(np.sum(lat.seconds)))
        rows.append(row)
    return rows


# ------------------------------------------------------------------------------- simulation
class Oracle:
    """An analysis function answered from a point's lattice: the nearest analysed point
    within half a 0.02 % step (the 0.1 % lattice within half its step where the fine ones
    did not go), its outcome cut at the ``stop_at`` asked; elsewhere, or where the lattice
    row stopped below the goal asked, a real analysis (kept). Counts analyses and the
    lattice's CPU seconds of those it stood for."""

    def __init__(self, lat: Lattice):
        self.lat = lat
        self.n = np.asarray(lat.n)
        order = np.argsort(self.n)
        self.sorted_n = self.n[order]
        self.order = order
        self.extra: dict[tuple[float, float | None], Outcome] = {}
        self.extra_seconds: dict[tuple[float, float | None], float] = {}
        self.real = None
        self.reset()

    def reset(self) -> None:
        self.analyses = 0
        self.seconds = 0.0

    def _nearest(self, x: float, reach: float) -> int | None:
        i = int(np.searchsorted(self.sorted_n, x))
        best = None
        for c in (i - 1, i):
            if 0 <= c < self.sorted_n.size and abs(self.sorted_n[c] - x) <= reach:
                if best is None or abs(self.sorted_n[c] - x) < abs(self.sorted_n[best] - x):
                    best = c
        return None if best is None else int(self.order[best])

    def __call__(self, intensity: float, stop_at: float | None, rtol: float) -> Outcome:
        self.analyses += 1
        x = math.log(intensity / self.lat.lower) / STEP
        i = self._nearest(x, FINE / 2 + 1e-9)
        if i is None:
            i = self._nearest(x, COARSE / 2 + 1e-9)
        if i is not None:
            out = self._cut(i, stop_at)
            if out is not None:
                self.seconds += self.lat.seconds[i]
                return out
        return self._real(intensity, stop_at, rtol)

    def _cut(self, i: int, stop_at: float | None) -> Outcome | None:
        lat = self.lat
        theta, over, st = lat.theta[i], lat.overturned[i], Status(lat.status[i])
        row_stop = lat.stop_at[i]
        if st is Status.FAILED:
            return Outcome(theta, over, st, "lattice")
        peak = math.pi / 2 if over else theta
        if st is Status.STOPPED_AT_LIMIT:
            # the row knows the response up to row_stop only
            if stop_at is None or stop_at > row_stop:
                return None
        if stop_at is not None and peak > stop_at:
            return Outcome(stop_at, False, Status.STOPPED_AT_LIMIT)
        return Outcome(theta, over, st)

    def _real(self, intensity: float, stop_at: float | None, rtol: float) -> Outcome:
        key = (intensity, stop_at)
        if key not in self.extra:
            if self.real is None:
                m, mode, R, t, _ = self.lat.key
                self.real = make_analysis(Cylinder(R, t), motions()[m], mode,
                                          rest_tilt=BASE.rest_tilt)
            t0 = time.process_time()
            self.extra[key] = self.real(intensity, stop_at, rtol)
            self.extra_seconds[key] = time.process_time() - t0
        self.seconds += self.extra_seconds[key]
        return self.extra[key]


def simulate(lat: Lattice, acc: Accuracy, goals, seeds: int) -> list[dict]:
    """The library's search on the lattice's oracle, ``seeds`` random offsets per point."""
    oracle = Oracle(lat)
    m, mode, R, t, _ = lat.key
    states = parse_limit_states(goals)
    out = []
    for s in range(seeds):
        oracle.reset()
        seed = cell_seed(f"{motions()[m].name}#{s}", R, t, mode)
        res = search_critical(oracle, states, lat.alpha, lower=lat.lower, upper=UPPER,
                              accuracy=acc, seed=seed)
        out.append({"intensity": dict(zip(res.limit_states, res.intensity.tolist(),
                                          strict=True)),
                    "analyses": oracle.analyses, "cpu": oracle.seconds})
    return out


# ----------------------------------------------------------------------------------- trade
def errors(ref: pd.DataFrame, runs: list[tuple[tuple, dict]]) -> dict:
    """Error statistics of answers against the reference, over the answers whose reference
    converged (the 0.01 % lattice's I10 within 1 % of the 0.02 % one's); runs are (point key,
    run)."""
    lookup = {(r.motion, r.mode, r.R, r.tan_alpha, r.goals, r.limit_state): r
              for r in ref.itertuples() if r.converged}
    err, analyses, cpu, steps = [], [], [], []
    for key, run in runs:
        m, mode, R, t, goals = key
        analyses.append(run["analyses"])
        cpu.append(run["cpu"])
        steps.append(run.get("steps", math.nan))
        for ls, value in run["intensity"].items():
            r = lookup.get((m, mode, R, t, len(goals), ls))
            if r is None or not math.isfinite(r.reference):
                continue
            err.append(value / r.reference - 1.0 if math.isfinite(value) else math.inf)
    e = np.abs(np.asarray(err))
    return {"answers": int(e.size), "within_2pct": float(np.mean(e <= 0.02)),
            "within_5pct": float(np.mean(e <= 0.05)), "err_median": float(np.median(e)),
            "err_p90": float(np.quantile(e, 0.9)), "analyses_per_point": float(np.mean(analyses)),
            "cpu_s_per_point": float(np.mean(cpu)), "steps_per_point": float(np.mean(steps))}


def sim_configs() -> list[Accuracy]:
    """The settings the simulation compares: the presets, then the default with one setting
    changed at a time (scan step, stratum width, reach, the confirmation)."""
    d = PRESETS["default"]
    out = [PRESETS["fast"], d, PRESETS["precise"]]
    for h, delta in ((0.01, 0.006), (0.015, 0.006), (0.025, 0.006), (0.04, 0.006)):
        out.append(d.with_(name=f"scan {100 * h:g} %, strata {100 * delta:g} %", scan_step=h,
                           local_step=delta, local_below=max(d.local_below, math.log1p(h))))
    for delta in (0.004, 0.008):
        out.append(d.with_(name=f"default, strata {100 * delta:g} %", local_step=delta))
    out.append(d.with_(name="default, reach -3/+1.5 %", local_below=0.03, local_above=0.015))
    out.append(d.with_(name="default without confirmation", confirm=False))
    return out


def sim_rows(lats: list[Lattice], ref: pd.DataFrame, seeds: int,
             configs: list[Accuracy] | None = None) -> list[dict]:
    rows = []
    for acc in configs or sim_configs():
        for goals in (GOALS_2, GOALS_7):
            runs = [(lat.key, r) for lat in lats if len(lat.key[4]) >= len(goals)
                    for r in simulate(lat, acc, goals, seeds)]
            if not runs:
                continue
            rows.append({"config": acc.name, "goals": len(goals), "scan_step": acc.scan_step,
                         "local_step": acc.local_step, "local_below": acc.local_below,
                         "local_above": acc.local_above, "points": len(runs) // seeds,
                         "seeds": seeds, **errors(ref, runs)})
            print(f"  sim {acc.name} ({len(goals)} goals): {rows[-1]}", flush=True)
    return rows


# ------------------------------------------------------------------------- real searches
BASELINE = "f651462"
"""The commit whose ``default`` preset the trade is measured against (main before issue 45:
a fixed 1 % scan, 0.5 % bisection and a 20-analysis refinement of near misses per point)."""

BASELINE_NAME = f"default before ({BASELINE}: 1 % scan + 20 refinement analyses)"
"""How the baseline is named in the tables."""

_REAL_SCRIPT = r"""
import json, sys, time
from rocking.dynamics import analysis
from rocking.dynamics.bodies import Cylinder
from rocking.spectra.critical import critical_intensity
sys.path.insert(0, {bench!r})
steps = [0]
_ground_response = analysis.ground_response
def counted(*args, **kwargs):  # integration steps: the work, whatever the machine's load
    r = _ground_response(*args, **kwargs)
    steps[0] += r.n_steps + r.n_rejected
    return r
analysis.ground_response = counted
from benchmarks.study_motions import study_motions
motions = study_motions()
jobs = json.loads(sys.argv[1])
configs = json.loads(sys.argv[2])
out = []
warm = set()
for m, mode, R, t, goals, upper in jobs:
    body = Cylinder(R, t)
    if mode not in warm:  # compilation (or the cache's load) is no search's cost
        critical_intensity(body, motions[m], list(goals)[:1], mode, accuracy="fast",
                           upper=1.5)
        warm.add(mode)
    for cfg in configs:
        steps[0] = 0
        t0 = time.process_time()
        res = critical_intensity(body, motions[m], list(goals), mode, accuracy=cfg,
                                 upper=upper)
        cpu = time.process_time() - t0
        out.append({{"key": [m, mode, R, t, list(goals)], "upper": upper,
                     "config": cfg if isinstance(cfg, str) else cfg.get("name", "custom"),
                     "intensity": dict(zip(res.limit_states, map(float, res.intensity))),
                     "analyses": res.n_analyses, "cpu": cpu, "steps": steps[0]}})
print(json.dumps(out))
"""


def real_searches(jobs, configs: list, src: Path | None = None) -> list[dict]:
    """Real searches of ``configs`` (preset names or accuracy dicts) on ``jobs`` (point
    keys, each with its search bound) in a subprocess running the library under ``src``
    (default this checkout's), with CPU seconds per search."""
    here = Path(__file__).resolve().parents[1]
    env = dict(os.environ)
    env["PYTHONPATH"] = str((src or here / "src").resolve())
    script = _REAL_SCRIPT.format(bench=str(here))
    args = [[*k[:4], list(k[4]), float(u)] for k, u in jobs]
    out = subprocess.run([sys.executable, "-c", script, json.dumps(args),
                          json.dumps(configs)], env=env, capture_output=True, text=True,
                         check=False)
    if out.returncode != 0:
        raise RuntimeError(f"real searches failed:\n{out.stderr[-3000:]}")
    rows = json.loads(out.stdout.strip().splitlines()[-1])
    for r in rows:
        r["key"] = (r["key"][0], r["key"][1], r["key"][2], r["key"][3], tuple(r["key"][4]))
    return rows


def side_by_side(jobs, configs: list, chunk: int = 6) -> list[dict]:
    """``configs`` of this checkout and the ``default`` of :data:`BASELINE` on ``jobs``,
    chunk by chunk in alternation (the load of the shared machine falls on both alike)."""
    runs: list[dict] = []
    for i in range(0, len(jobs), chunk):
        part = jobs[i:i + chunk]
        runs += real_searches(part, configs)
        for r in real_searches(part, ["default"], baseline_src()):
            r["config"] = BASELINE_NAME
            runs.append(r)
        print(f"  searches {min(i + chunk, len(jobs))}/{len(jobs)}", flush=True)
    return runs


def baseline_src() -> Path:
    """The library of :data:`BASELINE`, unpacked from git into a temporary folder."""
    root = Path(__file__).resolve().parents[1]
    dest = Path(tempfile.gettempdir()) / f"rocking-baseline-{BASELINE}"
    if not (dest / "src" / "rocking").exists():
        dest.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(["git", "-C", str(root), "archive", BASELINE, "src"],
                                 capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", str(dest)], input=archive, check=True)
    return dest / "src"


def trade_rows(points, ref: pd.DataFrame) -> tuple[list[dict], list[dict]]:
    """The presets as real searches beside the baseline's default (:func:`side_by_side`)."""
    runs = side_by_side([(k, UPPER) for k in points], ["fast", "default", "precise"])
    rows = []
    for config in dict.fromkeys(r["config"] for r in runs):
        for goals in (GOALS_2, GOALS_7):
            sel = [(r["key"], r) for r in runs
                   if r["config"] == config and len(r["key"][4]) == len(goals)]
            if sel:
                rows.append({"config": config, "goals": len(goals), "points": len(sel),
                             **errors(ref, sel)})
    return rows, runs


# ----------------------------------------------------------------------------------- paper
PAPER_GROUPS = (
    # (study, mode, tan α, goals, search bound, points in config/paper.yaml)
    ("elcentro", MODE_3D, 0.2, GOALS_7, 20.0, 220),
    ("elcentro", MODE_3D, 0.1, GOALS_2, 20.0, 220),
    ("elcentro", MODE_3D, 0.3, GOALS_2, 20.0, 220),
    ("elcentro", MODE_3D_DAMPED, 0.2, GOALS_2, 20.0, 220),
    ("elcentro", MODE_2D_X, 0.2, GOALS_2, 20.0, 220),
    ("elcentro", MODE_2D_Y, 0.2, GOALS_2, 20.0, 220),
    ("lomaprieta", MODE_3D, 0.2, GOALS_2, 60.0, 220),
    ("lomaprieta", MODE_2D_X, 0.2, GOALS_2, 60.0, 220),
    ("lomaprieta", MODE_2D_Y, 0.2, GOALS_2, 60.0, 220),
)
"""The spectrum points of config/paper.yaml (20 R × 11 motions per group)."""

PAPER_MOTIONS = {"elcentro": ("ec", "syn0", "syn3"), "lomaprieta": ("lp", "lpsyn0", "lpsyn1")}
PAPER_R = (1.0, 3.5, 6.0, 8.5, 10.0)
"""The sample of each group: three motions × five sizes of the study's R grid."""

PAPER_SEARCH_SECONDS = {"elcentro": 861.0, "lomaprieta": 339.0}
"""Wall seconds of each study's searches in the quiet paper run of 2026-11-28 (32 min 23 s
on 2 cores, docs/performance.md), made with :data:`BASELINE`'s default."""


def paper_rows() -> pd.DataFrame:
    """Per paper group: analyses, CPU seconds and integration steps per point of this
    default and the baseline's on the sample (:data:`PAPER_MOTIONS` × :data:`PAPER_R`)."""
    jobs = [((m, mode, R, t, goals), upper)
            for study, mode, t, goals, upper, _ in PAPER_GROUPS
            for m in PAPER_MOTIONS[study] for R in PAPER_R]
    runs = side_by_side(jobs, ["default"])
    group_of = {(m, mode, t, len(goals)): (study, mode, t, len(goals))
                for study, mode, t, goals, _, _ in PAPER_GROUPS for m in PAPER_MOTIONS[study]}
    rows = []
    for study, mode, t, goals, upper, count in PAPER_GROUPS:
        for config in ("default", BASELINE_NAME):
            sel = [r for r in runs if r["config"] == config and group_of.get(
                (r["key"][0], r["key"][1], r["key"][3], len(r["key"][4]))) ==
                (study, mode, t, len(goals))]
            rows.append({"study": study, "mode": mode, "tan_alpha": t, "goals": len(goals),
                         "upper": upper, "paper_points": count, "config": config,
                         "sample": len(sel),
                         "analyses_per_point": float(np.mean([r["analyses"] for r in sel])),
                         "cpu_s_per_point": float(np.mean([r["cpu"] for r in sel])),
                         "steps_per_point": float(np.mean([r["steps"] for r in sel]))})
    return pd.DataFrame(rows)


EXTRA_3D_POINTS = 440
"""Spectrum points the undamped 3D model under one component (modes 3d-x, 3d-y, issue 46)
adds to each study of config/paper.yaml: 20 R × 11 motions × 2 modes, two goals."""


def paper_estimate(groups: pd.DataFrame) -> pd.DataFrame:
    """Each study's searches in the paper run, from the sample: the timed wall seconds of
    the baseline's searches (:data:`PAPER_SEARCH_SECONDS`) scaled by the CPU seconds of the
    paper's points with this default over the baseline's (and by their integration steps,
    which the machine's load does not move); and with the 3d-x and 3d-y points priced as the
    study's 3D points with two goals (an assumption: the modes did not exist here)."""
    est = []
    for study, seconds in PAPER_SEARCH_SECONDS.items():
        g = groups[groups["study"] == study]
        cost = {c: float((d["paper_points"] * d["cpu_s_per_point"]).sum())
                for c, d in g.groupby("config")}
        work = {c: float((d["paper_points"] * d["steps_per_point"]).sum())
                for c, d in g.groupby("config")}
        ratio = cost["default"] / cost[BASELINE_NAME]
        three = g[(g["mode"] == MODE_3D) & (g["goals"] == 2) & (g["config"] == "default")]
        extra = EXTRA_3D_POINTS * float(three["cpu_s_per_point"].mean())
        est.append({"study": study, "search_cpu_s_before": cost[BASELINE_NAME],
                    "search_cpu_s_after": cost["default"], "cpu_ratio": ratio,
                    "steps_ratio": work["default"] / work[BASELINE_NAME],
                    "search_wall_s_before": seconds, "search_wall_s_after": seconds * ratio,
                    "search_wall_s_after_with_3d_x_y":
                        seconds * (cost["default"] + extra) / cost[BASELINE_NAME]})
    return pd.DataFrame(est)


def write_paper(groups: pd.DataFrame) -> pd.DataFrame:
    est = paper_estimate(groups)
    write_table("resolution_paper", groups, "The paper run's searches, sampled",
                "Real searches on a sample of config/paper.yaml's points (three motions × "
                "R = " + ", ".join(f"{r:g}" for r in PAPER_R) + " m per group), this "
                "default and the baseline's in alternation, chunk by chunk; CPU seconds on "
                "a 2-core machine shared with other work (load 11–15), integration steps "
                "whatever the load. The searches of each study in the paper run, estimated "
                "from the timed run of the baseline (El Centro 861 s, Loma Prieta 339 s of "
                "wall time on 2 quiet cores):\n\n" + est.to_markdown(index=False))
    return est


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and write the tables."""
    parser = argparse.ArgumentParser(prog="python -m benchmarks resolution")
    parser.add_argument("--points", type=int, default=len(POINTS),
                        help=f"first N points of the list (default all {len(POINTS)})")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes (lattices)")
    parser.add_argument("--seeds", type=int, default=16,
                        help="random offsets per point in the simulated trade")
    parser.add_argument("--stage", choices=("lattice", "sim", "trade", "paper", "all"),
                        default="all")
    args = parser.parse_args(argv)
    keys = list(POINTS[: args.points])
    lats = lattices(keys, args.jobs)
    ref = pd.DataFrame([r for lat in lats for r in reference_rows(lat)])
    write_table("resolution_reference", ref, "Reference I10 of the benchmark points",
                _reference_notes(ref, lats))
    print(ref.to_string(), flush=True)
    if args.stage in ("sim", "all"):
        sims = pd.DataFrame(sim_rows(lats, ref, args.seeds))
        write_table("resolution_trade_sim", sims, "Search settings simulated on the lattices",
                    f"The library's search with each setting, its analyses answered by the "
                    f"nearest lattice point (0.02 % lattice within ±0.01 %, 0.1 % within "
                    f"±0.05 %, else analysed), {args.seeds} random offsets per point; error "
                    f"against the reference I10; CPU seconds are the lattice analyses' own "
                    f"(each timed when the lattice was made, run to the largest goal it "
                    f"served: an upper bound of the search's).")
    if args.stage in ("trade", "all"):
        rows, runs = trade_rows(keys, ref)
        trade = pd.DataFrame(rows)
        (results_dir() / "resolution_trade_runs.json").write_text(
            json.dumps(runs, default=list))
        write_table("resolution_trade", trade, "The trade: presets against I10",
                    "Real searches, one offset per point, over the answers whose reference "
                    "converged; the presets and the baseline's default run chunk by chunk in "
                    "alternation (each in its own process, the kernels loaded before the "
                    "timing); CPU seconds per point on a 2-core machine shared with other "
                    "work (load 11–15: upper bounds), integration steps whatever the load.")
        print(trade.to_string(), flush=True)
    if args.stage in ("paper", "all"):
        groups = paper_rows()
        est = write_paper(groups)
        print(groups.to_string(), est.to_string(), sep="\n", flush=True)
    return 0


def _reference_notes(ref: pd.DataFrame, lats: list[Lattice]) -> str:
    ok = ref[np.isfinite(ref["reference"])]
    conv = ok["conv_001"].abs()
    lines = [
        "Motions: " + "; ".join(f"{k}: {v}" for k, v in MOTION_LABELS.items()) + ".",
        "",
        f"{len(lats)} points, {len(ref)} (point, limit state) answers, {len(ok)} with a "
        f"reference; {sum(len(lt.n) for lt in lats)} lattice analyses, "
        f"{sum(np.sum(lt.seconds) for lt in lats):.0f} CPU s.",
        f"Convergence, |I10(0.01 %)/I10(0.02 %) − 1|: median {conv.median():.4f}, 90th "
        f"percentile {conv.quantile(0.9):.4f}, largest {conv.max():.4f}; within 1 %: "
        f"{int((conv <= 0.01).sum())} of {conv.notna().sum()}.",
        f"First exceedance on the 1 % grid over I10: median {ok['ratio_1%'].median():.3f}, "
        f"10th–90th percentile {ok['ratio_1%'].quantile(0.1):.3f}–"
        f"{ok['ratio_1%'].quantile(0.9):.3f}; on the 0.1 % grid: median "
        f"{ok['ratio_0.1%'].median():.3f}, 10th–90th {ok['ratio_0.1%'].quantile(0.1):.3f}–"
        f"{ok['ratio_0.1%'].quantile(0.9):.3f}.",
        "",
    ]
    return "\n".join(lines)

