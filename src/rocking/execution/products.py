"""The products of a study: every store a study can make, one entry of :data:`PRODUCTS` each.

A product is a part of :class:`~rocking.config.study.StudySpec` (the spectra, the Fig 7
tilt map, the stripes) with its own store ``<root>/<study>/<name>-<digest>.zarr``. Its entry
says how that store is described, made and filled:

- ``spec``: the class of its part of the study (``to_attrs``, ``from_attrs``, ``digest``);
- ``create``: makes the empty store (layout, coordinates, attributes);
- ``fill``: the task body a Dask worker runs on one region;
- ``analyses_per_point``: what a point costs, for the choice of running in process.

Everything else is written once over the table: :func:`planned_spec` (the part a workflow job
was planned for), :func:`prepare_store` (created, resumed or replaced,
:func:`rocking.execution.prepare.ready_store`) and :func:`compute` (prepared, then filled on Dask
through one :class:`~rocking.store.StoreHandle`); in the workflow, the compute rule and
the ``product_*`` helpers of ``workflow/rules/common.smk``. What a product's numbers become
later (aggregates, tables, figures) are rules of their own.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from rocking import store
from rocking.config.products import SpectraSpec, StripesSpec, TiltMapSpec
from rocking.config.study import StudySpec
from rocking.execution import prepare

__all__ = ["PRODUCTS", "Product", "compute", "planned_spec", "prepare_store", "product"]

SPECTRA_ANALYSES_PER_POINT = 70
"""Typical analyses of one critical-intensity search (the paper run: 73–231 per point on
average per mode; small sizes R need fewer) for the in-process estimate."""


@dataclass(frozen=True)
class Product:
    """One kind of store a study makes.

    Attributes
    ----------
    name : str
        The study's part (``StudySpec.<name>``), the store's name (``<name>-<digest>.zarr``),
        the workflow's compute rule and completion marker (``<name>.done.json``).
    spec : type
        Class of the part (:mod:`rocking.config.products`).
    creates : str
        ``"module:function"`` of ``create(path, spec, config_digest, motions)``, the empty
        store at ``path`` (:attr:`create`).
    fills : str
        ``"module:function"`` of the task body ``fill(path, index, motions=...)``, which
        computes and writes one region (:attr:`fill`).
    analyses_per_point : int
        Analyses one point of the store is expected to run [-].

    The two functions are named, not imported: Snakemake reads this registry while it plans
    a run, and their modules (zarr, dask.array, the engine) are imported by the jobs that
    call them.
    """

    name: str
    spec: type
    creates: str
    fills: str
    analyses_per_point: int = 1

    @property
    def create(self) -> Callable[[Path, Any, str, str | Path], None]:
        return _function(self.creates)

    @property
    def fill(self) -> Callable[..., dict]:
        return _function(self.fills)


def _function(where: str) -> Callable:
    module, name = where.split(":")
    return getattr(importlib.import_module(module), name)


PRODUCTS: dict[str, Product] = {p.name: p for p in (
    Product("spectra", SpectraSpec, "rocking.execution.prepare:create_spectra_store",
            "rocking.execution.tasks:fill_spectra_region", SPECTRA_ANALYSES_PER_POINT),
    Product("tilt_map", TiltMapSpec, "rocking.execution.prepare:create_tilt_map_store",
            "rocking.execution.tasks:fill_tilt_map_region"),
    Product("stripes", StripesSpec, "rocking.execution.stripes:create_stripes_store",
            "rocking.execution.stripes:fill_stripes_region"),
)}
"""Every product, by name, in the order a study lists them."""


def product(kind: str) -> Product:
    """The entry of ``kind``.

    Raises
    ------
    ValueError
        Naming the kind and the known ones.
    """
    if kind not in PRODUCTS:
        raise ValueError(f"kind must be one of {sorted(PRODUCTS)}, got {kind!r}")
    return PRODUCTS[kind]


def planned_spec(config: Mapping[str, Any], study: str, kind: str, digest: str) -> Any:
    """The part ``kind`` (a name of :data:`PRODUCTS`) of study ``study``, rebuilt from the
    workflow configuration, checked against the ``digest`` the job was planned with (a
    rule's parameters carry only that hash, so its "reason" lines stay short).

    Raises
    ------
    ValueError
        If the kind is unknown, the study has no such part or its digest differs (naming
        both digests).
    """
    spec = getattr(StudySpec.from_config(config, study), product(kind).name)
    got = None if spec is None else spec.digest
    if got != digest:
        raise ValueError(f"studies.{study}: the {kind} settings of this configuration hash to "
                         f"{got}, the job was planned for {digest}; run snakemake again")
    return spec


def prepare_store(kind: str, path: str | Path, spec: Any, config_digest: str,
                  motions: str | Path) -> str:
    """Make the store of ``kind`` at ``path`` ready: resumed, created or replaced.

    Parameters
    ----------
    kind : str
        A name of :data:`PRODUCTS`.
    path : str or Path
        ``<root>/<study>/<kind>-<digest>.zarr`` (:func:`rocking.execution.prepare.keyed`).
    spec : object or dict
        The product's part of the study, or its ``to_attrs()`` mapping.
    config_digest : str
        ``spec.digest``.
    motions : str or Path
        The ensemble file.

    Returns
    -------
    str
        ``"created"``, ``"resumed"`` or ``"replaced"``.
    """
    p = product(kind)
    s = spec if isinstance(spec, p.spec) else p.spec.from_attrs(spec)
    return prepare.ready_store(path, config_digest,
                               lambda where: p.create(where, s, config_digest, motions))


def compute(kind: str, path: str | Path, spec: Any, config_digest: str,
            motions: str | Path, **fill_kw) -> dict[str, Any]:
    """Prepare the store of ``kind`` (:func:`prepare_store`) and fill it on Dask.

    ``fill_kw`` go to :func:`rocking.execution.cluster.fill_store` (workers, scheduler, progress,
    task key and label). Returns its summary with ``"store_state"`` added (created, resumed or
    replaced).
    """
    from rocking.execution import cluster
    from rocking.store import integrity

    p = product(kind)
    # one run at a time per store: another working directory starting the same study waits
    # for nothing and deletes nothing, it stops naming the run that holds the store
    with store.locked(path):
        state = prepare_store(kind, path, spec, config_digest, motions)
        handle = integrity.open_checked(path, "r+")
        summary = cluster.fill_store(handle, p.fill, motions, config_digest=config_digest,
                                     analyses_per_point=p.analyses_per_point, **fill_kw)
    return {**summary, "store_state": state}
