"""``python -m benchmarks monitors``: what the vertical forcing and the validity
monitors cost per analysis, against source trees of earlier commits.

Each tree (``--tree NAME=DIR``, DIR a ``src`` folder, e.g. from ``git archive <commit> src |
tar -x -C /tmp/base``; this tree is always one of them, named ``this``) runs the dynamics
benchmark's cases (:func:`benchmarks.dynamics._cases`, default rtol, summary-only
analyses; a tree whose ``ground_response`` takes ``monitors`` runs without them, as a study
without μ or a sliding goal does, unless named by ``--monitored NAME``: then the same tree
can be listed twice, with and without) in one persistent process per tree; for each case the
trees take turns, a few
analyses at a time, in a rotated order every round (interleaved: a shared machine's load
then falls on all of them alike). Per case and tree:
accepted steps, θmax to the bit (hex) and status, which must agree with the first tree, and
the CPU time of one analysis (``time.process_time``), best and median over rounds × repeats,
with the ratio to the first tree. Writes ``docs/benchmarks/monitors.csv`` and ``.md``
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

from benchmarks._io import write_table

WORKER = r"""
import inspect, json, os, sys, time
from benchmarks.dynamics import _cases
from rocking.dynamics.analysis import free_vibration, ground_response
kw = ({"monitors": os.environ["ROCKING_BENCH_MONITORS"] == "1"}
      if "monitors" in inspect.signature(ground_response).parameters else {})
calls = []
for name, model, body, motion, scale in _cases():
    if model == "3d-free":
        def fn(body=body):
            return free_vibration(body, 0.5 * body.alpha, 1e-8, duration=20.0, history=False)
    else:
        def fn(body=body, motion=motion, model=model, scale=scale):
            return ground_response(body, motion, model=model, scale=scale, history=False,
                                   **kw)
    fn()
    calls.append((name + " [" + model + "]", fn))
print(json.dumps([c for c, _ in calls]), flush=True)
for line in sys.stdin:
    i, reps = (int(v) for v in line.split())
    fn = calls[i][1]
    ts = []
    for _ in range(reps):
        t0 = time.process_time()
        r = fn()
        ts.append(time.process_time() - t0)
    print(json.dumps({"t": ts, "steps": int(r.n_steps), "theta_max": float(r.theta_max).hex(),
                      "status": r.status.value}), flush=True)
"""
"""A persistent worker per tree: builds the cases, warms them up, then times ``reps`` calls
of case ``i`` per line read; written against the API every compared tree has."""


def this_tree() -> str:
    """The ``src`` folder this package is imported from."""
    return str(Path(__file__).resolve().parents[2])


def measure(trees: dict[str, str], rounds: int, repeats: int,
            monitored: frozenset[str] = frozenset()) -> tuple[pd.DataFrame, list]:
    """Interleaved runs of every tree: one persistent process per tree, the trees in turn
    (rotated order) for each case and round, ``repeats`` calls each time, so that a shared
    machine's load falls on all trees alike. Trees in ``monitored`` ask for the validity
    monitors (where their API can say so). Returns the table and the 1-min load averages
    before and after each round."""
    names = list(trees)
    procs = {n: subprocess.Popen([sys.executable, "-c", WORKER], text=True,
                                 env=dict(os.environ, PYTHONPATH=trees[n],
                                          ROCKING_BENCH_MONITORS=str(int(n in monitored))),
                                 stdin=subprocess.PIPE, stdout=subprocess.PIPE)
             for n in names}
    try:
        cases = {n: json.loads(p.stdout.readline()) for n, p in procs.items()}
        case_names = cases[names[0]]
        if any(c != case_names for c in cases.values()):
            raise RuntimeError(f"the trees run different cases: {cases}")
        times: dict[tuple[str, str], list[float]] = {}
        facts: dict[tuple[str, str], tuple] = {}
        loads = [os.getloadavg()[0]]
        for r in range(rounds):
            for i, case in enumerate(case_names):
                for name in names[r % len(names):] + names[:r % len(names)]:
                    procs[name].stdin.write(f"{i} {repeats}\n")
                    procs[name].stdin.flush()
                    v = json.loads(procs[name].stdout.readline())
                    times.setdefault((case, name), []).extend(v["t"])
                    facts[case, name] = (v["steps"], v["theta_max"], v["status"])
            loads.append(os.getloadavg()[0])
    finally:
        for p in procs.values():
            p.stdin.close()
            p.wait()
    rows = []
    for case in case_names:
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
    parser = argparse.ArgumentParser(prog="python -m benchmarks monitors")
    parser.add_argument("--tree", action="append", default=[], metavar="NAME=DIR",
                        help="a source tree to compare (its src folder); first is the base")
    parser.add_argument("--monitored", action="append", default=[], metavar="NAME",
                        help="a tree whose analyses ask for the validity monitors")
    parser.add_argument("--rounds", type=int, default=40)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    trees = {}
    for spec in args.tree:
        name, sep, path = spec.partition("=")
        if not sep or not Path(path, "rocking").is_dir():
            parser.error(f"--tree must be NAME=DIR with DIR/rocking a package, got {spec!r}")
        trees[name] = path
    trees.setdefault("this", this_tree())
    unknown = sorted(set(args.monitored) - set(trees))
    if unknown:
        parser.error(f"--monitored names no tree: {unknown}")
    df, loads = measure(trees, args.rounds, args.repeats, frozenset(args.monitored))
    when = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    notes = (
        f"{when}. Trees: " + ", ".join(f"{k} = {v}" for k, v in trees.items())
        + (f"; asking for the monitors: {', '.join(args.monitored)}" if args.monitored
           else "")
        + f". {args.rounds} rounds × {args.repeats} repeats per tree and case, interleaved "
        "(one process per tree, the trees in turn, rotated order), CPU time of one "
        "summary-only analysis after warm-up; ratios against the first tree. 1-min load "
        f"average over the rounds: {min(loads):.1f}–{max(loads):.1f} "
        f"(mean {sum(loads) / len(loads):.1f})."
    )
    print(write_table("monitors", df, "Cost of the vertical forcing and the validity monitors",
                      notes))
    print(df.to_string(index=False))
    return 0
