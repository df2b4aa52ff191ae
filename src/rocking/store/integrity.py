"""Verification of a store: every finished region re-read, damaged ones made pending again.

Every chunk of a store carries a CRC-32C checksum (:func:`rocking.store.chunk_codecs`),
checked on every read. :func:`verify_store` reads every region marked done; a chunk that is
unreadable, missing or inconsistent with the others resets the region's done flag, so the
next fill recomputes exactly those regions.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np
import zarr

from rocking.store import (
    CHECKSUM_CODEC,
    DONE,
    REPAIR,
    REQUESTED_DIMS,
    StoreHandle,
    every_chunk,
    open_group,
)
from rocking.store.layout import Layout, region_coords


def has_checksums(path: str | Path) -> bool:
    """Whether every result array of a store carries :data:`CHECKSUM_CODEC` (stores made
    before checksums were introduced do not, and must be rebuilt to get them)."""
    return _checksummed(open_group(path, "r"))


def _checksummed(group: zarr.Group) -> bool:
    return all(any(getattr(c, "to_dict", lambda: {})().get("name") == CHECKSUM_CODEC
                   for c in group[k].metadata.codecs) for k in group.array_keys())


def chunk_file(path: Path, array: zarr.Array, sel: tuple[slice, ...]) -> Path:
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
        return chunk_file(self.path, self.arrays[name], sel)

    def exists(self, name: str, sel: tuple[slice, ...]) -> bool:
        return self.chunk_file(name, sel) in self.files[name]


def _region_problem(path: Path, group: zarr.Group, layout: Layout, index: int,
                    requested: np.ndarray | None, checksums: bool,
                    reader: _Reader | None = None) -> str | None:
    """What is wrong with the stored results of a done region, or None.

    Every chunk of the region is read (its checksum checked); with checksums, each must
    exist as a file (finished regions write all their chunks). Then the values must be
    consistent: a float NaN only where a flag explains it, ``pga_crit_g = pga_crit · tan α``.
    """
    region = layout.region(index)
    asked = True
    if requested is not None and "mode" in region and "tan_alpha" in region:
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
    if "pga_crit" in values and requested is not None:
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


def verify_store(store: StoreHandle, say: Callable[[str], None] | None = None,
                 repair: bool = True, not_done: list[int] | None = None) -> list[int]:
    """Re-read every finished region; mark the damaged ones not done, to be recomputed.

    A region counts as damaged when its done flag is unreadable, when a chunk of its results
    is unreadable (checksum mismatch, truncated file), missing (stores with checksums write
    every chunk of a finished region) or inconsistent (:func:`_region_problem`). Its done
    flag is reset, so the next fill recomputes exactly those regions, and deterministic
    tasks end with the same bytes as an undamaged run.

    Parameters
    ----------
    store : StoreHandle
        The open store (:func:`open_checked`), mode ``"r+"`` to repair.
    say : callable, optional
        Where the per-region lines go (default: a warning).
    repair : bool
        Reset the done flag of damaged regions (False: only report them; a store opened
        read-only is enough).
    not_done : list, optional
        Receives the regions not marked done (read on the way: no second read of the mask).

    Returns
    -------
    list of int
        The regions found damaged (now pending).

    Raises
    ------
    ValueError
        Naming the store and the remedy, when the metadata or coordinates are unreadable;
        when ``repair`` is asked of a store opened read-only.
    """
    path, layout, group = store.path, store.layout, store.group
    if repair and store.mode != "r+":
        raise ValueError(f"store {str(path)!r} is open read-only: open it with mode 'r+' to "
                         "repair it")
    say = say or (lambda text: warnings.warn(text, stacklevel=2))
    try:
        # the mask (mode, limit_state, tan_alpha) belongs to spectra stores; a stripes store
        # (one tan α, no such dimension) or a tilt map has none and asks for every cell
        spectra_like = all(d in layout.coords for d in REQUESTED_DIMS)
        requested = store.requested() if spectra_like else None
        checksums = _checksummed(group)
        for name in store.describing_arrays():  # auxiliary coordinates too (source_record)
            group[name][...]
    except Exception as exc:
        raise _unreadable(path, exc) from exc
    if not checksums:
        say(f"store {path} was made without chunk checksums (by an older version): a "
            f"flipped bit cannot be detected, only values that contradict each other; "
            f"delete the store to rebuild it with checksums")
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
                if not_done is not None:
                    not_done.append(index)
                continue
            problem = _region_problem(path, group, layout, index, requested, checksums,
                                      reader)
        if problem is not None:
            say(f"store {path}: chunk {index} damaged, {problem}"
                + ("; recomputing it" if repair else ""))
            if repair:
                every_chunk(group[DONE])[sel] = False
            damaged.append(index)
    return damaged


def open_checked(path: str | Path, mode: str = "r") -> StoreHandle:
    """The store at ``path`` opened once (:class:`~rocking.store.StoreHandle`).

    Raises
    ------
    ValueError
        Naming the store and the remedy, when its metadata or coordinates are unreadable.
    """
    try:
        return StoreHandle.open(path, mode)
    except Exception as exc:
        raise _unreadable(path, exc) from exc


def _unreadable(path: str | Path, exc: Exception) -> ValueError:
    return ValueError(f"store {str(path)!r}: metadata or coordinates are unreadable ({exc}); "
                      f"{REPAIR} (coordinates are restored from the configuration), or delete "
                      f"the store")


def require_intact(path: str | Path, say: Callable[[str], None] | None = None) -> None:
    """Check a store before its numbers are read into others (aggregates, tables): every
    region complete (done, whether the study asked for it or not) and every finished one
    verified (:func:`verify_store`).

    A region whose done flag is gone (its chunk file deleted) counts as not computed, never
    as an empty answer: a table of the store would otherwise hold NaN rows for it.

    Raises
    ------
    ValueError
        Naming the store, its damaged or missing regions (with the coordinates of the first)
        and the remedy; the store is not changed (opened read-only), so a damaged chunk is
        never tabulated.
    """
    store = open_checked(path, "r")
    layout = store.layout
    missing: list[int] = []
    damaged = verify_store(store, say=say, repair=False, not_done=missing)
    if damaged:
        raise ValueError(f"store {str(path)!r}: {len(damaged)} damaged chunks {damaged}; "
                         f"{REPAIR}")
    if missing:
        first = {d: _plain(v) for d, v in region_coords(layout, missing[0]).items()
                 if d in layout.task_dims}
        raise ValueError(f"store {str(path)!r}: {len(missing)} chunks not computed "
                         f"{_some(missing)} (the first at {first}); {REPAIR}")


def _plain(values: np.ndarray) -> list:
    """Coordinate values as plain Python numbers and strings (for a message)."""
    return [v.item() if isinstance(v, np.generic) else v for v in np.atleast_1d(values)]


def _some(indices: Sequence[int], n: int = 10) -> str:
    """At most ``n`` indices, the rest counted."""
    head = ", ".join(map(str, indices[:n]))
    return f"[{head}{f', ... {len(indices) - n} more' if len(indices) > n else ''}]"
