"""``rocking portfolio``: every column of an inventory under its site's hazard → portfolio.csv."""

from __future__ import annotations

from pathlib import Path

from rocking.cli import _common, _human
from rocking.cli.stripes import COMPONENT_NAMES

EXAMPLES = """  rocking portfolio --surface results/paper/elcentro \\
      --inventory config/inventory/example_columns.csv \\
      --hazard config/hazard/example_hazard_curve.csv --out results/portfolio
  rocking portfolio --surface results/elcentro --inventory park.csv \\
      --hazard hazard_curve-mean-PGA.csv --max-distance-km 2 --skip-invalid --out park"""

HEADER = ("rank", "id", "R [m]", "tan α [-]", "limit state", "median [g]", "β [-]",
          "λ [1/yr]", "λ 5 % [1/yr]", "λ 95 % [1/yr]", "return period [yr]", "P(50 yr) [-]",
          "site", "distance [km]")
"""Columns printed on the terminal (portfolio.csv has every column)."""

SHOWN = 20
"""Rows printed per limit state (the highest λ first); portfolio.csv has them all."""

SURFACE_TABLES = ("fragility.csv", "critical.csv", "records.csv", "motion_measures.csv")
"""The tables of a study's folder the surface is read from (rocking.fragility.surface)."""

PROGRESS_FROM = 2000
"""Inventories of at least this many columns report their progress on stderr."""


def add_parser(subparsers) -> None:
    """Register the ``portfolio`` subcommand."""
    p = _common.add_command(
        subparsers, "portfolio", examples=EXAMPLES,
        help="every column of an inventory: fragility from a study's surface, lambda, rank",
        description="From a study whose runs cover a grid of R and tan alpha (its "
        "fragility.csv and critical.csv), interpolate each limit state's lognormal fragility "
        "at every column of an inventory CSV (id, height and diameter or R and tan_alpha, "
        "optional mu, lon, lat or site), integrate it against the hazard of the column's "
        "site, and write portfolio.csv: median and beta with their 90 %% bootstrap interval "
        "and interpolation error, lambda with its 90 %% interval, return period, probability "
        "in 50 years, hazard site and distance, rank (docs/risk.md).",
    )
    p.add_argument("--surface", type=Path, required=True,
                   help="the study's results folder (fragility.csv and critical.csv), e.g. "
                   "results/paper/elcentro")
    p.add_argument("--inventory", type=Path, required=True,
                   help="CSV of columns: id, height, diameter (or R, tan_alpha) [m], "
                   "optional mu, lon, lat [deg] or site")
    p.add_argument("--hazard", required=True,
                   help="OpenQuake hazard-curve CSV of one or many sites (PGA), a two-column "
                   "table, or a power law 'k0,k'")
    site = p.add_argument_group("one site of a hazard file for every column (default: each "
                                "column's own: its site id, else the nearest to its lon/lat)")
    site.add_argument("--site-id", default=None, help="the site whose custom_site_id is this")
    site.add_argument("--site-lon", type=float, default=None,
                      help="the site nearest this longitude [deg] (with --site-lat)")
    site.add_argument("--site-lat", type=float, default=None,
                      help="the site nearest this latitude [deg] (with --site-lon)")
    p.add_argument("--max-distance-km", type=float, default=5.0,
                   help="farthest a hazard site may be from a column's lon/lat "
                   "(great-circle) [km]")
    p.add_argument("--kind", default=None,
                   help="the hazard curve's statistic when it is not the mean (quantile-<q>, "
                   "rlz-<n>)")
    p.add_argument("--hazard-unit", default=None,
                   help="unit of the hazard's levels when the file does not say: g, m/s2, "
                   "cm/s2 or gal (default g, OpenQuake's unit of PGA and SA)")
    p.add_argument("--component", default=None, choices=COMPONENT_NAMES, type=str.lower,
                   help="the hazard's horizontal component, any case (RotD50 for NGA-West2 "
                   "models; default: its file's component= comment; an OpenQuake file "
                   "without one is taken as rotd50, said): the study's fragility surface is "
                   "refitted in it from the study's motions")
    p.add_argument("--mode", default="3d", help="the study's analysis mode")
    p.add_argument("--limit-states", default=None,
                   help="only these, comma-separated (default: every one with a surface)")
    p.add_argument("--resamples", type=int, default=1000,
                   help="bootstrap resamples of the motions behind the intervals (0: none)")
    p.add_argument("--extrapolate", action="store_true",
                   help="answer columns beyond the study's grid too, marked extrapolated "
                   "(default: refused)")
    p.add_argument("--skip-invalid", action="store_true",
                   help="leave bad rows out, each listed (portfolio_skipped.csv), instead of "
                   "refusing the inventory")
    p.add_argument("--figures", action="store_true",
                   help="also draw portfolio_map.png and portfolio_ranked.png into --out")
    p.add_argument("--export", choices=("column", "size_class"), default=None,
                   help="also write the inventory as OpenQuake's exposure model with its "
                   "fragility model and pelicun's asset inputs into --out/exposure, one "
                   "taxonomy per column or per size class of (R, tan α)")
    p.add_argument("-o", "--out", type=Path, default=None,
                   help="folder for portfolio.csv (default: print the table)")
    _human.add_json(p, "the table")
    p.set_defaults(func=run)


def _forced_site(args):
    if (args.site_lon is None) != (args.site_lat is None):
        raise ValueError("--site-lon and --site-lat go together")
    if args.site_id is not None and args.site_lon is not None:
        raise ValueError("give --site-id or --site-lon/--site-lat, not both")
    if args.site_id is not None:
        return {"id": args.site_id}
    if args.site_lon is not None:
        return {"lon": args.site_lon, "lat": args.site_lat,
                "max_distance_km": args.max_distance_km}
    return None


def run(args) -> int:
    """Check everything, then compute, print or write portfolio.csv; returns 0."""
    import sys

    from rocking._validate import positive_finite
    from rocking.risk.portfolio import site_portfolio, write_portfolio

    positive_finite("--max-distance-km", args.max_distance_km)
    if args.resamples < 0:
        raise ValueError(f"--resamples must be >= 0, got {args.resamples}")
    if args.out is not None:
        _common.writable_folder(args.out)
    elif args.figures or args.export:
        raise ValueError("--figures and --export need --out (the folder they go to)")
    if not Path(args.hazard).exists() and "," not in args.hazard:
        raise ValueError(f"--hazard: no such file: {args.hazard!r}")
    folder = args.surface.parent if args.surface.suffix == ".csv" else args.surface
    _common.check_handed([folder / n for n in SURFACE_TABLES], "portfolio")
    states = None if args.limit_states is None else \
        [s.strip() for s in args.limit_states.split(",") if s.strip()]
    result = site_portfolio(args.surface, args.inventory, args.hazard, site=_forced_site(args),
                            kind=args.kind, unit=args.hazard_unit, component=args.component,
                            mode=args.mode, limit_states=states, resamples=args.resamples,
                            extrapolate=args.extrapolate, skip_invalid=args.skip_invalid,
                            max_distance_km=args.max_distance_km,
                            progress_from=PROGRESS_FROM)
    table, inventory = result.table, result.inventory
    for note in [*inventory.notes, *result.notes]:
        print(f"rocking portfolio: {note}", file=sys.stderr)
    if args.export:  # every refusal of the export before any file is written
        from rocking.risk.exposure import check_exposure

        check_exposure(table, taxonomy_by=args.export)
    if args.out is not None:
        path = write_portfolio(table, args.out, inventory.skipped)
        if args.figures:
            from rocking.plot import render
            from rocking.plot.registry import figures

            for name in (n for n, f in figures().items() if f.section == "portfolio"):
                render(name, [args.out / f"{name}.png"], args.out / f"{name}.json",
                       portfolio=table, hazard=str(args.hazard), study=str(args.surface))
        if args.export:
            from rocking.risk.exposure import write_exposure

            export = write_exposure(table, args.out / "exposure", taxonomy_by=args.export)
            print(f"OpenQuake exposure and fragility models, pelicun inputs "
                  f"({len(export.taxonomies)} taxonomies): {args.out / 'exposure'}",
                  file=sys.stderr)
    if args.json:
        from rocking import _json

        print(_json.dumps({"surface": str(args.surface), "hazard": str(args.hazard),
                           "skipped": inventory.skipped_note(), "notes": result.notes,
                           "site": result.site.to_dict(orient="records"),
                           "rows": table.to_dict(orient="records")}, indent=1))
        return 0
    print(human(table, inventory, args, result.site))
    if args.out is not None:
        n_states = table["limit_state"].nunique()
        print(f"{len(table)} rows ({len(inventory.columns)} columns × {n_states} limit "
              f"states, every column) written: {path}")
    return 0


def human(table, inventory, args, site=None) -> str:
    """The site's answer, then the highest-λ columns of each limit state, for people."""
    from rocking.risk.portfolio import error_words, site_lines

    first = table.iloc[0]
    head = _human.block([("surface", str(args.surface)), ("inventory", str(args.inventory)),
                         ("hazard", str(args.hazard)),
                         ("in", f"{first['measure']}, {first['component']} component [g]"),
                         ("columns", f"{len(inventory.columns)} valid, "
                                     f"{len(inventory.skipped)} skipped")])
    lines = [head]
    if site is not None and len(site):
        lines += ["", "the site:", *(f"  {line}" for line in site_lines(site))]
    extrapolated = int(table.drop_duplicates("id")["extrapolated"].sum())
    if extrapolated:
        lines.append(f"WARNING: {extrapolated} column(s) beyond the study's grid, extrapolated "
                     "(the extrapolated column of portfolio.csv)")
    for ls, part in table.groupby("limit_state", sort=False):
        rows = [[_human.num(r["rank"]), r["id"], _human.num(r["R"], 4),
                 _human.num(r["tan_alpha"], 4), ls, _human.num(r["median"], 4),
                 _human.num(r["beta"], 3), _human.num(r["lambda"], 4),
                 _human.num(r["lambda_p05"], 3), _human.num(r["lambda_p95"], 3),
                 _human.num(r["return_period"], 4), _human.num(r["p_50yr"], 3),
                 r["hazard_site"], _human.num(r["hazard_distance_km"], 3)]
                for r in part.head(SHOWN).to_dict(orient="records")]
        more = f" (the {SHOWN} highest of {len(part)})" if len(part) > SHOWN else ""
        lines += ["", f"{ls}{more}: interpolation error of the median "
                  + error_words(float(part["interp_error"].iloc[0])),
                  _human.table(HEADER, rows, left=(1, 4, 12))]
    return "\n".join(lines)
