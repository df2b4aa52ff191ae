"""Benchmark of the provenance checks (:mod:`rocking.provenance`): CPU seconds per rule.

``python -m benchmarks provenance RUN CONFIG [--paper-bytes]`` takes a finished run (its
working directory ``RUN`` and ``--configfile`` ``CONFIG``), lists every job of its default
target (a dry run of them all) and measures, per job, in this process (CPU seconds,
``time.process_time``; each job starts with an empty digest cache, as a job's process does):

- ``plan``: what the planning of a run costs (``workflow/rules/provenance.smk``): every
  output held against its record (:func:`rocking.provenance.problem` with ``fast``: a stat
  and the records read; files hashed only where their size or date moved);
- ``read``: what a job's block costs before its work (:func:`rocking.execution.logs.job`):
  every input checked against its record, hashed (and what its record says it was made
  from);
- ``write``: what it costs after: every output hashed and recorded (in a copy of the run).

Written to ``results/benchmarks/provenance.csv`` and ``.md``: per rule, jobs, files and
bytes hashed, the three costs. ``--paper-bytes`` extrapolates to the paper's run
(``config/paper.yaml``): the cost of a rule scales with the bytes it hashes (throughput
measured here) plus a fixed cost per file; the paper's files are counted from its
configuration (fragility rows, bootstrap resamples, motions).

CPU seconds on a shared machine (others' jobs slow the caches, not the count).
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd

from benchmarks._io import write_table
from rocking import provenance

REPO = Path(__file__).resolve().parents[1]


def jobs(run: Path, config: Path) -> list[dict]:
    """Every job of the default target: rule, inputs, outputs (a dry run of all of them)."""
    out = subprocess.run([sys.executable, "-m", "snakemake", "-s", str(REPO / "Snakefile"),
                          "--configfile", str(config), "--cores", "1", "-n", "--forceall",
                          "--nocolor"], cwd=run, capture_output=True, text=True, check=True)
    found = []
    for block in re.split(r"\n(?=(?:local)?rule \w+:\n)", out.stdout):
        head = re.match(r"(?:local)?rule (\w+):\n", block)
        if head is None or head.group(1) == "all":
            continue
        fields = dict(re.findall(r"^    (input|output): (.*)$", block, re.MULTILINE))
        found.append({"rule": head.group(1),
                      "input": [f for f in fields.get("input", "").split(", ") if f],
                      "output": [f for f in fields.get("output", "").split(", ") if f]})
    return found


def _size(path: Path) -> int:
    if path.is_dir():
        return sum(f.stat().st_size for f in path.rglob("*") if f.is_file())
    return path.stat().st_size if path.exists() else 0


def _cpu(fn) -> float:
    provenance._sha_cache.clear()  # a job is a process of its own
    t0 = time.process_time()
    fn()
    return time.process_time() - t0


def measure(run: Path, config: Path) -> pd.DataFrame:
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        copy = Path(tmp) / "run"
        shutil.copytree(run, copy, symlinks=True,
                        ignore=shutil.ignore_patterns("*.zarr", ".snakemake"))
        for j in jobs(run, config):
            outs = [run / f for f in j["output"]]
            ins = [run / f for f in j["input"] if not f.endswith("numba_cache.json")]
            plan = _cpu(lambda o=outs, r=j["rule"]: [provenance.problem(f, rule=r, fast=True)
                                                      for f in o])
            read = _cpu(lambda i=ins: [provenance.check(f) for f in i])

            def write(j=j):
                copied = [copy / f for f in j["output"]]
                for f in copied:
                    provenance.record(f, inputs=[copy / i for i in j["input"]],
                                      together=copied, settings="0" * 16, rule=j["rule"])

            rows.append({"rule": j["rule"], "jobs": 1, "files": len(ins) + len(outs),
                         "bytes": sum(map(_size, ins + outs)), "plan_s": plan,
                         "read_s": read, "write_s": _cpu(write)})
    frame = pd.DataFrame(rows).groupby("rule", as_index=False).sum()
    return frame.sort_values("read_s", ascending=False, ignore_index=True)


def throughput() -> float:
    """sha256 of 64 MiB: CPU seconds per byte."""
    with tempfile.NamedTemporaryFile() as fh:
        fh.write(b"\0" * (64 << 20))
        fh.flush()
        t0 = time.process_time()
        provenance.file_sha256(fh.name)
        return (time.process_time() - t0) / (64 << 20)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks provenance")
    p.add_argument("run", type=Path, help="working directory of a finished run")
    p.add_argument("config", type=Path, help="its --configfile")
    p.add_argument("--paper-bytes", type=float, default=None, metavar="BYTES",
                   help="bytes the paper run's jobs hash in all (inputs and outputs, "
                   "counted over every job): the cost extrapolated to it")
    args = p.parse_args(argv)
    frame = measure(args.run.resolve(), args.config.resolve())
    per_byte = throughput()
    total = frame[["plan_s", "read_s", "write_s"]].sum()
    notes = (f"Run {args.run} ({len(frame)} rules, {int(frame['jobs'].sum())} jobs, "
             f"{int(frame['bytes'].sum())} bytes in their files). sha256: "
             f"{1 / per_byte / 1e6:.0f} MB per CPU second. Totals: plan {total['plan_s']:.3f} "
             f"s, read {total['read_s']:.3f} s, write {total['write_s']:.3f} s.")
    if args.paper_bytes:
        fixed = (total["read_s"] + total["write_s"] - per_byte * 2 * frame["bytes"].sum()) \
            / frame["files"].sum()
        notes += (f" Paper run: {args.paper_bytes:.3g} bytes hashed once at reading and once "
                  f"at writing: about {2 * per_byte * args.paper_bytes:.1f} CPU s, plus "
                  f"{max(fixed, 0.0) * 1e3:.2f} ms per file.")
    write_table("provenance", frame, "Provenance checks: CPU seconds per rule", notes)
    print(frame.to_string(index=False))
    print(notes)
    return 0
