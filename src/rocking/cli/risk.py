"""``rocking risk``: mean annual frequency of each limit state of a study under a hazard curve.

Reads a study's ``fragility.csv`` (the lognormal fits of the performance spectra, PGA),
``suite_fragility.csv`` (the same over the suite in each intensity measure) or
``stripe_fragility.csv`` (the multiple-stripe fits; which one is told by its columns) and a
hazard curve (an OpenQuake hazard-curve CSV of PGA or SA(T), a two-column table, or a power law
``k0,k``), brings the fragility into the hazard's measure, component and unit
(:func:`rocking.risk.reconcile.reconcile`: refitted from the study's motions beside the table
where its component is another, refused where the measure is one the study does not fit),
and prints or writes the risk table: per mode, tan α, R and limit state the mean
annual frequency [1/yr] with its 90 % bootstrap interval (from ``<table>_bootstrap.nc`` beside
the table), return period [yr] and probability of exceedance in 50 years
(:func:`rocking.risk.risk_table`). Rows without a fit are kept with their status (and named in
one line). ``--json`` prints the table as JSON. Optionally writes the OpenQuake NRML and
pelicun exports of the same fragilities (PGA only).
"""

from __future__ import annotations

from pathlib import Path

from rocking.cli import _common, _human
from rocking.cli.stripes import COMPONENT_NAMES
from rocking.spectra.accuracy import DEFAULT_UPPER

EXAMPLES = """\
  rocking risk --fragility results/paper/elcentro/fragility.csv \\
      --hazard config/hazard/example_hazard_curve.csv --site-lon 0 --site-lat 0
  rocking risk --fragility results/elcentro/fragility.csv --hazard 1e-4,2.5 --mode 3d \\
      --limit-states overturning -o risk.csv
  rocking risk --fragility results/elcentro/fragility.csv --hazard hazard_curve-mean-PGA.csv \\
      --site-id ATH --im-factor 1.1 --nrml fragility.nrml.xml --pelicun fragility.pelicun.csv
  rocking risk --fragility results/mysuite/suite_fragility.csv \\
      --hazard "hazard_curve-quantile_0.85-SA(1.0).csv" --measure sa:1.0 \\
      --site-lon 23.73 --site-lat 37.98 --kind quantile-0.85"""

HEADER = ("mode", "tan α [-]", "R [m]", "limit state", "median [g]",
          "median PGA/(g tan α) [-]", "β [-]", "n",
          "λ [1/yr]", "λ 5 % [1/yr]", "λ 95 % [1/yr]", "return period [yr]", "P(50 yr) [-]",
          "fit")
"""Columns printed on the terminal (a file or ``--json`` gets every column of the table)."""


def add_parser(subparsers) -> None:
    """Register the ``risk`` subcommand."""
    p = _common.add_command(
        subparsers, "risk", examples=EXAMPLES,
        help="mean annual frequency of each limit state under a hazard curve",
        description="From fragility to risk: integrate each lognormal fragility of a study's "
        "fragility table against a hazard curve of PGA or Sa(T) [g], with the 90 %% interval "
        "of a bootstrap over the motions. The fragility and the hazard must be in one "
        "horizontal component: --component names the hazard's (a table's component column "
        "says the fragility's; docs/risk.md).",
    )
    p.add_argument("--fragility", type=Path, required=True,
                   help="a study's fragility table: results/<study>/fragility.csv or .nc "
                   "(critical intensities, PGA), suite_fragility.csv (critical intensities in "
                   "each intensity measure), or stripe_fragility.csv (multiple stripes)")
    p.add_argument("--hazard", required=True,
                   help="OpenQuake hazard-curve CSV (PGA or SA(T)), a two-column table "
                   "(intensity, annual_rate or poe), or a power law 'k0,k' (annual rate "
                   "k0 IM^-k, IM in g)")
    p.add_argument("--measure", default=None,
                   help="intensity measure: pga or sa:<T> (default: the hazard file's; pga "
                   "for a power law)")
    site = p.add_argument_group(
        "site and curve of an OpenQuake hazard file of several sites (studies: hazard.site, "
        "hazard.kind)")
    site.add_argument("--site-id", default=None,
                      help="the site whose custom_site_id is this")
    site.add_argument("--site-lon", type=float, default=None,
                      help="the site nearest this longitude [deg] (with --site-lat)")
    site.add_argument("--site-lat", type=float, default=None,
                      help="the site nearest this latitude [deg] (with --site-lon)")
    site.add_argument("--max-distance-km", type=float, default=None,
                      help="farthest the nearest site may be from --site-lon/--site-lat "
                      "(great-circle) [km] (default 5)")
    site.add_argument("--site", type=int, default=None, help="the site of this row (0 = first)")
    site.add_argument("--kind", default=None,
                      help="the curve's statistic when it is not the mean: quantile-<q> or "
                      "rlz-<n>, as the file's kind= says (a quantile is never taken as the "
                      "mean)")
    p.add_argument("--hazard-unit", default=None,
                   help="unit of the hazard's levels when the file does not say: g, m/s2, "
                   "cm/s2 or gal (default g, OpenQuake's unit of PGA and SA)")
    p.add_argument("--investigation-time", type=float, default=None,
                   help="investigation time of a two-column table's poe [yr]")
    p.add_argument("--component", default=None, choices=COMPONENT_NAMES, type=str.lower,
                   help="horizontal component of the hazard, any case (RotD50 for NGA-West2 "
                   "models): the fragility is taken or refitted in it (default: a "
                   "component= comment of the hazard file; for an OpenQuake file without "
                   "one rotd50, said; else the table's)")
    p.add_argument("--im-factor", type=float, default=1.0,
                   help="study PGA / hazard PGA (e.g. RotD100/RotD50), instead of "
                   "--component")
    p.add_argument("--mode", default=None,
                   help="only this mode (3d, 3d-damped, 3d-x, 3d-y, 2d-x, 2d-y)")
    p.add_argument("--tan-alpha", type=float, default=None, help="only this slenderness")
    _common.add_dimensions(p)  # only the row of this body (its R and tan alpha)
    p.add_argument("--limit-states", default=None,
                   help="only these, comma-separated (e.g. overturning,tilt:1/3)")
    p.add_argument("-o", "--out", type=Path, default=None,
                   help="write the table to this .csv (default: print it)")
    p.add_argument("--upper", type=float, default=DEFAULT_UPPER,
                   help="the study's search bound PGA/(g tan alpha), for the NRML maxIML [-]")
    p.add_argument("--nrml", type=Path, default=None,
                   help="also write the OpenQuake NRML 0.5 fragility model here (.xml)")
    p.add_argument("--pelicun", type=Path, default=None,
                   help="also write the pelicun damage model CSV here (.csv)")
    _human.add_json(p, "the table (with the hazard and the fragility it integrates)")
    p.set_defaults(func=run)


def _hazard(args):
    from rocking.motions.measures import same_measure
    from rocking.risk.hazard import parse_hazard

    if args.component is not None and args.im_factor != 1.0:
        raise ValueError("give --component (the fragility in the hazard's component) or "
                         "--im-factor (the hazard rescaled), not both")
    spec = {"file": args.hazard}
    site = _site(args)
    for key, value in (("site", site), ("investigation_time", args.investigation_time),
                       ("kind", args.kind), ("unit", args.hazard_unit)):
        if value is not None:
            spec[key] = value
    if Path(args.hazard).exists():
        curve = parse_hazard(spec, component=args.component)
        if args.measure is not None and not same_measure(args.measure, curve.measure):
            raise ValueError(f"--measure {args.measure} does not match the hazard "
                             f"{args.hazard}, which is of {curve.imt}")
    elif len(spec) > 1:
        raise ValueError(f"--hazard {args.hazard!r} is no file: --site*, --kind, "
                         "--hazard-unit and --investigation-time apply to a hazard file")
    else:
        curve = parse_hazard(args.hazard, measure=args.measure, component=args.component)
    return curve.scaled(args.im_factor) if args.im_factor != 1.0 else curve


def _site(args):
    """The hazard.site mapping (or row) of the --site* options; None without them."""
    near = args.site_lon is not None or args.site_lat is not None
    given = [name for name, there in (("--site-id", args.site_id is not None),
                                      ("--site-lon/--site-lat", near),
                                      ("--site", args.site is not None)) if there]
    if len(given) > 1:
        raise ValueError(f"give one of --site-id, --site-lon/--site-lat, --site, got "
                         f"{' and '.join(given)}")
    if (args.site_lon is None) != (args.site_lat is None):
        raise ValueError("--site-lon and --site-lat go together")
    if args.max_distance_km is not None and args.site_lon is None:
        raise ValueError("--max-distance-km applies to --site-lon/--site-lat")
    if args.site_id is not None:
        return {"id": args.site_id}
    if args.site_lon is not None:
        near = {"lon": args.site_lon, "lat": args.site_lat}
        if args.max_distance_km is not None:
            near["max_distance_km"] = args.max_distance_km
        return near
    return args.site


def _select(frag, args):
    """The rows (with a fit or without) of the mode, tan α and limit states asked for."""
    import dataclasses

    import pandas as pd

    from rocking.spectra.limit_states import parse_limit_states

    both = pd.concat([frag.rows.assign(_fit=True), frag.skipped.assign(_fit=False)],
                     ignore_index=True)
    if args.mode is not None:
        if args.mode not in set(both["mode"]):
            raise ValueError(f"--mode {args.mode!r} is not in the table (has "
                             f"{sorted(set(both['mode']))})")
        both = both[both["mode"] == args.mode]
    if args.tan_alpha is not None:
        both = both[(both["tan_alpha"] - args.tan_alpha).abs() < 1e-9]
        if both.empty:
            raise ValueError(f"--tan-alpha {args.tan_alpha:g} is not in the table")
    both = _body_rows(both, args)
    if args.limit_states is not None:
        names = [ls.name for ls in parse_limit_states(args.limit_states, sort=False)]
        both = both[both["limit_state"].isin(names)]
        if both.empty:
            raise ValueError(f"--limit-states {args.limit_states!r}: none in the table")
    rows = both[both["_fit"].astype(bool)].drop(columns="_fit").reset_index(drop=True)
    skipped = both[~both["_fit"].astype(bool)].drop(columns="_fit").reset_index(drop=True)
    return dataclasses.replace(frag, rows=rows, skipped=skipped)


def _body_rows(rows, args):
    """The rows of the body of ``--height``/``--diameter`` (its R and tan α, printed on
    stderr), or a line saying which bodies the table has."""
    import sys

    from rocking.dynamics.dimensions import AGREE_RTOL, body_line, body_size, swap_warning

    size = body_size(args.height, args.diameter, tan_alpha=args.tan_alpha,
                     names=("--height", "--diameter", "--R", "--tan-alpha"))
    if size is None:
        return rows
    R, tan_alpha = size
    print(f"rocking risk: {body_line(args.height, args.diameter, R, tan_alpha)}",
          file=sys.stderr)
    swapped = swap_warning(args.height, args.diameter, ("--height", "--diameter"))
    if swapped:
        print(f"rocking risk: {swapped}", file=sys.stderr)
    mine = ((rows["R"] - R).abs() <= AGREE_RTOL * R) \
        & ((rows["tan_alpha"] - tan_alpha).abs() <= AGREE_RTOL * tan_alpha)
    if not mine.any():
        sizes = sorted({float(r) for r in rows["R"]})
        shown = ", ".join(f"{r:g}" for r in sizes[:6]) + (", ..." if len(sizes) > 6 else "")
        raise ValueError(f"--height {args.height:g} --diameter {args.diameter:g} (R = {R:.6g} "
                         f"m, tan alpha = {tan_alpha:.6g}) is not a body of the table (tan "
                         f"alpha {sorted({float(t) for t in rows['tan_alpha']})}, R {shown}); "
                         f"run the study with studies.<name>.height and diameter")
    return rows[mine]


def run(args) -> int:
    """Print or write the risk table (and the exports when asked); returns 0."""
    from rocking.motions.measures import VECTOR_PEAK
    from rocking.risk.nrml import write_nrml
    from rocking.risk.pelicun import write_pelicun_csv
    from rocking.risk.reconcile import reconcile
    from rocking.risk.risk_table import risk_table

    if args.out is not None:
        _common.check_output(args.out, (".csv",))
    if not args.fragility.exists():
        raise ValueError(f"--fragility: no such file: {str(args.fragility)!r}")
    # and the tables beside it a refit in the hazard's terms reads (rocking.risk.reconcile)
    _common.check_handed([args.fragility, *(args.fragility.parent / n for n in
                                            ("critical.csv", "motion_measures.csv"))], "risk")
    hazard = _hazard(args)
    frag = _select(reconcile(args.fragility, hazard), args)
    table = risk_table(frag, hazard)
    if (args.nrml is not None or args.pelicun is not None) and (
            hazard.measure != "pga" or frag.component != VECTOR_PEAK):
        raise ValueError("--nrml and --pelicun export vector-peak PGA fragilities only")
    if args.nrml is not None:
        write_nrml(frag, args.nrml, search_upper=args.upper)
    if args.pelicun is not None:
        write_pelicun_csv(frag, args.pelicun)
    if args.out is not None:
        with _common.replacing(args.out) as tmp:
            table.to_csv(tmp, index=False, float_format="%.6g")
    if args.json:
        from rocking import _json
        from rocking.units import strip_units

        plain = table.rename(columns={c: strip_units(c) for c in table.columns})
        from rocking.report.risk import below_first_warning

        print(_json.dumps({"hazard": hazard.source, "fragility": frag.kind,
                           "measure": hazard.measure, "component": frag.component,
                           "terms_note": frag.note, "hazard_note": hazard.note,
                           "hazard_site": hazard.site, "hazard_kind": hazard.kind,
                           "hazard_unit": hazard.unit,
                           "below_first_warning": below_first_warning(table),
                           "skipped": frag.skipped_note(),
                           "units": {strip_units(c): c.split(" [", 1)[1].rstrip("]")
                                     for c in table.columns if " [" in c},
                           "rows": plain.to_dict(orient="records")}, indent=1))
        return 0
    print(human(table, frag, hazard, args))
    return 0


def human(table, frag, hazard, args) -> str:
    """The risk table for people: the hazard, which fragility, then one row per fit."""
    from rocking.fragility.table import KINDS
    from rocking.report.risk import below_first_warning
    from rocking.units import strip_units

    what = hazard.source if hazard.imt in hazard.source else f"{hazard.source} ({hazard.imt})"
    said = [("hazard", what)]
    said += [(name, value) for name, value in (("site", hazard.site), ("kind", hazard.kind),
                                               ("levels in", hazard.unit if hazard.unit != "g"
                                                else "")) if value]
    head = _human.block([*said, ("fragility", f"{args.fragility}: {KINDS[frag.kind]}"),
                         ("in", f"{frag.measure}, {frag.component} component [{frag.unit}]")])
    plain = table.rename(columns={c: strip_units(c) for c in table.columns})
    rows = []
    for r in plain.to_dict(orient="records"):
        rows.append([r["mode"], _human.num(r["tan_alpha"]), _human.num(r["R"]),
                     r["limit_state"], _human.num(r["median_im"]),
                     _human.num(r["median_pga_g"] / r["tan_alpha"]), _human.num(r["beta"], 3),
                     _human.num(r["n"]), _human.num(r["maf"], 4),
                     _human.num(r["lambda_p05"], 3), _human.num(r["lambda_p95"], 3),
                     _human.num(r["return_period"], 4), _human.num(r["p_50yr"], 3),
                     r["status"]])
    lines = [head]
    for note in (hazard.note, frag.note):
        if note:
            lines.append(note)
    warning = below_first_warning(table)
    if warning:
        lines.append(warning)
    if frag.skipped_note():
        lines.append(frag.skipped_note())
    if frag.samples is None:
        lines.append("no bootstrap samples beside the table (<table>_bootstrap.nc): no "
                     "interval on λ")
    else:
        lines.append(f"λ 5 %–95 %: the 90 % interval of λ over {frag.samples.n_resamples} "
                     "resamples of the motions (each refitted and integrated)")
    lines += ["", _human.table(HEADER, rows, left=(0, 3, 13))]
    if args.out is not None:
        lines.append(f"{len(table)} rows (every column) written: {args.out}")
    return "\n".join(lines)
