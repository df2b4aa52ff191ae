"""Multiple-stripe runs of a study: a chunked zarr store, its fragility table.

``results/<study>/stripes.zarr`` holds, for every (mode, motion, R, stripe intensity), whether
the analysis exceeded each limit state (``exceeded`` over mode, limit_state, motion, R,
intensity) and whether it failed. It is made, filled on Dask and resumed exactly like the
spectra store (:mod:`rocking.study.store`, :mod:`rocking.study.cluster`): a task is one mode,
one motion and ``chunk_R`` sizes, and runs :func:`rocking.spectra.stripes.stripe_outcomes`.
:func:`stripe_table` fits the lognormal of :mod:`rocking.spectra.stripes` per (mode, limit
state, R) and sets it beside the first-exceedance fragility of the spectra
(:func:`rocking.spectra.fragility.fragility_table`).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from .. import __version__
from ..spectra.accuracy import get_accuracy
from . import store, tasks
from .layout import Layout, Variable, label_coord, region_coords, value_coord
from .prepare import ready_store
from .spec import Damping, StripesSpec

log = logging.getLogger(__name__)

STRIPES_DIMS = ("mode", "limit_state", "motion", "R", "intensity")
"""Dimensions of ``exceeded``, in storage order."""

STRIPES_TASK_DIMS = ("mode", "motion", "R")
"""A task analyses one motion at every stripe for a few sizes R in one mode."""


def stripes_layout(modes: Sequence[str], limit_states: Sequence[str], motions: Sequence[str],
                   R: Sequence[float], intensity: Sequence[float], chunk_R: int) -> Layout:
    """Layout of a stripes store.

    Parameters
    ----------
    modes, limit_states, motions : sequence of str
    R : sequence of float
        Semi-diagonals [m].
    intensity : sequence of float
        Stripes, PGA/(g tan α) [-], increasing.
    chunk_R : int
        Sizes R per task.
    """
    x = np.asarray(intensity, dtype=float)
    if x.ndim != 1 or np.any(np.diff(x) <= 0):
        raise ValueError(f"stripe intensities must be strictly increasing, got {intensity!r}")
    coords = {
        "mode": label_coord("mode", modes),
        "limit_state": label_coord("limit_state", limit_states),
        "motion": label_coord("motion", motions),
        "R": value_coord("R", R),
        "intensity": value_coord("intensity", intensity),
    }
    variables = {
        "exceeded": Variable(STRIPES_DIMS, "bool", False),
        "failed": Variable(("mode", "motion", "R", "intensity"), "bool", False),
        "n_analyses": Variable(STRIPES_TASK_DIMS, "int32", 0),
    }
    return Layout(coords, variables, STRIPES_TASK_DIMS, {"R": int(chunk_R)})


def prepare_store(path: str | Path, spec: StripesSpec | dict[str, Any], config_digest: str,
                  motions: str | Path) -> str:
    """Make (or keep, or replace) the stripes store of a study.

    ``spec``: a :class:`~rocking.study.spec.StripesSpec` or its ``to_attrs()`` (the
    workflow's ``stripes_spec``). Returns ``"created"``, ``"resumed"`` or ``"replaced"``.
    """
    from ..spectra.limit_states import parse_limit_states

    s = spec if isinstance(spec, StripesSpec) else StripesSpec.from_attrs(spec)

    def create(p: Path) -> None:
        ensemble = tasks.ensemble_attrs(motions, s.ensemble.name)
        names = [m["name"] for m in ensemble["motions"]]
        states = [ls.name for ls in parse_limit_states(list(s.limit_states), sort=False)]
        layout = stripes_layout(s.modes, states, names, s.R, s.intensity, s.chunk_R)
        attrs = {
            "title": f"Multiple-stripe analyses, study {s.study}",
            "config": s.to_attrs(),
            "tan_alpha": float(s.tan_alpha),
            "tolerances": get_accuracy(s.accuracy).to_dict(),
            "model_options": Damping.options(s.damping),
            "rocking_version": __version__,
            "ensemble": ensemble,
            "intensity_definition": "PGA/(g tan alpha), PGA = max sqrt(ax^2 + ay^2) of the pair",
        }
        pga_g = ("intensity", [i * float(s.tan_alpha) for i in s.intensity])
        store.create_store(p, layout, attrs, config_digest,
                           coords={**tasks.identity_coords(ensemble), "pga_g": pga_g})
        log.info("created %s: %d chunks, %d motions x %d stripes", p, layout.n_regions,
                 len(names), len(s.intensity))

    return ready_store(path, config_digest, create)


def fill_stripes_region(path: str | Path, index: int, motions: tasks.MotionSource,
                        ) -> dict[str, float]:
    """Analyse one motion at every stripe for the sizes R of region ``index``; write them.

    Returns ``index``, ``points`` (analyses asked for) and compute ``seconds``.
    """
    from ..dynamics.bodies import Cylinder
    from ..spectra.limit_states import parse_limit_states
    from ..spectra.stripes import stripe_outcomes

    t0 = time.perf_counter()
    layout = store.open_layout(path)
    attrs = store.read_attrs(path)
    rc = region_coords(layout, index)
    (mode,), (name,) = rc["mode"], rc["motion"]
    motion = tasks.motion_named(motions, name)
    states = parse_limit_states([str(s) for s in layout.coords["limit_state"]], sort=False)
    x = np.asarray(layout.coords["intensity"], dtype=float)
    acc = get_accuracy(attrs["tolerances"])
    tan_alpha = float(attrs["tan_alpha"])
    exc, fail, runs = [], [], []
    for R in rc["R"]:
        e, f, n = stripe_outcomes(Cylinder(float(R), tan_alpha), motion, states, x, str(mode),
                                  acc, **attrs.get("model_options", {}))
        exc.append(e.T)  # (limit_state, intensity)
        fail.append(f)
        runs.append(n)
    values = {
        # (R, limit_state, intensity) -> (mode=1, limit_state, motion=1, R, intensity)
        "exceeded": np.stack(exc, axis=1)[None, :, None],
        "failed": np.stack(fail)[None, None],
        "n_analyses": np.asarray(runs, dtype=np.int32)[None, None],
    }
    store.write_region(path, layout, index, values)
    return {"index": index, "points": len(rc["R"]) * x.size,
            "seconds": time.perf_counter() - t0}


def compute(path: str | Path, spec: Any, config_digest: str, motions: str | Path,
            **fill_kw) -> dict[str, Any]:
    """Prepare the stripes store and fill it on Dask (``fill_kw``: as
    :func:`rocking.study.cluster.fill_store`); returns its summary with ``store_state``."""
    from . import cluster

    state = prepare_store(path, spec, config_digest, motions)
    summary = cluster.fill_store(path, fill_stripes_region, motions,
                                 config_digest=config_digest, **fill_kw)
    return {**summary, "store_state": state}


def stripe_fits(ds: xr.Dataset) -> dict[tuple[str, float], Any]:
    """:class:`rocking.spectra.stripes.StripeFragility` per (mode, R) of a stripes store."""
    from ..spectra.stripes import from_outcomes

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
                tan_alpha=tan_alpha, n_analyses=int(n_runs[i, :, k].sum()))
    return out


TABLE_COLUMNS = ("mode", "limit_state", "tan_alpha", "R", "median", "median_lo", "median_hi",
                 "median_pga_g", "beta", "beta_lo", "beta_hi", "status", "reason", "n_motions",
                 "stripes", "first_median", "first_beta", "first_status", "ratio")
"""Columns of ``stripe_fragility.csv`` (before units are added to the titles)."""


def stripe_table(ds: xr.Dataset, first: xr.Dataset | None = None) -> pd.DataFrame:
    """One row per (mode, limit_state, R): the stripe fit and the first-exceedance fit.

    Parameters
    ----------
    ds : xarray.Dataset
        A stripes store.
    first : xarray.Dataset, optional
        :func:`rocking.spectra.fragility.fragility_table` of the same study: its ``median``,
        ``beta`` and ``status`` at the same (mode, limit_state, tan α, R) become
        ``first_median``, ``first_beta``, ``first_status``, and ``ratio`` = stripe median /
        first-exceedance median (NaN where the spectra have no such cell).

    Returns
    -------
    pandas.DataFrame
        Columns :data:`TABLE_COLUMNS` (medians in PGA/(g tan α), median_pga_g in g).
    """
    rows = []
    for (mode, R), r in stripe_fits(ds).items():
        summary = r.summary_frame()
        for rec in summary.to_dict(orient="records"):
            ls = rec["limit_state"]
            fm, fb, fs = _first(first, mode, ls, r.tan_alpha, R)
            rows.append({"mode": mode, "tan_alpha": r.tan_alpha, "R": R, **rec,
                         "n_motions": int(r.n_motions.min()), "stripes": int(r.intensities.size),
                         "first_median": fm, "first_beta": fb, "first_status": fs,
                         "ratio": rec["median"] / fm if np.isfinite(fm) else np.nan})
    return pd.DataFrame(rows, columns=list(TABLE_COLUMNS))


def _first(first: xr.Dataset | None, mode: str, ls: str, tan_alpha: float,
           R: float) -> tuple[float, float, str]:
    """(median, beta, status) of the first-exceedance fit at one cell, NaN if absent."""
    none = (float("nan"), float("nan"), "not computed")
    if first is None:
        return none
    try:
        cell = first.sel(mode=mode, limit_state=ls)
        cell = cell.isel(tan_alpha=int(np.flatnonzero(np.isclose(cell["tan_alpha"].values,
                                                                  tan_alpha))[0]),
                         R=int(np.flatnonzero(np.isclose(cell["R"].values, R))[0]))
    except (KeyError, IndexError):
        return none
    return float(cell["median"]), float(cell["beta"]), str(cell["status"].values)


__all__ = ["STRIPES_DIMS", "STRIPES_TASK_DIMS", "TABLE_COLUMNS", "compute",
           "fill_stripes_region", "prepare_store", "stripe_fits", "stripe_table",
           "stripes_layout"]
