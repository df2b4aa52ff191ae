"""Multiple-stripe runs of a study: a chunked zarr store, filled, and its fragility table
written.

``results/<study>/stripes.zarr`` holds, for every (mode, motion, R, stripe intensity), whether
the analysis exceeded each limit state (``exceeded`` over mode, limit_state, motion, R,
intensity) and whether it failed. It is made, filled on Dask and resumed exactly like the
spectra store (:mod:`rocking.store`, :mod:`rocking.execution.cluster`): a task is one mode,
one motion and ``chunk_R`` sizes, and runs :func:`rocking.fragility.stripes.stripe_outcomes`.
The fits are :mod:`rocking.fragility.stripe_table`'s; this module keeps the analyses of the
stripes refinement adds (:class:`RefineCache`, so a killed job resumes) and writes the tables
(:func:`write_stripe_fragility`).
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
from rocking.dynamics.contact import Contact
from rocking.execution import tasks
from rocking.fragility.stripe_table import (
    STRIPES_DIMS,
    STRIPES_TASK_DIMS,
    bootstrap_dataset,
    bootstrap_rows,
    store_component,
    store_jitter,
    store_measure,
    stripe_table,
    table_headers,
)
from rocking.motions.measures import VECTOR_PEAK, Measure
from rocking.spectra.accuracy import Accuracy
from rocking.store.attrs import decode_attrs
from rocking.store.layout import Layout, Variable, label_coord, region_coords, value_coord

log = logging.getLogger(__name__)



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
        "tolerances": s.accuracy.to_dict(),
        "model_options": Damping.options(s.damping),
        "rocking_version": __version__,
        "ensemble": ensemble,
        "intensity_definition": "PGA/(g tan alpha), PGA = max sqrt(ax^2 + ay^2) of the pair",
        # each analysis at its stripe times exp(u), u uniform in [-jitter, jitter] drawn
        # from its identity (rocking.fragility.stripes.jittered)
        "jitter": float(s.jitter),
    }
    if s.measure == "pga" and s.component == VECTOR_PEAK:
        extra = {"pga_g": ("intensity", [i * float(s.tan_alpha) for i in s.intensity])}
    else:  # every motion scaled so that its measure equals the stripe's
        scale = Measure.of(s.measure).per_normalized(s.tan_alpha)
        attrs["measure"] = s.measure
        attrs["component"] = s.component
        attrs["intensity_definition"] = (
            f"{s.measure}/(g tan alpha) ({Measure.of(s.measure).label}, {s.component} of the "
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
    acc = Accuracy.of(attrs["tolerances"])
    contact = Contact.of(**attrs.get("model_options", {}))  # the store's, read once
    tan_alpha = float(attrs["tan_alpha"])
    exc, fail, runs = [], [], []
    for R in rc["R"]:
        e, f, n = stripe_outcomes(Cylinder(float(R), tan_alpha), motion, states, x, str(mode),
                                  acc, contact=contact, measure=store_measure(attrs),
                                  component=store_component(attrs),
                                  jitter=store_jitter(attrs))
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
    acc = Accuracy.of(attrs["tolerances"])
    contact = Contact.of(**attrs.get("model_options", {}))

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
                                          np.array([float(x)]), result.mode, acc,
                                          contact=contact,
                                          measure=result.measure,
                                          component=result.component,
                                          jitter=result.jitter)
                hit = (tuple(bool(v) for v in e[0]), bool(f[0]), int(r))
                cache.put(key, hit)
            exc[m], fail[m], runs = hit[0], hit[1], runs + hit[2]
        return exc, fail, runs

    return analyze


def stripe_rows(ds: xr.Dataset, *, refine: int = 0, cache: str | Path | None = None,
                motions: tasks.MotionSource | None = None) -> dict[tuple[str, str, float], Any]:
    """The fit of every (mode, limit state, R) of a stripes store, refined where separated
    (:func:`rocking.fragility.stripe_table.refined_rows`), the refined stripes' analyses
    kept in a :class:`RefineCache`.

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
    from rocking.fragility.stripe_table import refined_rows, stripe_fits

    # analyses of another store or motions are redone where they can be (motions given)
    store_cache = RefineCache(cache, ds.encoding.get("source"), ds.attrs,
                              rebuild=motions is not None)
    return refined_rows(stripe_fits(ds), refine,
                        lambda r: _cached_analyzer(r, ds, store_cache, motions),
                        where=str(store_cache.path))


__all__ = ["STRIPES_DIMS", "STRIPES_TASK_DIMS",
           "RefineCache", "create_stripes_store", "fill_stripes_region", "refine_cache_path",
           "stripe_rows", "stripes_layout", "write_stripe_fragility"]


def write_stripe_fragility(store_path: str | Path, csv: str | Path, samples: str | Path, *,
                           fragility: str | Path | None = None,
                           motions: tasks.MotionSource | None = None, refine: int = 0,
                           resamples: int = 0, study: str = "",
                           refined: str | Path | None = None,
                           exceedance: str | Path | None = None) -> pd.DataFrame:
    """``stripe_fragility.csv`` and ``stripe_fragility_bootstrap.nc`` of a stripes store.

    Refines separated rows (analyses kept in :func:`refine_cache_path`, so a killed run
    resumes), bootstraps every row over the motions, and writes both files (the table with
    its estimator, measure, component, unit and jitter, :func:`rocking.fragility.table.
    write_fragilities`; the samples' record says they belong to the table).
    ``refined``: the refined analyses are also written there, whole (what the figure
    replays). ``exceedance``: the ensemble's exceedance probability at every stripe with its
    bootstrap interval over the motions (:func:`rocking.fragility.stripes.exceedance_table`,
    ``stripe_exceedance.csv``). Returns the table (bare column names).
    """
    from rocking.fragility.stripes import exceedance_table
    from rocking.fragility.table import STRIPES, write_fragilities
    from rocking.provenance import write_atomic

    critical = None
    if fragility is not None:
        with xr.open_dataset(fragility) as f:
            critical = f.load()
    ds = xr.open_zarr(store_path, consolidated=True)
    t0 = time.perf_counter()
    cache = refine_cache_path(store_path)
    rows = stripe_rows(ds, refine=refine, cache=cache, motions=motions)
    log.info("fits of %d rows (%d refined, %d stripes added) in %.1f s", len(rows),
             sum(r.n_refined > 0 for r in rows.values()),
             sum(r.n_refined for r in rows.values()), time.perf_counter() - t0)
    boot = bootstrap_rows(rows, resamples) if resamples > 0 else None
    table = stripe_table(ds, critical, rows=rows, boot=boot)
    jitter = store_jitter(ds.attrs)
    quantity = {"quantity": "mean_local_exceedance" if jitter else "fixed_stripes",
                "p": float("nan"), "w": jitter}
    write_fragilities(table.rename(columns=table_headers(table)), csv, estimator=STRIPES,
                      measure=store_measure(ds.attrs), component=store_component(ds.attrs),
                      quantity=quantity)
    if exceedance is not None:
        shares = pd.concat([exceedance_table(r, max(resamples, 1)).assign(
            mode=mode, tan_alpha=r.tan_alpha, R=R) for (mode, _, R), r in rows.items()],
            ignore_index=True)
        front = ["mode", "tan_alpha", "R"]
        shares = shares[front + [c for c in shares.columns if c not in front]]
        write_atomic(exceedance, lambda tmp: shares.to_csv(tmp, index=False,
                                                           float_format="%.10g"))
    empty = {k: {"median": np.zeros(0), "beta": np.zeros(0), "status": np.zeros(0, np.int8)}
             for k in rows}
    from rocking.fragility.bootstrap import write_bootstrap

    write_bootstrap(bootstrap_dataset(table, rows, boot if boot is not None else empty,
                                      study=study), samples, table=csv)
    if refined is not None:
        RefineCache(cache, store_path, ds.attrs).copy_to(refined)
    return table
