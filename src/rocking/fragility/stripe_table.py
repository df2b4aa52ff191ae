"""The multiple-stripe fragility table of a stripes store: every (mode, limit state, R) fitted.

A stripes store (:mod:`rocking.execution.stripes` makes and fills it) holds whether each
motion exceeded each limit state at each stripe; this module reads those outcomes into
:class:`rocking.fragility.stripes.StripeFragility` per (mode, R) (:func:`stripe_fits`),
refines the separated fits (:func:`refined_rows`, the analyses of the added stripes from a
callable the caller gives: the execution layer keeps them in its cache), bootstraps every row
over the motions (:func:`bootstrap_rows`, :func:`bootstrap_dataset`) and sets the fit beside
the critical-intensity one of the spectra (:func:`stripe_table`: ``stripe_fragility.csv``). The
store's attributes say what its stripes are in (:func:`store_measure`,
:func:`store_component`, :func:`store_jitter`).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from rocking import __version__
from rocking.fragility.stripes import MEASURE_COLUMNS
from rocking.motions.measures import DEFAULT_COMPONENT, VECTOR_PEAK, Measure

log = logging.getLogger(__name__)

STRIPES_DIMS = ("mode", "limit_state", "motion", "R", "intensity")
"""Dimensions of a stripes store's ``exceeded``, in storage order."""

STRIPES_TASK_DIMS = ("mode", "motion", "R")
"""A task analyses one motion at every stripe for a few sizes R in one mode."""


def store_measure(attrs) -> str:
    """The intensity measure of a stripes store's stripes (``"pga"`` for a store without
    one: those made before stripes had a measure)."""
    return str(attrs.get("measure", "pga"))


def store_jitter(attrs) -> float:
    """The half-width in ln s of a stripes store's jitter (0 for a store without one: its
    stripes were analysed exactly)."""
    return float(attrs.get("jitter", 0.0))


def store_component(attrs) -> str:
    """The horizontal component of a stripes store's measure (the vector peak,
    :data:`~rocking.motions.measures.DEFAULT_COMPONENT`, for a store without one: the
    spectra's PGA, and stores made before components)."""
    return str(attrs.get("component", DEFAULT_COMPONENT))


def stripe_fits(ds: xr.Dataset) -> dict[tuple[str, float], Any]:
    """:class:`rocking.fragility.stripes.StripeFragility` per (mode, R) of a stripes store."""
    from rocking.fragility.stripes import from_outcomes

    missing = ~ds["done"].values.astype(bool)
    if missing.any():
        raise ValueError(f"stripes store is incomplete: {int(missing.sum())} chunks not done")
    tan_alpha = float(ds.attrs["tan_alpha"]) if "tan_alpha" in ds.attrs else float("nan")
    exceeded = ds["exceeded"].transpose(*STRIPES_DIMS).values.astype(bool)
    failed = ds["failed"].transpose("mode", "motion", "R", "intensity").values.astype(bool)
    n_runs = ds["n_analyses"].transpose(*STRIPES_TASK_DIMS).values
    motions = [str(m) for m in ds["motion"].values]
    states = [str(s) for s in ds["limit_state"].values]
    x = ds["intensity"].values.astype(float)
    out = {}
    for i, mode in enumerate(str(m) for m in ds["mode"].values):
        for k, R in enumerate(ds["R"].values.astype(float)):
            # (limit_state, motion, intensity) -> (intensity, motion, limit_state)
            exc = exceeded[i, :, :, k, :].transpose(2, 1, 0)
            out[(mode, float(R))] = from_outcomes(
                x, states, motions, exc, failed[i, :, k, :].T, mode=mode, R=float(R),
                tan_alpha=tan_alpha, n_analyses=int(n_runs[i, :, k].sum()),
                measure=store_measure(ds.attrs), component=store_component(ds.attrs),
                jitter=store_jitter(ds.attrs))
    return out


def refined_rows(fits: dict, refine: int, analyzer: Callable[[Any], Callable] | None = None,
                 *, where: str = "") -> dict[tuple[str, str, float], Any]:
    """One :class:`~rocking.fragility.stripes.StripeFragility` per (mode, limit state, R),
    refined where separated.

    Parameters
    ----------
    fits : dict
        (mode, R) → the stripes as asked (:func:`stripe_fits`).
    refine : int
        Most stripes added per row (:func:`rocking.fragility.stripes.refine_stripes`); 0: none.
    analyzer : callable, optional
        ``analyzer(result)`` → ``analyze(x)`` for one (mode, R): the analyses of an added
        stripe (needed only where a fit is separated and ``refine`` > 0).
    where : str
        Where the refined analyses are kept, for the log.
    """
    from rocking.fragility.stripes import refine_stripes

    out = {}
    for (mode, R), r in fits.items():
        analyze = None
        for j, ls in enumerate(r.limit_states):
            if refine > 0 and r.fits[ls].status == "separated":
                analyze = analyze or analyzer(r)
                row = refine_stripes(r, ls, analyze, refine, log=log.info)
                log.info("%s, %s, R = %g m: %s after %d stripe(s) added (analyses kept in %s)",
                         mode, ls, R, row.fits[ls].status, row.n_refined, where)
            else:
                row = from_outcomes_of(r, j)
            out[(mode, ls, R)] = row
    return out


def from_outcomes_of(result, j: int):
    """The :class:`~rocking.fragility.stripes.StripeFragility` of limit state ``j`` alone."""
    from rocking.fragility.stripes import from_outcomes

    return from_outcomes(result.intensities, [result.limit_states[j]], result.motions,
                         result.exceeded[:, :, [j]], result.failed, mode=result.mode,
                         accuracy=result.accuracy, R=result.R, tan_alpha=result.tan_alpha,
                         n_analyses=result.n_analyses, measure=result.measure,
                         component=result.component, jitter=result.jitter)


TABLE_COLUMNS = ("mode", "limit_state", "tan_alpha", "R", "median", "median_lo", "median_hi",
                 "median_pga_g", "beta", "beta_lo", "beta_hi", "status", "reason", "n_motions",
                 "stripes", "critical_median", "critical_beta", "critical_status", "ratio",
                 "measure", "component", "median_im", "median_p05", "median_p95", "bracket_lo",
                 "bracket_hi", "n_refined", "boot_defined")
"""Columns of ``stripe_fragility.csv`` (before units are added to the titles). ``median``
and its Wald interval are in measure/(g tan α); ``median_im``, ``median_p05``,
``median_p95`` (the bootstrap's 90 % interval), ``bracket_lo``, ``bracket_hi`` in the
measure's unit (:data:`MEASURE_COLUMNS`); ``median_pga_g`` [g] only for the measure PGA;
``stripes`` counts the stripes as asked, ``n_refined`` those added; ``boot_defined`` is the
share of resamples with a median."""



def table_headers(table: pd.DataFrame) -> dict[str, str]:
    """CSV titles of a stripe table: :func:`rocking.units.header`, and the unit of the
    table's measure for :data:`MEASURE_COLUMNS`."""
    from rocking.units import header

    measures = set(table["measure"]) if len(table) else {"pga"}
    units = {Measure.of(m).unit for m in measures}
    unit = units.pop() if len(units) == 1 else "measure unit"
    return {c: f"{c} [{unit}]" if c in MEASURE_COLUMNS else
            ("n_refined" if c == "n_refined" else header(c)) for c in table.columns}


def stripe_table(ds: xr.Dataset, critical: xr.Dataset | None = None, *,
                 rows: dict | None = None, boot: dict | None = None) -> pd.DataFrame:
    """One row per (mode, limit_state, R): the stripe fit and the critical-intensity fit.

    Parameters
    ----------
    ds : xarray.Dataset
        A stripes store.
    critical : xarray.Dataset, optional
        :func:`rocking.fragility.lognormal.fragility_table` of the same study (the
        critical-intensity fragility): its ``median``, ``beta`` and ``status`` at the same
        (mode, limit_state, tan α, R) become ``critical_median``, ``critical_beta``,
        ``critical_status``, and ``ratio`` = stripe median / critical-intensity median (NaN
        where the spectra have no such cell, or the stripes are in another measure than
        PGA).
    rows : dict, optional
        :func:`stripe_rows` (refined fits); None: the stripes as asked.
    boot : dict, optional
        Per (mode, limit state, R), :func:`rocking.fragility.stripes.bootstrap_stripes` of the
        row: gives ``median_p05``, ``median_p95``, ``boot_defined`` (NaN without).

    Returns
    -------
    pandas.DataFrame
        Columns :data:`TABLE_COLUMNS`.
    """
    from rocking.fragility.stripes import bootstrap_interval

    if rows is None:
        rows = refined_rows(stripe_fits(ds), 0)
    base = {(m, R): r.intensities.size for (m, R), r in stripe_fits(ds).items()}
    out = []
    for (mode, ls, R), r in rows.items():
        (rec,) = r.summary_frame().to_dict(orient="records")
        cm, cb, cs = (_critical(critical, mode, ls, r.tan_alpha, R)
                      if r.measure == "pga" and r.component == VECTOR_PEAK
                      else (np.nan, np.nan, f"not comparable ({r.measure} {r.component}, "
                            "not the vector-peak pga)"))
        p05 = p95 = defined = np.nan
        if boot is not None and (mode, ls, R) in boot:
            med = boot[(mode, ls, R)]["median"]
            p05, p95 = (v * r.scale for v in bootstrap_interval(med))
            defined = float(np.mean(~np.isnan(med)))
        out.append({"mode": mode, "tan_alpha": r.tan_alpha, "R": R, **rec,
                    "n_motions": int(r.n_motions.min()), "stripes": int(base[(mode, R)]),
                    "critical_median": cm, "critical_beta": cb, "critical_status": cs,
                    "ratio": rec["median"] / cm if np.isfinite(cm) else np.nan,
                    "median_p05": p05, "median_p95": p95, "boot_defined": defined})
    return pd.DataFrame(out, columns=list(TABLE_COLUMNS))


def bootstrap_rows(rows: dict, resamples: int, seed: int | None = None) -> dict:
    """:func:`rocking.fragility.stripes.bootstrap_stripes` of every row of :func:`stripe_rows`
    (the same resamples of the motions for all), logging the seconds it took."""
    from rocking.fragility.stripes import BOOTSTRAP_SEED, bootstrap_stripes

    t0 = time.perf_counter()
    out = {}
    for key, r in rows.items():
        (ls,) = r.limit_states
        out[key] = bootstrap_stripes(r, resamples, BOOTSTRAP_SEED if seed is None else seed)[ls]
    log.info("bootstrap: %d resamples of the motions for %d rows in %.1f s", resamples,
             len(rows), time.perf_counter() - t0)
    return out


def bootstrap_dataset(table: pd.DataFrame, rows: dict, boot: dict, *, seed: int | None = None,
                      study: str = "") -> xr.Dataset:
    """The resampled fits as ``stripe_fragility_bootstrap.nc``: ``median`` [the measure's
    unit] and ``beta`` [-] over (``row``, ``resample``), ``row`` in the table's order
    (its mode, limit_state, R, measure as coordinates), ``status`` codes of each fit."""
    from rocking.fragility.stripes import BOOT_CODES, BOOTSTRAP_SEED
    keys = list(zip(table["mode"], table["limit_state"], table["R"], strict=True))
    median = np.stack([boot[k]["median"] * rows[k].scale for k in keys]) if keys \
        else np.zeros((0, 0))
    beta = np.stack([boot[k]["beta"] for k in keys]) if keys else np.zeros((0, 0))
    status = np.stack([boot[k]["status"] for k in keys]) if keys else np.zeros((0, 0), np.int8)
    measure = str(table["measure"].iloc[0]) if keys else "pga"
    unit = Measure.of(measure).unit
    dims = ("row", "resample")
    ds = xr.Dataset(
        {"median": (dims, median, {"units": unit, "long_name": f"median {measure} of the "
                                   "resample's lognormal fit (geometric middle of the "
                                   "bracket where it separates, inf where no motion exceeds, "
                                   "0 where all do, NaN where no fit)"}),
         "beta": (dims, beta, {"units": "-", "long_name": "lognormal dispersion of the "
                               "resample (0 where it separates)"}),
         "status": (dims, status, {"flag_values": list(BOOT_CODES.values()),
                                   "flag_meanings": " ".join(BOOT_CODES)})},
        coords={"row": np.arange(len(keys)), "resample": np.arange(median.shape[1]),
                "mode": ("row", [k[0] for k in keys]),
                "limit_state": ("row", [k[1] for k in keys]),
                "R": ("row", np.array([k[2] for k in keys], dtype=float), {"units": "m"}),
                "tan_alpha": ("row", table["tan_alpha"].to_numpy(dtype=float))},
        attrs={"title": f"Bootstrap over motions of the stripe fragility, study {study}",
               "measure": measure, "seed": int(BOOTSTRAP_SEED if seed is None else seed),
               "resamples": int(median.shape[1]), "interval": "median_p05, median_p95 of "
               "stripe_fragility.csv: 5 and 95 % order statistics (inverted_cdf) of median "
               "over the resamples that have one", "rocking_version": __version__})
    return ds


def _critical(critical: xr.Dataset | None, mode: str, ls: str, tan_alpha: float,
              R: float) -> tuple[float, float, str]:
    """(median, beta, status) of the critical-intensity fit at one cell, NaN if absent."""
    none = (float("nan"), float("nan"), "not computed")
    if critical is None:
        return none
    try:
        cell = critical.sel(mode=mode, limit_state=ls)
        cell = cell.isel(tan_alpha=int(np.flatnonzero(np.isclose(cell["tan_alpha"].values,
                                                                  tan_alpha))[0]),
                         R=int(np.flatnonzero(np.isclose(cell["R"].values, R))[0]))
    except (KeyError, IndexError):
        return none
    return float(cell["median"]), float(cell["beta"]), str(cell["status"].values)


__all__ = ["STRIPES_DIMS", "STRIPES_TASK_DIMS", "TABLE_COLUMNS", "bootstrap_dataset",
           "bootstrap_rows", "from_outcomes_of", "refined_rows", "store_component",
           "store_jitter", "store_measure", "stripe_fits", "stripe_table", "table_headers"]
