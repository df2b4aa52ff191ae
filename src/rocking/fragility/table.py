"""The study's fragility table as the rows the exports and the risk table need.

Reads what :func:`rocking.fragility.lognormal.fragility_table` computes (the Dataset, its flat
:func:`~rocking.fragility.lognormal.to_frame` table, or ``results/<study>/fragility.csv`` /
``.nc``) and keeps, per (mode, tan α, R, limit state), the median PGA capacity in g and β.
Rows without a fit (median or β NaN: too few motions reached the limit state, or no spread)
are set aside in :attr:`Fragilities.skipped` with their status, never silently dropped; cells
the study never asked for (status ``not-computed``) are not part of it and are only counted.
Limit states are ordered by increasing severity: increasing tilt goal, overturning last.

Two fragilities of a study are read the same way, and :attr:`Fragilities.kind` says which:
``first_exceedance`` (``fragility.csv``: a lognormal fitted to each motion's smallest
exceeding intensity) and ``stripes`` (``stripe_fragility.csv`` of
:func:`rocking.execution.stripes.stripe_table`: a lognormal fitted by binomial maximum likelihood
to the share of motions exceeding at fixed intensities). The exports and the risk table carry
the kind in their ids and a column (:data:`KINDS`).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pandas as pd

from rocking.fragility.bootstrap import BootstrapSamples
from rocking.spectra.limit_states import TILT_AXIS, parse_limit_state, severity, sort_limit_states
from rocking.units import strip_units

log = logging.getLogger(__name__)

KEYS = ("mode", "tan_alpha", "R", "limit_state")
"""Columns that identify a fragility."""

COLUMNS = (*KEYS, "median_g", "beta", "n", "bracket_lo", "bracket_hi", "row", "status")
"""Columns of :attr:`Fragilities.rows` and :attr:`Fragilities.skipped` (``n`` motions fitted,
``row`` the row of the table read, −1 for a frame without one)."""

SUITE_GROUPS = ("records", "synthetic")
"""Motion groups of ``suite_fragility.csv``, in the order the risk table prefers them."""

NOT_COMPUTED = "not-computed"

FIRST_EXCEEDANCE = "first_exceedance"
STRIPES = "stripes"
KINDS = {
    FIRST_EXCEEDANCE: "first-exceedance fragility: lognormal fitted to each motion's smallest "
                      "intensity exceeding the limit state (motions not reached censored at "
                      "the search bound)",
    STRIPES: "multiple-stripe fragility: lognormal fitted by binomial maximum likelihood to "
             "the share of motions exceeding the limit state at fixed intensities",
}
"""Which fragility a table holds → one line saying what it is (descriptions of the exports)."""


def fragility_kind(frame: pd.DataFrame) -> str:
    """:data:`STRIPES` for a stripe table (it has a ``stripes`` column, the number of stripe
    intensities), else :data:`FIRST_EXCEEDANCE`."""
    return STRIPES if "stripes" in _plain_columns(frame).columns else FIRST_EXCEEDANCE


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
        Which fragility: ``"first_exceedance"`` or ``"stripes"`` (:data:`KINDS`).
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
    """

    rows: pd.DataFrame
    skipped: pd.DataFrame
    n_not_computed: int = 0
    kind: str = FIRST_EXCEEDANCE
    measure: str = "pga"
    samples: BootstrapSamples | None = None
    source: str = ""
    component: str = "vector_peak"

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"kind must be one of {sorted(KINDS)}, got {self.kind!r}")

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
        ``results/<study>/fragility.csv`` or ``.nc`` (first exceedance in PGA),
        ``suite_fragility.csv`` (first exceedance in each intensity measure of the study),
        ``stripe_fragility.csv``, or the table itself; column titles with or without units.
    kind : {"first_exceedance", "stripes"}, optional
        Which fragility the table holds; default: told by its columns
        (:func:`fragility_kind`).
    measure : str, optional
        The intensity measure wanted (``"pga"``, ``"sa:1.0"``; default ``pga``). A suite or
        stripe table with a ``measure`` column gives its rows of that measure; a suite table
        its ``records`` rows (its ``synthetic`` ones where it has no records).
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
    from rocking.motions.measures import DEFAULT_COMPONENT, same_measure

    frame = _plain_columns(_as_frame(source)).reset_index(drop=True)
    n_total = len(frame)
    frame["row"] = np.arange(n_total)
    if kind is None:
        kind = fragility_kind(frame)
    elif kind not in KINDS:
        raise ValueError(f"kind must be one of {sorted(KINDS)}, got {kind!r}")
    where = str(source) if isinstance(source, str | Path) else "fragility table"
    measure = "pga" if measure is None else measure
    have = (list(dict.fromkeys(frame["component"].astype(str))) if "component" in frame.columns
            else [DEFAULT_COMPONENT])
    if component is None:
        component = have[0] if have else DEFAULT_COMPONENT
    if component not in have:
        raise ValueError(f"{where} has no fit in the component {component} (its components: "
                         f"{', '.join(have)}): fit it there (studies.<name>.component, or "
                         "hazard: {file, component} so the suite is fitted in it too), or "
                         "declare the hazard's component if it is one of those")
    if "component" in frame.columns:
        frame = frame[frame["component"].astype(str) == component]
    frame, median_col = _in_measure(frame, measure, where, same_measure)
    if "measure" in frame.columns and len(frame):
        measure = str(frame["measure"].iloc[0])  # the table's own spelling (sa:1.0)
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
    return Fragilities(rows, skipped, int(not_computed.sum()), kind, measure,
                       _samples(source, bootstrap, n_total),
                       str(source) if isinstance(source, str | Path) else "", component)


def _in_measure(frame: pd.DataFrame, measure: str, where: str, same_measure):
    """The rows of ``frame`` in ``measure`` and the column holding their median [g]."""
    has_measure = "measure" in frame.columns
    if "motions" in frame.columns and has_measure:  # suite_fragility.csv
        rows = frame[[same_measure(str(m), measure) for m in frame["measure"]]]
        if rows.empty:
            raise ValueError(f"{where} has no fit in {measure} (its measures: "
                             f"{sorted(set(map(str, frame['measure'])))}): add {measure} to "
                             "the study's intensity_measures (if it is there, the table is "
                             "older than the configuration: rerun with `snakemake "
                             "--forcerun records_table`)")
        groups = [g for g in SUITE_GROUPS if g in set(rows["motions"])]
        fitted = [g for g in groups if np.isfinite(rows.loc[rows["motions"] == g,
                                                            "median"]).any()]
        group = (fitted or groups)[0]
        return rows[rows["motions"] == group], "median"
    if has_measure:  # a stripe table that says its measure
        rows = frame[[same_measure(str(m), measure) for m in frame["measure"]]]
        if rows.empty:
            raise ValueError(f"{where} has no fit in {measure} (its measure: "
                             f"{sorted(set(map(str, frame['measure'])))})")
        return rows, ("median_im" if "median_im" in rows.columns else "median_pga_g")
    if not same_measure(measure, "pga"):
        raise ValueError(f"{where} holds fits in PGA only, not {measure}: give the suite's "
                         "suite_fragility.csv (or a stripe table in that measure)")
    return frame, "median_pga_g"


def _bracket(frame: pd.DataFrame, name: str, kind: str) -> pd.Series:
    """A stripe table's bracketing intensity [g] (NaN where absent: old tables, or the
    first-exceedance table, whose ``bracket_*`` columns mean something else)."""
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


__all__ = ["COLUMNS", "FIRST_EXCEEDANCE", "KEYS", "KINDS", "STRIPES", "SUITE_GROUPS",
           "Fragilities",
           "fragility_kind", "lognormal_moments", "median_beta", "read_fragilities"]
