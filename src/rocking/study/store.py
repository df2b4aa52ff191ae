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
configuration differs refuses to add to it (:func:`check_config_hash`) instead of mixing
results.
"""

from __future__ import annotations

import hashlib
import json
import math
import shutil
import time
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Any

import dask.array as da
import numpy as np
import xarray as xr
import zarr

from .. import _json
from .._json import json_default
from ..motions.motion import GroundMotion
from ..motions.records import file_sha256
from ..units import QUANTITIES
from ..units import attrs as cf_attrs

SPECTRA_DIMS = ("mode", "limit_state", "motion", "tan_alpha", "R")
"""Dimensions of the spectra variables, in storage order."""

SPECTRA_TASK_DIMS = ("mode", "motion", "tan_alpha", "R")
"""Dimensions the spectra grid is cut along; each task holds all limit states of its points."""

TILT_MAP_DIMS = ("mode", "R", "intensity")
"""Dimensions of the Fig 7 map ``theta_max_over_alpha``."""

TILT_MAP_TASK_DIMS = ("mode", "R")
"""A tilt-map task computes every intensity of a few sizes R for one mode."""

DONE = "done"
"""Name of the completion mask."""

REQUESTED = "requested"
"""Name of the spectra store's mask of cells some run of the study asks for."""

REQUESTED_DIMS = ("mode", "limit_state", "tan_alpha")
"""Dimensions of :data:`REQUESTED`."""

# Snakemake marks a finished directory output with a ".snakemake_timestamp" file; zarr notes
# it is not part of the hierarchy whenever it lists a store's members. It is harmless.
warnings.filterwarnings("ignore", message=r"Object at \.snakemake_timestamp is not recognized")


@dataclass(frozen=True)
class Variable:
    """One data variable of a store.

    Attributes
    ----------
    dims : tuple of str
        Its dimensions, a subset of the layout's, in storage order.
    dtype : str
        NumPy dtype name.
    fill : Any
        Value of never-written entries (NaN for floats: "not computed").
    """

    dims: tuple[str, ...]
    dtype: str
    fill: Any


@dataclass(frozen=True)
class Layout:
    """Coordinates, variables and task chunking of a store.

    Attributes
    ----------
    coords : dict of str to ndarray
        Coordinate values of every dimension.
    variables : dict of str to Variable
        Data variables (the ``done`` mask is added automatically over ``task_dims``).
    task_dims : tuple of str
        Dimensions cut into task regions, in the order regions are numbered (C order).
    task_chunks : dict of str to int
        Region length along each task dimension (the last region may be shorter).
    static : dict of str to Variable
        Variables of the configuration rather than of the results (e.g. ``requested``),
        written whole when the store is created, never by a task.
    """

    coords: dict[str, np.ndarray]
    variables: dict[str, Variable]
    task_dims: tuple[str, ...]
    task_chunks: dict[str, int]
    static: dict[str, Variable] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for dim in self.task_dims:
            if dim not in self.coords:
                raise ValueError(f"task dimension {dim!r} has no coordinate")
            n = self.task_chunks.get(dim, 1)
            if not isinstance(n, (int, np.integer)) or n < 1:
                raise ValueError(f"task chunk along {dim!r} must be an integer >= 1, got {n!r}")
        for name, var in self.variables.items():
            missing = [d for d in var.dims if d not in self.coords]
            if missing:
                raise ValueError(f"variable {name!r} uses dimensions without coordinates "
                                 f"{missing}")
            if not set(self.task_dims) <= set(var.dims):
                raise ValueError(f"variable {name!r} must span every task dimension "
                                 f"{self.task_dims}, has {var.dims}")
        for name, var in self.static.items():
            missing = [d for d in var.dims if d not in self.coords]
            if missing or name in self.variables:
                raise ValueError(f"static variable {name!r} uses dimensions without "
                                 f"coordinates {missing} or repeats a variable's name")

    def shape(self, dims: Sequence[str]) -> tuple[int, ...]:
        """Array shape over ``dims``."""
        return tuple(len(self.coords[d]) for d in dims)

    def chunks(self, dims: Sequence[str]) -> tuple[int, ...]:
        """Chunk shape over ``dims``: the task chunk along task dims, whole elsewhere."""
        return tuple(
            min(self.task_chunks.get(d, 1), len(self.coords[d])) if d in self.task_dims
            else len(self.coords[d])
            for d in dims
        )

    @property
    def region_counts(self) -> tuple[int, ...]:
        """Number of regions along each task dimension."""
        return tuple(math.ceil(n / c) for n, c in
                     zip(self.shape(self.task_dims), self.chunks(self.task_dims), strict=True))

    @property
    def n_regions(self) -> int:
        """Total number of task regions."""
        return int(np.prod(self.region_counts))

    def region(self, index: int) -> dict[str, slice]:
        """The slices along the task dimensions of region ``index`` (C order)."""
        if not 0 <= index < self.n_regions:
            raise ValueError(f"region index must be in [0, {self.n_regions}), got {index!r}")
        block = np.unravel_index(index, self.region_counts)
        out = {}
        for dim, b, c, n in zip(self.task_dims, block, self.chunks(self.task_dims),
                                self.shape(self.task_dims), strict=True):
            out[dim] = slice(int(b) * c, min((int(b) + 1) * c, n))
        return out

    def selection(self, dims: Sequence[str], region: dict[str, slice]) -> tuple[slice, ...]:
        """Index tuple of ``region`` in an array over ``dims`` (whole along other dims)."""
        return tuple(region.get(d, slice(None)) for d in dims)

    def to_json(self) -> str:
        """The chunking part of the layout (coordinates live in the store's arrays)."""
        return json.dumps({"task_dims": list(self.task_dims),
                           "task_chunks": {d: int(self.task_chunks.get(d, 1))
                                           for d in self.task_dims},
                           "static": sorted(self.static)})


def spectra_layout(modes: Sequence[str], limit_states: Sequence[str], motions: Sequence[str],
                   tan_alpha: Sequence[float], R: Sequence[float], chunk_R: int) -> Layout:
    """Layout of a performance-spectra store (``docs/design.md``, "Study store").

    Besides the results it holds the static ``requested`` (mode, limit_state, tan_alpha):
    which cells the study's runs ask for (:mod:`rocking.study.plan`); cells not requested
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
        "mode": _labels("mode", modes),
        "limit_state": _labels("limit_state", limit_states),
        "motion": _labels("motion", motions),
        "tan_alpha": _values("tan_alpha", tan_alpha),
        "R": _values("R", R),
    }
    variables = {
        "pga_crit": Variable(SPECTRA_DIMS, "float64", np.nan),
        "pga_crit_g": Variable(SPECTRA_DIMS, "float64", np.nan),
        "not_reached": Variable(SPECTRA_DIMS, "bool", False),
        "non_monotonic": Variable(SPECTRA_DIMS, "bool", False),
        "failed": Variable(SPECTRA_DIMS, "bool", False),
        "unresolved": Variable(SPECTRA_DIMS, "bool", False),
        "n_analyses": Variable(SPECTRA_DIMS, "int32", 0),
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
        "mode": _labels("mode", modes),
        "R": _values("R", R),
        "intensity": _values("intensity", intensity),
    }
    variables = {
        "theta_max_over_alpha": Variable(TILT_MAP_DIMS, "float64", np.nan),
        "overturned": Variable(TILT_MAP_DIMS, "bool", False),
        "failed": Variable(TILT_MAP_DIMS, "bool", False),
    }
    return Layout(coords, variables, TILT_MAP_TASK_DIMS, {"R": int(chunk_R)})


def _labels(name: str, values: Sequence[str]) -> np.ndarray:
    labels = [str(v) for v in values]
    if not labels:
        raise ValueError(f"{name} must not be empty, got {values!r}")
    dup = sorted({v for v in labels if labels.count(v) > 1})
    if dup:
        raise ValueError(f"{name} has duplicate labels {dup}")
    # object dtype: zarr v3 stores it as its variable-length "string" type
    return np.array(labels, dtype=object)


def _values(name: str, values: Sequence[float]) -> np.ndarray:
    a = np.asarray(values, dtype=np.float64)
    if a.ndim != 1 or a.size == 0:
        raise ValueError(f"{name} must be a non-empty list of numbers, got {values!r}")
    if not np.all(np.isfinite(a)) or np.any(a <= 0):
        raise ValueError(f"{name} must hold finite numbers > 0, got {values!r}")
    if np.unique(a).size != a.size:
        raise ValueError(f"{name} has duplicate values {values!r}")
    return a


def config_hash(obj: Any) -> str:
    """Short sha256 of the canonical JSON of ``obj`` (sorted keys, no blanks).

    Used as the identity of the result-affecting configuration of a store.
    """
    text = json.dumps(obj, sort_keys=True, separators=(",", ":"), default=json_default)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


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
        :func:`config_hash` of the result-affecting configuration.
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
    for name, var in {**layout.variables, DONE: _done_variable(layout)}.items():
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
    encoding = {name: {"chunks": layout.chunks(ds[name].dims)}
                for name in [*layout.variables, DONE]}
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
        for index in regions_not_requested(layout, static.get(REQUESTED)):
            group[DONE][layout.selection(layout.task_dims, layout.region(index))] = True
    if path.exists():
        shutil.rmtree(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp.rename(path)
    return path


def _cf(name: str) -> dict[str, str]:
    # units and long_name of every known output; others (a test's own) get a neutral pair
    return cf_attrs(name) if name in QUANTITIES else {"units": "1", "long_name": name}


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
    group = _open_group(path, "r")
    chunking = json.loads(group.attrs["layout"])
    names = list(group.array_keys())
    dims_of = {k: tuple(group[k].metadata.dimension_names) for k in names}
    coord_names = [k for k, d in dims_of.items() if d == (k,)]
    coords = {k: _read_coord(group[k]) for k in coord_names}
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
    if REQUESTED not in layout.static:
        return np.ones(layout.shape(REQUESTED_DIMS), dtype=bool)
    return np.asarray(_open_group(path, "r")[REQUESTED][...], dtype=bool)


def _read_coord(array: zarr.Array) -> np.ndarray:
    values = array[...]
    if values.dtype.kind in "OUT":
        return np.array([str(v) for v in values], dtype=object)
    return np.asarray(values, dtype=np.float64)


def _open_group(path: str | Path, mode: str) -> zarr.Group:
    path = Path(path)
    if not (path / "zarr.json").is_file():
        raise ValueError(f"store {str(path)!r} does not exist or is not a zarr v3 group")
    return zarr.open_group(path, mode=mode, zarr_format=3)


def read_attrs(path: str | Path) -> dict[str, Any]:
    """Store attributes, with JSON-encoded values decoded."""
    out = {}
    for k, v in _open_group(path, "r").attrs.items():
        try:
            out[k] = json.loads(v) if isinstance(v, str) else v
        except json.JSONDecodeError:
            out[k] = v
    return out


def check_config_hash(path: str | Path, expected: str) -> None:
    """Refuse to continue a store built for another configuration.

    Raises
    ------
    ValueError
        Naming both hashes, when the store's ``config_hash`` differs from ``expected``.
    """
    found = _open_group(path, "r").attrs.get("config_hash")
    if found != expected:
        raise ValueError(
            f"store {str(path)!r} has config_hash={found!r} but this run's configuration has "
            f"config_hash={expected!r}; rebuild the store (its rule reruns when the "
            f"configuration changes) instead of mixing results"
        )


def done_mask(path: str | Path) -> np.ndarray:
    """The completion mask over the task dimensions.

    Raises
    ------
    ValueError
        Naming the store and the remedy, when a chunk of the mask cannot be read.
    """
    try:
        return np.asarray(_open_group(path, "r")[DONE][...], dtype=bool)
    except Exception as exc:
        raise ValueError(f"store {str(path)!r}: the done mask is unreadable ({exc}); "
                         f"{REPAIR}") from exc


def pending_regions(path: str | Path, layout: Layout | None = None) -> list[int]:
    """Indices of the task regions not yet marked done, in order."""
    layout = open_layout(path) if layout is None else layout
    done = done_mask(path)
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
    group = _open_group(path, "r+")
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
        _every_chunk(group[name])[sel] = a
    # the mask goes last: a region is done only once every result of it is on disk
    _every_chunk(group[DONE])[layout.selection(layout.task_dims, region)] = True


# --------------------------------------------------------------------------------------------
# Integrity: a checksum on every chunk, and a pass that re-reads every finished region
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


def _every_chunk(array: zarr.Array) -> zarr.Array:
    """``array`` writing chunk files even for chunks equal to the fill value."""
    return array.with_config({"write_empty_chunks": True})


def has_checksums(path: str | Path) -> bool:
    """Whether every result array of a store carries :data:`CHECKSUM_CODEC` (stores made
    before checksums were introduced do not, and must be rebuilt to get them)."""
    group = _open_group(path, "r")
    return all(any(getattr(c, "to_dict", lambda: {})().get("name") == CHECKSUM_CODEC
                   for c in group[k].metadata.codecs) for k in group.array_keys())


def _chunk_file(path: Path, array: zarr.Array, sel: tuple[slice, ...]) -> Path:
    """The file holding the chunk that starts at the start of ``sel`` (one region)."""
    coords = tuple((s.start or 0) // c for s, c in zip(sel, array.chunks, strict=True))
    return path / array.path / array.metadata.encode_chunk_key(coords)


class _Reader:
    """Reads a store's arrays for verification: each whole at once (zarr decodes the
    chunks concurrently), a region at a time only for an array with a damaged chunk."""

    def __init__(self, path: Path, group: zarr.Group, names: Sequence[str]) -> None:
        self.path = path
        self.arrays = {name: group[name] for name in names}  # each opened once
        self.whole: dict[str, np.ndarray | None] = {}
        self.files: dict[str, set[Path]] = {}
        for name, array in self.arrays.items():
            try:
                self.whole[name] = np.asarray(array[...])
            except Exception:  # some chunk is damaged: read it region by region
                self.whole[name] = None
            folder = path / array.path
            self.files[name] = {p for p in folder.rglob("*") if p.is_file()}

    def read(self, name: str, sel: tuple[slice, ...]) -> np.ndarray:
        whole = self.whole[name]
        return whole[sel] if whole is not None else np.asarray(self.arrays[name][sel])

    def chunk_file(self, name: str, sel: tuple[slice, ...]) -> Path:
        return _chunk_file(self.path, self.arrays[name], sel)

    def exists(self, name: str, sel: tuple[slice, ...]) -> bool:
        return self.chunk_file(name, sel) in self.files[name]


def _region_problem(path: Path, group: zarr.Group, layout: Layout, index: int,
                    requested: np.ndarray, checksums: bool,
                    reader: _Reader | None = None) -> str | None:
    """What is wrong with the stored results of a done region, or None.

    Every chunk of the region is read (its checksum checked); with checksums, each must
    exist as a file (finished regions write all their chunks). Then the values must be
    consistent: a float NaN only where a flag explains it, ``pga_crit_g = pga_crit · tan α``.
    """
    region = layout.region(index)
    asked = True
    if "limit_state" in layout.coords and "mode" in region and "tan_alpha" in region:
        wanted = requested[region["mode"], :, region["tan_alpha"]]  # (mode, ls, tan α)
        asked = bool(wanted.any())
    reader = reader or _Reader(path, group, list(layout.variables))
    values = {}
    for name, var in layout.variables.items():
        sel = layout.selection(var.dims, region)
        if checksums and asked and not reader.exists(name, sel):
            return f"{name}: chunk file {reader.chunk_file(name, sel)} is missing"
        try:
            values[name] = reader.read(name, sel)
        except Exception as exc:  # checksum mismatch, truncation, decompression error
            return f"{name}: chunk {reader.chunk_file(name, sel)} is unreadable " \
                   f"({type(exc).__name__}: {exc})"
    if "pga_crit" in values:
        p = values["pga_crit"]  # (mode, limit_state, motion, tan_alpha, R)
        ta = layout.coords["tan_alpha"][region["tan_alpha"]][None, None, None, :, None]
        if not np.array_equal(p * ta, values["pga_crit_g"], equal_nan=True):
            return "pga_crit_g differs from pga_crit · tan_alpha"
        ok = values["not_reached"] | ~requested[region["mode"], :, region["tan_alpha"]][
            :, :, None, :, None]
        if np.any(np.isnan(p) & ~ok):
            return "pga_crit is NaN at a point whose limit state was reached"
    if "theta_max_over_alpha" in values and np.any(
            np.isnan(values["theta_max_over_alpha"]) & ~values["failed"]):
        return "theta_max_over_alpha is NaN at an analysis that did not fail"
    return None


def verify_store(path: str | Path, layout: Layout | None = None,
                 say: Callable[[str], None] | None = None, repair: bool = True) -> list[int]:
    """Re-read every finished region; mark the damaged ones not done, to be recomputed.

    A region counts as damaged when its done flag is unreadable, when a chunk of its results
    is unreadable (checksum mismatch, truncated file), missing (stores with checksums write
    every chunk of a finished region) or inconsistent (:func:`_region_problem`). Its done
    flag is reset, so the next fill recomputes exactly those regions, and deterministic
    tasks end with the same bytes as an undamaged run.

    Parameters
    ----------
    path : str or Path
        Store directory.
    layout : Layout, optional
        Its layout (read when not given).
    say : callable, optional
        Where the per-region lines go (default: a warning).
    repair : bool
        Reset the done flag of damaged regions (False: only report them; the store is
        opened read-only).

    Returns
    -------
    list of int
        The regions found damaged (now pending).

    Raises
    ------
    ValueError
        Naming the store and the remedy, when the metadata or coordinates are unreadable.
    """
    path = Path(path)
    say = say or (lambda text: warnings.warn(text, stacklevel=2))
    try:
        layout = open_layout(path) if layout is None else layout
        requested = read_requested(path, layout) if REQUESTED in layout.static or \
            "limit_state" in layout.coords else np.ones((1, 1, 1), dtype=bool)
        checksums = has_checksums(path)
    except Exception as exc:
        raise ValueError(f"store {str(path)!r}: metadata or coordinates are unreadable "
                         f"({exc}); delete the store, its rule makes it anew") from exc
    if not checksums:
        say(f"store {path} was made without chunk checksums (by an older version): a "
            f"flipped bit cannot be detected, only values that contradict each other; "
            f"delete the store to rebuild it with checksums")
    group = _open_group(path, "r+" if repair else "r")
    reader = _Reader(path, group, [DONE, *layout.variables])
    damaged = []
    for index in range(layout.n_regions):
        sel = layout.selection(layout.task_dims, layout.region(index))
        try:
            done = bool(np.all(reader.read(DONE, sel)))
        except Exception as exc:
            problem = f"done flag {reader.chunk_file(DONE, sel)} is unreadable ({exc})"
        else:
            if not done:
                continue
            problem = _region_problem(path, group, layout, index, requested, checksums,
                                      reader)
        if problem is not None:
            say(f"store {path}: chunk {index} damaged, {problem}"
                + ("; recomputing it" if repair else ""))
            if repair:
                _every_chunk(group[DONE])[sel] = False
            damaged.append(index)
    return damaged


def consolidate(path: str | Path) -> None:
    """Consolidate the store metadata (once, after the last region is written)."""
    with warnings.catch_warnings():
        # zarr notes that consolidated metadata is not (yet) in the v3 specification;
        # xarray reads it and it is what open_zarr looks for first
        warnings.simplefilter("ignore", UserWarning)
        zarr.consolidate_metadata(str(path), zarr_format=3)


def finalize(path: str | Path) -> None:
    """Check that every region is done, then consolidate the metadata.

    Raises
    ------
    ValueError
        If some region is not done (naming how many).
    """
    done = done_mask(path)
    if not done.all():
        raise ValueError(f"store {str(path)!r} has {int((~done).sum())} of {done.size} "
                         f"points not done")
    consolidate(path)


def ensemble_attrs(motions_path: str | Path, name: str) -> dict[str, Any]:
    """What a store records about its ensemble: file hash, motions, labels, stand-in flags."""
    motions = list(motions_by_name(motions_path).values())
    from ..motions.source import identity

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
        "file_sha256": file_sha256(motions_path),
        "stand_in": any(r["stand_in"] for r in rows),
        "motions": rows,
    }


def check_ensemble(path: str | Path, motions_path: str | Path) -> None:
    """Refuse to fill a store from another ensemble file than the one it was made for.

    Raises
    ------
    ValueError
        Naming the file and both sha256 values.
    """
    expected = read_attrs(path)["ensemble"]["file_sha256"]
    found = file_sha256(motions_path)
    if found != expected:
        raise ValueError(f"ensemble file {str(motions_path)!r} has sha256 {found} but store "
                         f"{str(path)!r} was made from sha256 {expected}; rebuild the store")


SECONDS_PER_SAMPLE = 0.4e-6
"""Lower estimate of the cost of one analysis per record sample [s]: the cheapest mode (2D,
"fast" preset) on El Centro took 0.46 µs per sample on a 2-core development machine
(results/benchmarks/workflow.md has the measured costs). Only sizes tasks for
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


MODE_COST = {"3d-damped": 3.0, "3d": 2.0, "2d-x": 1.0, "2d-y": 1.0}
"""Relative cost of a search per mode (3D searches take several times a 2D one)."""


def costliest_first(layout: Layout, indices: Sequence[int]) -> list[int]:
    """Regions ordered by a rough cost estimate, largest first.

    Long tasks started last would leave the other workers idle at the end of a run; running
    them first (largest-processing-time-first scheduling) evens out the finish. The estimate
    is the mode's :data:`MODE_COST` times the sum of the sizes R (larger bodies need more
    analyses to tip). Layouts without a mode or R dimension keep their order.
    """

    def cost(i: int) -> float:
        rc = region_coords(layout, i)
        mode = rc.get("mode", ["?"])[0]
        return MODE_COST.get(str(mode), 1.0) * float(np.sum(rc.get("R", [1.0])))

    return sorted(indices, key=lambda i: (-cost(i), i))


POINT_FREE_DIMS = ("limit_state",)
"""Dimensions that do not multiply the work: one search decides every limit state."""


def region_points(layout: Layout, index: int) -> int:
    """Points of work in region ``index``: spectrum points (searches) or tilt-map analyses.

    The product of the region's lengths over the largest variable's dimensions, without
    :data:`POINT_FREE_DIMS`; tasks report the same count as ``points``.
    """
    region = layout.region(index)
    dims = max((v.dims for v in layout.variables.values()), key=len)
    n = 1
    for d in dims:
        if d in region:
            n *= len(range(*region[d].indices(len(layout.coords[d]))))
        elif d not in POINT_FREE_DIMS:
            n *= len(layout.coords[d])
    return n


def region_coords(layout: Layout, index: int) -> dict[str, np.ndarray]:
    """Coordinate values of region ``index`` along every dimension."""
    region = layout.region(index)
    return {d: v[region[d]] if d in region else v for d, v in layout.coords.items()}


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
    from ..motions.ensemble_io import load_ensemble

    return {m.name: m for m in load_ensemble(path)}


# --------------------------------------------------------------------------------------------
# Task bodies (run in Dask workers): compute one region, write it, report timing
# --------------------------------------------------------------------------------------------

BatchFunction = Callable[..., list]
"""``critical_intensity_batch(tasks, limit_states, accuracy=..., upper=..., omega_n=...,
zeta=...) -> list[CriticalResult]`` with a task ``(R, tan_alpha, motion, mode)``."""


def fill_spectra_region(path: str | Path, index: int, motions: MotionSource, *,
                        batch: BatchFunction | None = None) -> dict[str, float]:
    """Compute and store the critical intensities of one region of a spectra store.

    The region is one mode, one motion, one tan α and a run of sizes R; every limit state
    of the store is found in the same search. Tolerances and search options come from the
    store's ``tolerances`` and ``search_options`` attributes, so a worker needs nothing else.

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
        from ..spectra.critical import critical_intensity_batch as batch
    layout = open_layout(path)
    attrs = read_attrs(path)
    rc = region_coords(layout, index)
    (mode,), (name,), (tan_alpha,) = rc["mode"], rc["motion"], rc["tan_alpha"]
    motion = _motion(motions, name)
    limit_states = [str(s) for s in layout.coords["limit_state"]]
    region = layout.region(index)
    # (limit_state,): the cells of this region some run of the study asks for
    wanted = read_requested(path, layout)[region["mode"], :, region["tan_alpha"]][0, :, 0]
    computed = [ls for ls, w in zip(limit_states, wanted, strict=True) if w]
    tasks = [(float(R), float(tan_alpha), motion, str(mode)) for R in rc["R"]]
    results = batch(tasks, computed, accuracy=attrs["tolerances"],
                    **attrs.get("search_options", {})) if computed else []
    flat = spectra_values(results, limit_states, computed) if computed else \
        _unrequested_values(len(limit_states), len(tasks))
    flat["pga_crit_g"] = flat["pga_crit"] * float(tan_alpha)  # PGA [g] = I·tan α
    # (limit_state, R) -> (mode=1, limit_state, motion=1, tan_alpha=1, R)
    # a store made before a variable existed (e.g. ``unresolved``) keeps its own variables
    values = {k: v[None, :, None, None, :] for k, v in flat.items() if k in layout.variables}
    # NaN is an answer where the limit state was not reached, or where nobody asked
    nan_ok = values["not_reached"] | ~wanted[None, :, None, None, None]
    write_region(path, layout, index, values,
                 nan_allowed={"pga_crit": nan_ok, "pga_crit_g": nan_ok})
    return {"index": index, "points": len(tasks), "seconds": time.perf_counter() - t0}


def _motion(source: MotionSource, name: str) -> GroundMotion:
    by_name = motions_by_name(source)
    if name not in by_name:
        raise ValueError(f"motion {name!r} of the store is not in the ensemble "
                         f"{sorted(by_name)}")
    return by_name[name]


def _unrequested_values(n_ls: int, n: int) -> dict[str, np.ndarray]:
    """Arrays (limit_state, point) of cells not computed: NaN and every flag false."""
    return {
        "pga_crit": np.full((n_ls, n), np.nan),
        "not_reached": np.zeros((n_ls, n), dtype=bool),
        "non_monotonic": np.zeros((n_ls, n), dtype=bool),
        "failed": np.zeros((n_ls, n), dtype=bool),
        "unresolved": np.zeros((n_ls, n), dtype=bool),
        "n_analyses": np.zeros((n_ls, n), dtype=np.int32),
    }


def spectra_values(results: Sequence[Any], limit_states: Sequence[str],
                   computed: Sequence[str] | None = None) -> dict[str, np.ndarray]:
    """Arrays (limit_state, point) of a batch of critical-intensity results.

    Parameters
    ----------
    results : sequence of CriticalResult
        One per point, as returned by :func:`rocking.spectra.critical.critical_intensity_batch`:
        ``limit_states`` (names), arrays ``intensity`` (PGA/(g tan α) [-], NaN where not
        reached), ``not_reached``, ``non_monotonic``, ``failed``, ``unresolved`` (false
        where a result has none) and the count ``n_analyses``.
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
            out["not_reached"][i, j] = res.not_reached[k]
            out["non_monotonic"][i, j] = res.non_monotonic[k]
            out["failed"][i, j] = res.failed[k]
            unresolved = getattr(res, "unresolved", None)
            out["unresolved"][i, j] = False if unresolved is None else unresolved[k]
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
        from ..spectra.tilt_map import tilt_map
    layout = open_layout(path)
    attrs = read_attrs(path)
    rc = region_coords(layout, index)
    (mode,) = rc["mode"]
    out = tilt_map([float(r) for r in rc["R"]], float(attrs["tan_alpha"]),
                   _motion(motions, attrs["motion"]), [float(i) for i in rc["intensity"]],
                   str(mode), accuracy=attrs["tolerances"], **attrs.get("model_options", {}))
    values = {k: out[k].transpose("R", "intensity").values[None]
              for k in ("theta_max_over_alpha", "overturned", "failed")}
    write_region(path, layout, index, values,
                 nan_allowed={"theta_max_over_alpha": values["failed"]})
    return {"index": index, "points": int(values["failed"].size),
            "seconds": time.perf_counter() - t0}
