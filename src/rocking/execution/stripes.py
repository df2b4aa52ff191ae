"""Multiple-stripe runs of a study: a chunked zarr store, its fragility table.

``results/<study>/stripes.zarr`` holds, for every (mode, motion, R, stripe intensity), whether
the analysis exceeded each limit state (``exceeded`` over mode, limit_state, motion, R,
intensity) and whether it failed. It is made, filled on Dask and resumed exactly like the
spectra store (:mod:`rocking.store`, :mod:`rocking.execution.cluster`): a task is one mode,
one motion and ``chunk_R`` sizes, and runs :func:`rocking.fragility.stripes.stripe_outcomes`.
:func:`stripe_table` fits the lognormal of :mod:`rocking.fragility.stripes` per (mode, limit
state, R) and sets it beside the first-exceedance fragility of the spectra
(:func:`rocking.fragility.lognormal.fragility_table`).
"""

from __future__ import annotations

import json
import logging
import os
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from rocking import __version__, store
from rocking.config.damping import Damping
from rocking.config.products import StripesSpec
from rocking.execution import tasks
from rocking.fragility.stripes import MEASURE_COLUMNS, measure_scale
from rocking.spectra.accuracy import get_accuracy
from rocking.store.attrs import decode_attrs
from rocking.store.layout import Layout, Variable, label_coord, region_coords, value_coord

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


def create_stripes_store(path: Path, s: StripesSpec, config_digest: str,
                         motions: str | Path) -> None:
    """Create the empty stripes store of a study at ``path`` (the stripes'
    :attr:`~rocking.execution.products.Product.create`; as
    :func:`rocking.execution.prepare.create_spectra_store`)."""
    from rocking.spectra.limit_states import parse_limit_states

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
    if s.measure == "pga" and s.component == "vector_peak":
        extra = {"pga_g": ("intensity", [i * float(s.tan_alpha) for i in s.intensity])}
    else:  # every motion scaled so that its measure equals the stripe's
        scale = measure_scale(s.measure, s.tan_alpha)
        attrs["measure"] = s.measure
        attrs["component"] = s.component
        attrs["intensity_definition"] = (
            f"{s.measure}/(g tan alpha) ({measure_label(s.measure)}, {s.component} of the "
            "pair): each motion scaled so that its measure equals the stripe's")
        extra = {"im": ("intensity", [i * scale for i in s.intensity])}
    store.create_store(path, layout, attrs, config_digest,
                       coords={**tasks.identity_coords(ensemble), **extra})
    log.info("created %s: %d chunks, %d motions x %d stripes", path, layout.n_regions,
             len(names), len(s.intensity))


def fill_stripes_region(path: str | Path, index: int, motions: tasks.MotionSource,
                        ) -> dict[str, float]:
    """Analyse one motion at every stripe for the sizes R of region ``index``; write them.

    Returns ``index``, ``points`` (analyses asked for) and compute ``seconds``.
    """
    from rocking.dynamics.bodies import Cylinder
    from rocking.fragility.stripes import stripe_outcomes
    from rocking.spectra.limit_states import parse_limit_states

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
                                  acc, **attrs.get("model_options", {}),
                                  measure=store_measure(attrs),
                                  component=store_component(attrs))
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


def store_measure(attrs) -> str:
    """The intensity measure of a stripes store's stripes (``"pga"`` for a store without
    one: those made before stripes had a measure)."""
    return str(attrs.get("measure", "pga"))


def store_component(attrs) -> str:
    """The horizontal component of a stripes store's measure (``"vector_peak"`` for a store
    without one: the spectra's PGA, and stores made before components)."""
    return str(attrs.get("component", "vector_peak"))


def measure_label(measure: str) -> str:
    """``"PGA"``, ``"PGV"``, ``"Sa(1 s)"``: the measure as an axis names it."""
    from rocking.motions.measures import parse_measure

    kind, period = parse_measure(measure)
    return f"Sa({period:g} s)" if kind == "sa" else kind.upper()


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
                measure=store_measure(ds.attrs), component=store_component(ds.attrs))
    return out


def refine_cache_path(store_path: str | Path) -> Path:
    """Where the analyses of refined stripes of a store are kept:
    ``stripes-<digest>.refined.jsonl`` beside ``stripes-<digest>.zarr`` (the digest names
    the configuration, so a new one starts a new file)."""
    p = Path(store_path)
    return p.with_name(f"{p.stem}.refined.jsonl")


class RefineCache:
    """Analyses of refined stripes, one JSON line each, appended (and flushed) as each is
    done: a refinement killed part way resumes without redoing any, and reads them back
    exactly (JSON keeps every float).

    Keys are (mode, R [m], motion, stripe [measure/(g tan α)]); values (exceeded per limit
    state, failed, analyses run). Its record (:mod:`rocking.provenance`) names the store the
    analyses belong to (its identity: config hash and motions' sha256) and holds the sha256
    of the lines written so far, renewed after each line: a line written after the last
    record (a kill between the two) is dropped; a file of another store or motions (copied
    from another study), changed or cut short since, is started anew where the analyses can
    be redone (``rebuild``), else refused in one line naming the file
    (:class:`rocking.provenance.ProvenanceError`).
    """

    def __init__(self, path: str | Path | None, store_path: str | Path | None,
                 attrs: dict, *, rebuild: bool = False):
        import hashlib

        from rocking import provenance

        self.path = None if path is None else Path(path)
        identity = provenance.store_identity(attrs)
        self.made_from = {str(store_path): identity} if store_path else {}
        self._data: dict[tuple, tuple] = {}
        self._sha = hashlib.sha256()
        if self.path is None or not self.path.exists():
            return
        why = provenance.problem(self.path, expect=[identity], partial=True, prefix=True)
        if why is not None:
            if not rebuild:
                raise provenance.ProvenanceError(f"{self.path}: {why}: "
                                                 f"{provenance.remake(self.path)}")
            log.warning("%s: %s: started anew (its analyses are redone)", self.path, why)
            provenance.forget(self.path)
            return
        size = provenance.read_record(self.path)["size"]
        raw = self.path.read_bytes()
        if len(raw) > size:  # killed between a line and its record: the line is redone
            raw = raw[:size]
            self.path.write_bytes(raw)
        self._sha.update(raw)
        for line in raw.splitlines():
            d = json.loads(line)
            self._data[(d["mode"], d["R"], d["motion"], d["x"])] = (
                tuple(d["exceeded"]), d["failed"], d["runs"])

    def __len__(self) -> int:
        return len(self._data)

    def get(self, key: tuple) -> tuple | None:
        return self._data.get(key)

    def put(self, key: tuple, value: tuple) -> None:
        from rocking import provenance

        self._data[key] = value
        if self.path is None:
            return
        line = _line(key, value)
        with open(self.path, "a") as fh:
            fh.write(line)
            fh.flush()
            os.fsync(fh.fileno())
        self._sha.update(line.encode())
        provenance.record(self.path, inputs=self.made_from, sha256=self._sha.hexdigest())

    def copy_to(self, path: str | Path) -> Path:
        """The analyses as a file of their own, written whole under a temporary name, with
        its record: what a figure replays the refinement from."""
        from rocking import provenance

        # in key order: the same analyses give the same file, however a killed run resumed
        body = "".join(_line(k, v) for k, v in sorted(self._data.items()))
        provenance.write_atomic(path, lambda tmp: Path(tmp).write_text(body))
        provenance.record(path, inputs=self.made_from)
        return Path(path)


def _line(key: tuple, value: tuple) -> str:
    """One line of a :class:`RefineCache` file."""
    mode, R, motion, x = key
    return json.dumps({"mode": mode, "R": R, "motion": motion, "x": x,
                       "exceeded": [bool(v) for v in value[0]], "failed": bool(value[1]),
                       "runs": int(value[2])}, sort_keys=True) + "\n"


def _cached_analyzer(result, ds: xr.Dataset, cache: RefineCache, motions):
    """``analyze(x)`` of :func:`rocking.fragility.stripes.refine_stripes` for one (mode, R) of
    a store: each motion from ``cache`` or, if absent there, analysed (``motions``: the
    ensemble file) and added to it."""
    from rocking.dynamics.bodies import Cylinder
    from rocking.fragility.stripes import stripe_outcomes
    from rocking.spectra.limit_states import parse_limit_states

    states = parse_limit_states(list(result.limit_states), sort=False)
    body = Cylinder(float(result.R), float(result.tan_alpha))
    attrs = decode_attrs(ds.attrs)
    acc = get_accuracy(attrs["tolerances"])
    options = attrs.get("model_options", {})

    def analyze(x: float):
        exc = np.zeros((len(result.motions), len(states)), dtype=bool)
        fail = np.zeros(len(result.motions), dtype=bool)
        runs = 0
        for m, name in enumerate(result.motions):
            key = (result.mode, float(result.R), name, float(x))
            hit = cache.get(key)
            if hit is None:
                if motions is None:
                    raise ValueError(f"the refined stripe {x!r} of {result.mode}, R = "
                                     f"{result.R:g} m, motion {name!r} is not in "
                                     f"{cache.path}: run the stripe_fragility step first")
                e, f, r = stripe_outcomes(body, tasks.motion_named(motions, name), states,
                                          np.array([float(x)]), result.mode, acc, **options,
                                          measure=result.measure,
                                          component=result.component)
                hit = (tuple(bool(v) for v in e[0]), bool(f[0]), int(r))
                cache.put(key, hit)
            exc[m], fail[m], runs = hit[0], hit[1], runs + hit[2]
        return exc, fail, runs

    return analyze


def stripe_rows(ds: xr.Dataset, *, refine: int = 0, cache: str | Path | None = None,
                motions: tasks.MotionSource | None = None) -> dict[tuple[str, str, float], Any]:
    """The fit of every (mode, limit state, R) of a stripes store, refined where separated.

    Parameters
    ----------
    ds : xarray.Dataset
        A complete stripes store.
    refine : int
        Most stripes added per row (:func:`rocking.fragility.stripes.refine_stripes`); 0: none.
    cache : path, optional
        The :class:`RefineCache` file (:func:`refine_cache_path`): analyses found there are
        not redone, new ones are added; a file of another store or motions, or changed since
        it was written, is started anew (with ``motions``) or refused.
    motions : path, optional
        The ensemble file, to analyse refined stripes not in ``cache`` (None: every one must
        be there, as when a figure replays the refinement).

    Returns
    -------
    dict
        (mode, limit state, R) → :class:`rocking.fragility.stripes.StripeFragility` of that
        limit state, ``n_refined`` stripes added.
    """
    from rocking.fragility.stripes import refine_stripes

    # analyses of another store or motions are redone where they can be (motions given)
    store_cache = RefineCache(cache, ds.encoding.get("source"), ds.attrs,
                              rebuild=motions is not None)
    out = {}
    for (mode, R), r in stripe_fits(ds).items():
        analyze = None
        for j, ls in enumerate(r.limit_states):
            if refine > 0 and r.fits[ls].status == "separated":
                analyze = analyze or _cached_analyzer(r, ds, store_cache, motions)
                before = len(store_cache)
                row = refine_stripes(r, ls, analyze, refine, log=log.info)
                log.info("%s, %s, R = %g m: %s after %d stripe(s) added (%d analyses new, %d "
                         "from %s)", mode, ls, R, row.fits[ls].status, row.n_refined,
                         len(store_cache) - before,
                         row.n_refined * len(r.motions) - (len(store_cache) - before),
                         store_cache.path)
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
                         component=result.component)


TABLE_COLUMNS = ("mode", "limit_state", "tan_alpha", "R", "median", "median_lo", "median_hi",
                 "median_pga_g", "beta", "beta_lo", "beta_hi", "status", "reason", "n_motions",
                 "stripes", "first_median", "first_beta", "first_status", "ratio", "measure",
                 "component", "median_im", "median_p05", "median_p95", "bracket_lo", "bracket_hi",
                 "n_refined", "boot_defined")
"""Columns of ``stripe_fragility.csv`` (before units are added to the titles). ``median``
and its Wald interval are in measure/(g tan α); ``median_im``, ``median_p05``,
``median_p95`` (the bootstrap's 90 % interval), ``bracket_lo``, ``bracket_hi`` in the
measure's unit (:data:`MEASURE_COLUMNS`); ``median_pga_g`` [g] only for the measure PGA;
``stripes`` counts the stripes as asked, ``n_refined`` those added; ``boot_defined`` is the
share of resamples with a median."""



def table_headers(table: pd.DataFrame) -> dict[str, str]:
    """CSV titles of a stripe table: :func:`rocking.units.header`, and the unit of the
    table's measure for :data:`MEASURE_COLUMNS`."""
    from rocking.motions.measures import MEASURE_UNITS, parse_measure
    from rocking.units import header

    measures = set(table["measure"]) if len(table) else {"pga"}
    units = {MEASURE_UNITS[parse_measure(m)[0]] for m in measures}
    unit = units.pop() if len(units) == 1 else "measure unit"
    return {c: f"{c} [{unit}]" if c in MEASURE_COLUMNS else
            ("n_refined" if c == "n_refined" else header(c)) for c in table.columns}


def stripe_table(ds: xr.Dataset, first: xr.Dataset | None = None, *,
                 rows: dict | None = None, boot: dict | None = None) -> pd.DataFrame:
    """One row per (mode, limit_state, R): the stripe fit and the first-exceedance fit.

    Parameters
    ----------
    ds : xarray.Dataset
        A stripes store.
    first : xarray.Dataset, optional
        :func:`rocking.fragility.lognormal.fragility_table` of the same study: its ``median``,
        ``beta`` and ``status`` at the same (mode, limit_state, tan α, R) become
        ``first_median``, ``first_beta``, ``first_status``, and ``ratio`` = stripe median /
        first-exceedance median (NaN where the spectra have no such cell, or the stripes
        are in another measure than PGA).
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
        rows = stripe_rows(ds)
    base = {(m, R): r.intensities.size for (m, R), r in stripe_fits(ds).items()}
    out = []
    for (mode, ls, R), r in rows.items():
        (rec,) = r.summary_frame().to_dict(orient="records")
        fm, fb, fs = (_first(first, mode, ls, r.tan_alpha, R)
                      if r.measure == "pga" and r.component == "vector_peak"
                      else (np.nan, np.nan, f"not comparable ({r.measure} {r.component}, "
                            "not the vector-peak pga)"))
        p05 = p95 = defined = np.nan
        if boot is not None and (mode, ls, R) in boot:
            med = boot[(mode, ls, R)]["median"]
            p05, p95 = (v * r.scale for v in bootstrap_interval(med))
            defined = float(np.mean(~np.isnan(med)))
        out.append({"mode": mode, "tan_alpha": r.tan_alpha, "R": R, **rec,
                    "n_motions": int(r.n_motions.min()), "stripes": int(base[(mode, R)]),
                    "first_median": fm, "first_beta": fb, "first_status": fs,
                    "ratio": rec["median"] / fm if np.isfinite(fm) else np.nan,
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
    from rocking.motions.measures import MEASURE_UNITS, parse_measure

    keys = list(zip(table["mode"], table["limit_state"], table["R"], strict=True))
    median = np.stack([boot[k]["median"] * rows[k].scale for k in keys]) if keys \
        else np.zeros((0, 0))
    beta = np.stack([boot[k]["beta"] for k in keys]) if keys else np.zeros((0, 0))
    status = np.stack([boot[k]["status"] for k in keys]) if keys else np.zeros((0, 0), np.int8)
    measure = str(table["measure"].iloc[0]) if keys else "pga"
    unit = MEASURE_UNITS[parse_measure(measure)[0]]
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


__all__ = ["MEASURE_COLUMNS", "STRIPES_DIMS", "STRIPES_TASK_DIMS", "TABLE_COLUMNS",
           "RefineCache", "bootstrap_dataset", "bootstrap_rows", "create_stripes_store",
           "fill_stripes_region", "measure_label", "refine_cache_path",
           "store_component", "store_measure", "stripe_fits", "stripe_rows", "stripe_table",
           "stripes_layout",
           "table_headers", "write_stripe_fragility"]


def write_stripe_fragility(store_path: str | Path, csv: str | Path, samples: str | Path, *,
                           fragility: str | Path | None = None,
                           motions: tasks.MotionSource | None = None, refine: int = 0,
                           resamples: int = 0, study: str = "",
                           refined: str | Path | None = None) -> pd.DataFrame:
    """``stripe_fragility.csv`` and ``stripe_fragility_bootstrap.nc`` of a stripes store.

    Refines separated rows (analyses kept in :func:`refine_cache_path`, so a killed run
    resumes), bootstraps every row over the motions, and writes both files (the samples'
    record says they belong to the table). ``refined``: the refined
    analyses are also written there, whole (what the figure replays). Returns the table
    (bare column names).
    """
    from rocking.provenance import write_atomic

    first = None
    if fragility is not None:
        with xr.open_dataset(fragility) as f:
            first = f.load()
    ds = xr.open_zarr(store_path, consolidated=True)
    t0 = time.perf_counter()
    cache = refine_cache_path(store_path)
    rows = stripe_rows(ds, refine=refine, cache=cache, motions=motions)
    log.info("fits of %d rows (%d refined, %d stripes added) in %.1f s", len(rows),
             sum(r.n_refined > 0 for r in rows.values()),
             sum(r.n_refined for r in rows.values()), time.perf_counter() - t0)
    boot = bootstrap_rows(rows, resamples) if resamples > 0 else None
    table = stripe_table(ds, first, rows=rows, boot=boot)
    write_atomic(csv, lambda tmp: table.rename(columns=table_headers(table)).to_csv(
        tmp, index=False, float_format="%.10g"))
    empty = {k: {"median": np.zeros(0), "beta": np.zeros(0), "status": np.zeros(0, np.int8)}
             for k in rows}
    from rocking.fragility.bootstrap import write_bootstrap

    write_bootstrap(bootstrap_dataset(table, rows, boot if boot is not None else empty,
                                      study=study), samples, table=csv)
    if refined is not None:
        RefineCache(cache, store_path, ds.attrs).copy_to(refined)
    return table
