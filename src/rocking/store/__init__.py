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
:class:`~rocking.store.layout.Layout`; every chunk carries a checksum (:func:`chunk_codecs`)
that :func:`rocking.store.integrity.verify_store` checks. What the study's stores hold and how
a worker fills a region: :mod:`rocking.execution.tasks`.

This module is the stores' one public entry; their code is split by what it does:
:mod:`.store_read` (open a store, read its layout, masks and attributes),
:mod:`.store_write` (create, write a region, checksums, consolidate), :mod:`.store_resume`
(compare and restore the describing arrays, one run per store) and :mod:`.store_handle`
(:class:`StoreHandle`, a store opened once).
"""

from __future__ import annotations

from rocking._lazy import lazy_exports

# Imported when first used (rocking._lazy): a light submodule (rocking.store.attrs, the
# digests that name stores, read while Snakemake plans a run) must not pull in zarr and
# dask.array with the package.
_EXPORTS = {
    "StoreHandle": "handle",
    **dict.fromkeys(("DONE", "REPAIR", "REQUESTED", "REQUESTED_DIMS", "describing_arrays",
                     "done_mask", "open_group", "open_layout", "pending_regions", "read_attrs",
                     "read_requested", "regions_not_requested"), "read"),
    **dict.fromkeys(("differing_arrays", "locked", "restore_arrays"), "resume"),
    **dict.fromkeys(("CHECKSUM_CODEC", "chunk_codecs", "consolidate", "create_store",
                     "describing_only", "every_chunk", "write_region"), "write"),
}

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
__all__ = sorted(_EXPORTS)
