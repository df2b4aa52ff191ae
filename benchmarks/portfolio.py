"""How long a site's portfolio takes: many columns over few hazard sites, and few columns over
a regional hazard file of many sites.

``python -m benchmarks portfolio [--study results/paper/elcentro] [--cases
10000x100,100x10000] [--resamples 1000]`` runs each case ``<columns>x<sites>``: it writes an
OpenQuake-format hazard file of that many sites (the example curve's site 0 scaled by
factors 0.3–1.5, on a 0.05° grid) and an inventory of that many random columns (heights
4–16 m, tan α 0.1–0.3, each within 2 km of a site) into a temporary folder, then times, wall
and CPU: building the surface (its bootstrap refits), reading the hazard's sites (the file
parsed once), reading and checking the inventory (each column given its nearest site), and
the portfolio table (every column: fragility with its interval, λ with its 90 % interval
over the resamples; the curves of the sites used made then). Writes
``docs/benchmarks/portfolio.{csv,md}``. The budgets: 10,000 columns over 100 sites within
30 s on 2 cores (issue 41); 100 columns over 10,000 sites in seconds (issue 47: it did not
finish in 10 minutes when every site re-read the file).
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

CASES = ("10000x100", "100x10000")
"""The cases run by default: ``<columns>x<sites>``."""


def write_hazard(path: Path, n_sites: int, seed: int = 41) -> None:
    """An OpenQuake hazard-curve CSV of ``n_sites`` sites: the example's site 0 scaled."""
    from rocking.risk.hazard import HazardCurve

    base = HazardCurve.from_file("config/hazard/example_hazard_curve.csv", site=0)
    rng = np.random.default_rng(seed)
    side = int(np.ceil(np.sqrt(n_sites)))
    head = ("#,,,,\"generated_by='rocking benchmark', kind='mean', investigation_time=1.0, "
            "imt='PGA', component='vector_peak'\"\ncustom_site_id,lon,lat,depth,"
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

    p = argparse.ArgumentParser(prog="python -m benchmarks portfolio")
    p.add_argument("--study", type=Path, default=Path("results/paper/elcentro"))
    p.add_argument("--cases", default=",".join(CASES),
                   help="comma-separated <columns>x<sites> (default: %(default)s)")
    p.add_argument("--resamples", type=int, default=1000)
    args = p.parse_args(argv)
    load_before = os.getloadavg()[0]
    rows = []
    for case in args.cases.split(","):
        n_columns, n_sites = (int(v) for v in case.lower().split("x"))
        rows += _case(args.study, n_columns, n_sites, args.resamples)
    frame = pd.DataFrame(rows)
    write_table("portfolio", frame, "Portfolio: many columns over few sites, few columns over "
                "many sites",
                f"Surface: {args.study}; {args.resamples} bootstrap resamples; wall and CPU "
                "(process) seconds of one run, single process; the machine's other load "
                f"counts in wall (1-minute load average {load_before:.1f} before, "
                f"{os.getloadavg()[0]:.1f} after, on {os.cpu_count()} cores).")
    print(frame.to_string(index=False))
    return 0


def _case(study: Path, n_columns: int, n_sites: int, resamples: int) -> list[dict]:
    """The timed steps of one case (module docstring)."""
    from rocking.fragility.surface import FragilitySurface
    from rocking.risk.inventory import read_hazard_sites, read_inventory
    from rocking.risk.portfolio import portfolio_table

    case = f"{n_columns} columns x {n_sites} sites"
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        hazard_path, inv_path = Path(tmp) / "hazard.csv", Path(tmp) / "columns.csv"
        write_hazard(hazard_path, n_sites)
        write_inventory(inv_path, n_columns, n_sites)
        surface, w, c = _timed(lambda: FragilitySurface.from_study(study,
                                                                   n_resamples=resamples))
        rows.append({"case": case, "step": "surface (bootstrap refits of every node)",
                     "wall_s": w, "cpu_s": c})
        hazard, w, c = _timed(lambda: read_hazard_sites(hazard_path))
        rows.append({"case": case, "step": f"hazard: {n_sites} sites read (one parse)",
                     "wall_s": w, "cpu_s": c})
        inventory, w, c = _timed(lambda: read_inventory(inv_path, surface=surface,
                                                        hazard=hazard))
        n = len(inventory.columns)
        rows.append({"case": case, "step": f"inventory: {n} columns checked, nearest of "
                     f"{n_sites} sites given", "wall_s": w, "cpu_s": c})
        table, w, c = _timed(lambda: portfolio_table(surface, inventory, hazard))
        rows.append({"case": case, "step": f"portfolio table: {n} columns × "
                     f"{table['limit_state'].nunique()} limit states × {resamples} resamples "
                     f"({len(hazard._made)} site curves made)", "wall_s": w, "cpu_s": c})
    rows.append({"case": case, "step": "hazard + inventory + table",
                 "wall_s": sum(r["wall_s"] for r in rows[1:]),
                 "cpu_s": sum(r["cpu_s"] for r in rows[1:])})
    return rows
