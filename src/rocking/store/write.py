"""Writing a resumable grid store (:mod:`rocking.store`): its creation (built aside and
renamed into place, chunk checksums on every array), the results of one region followed by
its ``done`` flag, and the metadata consolidated at the end.
"""

from __future__ import annotations

import contextlib
import contextvars
import shutil
import warnings
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import dask.array as da
import numpy as np
import xarray as xr
import zarr

from rocking import _json
from rocking.store.layout import Layout, Variable
from rocking.store.read import DONE, REQUESTED, open_group, regions_not_requested
from rocking.units import QUANTITIES
from rocking.units import attrs as cf_attrs

CHECKSUM_CODEC = "crc32c"
"""Name of the checksum codec that ends every array's codec pipeline."""


def chunk_codecs() -> list:
    """Bytes-to-bytes codecs of every array: zarr's default zstd, then a CRC-32C checksum.

    The checksum is computed over the compressed bytes and checked on every read, so a
    flipped bit or a truncated chunk file raises instead of decoding to other numbers.
    """
    from zarr.codecs import Crc32cCodec, ZstdCodec

    return [ZstdCodec(level=0, checksum=False), Crc32cCodec()]


def every_chunk(array: zarr.Array) -> zarr.Array:
    """``array`` writing chunk files even for chunks equal to the fill value."""
    return array.with_config({"write_empty_chunks": True})


def create_store(path: str | Path, layout: Layout, attrs: dict[str, Any],
                 config_digest: str,
                 coords: dict[str, tuple[str, Sequence[Any]]] | None = None,
                 static: dict[str, np.ndarray] | None = None) -> Path:
    """Create an empty store (replacing any store at ``path``).

    The store is built in a sibling temporary directory and renamed into place, so a
    creation that is interrupted never leaves a half-made store at ``path``. Regions in which
    the static ``requested`` mask (if the layout has one) asks for nothing are marked done at
    once: there is nothing to compute in them.

    Parameters
    ----------
    path : str or Path
        Store directory, e.g. ``results/<study>/spectra.zarr``.
    layout : Layout
        Coordinates, variables and task chunking.
    attrs : dict
        Attributes; values that are not strings are stored as JSON text (``config``,
        ``tolerances``, ``ensemble``...), readable with ``json.loads``.
    config_digest : str
        :func:`rocking.store.attrs.config_hash` of the result-affecting configuration (the
        ``digest`` of a :class:`~rocking.config.products.SpectraSpec` or its kin).
    coords : dict, optional
        Auxiliary coordinates ``{name: (dim, values)}``, e.g. each motion's source record
        and processing (:func:`identity_coords`).
    static : dict of str to ndarray, optional
        Values of the layout's static variables (each shaped over its dims); a variable
        left out takes its fill value everywhere.

    Returns
    -------
    Path
        The store path.
    """
    path = Path(path)
    static = _static_values(layout, static or {})
    tmp = path.with_name(path.name + ".creating")
    shutil.rmtree(tmp, ignore_errors=True)
    ds = xr.Dataset(coords={d: (d, v, _cf(d)) for d, v in layout.coords.items()})
    for name, (dim, values) in (coords or {}).items():
        kind = "O" if any(isinstance(v, str) for v in values) else "f8"
        ds = ds.assign_coords({name: (dim, np.array(list(values), dtype=kind), _cf(name))})
    reference = _DESCRIBING_ONLY.get()
    results = {} if reference else {**layout.variables, DONE: _done_variable(layout)}
    for name, var in results.items():
        shape, chunks = layout.shape(var.dims), layout.chunks(var.dims)
        # lazy fill: to_zarr(compute=False) writes metadata and coordinates, no chunk files
        ds[name] = (var.dims, da.full(shape, var.fill, dtype=var.dtype, chunks=chunks),
                    _cf(name))
    for name, values in static.items():
        ds[name] = (layout.static[name].dims, values, _cf(name))
    ds.attrs = {k: v if isinstance(v, str) else _json.dumps(v) for k, v in attrs.items()}
    ds.attrs["Conventions"] = "CF-1.10"
    ds.attrs["config_hash"] = config_digest
    ds.attrs["layout"] = layout.to_json()
    encoding = {name: {"chunks": layout.chunks(ds[name].dims)} for name in results}
    # every array, coordinates included, gets a checksum on each chunk (verify_store)
    for name in [*ds.data_vars, *ds.coords]:
        encoding.setdefault(name, {})["compressors"] = chunk_codecs()
    ds.to_zarr(tmp, mode="w", compute=False, zarr_format=3, consolidated=False,
               encoding=encoding)
    if static:
        # to_zarr(compute=False) leaves out eager data too: write the static arrays now
        group = zarr.open_group(tmp, mode="r+", zarr_format=3)
        for name, values in static.items():
            group[name][...] = values
        for index in ([] if reference else regions_not_requested(layout,
                                                                 static.get(REQUESTED))):
            group[DONE][layout.selection(layout.task_dims, layout.region(index))] = True
    if path.exists():
        shutil.rmtree(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp.rename(path)
    return path


_DESCRIBING_ONLY: contextvars.ContextVar[bool] = contextvars.ContextVar("describing_only",
                                                                       default=False)


@contextlib.contextmanager
def describing_only() -> Iterator[None]:
    """Within the block, :func:`create_store` writes only the arrays that describe the grid
    (coordinates, auxiliary coordinates, static variables: :func:`describing_arrays`), not
    the result arrays nor ``done``: the reference a resumed store's coordinates are compared
    with (:func:`rocking.execution.prepare.repair_coordinates`), made in milliseconds instead of
    seconds (the lazy result arrays of a large grid cost most of a creation)."""
    token = _DESCRIBING_ONLY.set(True)
    try:
        yield
    finally:
        _DESCRIBING_ONLY.reset(token)


def _cf(name: str) -> dict[str, str]:
    # units and long_name of every known output; others (a test's own) get a neutral pair
    return cf_attrs(name) if name in QUANTITIES else {"units": "1", "long_name": name}


def _done_variable(layout: Layout) -> Variable:
    return Variable(layout.task_dims, "bool", False)


def _static_values(layout: Layout, values: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Values of every static variable of ``layout``, checked (fill value where not given)."""
    unknown = sorted(set(values) - set(layout.static))
    if unknown:
        raise ValueError(f"static values {unknown} are not static variables of the layout "
                         f"{sorted(layout.static)}")
    out = {}
    for name, var in layout.static.items():
        shape = layout.shape(var.dims)
        a = np.asarray(values.get(name, np.full(shape, var.fill)), dtype=var.dtype)
        if a.shape != shape:
            raise ValueError(f"static variable {name!r} has shape {a.shape}, expected "
                             f"{shape} over {var.dims}")
        out[name] = a
    return out


def write_region(path: str | Path, layout: Layout, index: int,
                 values: dict[str, np.ndarray],
                 nan_allowed: dict[str, np.ndarray] | None = None) -> None:
    """Write the results of region ``index``, then mark it done.

    Parameters
    ----------
    path : str or Path
        Store directory.
    layout : Layout
        The store's layout.
    index : int
        Region index.
    values : dict of str to ndarray
        One array per data variable, shaped like the region over the variable's dims.
    nan_allowed : dict of str to ndarray of bool, optional
        Per float variable, where NaN is a legitimate answer (e.g. where a flag says
        "not reached"); NaN anywhere else is refused.

    Raises
    ------
    ValueError
        If a variable is missing, unknown or mis-shaped, or a float result is NaN where not
        allowed (a NaN is a result only when a flag explains it, never silently).
    """
    region = layout.region(index)
    missing = sorted(set(layout.variables) - set(values))
    extra = sorted(set(values) - set(layout.variables))
    if missing or extra:
        raise ValueError(f"region {index}: missing variables {missing}, unknown {extra}")
    group = open_group(path, "r+")
    arrays = {}
    for name, var in layout.variables.items():
        sel = layout.selection(var.dims, region)
        expected = tuple(len(range(*s.indices(n))) for s, n in
                         zip(sel, layout.shape(var.dims), strict=True))
        a = np.asarray(values[name], dtype=var.dtype)
        if a.shape != expected:
            raise ValueError(f"region {index}: {name} has shape {a.shape}, expected {expected}")
        bad = np.isnan(a) if a.dtype.kind == "f" else np.zeros(a.shape, dtype=bool)
        if nan_allowed and name in nan_allowed:
            bad &= ~np.broadcast_to(np.asarray(nan_allowed[name], dtype=bool), a.shape)
        if bad.any():
            raise ValueError(f"region {index}: {name} holds an unexplained NaN at "
                             f"{np.argwhere(bad)[0].tolist()}")
        arrays[name] = (sel, a)
    for name, (sel, a) in arrays.items():
        # every chunk of a done region exists on disk, even one equal to the fill value:
        # a missing chunk file is then damage (verify_store), never "all fill"
        every_chunk(group[name])[sel] = a
    # the mask goes last: a region is done only once every result of it is on disk
    every_chunk(group[DONE])[layout.selection(layout.task_dims, region)] = True


def consolidate(path: str | Path) -> None:
    """Consolidate the store metadata (once, after the last region is written)."""
    with warnings.catch_warnings():
        # zarr notes that consolidated metadata is not (yet) in the v3 specification;
        # xarray reads it and it is what open_zarr looks for first
        warnings.simplefilter("ignore", UserWarning)
        zarr.consolidate_metadata(str(path), zarr_format=3)
