"""``rocking motions``: a record and its synthetic RDK pairs, written as one ensemble file.

The pipeline is :func:`rocking.motions.build.build_ensemble`; this command writes the
record first, then the pairs, with :mod:`rocking.motions.ensemble_io`, and the fitted
parameters as JSON.

Example::

    rocking motions --record el-centro-1940 -n 10 --seed 2017 \\
        -o results/motions/elcentro.nc
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from ..motions.build import HIGHPASS_KINDS


def _rotation(text: str) -> float | str:
    if text.strip().lower() == "auto":
        return "auto"
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"rotation must be 'auto' or degrees, got {text!r}") \
            from None


def add_parser(subparsers) -> None:
    """Register the ``motions`` subcommand."""
    p = subparsers.add_parser(
        "motions",
        help="record + synthetic RDK pairs to an ensemble file",
        description="Rotate a record pair to its principal axes, high-pass it, fit the "
        "Rezaeian-Der Kiureghian model and write the record plus N synthetic pairs.",
    )
    src = p.add_mutually_exclusive_group()
    src.add_argument("--record", default=None,
                     help="named record (el-centro-1940, loma-prieta-corralitos, "
                     "loma-prieta-sjte); default el-centro-1940")
    src.add_argument("--files", nargs=2, metavar=("X", "Y"), default=None,
                     help="two component files (AT2 or text, in g)")
    p.add_argument("--paths", nargs=2, metavar=("X", "Y"), default=None,
                   help="files for a named record (e.g. RSN801 SJTE315 SJTE225)")
    p.add_argument("--name", default=None, help="motion name when --files is used")
    p.add_argument("-n", "--n-synthetic", type=int, default=10, help="synthetic pairs")
    p.add_argument("--seed", type=int, default=2017, help="root seed")
    p.add_argument("--rotation", type=_rotation, default="auto",
                   help="'auto' or the forced offset of the major axis [deg], e.g. 22.33")
    p.add_argument("--highpass", choices=HIGHPASS_KINDS, default="oscillator")
    p.add_argument("--fc-hz", type=float, default=None,
                   help="high-pass corner [Hz] (default: Brune corner of --mw)")
    p.add_argument("--mw", type=float, default=None,
                   help="moment magnitude (default: the named record's)")
    p.add_argument("--stress-bar", type=float, default=50.0, help="Brune stress drop [bar]")
    p.add_argument("--beta-kms", type=float, default=3.5, help="shear-wave velocity [km/s]")
    p.add_argument("--order", type=int, default=4, help="Butterworth order")
    p.add_argument("--method", choices=("time", "spectral"), default="time")
    p.add_argument("--axes", choices=("principal", "record"), default="principal")
    p.add_argument("--max-duration", type=float, default=None,
                   help="keep the first seconds of every motion [s]")
    p.add_argument("-o", "--out", type=Path, required=True, help="ensemble file (.nc)")
    p.add_argument("--params-out", type=Path, default=None,
                   help="JSON of settings and fitted parameters (default: OUT with .json)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress on stderr")
    p.set_defaults(func=run)


def run(args) -> int:
    """Build the ensemble, write the NetCDF and JSON files; returns 0."""
    from ..motions.build import build_ensemble, read_motion
    from ..motions.ensemble_io import save_ensemble

    def say(message: str) -> None:
        if not args.quiet:
            print(f"rocking motions: {message}", file=sys.stderr, flush=True)

    if args.out.suffix.lower() != ".nc":
        raise ValueError(f"out must end in .nc, got {str(args.out)!r}")
    record = args.record if (args.record or args.files) else "el-centro-1940"
    paths = args.files or args.paths
    motion = read_motion(record, paths, args.name)
    say(f"read {motion.name} ({motion.npts} samples, dt {motion.dt} s, vector PGA "
        f"{motion.pga_g:.4f} g){' [stand-in]' if motion.metadata.get('stand_in') else ''}")
    build = build_ensemble(
        motion, args.n_synthetic, args.seed, rotation=args.rotation, highpass=args.highpass,
        fc_hz=args.fc_hz, mw=args.mw, stress_bar=args.stress_bar, beta_kms=args.beta_kms,
        order=args.order, method=args.method, axes=args.axes, max_duration=args.max_duration,
        progress=say,
    )
    params = build.parameters()
    save_ensemble(args.out, build.motions, attrs={k: params[k] for k in (
        "record", "label", "stand_in", "stand_in_for", "rotation_deg", "highpass", "seed",
        "n_synthetic")})
    params_out = args.params_out or args.out.with_suffix(".json")
    params_out.parent.mkdir(parents=True, exist_ok=True)
    params_out.write_text(json.dumps(params, indent=2, sort_keys=True, default=str) + "\n")
    say(f"wrote {len(build.motions)} motions to {args.out} and parameters to {params_out}")
    return 0
