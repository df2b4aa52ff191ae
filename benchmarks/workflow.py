"""Benchmark of the workflow: default run, paper cost per point, Dask speed-up 1 → 2 workers.

``python -m benchmarks workflow [--skip-default-run] [--targets ...]`` writes
``docs/benchmarks/workflow.csv`` and ``.md``:

- ``default_run``: wall time of ``snakemake --cores 2`` on ``config/config.yaml`` in a fresh
  directory (everything: motions, stores, Dask, statistics, and the figures when their rules
  exist), and per rule;
- ``paper_point``: seconds per spectrum point of the paper configuration
  (``config/paper.yaml``: its accuracy, limit states and motions), measured through the
  store's task body on a sample of the grid, per mode, and the paper study extrapolated;
- ``speedup``: the same chunks computed on an embedded LocalCluster of 1 and of 2 worker
  processes (compute wall time, cluster start-up excluded, then included).

Seconds are wall times on a shared machine: other jobs may run at the same time.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from benchmarks._io import write_table
from rocking import store
from rocking.config.damping import Damping
from rocking.config.products import SpectraSpec
from rocking.config.study import StudySpec
from rocking.execution import cluster, tasks
from rocking.spectra.modes import MODE_2D_X, MODE_2D_Y, MODE_3D, MODE_3D_DAMPED
from rocking.store.layout import region_coords

REPO = Path(__file__).resolve().parents[1]
SAMPLE_R = [0.5, 3.0, 6.0, 10.0]
"""Sizes [m] of the paper-cost sample (the cost grows with R: more analyses per search)."""
SPEEDUP_R = [1.0, 2.0, 4.0, 6.0, 8.0, 10.0]


def _snakemake(workdir: Path, *args: str, cores: int = 2) -> float:
    """Run the workflow in ``workdir``; return its wall time [s]."""
    cmd = [sys.executable, "-m", "snakemake", "-s", str(REPO / "Snakefile"), "--directory",
           str(workdir), "--cores", str(cores), "--nocolor", *args]
    t0 = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True)
    seconds = time.perf_counter() - t0
    (workdir / "snakemake.out").write_text(out.stdout + out.stderr)
    if out.returncode != 0:
        raise RuntimeError(f"snakemake {' '.join(args)} failed:\n{out.stderr[-3000:]}")
    return seconds


def _rule_times(workdir: Path) -> dict[str, float]:
    """Wall seconds per rule from the snakemake log (start and finish lines)."""
    text = (workdir / "snakemake.out").read_text()
    stamp = r"\[(\w{3} \w{3} +\d+ \d\d:\d\d:\d\d \d{4})\]"
    starts, totals = {}, {}
    current = None
    for line in text.splitlines():
        m = re.match(stamp, line)
        if m:
            current = time.mktime(time.strptime(m.group(1), "%a %b %d %H:%M:%S %Y"))
            continue
        m = re.match(r"(?:local)?rule (\w+):", line)
        if m and current is not None:
            starts.setdefault(m.group(1), []).append(current)
        m = re.match(r"Finished jobid: \d+ \(Rule: (\w+)\)", line)
        if m and current is not None and starts.get(m.group(1)):
            totals[m.group(1)] = totals.get(m.group(1), 0.0) + current - starts[m.group(1)].pop(0)
    return totals


def default_run(rows: list[dict], targets: list[str]) -> None:
    workdir = Path(tempfile.mkdtemp(prefix="rocking-default-run-"))
    seconds = _snakemake(workdir, *targets)
    what = " ".join(targets) or "all"
    rows.append(_row("default_run", "wall time", seconds, "s",
                     f"snakemake --cores 2 {what}, config/config.yaml, fresh directory"))
    for rule, s in sorted(_rule_times(workdir).items(), key=lambda kv: -kv[1]):
        rows.append(_row("default_run", f"rule {rule}", s, "s", "summed over its jobs"))
    for done in sorted(workdir.glob("results/*/*.done.json")):
        summary = json.loads(done.read_text())
        cs = summary["chunk_seconds"]
        rows.append(_row("default_run", f"{done.parent.name}/{done.name} chunks",
                         summary["chunks"], "chunks",
                         f"chunk compute s min {cs['min']:.3f} / median {cs['median']:.3f} / "
                         f"max {cs['max']:.3f}"))
    shutil.rmtree(workdir, ignore_errors=True)


def _paper_spec(study: str = "elcentro") -> SpectraSpec:
    """The spectra of one study of config/paper.yaml."""
    paper = yaml.safe_load((REPO / "config/paper.yaml").read_text())
    return StudySpec.from_config(paper, study).spectra


def _paper_ensemble(workdir: Path) -> Path:
    """The El Centro ensemble file of config/paper.yaml (named after its settings' digest)."""
    digest = _paper_spec().ensemble.digest
    return workdir / f"results/motions/elcentro-{digest}.nc"


def _paper_store(workdir: Path, modes: list[str], R: list[float], motions: list[str],
                 name: str) -> Path:
    """A store with the paper's settings on a sub-grid at tan α = 0.2, one size R per chunk;
    each mode searches the limit states the paper's runs ask of it there."""
    spec = _paper_spec()
    plan = spec.plan
    k = plan.tan_alpha.index(0.2)
    requested = plan.requested[[plan.modes.index(m) for m in modes]][:, :, [k]]
    ensemble = _paper_ensemble(workdir)
    layout = tasks.spectra_layout(modes, plan.limit_states, motions, [0.2], R, 1)
    options = {"upper": spec.upper,
               **(Damping.options(spec.damping) if MODE_3D_DAMPED in modes else {})}
    attrs = {"tolerances": spec.accuracy.to_dict(), "search_options": options,
             "ensemble": tasks.ensemble_attrs(ensemble, "elcentro")}
    path = workdir / f"{name}.zarr"
    store.create_store(path, layout, attrs, name, static={store.REQUESTED: requested})
    return path


def paper_point_cost(rows: list[dict], workdir: Path) -> None:
    ensemble = _paper_ensemble(workdir)
    names = [m["name"] for m in tasks.ensemble_attrs(ensemble, "elcentro")["motions"]]
    modes = [MODE_3D, MODE_3D_DAMPED, MODE_2D_X, MODE_2D_Y]
    path = _paper_store(workdir, modes, SAMPLE_R, names[:2], "paper-sample")
    layout = store.open_layout(path)
    per_mode: dict[str, list[float]] = {m: [] for m in modes}
    analyses: dict[str, list[int]] = {m: [] for m in modes}
    for i in range(layout.n_regions):
        rep = tasks.fill_spectra_region(path, i, ensemble)
        mode = str(region_coords(layout, i)["mode"][0])
        per_mode[mode].append(rep["seconds"] / rep["points"])
    ds = store.read_attrs(path)
    import xarray as xr

    n_an = xr.open_zarr(path, consolidated=False)["n_analyses"].max("limit_state")
    for mode in modes:
        analyses[mode] = n_an.sel(mode=mode).values.ravel().tolist()
    paper = yaml.safe_load((REPO / "config/paper.yaml").read_text())
    total_points = 0
    total_seconds = 0.0
    for name in paper["studies"]:
        spec = _paper_spec(name)
        n_motions = 1 + spec.ensemble.n_synthetic
        # every study is costed like El Centro's points, mode by mode
        for mode, n in spec.plan.points(n_motions, len(spec.R)).items():
            total_points += n
            total_seconds += n * float(np.mean(per_mode[mode]))
    tol = ds["tolerances"]
    for mode in modes:
        rows.append(_row("paper_point", f"seconds per point, {mode}",
                         float(np.mean(per_mode[mode])), "s",
                         f"mean of {len(per_mode[mode])} points (R {SAMPLE_R} m, tan α 0.2, "
                         f"record + 1 synthetic pair, the paper's limit states of the mode, "
                         f"accuracy "
                         f"{tol['name']}); max {max(per_mode[mode]):.2f} s; analyses per "
                         f"point mean {np.mean(analyses[mode]):.0f}"))
    rows.append(_row("paper_point", "paper study, extrapolated", total_seconds / 3600.0,
                     "core-hours", f"{total_points} points of config/paper.yaml x the mean "
                     "cost of their mode"))


def speedup(rows: list[dict], workdir: Path) -> None:
    ensemble = _paper_ensemble(workdir)
    names = [m["name"] for m in tasks.ensemble_attrs(ensemble, "elcentro")["motions"]]
    walls = {}
    for n_workers in (1, 2):
        path = _paper_store(workdir, [MODE_3D, MODE_2D_X], SPEEDUP_R, names[:1],
                            f"speedup-{n_workers}")
        layout = store.open_layout(path)
        t0 = time.perf_counter()
        with cluster.dask_client(cluster.Target("local"), n_workers) as client:
            t1 = time.perf_counter()
            order = tasks.costliest_first(layout, range(layout.n_regions))
            cluster.run_regions(client, tasks.fill_spectra_region, order,
                                (str(path),), {"motions": str(ensemble)}, interval=1e9)
            t2 = time.perf_counter()
        walls[n_workers] = (t2 - t1, time.perf_counter() - t0)
        rows.append(_row("speedup", f"{n_workers} worker(s), compute", t2 - t1, "s",
                         f"{layout.n_regions} chunks (3d and 2d-x, record, 6 sizes R, paper "
                         "accuracy), from first submit to last result"))
        rows.append(_row("speedup", f"{n_workers} worker(s), with cluster start/stop",
                         time.perf_counter() - t0, "s", ""))
    rows.append(_row("speedup", "speed-up 1 -> 2 workers, compute", walls[1][0] / walls[2][0],
                     "x", "2 cores shared with other jobs"))
    rows.append(_row("speedup", "speed-up 1 -> 2 workers, with start/stop",
                     walls[1][1] / walls[2][1], "x", ""))


def _row(part: str, measurement: str, value: float, unit: str, notes: str) -> dict:
    return {"part": part, "measurement": measurement, "value": round(float(value), 4),
            "unit": unit, "notes": notes}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m benchmarks workflow",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--skip-default-run", action="store_true",
                        help="do not time the default workflow run")
    parser.add_argument("--targets", nargs="*", default=[],
                        help="targets of the default run (default: all)")
    args = parser.parse_args(argv)
    os.environ.pop(cluster.ENV_ADDRESS, None)
    rows: list[dict] = []
    if not args.skip_default_run:
        default_run(rows, args.targets)
    workdir = Path(tempfile.mkdtemp(prefix="rocking-paper-sample-"))
    _snakemake(workdir, str(_paper_ensemble(workdir).relative_to(workdir)), "--configfile",
               str(REPO / "config/paper.yaml"), cores=1)
    paper_point_cost(rows, workdir)
    speedup(rows, workdir)
    shutil.rmtree(workdir, ignore_errors=True)
    df = pd.DataFrame(rows)
    write_table("workflow", df, "Workflow: default run, paper cost per point, Dask speed-up",
                notes=f"{os.cpu_count()} cores shared with other jobs; wall-clock seconds.")
    print(df.to_string(index=False))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
