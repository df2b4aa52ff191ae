"""Where the paper run's time goes, and what the "decided" early end of an analysis saves.

``python -m benchmarks paper_cost [--run DIR] [--quick]`` reads a finished run of
``config/paper.yaml`` in ``DIR`` (default ``.``; read only) and writes to
``docs/benchmarks/``:

- ``paper_rules.{csv,md}``: every rule of the run's Snakemake logs (``.snakemake/log``) with
  its start, end and wall seconds, in the order they started;
- ``paper_cost.{csv,md}``: a sample of the run's spectrum points (per study: its record and
  one synthetic pair, four sizes R, every requested mode and tan α with its limit states),
  each searched twice in this process, with the early end of decided analyses
  (``stop_when_decided``, the default) and without it (main's behaviour before it): analyses,
  integration steps (accepted + rejected) and CPU seconds of both, and whether the answers,
  the flags and every analysis of the search (intensity, peak tilt, status) are identical
  to the bit;
- ``paper_cost_summary.{csv,md}``: per study, mode and tan α, the run's own analysis count
  (from its store) times the sample's CPU seconds per analysis, without and with the early
  end: the CPU cost of the paper run's searches, and what the early end saves.

Counts (analyses, steps) do not depend on the load of the machine; CPU seconds do a little
(process time, not wall time); the run's rule times are wall times of that run.
"""

from __future__ import annotations

import argparse
import dataclasses
import functools
import re
import time
from collections.abc import Iterator
from contextlib import contextmanager
from datetime import datetime
from pathlib import Path

import numpy as np
import pandas as pd

from benchmarks._io import write_table

SAMPLE_R = (1.0, 4.0, 7.0, 10.0)
"""Sizes R [m] sampled per (study, motion, mode, tan α): the paper's grid spans 0.5–10 m
and the cost of a search grows with R."""

SYNTHETIC_INDEX = 3
"""Which synthetic pair of each ensemble is sampled beside the record."""


# ------------------------------------------------------------------------------ rule times
_STAMP = re.compile(r"^\[(\w{3} \w{3} +\d+ [\d:]+ \d{4})\]$")
_START = re.compile(r"^(?:local)?rule (\w+):$")
_JOBID = re.compile(r"^\s+jobid: (\d+)$")
_FINISHED = re.compile(r"^Finished jobid: (\d+) \(Rule: (\w+)\)$")
_WILDCARDS = re.compile(r"^\s+wildcards: (.+)$")


def rule_times(run_dir: str | Path) -> pd.DataFrame:
    """Start, end and wall seconds of every job in the Snakemake logs of ``run_dir``.

    Parameters
    ----------
    run_dir : str or Path
        A workflow directory with ``.snakemake/log/*.snakemake.log``.

    Returns
    -------
    DataFrame
        ``log`` (file), ``rule``, ``wildcards``, ``start``, ``end``, ``seconds`` [s]; a job
        that never finished (a failed rule) has ``end`` NaT and ``seconds`` NaN.
    """
    logs = sorted(Path(run_dir, ".snakemake", "log").glob("*.snakemake.log"))
    if not logs:
        raise ValueError(f"no Snakemake logs in {Path(run_dir, '.snakemake', 'log')}")
    rows = []
    for log in logs:
        stamp, pending, jobs = None, None, {}
        for line in log.read_text().splitlines():
            if m := _STAMP.match(line):
                stamp = datetime.strptime(m.group(1), "%a %b %d %H:%M:%S %Y")
            elif m := _START.match(line):
                pending = {"log": log.name, "rule": m.group(1), "wildcards": "",
                           "start": stamp, "end": pd.NaT}
            elif pending is not None and (m := _WILDCARDS.match(line)):
                pending["wildcards"] = m.group(1)
            elif pending is not None and "jobid" not in pending and (m := _JOBID.match(line)):
                pending["jobid"] = m.group(1)
                jobs[m.group(1)] = pending
                rows.append(pending)
            elif m := _FINISHED.match(line):
                if m.group(1) in jobs:
                    jobs.pop(m.group(1))["end"] = stamp
    df = pd.DataFrame(rows).drop(columns="jobid")
    df["seconds"] = (pd.to_datetime(df["end"]) - pd.to_datetime(df["start"])).dt.total_seconds()
    return df


# ------------------------------------------------------------------------ the sampled searches
@contextmanager
def counted_analyses(decided: bool) -> Iterator[dict]:
    """Every analysis run inside the block goes through ``ground_response`` with
    ``stop_when_decided=decided``; yields a dict counting analyses and steps."""
    from rocking.dynamics import analysis

    original = analysis.ground_response
    count = {"analyses": 0, "steps": 0}

    @functools.wraps(original)
    def wrapped(*args, **kwargs):
        # the search asks for whole records where a goal needs them (a sliding goal): keep it
        kwargs["stop_when_decided"] = decided and kwargs.get("stop_when_decided", True)
        r = original(*args, **kwargs)
        count["analyses"] += 1
        count["steps"] += int(r.n_steps) + int(r.n_rejected)
        return r

    analysis.ground_response = wrapped
    try:
        yield count
    finally:
        analysis.ground_response = original


def _answers(res) -> tuple:
    """Everything a search returns that a store or a figure could see, exactly."""
    flags = tuple(np.asarray(getattr(res, k)).tobytes()
                  for k in ("not_reached", "non_monotonic", "failed", "plateau"))
    return (np.asarray(res.intensity).tobytes(), np.asarray(res.i50).tobytes(), flags,
            # repr: exact for floats, and NaN (monitors a search did not run) equals itself
            tuple(repr(dataclasses.astuple(e)) for e in res.evaluations))


def search_pair(body, motion, limit_states, mode: str, upper: float,
                accuracy) -> dict:
    """One spectrum point searched without and with the early end: counts, CPU, identity."""
    from rocking.spectra.critical import critical_intensity

    row = {}
    answers = {}
    for label, decided in (("before", False), ("after", True)):
        with counted_analyses(decided) as count:
            t0 = time.process_time()
            res = critical_intensity(body, motion, limit_states, mode, accuracy=accuracy,
                                     upper=upper)
            cpu = time.process_time() - t0
        answers[label] = _answers(res)
        row[f"analyses_{label}"] = count["analyses"]
        row[f"steps_{label}"] = count["steps"]
        row[f"cpu_s_{label}"] = cpu
    row["identical"] = answers["before"] == answers["after"]
    return row


def _study_cells(store: Path) -> tuple[pd.DataFrame, dict]:
    """Per (mode, tan α) of a spectra store: the limit states asked, the analyses the run
    spent (sum over motions and R); and the store's attributes."""
    import xarray as xr

    from rocking.store import read_attrs

    attrs = read_attrs(store)
    ds = xr.open_zarr(store)
    req = ds["requested"].load()
    n = ds["n_analyses"].max("limit_state").load()
    rows = []
    for mode in ds["mode"].values:
        for ta in ds["tan_alpha"].values:
            asked = req.sel(mode=mode, tan_alpha=ta)
            if not bool(asked.any()):
                continue
            states = [str(s) for s in ds["limit_state"].values[asked.values]]
            x = n.sel(mode=mode, tan_alpha=ta)
            rows.append({"mode": str(mode), "tan_alpha": float(ta), "limit_states": states,
                         "points": int(x.size), "run_analyses": int(x.sum())})
    return pd.DataFrame(rows), attrs


def sample_study(run_dir: Path, study: str, R_values, n_motions: int) -> list[dict]:
    """Search the sampled points of one study of the run twice (:func:`search_pair`)."""
    from rocking.dynamics.bodies import Cylinder
    from rocking.execution.tasks import motions_by_name

    store = run_dir / "results" / study / "spectra.zarr"
    cells, attrs = _study_cells(store)
    ensemble = motions_by_name(run_dir / attrs["ensemble"]["file"])
    names = list(ensemble)
    picked = [names[0]] + ([names[min(SYNTHETIC_INDEX + 1, len(names) - 1)]]
                           if n_motions > 1 else [])
    upper = float(attrs["search_options"]["upper"])
    rows = []
    for cell in cells.itertuples():
        for name in picked:
            for R in R_values:
                row = {"study": study, "mode": cell.mode, "tan_alpha": cell.tan_alpha,
                       "goals": len(cell.limit_states), "motion": name, "R": R}
                row.update(search_pair(Cylinder(R, cell.tan_alpha), ensemble[name],
                                       cell.limit_states, cell.mode, upper,
                                       attrs["tolerances"]))
                print(f"  {study} {cell.mode} tan α {cell.tan_alpha:g} {name} R {R:g}: "
                      f"{row['analyses_after']} analyses, steps {row['steps_before']} → "
                      f"{row['steps_after']}, CPU {row['cpu_s_before']:.2f} → "
                      f"{row['cpu_s_after']:.2f} s, identical {row['identical']}", flush=True)
                rows.append(row)
    return rows


def summary(run_dir: Path, sample: pd.DataFrame) -> pd.DataFrame:
    """The run's analyses per (study, mode, tan α) times the sample's CPU per analysis."""
    out = []
    for study, part in sample.groupby("study", sort=False):
        cells, _ = _study_cells(run_dir / "results" / study / "spectra.zarr")
        for cell in cells.itertuples():
            s = part[(part["mode"] == cell.mode) & (part["tan_alpha"] == cell.tan_alpha)]
            per = {k: s[f"cpu_s_{k}"].sum() / s[f"analyses_{k}"].sum()
                   for k in ("before", "after")}
            out.append({
                "study": study, "mode": cell.mode, "tan_alpha": cell.tan_alpha,
                "goals": len(cell.limit_states), "points": cell.points,
                "run_analyses": cell.run_analyses,
                "ms_per_analysis_before": 1e3 * per["before"],
                "ms_per_analysis_after": 1e3 * per["after"],
                "steps_after_over_before": s["steps_after"].sum() / s["steps_before"].sum(),
                "cpu_s_before": cell.run_analyses * per["before"],
                "cpu_s_after": cell.run_analyses * per["after"],
                "sampled_points_identical": f"{int(s['identical'].sum())}/{len(s)}",
            })
    df = pd.DataFrame(out)
    total = {"study": "all", "mode": "", "tan_alpha": np.nan, "goals": np.nan,
             "points": df["points"].sum(), "run_analyses": df["run_analyses"].sum(),
             "ms_per_analysis_before": np.nan, "ms_per_analysis_after": np.nan,
             "steps_after_over_before": sample["steps_after"].sum()
             / sample["steps_before"].sum(),
             "cpu_s_before": df["cpu_s_before"].sum(), "cpu_s_after": df["cpu_s_after"].sum(),
             "sampled_points_identical":
                 f"{int(sample['identical'].sum())}/{len(sample)}"}
    return pd.concat([df, pd.DataFrame([total])], ignore_index=True)


def main(argv: list[str] | None = None) -> int:
    """Write the rule times, the sampled searches and the summary (module docstring)."""
    parser = argparse.ArgumentParser(prog="python -m benchmarks paper_cost")
    parser.add_argument("--run", default=".", help="directory of a finished paper.yaml run")
    parser.add_argument("--quick", action="store_true",
                        help="the record only, sizes 4 and 10 m")
    args = parser.parse_args(argv)
    run_dir = Path(args.run)
    rules = rule_times(run_dir)
    write_table("paper_rules", rules, "Rules of the paper run, from its Snakemake logs",
                f"Run directory: {run_dir.resolve()}. Wall seconds of that run.")
    from rocking.execution.warmup import warm_numba_cache

    warm_numba_cache()  # compilation or loading is not part of any search below
    R_values = (4.0, 10.0) if args.quick else SAMPLE_R
    rows = []
    for study in sorted(p.parent.name for p in (run_dir / "results").glob("*/spectra.zarr")):
        rows += sample_study(run_dir, study, R_values, 1 if args.quick else 2)
    sample = pd.DataFrame(rows)
    write_table("paper_cost", sample, "Sampled spectrum points of the paper run, searched "
                "without (before) and with (after) the early end of decided analyses",
                "CPU seconds are process time of one search in this process (kernels "
                "loaded beforehand); steps are accepted + rejected integration steps; "
                "identical: answers, flags and every analysis (intensity, peak tilt, status) "
                "equal to the bit.")
    table = summary(run_dir, sample)
    write_table("paper_cost_summary", table, "CPU cost of the paper run's searches, "
                "before and after the early end of decided analyses",
                "run_analyses: analyses of the run (its stores); CPU: run_analyses × the "
                "sample's CPU seconds per analysis of the same study, mode and tan α.")
    print(table.to_string(index=False))
    return 0 if bool(sample["identical"].all()) else 1
