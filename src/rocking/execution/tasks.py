"""What the study's stores hold and how a worker fills one region of them.

- the layouts of the spectra store (mode, limit_state, motion, tan_alpha, R) and of the Fig 7
  tilt map (mode, R, intensity) (``docs/design.md``, "Study store");
- the provenance a store records about its ensemble (file hash, each motion's identity);
- the cost model that sizes and orders tasks (:func:`auto_chunk_R`, :data:`MODE_COST`);
- the task bodies run in Dask workers: compute one region with the physics, write it with
  :func:`rocking.store.write_region`, report the time it took.
"""

from __future__ import annotations

import copy
import math
import time
from collections.abc import Callable, Sequence
from functools import lru_cache
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from rocking.motions.ensemble_io import verify_digest
from rocking.motions.motion import GroundMotion
from rocking.spectra.modes import (
    MODE_2D_X,
    MODE_2D_Y,
    MODE_3D,
    MODE_3D_DAMPED,
    MODE_3D_X,
    MODE_3D_Y,
)
from rocking.store import (
    REQUESTED,
    REQUESTED_DIMS,
    StoreHandle,
    open_layout,
    read_attrs,
    read_requested,
    write_region,
)
from rocking.store.layout import Layout, Variable, label_coord, region_coords, value_coord

SPECTRA_DIMS = ("mode", "limit_state", "motion", "tan_alpha", "R")
"""Dimensions of the spectra variables, in storage order."""

SPECTRA_TASK_DIMS = ("mode", "motion", "tan_alpha", "R")
"""Dimensions the spectra grid is cut along; each task holds all limit states of its points."""

TILT_MAP_DIMS = ("mode", "R", "intensity")
"""Dimensions of the Fig 7 map ``theta_max_over_alpha``."""

TILT_MAP_TASK_DIMS = ("mode", "R")
"""A tilt-map task computes every intensity of a few sizes R for one mode."""


def spectra_layout(modes: Sequence[str], limit_states: Sequence[str], motions: Sequence[str],
                   tan_alpha: Sequence[float], R: Sequence[float], chunk_R: int) -> Layout:
    """Layout of a performance-spectra store (``docs/design.md``, "Study store").

    Each cell holds the study's quantity (:class:`rocking.spectra.quantity.Quantity`, named
    in the store's ``quantity`` attribute): ``pga_crit`` its answer in PGA/(g tan α) (I_p by
    default, or the first exceedance on the scan grid), ``pga_crit_g`` the same PGA in g,
    ``i50`` the intensity where half the nearby intensities exceed (I_0.5; NaN where the
    search saw no such share), ``first_exceedance`` the smallest exceeding intensity the
    scan saw, whatever the quantity, and ``plateau`` where the local exceedance probability
    rises near p without crossing it (I_p ill-conditioned there). The validity flags of
    each answer: ``slides`` (float: 1/0, NaN where the study gave no ``mu`` or the cell was
    not requested) and ``lifts_off`` (bool).

    Besides the results it holds the static ``requested`` (mode, limit_state, tan_alpha):
    which cells the study's runs ask for (:mod:`rocking.config.plan`); cells not requested
    are never computed and keep the fill values (NaN, flags false).

    Parameters
    ----------
    modes, limit_states, motions : sequence of str
        Coordinate labels (limit states in their canonical spelling).
    tan_alpha : sequence of float
        Slenderness values [-].
    R : sequence of float
        Semi-diagonals [m].
    chunk_R : int
        Sizes R per task (a task is one mode, motion and tan α and ``chunk_R`` sizes).

    Returns
    -------
    Layout
    """
    coords = {
        "mode": label_coord("mode", modes),
        "limit_state": label_coord("limit_state", limit_states),
        "motion": label_coord("motion", motions),
        "tan_alpha": value_coord("tan_alpha", tan_alpha),
        "R": value_coord("R", R),
    }
    variables = {
        "pga_crit": Variable(SPECTRA_DIMS, "float64", np.nan),
        "pga_crit_g": Variable(SPECTRA_DIMS, "float64", np.nan),
        "i50": Variable(SPECTRA_DIMS, "float64", np.nan),
        "first_exceedance": Variable(SPECTRA_DIMS, "float64", np.nan),
        "plateau": Variable(SPECTRA_DIMS, "bool", False),
        "not_reached": Variable(SPECTRA_DIMS, "bool", False),
        "non_monotonic": Variable(SPECTRA_DIMS, "bool", False),
        "failed": Variable(SPECTRA_DIMS, "bool", False),
        "n_analyses": Variable(SPECTRA_DIMS, "int32", 0),
        "slides": Variable(SPECTRA_DIMS, "float64", np.nan),
        "lifts_off": Variable(SPECTRA_DIMS, "bool", False),
    }
    # fill True: a store made without a study plan computes every cell
    static = {REQUESTED: Variable(REQUESTED_DIMS, "bool", True)}
    return Layout(coords, variables, SPECTRA_TASK_DIMS, {"R": int(chunk_R)}, static)


def tilt_map_layout(modes: Sequence[str], R: Sequence[float], intensity: Sequence[float],
                    chunk_R: int) -> Layout:
    """Layout of the Fig 7 store: ``theta_max_over_alpha`` over (mode, R, intensity).

    Parameters
    ----------
    modes : sequence of str
        Analysis modes, e.g. ``["3d", "3d-damped"]``.
    R : sequence of float
        Semi-diagonals [m].
    intensity : sequence of float
        Normalized intensities PGA/(g tan α) [-].
    chunk_R : int
        Sizes R per task.
    """
    coords = {
        "mode": label_coord("mode", modes),
        "R": value_coord("R", R),
        "intensity": value_coord("intensity", intensity),
    }
    variables = {
        "theta_max_over_alpha": Variable(TILT_MAP_DIMS, "float64", np.nan),
        "overturned": Variable(TILT_MAP_DIMS, "bool", False),
        "failed": Variable(TILT_MAP_DIMS, "bool", False),
    }
    return Layout(coords, variables, TILT_MAP_TASK_DIMS, {"R": int(chunk_R)})


IDENTITY_COORDS = ("source_record", "processing", "PGA", "rotation_deg", "highpass_fc_hz",
                   "padding_s", "duration_s")
"""Per-motion fields of :func:`ensemble_attrs` stored as coordinates along ``motion``."""


def identity_coords(ensemble: dict[str, Any]) -> dict[str, tuple[str, list]]:
    """Coordinates along ``motion`` saying where each motion comes from (for create_store).

    Parameters
    ----------
    ensemble : dict
        :func:`ensemble_attrs` of the store's ensemble file.
    """
    rows = ensemble["motions"]
    return {k: ("motion", [math.nan if r.get(k) is None and k not in ("source_record",
                                                                        "processing")
                           else r.get(k, "") for r in rows])
            for k in IDENTITY_COORDS}


def ensemble_attrs(motions_path: str | Path, name: str) -> dict[str, Any]:
    """What a store records about its ensemble: file hash, motions, labels, stand-in flags."""
    motions = list(motions_by_name(motions_path).values())
    from rocking.motions.source import identity

    rows = []
    for m in motions:
        meta = m.metadata
        who = identity(m)
        rows.append({
            "name": m.name,
            "label": str(meta.get("label", meta.get("title", m.name))),
            "stand_in": bool(meta.get("stand_in", False)),
            "stand_in_for": meta.get("stand_in_for"),
            "dt": m.dt,
            "npts": m.npts,
            **{k: who[k] for k in IDENTITY_COORDS},
        })
    return {
        "name": name,
        "file": str(motions_path),
        "file_sha256": verify_digest(motions_path),
        "stand_in": any(r["stand_in"] for r in rows),
        "motions": rows,
    }


def check_ensemble(store: StoreHandle, motions_path: str | Path) -> None:
    """Refuse to fill a store from another ensemble file than the one it was made for.

    Raises
    ------
    MotionsDigestError
        The file differs from its own digest (damaged after it was made: rebuild it).
    ValueError
        Naming the file and both sha256 values, when the store was made from other motions.
    """
    # the file against its own digest first: a damaged file is rebuilt, not a store made of it
    found = verify_digest(motions_path)
    expected = store.attrs["ensemble"]["file_sha256"]
    if found != expected:
        raise ValueError(f"ensemble file {str(motions_path)!r} has sha256 {found} but store "
                         f"{str(store.path)!r} was made from sha256 {expected}: the motions "
                         f"were made anew with other numbers; delete the store, its rule makes "
                         f"it anew from these motions")


SECONDS_PER_SAMPLE = 0.4e-6
"""Lower estimate of the cost of one analysis per record sample [s]: the cheapest mode (2D,
"fast" preset) on El Centro took 0.46 µs per sample on a 2-core development machine
(``python -m benchmarks workflow`` measures the costs). Only sizes tasks for
``chunk_R: auto``; the other modes cost more, so tasks are at least this long."""

ANALYSES_PER_POINT = 10
"""Lower estimate of the analyses of one critical-intensity search (scan + bisection)."""


def auto_chunk_R(n_R: int, npts: int, min_task_seconds: float) -> int:
    """Sizes R per task so that a task holds at least ``min_task_seconds`` of work.

    Parameters
    ----------
    n_R : int
        Sizes R in the grid.
    npts : int
        Samples of the shortest motion (the cheapest searches).
    min_task_seconds : float
        Least work per task [s] (Dask's per-task overhead is ~1 ms; ≥ 0.1 s keeps it < 1 %).

    Returns
    -------
    int
        In [1, n_R].
    """
    point = ANALYSES_PER_POINT * npts * SECONDS_PER_SAMPLE
    return int(min(n_R, max(1, math.ceil(min_task_seconds / point))))


MODE_COST = {MODE_3D_DAMPED: 4.0, MODE_3D: 1.5, MODE_3D_X: 2.0, MODE_3D_Y: 1.5, MODE_2D_X: 1.0,
             MODE_2D_Y: 1.0}
"""Relative cost of a search per mode, measured on the paper run (``python -m
benchmarks paper_cost``, docs/performance.md): CPU per El Centro spectrum point
3d-damped 1.2 s, 3d 0.4 s, 2D 0.3 s (more analyses of 1.8 ms against 5–8 ms); the 3D model
under one component runs analyses of the 3D model's cost, 1.09–1.49 times as many under x and
0.97 times under y (El Centro and Loma Prieta, tan α 0.2, 20 R, 11 motions). Every mode of
:data:`rocking.spectra.modes.MODES` has an entry (``tests/test_design_registries.py``); a
region of another mode is an error (:func:`mode_cost`), not a silent guess."""


def mode_cost(mode: str) -> float:
    """The relative cost of a search in ``mode`` [-] (:data:`MODE_COST`).

    Raises
    ------
    KeyError
        For a mode without an entry, naming it and where to add it.
    """
    try:
        return MODE_COST[str(mode)]
    except KeyError:
        raise KeyError(f"mode {mode!r} has no cost in rocking.execution.tasks.MODE_COST: add it "
                       f"(docs/design.md, 'Adding a model')") from None


def costliest_first(layout: Layout, indices: Sequence[int]) -> list[int]:
    """Regions ordered by a rough cost estimate, largest first.

    Long tasks started last would leave the other workers idle at the end of a run; running
    them first (largest-processing-time-first scheduling) evens out the finish. The estimate
    is the mode's :data:`MODE_COST` times the sum of the sizes R (larger bodies need more
    analyses to tip). A layout without a mode dimension costs every region 1 per mode, one
    without R 1 per size: such layouts keep their order.
    """

    def cost(i: int) -> float:
        rc = region_coords(layout, i)
        per_mode = mode_cost(rc["mode"][0]) if "mode" in rc else 1.0
        return per_mode * float(np.sum(rc.get("R", [1.0])))

    return sorted(indices, key=lambda i: (-cost(i), i))


# --------------------------------------------------------------------------------------------
# Motions as seen by a worker process
# --------------------------------------------------------------------------------------------

MotionSource = str | Path | Sequence[GroundMotion]
"""An ensemble file (``rocking.motions.ensemble_io`` format) or the motions themselves."""


def motions_by_name(source: MotionSource) -> dict[str, GroundMotion]:
    """Motions of ``source`` keyed by name (files are read once per worker process)."""
    if isinstance(source, (str, Path)):
        p = Path(source)
        st = p.stat()
        return _load_ensemble_cached(str(p.resolve()), st.st_mtime_ns, st.st_size)
    return {m.name: m for m in source}


@lru_cache(maxsize=4)
def _load_ensemble_cached(path: str, mtime_ns: int, size: int) -> dict[str, GroundMotion]:
    # mtime and size are part of the key: a rewritten file is read again
    from rocking.motions.ensemble_io import load_ensemble

    return {m.name: m for m in load_ensemble(path)}


# --------------------------------------------------------------------------------------------
# Task bodies (run in Dask workers): compute one region, write it, report timing
# --------------------------------------------------------------------------------------------

def store_metadata(path: str | Path) -> tuple[Layout, dict[str, Any], np.ndarray]:
    """Layout, attributes and ``requested`` mask of a store, read once per worker process.

    A worker fills many regions of one store, and rereading its metadata cost 35 ms per
    region (of 83 ms of store work; docs/performance.md). The key includes the modification
    time and size of the store's root metadata, which a new store at the same path rewrites,
    so a worker of a long-lived cluster never sees an old store's layout.
    """
    p = Path(path)
    st = (p / "zarr.json").stat()
    layout, attrs, requested = _store_metadata(str(p.resolve()), st.st_mtime_ns, st.st_size)
    return layout, copy.deepcopy(attrs), requested


@lru_cache(maxsize=8)
def _store_metadata(path: str, mtime_ns: int, size: int):
    layout = open_layout(path)
    requested = read_requested(path, layout) if REQUESTED in layout.static else None
    if requested is not None:
        requested.setflags(write=False)
    return layout, read_attrs(path), requested


BatchFunction = Callable[..., list]
"""``critical_intensity_batch(tasks, limit_states, accuracy=..., upper=..., omega_n=...,
zeta=...) -> list[CriticalResult]`` with a task ``(R, tan_alpha, motion, mode)``."""


def fill_spectra_region(path: str | Path, index: int, motions: MotionSource, *,
                        batch: BatchFunction | None = None) -> dict[str, float]:
    """Compute and store the critical intensities of one region of a spectra store.

    The region is one mode, one motion, one tan α and a run of sizes R; every limit state
    of the store is found in the same search. Tolerances, quantity and search options come
    from the store's ``tolerances``, ``quantity`` and ``search_options`` attributes, so a
    worker needs nothing else.

    Parameters
    ----------
    path : str or Path
        Spectra store.
    index : int
        Region index (see :meth:`Layout.region`).
    motions : str, Path or sequence of GroundMotion
        The ensemble the store was built for.
    batch : callable, optional
        Default :func:`rocking.spectra.critical.critical_intensity_batch`; tests inject
        stand-ins with the same signature.

    Returns
    -------
    dict
        ``index``, ``points`` and compute ``seconds`` of the region.
    """
    t0 = time.perf_counter()
    if batch is None:
        from rocking.spectra.critical import critical_intensity_batch as batch
    layout, attrs, requested = store_metadata(path)
    rc = region_coords(layout, index)
    (mode,), (name,), (tan_alpha,) = rc["mode"], rc["motion"], rc["tan_alpha"]
    motion = motion_named(motions, name)
    limit_states = [str(s) for s in layout.coords["limit_state"]]
    region = layout.region(index)
    # (limit_state,): the cells of this region some run of the study asks for
    if requested is None:  # a store made without a study plan computes every cell
        requested = read_requested(path, layout)
    wanted = requested[region["mode"], :, region["tan_alpha"]][0, :, 0]
    computed = [ls for ls, w in zip(limit_states, wanted, strict=True) if w]
    tasks = [(float(R), float(tan_alpha), motion, str(mode)) for R in rc["R"]]
    if "quantity" not in attrs:  # never a silent default: the store says what it holds
        raise ValueError(f"store {str(path)!r} has no 'quantity' attribute: made by an older "
                         "version; delete it and run its rule again")
    results = batch(tasks, computed, accuracy=attrs["tolerances"],
                    quantity=attrs["quantity"], **attrs.get("search_options", {})) \
        if computed else []
    flat = spectra_values(results, limit_states, computed) if computed else \
        _unrequested_values(len(limit_states), len(tasks))
    flat["pga_crit_g"] = flat["pga_crit"] * float(tan_alpha)  # PGA [g] = I·tan α
    # (limit_state, R) -> (mode=1, limit_state, motion=1, tan_alpha=1, R)
    values = {k: v[None, :, None, None, :] for k, v in flat.items()}
    # NaN is an answer where the limit state was not reached, or where nobody asked
    nan_ok = values["not_reached"] | ~wanted[None, :, None, None, None]
    # slides says nothing (NaN) without the study's mu, or where nobody asked
    no_mu = attrs.get("search_options", {}).get("mu") is None
    nan_slides = ~wanted[None, :, None, None, None] | no_mu
    # I_0.5 is NaN where the analysed intensities never made half of a window exceed
    write_region(path, layout, index, values,
                 nan_allowed={"pga_crit": nan_ok, "pga_crit_g": nan_ok, "slides": nan_slides,
                              "first_exceedance": nan_ok, "i50": np.ones_like(nan_ok)})
    return {"index": index, "points": len(tasks), "seconds": time.perf_counter() - t0}


def motion_named(source: MotionSource, name: str) -> GroundMotion:
    by_name = motions_by_name(source)
    if name not in by_name:
        raise ValueError(f"motion {name!r} of the store is not in the ensemble "
                         f"{sorted(by_name)}")
    return by_name[name]


def _unrequested_values(n_ls: int, n: int) -> dict[str, np.ndarray]:
    """Arrays (limit_state, point) of cells not computed: NaN and every flag false."""
    return {
        "pga_crit": np.full((n_ls, n), np.nan),
        "i50": np.full((n_ls, n), np.nan),
        "first_exceedance": np.full((n_ls, n), np.nan),
        "plateau": np.zeros((n_ls, n), dtype=bool),
        "not_reached": np.zeros((n_ls, n), dtype=bool),
        "non_monotonic": np.zeros((n_ls, n), dtype=bool),
        "failed": np.zeros((n_ls, n), dtype=bool),
        "n_analyses": np.zeros((n_ls, n), dtype=np.int32),
        "slides": np.full((n_ls, n), np.nan),
        "lifts_off": np.zeros((n_ls, n), dtype=bool),
    }


def spectra_values(results: Sequence[Any], limit_states: Sequence[str],
                   computed: Sequence[str] | None = None) -> dict[str, np.ndarray]:
    """Arrays (limit_state, point) of a batch of critical-intensity results.

    Parameters
    ----------
    results : sequence of CriticalResult
        One per point, as returned by :func:`rocking.spectra.critical.critical_intensity_batch`:
        ``limit_states`` (names), arrays ``intensity`` (the quantity's answer, PGA/(g tan α)
        [-], NaN where not reached), ``i50``, ``first_exceedance``, ``plateau``,
        ``not_reached``, ``non_monotonic``, ``failed``, ``slides`` (NaN where none),
        ``lifts_off`` (false where none) and the count ``n_analyses``.
    limit_states : sequence of str
        Order of the first axis (canonical names, as in the store).
    computed : sequence of str, optional
        The limit states the results answer (default all); the others stay NaN with every
        flag false (not requested).

    Raises
    ------
    ValueError
        If a result lacks a limit state of ``computed``, or has a NaN intensity for a limit
        state it reports as reached.
    """
    n_ls, n = len(limit_states), len(results)
    out = _unrequested_values(n_ls, n)
    computed = set(limit_states if computed is None else computed)
    for j, res in enumerate(results):
        names = list(res.limit_states)
        for i, ls in enumerate(limit_states):
            if ls not in computed:
                continue
            if ls not in names:
                raise ValueError(f"result {j} has no limit state {ls!r} (has {names})")
            k = names.index(ls)
            out["pga_crit"][i, j] = res.intensity[k]
            out["i50"][i, j] = res.i50[k]
            out["first_exceedance"][i, j] = res.first_exceedance[k]
            out["plateau"][i, j] = res.plateau[k]
            out["not_reached"][i, j] = res.not_reached[k]
            out["non_monotonic"][i, j] = res.non_monotonic[k]
            out["failed"][i, j] = res.failed[k]
            slides, lifts_off = (getattr(res, f, None) for f in ("slides", "lifts_off"))
            out["slides"][i, j] = np.nan if slides is None else slides[k]
            out["lifts_off"][i, j] = False if lifts_off is None else lifts_off[k]
            out["n_analyses"][i, j] = res.n_analyses
    bad = np.isnan(out["pga_crit"]) & ~out["not_reached"]
    bad &= np.isin(np.asarray(limit_states, dtype=object), list(computed))[:, None]
    if bad.any():
        i, j = np.argwhere(bad)[0]
        raise ValueError(f"point {j}: intensity of {limit_states[i]!r} is NaN but the limit "
                         f"state is not flagged not_reached")
    return out


TiltMapFunction = Callable[..., xr.Dataset]
"""``tilt_map(R_values, tan_alpha, motion, intensities, mode, accuracy=..., omega_n=...,
zeta=...) -> Dataset`` with ``theta_max_over_alpha``, ``overturned``, ``failed`` (R, intensity)."""


def fill_tilt_map_region(path: str | Path, index: int, motions: MotionSource, *,
                         tilt_map: TiltMapFunction | None = None) -> dict[str, float]:
    """Compute and store θmax/α over all intensities for one mode and a run of sizes R.

    The motion, tan α, tolerances and model options come from the store's attributes
    (``motion``, ``tan_alpha``, ``tolerances``, ``model_options``).

    Parameters
    ----------
    path : str or Path
        Tilt-map store.
    index : int
        Region index.
    motions : str, Path or sequence of GroundMotion
        Ensemble holding the store's motion.
    tilt_map : callable, optional
        Default :func:`rocking.spectra.tilt_map.tilt_map`; tests inject stand-ins.

    Returns
    -------
    dict
        ``index``, ``points`` and compute ``seconds`` of the region.
    """
    t0 = time.perf_counter()
    if tilt_map is None:
        from rocking.spectra.tilt_map import tilt_map
    layout, attrs, _ = store_metadata(path)
    rc = region_coords(layout, index)
    (mode,) = rc["mode"]
    out = tilt_map([float(r) for r in rc["R"]], float(attrs["tan_alpha"]),
                   motion_named(motions, attrs["motion"]), [float(i) for i in rc["intensity"]],
                   str(mode), accuracy=attrs["tolerances"], **attrs.get("model_options", {}))
    values = {k: out[k].transpose("R", "intensity").values[None]
              for k in ("theta_max_over_alpha", "overturned", "failed")}
    write_region(path, layout, index, values,
                 nan_allowed={"theta_max_over_alpha": values["failed"]})
    return {"index": index, "points": int(values["failed"].size),
            "seconds": time.perf_counter() - t0}
