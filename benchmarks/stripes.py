"""Convergence of the multiple-stripe fragility with the number of stripes and of motions.

``python -m benchmarks stripes [--synthetic N] [--stripes M] [--R R]`` writes
``docs/benchmarks/stripes.csv`` / ``.md``: for a cylinder (default R = 6 m, tan α = 0.2,
mode 3d) under El Centro and N synthetic pairs of the study's ensemble builder (seed 2017),
every motion is analysed once at each of M reference stripes geometric over (1, 20]
(:func:`rocking.fragility.stripes.stripe_intensities`). Since one analysis at an intensity does
not depend on the other stripes, coarser stripe sets are subsets of the reference (every s-th
stripe, at each of the s phases) and smaller ensembles are subsets of the motions, so the
convergence is measured without re-running anything:

- stripes: the median θ of overturning and θ > α/3 fitted to every s-th stripe, against the
  reference (all M stripes, all motions): the largest and the median relative change over the
  s phases;
- motions: the median fitted to random subsets of n motions (all M stripes), its spread over
  the subsets (the record-to-record sampling error that more stripes cannot remove), and the
  Wald standard error the fit itself reports.

Beside them, the first-exceedance answers of the default search for the same motions: their
mean and their lognormal median (:func:`rocking.fragility.lognormal.fit_lognormal`).
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
import pandas as pd

from benchmarks._io import write_table
from rocking.dynamics.bodies import Cylinder
from rocking.fragility.lognormal import fit_lognormal
from rocking.fragility.stripes import fit_stripes, stripe_intensities, stripe_outcomes
from rocking.spectra.accuracy import Accuracy
from rocking.spectra.critical import critical_intensity
from rocking.spectra.limit_states import parse_limit_states
from rocking.spectra.modes import MODE_3D

STATES = ("overturning", "tilt:1/3")
STRIDES = (1, 2, 4, 8, 16, 32)
SUBSETS = (4, 8, 12, 16)
N_DRAWS = 40


def _ensemble(n: int):
    from rocking.motions.build import build_ensemble
    from rocking.motions.catalogue import load_record

    return build_ensemble(load_record("el-centro-1940"), n, seed=2017).motions


def _fit(x, exceeded, j):
    k = exceeded[:, :, j].sum(axis=1)
    n = np.full(x.size, exceeded.shape[1])
    return fit_stripes(x, k, n)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks stripes")
    p.add_argument("--synthetic", type=int, default=20, help="synthetic pairs beside the record")
    p.add_argument("--stripes", type=int, default=160, help="reference stripes in (1, 20]")
    p.add_argument("--R", type=float, default=6.0, help="cylinder semi-diagonal [m]")
    p.add_argument("--tan-alpha", type=float, default=0.2)
    args = p.parse_args(argv)
    body = Cylinder(args.R, args.tan_alpha)
    states = parse_limit_states(list(STATES), sort=False)
    acc = Accuracy.of("default")
    motions = _ensemble(args.synthetic)
    x = stripe_intensities(args.stripes)
    t0 = time.perf_counter()
    outs = [stripe_outcomes(body, m, states, x, MODE_3D, acc) for m in motions]
    t_stripes = time.perf_counter() - t0
    exceeded = np.stack([o[0] for o in outs], axis=1)  # (stripes, motions, states)
    if any(o[1].any() for o in outs):
        print("warning: some analyses failed; they count as not exceeding here")
    runs = sum(o[2] for o in outs)
    rows = []
    for j, name in enumerate(STATES):
        ref = _fit(x, exceeded, j)
        rows.append({"limit_state": name, "study": "reference", "stripes": x.size,
                     "motions": len(motions), "median": ref.median, "beta": ref.beta,
                     "ci_lo": ref.median_ci[0], "ci_hi": ref.median_ci[1],
                     "max_rel_change": 0.0, "median_rel_change": 0.0, "status": ref.status})
        for s in STRIDES[1:]:
            meds = np.array([_fit(x[ph::s], exceeded[ph::s], j).median for ph in range(s)])
            change = np.abs(meds / ref.median - 1.0)
            rows.append({"limit_state": name, "study": f"every {s}th stripe, {s} phases",
                         "stripes": x[::s].size, "motions": len(motions),
                         "median": float(np.nanmedian(meds)), "beta": math.nan,
                         "ci_lo": float(np.nanmin(meds)), "ci_hi": float(np.nanmax(meds)),
                         "max_rel_change": float(np.nanmax(change)),
                         "median_rel_change": float(np.nanmedian(change)),
                         "status": f"{int(np.isnan(meds).sum())} undefined"})
        rng = np.random.default_rng(0)
        for n in SUBSETS:
            if n >= len(motions):
                continue
            meds, ses = [], []
            for _ in range(N_DRAWS):
                pick = np.sort(rng.choice(len(motions), n, replace=False))
                f = _fit(x, exceeded[:, pick], j)
                meds.append(f.median)
                ses.append(math.log(f.median_ci[1] / f.median) / 1.959964)
            meds = np.array(meds)
            ok = np.isfinite(meds)
            spread = float(np.std(np.log(meds[ok]), ddof=1)) if ok.sum() > 1 else math.nan
            rows.append({"limit_state": name, "study": f"{N_DRAWS} random sets of {n} motions",
                         "stripes": x.size, "motions": n,
                         "median": float(np.nanmedian(meds)), "beta": math.nan,
                         "ci_lo": float(np.nanpercentile(meds, 5)),
                         "ci_hi": float(np.nanpercentile(meds, 95)),
                         "max_rel_change": float(np.nanmax(np.abs(meds / ref.median - 1))),
                         "median_rel_change": float(np.nanmedian(np.abs(meds / ref.median - 1))),
                         "status": f"sd ln median {spread:.3f}, fit se {np.nanmedian(ses):.3f}"})
    t1 = time.perf_counter()
    crit = [critical_intensity(body, m, list(STATES), MODE_3D, accuracy=acc) for m in motions]
    t_search = time.perf_counter() - t1
    for j, name in enumerate(STATES):
        vals = np.array([c.intensity[j] for c in crit])
        nr = np.array([bool(c.not_reached[j]) for c in crit])
        fit = fit_lognormal(np.where(nr, 20.0, vals), nr)
        rows.append({"limit_state": name, "study": "first exceedance (default search)",
                     "stripes": 0, "motions": len(motions), "median": fit.median,
                     "beta": fit.beta, "ci_lo": float(np.nanmin(vals)),
                     "ci_hi": float(np.nanmax(vals)), "max_rel_change": math.nan,
                     "median_rel_change": math.nan,
                     "status": f"mean {np.nanmean(vals):.4g} of {int((~nr).sum())} reached"})
    df = pd.DataFrame(rows)
    notes = (f"R = {args.R:g} m, tan alpha = {args.tan_alpha:g}, mode 3d, default accuracy; "
             f"El Centro + {args.synthetic} synthetic pairs (seed 2017). Reference: "
             f"{x.size} stripes geometric in (1, 20], {runs} analyses, {t_stripes:.0f} s; "
             f"first-exceedance searches {sum(c.n_analyses for c in crit)} analyses, "
             f"{t_search:.0f} s. Stride rows: ci_lo/ci_hi = smallest/largest median over the "
             "phases; motion rows: 5th/95th percentile over the random sets; first-exceedance "
             "row: median = lognormal fit, ci = smallest/largest answer.")
    path = write_table("stripes", df, "Multiple-stripe fragility: convergence", notes)
    print(notes)
    print(df.to_string(index=False))
    print(f"written {path}")
    return 0
