"""Reading a resumable grid store (:mod:`rocking.store`): its zarr group, attributes,
layout, ``requested`` and ``done`` masks, the arrays describing its grid and the regions still
pending. Each reader has a form on a path and one on an open group (``*_of``), which
:class:`~rocking.store.handle.StoreHandle` uses to read a store's metadata once.
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import zarr

from rocking.store.attrs import decode_attrs
from rocking.store.layout import Layout, Variable

DONE = "done"
"""Name of the completion mask."""

REQUESTED = "requested"
"""Name of the spectra store's mask of cells some run of the study asks for."""

REQUESTED_DIMS = ("mode", "limit_state", "tan_alpha")
"""Dimensions of :data:`REQUESTED`."""

REPAIR = ("run the store's rule again with `snakemake --forcerun spectra` (or `--forcerun "
          "tilt_map`): it re-reads every finished chunk and recomputes the damaged ones")
"""The remedy every store error names."""

# Snakemake marks a finished directory output with a ".snakemake_timestamp" file; zarr notes
# it is not part of the hierarchy whenever it lists a store's members. It is harmless.
warnings.filterwarnings("ignore", message=r"Object at \.snakemake_timestamp is not recognized")


def open_group(path: str | Path, mode: str) -> zarr.Group:
    """The zarr v3 root group of the store at ``path`` (one line when there is none)."""
    path = Path(path)
    if not (path / "zarr.json").is_file():
        raise ValueError(f"store {str(path)!r} does not exist or is not a zarr v3 group")
    return zarr.open_group(path, mode=mode, zarr_format=3)


def read_attrs(path: str | Path) -> dict[str, Any]:
    """Store attributes, with JSON-encoded values decoded (:func:`.store_attrs.decode_attrs`)."""
    return decode_attrs(open_group(path, "r").attrs)


def open_layout(path: str | Path) -> Layout:
    """Read the layout of an existing store."""
    return layout_of(open_group(path, "r"), path)


def layout_of(group: zarr.Group, path: str | Path) -> Layout:
    """The layout of the open store ``group`` (``path`` names it in errors)."""
    chunking = json.loads(group.attrs["layout"])
    names = list(group.array_keys())
    dims_of = {k: tuple(group[k].metadata.dimension_names) for k in names}
    coord_names = [k for k, d in dims_of.items() if d == (k,)]
    coords = {}
    for k in coord_names:
        try:
            coords[k] = _read_coord(group[k])
        except Exception as exc:  # a checksum mismatch or truncated chunk of a coordinate
            raise ValueError(f"store {str(path)!r}: coordinate {k!r} is unreadable "
                             f"({type(exc).__name__}: {exc}); {REPAIR}") from exc
    task_dims = set(chunking["task_dims"])
    static_names = set(chunking.get("static", []))
    variables, static = {}, {}
    for k in names:
        if k in coords or k == DONE:
            continue
        var = Variable(dims_of[k], str(group[k].dtype), group[k].fill_value)
        if k in static_names:
            static[k] = var
        # data variables span every task dimension; auxiliary coordinates (a motion's
        # source record, processing) span one dimension and are not results
        elif task_dims <= set(dims_of[k]):
            variables[k] = var
    return Layout(coords, variables, tuple(chunking["task_dims"]),
                  {k: int(v) for k, v in chunking["task_chunks"].items()}, static)


def _read_coord(array: zarr.Array) -> np.ndarray:
    values = array[...]
    if values.dtype.kind in "OUT":
        return np.array([str(v) for v in values], dtype=object)
    return np.asarray(values, dtype=np.float64)


def read_requested(path: str | Path, layout: Layout | None = None) -> np.ndarray:
    """The ``requested`` mask (mode, limit_state, tan_alpha) of a spectra store; all True
    for a store without one."""
    layout = open_layout(path) if layout is None else layout
    return requested_of(open_group(path, "r"), layout)


def requested_of(group: zarr.Group, layout: Layout) -> np.ndarray:
    """The ``requested`` mask of the open store ``group`` (all True without one)."""
    if REQUESTED not in layout.static:
        return np.ones(layout.shape(REQUESTED_DIMS), dtype=bool)
    return np.asarray(group[REQUESTED][...], dtype=bool)


def describing_arrays(path: str | Path) -> list[str]:
    """The arrays of a store that describe its grid rather than hold results: coordinates,
    auxiliary coordinates (a motion's source record) and static variables (``requested``);
    every array but ``done`` and those spanning every task dimension."""
    return describing_of(open_group(path, "r"))


def describing_of(group: zarr.Group) -> list[str]:
    """:func:`describing_arrays` of the open store ``group``."""
    task_dims = set(json.loads(group.attrs["layout"])["task_dims"])
    return sorted(k for k in group.array_keys() if k != DONE
                  and not task_dims <= set(group[k].metadata.dimension_names))


def done_mask(path: str | Path) -> np.ndarray:
    """The completion mask over the task dimensions.

    Raises
    ------
    ValueError
        Naming the store and the remedy, when a chunk of the mask cannot be read.
    """
    return done_of(open_group(path, "r"), path)


def done_of(group: zarr.Group, path: str | Path) -> np.ndarray:
    """:func:`done_mask` of the open store ``group`` (``path`` names it in errors)."""
    try:
        return np.asarray(group[DONE][...], dtype=bool)
    except Exception as exc:
        raise ValueError(f"store {str(path)!r}: the done mask is unreadable ({exc}); "
                         f"{REPAIR}") from exc


def pending_regions(path: str | Path, layout: Layout | None = None) -> list[int]:
    """Indices of the task regions not yet marked done, in order."""
    layout = open_layout(path) if layout is None else layout
    return pending_of(layout, done_mask(path))


def pending_of(layout: Layout, done: np.ndarray) -> list[int]:
    """Indices of the regions of ``layout`` not all marked in ``done``, in order."""
    return [i for i in range(layout.n_regions)
            if not np.all(done[layout.selection(layout.task_dims, layout.region(i))])]


def regions_not_requested(layout: Layout, requested: np.ndarray | None) -> list[int]:
    """Regions of a spectra layout whose (mode, tan α) asks for no limit state.

    Parameters
    ----------
    layout : Layout
        A spectra layout (task dims mode, motion, tan_alpha, R).
    requested : ndarray of bool or None
        (mode, limit_state, tan_alpha) mask; None: everything is requested.
    """
    if requested is None:
        return []
    wanted = np.asarray(requested, dtype=bool).any(axis=REQUESTED_DIMS.index("limit_state"))
    out = []
    for index in range(layout.n_regions):
        region = layout.region(index)
        if not wanted[region["mode"], region["tan_alpha"]].any():
            out.append(index)
    return out
