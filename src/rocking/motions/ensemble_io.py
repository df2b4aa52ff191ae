"""Save and load a list of ground motions as one NetCDF file (``results/motions/<name>.nc``).

Layout (see docs/design.md): variables ``ax``, ``ay`` with dims (motion, time), zero-padded to
the longest motion, ``npts`` (motion) giving each motion's own length, ``dt`` (motion),
``metadata`` (motion) holding each motion's metadata as a JSON string, and the coordinate
``motion`` with the names (unique). Float64 values are stored as they are, so the round trip
is lossless; metadata comes back as JSON does (tuples as lists, numpy scalars as numbers).

A file whose motions include one with a vertical component (a record of an ensemble with
``vertical: true``; synthetic pairs stay horizontal) also holds ``az`` (motion, time) [m/s²,
positive up] and ``has_az`` (motion, 1 where the motion carries a vertical component, 0
where it has none: its row of ``az`` is zeros). A file without them is read as before
(every motion horizontal), and a file of horizontal motions is written without them, byte
for byte as before. The file's digest (below) covers ``az`` like every other variable.

Each motion's identity is also stored in plain variables over ``motion``, readable without
parsing JSON (:func:`rocking.motions.identity.identity`): ``source_record`` (the recorded pair
it comes from: in a suite, which record), ``kind`` (``record`` or ``synthetic``), ``processing``
(one line: rotation, high-pass corner, padding, cut), ``rotation_deg``, ``highpass_fc_hz``,
``padding_s``, ``duration_s``, ``PGA`` [g], ``Ia_x``, ``Ia_y`` [m/s]. Every variable has CF
``units`` and ``long_name``.

Beside each file lies its digest, ``<file>.sha256`` (one ``sha256sum`` line: ``sha256sum -c``
checks it too), written when the file is made (:func:`write_digest`) and checked before every
read (:func:`verify_digest`): a file changed or damaged after it was made is refused with a line
naming it and the command that rebuilds it, never read into other numbers.
"""

from __future__ import annotations

import json
import logging
import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from rocking import _json
from rocking.motions.identity import identity
from rocking.motions.motion import GroundMotion
from rocking.motions.readers import file_sha256
from rocking.provenance import write_atomic
from rocking.units import attrs as _attrs

__all__ = ["FORMAT", "IDENTITY", "MotionsDigestError", "digest_path", "ensemble_attrs",
           "load_ensemble", "open_netcdf", "save_ensemble", "verify_digest", "write_digest"]

log = logging.getLogger(__name__)

FORMAT = "rocking-ensemble-1"
"""Value of the ``format`` attribute; bumped when the layout changes."""

IDENTITY = ("source_record", "kind", "processing", "rotation_deg", "highpass_fc_hz",
            "padding_s", "duration_s", "PGA", "Ia_x", "Ia_y")
"""Per-motion identity variables (see :func:`rocking.motions.identity.identity`)."""

_TEXT = ("source_record", "kind", "processing")

REBUILD = ("rebuild the motions: `snakemake --forcerun motions` in the workflow (it rewrites "
           "the file and its digest; the stores resume), or run again the `rocking motions` "
           "command that wrote it")
"""The remedy a motions file that fails its digest names."""


class MotionsDigestError(ValueError):
    """A motions file whose bytes differ from the digest written when it was made."""


def digest_path(path: str | Path) -> Path:
    """Where the digest of the motions file ``path`` lies: ``<path>.sha256``."""
    p = Path(path)
    return p.with_name(p.name + ".sha256")


def write_digest(path: str | Path, sha256: str | None = None) -> str:
    """Write ``<path>.sha256`` (``sha256sum`` format), atomically; return the digest (hex)."""
    p = Path(path)
    sha256 = sha256 or file_sha256(p)
    side = digest_path(p)
    write_atomic(side, lambda tmp: tmp.write_text(f"{sha256}  {p.name}\n", encoding="ascii"))
    return sha256


def verify_digest(path: str | Path) -> str:
    """Check a motions file against the digest written beside it when it was made.

    A file without a digest (made before digests were written) has one recorded now, with a
    warning: from then on it is checked like the others.

    Returns
    -------
    str
        The file's sha256 (hex), so that callers need not hash it again.

    Raises
    ------
    MotionsDigestError
        Naming the file, both digests and the command that rebuilds the motions.
    """
    p = Path(path)
    if not p.is_file():
        raise FileNotFoundError(f"ensemble file not found: {p}")
    found = file_sha256(p)
    side = digest_path(p)
    try:
        text = side.read_text(encoding="ascii", errors="replace").split()
    except FileNotFoundError:
        try:
            write_digest(p, found)
        except OSError as exc:  # a read-only results folder: checked from the next write on
            log.warning("motions file %s has no digest (made before digests were written) "
                        "and none can be written (%s)", p, exc)
        else:
            log.warning("motions file %s has no digest (made before digests were written): "
                        "recorded now in %s", p, side)
        return found
    expected = text[0] if text else ""
    if found != expected:
        raise MotionsDigestError(
            f"motions file {str(p)!r} has sha256 {found} but was written with sha256 "
            f"{expected or '(unreadable)'} ({side}): it was changed or damaged after it was "
            f"made; {REBUILD}")
    return found


def open_netcdf(path: str | Path) -> xr.Dataset:
    """Open a NetCDF file for reading, without memory-mapping classic files.

    scipy's reader maps classic (NetCDF3) files into memory and warns ("Cannot close a
    netcdf_file opened with mmap=True") when the file is closed while arrays still refer to
    it; reading without the map copies the data and closes cleanly.
    """
    p = Path(path)
    if not p.is_file():
        raise FileNotFoundError(f"NetCDF file not found: {p}")
    with p.open("rb") as fh:
        magic = fh.read(8)
    if magic[:3] == b"CDF":
        return xr.open_dataset(p, engine="scipy", mmap=False)
    if magic[:8] != b"\x89HDF\r\n\x1a\n":
        raise ValueError(f"{p}: not a NetCDF file")
    return xr.open_dataset(p)


def save_ensemble(
    path: str | Path, motions: Sequence[GroundMotion], attrs: dict[str, Any] | None = None,
    *, digest: bool = True,
) -> Path:
    """Write motions to a NetCDF file (atomically: temporary file, then rename), and its
    digest beside it (:func:`write_digest`).

    Parameters
    ----------
    path : str or Path
        Output file (``.nc``); parent folders are created.
    motions : sequence of GroundMotion
        The motions, the record first by convention; names must be unique.
    attrs : dict, optional
        Extra global attributes (JSON-encoded under ``attrs_json``).
    digest : bool
        Write ``<path>.sha256`` (False: a caller writing to a temporary file it renames
        afterwards writes the digest of the final name itself).

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    ValueError
        No motions, a non-GroundMotion item, duplicate names, metadata that JSON cannot
        encode (naming the motion).
    """
    motions = list(motions)
    if not motions:
        raise ValueError("motions must hold at least one GroundMotion, got an empty list")
    for i, m in enumerate(motions):
        if not isinstance(m, GroundMotion):
            raise ValueError(f"motions[{i}] must be a GroundMotion, got {type(m).__name__}")
    names = [m.name for m in motions]
    dupes = sorted({n for n in names if names.count(n) > 1})
    if dupes:
        raise ValueError(f"motion names must be unique, repeated: {dupes}")
    n_max = max(m.npts for m in motions)
    ax = np.zeros((len(motions), n_max))
    ay = np.zeros((len(motions), n_max))
    meta = []
    for i, m in enumerate(motions):
        ax[i, : m.npts] = m.ax
        ay[i, : m.npts] = m.ay
        try:
            meta.append(_json.dumps(m.metadata, sort_keys=True))
        except (TypeError, ValueError) as exc:
            raise ValueError(f"metadata of motion {m.name!r} cannot be saved: {exc}") from None
    ids = [identity(m) for m in motions]
    ds = xr.Dataset(
        {
            "ax": (("motion", "time"), ax, _attrs("ax")),
            "ay": (("motion", "time"), ay, _attrs("ay")),
            "npts": ("motion", np.array([m.npts for m in motions], dtype=np.int64),
                     _attrs("npts")),
            "dt": ("motion", np.array([m.dt for m in motions]), _attrs("dt")),
            "metadata": ("motion", np.array(meta, dtype=object), _attrs("metadata")),
            **{k: ("motion", np.array([i[k] for i in ids],
                                      dtype=object if k in _TEXT else float), _attrs(k))
               for k in IDENTITY},
            **_vertical_variables(motions, n_max),
        },
        coords={"motion": ("motion", np.array(names, dtype=object), _attrs("motion"))},
        attrs={
            "format": FORMAT,
            "title": "Ground-motion ensemble (rocking): the processed record, then its "
                     "synthetic pairs",
            "attrs_json": _json.dumps(attrs or {}, sort_keys=True),
        },
    )
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    write_atomic(out, ds.to_netcdf)
    if digest:
        write_digest(out)
    return out


def _vertical_variables(motions: Sequence[GroundMotion], n_max: int) -> dict[str, Any]:
    """``az`` and ``has_az`` when some motion carries a vertical component, else nothing
    (a horizontal ensemble's file stays as it was)."""
    if all(m.az is None for m in motions):
        return {}
    az = np.zeros((len(motions), n_max))
    for i, m in enumerate(motions):
        if m.az is not None:
            az[i, : m.npts] = m.az
    has = np.array([m.az is not None for m in motions], dtype=np.int8)
    return {"az": (("motion", "time"), az, _attrs("az")),
            "has_az": ("motion", has, _attrs("has_az"))}


def load_ensemble(path: str | Path) -> list[GroundMotion]:
    """Read motions written by :func:`save_ensemble`, in the stored order.

    Parameters
    ----------
    path : str or Path
        The NetCDF file.

    Returns
    -------
    list of GroundMotion
        Each cut to its own ``npts``, with its ``dt``, name and metadata, and its vertical
        component where the file holds one for it (``has_az``).

    Raises
    ------
    MotionsDigestError
        The file differs from the digest written when it was made (:func:`verify_digest`).
    ValueError
        A file without the expected variables, or an ``npts`` outside the stored length.
    """
    p = Path(path)
    verify_digest(p)
    with open_netcdf(p) as ds:
        missing = [v for v in ("ax", "ay", "npts", "dt", "metadata") if v not in ds]
        if missing:
            raise ValueError(f"{p} is not a rocking ensemble: missing variables {missing}")
        ax = ds["ax"].values
        ay = ds["ay"].values
        npts = ds["npts"].values
        dts = ds["dt"].values
        metas = ds["metadata"].values
        names = ds["motion"].values
        # files written before the format held a vertical component: every motion horizontal
        az = ds["az"].values if "az" in ds else None
        has_az = ds["has_az"].values if "has_az" in ds else np.zeros(len(names), np.int8)
    if az is not None and az.shape != ax.shape:
        raise ValueError(f"{p}: az has shape {az.shape}, ax {ax.shape}")
    out = []
    for i, name in enumerate(names):
        n = int(npts[i])
        if not 2 <= n <= ax.shape[1]:
            raise ValueError(f"{p}: npts={n} of motion {name!r} is outside 2..{ax.shape[1]}")
        if not math.isfinite(float(dts[i])):
            raise ValueError(f"{p}: dt of motion {name!r} is {dts[i]!r}")
        out.append(
            GroundMotion(ax[i, :n], ay[i, :n], float(dts[i]), str(name), json.loads(metas[i]),
                         az[i, :n] if az is not None and has_az[i] else None)
        )
    return out


def ensemble_attrs(path: str | Path) -> dict[str, Any]:
    """Global attributes stored by :func:`save_ensemble` (``attrs`` argument) [-]; the file
    is checked against its digest first (:func:`verify_digest`)."""
    verify_digest(path)
    with open_netcdf(path) as ds:
        return json.loads(ds.attrs.get("attrs_json", "{}"))
