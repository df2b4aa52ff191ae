"""Ensemble statistics of performance spectra: mean, std, median and count over motions.

The paper's Figs 10–12 plot, for each size R, the mean over the ground motions of the
critical intensity PGA/(g tan α); here that is the mean of the per-motion answers of the
study's quantity (:class:`rocking.spectra.quantity.Quantity`: I10 by default, the lowest
intensity near which a tenth of the intensities exceed), named with its p and w in every
table (:func:`quantity_columns`), so that tables of two quantities are never mixed. A motion
whose search ended without reaching the limit state (``not_reached``) has no critical
intensity, only a lower bound (the search bound); it is left out of ``mean``, ``std`` and
``median`` and counted separately (``n_not_reached``), so ``count`` says how many motions
they rest on, and such a mean is biased low: it is the mean of the motions that happened to
exceed below the bound. Two columns keep that from passing as the ensemble mean:
``censoring`` says in words how each cell treats the motions not reached, and ``median_all``
is the median over all motions with those counted above the bound — the Kaplan–Meier median,
exact here because every censored value lies above every observed one; it is NaN when half
or more of the motions were not reached (the median is then somewhere above the bound).
Cells no run of the study asked for (``requested`` false, see :mod:`rocking.config.plan`)
were never computed: their statistics are NaN with count 0, and ``requested`` is carried
over so that a reader can tell "not computed" from "not reached".
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr

from rocking.spectra.quantity import COLUMNS as QUANTITY_NAMES
from rocking.store import REPAIR
from rocking.units import CSV_FLOAT_FORMAT, attrs, header

STAT_DIMS = ("mode", "limit_state", "tan_alpha", "R")
"""Dimensions of the aggregated spectra."""


def ensemble_statistics(ds: xr.Dataset) -> xr.Dataset:
    """Statistics over ``motion`` of ``pga_crit`` per (mode, limit_state, tan_alpha, R).

    Parameters
    ----------
    ds : xarray.Dataset
        A spectra store (``pga_crit``, ``not_reached``, ``done``), e.g. from
        ``xarray.open_zarr``.

    Returns
    -------
    xarray.Dataset
        ``mean``, ``std`` (sample, ddof = 1; NaN with fewer than 2 values), ``median``
        [PGA/(g tan α), -] over the motions reached, ``mean_pga_g`` (the mean as PGA [g]),
        ``median_all`` (over all motions, :func:`median_all`), ``count`` (motions used),
        ``n_not_reached``, ``censoring`` (:func:`censoring_notes`) and ``requested``
        (mode, limit_state, tan_alpha; all true for a store without the mask); CF
        ``units`` and ``long_name`` on everything.

    Raises
    ------
    ValueError
        If the store has points not computed yet (``done`` false): statistics of a partial
        ensemble would look like results.
    """
    missing = ~ds["done"].values.astype(bool)
    if missing.any():
        # labels are numpy scalars or (mode, motion) plain str: no .item() on those
        first = {d: _plain(ds["done"][d].values[i])
                 for d, i in zip(ds["done"].dims, np.argwhere(missing)[0], strict=True)}
        raise ValueError(f"spectra store is incomplete: {int(missing.sum())} points not done, "
                         f"first at {first}")
    pga = ds["pga_crit"].load()
    if "requested" in ds:
        requested = ds["requested"].load().astype(bool)
    else:
        requested = xr.ones_like(pga.isel(motion=0, R=0, drop=True), dtype=bool)
    reached = ~ds["not_reached"].load().astype(bool) & requested
    if bool((pga.isnull() & reached).any()):
        raise ValueError("pga_crit is NaN at a point whose limit state was reached")
    values = pga.where(reached)
    count = reached.sum("motion").astype(np.int32)
    n_not_reached = (~reached & requested).sum("motion").astype(np.int32)
    out = xr.Dataset(
        {
            "mean": values.mean("motion", skipna=True),
            "std": values.std("motion", ddof=1, skipna=True).where(count >= 2),
            "median": values.median("motion", skipna=True),
            "median_all": median_all(pga, reached, requested),
            "count": count,
            "n_not_reached": n_not_reached,
        }
    ).transpose(*STAT_DIMS)
    out["requested"] = requested.transpose(*(d for d in STAT_DIMS if d in requested.dims))
    out["mean_pga_g"] = out["mean"] * out["tan_alpha"]
    out["censoring"] = censoring_notes(out)
    # answers where P rises near p without crossing it (I_p ill-conditioned): the count
    # says how many of a mean's answers a small change of the response could move down
    flag = ds["plateau"].load().astype(bool) & reached
    out["n_plateau"] = flag.sum("motion").astype(np.int32).transpose(*STAT_DIMS)
    out.update(validity_counts(ds, requested))
    for name in out.variables:
        out[name].attrs = attrs(str(name))
    out["std"].attrs["ddof"] = 1
    out.attrs = {k: v for k, v in ds.attrs.items() if k != "layout"}
    out.attrs["motions"] = ", ".join(map(str, ds["motion"].values))
    out.attrs["quantity"] = _json_text(store_quantity(ds.attrs))
    return out


def _json_text(value) -> str:
    import json

    return json.dumps(value, sort_keys=True)


def store_quantity(attrs) -> dict:
    """The quantity a spectra store (or a table made from it) holds, from its ``quantity``
    attribute (:meth:`rocking.spectra.quantity.Quantity.to_dict`: name, p, w).

    Raises
    ------
    ValueError
        For a store without it (made before the quantity was recorded): its answers are
        first exceedances of an older search, not to be set beside these.
    """
    from rocking.spectra.quantity import Quantity
    from rocking.store.attrs import decode_attrs

    found = decode_attrs(dict(attrs)).get("quantity")
    if found is None:
        raise ValueError("spectra store without a 'quantity' attribute: made by an older "
                         "version whose answers are first exceedances of another search; "
                         "delete it and run its rule again")
    return Quantity.from_value(found).to_dict()


QUANTITY_COLUMNS = (*QUANTITY_NAMES, "scan_step")
"""Columns naming the quantity of every table of answers: its name, p and w
(:meth:`rocking.spectra.quantity.Quantity.columns`, the names of ``rocking spectra``'s table)
and the step of the scan grid (which labels a first exceedance)."""


def quantity_values(attrs) -> dict[str, object]:
    """:data:`QUANTITY_COLUMNS` of a store (or of a table made from one) by their names."""
    from rocking.spectra.quantity import Quantity
    from rocking.store.attrs import decode_attrs

    step = (decode_attrs(dict(attrs)).get("tolerances") or {}).get("scan_step")
    return {**Quantity.from_value(store_quantity(attrs)).columns(),
            "scan_step": np.nan if step is None else float(step)}


def quantity_columns(frame: pd.DataFrame, attrs, after: Sequence[str]) -> pd.DataFrame:
    """``frame`` with the :data:`QUANTITY_COLUMNS` of the store whose ``attrs`` it was made
    from, placed after its key columns ``after`` (headers with units)."""
    keys = [c for c in frame.columns if c in after]
    rest = [c for c in frame.columns if c not in after]
    out = frame[keys].copy()
    for name, value in quantity_values(attrs).items():
        out[header(name)] = value
    return pd.concat([out, frame[rest]], axis=1)


def monitored(ds: xr.Dataset) -> xr.DataArray:
    """Per (mode, tan_alpha), whether the searches ran the support monitors (N, μ_req), so
    that ``lifts_off`` was looked at: only where the study gave μ or a requested limit state
    of that (mode, tan α) watches them (sliding; :func:`rocking.spectra.critical.make_analysis`
    compiles them in only there). Elsewhere ``lifts_off`` is false without having been looked
    at, and the tables leave it empty."""
    from rocking.spectra.limit_states import parse_limit_state
    from rocking.store.attrs import decode_attrs

    mu = decode_attrs(ds.attrs).get("search_options", {}).get("mu")
    dims = tuple(d for d in ("mode", "tan_alpha") if d in ds.dims)
    base = xr.DataArray(np.zeros([ds.sizes[d] for d in dims], dtype=bool), dims=dims,
                        coords={d: ds[d] for d in dims})
    if mu is not None:
        return ~base
    watches = xr.DataArray([parse_limit_state(str(ls)).whole_record
                            for ls in ds["limit_state"].values], dims="limit_state",
                           coords={"limit_state": ds["limit_state"]})
    asked = ds["requested"].load().astype(bool) if "requested" in ds else xr.DataArray(True)
    seen = asked & watches
    return (seen.any([d for d in seen.dims if d not in dims]) | base).transpose(*dims)


def validity_counts(ds: xr.Dataset, requested: xr.DataArray) -> dict[str, xr.DataArray]:
    """``n_lifts_off`` where the searches were monitored (:func:`monitored`; -1 elsewhere:
    not looked at) and, where the study gave μ, ``n_slides``: per cell, the motions whose
    analyses up to the answer had N ≤ 0 or slid in contact (reached or not; left out for a
    store made before these flags, ``n_slides`` without μ)."""
    out = {}
    if "lifts_off" in ds:
        flag = ds["lifts_off"].load().astype(bool) & requested
        count = flag.sum("motion").astype(np.int32)
        count = count.where(monitored(ds).broadcast_like(count), -1).astype(np.int32)
        out["n_lifts_off"] = count.transpose(*STAT_DIMS)
    if "slides" in ds and bool(ds["slides"].notnull().any()):
        flag = (ds["slides"].load() == 1.0) & requested
        out["n_slides"] = flag.sum("motion").astype(np.int32).transpose(*STAT_DIMS)
    return out


def _plain(value):
    """A coordinate value as a plain Python number or string."""
    return value.item() if isinstance(value, np.generic) else value


def median_all(pga: xr.DataArray, reached: xr.DataArray,
               requested: xr.DataArray) -> xr.DataArray:
    """Median over all motions of a requested cell, not-reached ones counted above the bound.

    A not-reached motion only says that its critical intensity lies above the search bound,
    hence above every intensity that was reached: set to +inf, it takes its true rank, and the
    ordinary median is the Kaplan–Meier median of the right-censored sample. Where a middle
    order statistic is one of them (half or more not reached) the median is not determined
    below the bound: NaN [PGA/(g tan α)].
    """
    ranked = xr.where(reached, pga, np.inf).where(requested)
    med = ranked.median("motion", skipna=True)
    return med.where(np.isfinite(med))


def censoring_notes(stats: xr.Dataset) -> xr.DataArray:
    """Per cell, how the statistics treat motions not reached (the ``censoring`` column)."""
    count = stats["count"].values
    nr = stats["n_not_reached"].values
    req = stats["requested"].broadcast_like(stats["count"]).transpose(
        *stats["count"].dims).values.astype(bool)
    med_all = stats["median_all"].values
    notes = np.empty(count.shape, dtype=object)
    for idx in np.ndindex(count.shape):
        k, n = int(nr[idx]), int(nr[idx] + count[idx])
        if not req[idx]:
            notes[idx] = "not computed"
        elif k == 0:
            notes[idx] = "none"
        elif k == n:
            notes[idx] = f"all {n} not reached: no statistic"
        else:
            tail = ("median_all over all motions" if np.isfinite(med_all[idx])
                    else "median_all above the search bound")
            notes[idx] = (f"excluded {k} of {n}: mean, std, median over the {n - k} reached "
                          f"only (biased low); {tail}")
    return xr.DataArray(notes.astype(str), dims=stats["count"].dims,
                        coords=stats["count"].coords)


def to_frame(stats: xr.Dataset) -> pd.DataFrame:
    """Long table, one row per (mode, limit_state, tan_alpha, R); headers with units."""
    cols = ["mean", "mean_pga_g", "std", "median", "median_all", "count", "n_not_reached",
            "n_plateau", "n_slides", "n_lifts_off", "censoring", "requested"]
    cols = [c for c in cols if c in stats]
    df = stats[cols].to_dataframe().reset_index()[[*STAT_DIMS, *cols]]
    df = df.rename(columns=header)
    return quantity_columns(df, stats.attrs, [header(d) for d in STAT_DIMS])


CRITICAL_COLUMNS = ("pga_crit", "pga_crit_g", "i50", "first_exceedance", "plateau",
                    "not_reached", "non_monotonic", "failed", "slides", "lifts_off",
                    "n_analyses")
"""Per-motion results of a spectra store, as :func:`critical_frame` lists them."""


def requested_answers(ds: xr.Dataset, columns: Sequence[str]) -> pd.DataFrame:
    """``columns`` of a spectra store as one row per (mode, limit_state, motion, tan_alpha,
    R) that the study's runs asked for (cells no run asked for left out), labels as str, in
    the store's order; one conversion of the whole store (a paper study has 10^5 rows)."""
    frame = ds[list(columns)].reset_coords(drop=True).load().to_dataframe().reset_index()
    if "requested" in ds:
        req = ds["requested"].reset_coords(drop=True).load().to_dataframe().reset_index()
        frame = frame.merge(req, on=list(ds["requested"].dims))
        frame = frame[frame["requested"].astype(bool)].drop(columns="requested")
    for dim in ("mode", "limit_state", "motion"):
        frame[dim] = frame[dim].astype(str)
    if "pga_crit" in frame and "not_reached" in frame:
        # a requested answer is a number or "not reached", never an empty cell
        blank = frame["pga_crit"].isna() & ~frame["not_reached"].astype(bool)
        if blank.any():
            row = frame[blank].iloc[0]
            raise ValueError(f"spectra store: {int(blank.sum())} requested answers are NaN "
                             f"without a flag, the first at mode={row['mode']}, limit_state="
                             f"{row['limit_state']}, motion={row['motion']}, tan_alpha="
                             f"{row['tan_alpha']}, R={row['R']}; the store is incomplete or "
                             f"damaged: {REPAIR}")
    return frame


def nullable_flag(values: pd.Series) -> pd.Series:
    """A flag stored as float (1.0/0.0, NaN: nothing said, e.g. ``slides`` without the
    study's μ) as pandas' nullable boolean: the CSV tables write True/False like every
    other flag, and an empty cell where it says nothing."""
    v = pd.to_numeric(values, errors="raise").astype(float)
    return pd.Series(pd.array([pd.NA if np.isnan(x) else bool(x) for x in v],
                              dtype="boolean"), index=values.index, name=values.name)


def unmonitored_empty(ds: xr.Dataset, frame: pd.DataFrame) -> pd.Series:
    """``frame``'s ``lifts_off`` (rows with ``mode`` and ``tan_alpha``) as True/False where
    the searches were monitored, empty where they were not (:func:`monitored`)."""
    mask = monitored(ds)
    if mask.ndim == 0:
        seen = np.full(len(frame), bool(mask))
    else:
        table = mask.to_series()
        names = list(table.index.names)
        table.index = pd.MultiIndex.from_arrays(
            [table.index.get_level_values(n).astype(str) if n == "mode" else
             table.index.get_level_values(n) for n in names])
        keys = pd.MultiIndex.from_arrays(
            [frame[n].astype(str) if n == "mode" else frame[n] for n in names])
        seen = table.reindex(keys).fillna(False).to_numpy(dtype=bool)
    flag = frame["lifts_off"].astype(bool).to_numpy()
    return pd.Series(pd.array([bool(f) if s else pd.NA for f, s in zip(flag, seen,
                                                                        strict=True)],
                              dtype="boolean"), index=frame.index, name="lifts_off")


def critical_frame(ds: xr.Dataset) -> pd.DataFrame:
    """Every computed answer of a spectra store, one row per (mode, limit_state, motion,
    tan_alpha, R) that the study's runs asked for: the quantity (name, p, w), the critical
    intensity [PGA/(g tan α)], as PGA [g], I50, the first exceedance on the scan grid, the
    search's flags and its analyses; headers with units."""
    cols = [c for c in CRITICAL_COLUMNS if c in ds]
    dims = ["mode", "limit_state", "motion", "tan_alpha", "R"]
    frame = requested_answers(ds, cols)[[*dims, *cols]]
    if "slides" in frame:
        frame["slides"] = nullable_flag(frame["slides"])
    if "lifts_off" in frame:
        frame["lifts_off"] = unmonitored_empty(ds, frame)
    frame = frame.sort_values(dims, kind="stable").reset_index(drop=True).rename(columns=header)
    return quantity_columns(frame, ds.attrs, [header(d) for d in dims])


CRITICAL_FLOAT_FORMAT = "%.10g"
"""Digits of ``critical.csv`` (10 significant: below any answer's resolution)."""


def write_critical_table(store: str | Path, csv: str | Path) -> Path:
    """``critical.csv``: the spectra store of a study as one row per computed answer
    (:func:`critical_frame`), written under a temporary name and renamed; returns ``csv``."""
    from rocking.provenance import write_atomic

    with xr.open_zarr(store, consolidated=True) as ds:
        frame = critical_frame(ds)
    csv = Path(csv)
    write_atomic(csv, lambda tmp: frame.to_csv(tmp, index=False,
                                               float_format=CRITICAL_FLOAT_FORMAT))
    return csv


def write_statistics(stats: xr.Dataset, nc_path: str | Path, csv_path: str | Path) -> None:
    """Write ``mean_spectra.nc`` (netCDF) and its CSV twin."""
    nc = stats.copy()
    for dim in ("mode", "limit_state"):
        # plain str labels: the netCDF writer does not take numpy's StringDType
        nc = nc.assign_coords({dim: (dim, np.array([str(v) for v in nc[dim].values],
                                                    dtype=object), nc[dim].attrs)})
    nc.to_netcdf(nc_path)
    to_frame(nc).to_csv(csv_path, index=False, float_format=CSV_FLOAT_FORMAT)
