"""Resumable zarr v3 stores of gridded study results, written chunk by chunk by Dask tasks.

A store holds data variables on a grid of coordinates (``results/<study>/spectra.zarr``: dims
mode, limit_state, motion, tan_alpha, R; ``tilt_map.zarr``: mode, R, intensity; see
``docs/design.md``). Every variable and coordinate carries CF ``units`` and ``long_name``
(:mod:`rocking.units`); the motions carry their identity (source record, processing, PGA) as
coordinates along ``motion``. Some dimensions are *task dimensions*: the grid is cut along them
into rectangular regions, one per task, and every array is chunked so that one region is
exactly one chunk of every variable. A task therefore owns whole chunk files and tasks never
write to the same file, which makes concurrent writes from independent worker processes safe
without locks (zarr's local store writes each chunk file atomically, by a rename).

A boolean ``done`` array over the task dimensions, chunked like the tasks, is set for a
region only *after* all its results are written. A run that is killed at any point leaves
every region either marked done with complete results or not marked (its partial results are
rewritten whole by the next run), so a restarted run computes only the missing regions and
ends with the same bytes as an uninterrupted one.

The store also records a hash of the configuration that produced it: a run whose
configuration differs refuses to add to it (:meth:`StoreHandle.check_config_hash`) instead of
mixing results. The driver of a fill opens a store once (:class:`StoreHandle`). Its grid is a
:class:`~rocking.study.layout.Layout`; every chunk carries a checksum (:func:`chunk_codecs`)
that :func:`rocking.study.integrity.verify_store` checks. What the study's stores hold and how
a worker fills a region: :mod:`rocking.study.tasks`.
"""

from __future__ import annotations

import contextlib
import contextvars
import json
import os
import shutil
import warnings
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import dask.array as da
import numpy as np
import xarray as xr
import zarr

from .. import _json
from ..units import QUANTITIES
from ..units import attrs as cf_attrs
from .layout import Layout, Variable
from .store_attrs import decode_attrs

DONE = "done"
"""Name of the completion mask."""

REQUESTED = "requested"
"""Name of the spectra store's mask of cells some run of the study asks for."""

REQUESTED_DIMS = ("mode", "limit_state", "tan_alpha")
"""Dimensions of :data:`REQUESTED`."""

# Snakemake marks a finished directory output with a ".snakemake_timestamp" file; zarr notes
# it is not part of the hierarchy whenever it lists a store's members. It is harmless.
warnings.filterwarnings("ignore", message=r"Object at \.snakemake_timestamp is not recognized")


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
        :func:`rocking.study.store_attrs.config_hash` of the result-affecting configuration (the
        ``digest`` of a :class:`~rocking.study.product_specs.SpectraSpec` or its kin).
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
    with (:func:`rocking.study.prepare.repair_coordinates`), made in milliseconds instead of
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


def open_layout(path: str | Path) -> Layout:
    """Read the layout of an existing store."""
    return _layout_of(open_group(path, "r"), path)


def _layout_of(group: zarr.Group, path: str | Path) -> Layout:
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


def read_requested(path: str | Path, layout: Layout | None = None) -> np.ndarray:
    """The ``requested`` mask (mode, limit_state, tan_alpha) of a spectra store; all True
    for a store without one."""
    layout = open_layout(path) if layout is None else layout
    return _requested_of(open_group(path, "r"), layout)


def _requested_of(group: zarr.Group, layout: Layout) -> np.ndarray:
    if REQUESTED not in layout.static:
        return np.ones(layout.shape(REQUESTED_DIMS), dtype=bool)
    return np.asarray(group[REQUESTED][...], dtype=bool)


def describing_arrays(path: str | Path) -> list[str]:
    """The arrays of a store that describe its grid rather than hold results: coordinates,
    auxiliary coordinates (a motion's source record) and static variables (``requested``);
    every array but ``done`` and those spanning every task dimension."""
    return _describing_of(open_group(path, "r"))


def _describing_of(group: zarr.Group) -> list[str]:
    task_dims = set(json.loads(group.attrs["layout"])["task_dims"])
    return sorted(k for k in group.array_keys() if k != DONE
                  and not task_dims <= set(group[k].metadata.dimension_names))


def differing_arrays(path: str | Path, reference: str | Path) -> list[str]:
    """The describing arrays of ``path`` (:func:`describing_arrays` of ``reference``) that
    are unreadable (checksum mismatch, truncated chunk), missing, or hold other values than
    in ``reference``, a store made anew for the same configuration. A missing chunk file of
    a coordinate reads as its fill value, so values are compared, not only read."""
    group, ref = open_group(path, "r"), open_group(reference, "r")
    out = []
    for name in describing_arrays(reference):
        expected = np.asarray(ref[name][...])
        try:
            found = np.asarray(group[name][...])
        except Exception:  # unreadable or absent
            out.append(name)
            continue
        same = found.shape == expected.shape and (
            np.array_equal(found, expected, equal_nan=True) if expected.dtype.kind == "f"
            else bool(np.all(found == expected)))
        if not same:
            out.append(name)
    return out


def restore_arrays(path: str | Path, reference: str | Path, names: Sequence[str]) -> None:
    """Replace the arrays ``names`` of store ``path`` by those of ``reference`` (each
    written whole to a sibling folder, then renamed into place)."""
    path, reference = Path(path), Path(reference)
    for name in names:
        tmp = path / f".{name}.restoring"
        shutil.rmtree(tmp, ignore_errors=True)
        shutil.copytree(reference / name, tmp)
        shutil.rmtree(path / name, ignore_errors=True)
        tmp.rename(path / name)


@contextlib.contextmanager
def locked(path: str | Path) -> Iterator[Path]:
    """Hold the lock of store ``path`` (``<path>.lock``, an exclusive ``flock``) for the
    block: two runs of one study (from two working directories sharing the results) can
    then never replace or delete a store the other is making or filling.

    Raises
    ------
    RuntimeError
        In one line naming the store, the lock file and the run holding it, when another
        process holds the lock (it is not waited for).
    """
    import fcntl
    import socket
    import time

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    lock = path.with_name(path.name + ".lock")
    fh = lock.open("a+")
    try:
        try:
            fcntl.flock(fh.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            fh.seek(0)
            holder = fh.read().strip() or "another process"
            raise RuntimeError(f"store {str(path)!r} is in use by {holder} (lock {lock}); "
                               f"wait for that run to end, then run again (it resumes "
                               f"from what that run finished)") from None
        # the lock file is never deleted (that would race with a waiting opener); it names
        # its holder for the message above
        fh.seek(0)
        fh.truncate()
        fh.write(f"pid {os.getpid()} on {socket.gethostname()} since "
                 f"{time.strftime('%Y-%m-%d %H:%M:%S %Z')} in {os.getcwd()}")
        fh.flush()
        yield path
    finally:
        fh.close()  # closing releases the flock


def _read_coord(array: zarr.Array) -> np.ndarray:
    values = array[...]
    if values.dtype.kind in "OUT":
        return np.array([str(v) for v in values], dtype=object)
    return np.asarray(values, dtype=np.float64)


def open_group(path: str | Path, mode: str) -> zarr.Group:
    path = Path(path)
    if not (path / "zarr.json").is_file():
        raise ValueError(f"store {str(path)!r} does not exist or is not a zarr v3 group")
    return zarr.open_group(path, mode=mode, zarr_format=3)


def read_attrs(path: str | Path) -> dict[str, Any]:
    """Store attributes, with JSON-encoded values decoded (:func:`.store_attrs.decode_attrs`)."""
    return decode_attrs(open_group(path, "r").attrs)


def done_mask(path: str | Path) -> np.ndarray:
    """The completion mask over the task dimensions.

    Raises
    ------
    ValueError
        Naming the store and the remedy, when a chunk of the mask cannot be read.
    """
    return _done_of(open_group(path, "r"), path)


def _done_of(group: zarr.Group, path: str | Path) -> np.ndarray:
    try:
        return np.asarray(group[DONE][...], dtype=bool)
    except Exception as exc:
        raise ValueError(f"store {str(path)!r}: the done mask is unreadable ({exc}); "
                         f"{REPAIR}") from exc


def pending_regions(path: str | Path, layout: Layout | None = None) -> list[int]:
    """Indices of the task regions not yet marked done, in order."""
    layout = open_layout(path) if layout is None else layout
    return _pending(layout, done_mask(path))


def _pending(layout: Layout, done: np.ndarray) -> list[int]:
    return [i for i in range(layout.n_regions)
            if not np.all(done[layout.selection(layout.task_dims, layout.region(i))])]


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


# --------------------------------------------------------------------------------------------
# Integrity: a checksum on every chunk (verified by rocking.study.integrity.verify_store)
# --------------------------------------------------------------------------------------------

REPAIR = ("run the store's rule again with `snakemake --forcerun spectra` (or `--forcerun "
          "tilt_map`): it re-reads every finished chunk and recomputes the damaged ones")
"""The remedy every store error names."""

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


def consolidate(path: str | Path) -> None:
    """Consolidate the store metadata (once, after the last region is written)."""
    with warnings.catch_warnings():
        # zarr notes that consolidated metadata is not (yet) in the v3 specification;
        # xarray reads it and it is what open_zarr looks for first
        warnings.simplefilter("ignore", UserWarning)
        zarr.consolidate_metadata(str(path), zarr_format=3)


@dataclass(frozen=True, eq=False)
class StoreHandle:
    """A store opened once: its path, zarr group, layout and decoded attributes.

    The driver of a fill (:func:`rocking.study.cluster.fill_store`) and the verification of
    a store (:func:`rocking.study.integrity.verify_store`) take one instead of a path, so the
    store's metadata is read once, not by every step. Task bodies in worker processes still
    take the path (a handle is not sent between processes).

    Attributes
    ----------
    path : Path
        Store directory.
    group : zarr.Group
        The open root group (mode ``mode``).
    layout : Layout
        Coordinates, variables and task regions.
    attrs : dict
        Attributes with JSON-text values decoded (:func:`read_attrs`).
    mode : str
        ``"r"`` (read only) or ``"r+"`` (results and done flags may be written).
    """

    path: Path
    group: zarr.Group
    layout: Layout
    attrs: dict[str, Any]
    mode: str

    @classmethod
    def open(cls, path: str | Path, mode: str = "r") -> StoreHandle:
        """Open the store at ``path`` and read its layout and attributes.

        Raises
        ------
        ValueError
            When ``path`` is not a zarr v3 store, or a coordinate is unreadable (naming the
            store and the remedy).
        """
        if mode not in ("r", "r+"):
            raise ValueError(f"mode must be 'r' or 'r+', got {mode!r}")
        path = Path(path)
        group = open_group(path, mode)
        return cls(path, group, _layout_of(group, path), decode_attrs(group.attrs), mode)

    def check_config_hash(self, expected: str) -> None:
        """Refuse to continue a store built for another configuration.

        Raises
        ------
        ValueError
            Naming both hashes, when the store's ``config_hash`` differs from ``expected``.
        """
        found = self.group.attrs.get("config_hash")
        if found != expected:
            raise ValueError(
                f"store {str(self.path)!r} has config_hash={found!r} but this run's "
                f"configuration has config_hash={expected!r}; rebuild the store (its rule "
                f"reruns when the configuration changes) instead of mixing results"
            )

    def requested(self) -> np.ndarray:
        """The ``requested`` mask (:func:`read_requested`)."""
        return _requested_of(self.group, self.layout)

    def describing_arrays(self) -> list[str]:
        """The arrays describing the grid (:func:`describing_arrays`)."""
        return _describing_of(self.group)

    def done_mask(self) -> np.ndarray:
        """The completion mask over the task dimensions (:func:`done_mask`)."""
        return _done_of(self.group, self.path)

    def pending_regions(self) -> list[int]:
        """Indices of the task regions not yet marked done, in order."""
        return _pending(self.layout, self.done_mask())

    def finalize(self) -> None:
        """Check that every region is done, then consolidate the metadata.

        Raises
        ------
        ValueError
            If some region is not done (naming how many).
        """
        done = self.done_mask()
        if not done.all():
            raise ValueError(f"store {str(self.path)!r} has {int((~done).sum())} of "
                             f"{done.size} points not done")
        consolidate(self.path)
