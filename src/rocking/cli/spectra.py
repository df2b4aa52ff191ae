"""``rocking spectra``: one seismic performance rocking spectrum to CSV or JSON.

Example::

    rocking spectra --R 0.5,1,2,5,10 --tan-alpha 0.2 --record el-centro-1940 \\
        --mode 3d --limit-states tilt:1/3,overturning --accuracy default -o spectrum.csv
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import pandas as pd

from ..spectra.accuracy import PRESETS, get_accuracy
from ..spectra.critical import MODES, critical_intensity_batch
from ..spectra.limit_states import parse_limit_states
from ..spectra.search import DEFAULT_UPPER


def _floats(text: str) -> list[float]:
    """Comma-separated numbers (``"0.5,1,2"``)."""
    try:
        return [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}") \
            from None


def add_parser(subparsers) -> None:
    """Register the ``spectra`` subcommand."""
    p = subparsers.add_parser(
        "spectra",
        help="critical PGA/(g tan α) of cylinders vs R for one scaled record",
        description="Seismic performance rocking spectrum of one ground-motion pair: for each "
        "R, the smallest normalized intensity PGA/(g tan α) exceeding each limit state.",
    )
    p.add_argument("--R", dest="R", type=_floats, action="extend", required=True,
                   help="cylinder semi-diagonals [m], comma-separated or repeated")
    p.add_argument("--tan-alpha", type=float, default=0.2, help="slenderness b/h [-]")
    src = p.add_mutually_exclusive_group()
    src.add_argument("--record", default="el-centro-1940",
                     help="named record (see rocking.motions.records); default el-centro-1940")
    src.add_argument("--files", nargs=2, metavar=("X", "Y"),
                     help="two component files (x, y) in g instead of a named record")
    p.add_argument("--mode", choices=list(MODES), default="3d")
    p.add_argument("--limit-states", default="default",
                   help="comma-separated: overturning, tilt:<r> (e.g. tilt:1/3); 'default' = "
                   "tilt:0.1,0.2,1/3,0.5,0.75,1 and overturning")
    p.add_argument("--accuracy", choices=sorted(PRESETS), default="default",
                   help="search and ODE tolerances preset")
    p.add_argument("--upper", type=float, default=DEFAULT_UPPER,
                   help="highest PGA/(g tan α) searched [-]")
    p.add_argument("--omega-n", type=float, default=None,
                   help="contact spring frequency of mode 3d-damped [rad/s]")
    p.add_argument("--zeta", type=float, default=None, help="contact damping ratio [-]")
    p.add_argument("-o", "--out", type=Path, default=None,
                   help="output file, .csv or .json (default: table on stdout)")
    p.set_defaults(func=run)


def _motion(args):
    from ..motions.records import load_record  # import the readers only when the command runs

    if args.files:
        return load_record(Path(args.files[0]).stem, paths=args.files)
    return load_record(args.record)


def run(args) -> int:
    """Compute the spectrum and write it; returns 0."""
    out = args.out
    if out is not None and out.suffix.lower() not in {".csv", ".json"}:
        raise ValueError(f"out must end in .csv or .json, got {str(out)!r}")
    states = parse_limit_states(args.limit_states)
    acc = get_accuracy(args.accuracy)
    motion = _motion(args)
    tasks = [(R, args.tan_alpha, motion, args.mode) for R in args.R]
    t0 = time.perf_counter()
    results = critical_intensity_batch(tasks, states, accuracy=acc, upper=args.upper,
                                       omega_n=args.omega_n, zeta=args.zeta)
    seconds = time.perf_counter() - t0
    table = pd.concat([r.to_frame() for r in results], ignore_index=True)
    if out is None:
        cols = ["R", "limit_state", "intensity", "not_reached", "non_monotonic", "failed",
                "n_analyses"]
        print(table[cols].to_string(index=False))
    elif out.suffix.lower() == ".csv":
        out.parent.mkdir(parents=True, exist_ok=True)
        table.to_csv(out, index=False)
    else:
        out.parent.mkdir(parents=True, exist_ok=True)
        doc = {
            "motion": {"name": motion.name, "pga": motion.pga, "dt": motion.dt,
                       "npts": motion.npts,
                       "metadata": json.loads(json.dumps(motion.metadata, default=str))},
            "mode": args.mode,
            "tan_alpha": args.tan_alpha,
            "limit_states": [s.name for s in states],
            "accuracy": acc.to_dict(),
            "upper": args.upper,
            "seconds": seconds,
            # NaN is not JSON: a not-reached intensity is written as null.
            "results": [{k: (None if isinstance(v, float) and v != v else v)
                         for k, v in row.items()} for r in results for row in r.to_records()],
        }
        out.write_text(json.dumps(doc, indent=1) + "\n")
    n = sum(r.n_analyses for r in results)
    print(f"{len(results)} spectrum point(s), {n} analyses, {seconds:.2f} s", file=sys.stderr)
    return 0
