"""How long an inventory of 10,000 columns over 100 hazard sites takes once the surface exists.

``python -m benchmarks portfolio [--study results/paper/elcentro] [--columns 10000]
[--sites 100] [--resamples 1000]`` writes an OpenQuake-format hazard file of ``--sites``
sites (the example curve's site 0 scaled by factors 0.3–1.5, on a 0.05° grid) and an
inventory of ``--columns`` random columns (heights 4–16 m, tan α 0.1–0.3, each within 2 km
of a site) into a temporary folder, then times, wall and CPU: building the surface (its
bootstrap refits), reading the hazard's sites, reading and checking the inventory, and the
portfolio table (every column: fragility with its interval, λ with its 90 % interval over
the resamples). Writes ``docs/benchmarks/portfolio.{csv,md}``. The budget (issue 41): the
inventory, hazard and table steps together within 30 s on 2 cores.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

from benchmarks._io import write_table

BUDGET_S = 30.0
"""Wall seconds allowed for hazard + inventory + table (issue 41, item 5)."""


def write_hazard(path: Path, n_sites: int, seed: int = 41) -> None:
    """An OpenQuake hazard-curve CSV of ``n_sites`` sites: the example's site 0 scaled."""
    from rocking.risk.hazard import HazardCurve

    base = HazardCurve.from_file("config/hazard/example_hazard_curve.csv", site=0)
    rng = np.random.default_rng(seed)
    side = int(np.ceil(np.sqrt(n_sites)))
    head = ("#,,,,\"generated_by='rocking benchmark', kind='mean', investigation_time=1.0, "
            "imt='PGA'\"\ncustom_site_id,lon,lat,depth,"
            + ",".join(f"poe-{x:.7f}" for x in base.im_g))
    lines = [head]
    for k in range(n_sites):
        rate = base.annual_rate * rng.uniform(0.3, 1.5)
        poe = -np.expm1(-rate)
        lines.append(f"s{k:03d},{0.05 * (k % side):.5f},{0.05 * (k // side):.5f},0.0,"
                     + ",".join(f"{p:.6E}" for p in poe))
    path.write_text("\n".join(lines) + "\n")


def write_inventory(path: Path, n_columns: int, n_sites: int, seed: int = 41) -> None:
    """``n_columns`` columns, each within about 2 km of one of the sites."""
    rng = np.random.default_rng(seed)
    side = int(np.ceil(np.sqrt(n_sites)))
    k = rng.integers(0, n_sites, n_columns)
    height = rng.uniform(4.0, 16.0, n_columns)
    tan_alpha = rng.uniform(0.1, 0.3, n_columns)
    frame = pd.DataFrame({
        "id": [f"c{i:05d}" for i in range(n_columns)],
        "height": np.round(height, 3),
        "diameter": np.round(height * tan_alpha, 3),
        "lon": 0.05 * (k % side) + rng.uniform(-0.012, 0.012, n_columns),
        "lat": 0.05 * (k // side) + rng.uniform(-0.012, 0.012, n_columns)})
    # the grid spans R 0.5–10 m: keep every column on it
    R = 0.5 * np.hypot(frame["height"], frame["diameter"])
    ta = frame["diameter"] / frame["height"]
    frame = frame[(R <= 10.0) & (ta >= 0.1) & (ta <= 0.3)]
    frame.to_csv(path, index=False, float_format="%.6f")


def _timed(fn):
    w0, c0 = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - w0, time.process_time() - c0


def main(argv: list[str] | None = None) -> int:
    from rocking.fragility.surface import FragilitySurface
    from rocking.risk.inventory import read_hazard_sites, read_inventory
    from rocking.risk.portfolio import portfolio_table

    p = argparse.ArgumentParser(prog="python -m benchmarks portfolio")
    p.add_argument("--study", type=Path, default=Path("results/paper/elcentro"))
    p.add_argument("--columns", type=int, default=10_000)
    p.add_argument("--sites", type=int, default=100)
    p.add_argument("--resamples", type=int, default=1000)
    args = p.parse_args(argv)
    load_before = os.getloadavg()[0]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        hazard_path, inv_path = Path(tmp) / "hazard.csv", Path(tmp) / "columns.csv"
        write_hazard(hazard_path, args.sites)
        write_inventory(inv_path, args.columns, args.sites)
        surface, w, c = _timed(lambda: FragilitySurface.from_study(
            args.study, n_resamples=args.resamples))
        rows.append({"step": "surface (bootstrap refits of every node)", "wall_s": w,
                     "cpu_s": c})
        hazard, w, c = _timed(lambda: read_hazard_sites(hazard_path))
        rows.append({"step": f"hazard: {args.sites} sites read", "wall_s": w, "cpu_s": c})
        inventory, w, c = _timed(lambda: read_inventory(inv_path, surface=surface,
                                                        hazard=hazard))
        n = len(inventory.columns)
        rows.append({"step": f"inventory: {n} columns checked, sites assigned",
                     "wall_s": w, "cpu_s": c})
        table, w, c = _timed(lambda: portfolio_table(surface, inventory, hazard))
        rows.append({"step": f"portfolio table: {n} columns × "
                     f"{table['limit_state'].nunique()} limit states × {args.resamples} "
                     "resamples", "wall_s": w, "cpu_s": c})
    budget = sum(r["wall_s"] for r in rows[1:])
    rows.append({"step": f"hazard + inventory + table (budget {BUDGET_S:g} s)",
                 "wall_s": budget, "cpu_s": sum(r["cpu_s"] for r in rows[1:])})
    frame = pd.DataFrame(rows)
    write_table("portfolio", frame, f"Portfolio: {n} columns over {args.sites} hazard sites",
                f"Surface: {args.study}; {args.resamples} bootstrap resamples; wall and CPU "
                "(process) seconds of one run, single process; the machine's other load "
                f"counts in wall (1-minute load average {load_before:.1f} before, "
                f"{os.getloadavg()[0]:.1f} after, on {os.cpu_count()} cores).")
    print(frame.to_string(index=False))
    return 0
