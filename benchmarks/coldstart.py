"""Cold start: seconds to the first spectrum point of each mode with an empty numba cache.

``python -m benchmarks coldstart`` writes ``docs/benchmarks/coldstart.csv`` and
``.md``. Each scenario runs in a fresh process whose numba cache (``NUMBA_CACHE_DIR``) starts
empty, starts an embedded Dask cluster of two worker processes as the workflow does and has
each worker compute one spectrum point per mode, as every worker of a study eventually does
(El Centro, R = 2 m, tan α = 0.2, overturning and θ > α/3, "default" accuracy):

- ``before``: the workers start at once, so each compiles the kernels it meets itself;
- ``after``: :func:`rocking.execution.warmup.warm_numba_cache` runs first in the client process
  (the workflow's ``numba_cache`` step), the workers then load the kernels from the cache;
- ``warm``: ``after`` again on the cache the previous scenario filled (every later rule or
  run on the machine).

Per scenario and mode: seconds from the start of the scenario (before any warm-up or cluster)
until both workers have computed their point of the mode, and the longer of the two workers'
time inside the search (its compilation included when the worker compiles); per scenario:
the warm-up time and the total. The warm-up compiles the three dynamics models in parallel
processes, one per core. Wall times on a shared
machine: compilation is CPU-bound, so a loaded machine stretches it.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import pandas as pd

from benchmarks._io import write_table
from rocking.spectra.modes import MODES

R = 2.0
TAN_ALPHA = 0.2
LIMIT_STATES = ("overturning", "tilt:1/3")


def _point(mode: str) -> tuple[float, float]:
    """One spectrum point of ``mode`` (a Dask task): (start, end) of the search [epoch s]."""
    from rocking.dynamics.bodies import Cylinder
    from rocking.motions.catalogue import load_record
    from rocking.spectra.critical import critical_intensity

    motion = load_record("el-centro-1940")
    t0 = time.time()
    critical_intensity(Cylinder(R, TAN_ALPHA), motion, LIMIT_STATES, mode)
    return t0, time.time()


def scenario(warm: bool) -> dict:
    """Run one scenario in this process; seconds since its start per mode."""
    from distributed import Client, LocalCluster

    from rocking.execution.warmup import warm_numba_cache

    t0 = time.time()
    warm_seconds = 0.0
    if warm:
        warm_numba_cache(tuple(MODES), processes=os.cpu_count() or 1)
        warm_seconds = time.time() - t0
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=":0") as cluster, Client(cluster) as client:
        workers = list(client.scheduler_info()["workers"])
        futures = {mode: [client.submit(_point, mode, pure=False, workers=[w])
                          for w in workers] for mode in MODES}
        spans = {mode: [f.result() for f in fs] for mode, fs in futures.items()}
    return {"warm_up": warm_seconds, "total": time.time() - t0,
            "first_result": {m: max(e for _, e in v) - t0 for m, v in spans.items()},
            "in_search": {m: max(e - b for b, e in v) for m, v in spans.items()}}


def main(argv: list[str] | None = None) -> int:
    """Run the scenarios in fresh processes and write the table."""
    parser = argparse.ArgumentParser(prog="python -m benchmarks coldstart")
    parser.add_argument("--scenario", choices=("before", "after"),
                        help=argparse.SUPPRESS)  # internal: one scenario in this process
    args = parser.parse_args(argv)
    if args.scenario:
        print(json.dumps(scenario(args.scenario == "after")))
        return 0
    rows = []
    with tempfile.TemporaryDirectory(prefix="numba-cold-") as tmp:
        for name, kind, cache in (("before", "before", "a"), ("after", "after", "b"),
                                  ("warm", "after", "b")):
            env = {**os.environ, "NUMBA_CACHE_DIR": os.path.join(tmp, cache)}
            out = subprocess.run([sys.executable, "-m", "benchmarks", "coldstart",
                                  "--scenario", kind], env=env, capture_output=True,
                                 text=True, check=True)
            res = json.loads(out.stdout.strip().splitlines()[-1])
            print(f"  {name}: {res}", flush=True)
            for mode, seconds in res["first_result"].items():
                rows.append({"scenario": name, "mode": mode, "seconds_to_result": seconds,
                             "seconds_in_search": res["in_search"][mode],
                             "warm_up_seconds": res["warm_up"], "total_seconds": res["total"]})
    df = pd.DataFrame(rows)
    notes = (f"One point per mode (El Centro, R = {R:g} m, tan α = {TAN_ALPHA:g}, "
             f"{', '.join(LIMIT_STATES)}, accuracy 'default') on an embedded LocalCluster of 2 "
             "worker processes, each scenario in a fresh process with its own numba cache "
             "directory; seconds from the scenario's start (warm-up, cluster start, import "
             f"of the record included). {os.cpu_count()} cores shared with other jobs.")
    write_table("coldstart", df, "Cold start: first spectrum point per mode", notes)
    print(df.to_string(index=False))
    return 0
