"""``python -m benchmarks motions``: cost of the ground-motion stage.

Rows: reading and processing the El Centro pair (principal axes + oscillator high-pass),
fitting the RDK model to it (count-based and spectrum-matched identification), simulating
200 high-passed pairs, and 200 response spectra at 100 periods. Each timing is the best
of ``--repeat`` runs after one warm-up (numba compiles and caches are excluded).
Writes ``docs/benchmarks/motions.csv`` and ``.md``.
"""

from __future__ import annotations

import argparse

import numpy as np
import pandas as pd

from benchmarks._io import best_of, write_table


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and write the tables; returns 0."""
    p = argparse.ArgumentParser(prog="python -m benchmarks motions")
    p.add_argument("--n", type=int, default=200, help="synthetic pairs and spectra")
    p.add_argument("--periods", type=int, default=100, help="periods per spectrum")
    p.add_argument("--repeat", type=int, default=3, help="timed runs per row (best kept)")
    p.add_argument("--seed", type=int, default=2017)
    args = p.parse_args(argv)

    from rocking.motions.catalogue import load_record
    from rocking.motions.highpass import brune_corner, highpass_motion
    from rocking.motions.principal import to_principal_axes
    from rocking.motions.response_spectrum import pseudo_acceleration

    rows = []
    fc = brune_corner(6.95)

    def process():
        rotated, _ = to_principal_axes(load_record("el-centro-1940"))
        return highpass_motion(rotated, "oscillator", fc)

    t, record = best_of(process, args.repeat)
    rows.append({"task": "read + sha256 + principal axes + high-pass, El Centro pair",
                 "n": 1, "seconds": t, "per_item_ms": 1e3 * t})

    from rocking.motions.stochastic import fit_rdk, synthesize

    rotated, _ = to_principal_axes(load_record("el-centro-1940"))
    t, _ = best_of(lambda: fit_rdk(rotated, 0.0, method="counts", seed=args.seed),
                    max(1, args.repeat - 2))
    rows.append({"task": "fit_rdk, counts (both components; zeta search, 50 sims per zeta)",
                 "n": 1, "seconds": t, "per_item_ms": 1e3 * t})
    t, fit = best_of(lambda: fit_rdk(rotated, 0.0, fc_hz=fc, seed=args.seed),
                      max(1, args.repeat - 2))
    steps = fit.major.diagnostics["spectrum_fit"]["iterations"]
    rows.append({"task": f"fit_rdk, spectrum (both components; {steps} Gauss-Newton steps, "
                         "20 sims each)", "n": 1, "seconds": t, "per_item_ms": 1e3 * t})

    t, pairs = best_of(lambda: synthesize(fit, args.n, args.seed, fc_hz=fc),
                        max(1, args.repeat - 2))
    rows.append({"task": f"synthesize {args.n} pairs (time domain, oscillator high-pass)",
                 "n": args.n, "seconds": t, "per_item_ms": 1e3 * t / args.n})

    acc = np.vstack([m.ax for m in pairs])
    periods = np.logspace(-2, 1, args.periods)
    t, _ = best_of(lambda: pseudo_acceleration(acc, record.dt, periods), args.repeat)
    rows.append({"task": f"{args.n} response spectra x {args.periods} periods "
                         f"({acc.shape[1]} samples)",
                 "n": args.n, "seconds": t, "per_item_ms": 1e3 * t / args.n})

    df = pd.DataFrame(rows)
    df["seconds"] = df["seconds"].round(4)
    df["per_item_ms"] = df["per_item_ms"].round(3)
    write_table(
        "motions", df, "Ground-motion stage",
        notes=f"Best of {args.repeat} runs after a warm-up (fit and synthesis: best of "
        f"{max(1, args.repeat - 2)}); El Centro RSN 6, dt = 0.01 s, high-pass at the Brune "
        f"corner {fc:.4f} Hz.",
    )
    return 0
