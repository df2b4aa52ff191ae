"""The study as one typed object (rocking.config.study and its parts): built from a
configuration with the schema's defaults, grids expanded as the workflow always did,
round-tripped through store attributes, and hashed so that what decides the numbers changes
the hash and nothing else does."""

from __future__ import annotations

import copy
import json
from pathlib import Path

import numpy as np
import pytest
import yaml

from rocking.config.ensemble import EnsembleSpec
from rocking.config.fields import DEFAULTS, expand_grid
from rocking.config.products import SpectraSpec, StripesSpec, TiltMapSpec
from rocking.config.study import StudySpec
from rocking.spectra.quantity import Quantity
from rocking.store.attrs import config_hash, decode_attrs

ROOT = Path(__file__).resolve().parents[1]
CONFIGS = ["config/config.yaml", "config/paper.yaml"]


def _raw(name: str) -> dict:
    return yaml.safe_load((ROOT / name).read_text())


def _validated(name: str) -> dict:
    """The configuration as the Snakefile sees it: schema defaults filled in by snakemake."""
    from snakemake.utils import validate

    config = _raw(name)
    validate(config, str(ROOT / "workflow/schemas/config.schema.yaml"))
    return config


def _legacy_grid(spec, field):
    """workflow/rules/common.smk's expand_grid before rocking.study.spec (reference copy)."""
    if isinstance(spec, list):
        values = [float(v) for v in spec]
    else:
        start, stop, num = float(spec["start"]), float(spec["stop"]), int(spec["num"])
        if spec.get("spacing", "linear") == "log":
            values = np.geomspace(start, stop, num)
        else:
            values = np.linspace(start, stop, num)
        values = [float(f"{v:.12g}") for v in values]
    return values


def _legacy_spectra_spec(config: dict, study: str) -> dict:
    """common.smk's spectra_spec before rocking.study.spec (reference copy): its hash is the
    config_hash of every spectra store made so far."""
    from rocking.config.plan import plan_study

    s = config["studies"][study]
    name = s["ensemble"]
    runs = [{**r, "tan_alpha": _legacy_grid(r["tan_alpha"], "")} for r in s["runs"]]
    plan = plan_study(runs)
    options = {"upper": float(config["search"]["upper"] if s.get("upper") is None
                              else s["upper"])}
    if "3d-damped" in plan.modes:
        options.update(omega_n=float(config["damped"]["omega_n"]),
                       zeta=float(config["damped"]["zeta"]))
    # the schema's later default vertical: false was never hashed (only vertical: true is)
    ensemble = {k: v for k, v in config["ensembles"][name].items()
                if not (k == "vertical" and v is False)}
    return {"study": study,
            "ensemble": {"name": name, **ensemble,
                         "max_duration": config["motions"]["max_duration"]},
            "R": _legacy_grid(s["R"], ""), **plan.to_dict(), "tan_alpha": list(plan.tan_alpha),
            "limit_states": list(plan.limit_states), "modes": list(plan.modes),
            "chunk_R": s["chunk_R"],
            "min_task_seconds": config["dask"]["min_task_seconds"] if s["chunk_R"] == "auto"
            else None,
            "accuracy": config["accuracy"],
            # the quantity, whole (name, p, w), since the search that estimates I10
            "quantity": Quantity.from_value(config["quantity"]).to_dict(),
            "search_options": options}


def _small() -> dict:
    return {"ensembles": {"e": {"record": "el-centro-1940", "n_synthetic": 2}},
            "studies": {"s": {"ensemble": "e", "R": {"start": 0.5, "stop": 2.0, "num": 4},
                              "chunk_R": 2,
                              "runs": [{"modes": ["3d", "3d-damped"], "tan_alpha": [0.2],
                                        "limit_states": ["overturning"], "purpose": "a"}],
                              "tilt_map": {"R": [1.0, 2.0], "intensity": [1.0, 2.0]},
                              "stripes": {"modes": ["3d", "3d-damped"], "R": [1.0],
                                          "intensity": [1.5, 3.0]},
                              "hazard": {"k0": 1e-4, "k": 3.0}}}}


def test_defaults_are_the_schemas():
    schema = yaml.safe_load((ROOT / "workflow/schemas/config.schema.yaml").read_text())
    props = schema["properties"]
    assert DEFAULTS["accuracy"] == props["accuracy"]["default"]
    for section in ("search", "damped", "motions"):
        assert DEFAULTS[section] == {k: v["default"]
                                     for k, v in props[section]["properties"].items()}
    assert DEFAULTS["dask"]["min_task_seconds"] == \
        props["dask"]["properties"]["min_task_seconds"]["default"]
    ensemble = props["ensembles"]["additionalProperties"]["properties"]
    assert DEFAULTS["ensemble"] == {k: v["default"] for k, v in ensemble.items()
                                    if k not in ("record", "records")}
    study = props["studies"]["additionalProperties"]["properties"]
    assert DEFAULTS["study"] == {k: study[k]["default"]
                                 for k in ("chunk_R", "upper", "intensity_measures", "mu",
                                           "component")}
    for part in ("tilt_map", "stripes"):
        assert DEFAULTS[part] == {k: v["default"] for k, v in study[part]["properties"].items()
                                  if "default" in v}


@pytest.mark.parametrize("name", CONFIGS)
def test_committed_configs_give_the_stores_they_always_gave(name):
    """Grids, store descriptions and hashes equal the workflow's before this module (stores
    already made are resumed), whether or not the schema's defaults were filled in."""
    validated, raw = _validated(name), _raw(name)
    for study, s in validated["studies"].items():
        spec = StudySpec.from_config(validated, study)
        assert StudySpec.from_config(raw, study) == spec
        assert spec.spectra.R == tuple(_legacy_grid(s["R"], ""))
        legacy_t = sorted({t for r in s["runs"] for t in _legacy_grid(r["tan_alpha"], "")})
        assert spec.spectra.plan.tan_alpha == tuple(legacy_t)
        for part in ("tilt_map", "stripes"):
            if s.get(part) is None:
                assert getattr(spec, part) is None
                continue
            got = getattr(spec, part)
            assert got.R == tuple(_legacy_grid(s[part]["R"], ""))
            assert got.intensity == tuple(_legacy_grid(s[part]["intensity"], ""))
        legacy = _legacy_spectra_spec(validated, study)
        assert spec.spectra.to_attrs() == legacy
        assert spec.spectra.digest == config_hash(legacy)


def test_log_grid_is_rounded_and_includes_its_ends():
    values = expand_grid({"start": 1.1, "stop": 15.0, "num": 10, "spacing": "log"}, "g")
    assert values[0] == 1.1 and values[-1] == 15.0
    np.testing.assert_allclose(np.diff(np.log(values)), np.log(15.0 / 1.1) / 9, rtol=1e-9)
    assert expand_grid({"start": 0.5, "stop": 3.35, "num": 4}, "g")[-1] == 3.35


def test_attrs_round_trip_exactly():
    spec = StudySpec.from_config(_small(), "s")
    text = json.dumps(spec.to_attrs())  # what a store keeps: JSON text
    back = StudySpec.from_attrs(json.loads(text))
    assert back == spec
    assert back.to_attrs() == spec.to_attrs() and back.digest == spec.digest
    for part, cls in ((spec.spectra, SpectraSpec), (spec.tilt_map, TiltMapSpec),
                      (spec.stripes, StripesSpec)):
        again = cls.from_attrs(decode_attrs({"config": json.dumps(part.to_attrs())})["config"])
        assert again == part and again.digest == part.digest
    assert EnsembleSpec.from_attrs(spec.ensemble.to_attrs()) == spec.ensemble
    assert spec.spectra.damping.to_attrs() == {"omega_n": 2000.0, "zeta": 5.0}


def _digests(config: dict) -> tuple[str, str, str]:
    s = StudySpec.from_config(config, "s")
    return s.spectra.digest, s.tilt_map.digest, s.stripes.digest


def _changed(path: str, value) -> dict:
    config = copy.deepcopy(_small())
    *keys, last = path.split(".")
    node = config
    for k in keys:
        node = node.setdefault(k, {})
    node[last] = value
    return config


@pytest.mark.parametrize("path, value, changes", [
    ("accuracy", "fast", (True, True, True)),
    # the quantity decides the spectra store only (tilt maps and stripes analyse given
    # intensities): another quantity, p or w is another store, its name another digest
    ("quantity", "first_exceedance", (True, False, False)),
    ("quantity", {"p": 0.2}, (True, False, False)),
    ("quantity", {"name": "exceedance_quantile", "w": 0.025}, (True, False, False)),
    ("damped.omega_n", 200.0, (True, True, True)),
    ("motions.max_duration", 10.0, (True, True, True)),
    ("ensembles.e.seed", 1, (True, True, True)),
    ("ensembles.e.n_synthetic", 3, (True, True, True)),
    ("studies.s.chunk_R", 1, (True, False, False)),  # the spectra store's own chunking
    ("studies.s.tilt_map.tan_alpha", 0.1, (False, True, False)),
    ("studies.s.stripes.intensity", [1.5, 4.0], (False, False, True)),
])
def test_digest_changes_with_what_decides_the_numbers(path, value, changes):
    """(spectra, tilt map, stripes): each store's hash moves with its own settings."""
    before, after = _digests(_small()), _digests(_changed(path, value))
    assert tuple(a != b for a, b in zip(before, after, strict=True)) == changes


@pytest.mark.parametrize("path, value", [
    ("dask.progress_interval", 1),
    ("dask.scheduler_address", "tcp://h:1"),
    ("dask.worker_timeout", 5),
    ("dask.min_task_seconds", 3.0),  # chunk_R is a number: it cannot matter
])
def test_digest_ignores_dask_and_progress_settings(path, value):
    assert _digests(_changed(path, value)) == _digests(_small())


def test_digest_ignores_purposes_and_an_unused_contact_model():
    config = _small()
    config["studies"]["s"]["runs"][0]["purpose"] = "another label"
    assert _digests(config) == _digests(_small())
    undamped = _changed("studies.s.runs", [{"modes": ["3d"], "tan_alpha": [0.2],
                                            "limit_states": ["overturning"]}])
    undamped["studies"]["s"]["tilt_map"]["modes"] = ["3d"]
    undamped["studies"]["s"]["stripes"]["modes"] = ["3d"]
    other = copy.deepcopy(undamped)
    other["damped"] = {"omega_n": 100.0, "zeta": 0.1}
    assert _digests(other) == _digests(undamped)


def test_hazard_decides_no_store():
    spec = StudySpec.from_config(_small(), "s")
    assert spec.hazard == {"k0": 1e-4, "k": 3.0}
    other = _changed("studies.s.hazard", "curve.csv")
    assert _digests(other) == _digests(_small())
    assert StudySpec.from_config(other, "s").digest != spec.digest


def test_upper_and_search_bound():
    assert StudySpec.from_config(_small(), "s").spectra.upper == 20.0
    own = _changed("studies.s.upper", 60)
    assert StudySpec.from_config(own, "s").spectra.search_options()["upper"] == 60.0


@pytest.mark.parametrize("path, value, message", [
    ("studies.s.R", {"start": 2.0, "stop": 1.0, "num": 3}, "studies.s.R: stop=1.0"),
    ("studies.s.R", {"start": 1.0, "stop": 2.0}, "studies.s.R="),
    ("studies.s.R", [1.0, -2.0], "studies.s.R must hold finite numbers > 0"),
    ("studies.s.R", [1.0, 1.0], "studies.s.R: repeated values"),
    ("studies.s.chunk_R", 0, "studies.s.chunk_R must be an integer >= 1 or auto, got 0"),
    ("studies.s.upper", 0.5, "studies.s.upper must be > 1"),
    ("studies.s.colour", "red", "studies.s has unknown key(s) ['colour']"),
    ("studies.s.ensemble", "nope", "ensemble 'nope' is not a key of ensembles"),
    ("ensembles.e.seed", -1, "ensembles.e.seed must be an integer >= 0, got -1"),
    ("accuracy", "sloppy", "accuracy='sloppy'"),
    ("studies.s.tilt_map.modes", ["4d"], "studies.s.tilt_map.modes must be"),
    ("studies.s.stripes.limit_states", ["tilt:"], "studies.s.stripes.limit_states="),
    ("studies.s.stripes.intensity", "many", "studies.s.stripes.intensity must be a list"),
    ("studies.s.hazard", 3, "studies.s.hazard must be a file name or a mapping, got 3"),
])
def test_bad_settings_name_the_key_and_value(path, value, message):
    with pytest.raises(ValueError) as err:
        StudySpec.from_config(_changed(path, value), "s")
    assert message in str(err.value)


def test_unknown_study_is_named():
    with pytest.raises(ValueError, match="study 'x' is not a key of studies"):
        StudySpec.from_config(_small(), "x")


@pytest.mark.parametrize("value", [None, "exceedance_quantile",
                                   {"name": "exceedance_quantile", "p": 0.1, "w": 0.02},
                                   {"p": 0.1}])
def test_the_default_quantity_however_written_is_one_store(value):
    """A name, a mapping with some or all of name, p and w, or nothing: the same choice
    hashes alike (the spec holds Quantity.to_dict(), all three)."""
    config = _small() if value is None else _changed("quantity", value)
    assert _digests(config) == _digests(_small())
    assert StudySpec.from_config(config, "s").spectra.quantity == Quantity().to_dict()
