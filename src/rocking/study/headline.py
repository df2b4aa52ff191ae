"""The headline cells searched for their first exceedance on nested scan grids.

The paper's headline number (§5.4, Fig 12: a 10 m cylinder of tan α = 0.2 overturns under
bidirectional El Centro motions at PGA/(g tan α) "about 4") is a mean over motions of one
answer per motion. This project's answer is I10 (:class:`rocking.spectra.quantity.Quantity`),
which converges; the classic answer, the smallest exceeding intensity on a scan grid, does not:
below a motion's robust rise the body exceeds the goal in narrow windows that a finer grid
finds more of, so the mean first exceedance falls as the grid is refined. :func:`grid_answers`
searches the headline cells (every motion at that one size, slenderness, mode and limit
state) with ``Quantity("first_exceedance")`` on each grid of :data:`STEPS`, so that the report
can set the mean I10 beside the mean first exceedance of the same cells on a 1 %, 0.5 %,
0.2 % and 0.1 % grid: why "about 4" and 4.75 can both be found.

``headline.csv`` (:func:`write_headline`): one row per motion and grid step, with the
study's own answer (I10) of the cell beside it, the analyses and CPU seconds each search
took.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr

STEPS = (0.01, 0.005, 0.002, 0.001)
"""Relative steps of the scan grids of the headline's first exceedances [-]."""
MODE = "3d"
LIMIT_STATE = "overturning"
TAN_ALPHA = 0.2
R = 10.0
"""The paper's headline cell (§5.4): 3D overturning of a 10 m cylinder at tan α = 0.2."""
COLUMNS = ("motion", "mode", "limit_state", "tan_alpha", "R", "scan_step",
           "first_exceedance", "not_reached", "answer", "quantity", "analyses", "cpu_s")
"""Columns of ``headline.csv`` (intensities in PGA/(g tan α); ``answer`` is the study's own
answer of the cell, its quantity named beside it)."""


def headline_cells(ds: xr.Dataset) -> dict | None:
    """The headline cell of a spectra store, or None where the store has none: mode
    :data:`MODE`, limit state :data:`LIMIT_STATE`, tan α :data:`TAN_ALPHA`, and R
    :data:`R` or the largest size below it, if that cell was requested."""
    modes = [str(m) for m in ds["mode"].values]
    states = [str(s) for s in ds["limit_state"].values]
    ta = ds["tan_alpha"].values.astype(float)
    if MODE not in modes or LIMIT_STATE not in states or not np.isclose(ta, TAN_ALPHA).any():
        return None
    sizes = ds["R"].values.astype(float)
    if not (sizes <= R + 1e-9).any():
        return None
    size = float(sizes[sizes <= R + 1e-9].max())
    t = float(ta[np.isclose(ta, TAN_ALPHA)][0])
    if "requested" in ds and not bool(ds["requested"].sel(mode=MODE, limit_state=LIMIT_STATE,
                                                          tan_alpha=t)):
        return None
    return {"mode": MODE, "limit_state": LIMIT_STATE, "tan_alpha": t, "R": size}


def _search(args) -> dict:
    """One first-exceedance search of a headline cell on one grid (a process pool's task)."""
    motion, cell, step, tolerances, options = args
    from rocking.dynamics.bodies import Cylinder
    from rocking.spectra.critical import critical_intensity
    from rocking.spectra.quantity import FIRST_EXCEEDANCE, Quantity

    t0 = time.process_time()
    res = critical_intensity(Cylinder(cell["R"], cell["tan_alpha"]), motion,
                             [cell["limit_state"]], cell["mode"],
                             accuracy={**tolerances, "scan_step": step},
                             quantity=Quantity(FIRST_EXCEEDANCE), **options)
    return {"motion": motion.name, "scan_step": step,
            "first_exceedance": float(res.intensity[0]),
            "not_reached": bool(res.not_reached[0]), "analyses": int(res.n_analyses),
            "cpu_s": time.process_time() - t0}


def grid_answers(motions: Sequence, cell: Mapping, tolerances: Mapping,
                 options: Mapping | None = None, steps: Sequence[float] = STEPS,
                 processes: int = 1) -> pd.DataFrame:
    """The first exceedance of ``cell`` for every motion on every grid of ``steps``.

    Parameters
    ----------
    motions : sequence of GroundMotion
        The study's motions.
    cell : mapping
        ``mode``, ``limit_state``, ``tan_alpha``, ``R`` (:func:`headline_cells`).
    tolerances : mapping
        The store's accuracy (its ``tolerances`` attribute); only the scan step changes.
    options : mapping, optional
        The store's ``search_options`` (``upper``, the contact model, ``mu``).
    steps : sequence of float
        Relative scan steps [-].
    processes : int
        Worker processes (1: in this process).

    Returns
    -------
    DataFrame
        One row per motion and step: ``first_exceedance`` [PGA/(g tan α)] (NaN where not
        reached), ``not_reached``, ``analyses``, ``cpu_s`` (the search's process time).
    """
    tasks = [(m, dict(cell), float(s), dict(tolerances), dict(options or {}))
             for m in motions for s in steps]
    # the longest searches (finest grid) first, so that two processes finish together
    order = sorted(range(len(tasks)), key=lambda i: tasks[i][2])
    if processes > 1:
        with ProcessPoolExecutor(processes) as pool:
            done = dict(zip(order, pool.map(_search, [tasks[i] for i in order]), strict=True))
    else:
        done = {i: _search(tasks[i]) for i in order}
    rows = [done[i] for i in range(len(tasks))]
    return pd.DataFrame(rows).assign(**{k: cell[k] for k in ("mode", "limit_state",
                                                             "tan_alpha", "R")})


def write_headline(store_path: str | Path, motions_path: str | Path, csv: str | Path,
                   processes: int = 1) -> pd.DataFrame:
    """``headline.csv`` of a study: :func:`grid_answers` of its headline cell beside the
    store's own answer of each motion there (empty, with its columns, when the store has no
    headline cell); written under a temporary name and renamed."""
    from rocking.execution.tasks import motions_by_name
    from rocking.provenance import write_atomic
    from rocking.spectra.quantity import Quantity
    from rocking.store.attrs import decode_attrs
    from rocking.study.aggregate import store_quantity
    from rocking.units import CSV_FLOAT_FORMAT

    with xr.open_zarr(store_path, consolidated=True) as ds:
        ds = ds.load()
    attrs = decode_attrs(dict(ds.attrs))
    cell = headline_cells(ds)
    if cell is None:
        table = pd.DataFrame(columns=list(COLUMNS))
    else:
        names = [str(m) for m in ds["motion"].values]
        by_name = motions_by_name(motions_path)
        table = grid_answers([by_name[n] for n in names], cell, attrs["tolerances"],
                             attrs.get("search_options"), processes=processes)
        own = ds["pga_crit"].sel(mode=cell["mode"], limit_state=cell["limit_state"],
                                 tan_alpha=cell["tan_alpha"], R=cell["R"])
        table["answer"] = table["motion"].map(dict(zip(names, own.values.astype(float),
                                                       strict=True)))
        table["quantity"] = Quantity.from_value(store_quantity(ds.attrs)).label
        table = table[list(COLUMNS)]
    write_atomic(Path(csv), lambda tmp: table.to_csv(tmp, index=False,
                                                     float_format=CSV_FLOAT_FORMAT))
    return table


def summary(table: pd.DataFrame) -> dict | None:
    """The headline in numbers from ``headline.csv``: the mean of the study's answers with
    its standard error and count, and per grid step the mean first exceedance of the same
    cells (over the motions reached on every grid); None for an empty table."""
    if table is None or not len(table):
        return None
    per = table.pivot_table(index="motion", columns="scan_step", values="first_exceedance")
    answers = table.drop_duplicates("motion").set_index("motion")["answer"].astype(float)
    ok = answers.notna() & per.notna().all(axis=1).reindex(answers.index, fill_value=False)
    n = int(ok.sum())
    if n == 0:
        return None
    a = answers[ok].to_numpy()
    se = float(np.std(a, ddof=1) / math.sqrt(n)) if n > 1 else math.nan
    grids = {float(s): float(per.loc[ok[ok].index, s].mean()) for s in per.columns}
    return {"mean": float(a.mean()), "se": se, "n": n, "of": int(len(answers)),
            "quantity": str(table["quantity"].iloc[0]), "grids": dict(sorted(grids.items(),
                                                                           reverse=True)),
            "R": float(table["R"].iloc[0]), "tan_alpha": float(table["tan_alpha"].iloc[0]),
            "cpu_s": float(table["cpu_s"].sum()), "analyses": int(table["analyses"].sum())}
