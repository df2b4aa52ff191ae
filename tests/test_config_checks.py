"""Configuration checks before any work: one line naming the key and the value."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from rocking.config.checks import check_config, schema_error

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
        (lambda c: c["studies"]["elcentro"].update(mu=0),
         "config key studies.elcentro.mu=0"),
        (lambda c: c["studies"]["elcentro"]["runs"][0].update(limit_states=["sliding:abc"]),
         "config key studies.elcentro.runs[0].limit_states[0]='sliding:abc'"),
        (lambda c: c.update(foo=1), "unknown config key 'foo' at the top level; allowed: "),
        (lambda c: c["studies"]["elcentro"].update(Rr=[1]),
         "unknown config key 'Rr' in studies.elcentro"),
        (lambda c: c["studies"]["elcentro"]["runs"][0].update(modes=["3d", "4d"]),
         "config key studies.elcentro.runs[0].modes[1]='4d': must be one of"),
        (lambda c: c["studies"]["elcentro"].update(modes=["3d"]),
         "unknown config key 'modes' in studies.elcentro; allowed: R, chunk_R, component, "
         "diameter, ensemble, hazard, height, intensity_measures, inventory, mu, reproduces, "
         "runs, stripes, tilt_map, upper"),
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
        # the quantity before anything else, and the accuracy's sample against its window
        (lambda c: c.update(quantity={"name": "exceedance_quantile", "p": 0.0}),
         "quantity.p must be a number in (0, 1), got 0.0"),
        (lambda c: c.update(quantity={"w": 0.2}),
         "accuracy='default': accuracy local_below + local_above"),
    ],
)
def test_cross_field_errors_name_key_and_value(change, message):
    cfg = _cfg(change)
    cfg["ensembles"]["elcentro"].setdefault("paths", None)
    with pytest.raises(ValueError) as err:
        check_config(cfg)
    assert message in str(err.value)


def _at2(path, values, dt=".0100"):
    body = "\n".join(f"  {v}" for v in values)
    path.write_text("PEER NGA STRONG MOTION DATABASE RECORD\nSite, 1/1/2000, Station, 90\n"
                    f"ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=   {len(values)}, "
                    f"DT=   {dt} SEC,\n{body}\n")
    return str(path)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda c, d: c["studies"]["elcentro"].update(R=[float("nan")]),
         "config key studies.elcentro.R[0]=nan: must be a finite number"),
        (lambda c, d: c["studies"]["elcentro"].update(R=[1.0, float("inf")]),
         "config key studies.elcentro.R[1]=inf: must be a finite number"),
        (lambda c, d: c["studies"]["elcentro"]["tilt_map"].update(motion="nope"),
         "studies.elcentro.tilt_map.motion='nope' is not a motion of the ensemble"),
        (lambda c, d: c.setdefault("motions", {}).update(max_duration=0.015),
         "motions.max_duration=0.015 s keeps fewer than two samples of ensembles.elcentro"),
        (lambda c, d: c["ensembles"]["elcentro"].update(
            record="site", paths=[_at2(d / "x.AT2", [0.1, "NaN", 0.2]),
                                  _at2(d / "y.AT2", [0.1, 0.2, 0.3])]),
         "line 6"),
        (lambda c, d: c["ensembles"]["elcentro"].update(
            record="site", paths=[_at2(d / "x.AT2", [0.1, 0.2, 0.3]),
                                  _at2(d / "y.AT2", [0.1, 0.2, 0.3], dt=".0200")]),
         "different dt"),
        (lambda c, d: c["ensembles"]["elcentro"].update(
            record="site", paths=[_at2(d / "x.AT2", [0.1, 0.2, 0.3]),
                                  _at2(d / "y.AT2", [0.0, 0.0, 0.0])]),
         "paths[1]=" ),
        (lambda c, d: c["studies"]["elcentro"].update(R={"start": 1, "stop": 2,
                                                         "num": 100_000_000}),
         "studies.elcentro.R: 100000000 values exceed the bound of 10000"),
        (lambda c, d: c["ensembles"]["elcentro"].update(n_synthetic=10**9),
         "ensembles.elcentro.n_synthetic=1000000000: building the ensemble needs about"),
    ],
    ids=["nan-grid", "inf-grid", "tilt-map-motion", "max-duration", "record-nan",
         "record-dt", "record-zeros", "huge-grid", "huge-ensemble"],
)
def test_what_a_real_run_rejects_is_rejected_before_work(change, message, tmp_path):
    import time

    cfg = _cfg(lambda c: None)
    if "tilt_map" not in cfg["studies"]["elcentro"]:
        cfg["studies"]["elcentro"]["tilt_map"] = {"R": [1.0], "intensity": [1.0]}
    change(cfg, tmp_path)
    cfg["ensembles"]["elcentro"].setdefault("paths", None)
    t0 = time.monotonic()
    with pytest.raises(ValueError) as err:
        check_config(cfg)
    assert message in str(err.value) and "\n" not in str(err.value)
    assert time.monotonic() - t0 < 5.0  # estimated, never expanded


def test_numbers_given_as_strings_are_taken_as_numbers():
    from rocking.config.checks import coerce_strings

    cfg = _cfg(lambda c: c.update(dask={"scheduler_address": "null", "progress_interval": "2",
                                        "worker_timeout": "1e2"}))
    coerce_strings(cfg, SCHEMA)
    assert cfg["dask"] == {"scheduler_address": None, "progress_interval": 2,
                           "worker_timeout": 100.0}
    assert schema_error(cfg, SCHEMA) is None
    bad = _cfg(lambda c: c.update(dask={"progress_interval": "soon"}))
    coerce_strings(bad, SCHEMA)
    assert schema_error(bad, SCHEMA).startswith("config key dask.progress_interval='soon'")
    # a grid's count written 1e8 (YAML 1.1 reads it as text) is the number it spells
    grid = _cfg(lambda c: c["studies"]["elcentro"].update(R={"start": 1, "stop": 2,
                                                             "num": "1e8"}))
    coerce_strings(grid, SCHEMA)
    assert grid["studies"]["elcentro"]["R"]["num"] == 1e8
    grid["ensembles"]["elcentro"].setdefault("paths", None)
    with pytest.raises(ValueError, match="R: 100000000 values exceed the bound"):
        check_config(grid)
    # a string the schema wants stays a string
    named = _cfg(lambda c: c["ensembles"]["elcentro"].update(record="1940"))
    coerce_strings(named, SCHEMA)
    assert named["ensembles"]["elcentro"]["record"] == "1940"


def test_user_record_needs_mw_and_passes_with_it():
    """A record the catalogue does not know has no magnitude for the high-pass corner."""
    from conftest import ELC180, ELC270, package_record

    cfg = _cfg(lambda c: None)
    cfg["ensembles"]["elcentro"].update(   # another record: not the recorded fit's
        record="my-pair", paths=[str(package_record(ELC180)), str(package_record(ELC270))],
        params=None)
    with pytest.raises(ValueError, match=r"^ensembles\.elcentro\.mw is needed"):
        check_config(cfg)
    cfg["ensembles"]["elcentro"]["mw"] = 6.9
    check_config(cfg)


# --- the body as engineers give it: height and diameter ----------------------------------

def _column(**study):
    """A study of one marble column (height 6 m, diameter 0.66 m) with stripes."""
    return {"ensembles": {"e": {"record": "el-centro-1940", "n_synthetic": 0}},
            "studies": {"col": {"ensemble": "e", "height": 6.0, "diameter": 0.66,
                                "runs": [{"modes": ["3d"], "limit_states": ["overturning"]}],
                                "stripes": {"height": 6.0, "diameter": 0.66,
                                            "intensity": [1.5, 3.0]}, **study}}}


def test_height_and_diameter_become_R_and_tan_alpha_printed(capsys):
    from snakemake.utils import validate

    from rocking.config.checks import validate_config
    from rocking.config.study import StudySpec

    R = (0.33**2 + 3.0**2) ** 0.5  # sqrt(b² + h²), written out
    cfg = _column()
    validate_config(cfg, REPO / "workflow/schemas/config.schema.yaml", validate)
    s = cfg["studies"]["col"]
    assert "height" not in s and s["R"] == [pytest.approx(R, rel=1e-12)]
    assert s["runs"][0]["tan_alpha"] == [pytest.approx(0.11, rel=1e-12)]
    assert s["stripes"]["tan_alpha"] == pytest.approx(0.11, rel=1e-12)  # not the 0.2 default
    assert capsys.readouterr().err.splitlines() == [
        "studies.col: height 6 m, diameter 0.66 m: R = 3.018 m, tan α = 0.11 (α = 6.28°)",
        "studies.col.stripes: height 6 m, diameter 0.66 m: R = 3.018 m, tan α = 0.11 "
        "(α = 6.28°)"]
    # the typed study of the raw configuration is the same study, and R and tan alpha given
    # beside the dimensions that agree change nothing
    spec = StudySpec.from_config(_column(), "col")
    assert spec == StudySpec.from_config(cfg, "col")
    agreeing = _column(R=[R])
    agreeing["studies"]["col"]["runs"][0]["tan_alpha"] = [0.11]
    assert StudySpec.from_config(agreeing, "col") == spec


@pytest.mark.parametrize(
    ("study", "message"),
    [
        ({"height": -6.0}, "studies.col.height must be a finite length > 0 [m], got -6.0"),
        ({"diameter": "big"}, "studies.col.diameter must be a finite length > 0 [m], got 'big'"),
        ({"R": [2.0]}, "studies.col.R 2.0 contradicts studies.col.height 6 and "
                       "studies.col.diameter 0.66 (studies.col.R = 3.0181)"),
        ({"runs": [{"modes": ["3d"], "tan_alpha": [0.2], "limit_states": ["overturning"]}]},
         "studies.col.runs[0].tan_alpha 0.2 contradicts the study's height and diameter "
         "(tan_alpha = 0.11)"),
        ({"stripes": {"height": 6.0, "intensity": [2.0]}},
         "studies.col.stripes.height and studies.col.stripes.diameter go together"),
        ({"stripes": {"height": 6.0, "diameter": 0.66, "tan_alpha": 0.2, "intensity": [2.0]}},
         "studies.col.stripes.tan_alpha 0.2 contradicts"),
    ],
)
def test_bad_dimensions_are_one_line(study, message):
    from snakemake.utils import validate

    from rocking.config.checks import validate_config

    with pytest.raises(ValueError) as err:
        validate_config(_column(**study), REPO / "workflow/schemas/config.schema.yaml", validate)
    assert str(err.value).startswith(message) and "\n" not in str(err.value)


@pytest.mark.parametrize(
    ("given", "message"),
    [
        ({"record": "loma-prieta-sjte", "vertical": True},
         "ensembles.elcentro.vertical: true for record 'loma-prieta-sjte', which ships no "
         "files"),
        ({"records": [{"record": "el-centro-1940"},
                      {"record": "fema-p695:far-field:1", "vertical": True}]},
         "ensembles.elcentro.records[1].vertical: true for FEMA P-695 record"),
        ({"record": "site", "mw": 6.0, "vertical": True, "paths": ["x", "y"]},
         "ensembles.elcentro.vertical: true but ensembles.elcentro.paths=['x', 'y'] has no "
         "vertical file"),
        ({"record": "site", "mw": 6.0, "paths": ["x", "y", "z"]},
         "ensembles.elcentro.paths=['x', 'y', 'z']: the third file is the vertical "
         "component; set ensembles.elcentro.vertical: true"),
        ({"record": "site", "mw": 6.0, "vertical": True, "paths": ["x", "y", "z2"]},
         "vertical file z2.AT2: dt 0.02 s differs from the horizontal pair's 0.01 s"),
        ({"record": "site", "mw": 6.0, "vertical": True, "paths": ["x", "y", "zlong"]},
         "vertical file zlong.AT2: 12 samples against 3 of the horizontal pair"),
        ({"record": "site", "mw": 6.0, "vertical": "yes", "paths": ["x", "y", "z"]},
         "ensembles.elcentro.vertical must be true or false, got 'yes'"),
    ],
    ids=["record-without-vertical-file", "fema-without-vertical", "two-paths",
         "three-paths-not-vertical", "vertical-other-dt", "vertical-other-length",
         "not-a-boolean"],
)
def test_vertical_bad_input_is_one_line_before_work(given, message, tmp_path):
    """``vertical: true`` for a record with no vertical file, three files without it, and a
    third file of another time step or length: one line naming the key, in the checks
    every dry run makes (the third file is read as the motions rule reads it)."""
    files = {"x": _at2(tmp_path / "x.AT2", [0.1, 0.2, 0.3]),
             "y": _at2(tmp_path / "y.AT2", [0.2, 0.1, 0.3]),
             "z": _at2(tmp_path / "z.AT2", [0.01, 0.05, 0.02]),
             "z2": _at2(tmp_path / "z2.AT2", [0.01, 0.05, 0.02], dt=".0200"),
             "zlong": _at2(tmp_path / "zlong.AT2", [0.01] * 12)}
    if "paths" in given:
        given = {**given, "paths": [files[k] for k in given["paths"]]}
        message = message.replace("['x', 'y']", repr([files["x"], files["y"]])).replace(
            "['x', 'y', 'z']", repr([files["x"], files["y"], files["z"]]))
    cfg = _cfg(lambda c: None)
    cfg["ensembles"]["elcentro"] = given
    with pytest.raises(ValueError) as err:
        check_config(cfg)
    assert message in str(err.value) and "\n" not in str(err.value)


def test_vertical_true_passes_for_the_shipped_records_and_three_files(tmp_path):
    """The four shipped records have their UP/DWN file; three files of one dt and length
    pass; the spec keeps the flag per record of a suite."""
    from rocking.config.ensemble import EnsembleSpec

    cfg = _cfg(lambda c: None)
    cfg["ensembles"]["elcentro"] = {
        "records": ["el-centro-1940", "loma-prieta-corralitos", "northridge-05-sylmar-1994",
                    {"record": "site", "highpass": "none", "vertical": False,
                     "paths": [_at2(tmp_path / "x.AT2", [0.1, 0.2, 0.3]),
                               _at2(tmp_path / "y.AT2", [0.2, 0.1, 0.3])]},
                    {"record": "site-v", "highpass": "none",
                     "paths": [_at2(tmp_path / "x.AT2", [0.1, 0.2, 0.3]),
                               _at2(tmp_path / "y.AT2", [0.2, 0.1, 0.3]),
                               _at2(tmp_path / "z.AT2", [0.0, 0.1, 0.0])]},
                    "san-fernando-pacoima-dam-1971"],
        "vertical": True, "n_synthetic": 0}
    check_config(cfg)
    spec = EnsembleSpec.from_config(cfg, "elcentro")
    assert [r.vertical for r in spec.records] == [True, True, True, False, True, True]
    assert EnsembleSpec.from_attrs(spec.to_attrs()) == spec
