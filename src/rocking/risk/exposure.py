"""An inventory of columns as OpenQuake's exposure model and pelicun's asset inputs.

From a portfolio table in long form (one row per column and limit state, the columns of
:mod:`rocking.risk.portfolio`'s ``portfolio.csv``: ``id, lon, lat, R, tan_alpha,
limit_state, median [g], beta``; ``taxonomy`` and ``value`` optional),
:func:`write_exposure` writes into one folder::

    exposure.xml            NRML 0.5 exposureModel: the header (cost type, tag names) naming
    exposure.csv            the assets: id, lon, lat, taxonomy, number, structural, R_m,
                            tan_alpha (tags)
    fragility.xml           NRML 0.5 fragilityModel: one continuous lognormal function per
                            taxonomy of exposure.csv, and none other
    pelicun/damage_model.csv  pelicun damage model: one component per taxonomy
    pelicun/assets.csv      per column: id, lon, lat, taxonomy, its pelicun component and
                            the file of its component marginals
    pelicun/marginals/<id>_marginals.csv  one asset's component assignment (pelicun's
                            ``load_cmp_model`` prefix ``marginals/<id>``)

OpenQuake's damage calculators (``scenario_damage``, run on them in the tests;
``classical_damage``, ``event_based_damage``) take ``exposure_file = exposure.xml`` and
``structural_fragility_file = fragility.xml`` as they are: the fragility model's
``lossCategory`` is ``structural``, the exposure's one cost type. Each column is one asset
(``number`` 1; ``structural`` its value, 1 when the table has no ``value``: the damage
distribution is then the probability of each damage state).

Taxonomies
----------
``taxonomy_by="column"``: one taxonomy per column, ``col_<id>`` (or the table's own
``taxonomy`` column), its fragility the column's own. ``taxonomy_by="size_class"``: the
columns binned by R and tan α (edges ``R_edges`` [m], ``tan_alpha_edges`` [-], intervals
``[lo, hi)``), the taxonomy ``R<lo>-<hi>m_tan<lo>-<hi>``; the class fragility is, per limit
state, that of its **most fragile member** (the smallest median, with that member's β): a
class never claims more capacity than any of its columns has. How coarse that is shows in
:attr:`ExposureExport.class_spread` (largest/smallest median within each class and limit
state); a spread near 1 says the class loses little.

Measure
-------
``imt`` is the fragility's intensity measure as OpenQuake names it (``PGA``, ``SA(1.0)``),
in g, in the hazard's horizontal ``component`` (the portfolio's: ``vector_peak``, the peak
over all orientations, RotD100). OpenQuake's ground-motion models give PGA in their own
component (often RotD50 or the geometric mean), so the component is written in both
descriptions, and a user whose hazard is in another component converts it (or gives a
fragility in that component) before the damage calculation. ``minIML`` and
``noDamageLimit`` are the uplift PGA g·tan α of the class's most slender member (the
smallest tan α: lowest uplift) when the measure is the vector-peak PGA; otherwise
``minIML`` is θ·exp(−4β) of the weakest limit state and there is no ``noDamageLimit``.
``maxIML`` is θ·exp(4β) of the most resistant limit state (probabilities never capped below
Φ(4) = 0.99997). Limit states are the tilt chain in increasing severity
(:mod:`rocking.risk.nrml`); sliding goals are left out and named.

pelicun
-------
The damage model CSV has the columns of :mod:`rocking.risk.pelicun` (``Demand-Directional``
1: the vector peak is already the peak over orientations, and pelicun would multiply a
non-directional demand by 1.2). pelicun assesses one asset at a time: for the column ``I``,
``asset.load_cmp_model("pelicun/marginals/I")`` reads its one component (quantity 1 at
location 1, direction 1), the demand sample is ``PGA-1-1`` in g, and
``damage.load_model_parameters(["pelicun/damage_model.csv"], {component})`` its fragility;
damage state i is the i-th limit state exceeded. pelicun's ``PGA`` demand is ground
acceleration only: an ``imt`` other than ``PGA`` writes no pelicun files
(:attr:`ExposureExport.notes` says so).
"""

from __future__ import annotations

import csv
import math
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from rocking._validate import positive_finite
from rocking.fragility.table import lognormal_moments
from rocking.motions.measures import (
    COMPONENTS,
    DEFAULT_COMPONENT,
    VECTOR_PEAK,
    measure_imt,
    parse_component,
    same_measure,
)
from rocking.risk.hazard import lon_lat_problem
from rocking.risk.nrml import MAX_IML_SIGMAS, MODEL_ID, NAMESPACE, nrml_limit_state
from rocking.risk.pelicun import DEMAND_TYPE, columns
from rocking.spectra.limit_states import TILT_AXIS, parse_limit_state, severity, sort_limit_states

REQUIRED = ("id", "lon", "lat", "limit_state", "median", "beta")
"""Columns the table must have (``R`` and ``tan_alpha`` too for size classes)."""

TAXONOMY_BY = ("column", "size_class")

MARGINALS_DIR = "marginals"
"""Folder (in ``pelicun/``) of the per-asset component marginals, ``<id>_marginals.csv``."""

ASSET_ID = re.compile(r"^[\w:-]{1,50}$", re.ASCII)
"""What OpenQuake's exposure reader accepts as an asset id (``valid.asset_id``)."""

TAXONOMY = re.compile(r"^[^\s#'\"]{1,100}$", re.ASCII)
"""An OpenQuake taxonomy: ASCII, no whitespace, no ``#``, quote or apostrophe."""

IMT = re.compile(r"^(PGA|SA\((\d+(\.\d*)?|\.\d+)\))$")

R_EDGES = (0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0)
"""Default size classes in R [m]: octaves."""

TAN_ALPHA_EDGES = (0.0, 0.1, 0.15, 0.2, 0.3, 0.5, 1.0)
"""Default classes of slenderness tan α [-]."""


@dataclass(frozen=True)
class ExposureExport:
    """What :func:`write_exposure` wrote.

    Attributes
    ----------
    paths : dict
        ``exposure_xml``, ``exposure_csv``, ``fragility_xml`` and, for PGA,
        ``pelicun_damage_model``, ``pelicun_assets`` → path.
    taxonomies : list of str
        The taxonomies, each with one fragility function and one pelicun component.
    limit_states : list of str
        The model's limit states (the study's names, increasing severity).
    assets : int
        Columns written (every column of the table).
    left_out : list of str
        Limit states of the table not in the model (sliding: not a damage state of the tilt
        chain).
    class_spread : dict
        ``size_class`` only: taxonomy → largest/smallest median of its members, worst limit
        state [-].
    notes : list of str
        Sentences for the caller's log.
    """

    paths: dict[str, Path]
    taxonomies: list[str]
    limit_states: list[str]
    assets: int
    left_out: list[str] = field(default_factory=list)
    class_spread: dict[str, float] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)


def write_exposure(table: pd.DataFrame | str | Path, folder: str | Path, *,
                   taxonomy_by: str = "column",
                   R_edges: tuple[float, ...] = R_EDGES,
                   tan_alpha_edges: tuple[float, ...] = TAN_ALPHA_EDGES,
                   limit_states: list[str] | None = None,
                   imt: str | None = None, component: str | None = None,
                   model_id: str = "rocking-inventory", currency: str = "EUR",
                   description: str = "") -> ExposureExport:
    """Write an inventory's exposure model, fragility model and pelicun inputs.

    Parameters
    ----------
    table : DataFrame or path
        Long form, one row per column and limit state: ``id, lon [deg], lat [deg],
        limit_state, median [g], beta [-]``, with ``R [m]`` and ``tan_alpha [-]`` (needed
        for size classes, written as tags), optional ``taxonomy`` and ``value``
        (replacement value in ``currency``; 1 when absent). ``portfolio.csv`` as it is.
    folder : path
        Output folder (made if absent; files of the same names are replaced).
    taxonomy_by : {"column", "size_class"}
        One taxonomy per column, or per class of (R, tan α) (module docstring).
    R_edges, tan_alpha_edges : tuple of float
        Class edges [m], [-], increasing; a column outside them is refused.
    limit_states : list of str, optional
        Limit states to export (default: every tilt-chain limit state of the table).
    imt : str, optional
        OpenQuake's name of the measure: ``PGA`` or ``SA(T)``, in g. Default: the table's
        ``measure`` (``pga``, ``sa:1.0``), else ``PGA``; one that contradicts the table's
        ``measure`` is refused.
    component : str, optional
        The horizontal component of the medians (and of the hazard the model is for), a
        name of :data:`rocking.motions.measures.COMPONENTS`; default the table's
        ``component`` column (else ``vector_peak``), which must agree where both are given.
    model_id : str
        Id of the exposure model; the fragility model's is ``<model_id>-fragility``.
    currency : str
        Unit of ``structural``.
    description : str
        Text prepended to both models' descriptions.

    Returns
    -------
    ExposureExport

    Raises
    ------
    ValueError
        Bad input, one line naming the row and the column, before any file is written.
    """
    assets, rows, params, spread, states, left_out, imt, component = _plan(
        table, taxonomy_by, R_edges, tan_alpha_edges, limit_states, imt, component, model_id)
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    paths = {"exposure_xml": folder / "exposure.xml", "exposure_csv": folder / "exposure.csv",
             "fragility_xml": folder / "fragility.xml"}
    what = (f"{description} " if description else "") + (
        f"Free-standing rocking columns (rocking package); fragility in {imt} [g] of the "
        f"{component} horizontal component ({COMPONENTS[component].imt_component}); "
        f"taxonomy per {taxonomy_by.replace('_', ' ')}.")
    _write_exposure_xml(paths["exposure_xml"], paths["exposure_csv"].name, model_id,
                        currency, what)
    _write_exposure_csv(paths["exposure_csv"], assets)
    _write_fragility_xml(paths["fragility_xml"], params, states, imt, component,
                         f"{model_id}-fragility", what, left_out)
    notes = []
    if imt == "PGA":
        pel = folder / "pelicun"
        pel.mkdir(exist_ok=True)
        paths["pelicun_damage_model"] = pel / "damage_model.csv"
        paths["pelicun_assets"] = pel / "assets.csv"
        _write_pelicun(paths["pelicun_damage_model"], paths["pelicun_assets"], params,
                       states, assets)
    else:
        notes.append(f"no pelicun files: pelicun's ground-motion demand is PGA, the "
                     f"fragility is in {imt}")
    if "extrapolated" in rows:
        beyond = rows.loc[rows["extrapolated"].astype(str).str.lower() == "true", "id"].unique()
        if len(beyond):
            notes.append(f"{len(beyond)} column(s) with fragilities extrapolated beyond the "
                         f"surface's grid exported as they are: {', '.join(beyond)}")
    if left_out:
        notes.append(f"{', '.join(left_out)} left out: sliding in contact is not a damage "
                     "state of the tilt-overturning chain")
    return ExposureExport(paths, list(params), states, len(assets), left_out, spread, notes)


# ------------------------------------------------------------------ validation


def check_exposure(table: pd.DataFrame | str | Path, *, taxonomy_by: str = "column",
                   R_edges: tuple[float, ...] = R_EDGES,
                   tan_alpha_edges: tuple[float, ...] = TAN_ALPHA_EDGES,
                   limit_states: list[str] | None = None, imt: str | None = None,
                   component: str | None = None,
                   model_id: str = "rocking-inventory") -> None:
    """Everything :func:`write_exposure` refuses, checked without writing anything (a command
    runs it before it writes ``portfolio.csv``, so a refusal leaves no file behind)."""
    _plan(table, taxonomy_by, R_edges, tan_alpha_edges, limit_states, imt, component,
          model_id)


def _plan(table, taxonomy_by, R_edges, tan_alpha_edges, limit_states, imt, component,
          model_id):
    """The checked assets, rows, fragility parameters of each taxonomy, class spread, limit
    states (and those left out), IMT and component of an export."""
    if taxonomy_by not in TAXONOMY_BY:
        raise ValueError(f"taxonomy_by must be one of {TAXONOMY_BY}, got {taxonomy_by!r}")
    if not MODEL_ID.match(model_id) or len(model_id) > 50:
        raise ValueError(f"model_id must be 1-50 letters, digits, '_' or '-', got {model_id!r}")
    if isinstance(table, str | Path):
        from rocking.risk.portfolio import read_portfolio

        frame = read_portfolio(table)
    else:
        frame = table.copy()
    frame = frame.reset_index(drop=True)
    assets, rows = _validated(frame, taxonomy_by)
    imt = _imt(imt, rows)
    if component is None:
        component = str(rows["component"].iloc[0]) if "component" in rows \
            else DEFAULT_COMPONENT
    component = parse_component(component)  # any case: RotD50
    if "component" in rows and parse_component(str(rows["component"].iloc[0])) != component:
        raise ValueError(f"component {component!r} is not the table's "
                         f"({rows['component'].iloc[0]!r})")
    states, left_out = _limit_states(rows, limit_states)
    rows = rows[rows["limit_state"].isin(states)]
    _check_complete(rows, states)
    if taxonomy_by == "column":
        if "taxonomy" in assets:
            assets["taxonomy"] = assets["taxonomy"].astype(str)
        else:
            assets["taxonomy"] = [f"col_{i}" for i in assets["id"]]
        _check_taxonomies(assets)
        params, spread = _column_params(assets, rows, states), {}
    else:
        assets["taxonomy"] = _size_classes(assets, _edges("R_edges", R_edges),
                                           _edges("tan_alpha_edges", tan_alpha_edges))
        params, spread = _class_params(assets, rows, states)
    return assets, rows, params, spread, states, left_out, imt, component


def _show(value) -> str:
    """A cell as the user wrote it: numbers plainly (``200``, ``nan``), text quoted."""
    if isinstance(value, int | float | np.integer | np.floating):
        return f"{float(value):g}"
    return repr(value)


def _where(frame: pd.DataFrame, i: int) -> str:
    """A row named as its inventory numbers it (the ``row`` column of ``portfolio.csv``),
    else as the table's 1-based data row."""
    who = f" (id {frame.at[i, 'id']!r})" if "id" in frame else ""
    if "row" in frame and pd.notna(frame.at[i, "row"]):
        return f"inventory row {int(float(frame.at[i, 'row']))}{who}"
    return f"row {i + 1} of the table{who}"


def _validated(frame: pd.DataFrame, taxonomy_by: str) -> tuple[pd.DataFrame, pd.DataFrame]:
    """One row per column (the assets) and the fragility rows; refuses bad input."""
    need = list(REQUIRED) + (["R", "tan_alpha"] if taxonomy_by == "size_class" else [])
    missing = [c for c in need if c not in frame]
    if missing:
        raise ValueError(f"the table lacks the column(s) {', '.join(missing)} "
                         f"(needed: {', '.join(need)})")
    if frame.empty:
        raise ValueError("the table has no rows")
    frame["id"] = frame["id"].astype(str)
    for col in ("mode", "fragility", "measure", "component"):
        kinds = sorted(frame[col].dropna().astype(str).unique()) if col in frame else []
        if len(kinds) > 1:
            raise ValueError(f"the table mixes {col}s ({', '.join(kinds)}): export one "
                             f"(e.g. table[table.{col} == {kinds[0]!r}])")
    numeric = ["lon", "lat", "median", "beta"] + [c for c in ("R", "tan_alpha", "value")
                                                    if c in frame]
    for col in numeric:
        values = pd.to_numeric(frame[col], errors="coerce")
        bad = values.isna() | ~np.isfinite(values)
        if bad.any():
            i = int(np.flatnonzero(bad.to_numpy())[0])
            raise ValueError(f"{_where(frame, i)}: {col} is missing or not a finite number "
                             f"({_show(frame.at[i, col])})")
        frame[col] = values.astype(float)
    for i, (lon, lat) in enumerate(zip(frame["lon"], frame["lat"], strict=True)):
        problem = lon_lat_problem(lon, lat)
        if problem:
            raise ValueError(f"{_where(frame, i)}: {problem}")
    for col in [c for c in ("median", "beta", "R", "tan_alpha", "value") if c in frame]:
        bad = frame[col] <= 0  # found in one pass, told by the one check (row and value)
        if bad.any():
            i = int(np.flatnonzero(bad.to_numpy())[0])
            positive_finite(f"{_where(frame, i)}: {col}", float(frame.at[i, col]))
    for i, ident in enumerate(frame["id"]):
        if not ASSET_ID.match(ident):
            raise ValueError(f"{_where(frame, i)}: id {ident!r} is not an OpenQuake asset id "
                             "(1-50 letters, digits, '_', '-' or ':')")
    canonical = {}  # each distinct name parsed once
    for name in frame["limit_state"].astype(str).unique():
        try:
            canonical[name] = parse_limit_state(name).name
        except ValueError as exc:
            i = int(np.flatnonzero((frame["limit_state"].astype(str) == name).to_numpy())[0])
            raise ValueError(f"{_where(frame, i)}: limit_state {name!r}: {exc}") from None
    frame["limit_state"] = frame["limit_state"].astype(str).map(canonical)
    dup = frame.duplicated(["id", "limit_state"])
    if dup.any():
        i = int(np.flatnonzero(dup.to_numpy())[0])
        raise ValueError(f"{_where(frame, i)}: duplicate id: limit state "
                         f"{frame.at[i, 'limit_state']} of this id is already in the table")
    per_column = [c for c in ("lon", "lat", "R", "tan_alpha", "taxonomy", "value", "row")
                  if c in frame]
    for col in per_column:
        differs = frame.groupby("id", sort=False)[col].transform("nunique") > 1
        if differs.any():
            i = int(np.flatnonzero(differs.to_numpy())[0])
            raise ValueError(f"{_where(frame, i)}: duplicate id with another {col} "
                             f"({_show(frame.at[i, col])}): ids must be unique per column")
    assets = frame.drop_duplicates("id")[["id", *per_column]].reset_index(drop=True)
    return assets, frame


def _imt(imt: str | None, rows: pd.DataFrame) -> str:
    measure = str(rows["measure"].iloc[0]) if "measure" in rows else None
    if imt is None:
        imt = measure_imt(measure) if measure else "PGA"
    elif measure and not same_measure(imt, measure):
        raise ValueError(f"imt {imt!r} is not the table's measure {measure!r}")
    if not IMT.match(imt):
        raise ValueError(f"imt must be PGA or SA(T) with T in s, got {imt!r}")
    return imt


def _limit_states(rows: pd.DataFrame, wanted: list[str] | None) -> tuple[list[str], list[str]]:
    have = sort_limit_states(set(rows["limit_state"]))
    if wanted:
        wanted = [parse_limit_state(s).name for s in wanted]
        absent = [s for s in wanted if s not in have]
        if absent:
            raise ValueError(f"limit_states: {', '.join(absent)} not in the table "
                             f"(it has {', '.join(have)})")
        have = sort_limit_states(wanted)
    states = [s for s in have if severity(s)[0] == TILT_AXIS]
    left_out = [s for s in have if severity(s)[0] != TILT_AXIS]
    if not states:
        raise ValueError(f"no limit state on the tilt chain to export (the table has "
                         f"{', '.join(have)})")
    return states, left_out


def _check_complete(rows: pd.DataFrame, states: list[str]) -> None:
    # (id, limit state) pairs are unique by now: a column lacks one iff it has fewer
    counts = rows.groupby("id", sort=False)["limit_state"].nunique()
    short = counts[counts < len(states)]
    if len(short):
        ident = short.index[0]
        have = set(rows.loc[rows["id"] == ident, "limit_state"])
        lacking = [s for s in states if s not in have]
        raise ValueError(f"id {ident!r}: no row for limit state(s) {', '.join(lacking)}; "
                         "every column needs every exported limit state (choose them with "
                         "limit_states=[...])")


def _check_taxonomies(assets: pd.DataFrame) -> None:
    for i, tax in enumerate(assets["taxonomy"]):
        if not TAXONOMY.match(tax):
            raise ValueError(f"id {assets.at[i, 'id']!r}: taxonomy {tax!r} is not an "
                             "OpenQuake taxonomy (ASCII, no whitespace, '#' or quotes)")
    per_tax = assets.groupby("taxonomy")["id"].nunique()
    shared = per_tax[per_tax > 1]
    if len(shared):
        raise ValueError(f"taxonomy {shared.index[0]!r} is given to {shared.iloc[0]} columns: "
                         "with taxonomy_by='column' each column has its own (use "
                         "taxonomy_by='size_class' to share)")


def _edges(name: str, edges) -> np.ndarray:
    e = np.asarray(edges, dtype=float)
    if e.ndim != 1 or len(e) < 2 or not np.all(np.isfinite(e)) or np.any(np.diff(e) <= 0):
        raise ValueError(f"{name} must be at least two finite increasing numbers, "
                         f"got {edges!r}")
    return e


# ------------------------------------------------------------------ taxonomies


def _size_classes(assets: pd.DataFrame, r_edges: np.ndarray,
                  t_edges: np.ndarray) -> list[str]:
    labels = []
    for col, edges, unit in (("R", r_edges, "m"), ("tan_alpha", t_edges, "")):
        values = assets[col].to_numpy()
        k = np.searchsorted(edges, values, side="right") - 1
        out = (k < 0) | (k >= len(edges) - 1)
        if out.any():
            a = assets.iloc[int(np.flatnonzero(out)[0])]
            raise ValueError(f"{_where(assets, int(np.flatnonzero(out)[0]))}: {col} = "
                             f"{a[col]:g} outside the class edges [{edges[0]:g}, "
                             f"{edges[-1]:g}){unit}")
        names = np.array([f"{lo:g}-{hi:g}{unit}" for lo, hi in zip(edges[:-1], edges[1:],
                                                                   strict=True)])
        labels.append(names[k])
    return [f"R{r}_tan{t}" for r, t in zip(*labels, strict=True)]


def _wide(rows: pd.DataFrame, key: str, states: list[str]) -> tuple[pd.DataFrame, ...]:
    """Median and β tables: one row per ``key``, one column per limit state."""
    return tuple(rows.pivot(index=key, columns="limit_state", values=v)[states]
                 for v in ("median", "beta"))


def _params(median: pd.DataFrame, beta: pd.DataFrame, uplift: pd.Series,
            states: list[str]) -> dict[str, dict]:
    m, b = median.to_numpy(), beta.to_numpy()
    return {tax: {"ls": {s: (float(m[i, j]), float(b[i, j])) for j, s in enumerate(states)},
                  "tan_alpha": None if uplift is None else float(uplift[tax])}
            for i, tax in enumerate(median.index)}


def _column_params(assets: pd.DataFrame, rows: pd.DataFrame,
                   states: list[str]) -> dict[str, dict]:
    # the table's own taxonomy column (if any) is the assets' now: merged once, not twice
    rows = rows.drop(columns="taxonomy", errors="ignore").merge(assets[["id", "taxonomy"]],
                                                                on="id")
    median, beta = _wide(rows, "taxonomy", states)
    order = list(dict.fromkeys(assets["taxonomy"]))  # the table's order of the columns
    uplift = (assets.set_index("taxonomy")["tan_alpha"] if "tan_alpha" in assets else None)
    return _params(median.loc[order], beta.loc[order], uplift, states)


def _class_params(assets: pd.DataFrame, rows: pd.DataFrame,
                  states: list[str]) -> tuple[dict[str, dict], dict[str, float]]:
    rows = rows.drop(columns="taxonomy", errors="ignore").merge(assets[["id", "taxonomy"]],
                                                                on="id")
    # per class and limit state the most fragile member (smallest median), with its own β
    weakest = rows.loc[rows.groupby(["taxonomy", "limit_state"])["median"].idxmin()]
    median, beta = _wide(weakest, "taxonomy", states)
    spread = rows.groupby(["taxonomy", "limit_state"])["median"].agg(lambda m: m.max() / m.min())
    uplift = assets.groupby("taxonomy")["tan_alpha"].min()  # the most slender member rocks first
    return (_params(median, beta, uplift, states),
            {t: float(v) for t, v in spread.groupby(level="taxonomy").max().items()})


# ------------------------------------------------------------------ writers


def _q(tag: str) -> str:
    return f"{{{NAMESPACE}}}{tag}"


def _num(x: float) -> str:
    return repr(float(x))


def _write_xml(root: ET.Element, path: Path) -> None:
    ET.indent(root, space="  ")
    ET.ElementTree(root).write(path, encoding="utf-8", xml_declaration=True)


def _write_exposure_xml(path: Path, csv_name: str, model_id: str, currency: str,
                        text: str) -> None:
    ET.register_namespace("", NAMESPACE)
    root = ET.Element(_q("nrml"))
    model = ET.SubElement(root, _q("exposureModel"), id=model_id, category="buildings",
                          taxonomySource="rocking: one taxonomy per column or size class")
    ET.SubElement(model, _q("description")).text = (
        f"{text} Each asset is one column (number 1); structural is its value.")
    conv = ET.SubElement(model, _q("conversions"))
    costs = ET.SubElement(conv, _q("costTypes"))
    ET.SubElement(costs, _q("costType"), name="structural", type="aggregated", unit=currency)
    ET.SubElement(model, _q("tagNames")).text = "R_m tan_alpha"
    ET.SubElement(model, _q("assets")).text = csv_name
    _write_xml(root, path)


def _write_exposure_csv(path: Path, assets: pd.DataFrame) -> None:
    out = pd.DataFrame({
        "id": assets["id"], "lon": assets["lon"], "lat": assets["lat"],
        "taxonomy": assets["taxonomy"], "number": 1.0,
        "structural": assets["value"] if "value" in assets else 1.0,
        # tags are strings to OpenQuake; '' would read as a missing tag
        "R_m": [f"{r:g}" for r in assets["R"]] if "R" in assets else "na",
        "tan_alpha": [f"{t:g}" for t in assets["tan_alpha"]] if "tan_alpha" in assets
        else "na"})
    out.to_csv(path, index=False, float_format="%.10g")


def _imls(params: dict, imt: str, component: str) -> dict[str, str]:
    medians = [(m, b) for m, b in params["ls"].values()]
    top = max(m * math.exp(MAX_IML_SIGMAS * b) for m, b in medians)
    uplift = params["tan_alpha"]
    if imt == "PGA" and component == VECTOR_PEAK and uplift is not None:
        # below the uplift PGA g·tan α a rigid body on rigid ground does not rock
        return {"imt": imt, "minIML": _num(uplift), "maxIML": _num(max(top, uplift)),
                "noDamageLimit": _num(uplift)}
    low = min(m * math.exp(-MAX_IML_SIGMAS * b) for m, b in medians)
    return {"imt": imt, "minIML": _num(low), "maxIML": _num(top)}


def _write_fragility_xml(path: Path, params: dict[str, dict], states: list[str], imt: str,
                         component: str, model_id: str, text: str,
                         left_out: list[str]) -> None:
    ET.register_namespace("", NAMESPACE)
    root = ET.Element(_q("nrml"))
    model = ET.SubElement(root, _q("fragilityModel"), id=model_id, assetCategory="buildings",
                          lossCategory="structural")
    mapping = ", ".join(f"{nrml_limit_state(s)} = {s}" for s in states)
    ET.SubElement(model, _q("description")).text = (
        f"{text} Lognormal capacity, mean/stddev arithmetic. Limit states: {mapping}."
        + (f" Left out: {', '.join(left_out)} (not on the tilt chain)." if left_out else ""))
    ET.SubElement(model, _q("limitStates")).text = " ".join(nrml_limit_state(s)
                                                            for s in states)
    for tax, p in params.items():
        func = ET.SubElement(model, _q("fragilityFunction"), id=tax, format="continuous",
                             shape="logncdf")
        ET.SubElement(func, _q("imls"), _imls(p, imt, component))
        for s in states:
            mean, std = lognormal_moments(*p["ls"][s])
            ET.SubElement(func, _q("params"), ls=nrml_limit_state(s), mean=_num(mean),
                          stddev=_num(std))
    _write_xml(root, path)


def component_of(taxonomy: str) -> str:
    """pelicun component id of a taxonomy: ``rocking.<taxonomy>`` with ``-`` as ``_``
    (pelicun joins component, location and direction with ``-``)."""
    return "rocking." + taxonomy.replace("-", "_")


def _write_pelicun(model_path: Path, assets_path: Path, params: dict[str, dict],
                   states: list[str], assets: pd.DataFrame) -> None:
    with model_path.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=columns(len(states)), restval="")
        w.writeheader()
        for tax, p in params.items():
            row = {"ID": component_of(tax), "Incomplete": 0, "Demand-Type": DEMAND_TYPE,
                   "Demand-Unit": "g", "Demand-Offset": 0, "Demand-Directional": 1}
            for i, s in enumerate(states, start=1):
                median, beta = p["ls"][s]
                row[f"LS{i}-Family"] = "lognormal"
                row[f"LS{i}-Theta_0"] = repr(median)
                row[f"LS{i}-Theta_1"] = repr(beta)
            w.writerow(row)
    marginals_dir = assets_path.parent / MARGINALS_DIR
    marginals_dir.mkdir(exist_ok=True)
    files = []
    for ident, tax in zip(assets["id"], assets["taxonomy"], strict=True):
        # pelicun's component marginals of one asset: one component, quantity 1, at the
        # ground (location 1, direction 1, where the demand PGA-1-1 is given)
        name = f"{MARGINALS_DIR}/{ident}_marginals.csv"
        with open(assets_path.parent / name, "w") as fh:
            fh.write(f"ID,Units,Location,Direction,Theta_0,Blocks\n{component_of(tax)},ea,1,1,1,1\n")
        files.append(name)
    pd.DataFrame({"id": assets["id"], "lon": assets["lon"], "lat": assets["lat"],
                  "taxonomy": assets["taxonomy"],
                  "component": [component_of(t) for t in assets["taxonomy"]],
                  "marginals": files}).to_csv(assets_path, index=False, float_format="%.10g")

__all__ = ["ExposureExport", "R_EDGES", "REQUIRED", "TAN_ALPHA_EDGES", "TAXONOMY_BY",
           "check_exposure", "component_of", "write_exposure"]
