"""Which physical direction the x and y components of a motion point to, in words.

A motion's metadata carries the azimuths of its components (degrees clockwise from north,
``x_azimuth`` and ``y_azimuth``, updated by every rotation) and, after a rotation to principal
axes, ``axes = "principal (x = major)"``. The paper's x is the E–W and its y the N–S component
of El Centro before its rotation by 22.33°; the figures say which axes they use so a reader can
match panels.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path

PAPER_AXES = "paper: x = E–W, y = N–S component before its 22.33° rotation to principal axes"
"""The paper's orientation (§4, Fig 6), quoted where ours differs."""

UNKNOWN = "x, y = first and second component of the motion (azimuths not recorded)"


def bearing(azimuth: float) -> str:
    """Quadrant bearing of an azimuth [deg clockwise from north], e.g. 340.5 → ``"N19.5°W"``.

    Exact cardinal directions are named (``"N"``, ``"E"``, ``"S"``, ``"W"``).
    """
    az = float(azimuth) % 360.0
    for name, value in (("N", 0.0), ("E", 90.0), ("S", 180.0), ("W", 270.0), ("N", 360.0)):
        if math.isclose(az, value, abs_tol=0.05):
            return name
    if az < 90.0:
        return f"N{az:.1f}°E"
    if az < 180.0:
        return f"S{180.0 - az:.1f}°E"
    if az < 270.0:
        return f"S{az - 180.0:.1f}°W"
    return f"N{360.0 - az:.1f}°W"


def _direction(azimuth: float) -> str:
    """``"az 340.5° (N19.5°W)"``, or the line a cardinal azimuth lies on (``"E–W (270°)"``)."""
    az = float(azimuth) % 360.0
    if any(math.isclose(az % 180.0, v, abs_tol=0.05) for v in (0.0, 180.0)):
        return f"N–S ({az:g}°)"
    if math.isclose(az % 180.0, 90.0, abs_tol=0.05):
        return f"E–W ({az:g}°)"
    return f"az {az:.1f}° ({bearing(az)})"


def describe(metadata: Mapping | None) -> dict[str, str]:
    """Directions of the x and y components of a motion from its metadata.

    Parameters
    ----------
    metadata : mapping or None
        :attr:`rocking.motions.motion.GroundMotion.metadata` (``x_azimuth``, ``y_azimuth``,
        ``axes``).

    Returns
    -------
    dict
        ``x``, ``y``: one direction each (e.g. ``"major principal axis, az 340.5° (N19.5°W)"``),
        ``text``: one line naming both, ``principal``: ``"yes"`` or ``"no"``.
    """
    meta = dict(metadata or {})
    az_x, az_y = meta.get("x_azimuth"), meta.get("y_azimuth")
    principal = str(meta.get("axes", "")).startswith("principal")
    if az_x is None or az_y is None:
        if principal:
            return {"x": "major principal axis", "y": "minor principal axis",
                    "text": "x = major, y = minor principal axis (azimuths not recorded)",
                    "principal": "yes"}
        return {"x": "first component", "y": "second component", "text": UNKNOWN,
                "principal": "no"}
    x, y = _direction(az_x), _direction(az_y)
    if principal:
        x, y = f"major principal axis, {x}", f"minor principal axis, {y}"
    return {"x": x, "y": y, "text": f"x = {x}; y = {y}", "principal": "yes" if principal else "no"}


def from_ensemble(path: str | Path | None) -> dict[str, str]:
    """:func:`describe` of the first motion (the record) of an ensemble file; unknown if None."""
    if path is None:
        return describe(None)
    from rocking.motions.ensemble_io import load_ensemble  # imported late: netCDF reading is heavy

    motions = load_ensemble(path)
    return describe(motions[0].metadata if motions else None)


def of_records(path: str | Path | None) -> dict[str, str]:
    """The directions of x and y of every record of an ensemble file (a suite's records each
    have their own principal axes; a synthetic motion, whose metadata names its ``record``,
    has its record's): ``text`` names each record's, or is "" when the file holds one record
    with recorded azimuths (then :func:`from_ensemble` says it)."""
    if path is None:
        return {"text": ""}
    from rocking.motions.ensemble_io import load_ensemble

    # records: motions that name no source record and carry their directions
    records = [m for m in load_ensemble(path) if not (m.metadata or {}).get("record")
               and (m.metadata or {}).get("x_azimuth") is not None]
    if len(records) <= 1:
        return {"text": ""}
    return {"text": "; ".join(f"{m.name}: {describe(m.metadata)['text']}" for m in records)
            .replace("; y = ", ", y = ")
            + " (each synthetic motion on its record's)"}
