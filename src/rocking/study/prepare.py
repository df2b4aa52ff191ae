"""The store a compute rule fills: reused if it was made for this configuration, else made anew.

A study's stores (``results/<study>/spectra.zarr``, ``tilt_map.zarr``) are side products of
their compute rule, not Snakemake outputs: Snakemake deletes the outputs of a failed job, and a
store must survive a killed run so that the next run computes only its missing chunks. The
rule's output is the completion marker (``*.done.json``); the store itself is prepared here,
at the start of the rule:

- no store yet: create an empty one (layout, coordinates, CF attributes, ``requested`` mask);
- a store of the same configuration hash: keep it and resume in it;
- a store of another configuration: replace it (its results answer another question).
"""

from __future__ import annotations

import logging
import shutil
from pathlib import Path
from typing import Any

from .. import __version__
from ..spectra.accuracy import get_accuracy
from . import store, tasks
from .spec import Damping, SpectraSpec, TiltMapSpec

log = logging.getLogger(__name__)


def _state(path: Path, config_digest: str) -> str:
    """``"missing"``, ``"same"`` or ``"other"`` (another configuration or unreadable)."""
    if not path.exists():
        return "missing"
    try:
        return "same" if store.read_attrs(path).get("config_hash") == config_digest else "other"
    except Exception:  # a directory that is not a readable store: replace it too
        return "other"


def _prepare(path: str | Path, config_digest: str, create) -> str:
    path = Path(path)
    state = _state(path, config_digest)
    if state == "same":
        log.info("store %s: same configuration (%s), resuming in it", path, config_digest)
        return "resumed"
    if state == "other":
        log.info("store %s: made for another configuration, replacing it", path)
        shutil.rmtree(path)
    create(path)
    return "created" if state == "missing" else "replaced"


def spectra_store(path: str | Path, spec: SpectraSpec | dict[str, Any], config_digest: str,
                  motions: str | Path) -> str:
    """Prepare the spectra store of a study.

    Parameters
    ----------
    path : str or Path
        ``results/<study>/spectra.zarr``.
    spec : SpectraSpec or dict
        The study's result-affecting description, or its ``to_attrs()`` mapping (the
        workflow's ``spectra_spec``).
    config_digest : str
        ``spec.digest``.
    motions : str or Path
        The ensemble file.

    Returns
    -------
    str
        ``"created"``, ``"resumed"`` or ``"replaced"``.
    """

    s = spec if isinstance(spec, SpectraSpec) else SpectraSpec.from_attrs(spec)

    def create(p: Path) -> None:
        ensemble = tasks.ensemble_attrs(motions, s.ensemble.name)
        names = [m["name"] for m in ensemble["motions"]]
        chunk_R = s.chunk_R
        if chunk_R == "auto":
            npts = min(m["npts"] for m in ensemble["motions"])
            chunk_R = tasks.auto_chunk_R(len(s.R), npts, s.min_task_seconds)
        plan = s.plan
        layout = tasks.spectra_layout(plan.modes, plan.limit_states, names, plan.tan_alpha,
                                      s.R, chunk_R)
        attrs = {
            "title": f"Seismic performance rocking spectra, study {s.study}",
            "config": s.to_attrs(),
            "tolerances": get_accuracy(s.accuracy).to_dict(),
            "search_options": s.search_options(),
            "rocking_version": __version__,
            "ensemble": ensemble,
            "pga_crit_definition": "PGA/(g tan alpha), PGA = max sqrt(ax^2 + ay^2) of the pair; "
                                   "pga_crit_g = pga_crit * tan_alpha is the same PGA in g",
        }
        store.create_store(p, layout, attrs, config_digest,
                           coords=tasks.identity_coords(ensemble),
                           static={store.REQUESTED: plan.requested})
        skipped = len(store.regions_not_requested(layout, plan.requested))
        log.info("created %s: %d chunks of %d sizes R (%d not requested by any run, marked "
                 "done), motions %s; points per mode %s", p, layout.n_regions, chunk_R, skipped,
                 names, plan.points(len(names), len(s.R)))

    return _prepare(path, config_digest, create)


def tilt_map_store(path: str | Path, spec: TiltMapSpec | dict[str, Any], config_digest: str,
                   motions: str | Path) -> str:
    """Prepare the Fig 7 tilt-map store of a study (``spec``: a :class:`TiltMapSpec` or its
    ``to_attrs()``, the workflow's ``tilt_map_spec``); returns ``"created"``, ``"resumed"``
    or ``"replaced"``."""
    s = spec if isinstance(spec, TiltMapSpec) else TiltMapSpec.from_attrs(spec)

    def create(p: Path) -> None:
        ensemble = tasks.ensemble_attrs(motions, s.ensemble.name)
        names = [m["name"] for m in ensemble["motions"]]
        motion = s.motion or names[0]  # the record comes first in an ensemble
        if motion not in names:
            raise ValueError(f"studies.{s.study}.tilt_map.motion={motion!r} is not a "
                             f"motion of ensemble {s.ensemble.name!r}: {names}")
        layout = tasks.tilt_map_layout(s.modes, s.R, s.intensity, s.chunk_R)
        who = next(m for m in ensemble["motions"] if m["name"] == motion)
        attrs = {
            "title": f"Peak tilt over size and intensity (Fig 7), study {s.study}",
            "config": s.to_attrs(),
            "motion": motion,
            "tan_alpha": s.tan_alpha,
            "tolerances": get_accuracy(s.accuracy).to_dict(),
            "model_options": Damping.options(s.damping),
            "rocking_version": __version__,
            "ensemble": ensemble,
            "motion_processing": who["processing"],
            "motion_PGA_g": who["PGA"],
        }
        pga_g = ("intensity", [i * s.tan_alpha for i in s.intensity])
        store.create_store(p, layout, attrs, config_digest, coords={"pga_g": pga_g})
        log.info("created %s: %d chunks, motion %s", p, layout.n_regions, motion)

    return _prepare(path, config_digest, create)


KINDS = {"spectra": spectra_store, "tilt_map": tilt_map_store}
"""Store kind → its preparation function."""


def compute(kind: str, path: str | Path, spec: dict[str, Any], config_digest: str,
            motions: str | Path, **fill_kw) -> dict[str, Any]:
    """Prepare a store of ``kind`` (``"spectra"`` or ``"tilt_map"``) and fill it on Dask.

    ``fill_kw`` go to :func:`rocking.study.cluster.fill_store` (workers, scheduler, progress,
    task key and label). Returns its summary with ``"store_state"`` added (created, resumed or
    replaced).
    """
    from . import cluster

    if kind not in KINDS:
        raise ValueError(f"kind must be one of {sorted(KINDS)}, got {kind!r}")
    state = KINDS[kind](path, spec, config_digest, motions)
    fill = tasks.fill_spectra_region if kind == "spectra" else tasks.fill_tilt_map_region
    summary = cluster.fill_store(path, fill, motions, config_digest=config_digest, **fill_kw)
    return {**summary, "store_state": state}
