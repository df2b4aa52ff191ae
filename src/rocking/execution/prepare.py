"""The store a compute rule fills: reused if it was made for this configuration, else made anew.

A study's stores are side products of their compute rule, not Snakemake outputs: Snakemake
deletes the outputs of a failed job, and a store must survive a killed run so that the next run
computes only its missing chunks. The rule's output is the completion marker (``*.done.json``);
the store itself is prepared here, at the start of the rule.

A store is named after the digest of what decides its numbers (:func:`keyed`:
``<root>/<study>/spectra-<digest>.zarr``), so a changed accuracy, grid or bound adds a store
and changing it back finds the earlier one finished; the unkeyed name (``spectra.zarr``) is a
relative symbolic link to the store of the latest run (:func:`link_alias`). At the start of
the rule:

- no store yet: create an empty one (layout, coordinates, CF attributes, ``requested`` mask);
- a store of the same configuration hash: keep it and resume in it;
- an unreadable store or one of another hash under this key: replace it;
- a store made before names were keyed (a directory at the unkeyed name): moved to the keyed
  name of its own hash (:func:`adopt_unkeyed`), so it is resumed, not recomputed.
"""

from __future__ import annotations

import logging
import os
import shutil
from pathlib import Path

from rocking import __version__, store
from rocking.config.damping import Damping
from rocking.config.products import SpectraSpec, TiltMapSpec
from rocking.provenance import scratch_path

log = logging.getLogger(__name__)


def _state(path: Path, config_digest: str) -> str:
    """``"missing"``, ``"same"`` or ``"other"`` (another configuration or unreadable)."""
    if not path.exists():
        return "missing"
    try:
        return "same" if store.read_attrs(path).get("config_hash") == config_digest else "other"
    except Exception:  # a directory that is not a readable store: replace it too
        return "other"


def keyed(path: str | Path, digest: str) -> Path:
    """``path`` with ``-<digest>`` before its suffix (``spectra.zarr`` → ``spectra-<digest>.zarr``).

    Raises
    ------
    ValueError
        If ``digest`` is not a non-empty hexadecimal string.
    """
    if not digest or any(c not in "0123456789abcdef" for c in digest):
        raise ValueError(f"digest must be lowercase hexadecimal, got {digest!r}")
    path = Path(path)
    return path.with_name(f"{path.stem}-{digest}{path.suffix}")


def unkeyed(path: str | Path, digest: str) -> Path:
    """Inverse of :func:`keyed`; ``path`` itself when its name does not end in the digest."""
    path = Path(path)
    tail = f"-{digest}{path.suffix}"
    if digest and path.name.endswith(tail):
        return path.with_name(path.name[: -len(tail)] + path.suffix)
    return path


def adopt_unkeyed(alias: str | Path) -> Path | None:
    """Move a store made before names were keyed (a real directory at ``alias``) to the keyed
    name of its own ``config_hash``; return where it went, or None when there was none.

    A store that cannot be read, or whose keyed name is taken, is left where it is (with a
    warning): nothing is deleted here.
    """
    alias = Path(alias)
    if alias.is_symlink() or not alias.is_dir():
        return None
    try:
        digest = str(store.read_attrs(alias)["config_hash"])
        target = keyed(alias, digest)
    except Exception as exc:  # not a store of ours: not ours to move
        log.warning("%s is not a readable store (%s); left in place", alias, exc)
        return None
    if target.exists():
        log.warning("%s and %s both exist; %s left in place", alias, target, alias)
        return None
    alias.rename(target)
    log.info("store %s (made before store names were keyed) moved to %s", alias, target)
    return target


def link_alias(path: str | Path, alias: str | Path) -> bool:
    """Point ``alias`` (a relative symbolic link in the same folder) at the store ``path``.

    An existing link is replaced atomically; a real file or directory at ``alias`` is never
    touched (returns False, with a warning).
    """
    path, alias = Path(path), Path(alias)
    if path.parent != alias.parent:
        raise ValueError(f"alias {alias} must lie beside the store {path}")
    if alias.exists() and not alias.is_symlink():
        log.warning("%s is not a link; the latest store is %s", alias, path)
        return False
    tmp = scratch_path(alias, "link")
    tmp.symlink_to(path.name, target_is_directory=True)
    os.replace(tmp, alias)
    return True


def ready_store(path: str | Path, config_digest: str, create) -> str:
    """Make the store at ``path`` ready for the configuration ``config_digest``: adopt an
    unkeyed store of this configuration, resume one of the same hash, or call ``create``.

    Returns
    -------
    str
        What was done: ``"resumed"``, ``"created"`` or ``"replaced"`` (as logged).
    """
    path = Path(path)
    alias = unkeyed(path, config_digest)
    if alias != path:
        adopt_unkeyed(alias)
    state = _state(path, config_digest)
    if state == "same":
        log.info("store %s: same configuration (%s), resuming in it", path, config_digest)
        repair_coordinates(path, create)
    elif state == "other":
        log.info("store %s: made for another configuration, replacing it", path)
        shutil.rmtree(path)
    if state != "same":
        create(path)
    if alias != path:
        link_alias(path, alias)
    return {"same": "resumed", "missing": "created"}.get(state, "replaced")


def repair_coordinates(path: str | Path, create) -> list[str]:
    """Verify the coordinates and static arrays of a store against the same arrays made anew
    (``create`` into a sibling folder) and restore those damaged: its coordinates are
    verified like its data, and repaired by the same rerun. Returns the arrays restored."""
    path = Path(path)
    fresh = scratch_path(path, "reference")
    try:
        with store.describing_only():
            create(fresh)
        damaged = store.differing_arrays(path, fresh)
        if damaged:
            log.warning("store %s: coordinates %s damaged (unreadable, missing or other "
                        "values); restored from the configuration", path, damaged)
            store.restore_arrays(path, fresh, damaged)
    finally:
        shutil.rmtree(fresh, ignore_errors=True)
    return damaged


def create_spectra_store(path: Path, s: SpectraSpec, config_digest: str,
                         motions: str | Path) -> None:
    """Create the empty spectra store of a study at ``path`` (the spectra's
    :attr:`~rocking.execution.products.Product.create`).

    Parameters
    ----------
    path : Path
        Where (:func:`ready_store` chooses: the keyed name, or a reference beside it).
    s : SpectraSpec
        The study's result-affecting description.
    config_digest : str
        ``s.digest``.
    motions : str or Path
        The ensemble file.
    """
    from rocking.execution import tasks  # zarr, xarray: imported by the job that creates
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
        "tolerances": s.accuracy.to_dict(),
        "quantity": dict(s.quantity),
        "search_options": s.search_options(),
        "rocking_version": __version__,
        "ensemble": ensemble,
        "pga_crit_definition": "PGA/(g tan alpha), PGA = max sqrt(ax^2 + ay^2) of the pair; "
                               "pga_crit_g = pga_crit * tan_alpha is the same PGA in g",
    }
    store.create_store(path, layout, attrs, config_digest,
                       coords=tasks.identity_coords(ensemble),
                       static={store.REQUESTED: plan.requested})
    skipped = len(store.regions_not_requested(layout, plan.requested))
    log.info("created %s: %d chunks of %d sizes R (%d not requested by any run, marked "
             "done), motions %s; points per mode %s", path, layout.n_regions, chunk_R, skipped,
             names, plan.points(len(names), len(s.R)))


def create_tilt_map_store(path: Path, s: TiltMapSpec, config_digest: str,
                          motions: str | Path) -> None:
    """Create the empty Fig 7 tilt-map store of a study at ``path`` (as
    :func:`create_spectra_store`).

    Raises
    ------
    ValueError
        When the map's motion is not a motion of the ensemble.
    """
    from rocking.execution import tasks  # zarr, xarray: imported by the job that creates
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
        "tolerances": s.accuracy.to_dict(),
        "model_options": Damping.options(s.damping),
        "rocking_version": __version__,
        "ensemble": ensemble,
        "motion_processing": who["processing"],
        "motion_PGA_g": who["PGA"],
    }
    pga_g = ("intensity", [i * s.tan_alpha for i in s.intensity])
    store.create_store(path, layout, attrs, config_digest, coords={"pga_g": pga_g})
    log.info("created %s: %d chunks, motion %s", path, layout.n_regions, motion)
