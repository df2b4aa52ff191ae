"""Checks of a workflow configuration that run before any work (``snakemake -n`` included).

Two layers: the JSON schema (``workflow/schemas/config.schema.yaml``), reported as one short
line naming the key first (jsonschema's own message prints the whole schema), and the
cross-field checks a schema cannot express: record names and files, and tilt goals that
exist for every slenderness of a study. Every message names the key and the value.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

__all__ = ["check_config", "schema_error", "validate_config"]


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

    schema = yaml.safe_load(Path(schema_path).read_text())
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
        An unknown record name without files, a record file that does not exist, a study
        naming an unknown ensemble, or a tilt goal r·α ≥ π/2 for a slenderness of its run.
    """
    for name, spec in config["ensembles"].items():
        _check_record(f"ensembles.{name}", spec)
    for study, s in config["studies"].items():
        if s["ensemble"] not in config["ensembles"]:
            raise ValueError(f"studies.{study}.ensemble={s['ensemble']!r} is not a key of "
                             f"ensembles {sorted(config['ensembles'])}")
        for i, run in enumerate(s["runs"]):
            _check_tilt_goals(f"studies.{study}.runs[{i}]", run["limit_states"],
                              _grid(run["tan_alpha"]))


def _check_record(key: str, spec: Mapping[str, Any]) -> None:
    from ..motions.records import RECORDS

    record, paths = spec["record"], spec.get("paths")
    if not paths:
        if record not in RECORDS:
            raise ValueError(f"{key}.record={record!r} is not a known record "
                             f"({', '.join(sorted(RECORDS))}); give its two acceleration "
                             f"files in {key}.paths")
        return
    for i, p in enumerate(paths):
        path = Path(p).expanduser()
        if not path.exists():
            raise ValueError(f"{key}.paths[{i}]={str(p)!r} does not exist")
        if not path.is_file():
            raise ValueError(f"{key}.paths[{i}]={str(p)!r} is not a file")


def _grid(spec) -> list[float]:
    if isinstance(spec, list):
        return [float(v) for v in spec]
    return [float(spec["start"]), float(spec["stop"])]  # the extremes decide the check


def _check_tilt_goals(key: str, limit_states, tan_alphas: list[float]) -> None:
    from ..spectra.limit_states import parse_limit_state

    for text in limit_states:
        ls = parse_limit_state(text)
        if ls.is_overturning:
            continue
        for tan_alpha in tan_alphas:
            alpha = math.atan(tan_alpha)
            if ls.ratio * alpha >= 0.5 * math.pi:
                raise ValueError(
                    f"{key}.limit_states: {text!r} with tan_alpha={tan_alpha:g} asks for "
                    f"theta > r*alpha = {ls.ratio * alpha:.4g} rad, not below pi/2 (a body "
                    f"tilted that far has overturned); use 'overturning' or a smaller r "
                    f"(r < {0.5 * math.pi / alpha:.4g} for this tan_alpha)")
