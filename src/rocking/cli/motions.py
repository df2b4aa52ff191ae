"""``rocking motions``: a record and its synthetic RDK pairs, written as one ensemble file.

The pipeline is :func:`rocking.motions.build.build_ensemble` (the workflow's ``motions``
rule calls it with the same settings); this command prints the fit quality (the ensemble's
median 5 % PSA ÷ the record's, per component and period band) and writes the record first,
then the pairs, with :mod:`rocking.motions.ensemble_io`, and the settings, fitted parameters
and fit quality as JSON. ``--compare`` also writes the other identification method's pairs
to ``<out stem>.compare.nc``.
"""

from __future__ import annotations

import sys
from pathlib import Path

from rocking.cli import _common

EXAMPLES = """\
  rocking motions --record el-centro-1940 -n 10 --seed 2017 -o results/motions/elcentro.nc
  rocking motions --record loma-prieta-sjte --files RSN801_LOMAP_SJTE315.AT2 \\
      RSN801_LOMAP_SJTE225.AT2 -n 10 -o results/motions/lomaprieta.nc
  rocking motions --files x.AT2 y.AT2 --name my-site --mw 6.5 -n 5 -o my-site.nc"""


def add_parser(subparsers) -> None:
    """Register the ``motions`` subcommand."""
    p = _common.add_command(
        subparsers, "motions", examples=EXAMPLES,
        help="record + synthetic RDK pairs -> ensemble file (.nc)",
        description="Rotate a record pair to its principal axes, high-pass it, fit the "
        "Rezaeian-Der Kiureghian model and write the record plus N synthetic pairs to one "
        "ensemble file (the record first). Default record: el-centro-1940.")
    _common.add_motion_source(p, ensemble=False)
    p.add_argument("--name", default=None,
                   help="motion name for --files without --record (default: the file stems)")
    p.add_argument("--vertical", action="store_true",
                   help="with --record: keep its vertical component (UP/DWN file) in the "
                   "record; three --files (x y z) imply it. Synthetic pairs stay horizontal")
    p.add_argument("-n", "--n-synthetic", type=int, default=10, help="synthetic pairs")
    p.add_argument("--seed", type=int, default=2017, help="root seed")
    _common.add_processing(p, rotation_default="auto", highpass_default="oscillator")
    g = p.add_argument_group("high-pass and simulation details")
    g.add_argument("--stress-bar", type=float, default=50.0, help="Brune stress drop [bar]")
    g.add_argument("--beta-kms", type=float, default=3.5, help="shear-wave velocity [km/s]")
    g.add_argument("--order", type=int, default=4, help="Butterworth order")
    g.add_argument("--method", choices=("time", "spectral"), default="time",
                   help="RDK discretization")
    g.add_argument("--fit-method", choices=("spectrum", "counts"), default="spectrum",
                   help="identification: match the record's 5 %% response spectrum "
                   "(default) or the RDK 2010 zero-crossing/extrema counts")
    g.add_argument("--compare", action="store_true",
                   help="also build the other identification's pairs (same seed), written "
                   "to OUT with the suffix .compare.nc")
    g.add_argument("--axes", choices=("principal", "record"), default="principal",
                   help="axes of the synthetic pairs")
    p.add_argument("-o", "--out", type=Path, required=True, help="ensemble file (.nc)")
    p.add_argument("--params-out", type=Path, default=None,
                   help="JSON of settings and fitted parameters (default: OUT with .json)")
    p.add_argument("--write-params", type=Path, default=None, metavar="FILE",
                   help="also write the rounded RDK fit and the digests of its pairs as a "
                   "recorded-parameters file (config/ensembles/<name>.params.json, named by "
                   "ensembles.<name>.params of a study; docs/motions.md)")
    _common.add_quiet(p)
    p.set_defaults(func=run)


def run(args) -> int:
    """Build the ensemble, write the NetCDF and JSON files; returns 0."""
    from rocking import _json
    from rocking.motions.build import ENSEMBLE_ATTRS, build_ensemble, comparison_path, quality_lines
    from rocking.motions.ensemble_io import save_ensemble, write_digest
    from rocking.motions.source import load_motion

    def say(message: str) -> None:
        if not args.quiet:
            print(f"rocking motions: {message}", file=sys.stderr, flush=True)

    _common.check_output(args.out, (".nc",))
    if args.params_out is not None:
        _common.check_output(args.params_out, (".json",), "--params-out")
    if args.write_params is not None:
        _common.check_output(args.write_params, (".json",), "--write-params")
        if args.n_synthetic < 1:
            raise ValueError("--write-params needs synthetic pairs (--n-synthetic >= 1): the "
                             "file records their fit")
    if args.rotation is None:
        raise ValueError("--rotation none: the ensemble's record is always on principal axes "
                         "(its fit needs them); give 'auto' or the forced offset [deg]")
    record = args.record if (args.record or args.files) else "el-centro-1940"
    motion = load_motion(record, args.files, name=args.name,
                         order_by_azimuth=args.order_by_azimuth, dt=args.dt, units=args.units,
                         vertical=args.vertical)
    from rocking.config.checks import check_ensemble_size, check_magnitude

    check_ensemble_size("--n-synthetic", args.n_synthetic, motion.npts)
    check_magnitude("--mw", args.mw)
    say(f"read {motion.name} ({motion.npts} samples, dt {motion.dt} s, vector PGA "
        f"{motion.pga_g:.4f} g){' [stand-in]' if motion.metadata.get('stand_in') else ''}")
    build = build_ensemble(
        motion, args.n_synthetic, args.seed, rotation=args.rotation, highpass=args.highpass,
        fc_hz=args.fc_hz, mw=args.mw, stress_bar=args.stress_bar, beta_kms=args.beta_kms,
        order=args.order, method=args.method, axes=args.axes, max_duration=args.max_duration,
        fit_method=args.fit_method, compare=args.compare, progress=say,
    )
    params = build.parameters()
    print("\n".join(quality_lines(params)))
    attrs = {k: params[k] for k in ENSEMBLE_ATTRS}
    with _common.replacing(args.out) as tmp:
        save_ensemble(tmp, build.motions, attrs=attrs, digest=False)
    write_digest(args.out)  # the digest of the final name, checked before every read
    if build.comparison:
        with _common.replacing(comparison_path(args.out)) as tmp:
            save_ensemble(tmp, build.comparison, attrs={**attrs, **params["comparison"]},
                          digest=False)
        write_digest(comparison_path(args.out))
    params_out = args.params_out or args.out.with_suffix(".json")
    with _common.replacing(params_out) as tmp:
        _json.write(tmp, params, sort_keys=True)
    if args.write_params is not None:
        from rocking.motions.build import recorded_entries
        from rocking.motions.stochastic.recorded import write_params_file

        settings = {"record": record, "paths": None if not args.files else
                    [str(f) for f in args.files], "units": args.units, "dt": args.dt,
                    "mw": args.mw, "rotation_deg": args.rotation, "highpass": args.highpass,
                    "fc_hz": args.fc_hz, "fit_method": args.fit_method}
        with _common.replacing(args.write_params) as tmp:
            write_params_file(tmp, args.write_params.name.split(".")[0],
                              recorded_entries(build, [settings]))
        say(f"wrote the recorded parameters to {args.write_params}")
    say(f"wrote {len(build.motions)} motions to {args.out} and parameters to {params_out}")
    return 0
