"""Configuration checks before any work: one line naming the key and the value."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from rocking.study.config_checks import check_config, schema_error

REPO = Path(__file__).resolve().parents[1]
SCHEMA = yaml.safe_load((REPO / "workflow/schemas/config.schema.yaml").read_text())
BASE = yaml.safe_load((REPO / "config/config.yaml").read_text())


def _cfg(change):
    cfg = json.loads(json.dumps(BASE))
    change(cfg)
    return cfg


def test_shipped_configurations_pass():
    for name in ("config.yaml", "paper.yaml"):
        cfg = yaml.safe_load((REPO / "config" / name).read_text())
        assert schema_error(cfg, SCHEMA) is None, name


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda c: c.update(foo=1), "unknown config key 'foo' at the top level; allowed: "),
        (lambda c: c["studies"]["elcentro"].update(Rr=[1]),
         "unknown config key 'Rr' in studies.elcentro"),
        (lambda c: c["studies"]["elcentro"]["runs"][0].update(modes=["3d", "4d"]),
         "config key studies.elcentro.runs[0].modes[1]='4d': must be one of"),
        (lambda c: c["studies"]["elcentro"].update(modes=["3d"]),
         "unknown config key 'modes' in studies.elcentro; allowed: R, chunk_R, ensemble, "
         "runs"),
        (lambda c: c.update(accuracy="fastest"), "config key accuracy='fastest'"),
    ],
)
def test_schema_errors_are_one_short_line(change, message):
    text = schema_error(_cfg(change), SCHEMA)
    assert text.startswith(message) and "\n" not in text and len(text) < 300


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda c: c["ensembles"]["elcentro"].update(record="kobe-1995"),
         "ensembles.elcentro.record='kobe-1995' is not a known record"),
        (lambda c: c["ensembles"]["elcentro"].update(paths=["/nope/x.AT2", "/nope/y.AT2"]),
         "ensembles.elcentro.paths[0]='/nope/x.AT2' does not exist"),
        (lambda c: c["ensembles"]["elcentro"].update(paths=["/", "/"]),
         "ensembles.elcentro.paths[0]='/' is not a file"),
        (lambda c: c["studies"]["elcentro"]["runs"][2].update(limit_states=["tilt:50"]),
         "studies.elcentro.runs[2].limit_states: 'tilt:50' with tan_alpha=0.2"),
        (lambda c: c["studies"]["elcentro"]["runs"][3].update(limit_states=["tilt:3"],
                                                              tan_alpha=[0.2, 1.0]),
         "studies.elcentro.runs[3].limit_states: 'tilt:3' with tan_alpha=1"),
    ],
)
def test_cross_field_errors_name_key_and_value(change, message):
    cfg = _cfg(change)
    cfg["ensembles"]["elcentro"].setdefault("paths", None)
    with pytest.raises(ValueError) as err:
        check_config(cfg)
    assert message in str(err.value)
