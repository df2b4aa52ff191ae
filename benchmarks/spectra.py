"""Benchmark of the critical-intensity search: accuracy versus cost, and the paper study's cost.

``python -m benchmarks spectra [--quick] [--only accuracy|cost]`` writes two tables
under ``docs/benchmarks/``:

- ``spectra.csv`` / ``.md`` (accuracy): error of I_crit against a converged reference (fixed
  0.5 % scan, 0.01 % brackets, rtol 1e-11) on El Centro, tan α = 0.2, 18 (R, mode) points,
  for the presets, for one tolerance at a time away from "default", and for the fixed and
  the adaptive scan, with all seven limit states and with the two of Figs 9, 11 and 12 (one
  search serves all limit states of a point, so the set searched changes the adaptive scan).
  Per configuration: median, 90th percentile and largest relative error over every answer
  reached in both, the fraction within 1 %, reached/not-reached mismatches, analyses and
  seconds per spectrum point. The reference takes long: it is computed once and cached in
  ``results/benchmarks/spectra_reference_<n>pts.json``, keyed by everything it depends on (motion,
  points, tolerances, the sources of the engine and of the search).
- ``spectra_cost.csv`` / ``.md`` (cost): per spectrum point, for R ∈ {0.5, 2, 4, 6, 10} m,
  every mode and the limit-state sets of ``config/paper.yaml``, on each ensemble's record and
  one synthetic pair of it: analyses, seconds, and the slowest analysis over the median one,
  with the fixed scan (the old default) and the "default" preset; then the paper study
  estimated as its spectrum points per (study, mode, limit-state set) × the mean seconds per
  point of that (ensemble, mode, set), on this machine's cores.

Seconds are wall time on a shared machine (other jobs may run): compare orders of magnitude;
analysis counts do not depend on the load.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import os
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from benchmarks._io import results_dir, write_table
from benchmarks.inputs import benchmark_records, with_synthetic
from rocking import __version__
from rocking.dynamics.bodies import Cylinder
from rocking.dynamics.names import MODEL_3D
from rocking.motions.motion import GroundMotion
from rocking.spectra.accuracy import PRESETS, Accuracy
from rocking.spectra.critical import MODES, make_analysis, uplift_intensity
from rocking.spectra.limit_states import DEFAULT_LIMIT_STATES
from rocking.spectra.modes import MODE_2D_X, MODE_2D_Y, MODE_3D, MODE_3D_DAMPED
from rocking.spectra.search import search_critical

TAN_ALPHA = 0.2
REFERENCE = Accuracy("reference", rtol=1e-11, rtol_damped=1e-9, scan_step=0.005,
                     bisection_tol=1e-4, scan="fixed", rest_tilt=0.0)
"""Reference: fixed 0.5 % scan steps, 0.01 % brackets, rtol 1e-11 (damped model 1e-9, where
its peaks agree with 1e-11 to ~1e-9), every micro-uplift followed to its end."""

FIXED = PRESETS["default"].with_(name="fixed 1 % scan, exact micro-uplift (before)",
                                 scan="fixed", scan_step=0.01, rest_tilt=0.0)
"""The "default" preset as it was before the micro-uplift rest criterion: a fixed 1 % scan,
every micro-uplift followed to its end."""

ADAPTIVE = PRESETS["default"].with_(name="adaptive 0.5–5 %, κ = 60", scan="adaptive",
                                    scan_step=0.005, scan_step_max=0.05, tilt_growth=60.0)
"""The adaptive scan measured against the default's fixed scan (the varied parameters of the
adaptive scan start from it)."""

GOALS_2 = ("overturning", "tilt:1/3")
"""The limit states of Figs 9, 11 and 12."""

COST_R = (0.5, 2.0, 4.0, 6.0, 10.0)
"""Sizes of the cost study [m]."""

ENGINE_SOURCES = ("dynamics", "spectra/search.py", "spectra/critical.py",
                  "spectra/limit_states.py")
"""Sources (under the package) whose change invalidates the cached reference."""


@dataclass(frozen=True)
class Point:
    """One spectrum point's answers and cost."""

    limit_states: tuple[str, ...]
    intensity: np.ndarray
    not_reached: np.ndarray
    non_monotonic: np.ndarray
    failed: np.ndarray
    n_analyses: int
    seconds: float
    analysis_seconds: tuple[float, ...] = ()

    def subset(self, names) -> Point:
        """The answers of some of its limit states (a search of more limit states finds the
        same windows for each: the reference's fixed scan does not depend on the set)."""
        idx = [self.limit_states.index(n) for n in names]
        return Point(tuple(names), self.intensity[idx], self.not_reached[idx],
                     self.non_monotonic[idx], self.failed[idx], self.n_analyses, self.seconds)


def _rest_tilt(acc: Accuracy, mode: str) -> float | None:
    """The rest tilt of ``acc`` in ``mode``. :data:`FIXED` stands for the engine before the
    micro-uplift criterion, which only changed the undamped 3D model: its other models keep
    their own (unchanged) rest tilts."""
    if acc == FIXED and MODES[mode][0] != MODEL_3D:
        return None
    return acc.rest_tilt


def solve_point(body: Cylinder, motion: GroundMotion, limit_states, mode: str,
                acc: Accuracy) -> Point:
    """Critical intensities of one point, each analysis timed (the search of
    :func:`rocking.spectra.critical.critical_intensity`, instrumented)."""
    analyze = make_analysis(body, motion, mode, rest_tilt=_rest_tilt(acc, mode))
    times: list[float] = []

    def timed(intensity, stop_at, rtol):
        t0 = time.perf_counter()
        out = analyze(intensity, stop_at, rtol)
        times.append(time.perf_counter() - t0)
        return out

    t0 = time.perf_counter()
    res = search_critical(timed, limit_states, body.alpha, lower=uplift_intensity(motion, mode),
                          accuracy=acc, rtol=acc.rtol_for(MODES[mode][0]))
    return Point(res.limit_states, res.intensity, res.not_reached, res.non_monotonic,
                 res.failed, res.n_analyses, time.perf_counter() - t0, tuple(times))


# --------------------------------------------------------------------------------- reference
def _digest(motion: GroundMotion) -> str:
    h = hashlib.sha256()
    for a in (motion.ax, motion.ay):
        h.update(np.ascontiguousarray(a, dtype=np.float64).tobytes())
    h.update(repr(motion.dt).encode())
    return h.hexdigest()[:16]


def _sources_digest() -> str:
    """sha256 of the engine's and the search's sources (a change invalidates the cache)."""
    root = Path(__file__).resolve().parents[1]
    h = hashlib.sha256(__version__.encode())
    for rel in ENGINE_SOURCES:
        p = root / rel
        for f in sorted(p.rglob("*.py")) if p.is_dir() else [p]:
            h.update(f.relative_to(root).as_posix().encode())
            h.update(f.read_bytes())
    return h.hexdigest()[:16]


def _reference(points, motion: GroundMotion, refresh: bool) -> list[Point]:
    """Reference answers of every point, from the cache when its key matches."""
    key = {"motion": motion.name, "motion_sha256": _digest(motion),
           "points": [list(p) for p in points], "tan_alpha": TAN_ALPHA,
           "limit_states": list(DEFAULT_LIMIT_STATES), "accuracy": REFERENCE.to_dict(),
           "sources": _sources_digest()}
    # one file per point set, so that a --quick smoke run never replaces the full reference
    path = results_dir() / f"spectra_reference_{len(points)}pts.json"
    if path.exists() and not refresh:
        cached = json.loads(path.read_text())
        if cached.get("key") == key:
            print(f"reference from {path}", flush=True)
            return [_point_from_json(p) for p in cached["points"]]
        print(f"{path} was made for another motion, grid or engine: recomputing", flush=True)
    print(f"reference: {len(points)} points (takes long; cached afterwards)", flush=True)
    out = []
    for R, mode in points:
        out.append(solve_point(Cylinder(R, TAN_ALPHA), motion, DEFAULT_LIMIT_STATES, mode,
                               REFERENCE))
        print(f"  reference {mode} R={R:g}: {out[-1].n_analyses} analyses, "
              f"{out[-1].seconds:.1f} s", flush=True)
    path.write_text(json.dumps({"key": key, "points": [_point_to_json(p) for p in out]},
                               indent=1))
    return out


def _point_to_json(p: Point) -> dict:
    return {"limit_states": list(p.limit_states), "intensity": p.intensity.tolist(),
            "not_reached": p.not_reached.tolist(), "non_monotonic": p.non_monotonic.tolist(),
            "failed": p.failed.tolist(), "n_analyses": p.n_analyses, "seconds": p.seconds}


def _point_from_json(d: dict) -> Point:
    return Point(tuple(d["limit_states"]), np.array(d["intensity"], dtype=float),
                 np.array(d["not_reached"], dtype=bool),
                 np.array(d["non_monotonic"], dtype=bool), np.array(d["failed"], dtype=bool),
                 int(d["n_analyses"]), float(d["seconds"]))


# ---------------------------------------------------------------------------------- accuracy
def _variants(quick: bool) -> list[tuple[str, Accuracy]]:
    """The presets, the fixed scan of before, one tolerance at a time away from "default",
    and the adaptive scan's own parameters."""
    base = PRESETS["default"]
    out: list[tuple[str, Accuracy]] = [("preset", PRESETS[k])
                                       for k in ("fast", "default", "precise")]
    out.append(("before", FIXED))
    out.append(("adaptive", ADAPTIVE))
    if quick:
        return out
    out += [("fixed scan_step", base.with_(scan_step=s)) for s in (0.005, 0.0075, 0.02, 0.05,
                                                                   0.1)]
    out += [("scan_step", ADAPTIVE.with_(scan_step=s)) for s in (0.0035, 0.0075)]
    out += [("scan_step_max", ADAPTIVE.with_(scan_step_max=s)) for s in (0.03, 0.1)]
    out += [("tilt_growth", ADAPTIVE.with_(tilt_growth=k)) for k in (40.0, 80.0, 120.0)]
    out.append(("precise, fixed", PRESETS["precise"].with_(
        name="precise with its former fixed 0.75 % scan", scan="fixed", scan_step=0.0075)))
    out += [("bisection_tol", base.with_(bisection_tol=t)) for t in (0.001, 0.02)]
    # The damped model keeps its decade above the undamped ones (as in the presets).
    ratio = base.rtol_damped / base.rtol
    out += [("rtol", base.with_(rtol=r, rtol_damped=r * ratio)) for r in (1e-6, 1e-8, 1e-10)
            if r != base.rtol]
    return out


def _label(varied: str, acc: Accuracy) -> str:
    if varied in ("preset", "before", "adaptive", "precise, fixed"):
        return acc.name
    if varied == "rtol":
        return f"rtol={acc.rtol:g} (damped {acc.rtol_damped:g})"
    if varied == "fixed scan_step":
        return f"fixed scan, scan_step={acc.scan_step:g}"
    return f"{varied}={getattr(acc, varied):g}"


def _accuracy_points(quick: bool) -> list[tuple[float, str]]:
    if quick:
        return [(R, m) for m in (MODE_3D, MODE_2D_X) for R in (1.0, 5.0)]
    many, few = (0.5, 1.0, 2.0, 3.0, 5.0, 10.0), (1.0, 3.0, 10.0)
    return ([(R, MODE_3D) for R in many] + [(R, MODE_2D_X) for R in many]
            + [(R, MODE_2D_Y) for R in few] + [(R, MODE_3D_DAMPED) for R in few])


def _run(points, motion, states, acc: Accuracy) -> list[Point]:
    return [solve_point(Cylinder(R, TAN_ALPHA), motion, states, mode, acc)
            for R, mode in points]


def _errors(results, reference) -> tuple[np.ndarray, int]:
    """Relative errors of every answer reached in both, and the reached/not mismatches."""
    errs, mismatched = [np.zeros(0)], 0
    for r, ref in zip(results, reference, strict=True):
        ref = ref.subset(r.limit_states)
        both = ~r.not_reached & ~ref.not_reached
        mismatched += int(np.sum(r.not_reached != ref.not_reached))
        errs.append(np.abs(r.intensity[both] - ref.intensity[both]) / ref.intensity[both])
    return np.concatenate(errs), mismatched


def _accuracy_rows(motion, quick: bool, refresh: bool) -> list[dict]:
    points = _accuracy_points(quick)
    reference = _reference(points, motion, refresh)
    rows = [_row("reference", REFERENCE, "7", reference, np.zeros(0), 0)]
    for varied, acc in _variants(quick):
        label = _label(varied, acc)
        goal_sets = [("7", DEFAULT_LIMIT_STATES)]
        if varied in ("preset", "before", "adaptive"):
            goal_sets.append(("2", GOALS_2))
        for goals, states in goal_sets:
            res = _run(points, motion, states, acc)
            err, mism = _errors(res, reference)
            rows.append(_row(label, acc, goals, res, err, mism))
            r = rows[-1]
            print(f"  {label}, {goals} goals: median err {r['err_median']:.2e}, p90 "
                  f"{r['err_p90']:.2e}, {r['analyses_per_point']:.1f} analyses/pt, "
                  f"{r['seconds_per_point']:.2f} s/pt", flush=True)
            if varied == "preset" and goals == "7":  # the presets also mode by mode
                for mode in dict.fromkeys(m for _, m in points):
                    sel = [i for i, (_, m) in enumerate(points) if m == mode]
                    e, mm = _errors([res[i] for i in sel], [reference[i] for i in sel])
                    rows.append(_row(label, acc, goals, [res[i] for i in sel], e, mm, mode))
    return rows


def _row(label, acc: Accuracy, goals: str, res, err, mism, mode="all") -> dict:
    n = len(res)
    return {
        "config": label,
        "goals": goals,
        "mode": mode,
        "scan": acc.scan,
        "scan_step": acc.scan_step,
        "scan_step_max": acc.scan_step_max if acc.scan == "adaptive" else math.nan,
        "tilt_growth": acc.tilt_growth if acc.scan == "adaptive" else math.nan,
        "bisection_tol": acc.bisection_tol,
        "rtol": acc.rtol,
        "rtol_damped": acc.rtol_damped,
        "points": n,
        "answers": int(err.size),
        "err_median": float(np.median(err)) if err.size else math.nan,
        "err_p90": float(np.quantile(err, 0.9)) if err.size else math.nan,
        "err_max": float(np.max(err)) if err.size else math.nan,
        "within_1pct": float(np.mean(err <= 0.01)) if err.size else math.nan,
        "reached_mismatch": mism,
        "non_monotonic": int(sum(int(r.non_monotonic.sum()) for r in res)),
        "failed": int(sum(int(r.failed.sum()) for r in res)),
        "analyses_per_point": sum(r.n_analyses for r in res) / n,
        "seconds_per_point": sum(r.seconds for r in res) / n,
    }


# -------------------------------------------------------------------------------------- cost
def paper_goal_sets(path: str | Path) -> tuple[dict, dict[str, dict[tuple[str, str], int]]]:
    """Limit-state sets per mode and spectrum points of a study configuration.

    Returns
    -------
    sets : dict
        mode → list of distinct limit-state sets (tuples of names) some run asks for.
    points : dict
        study → {(mode, "|".join(set)): spectrum points}, over every requested tan α.
    """
    import yaml

    from rocking.config.study import StudySpec

    cfg = yaml.safe_load(Path(path).read_text())
    sets: dict[str, list[tuple[str, ...]]] = {}
    points: dict[str, dict[tuple[str, str], int]] = {}
    for name in cfg["studies"]:
        spec = StudySpec.from_config(cfg, name).spectra
        n_motions = spec.ensemble.n_motions
        n_R = len(spec.R)
        plan = spec.plan
        counts: dict[tuple[str, str], int] = {}
        for mode in plan.modes:
            for t in plan.tan_alpha:
                states = tuple(plan.limit_states_of(mode, t))
                if not states:
                    continue
                sets.setdefault(mode, [])
                if states not in sets[mode]:
                    sets[mode].append(states)
                k = (mode, "|".join(states))
                counts[k] = counts.get(k, 0) + n_motions * n_R
        points[name] = counts
    return sets, points


def _cost_rows(records, sets, quick: bool) -> list[dict]:
    Rs = (0.5, 4.0, 10.0) if quick else COST_R
    rows = []
    for ensemble, (record, _) in records.items():
        motions = [record] if quick else with_synthetic(record)
        for acc in (FIXED, PRESETS["default"], ADAPTIVE):
            for mode, mode_sets in sets.items():
                for states in mode_sets:
                    for motion in motions:
                        for R in Rs:
                            p = solve_point(Cylinder(R, TAN_ALPHA), motion, states, mode, acc)
                            t = np.array(p.analysis_seconds)
                            rows.append({
                                "ensemble": ensemble, "motion": motion.name, "scan": acc.name,
                                "mode": mode, "goals": len(states),
                                "limit_states": "|".join(states), "R": R,
                                "analyses": p.n_analyses, "seconds": p.seconds,
                                "slowest_over_median": float(t.max() / np.median(t))
                                if t.size else math.nan,
                            })
                    last = pd.DataFrame(rows[-len(motions) * len(Rs):])
                    print(f"  cost {ensemble} {acc.name} {mode} {len(states)} goals: "
                          f"{last['analyses'].mean():.1f} analyses/pt, "
                          f"{last['seconds'].mean():.2f} s/pt", flush=True)
    return rows


def _estimate(cost: pd.DataFrame, points: dict) -> pd.DataFrame:
    """Paper study seconds = Σ points × mean s/pt of (ensemble, mode, limit-state set)."""
    ensembles = list(dict.fromkeys(cost["ensemble"]))
    rows = []
    for i, (study, counts) in enumerate(points.items()):
        # the studies' ensembles in order; the first record stands in for any extra one
        ensemble = ensembles[min(i, len(ensembles) - 1)]
        for (mode, states), n in counts.items():
            for scan in dict.fromkeys(cost["scan"]):
                sel = cost[(cost["ensemble"] == ensemble) & (cost["mode"] == mode)
                           & (cost["limit_states"] == states) & (cost["scan"] == scan)]
                rows.append({"study": study, "ensemble": ensemble, "mode": mode,
                             "limit_states": states, "points": n, "scan": scan,
                             "analyses_per_point": sel["analyses"].mean(),
                             "seconds_per_point": sel["seconds"].mean(),
                             "core_seconds": n * sel["seconds"].mean()})
    return pd.DataFrame(rows)


def _cost_tables(records, paper: Path, quick: bool) -> None:
    sets, points = paper_goal_sets(paper)
    cost = pd.DataFrame(_cost_rows(records, sets, quick))
    summary = (cost.groupby(["ensemble", "scan", "mode", "goals"], sort=False)
               .agg(points=("R", "size"), analyses_per_point=("analyses", "mean"),
                    seconds_per_point=("seconds", "mean"),
                    slowest_over_median_max=("slowest_over_median", "max"))
               .reset_index())
    est = _estimate(cost, points)
    cores = os.cpu_count() or 1
    totals = est.groupby("scan", sort=False)["core_seconds"].sum()
    lines = [f"{scan}: {s / 3600:.2f} core-hours, {s / 60 / cores:.0f} min on {cores} cores"
             for scan, s in totals.items()]
    labels = "; ".join(f"{k}: {v[1]}" for k, v in records.items())
    notes = (f"Motions: {labels}, each with one RDK pair fitted to it (seed 2017); tan α = "
             f"{TAN_ALPHA}; limit-state sets as {paper} asks for them per mode. "
             f"`slowest_over_median` is the slowest analysis of a point over its median "
             f"analysis.\n\nPaper study ({paper}: points per study, mode and limit-state set "
             f"× the mean seconds per point of its ensemble's motions here; tan α 0.1 and 0.3 "
             f"assumed to cost like 0.2; spectra stores only, without Fig 7's map and the "
             f"figures):\n\n" + "\n".join(f"- {x}" for x in lines) + "\n\nPer (ensemble, "
             "scan, mode, goals):\n\n" + summary.to_markdown(index=False) + "\n\nEstimate "
             "per study:\n\n" + est.to_markdown(index=False) + "\n\nPer point:")
    write_table("spectra_cost", cost, "Critical-intensity search: cost per spectrum point",
                notes)


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and write the tables."""
    parser = argparse.ArgumentParser(prog="python -m benchmarks spectra")
    parser.add_argument("--quick", action="store_true",
                        help="fewer points and configurations (smoke run)")
    parser.add_argument("--only", choices=("accuracy", "cost"),
                        help="run one of the two studies")
    parser.add_argument("--refresh-reference", action="store_true",
                        help="recompute the cached reference even if its key matches")
    parser.add_argument("--paper-config", default="config/paper.yaml",
                        help="study configuration whose limit-state sets and points the cost "
                             "study uses (default config/paper.yaml)")
    args = parser.parse_args(argv)
    records = benchmark_records()
    motion, label = next(iter(records.values()))
    # Warm-up: compile (or load cached) kernels outside the timed runs.
    for mode in (MODE_3D, MODE_3D_DAMPED, MODE_2D_X):
        solve_point(Cylinder(5.0, TAN_ALPHA), motion, ["tilt:0.1"], mode, PRESETS["fast"])
    if args.only in (None, "accuracy"):
        print("accuracy study", flush=True)
        df = pd.DataFrame(_accuracy_rows(motion, args.quick, args.refresh_reference))
        notes = (
            f"Motion: {label}, unscaled pair normalized by its vector PGA {motion.pga_g:.4f} "
            f"g; cylinder tan α = {TAN_ALPHA}; goals 7: {', '.join(DEFAULT_LIMIT_STATES)} "
            f"(one search serves all seven), goals 2: {', '.join(GOALS_2)} (Figs 9, 11, 12). "
            f"Errors are |I − I_ref|/I_ref over every answer reached in both, against the "
            f"reference (rtol {REFERENCE.rtol:g}, fixed relative scan step "
            f"{REFERENCE.scan_step:g}, bisection tolerance {REFERENCE.bisection_tol:g}). "
            f"'{FIXED.name}' is the default preset with the fixed scan it used before; other "
            f"rows vary one tolerance of the 'default' preset at a time.")
        write_table("spectra", df, "Critical-intensity search: accuracy and cost", notes)
    if args.only in (None, "cost"):
        paper = Path(args.paper_config)
        if paper.is_file():
            print("cost study", flush=True)
            _cost_tables(records, paper, args.quick)
        else:
            print(f"no {paper}: cost study skipped (run from the repository root)", flush=True)
    return 0
