"""Where a workflow run's time goes, rule by rule, in CPU seconds (load-independent).

``python -m benchmarks rule_cpu [--configfile config/config.yaml] [--workdir DIR] [--keep]
[--name main_job]`` runs ``snakemake --cores 2`` from empty in ``DIR`` (default a fresh
temporary folder; the numba cache too, unless ``--warm-numba``) and, while it runs, samples
every process under it twice a second: each job's script process and the processes it starts
(Dask workers, process pools) are charged to the job's rule, found from the log the job holds
open (``<root>/logs/.../<rule>.log``). It writes ``results/benchmarks/<name>_rules.{csv,md}``:
per rule, its jobs, wall seconds (first start to last end of its processes) and CPU seconds
(user + system of the job and its children, at their last sample: a process that ends between
two samples loses at most half a second), and the run's wall time, CPU time and the
Snakemake scheduler's own share.

CPU seconds say what a run costs on a quiet machine: on 2 cores the wall time of the run is
at least the larger of (CPU seconds)/2 and its longest chain of rules. Wall seconds of a
shared machine are upper bounds.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd

from benchmarks._io import write_table

REPO = Path(__file__).resolve().parents[1]
INTERVAL = 0.5
"""Seconds between two samples of the process tree."""
_LOG = re.compile(r"/logs/(?:[^/]+/)*([^/]+)\.log$")


def _rule_of(proc) -> str | None:
    """The job of a process: its script (``tmpXXXX.<script>.py``) and the stem of the
    ``<root>/logs/...`` log it holds open (a figure's name, a study's product), as
    ``script:stem`` (``script`` alone where they are the same)."""
    script = next((Path(c).name.split(".", 1)[1].removesuffix(".py")
                   for c in proc.cmdline() if "/.snakemake/scripts/" in c
                   or c.startswith(".snakemake/scripts/")), "?")
    try:
        for f in proc.open_files():
            m = _LOG.search(f.path)
            if m:
                return script if m.group(1) == script else f"{script}:{m.group(1)}"
    except Exception:  # noqa: BLE001 - the process ended between two calls
        return None
    return None


def _is_job(cmdline: list[str]) -> bool:
    """A Snakemake job: ``python .snakemake/scripts/tmpXXXX.<script>.py``."""
    return any("/.snakemake/scripts/" in c or c.startswith(".snakemake/scripts/")
               for c in cmdline)


def run(configfile: Path, workdir: Path, warm_numba: bool = False) -> tuple[pd.DataFrame, dict]:
    """Run the workflow in ``workdir`` and charge every process's CPU to its rule."""
    import psutil

    env = {k: v for k, v in os.environ.items() if k != "DASK_SCHEDULER_ADDRESS"}
    if not warm_numba:
        env["NUMBA_CACHE_DIR"] = str(workdir / ".numba-cache")
    cmd = [sys.executable, "-m", "snakemake", "-s", str(REPO / "Snakefile"), "--directory",
           str(workdir), "--cores", "2", "--nocolor", "--configfile", str(configfile)]
    t0 = time.perf_counter()
    top = psutil.Popen(cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True, cwd=REPO)
    jobs: dict[int, dict] = {}     # job pid -> rule, first and last seen, cpu per pid
    owner: dict[int, int] = {}     # any pid -> its job pid
    cpu: dict[int, float] = {}     # pid -> user + system at its last sample
    seen: dict[int, tuple[float, float]] = {}
    while top.poll() is None:
        now = time.perf_counter() - t0
        try:
            procs = [top, *top.children(recursive=True)]
        except psutil.NoSuchProcess:
            break
        for p in procs:
            try:
                if p.pid not in owner and p.pid != top.pid:
                    # a process under a job is the job's (a forked worker has the job's
                    # command line); else a job script is a job of its own
                    parent = p.parent()
                    while parent is not None and parent.pid not in owner \
                            and parent.pid != top.pid:
                        parent = parent.parent()
                    if parent is not None and parent.pid in owner:
                        owner[p.pid] = owner[parent.pid]
                    elif _is_job(p.cmdline()):
                        owner[p.pid] = p.pid
                        jobs[p.pid] = {"rule": None}
                if p.pid in jobs and jobs[p.pid]["rule"] is None:
                    jobs[p.pid]["rule"] = _rule_of(p)
                t = p.cpu_times()
                cpu[p.pid] = t.user + t.system
                first = seen.get(p.pid, (now, now))[0]
                seen[p.pid] = (first, now)
            except psutil.NoSuchProcess:
                continue
        time.sleep(INTERVAL)
    out = top.stdout.read() if top.stdout else ""
    wall = time.perf_counter() - t0
    (workdir / "snakemake.out").write_text(out)
    if top.returncode != 0:
        raise RuntimeError(f"snakemake failed ({top.returncode}):\n{out[-3000:]}")
    rows: dict[str, dict] = {}
    for pid, job in jobs.items():
        rule = job["rule"] or "(unknown)"
        members = [q for q, j in owner.items() if j == pid]
        row = rows.setdefault(rule, {"rule": rule, "jobs": 0, "cpu_s": 0.0, "start": None,
                                     "end": None})
        row["jobs"] += 1
        row["cpu_s"] += sum(cpu.get(q, 0.0) for q in members)
        start = min(seen[q][0] for q in members if q in seen)
        end = max(seen[q][1] for q in members if q in seen)
        row["start"] = start if row["start"] is None else min(row["start"], start)
        row["end"] = end if row["end"] is None else max(row["end"], end)
    table = pd.DataFrame(rows.values())
    table["wall_s"] = table["end"] - table["start"]
    table = table.sort_values("start").reset_index(drop=True)
    charged = float(table["cpu_s"].sum())
    total = sum(cpu.values())
    summary = {"wall_s": wall, "cpu_s": total, "jobs_cpu_s": charged,
               "scheduler_cpu_s": cpu.get(top.pid, 0.0)}
    return table[["rule", "jobs", "start", "end", "wall_s", "cpu_s"]], summary


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks rule_cpu", description=__doc__)
    ap.add_argument("--configfile", type=Path, default=REPO / "config" / "config.yaml")
    ap.add_argument("--workdir", type=Path, default=None)
    ap.add_argument("--name", default="main_job")
    ap.add_argument("--keep", action="store_true", help="keep the run's folder")
    ap.add_argument("--warm-numba", action="store_true",
                    help="use the machine's numba cache (default: an empty one, as a clone)")
    args = ap.parse_args(argv)
    workdir = args.workdir or Path(tempfile.mkdtemp(prefix="rocking-rule-cpu-"))
    workdir.mkdir(parents=True, exist_ok=True)
    try:
        table, s = run(args.configfile.resolve(), workdir, args.warm_numba)
    finally:
        if not args.keep and args.workdir is None:
            shutil.rmtree(workdir, ignore_errors=True)
    notes = (f"`snakemake --cores 2 --configfile {args.configfile}` from empty "
             f"({'warm' if args.warm_numba else 'empty'} numba cache): wall {s['wall_s']:.0f} s, "
             f"CPU {s['cpu_s']:.0f} s (jobs {s['jobs_cpu_s']:.0f} s, the Snakemake process "
             f"{s['scheduler_cpu_s']:.0f} s). start/end: seconds since the run began; cpu_s: "
             "user + system of the job's processes and their children. A shared machine "
             "stretches wall seconds, not CPU seconds.")
    path = write_table(f"{args.name}_rules", table, "Where the run's time goes, rule by rule",
                       notes)
    print(notes)
    print(table.to_string(index=False))
    print(path)
    return 0
