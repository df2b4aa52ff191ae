"""One fragility table type, read and written in one place.

Every fragility table of a study (``fragility.csv``: the lognormal of each motion's critical
intensity, from the spectra; ``suite_fragility.csv``: the same per group of motions in each
intensity measure; ``stripe_fragility.csv``: the multiple-stripe fit; a refit in another
measure or component, :mod:`rocking.fragility.refit`) is read by :func:`read_fragilities`
into :class:`Fragilities`, which carries what the numbers are in: its ``measure``,
``component`` and ``unit``, its estimator (``kind``), the per-motion quantity it was fitted
to (``quantity``: name, p, w of issue 45's critical intensity), and per row the mode, limit
state and body (tan α, R). Tables are written with those columns in front
(:data:`META`, :func:`write_fragilities`); a table written before them is read as what it
was (PGA in the vector peak, the classic first exceedance).

Per (mode, tan α, R, limit state) the reader keeps the median capacity in the measure's unit
(g for PGA and Sa) and β.
Rows without a fit (median or β NaN: too few motions reached the limit state, or no spread)
are set aside in :attr:`Fragilities.skipped` with their status, never silently dropped; cells
the study never asked for (status ``not-computed``) are not part of it and are only counted.
Limit states are ordered by increasing severity: increasing tilt goal, overturning last.

Two fragilities of a study are read the same way, and :attr:`Fragilities.kind` says which:
``critical_intensity`` (``fragility.csv``: a lognormal fitted to each motion's critical
intensity, the study's quantity, I10 by default: the IDA-type fit) and ``stripes``
(``stripe_fragility.csv`` of :func:`rocking.execution.stripes.stripe_table`: a lognormal
fitted by binomial maximum likelihood to the share of motions exceeding at fixed
intensities). The exports and the risk table carry
the kind in their ids and a column (:data:`KINDS`). A table written by an earlier version
names the critical-intensity fragility by its old name: it is read under today's
(:data:`RENAMED`, :func:`renamed`), and no table is written with the old one.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import pandas as pd

from rocking.fragility.bootstrap import BootstrapSamples
from rocking.motions.measures import DEFAULT_COMPONENT
from rocking.spectra.limit_states import TILT_AXIS, parse_limit_state, severity, sort_limit_states
from rocking.units import strip_units

log = logging.getLogger(__name__)

KEYS = ("mode", "tan_alpha", "R", "limit_state")
"""Columns that identify a fragility."""

META = ("estimator", "measure", "component", "unit", "quantity", "p", "w")
"""Columns every fragility table starts with: what its numbers are in (the estimator, the
intensity measure, its horizontal component and unit) and the per-motion quantity fitted
(``quantity`` name, ``p``, ``w``: :func:`quantity_of`)."""

LEGACY_QUANTITY = {"quantity": "first_exceedance", "p": math.nan, "w": math.nan}
"""The quantity of a table or store that states none (made before issue 45's quantity): the
first exceedance on the scan grid."""

COLUMNS = (*KEYS, "median_g", "beta", "n", "bracket_lo", "bracket_hi", "row", "status")
"""Columns of :attr:`Fragilities.rows` and :attr:`Fragilities.skipped` (``n`` motions fitted,
``row`` the row of the table read, −1 for a frame without one)."""

SUITE_GROUPS = ("records", "synthetic")
"""Motion groups of ``suite_fragility.csv``, in the order the risk table prefers them."""

NOT_COMPUTED = "not-computed"

CRITICAL_INTENSITY = "critical_intensity"
STRIPES = "stripes"
KINDS = {
    CRITICAL_INTENSITY: "critical-intensity fragility: lognormal fitted to each motion's "
                        "critical intensity (the study's quantity, the table's quantity "
                        "column: I10 by default; motions not reached censored at the search "
                        "bound)",
    STRIPES: "multiple-stripe fragility: lognormal fitted by binomial maximum likelihood to "
             "the share of motions exceeding the limit state at each stripe (jittered "
             "within +-w in ln s: the motions' mean local exceedance probability F(s))",
}
"""Which fragility a table holds → one line saying what it is (descriptions of the exports)."""

RENAMED = {"first_exceedance": CRITICAL_INTENSITY}
"""Estimator names written by earlier versions → today's (:data:`KINDS`): the values of a
table's ``estimator`` or ``fragility`` column are read under today's name (:func:`renamed`);
no table is written with an old one. (The critical-intensity fit was once named after the
quantity it was fitted to then, the first exceedance on the scan grid.)"""

RENAMED_COLUMNS = {"first_median": "critical_median", "first_beta": "critical_beta",
                   "first_status": "critical_status"}
"""Columns of a stripe table written by earlier versions → today's: the critical-intensity
fit set beside the stripe fit (:func:`rocking.fragility.stripe_table.stripe_table`)."""


def _kind_name(name) -> str:
    """Today's name of an estimator read from a table or given by a caller
    (:data:`RENAMED`); any other name as it is."""
    return RENAMED.get(str(name), str(name))


def renamed(frame: pd.DataFrame) -> pd.DataFrame:
    """A table as read (a fragility, stripe, risk or portfolio table, a pelicun export; column
    titles with or without units) in today's names: its ``estimator`` and ``fragility``
    values and the estimator that ends a pelicun component ``ID`` (:data:`RENAMED`), and its
    columns (:data:`RENAMED_COLUMNS`). A copy where anything changes; the frame itself where
    nothing does."""
    def kind_of_id(v):
        head, dot, tail = v.rpartition(".") if isinstance(v, str) else ("", "", v)
        return f"{head}.{_kind_name(tail)}" if dot and tail in RENAMED else v

    columns = {c: RENAMED_COLUMNS[strip_units(str(c))] + str(c)[len(strip_units(str(c))):]
               for c in frame.columns if strip_units(str(c)) in RENAMED_COLUMNS}
    values = {c: (lambda v: _kind_name(v) if isinstance(v, str) else v)
              for c in frame.columns if strip_units(str(c)) in ("estimator", "fragility")}
    if "ID" in frame.columns:
        values["ID"] = kind_of_id
    new = {c: frame[c].map(f) for c, f in values.items()}
    new = {c: v for c, v in new.items() if not v.equals(frame[c])}
    if not columns and not new:
        return frame
    return frame.assign(**new).rename(columns=columns)


def fragility_kind(frame: pd.DataFrame) -> str:
    """:data:`STRIPES` for a stripe table (it has a ``stripes`` column, the number of stripe
    intensities), else :data:`CRITICAL_INTENSITY`."""
    return STRIPES if "stripes" in _plain_columns(frame).columns else CRITICAL_INTENSITY


@dataclass(frozen=True)
class Fragilities:
    """Lognormal fragilities with a fit, and those without.

    Attributes
    ----------
    rows : pandas.DataFrame
        :data:`COLUMNS`; ``median_g`` the median capacity in the measure [g], ``beta`` [-];
        sorted by mode, tan α, R and increasing severity of the limit state.
    skipped : pandas.DataFrame
        Requested (mode, tan α, R, limit state) without a fit, with the reason (``status``)
        and, for stripes, the bracketing stripes' intensities (``bracket_lo``,
        ``bracket_hi`` [g], NaN where the table does not give them).
    n_not_computed : int
        Cells of the table the study did not ask for.
    kind : str
        Which fragility: ``"critical_intensity"`` or ``"stripes"`` (:data:`KINDS`).
    measure : str
        The intensity measure of the medians (``"pga"``, ``"sa:1.0"``).
    samples : BootstrapSamples, optional
        The table's bootstrap resamples (``<table>_bootstrap.nc``), rows addressed by the
        ``row`` column (the row of the table read).
    source : str
        The table read (a path), for notes.
    component : str
        Horizontal component of the measure (:data:`rocking.motions.measures.COMPONENTS`):
        the table's ``component`` column, ``vector_peak`` for a table without one (the
        spectra's fragility.csv, and tables written before components).
    quantity : dict
        The per-motion quantity behind a critical-intensity fit (``quantity``, ``p``, ``w``,
        :func:`quantity_of`); for stripes ``w`` is the half-width of the intensities'
        jitter in ln s (0: none).
    note : str
        How the fragility was brought into these terms, when it was (a refit), for the
        outputs to say.
    refitted : bool
        Refitted from the study's per-motion answers in another measure or component than
        its table's (:func:`rocking.fragility.refit.refit_study`).
    """

    rows: pd.DataFrame
    skipped: pd.DataFrame
    n_not_computed: int = 0
    kind: str = CRITICAL_INTENSITY
    measure: str = "pga"
    samples: BootstrapSamples | None = None
    source: str = ""
    component: str = DEFAULT_COMPONENT
    quantity: dict = field(default_factory=lambda: dict(LEGACY_QUANTITY))
    note: str = ""
    refitted: bool = False

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"kind must be one of {sorted(KINDS)}, got {self.kind!r}")

    @property
    def unit(self) -> str:
        """Unit of the medians: the measure's (g for PGA and Sa)."""
        from rocking.motions.measures import Measure

        return Measure.of(self.measure).unit

    @property
    def terms(self) -> str:
        """``"pga vector_peak [g]"``: what the medians are, in words for the outputs."""
        return f"{self.measure} {self.component} [{self.unit}]"

    def resamples(self, row: int) -> tuple[np.ndarray, np.ndarray] | None:
        """θ [g] and β [-] of the bootstrap resamples of the table's row ``row`` (the
        ``row`` column of :attr:`rows`), None without a bootstrap file."""
        if self.samples is None or row < 0:
            return None
        return self.samples.median[row], self.samples.beta[row]

    def limit_states(self) -> list[str]:
        """Limit states with at least one fit, in increasing severity."""
        return sort_limit_states(self.rows["limit_state"].unique())

    def groups(self):
        """``((mode, tan_alpha, R), rows)`` per body and mode, rows in increasing severity."""
        return self.rows.groupby(["mode", "tan_alpha", "R"], sort=False)

    def damage_chain(self) -> tuple[Fragilities, list[str]]:
        """The fragilities of the tilt axis (tilt goals, overturning last: nested damage
        states, each implied by the next), and the names of those left out: sliding goals
        are another axis (a column may slide without tilting and overturn without sliding),
        so no export puts them into the chain, where a reader would take the last as the
        most severe damage state."""
        def on_chain(frame: pd.DataFrame) -> pd.Series:
            return frame["limit_state"].map(lambda s: severity(s)[0] == TILT_AXIS).astype(bool)

        keep_rows, keep_skipped = on_chain(self.rows), on_chain(self.skipped)
        off = sort_limit_states(set(self.rows.loc[~keep_rows, "limit_state"])
                                | set(self.skipped.loc[~keep_skipped, "limit_state"]))
        if not off:
            return self, []
        return replace(self, rows=self.rows[keep_rows], skipped=self.skipped[keep_skipped]), off

    def skipped_note(self) -> str:
        """One line naming what has no fit (empty if nothing)."""
        if self.skipped.empty:
            return ""
        items = [f"{r.mode} tan α={r.tan_alpha:g} R={r.R:g} m {r.limit_state} ({r.status})"
                 for r in self.skipped.itertuples()]
        where = f" of {self.source}" if self.source else ""
        return (f"{len(items)} row(s){where} without a fit (NaN median), no λ integrated: "
                + "; ".join(items))


def _plain_columns(frame: pd.DataFrame) -> pd.DataFrame:
    # "tan_alpha [-]" → "tan_alpha", "median_pga_g [g]" → "median_pga_g"
    return frame.rename(columns={c: strip_units(str(c)) for c in frame.columns})


def _as_frame(source) -> pd.DataFrame:
    if isinstance(source, pd.DataFrame):
        return source
    if isinstance(source, str | Path):
        path = Path(source)
        if path.suffix == ".csv":
            return pd.read_csv(path)
        if path.suffix == ".nc":
            import xarray as xr

            with xr.open_dataset(path) as ds:
                return ds.load().to_dataframe().reset_index()
        raise ValueError(f"fragility table must be a .csv or .nc file, got {str(path)!r}")
    if hasattr(source, "to_dataframe"):  # the xarray Dataset of fragility_table
        return source.to_dataframe().reset_index()
    raise ValueError(f"fragility table must be a path, DataFrame or Dataset, got "
                     f"{type(source).__name__}")


def read_fragilities(source, kind: str | None = None, *, measure: str | None = None,
                     bootstrap=None, component: str | None = None) -> Fragilities:
    """The fitted lognormal fragilities of a study's fragility table, and those without.

    Parameters
    ----------
    source : path, pandas.DataFrame or xarray.Dataset
        ``results/<study>/fragility.csv`` or ``.nc`` (critical intensities in PGA),
        ``suite_fragility.csv`` (critical intensities in each intensity measure of the study),
        ``stripe_fragility.csv``, a refit (:func:`rocking.fragility.refit.fit_cells`), or
        the table itself; column titles with or without units.
    kind : {"critical_intensity", "stripes"}, optional
        Which fragility the table holds; default: its ``estimator`` column, else told by its
        columns (:func:`fragility_kind`). An earlier version's name is read as today's
        (:data:`RENAMED`).
    measure : str, optional
        The intensity measure wanted (any spelling, ``"pga"``, ``"SA(1.0)"``); default: the
        table's first. A table of several measures gives its rows of that one (a suite table
        its ``records`` rows, its ``synthetic`` ones where it has no fitted record rows);
        one without it is refused, naming the measures it has.
    bootstrap : path or False, optional
        The table's bootstrap samples (:mod:`rocking.fragility.bootstrap`); default
        ``<table>_bootstrap.nc`` beside a table given by path, when it exists; False: none.
    component : str, optional
        The horizontal component wanted: a table with a ``component`` column gives its rows
        in it (refused, naming the table's components, where it has none); a table without
        one is the vector peak. Default: the table's first component.

    Returns
    -------
    Fragilities
    """
    from rocking.motions.measures import Measure, parse_component

    frame = renamed(_plain_columns(_as_frame(source))).reset_index(drop=True)
    n_total = len(frame)
    frame["row"] = np.arange(n_total)
    where = str(source) if isinstance(source, str | Path) else "fragility table"
    if kind is None:
        kind = (str(frame["estimator"].iloc[0]) if "estimator" in frame.columns and len(frame)
                else fragility_kind(frame))
    kind = _kind_name(kind)
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {sorted(KINDS)}, got {kind!r}")
    have = (list(dict.fromkeys(frame["component"].astype(str))) if "component" in frame.columns
            else [DEFAULT_COMPONENT])
    component = have[0] if component is None and have else parse_component(
        component or DEFAULT_COMPONENT)
    if component not in have:
        raise ValueError(f"{where} has no fit in the component {component} (its components: "
                         f"{', '.join(have)})")
    if "component" in frame.columns:
        frame = frame[frame["component"].astype(str) == component]
    frame, median_col, measure = _in_measure(frame, measure, where)
    need = {"mode", "limit_state", "tan_alpha", "R", median_col, "beta"}
    missing = sorted(need - set(frame.columns))
    if missing:
        raise ValueError(f"{where} lacks the columns {missing} (has "
                         f"{sorted(map(str, frame.columns))})")
    status = (frame["status"].astype(str) if "status" in frame.columns
              else pd.Series("", index=frame.index))
    n_col = next((c for c in ("n", "n_motions") if c in frame.columns), None)
    nan = pd.Series(np.nan, index=frame.index)
    out = pd.DataFrame({
        "mode": frame["mode"].astype(str),
        "tan_alpha": frame["tan_alpha"].astype(float),
        "R": frame["R"].astype(float),
        "limit_state": [parse_limit_state(str(s)).name for s in frame["limit_state"]],
        "median_g": frame[median_col].astype(float),
        "beta": frame["beta"].astype(float),
        "n": frame[n_col].astype(float) if n_col else nan,
        "bracket_lo": _bracket(frame, "bracket_lo", kind),
        "bracket_hi": _bracket(frame, "bracket_hi", kind),
        "row": frame["row"].astype(int),
        "status": status.values,
    })
    fitted = np.isfinite(out["median_g"]) & np.isfinite(out["beta"])
    bad = fitted & ((out["median_g"] <= 0) | (out["beta"] <= 0))
    if bad.any():
        r = out[bad].iloc[0]
        raise ValueError(f"{where}: median and beta must be > 0, got {r.median_g!r}, "
                         f"{r.beta!r} at {r['mode']} tan_alpha={r.tan_alpha:g} R={r.R:g} "
                         f"{r.limit_state}")
    not_computed = ~fitted & (out["status"] == NOT_COMPUTED)
    rows = sort_rows(out[fitted])
    rows["status"] = rows["status"].replace("", "ok")
    skipped = sort_rows(out[~fitted & ~not_computed])
    skipped["status"] = skipped["status"].replace("", "no fit")
    return Fragilities(rows, skipped, int(not_computed.sum()), kind, Measure.of(measure).name,
                       _samples(source, bootstrap, n_total),
                       str(source) if isinstance(source, str | Path) else "", component,
                       quantity_of(frame))


def quantity_of(source) -> dict:
    """The per-motion quantity a table or store was made with: ``{"quantity", "p", "w"}``.

    ``source`` is a table (its ``quantity``, ``p``, ``w`` columns) or a store's attributes
    (``quantity``: a mapping ``{name, p, w}`` or its JSON); :data:`LEGACY_QUANTITY` where it
    states none."""
    import json

    if isinstance(source, pd.DataFrame):
        if "quantity" not in source.columns or source.empty:
            return dict(LEGACY_QUANTITY)
        first = source.iloc[0]
        return {"quantity": str(first["quantity"]),
                "p": float(first["p"]) if "p" in source.columns else math.nan,
                "w": float(first["w"]) if "w" in source.columns else math.nan}
    raw = dict(source).get("quantity") if source is not None else None
    if isinstance(raw, str):
        try:
            raw = json.loads(raw)
        except json.JSONDecodeError:
            raw = {"name": raw}
    if not isinstance(raw, dict):
        return dict(LEGACY_QUANTITY)
    return {"quantity": str(raw.get("name", raw.get("quantity", "first_exceedance"))),
            "p": float(raw.get("p", math.nan)), "w": float(raw.get("w", math.nan))}


def with_meta(frame: pd.DataFrame, *, estimator: str, measure=None,
              component: str | None = None, quantity: dict | None = None) -> pd.DataFrame:
    """``frame`` with the :data:`META` columns in front: ``measure`` and ``component`` the
    ones given, else the frame's own per row (a suite table of several); ``unit`` the
    measure's; the quantity's name, p and w."""
    from rocking.motions.measures import Measure, parse_component

    if estimator not in KINDS:
        raise ValueError(f"estimator must be one of {sorted(KINDS)}, got {estimator!r}")
    plain = _plain_columns(frame)
    n = len(frame)
    measures = ([Measure.of(measure).name] * n if measure is not None
                else [Measure.of(str(m)).name for m in plain["measure"]])
    components = ([parse_component(component)] * n if component is not None
                  else [parse_component(str(c)) for c in plain["component"]])
    q = {**LEGACY_QUANTITY, **(quantity or {})}
    meta = {"estimator": [estimator] * n, "measure": measures, "component": components,
            "unit": [Measure.of(m).unit for m in measures], "quantity": [q["quantity"]] * n,
            "p": [q["p"]] * n, "w": [q["w"]] * n}
    rest = frame[[c for c, t in zip(frame.columns, plain.columns, strict=True)
                  if t not in meta]]
    return pd.concat([pd.DataFrame(meta, index=frame.index), rest], axis=1)


def write_fragilities(frame: pd.DataFrame, path: str | Path, *, estimator: str,
                      measure=None, component: str | None = None,
                      quantity: dict | None = None, samples=None,
                      float_format: str = "%.10g") -> Path:
    """Write a fragility table with its :data:`META` columns (:func:`with_meta`), and its
    bootstrap samples beside it.

    Parameters
    ----------
    frame : pandas.DataFrame
        The table (column titles as they are to be written).
    path : path
        ``<name>.csv``; ``samples`` go to ``<name>_bootstrap.nc`` beside it.
    estimator, measure, component, quantity
        As :func:`with_meta`.
    samples : xarray.Dataset, optional
        ``median``, ``beta`` over (row, resample), rows in the table's order
        (:func:`rocking.fragility.bootstrap.write_bootstrap`: the samples' record says
        they belong to the table).
    """
    from rocking.fragility.bootstrap import bootstrap_path, write_bootstrap
    from rocking.provenance import write_atomic

    table = with_meta(frame, estimator=estimator, measure=measure, component=component,
                      quantity=quantity)
    path = Path(path)
    write_atomic(path, lambda tmp: table.to_csv(tmp, index=False, float_format=float_format))
    if samples is not None:
        write_bootstrap(samples, bootstrap_path(path), table=path)
    return path


def _in_measure(frame: pd.DataFrame, measure, where: str):
    """The rows of ``frame`` in ``measure`` (default: its first), the column holding their
    median [the measure's unit], and the measure's name."""
    from rocking.motions.measures import Measure

    if "measure" not in frame.columns:  # fragility.csv written before META: PGA
        if measure is not None and Measure.of(measure) != Measure("pga"):
            raise ValueError(f"{where} holds fits in PGA only, not {Measure.of(measure)}")
        return frame, "median_pga_g", "pga"
    names = [Measure.of(str(m)) for m in frame["measure"]]
    have = list(dict.fromkeys(names))
    wanted = Measure.of(measure) if measure is not None else (have[0] if have else
                                                              Measure("pga"))
    rows = frame[[m == wanted for m in names]]
    if rows.empty:
        raise ValueError(f"{where} has no fit in {wanted} (its measures: "
                         f"{', '.join(m.name for m in have) or 'none'})")
    if "motions" in rows.columns:  # suite_fragility.csv: one group of motions
        groups = [g for g in SUITE_GROUPS if g in set(rows["motions"])]
        fitted = [g for g in groups if np.isfinite(rows.loc[rows["motions"] == g,
                                                            "median"]).any()]
        group = (fitted or groups)[0]
        rows = rows[rows["motions"] == group]
    for column in ("median_im", "median_pga_g"):  # stripes; fragility.csv
        if column in rows.columns:
            return rows, column, wanted.name
    return rows, "median", wanted.name  # a table whose median is in its unit column


def _bracket(frame: pd.DataFrame, name: str, kind: str) -> pd.Series:
    """A stripe table's bracketing intensity [g] (NaN where absent: old tables, or the
    critical-intensity table, whose ``bracket_*`` columns mean something else)."""
    if kind != STRIPES or name not in frame.columns:
        return pd.Series(np.nan, index=frame.index)
    return frame[name].astype(float)


def _samples(source, bootstrap, n_rows: int):
    from rocking.fragility.bootstrap import bootstrap_path, read_bootstrap

    if bootstrap is False:
        return None
    table = source if isinstance(source, str | Path) else None
    if bootstrap is None:
        if table is None:
            return None
        path = bootstrap_path(source)
        if not path.exists():  # said, never a silent blank interval
            log.warning("%s has no bootstrap samples beside it (%s): the risk table's "
                        "lambda_p05/lambda_p95 of its rows stay empty", source, path.name)
            return None
        bootstrap = path
    return read_bootstrap(bootstrap, n_rows, table=table)


def sort_rows(frame: pd.DataFrame) -> pd.DataFrame:
    """Rows by mode, tan α, R, then limit state by :func:`severity` (tilt axis first, each
    axis mildest first)."""
    axis, level = zip(*[severity(s) for s in frame["limit_state"]], strict=True) \
        if len(frame) else ((), ())
    key = frame.assign(_axis=list(axis), _sev=list(level))
    return (key.sort_values(["mode", "tan_alpha", "R", "_axis", "_sev"], kind="stable")
            .drop(columns=["_axis", "_sev"]).reset_index(drop=True))


def lognormal_moments(median: float, beta: float) -> tuple[float, float]:
    """Arithmetic mean and standard deviation of a lognormal variable [same unit as median].

    mean = median·exp(β²/2), stddev = mean·√(exp(β²) − 1): the parameters OpenQuake's
    continuous fragility functions take (``mean``, ``stddev``), not the median and β.
    """
    mean = median * math.exp(0.5 * beta * beta)
    return mean, mean * math.sqrt(math.expm1(beta * beta))


def median_beta(mean: float, stddev: float) -> tuple[float, float]:
    """Inverse of :func:`lognormal_moments`: β = √ln(1 + (σ/μ)²), median = μ²/√(σ² + μ²)."""
    return mean * mean / math.hypot(stddev, mean), math.sqrt(math.log1p((stddev / mean) ** 2))


__all__ = ["COLUMNS", "CRITICAL_INTENSITY", "KEYS", "KINDS", "LEGACY_QUANTITY", "META",
           "RENAMED", "RENAMED_COLUMNS", "STRIPES", "SUITE_GROUPS", "Fragilities",
           "fragility_kind", "lognormal_moments", "median_beta", "quantity_of",
           "read_fragilities", "renamed", "with_meta", "write_fragilities"]
