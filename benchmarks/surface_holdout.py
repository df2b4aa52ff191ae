"""The fragility surface's error against direct studies at hold-out columns.

``python -m benchmarks surface_holdout --ensemble results/motions/elcentro-*.nc
[--study results/paper/elcentro] [--accuracy default] [--reuse]`` searches the critical PGA
of every motion of the ensemble at :data:`HOLDOUT` (columns between the El Centro grid's
points, and one grid node as a control that must give the study's own numbers back), in 3D
for overturning and θ > α/3, fits each column's lognormal as the study does
(:func:`rocking.fragility.lognormal.fit_lognormal`), and compares with the surface built from
the study (:class:`rocking.fragility.surface.FragilitySurface`). Writes to ``docs/benchmarks/``:

- ``surface_holdout_critical.csv`` (under ``results/benchmarks/``): the searches (one row
  per column, motion, limit state);
  ``--reuse`` reads it back instead of searching again;
- ``surface_holdout.{csv,md}``: per column and limit state the direct median and β, the
  surface's with their bootstrap interval, and the errors;
- ``surface_loo.{csv,md}``: the leave-one-out errors of the surface on its own grid.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
import pandas as pd

from benchmarks._io import results_dir, write_table

HOLDOUT = ((3.0, 0.2), (1.25, 0.15), (3.25, 0.25), (5.25, 0.15), (7.75, 0.25), (9.25, 0.12))
"""(R [m], tan α [-]) of the hold-out columns; the first is a grid node (the control)."""

LIMIT_STATES = ("overturning", "tilt:1/3")
MODE = "3d"
UPPER = 20.0
"""The gallery's search bound PGA/(g tan α) (config/paper.yaml search.upper)."""


def search(ensemble: Path, accuracy: str) -> pd.DataFrame:
    """The critical PGA of every motion at every hold-out column (3D, both limit states)."""
    from rocking.execution.tasks import motions_by_name
    from rocking.spectra.critical import critical_intensity_batch

    motions = motions_by_name(ensemble)
    rows = []
    for R, tan_alpha in HOLDOUT:
        t0 = time.process_time()
        tasks = [(R, tan_alpha, m, MODE) for m in motions.values()]
        for res in critical_intensity_batch(tasks, list(LIMIT_STATES), accuracy=accuracy,
                                            upper=UPPER):
            for i, ls in enumerate(res.limit_states):
                rows.append({"mode": MODE, "limit_state": ls, "motion": res.motion,
                             "tan_alpha": tan_alpha, "R": R,
                             "pga_crit": float(res.intensity[i]),
                             "pga_crit_g": float(res.intensity[i]) * tan_alpha,
                             "not_reached": bool(res.not_reached[i])})
        print(f"R {R:g} m, tan α {tan_alpha:g}: {len(tasks)} motions searched in "
              f"{time.process_time() - t0:.1f} CPU s", flush=True)
    return pd.DataFrame(rows)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks surface_holdout")
    p.add_argument("--ensemble", type=Path, required=False,
                   help="the El Centro ensemble file (results/motions/elcentro-*.nc)")
    p.add_argument("--study", type=Path, default=Path("results/paper/elcentro"))
    p.add_argument("--accuracy", default="default")
    p.add_argument("--reuse", action="store_true",
                   help="read surface_holdout_critical.csv instead of searching")
    args = p.parse_args(argv)
    out = results_dir() / "surface_holdout_critical.csv"
    if args.reuse:
        critical = pd.read_csv(out)
    else:
        if args.ensemble is None:
            p.error("--ensemble is needed unless --reuse")
        critical = search(args.ensemble, args.accuracy)
        critical.to_csv(out, index=False, float_format="%.10g")
    compare(critical, args.study)
    return 0


HAZARD = "config/hazard/example_hazard_curve.csv"
"""The example hazard (site 0) under which λ is compared too."""


def compare(critical: pd.DataFrame, study: Path) -> pd.DataFrame:
    """The surface against the direct fits at the hold-out columns, and its leave-one-out
    errors; both tables written (module docstring)."""
    from rocking.fragility.lognormal import bootstrap_lognormal, fit_lognormal, percentile_interval
    from rocking.fragility.surface import FragilitySurface
    from rocking.risk.annual_frequency import mean_annual_frequencies
    from rocking.risk.hazard import HazardCurve

    surface = FragilitySurface.from_study(study)
    hazard = HazardCurve.from_file(HAZARD, site=0)
    rows = []
    for (R, ta, ls), cell in critical.groupby(["R", "tan_alpha", "limit_state"], sort=False):
        fit = fit_lognormal(cell["pga_crit"].to_numpy(float),
                            cell["not_reached"].astype(bool).to_numpy())
        med_b, _ = bootstrap_lognormal(cell["pga_crit"].to_numpy(float),
                                       cell["not_reached"].astype(bool).to_numpy())
        d_lo, d_hi = percentile_interval(med_b * ta)
        ev = surface.evaluate([R], [ta], MODE, ls)
        m_d, b_d = fit.median * ta, fit.beta
        m_s, b_s = float(ev["median"][0]), float(ev["beta"][0])
        lam_d, lam_s = mean_annual_frequencies(np.array([m_d, m_s]), np.array([b_d, b_s]),
                                               hazard)
        rows.append({"R": R, "tan_alpha": ta, "limit_state": ls, "motions": len(cell),
                     "median_direct": m_d, "median_direct_p05": float(d_lo),
                     "median_direct_p95": float(d_hi), "median_surface": m_s,
                     "median_surface_p05": float(ev["median_p05"][0]),
                     "median_surface_p95": float(ev["median_p95"][0]),
                     "err_median_pct": 100 * (m_s / m_d - 1), "beta_direct": b_d,
                     "beta_surface": b_s, "err_beta": b_s - b_d, "lambda_direct": lam_d,
                     "lambda_surface": lam_s, "err_lambda_pct": 100 * (lam_s / lam_d - 1)})
    table = pd.DataFrame(rows)
    write_table("surface_holdout", table, "Fragility surface against direct studies at hold-out "
                "columns (El Centro, 3D)",
                f"Surface: {study} (bilinear in ln R and tan α of ln(θ/tan α) and β); "
                "direct: the ensemble searched at each column and fitted as the study fits "
                "(same preset and bound); "
                f"λ under {HAZARD} site 0. The first column is a grid node (the control).")
    loo = surface.loo_summary()
    write_table("surface_loo", loo, "Fragility surface: leave-one-out errors on its grid",
                "ln θ error = ln(predicted / study) (×100 ≈ %), β error = predicted − study; "
                "R: interior R nodes predicted along ln R; tan_alpha: the tan α 0.2 row "
                "predicted from 0.1 and 0.3.")
    print(table.to_string(index=False))
    print(loo.to_string(index=False))
    return table
