"""``python -m rocking.benchmarks monitors``: what the vertical forcing and the validity
monitors cost per analysis, against source trees of earlier commits.

Each tree (``--tree NAME=DIR``, DIR a ``src`` folder, e.g. from ``git archive <commit> src |
tar -x -C /tmp/base``; this tree is always one of them, named ``this``) runs the dynamics
benchmark's cases (:func:`rocking.benchmarks.dynamics._cases`, default rtol, summary-only
analyses) in a fresh process, the trees in turn and in a rotated order every round
(interleaved: a shared machine's load then falls on all of them alike). Per case and tree:
accepted steps, θmax to the bit (hex) and status, which must agree with the first tree, and
the CPU time of one analysis (``time.process_time``), best and median over rounds × repeats,
with the ratio to the first tree. Writes ``results/benchmarks/monitors.csv`` and ``.md``
with the date and the load averages seen.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

import pandas as pd

from ._io import write_table

WORKER = r"""
import json, sys, time
from rocking.benchmarks.dynamics import _cases
from rocking.dynamics.analysis import free_vibration, ground_response
reps = int(sys.argv[1])
out = {}
for name, model, body, motion, scale in _cases():
    if model == "3d-free":
        def fn():
            return free_vibration(body, 0.5 * body.alpha, 1e-8, duration=20.0, history=False)
    else:
        def fn():
            return ground_response(body, motion, model=model, scale=scale, history=False)
    r = fn()
    r = fn()
    ts = []
    for _ in range(reps):
        t0 = time.process_time()
        r = fn()
        ts.append(time.process_time() - t0)
    out[name + " [" + model + "]"] = {"t": ts, "steps": int(r.n_steps),
                                     "theta_max": float(r.theta_max).hex(),
                                     "status": r.status.value}
print(json.dumps(out))
"""
"""The per-process measurement; written against the API every compared tree has."""


def _this_tree() -> str:
    return str(Path(__file__).resolve().parents[2])


def _round(tree: str, repeats: int) -> dict:
    env = dict(os.environ, PYTHONPATH=tree)
    out = subprocess.run([sys.executable, "-c", WORKER, str(repeats)], env=env,
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def measure(trees: dict[str, str], rounds: int, repeats: int) -> tuple[pd.DataFrame, list]:
    """Interleaved runs of every tree; (table, 1-min load averages before and after each
    round)."""
    names = list(trees)
    for name in names:  # fill each tree's numba cache before timing
        _round(trees[name], 1)
    times: dict[tuple[str, str], list[float]] = {}
    facts: dict[tuple[str, str], tuple] = {}
    loads = [os.getloadavg()[0]]
    for r in range(rounds):
        for name in names[r % len(names):] + names[:r % len(names)]:
            for case, v in _round(trees[name], repeats).items():
                times.setdefault((case, name), []).extend(v["t"])
                facts[case, name] = (v["steps"], v["theta_max"], v["status"])
        loads.append(os.getloadavg()[0])
    rows = []
    for case in dict.fromkeys(c for c, _ in facts):
        b_best = min(times[case, names[0]])
        b_med = statistics.median(times[case, names[0]])
        for name in names:
            t = times[case, name]
            steps, th, status = facts[case, name]
            rows.append({
                "case": case, "tree": name, "steps": steps, "theta_max_hex": th,
                "status": status, "same_as_first": (steps, th, status) == facts[case, names[0]],
                "ms_best": 1e3 * min(t), "ms_median": 1e3 * statistics.median(t),
                "best_vs_first": min(t) / b_best - 1.0,
                "median_vs_first": statistics.median(t) / b_med - 1.0, "n": len(t),
            })
    return pd.DataFrame(rows), loads


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m rocking.benchmarks monitors")
    parser.add_argument("--tree", action="append", default=[], metavar="NAME=DIR",
                        help="a source tree to compare (its src folder); first is the base")
    parser.add_argument("--rounds", type=int, default=8)
    parser.add_argument("--repeats", type=int, default=21)
    args = parser.parse_args(argv)
    trees = {}
    for spec in args.tree:
        name, sep, path = spec.partition("=")
        if not sep or not Path(path, "rocking").is_dir():
            parser.error(f"--tree must be NAME=DIR with DIR/rocking a package, got {spec!r}")
        trees[name] = path
    trees.setdefault("this", _this_tree())
    df, loads = measure(trees, args.rounds, args.repeats)
    when = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    notes = (
        f"{when}. Trees: " + ", ".join(f"{k} = {v}" for k, v in trees.items())
        + f". {args.rounds} rounds × {args.repeats} repeats per tree, interleaved (rotated "
        "order), fresh process per round, CPU time of one summary-only analysis after "
        "warm-up; ratios against the first tree. 1-min load average before and after each "
        f"round: {', '.join(f'{x:.1f}' for x in loads)}."
    )
    print(write_table("monitors", df, "Cost of the vertical forcing and the validity monitors",
                      notes))
    print(df.to_string(index=False))
    return 0
