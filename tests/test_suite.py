"""Record suites: the spec, the processing keys, the intensity measures, the suite's ensemble
file and the per-record table, checked against independent computations."""

from __future__ import annotations

import copy
import json
import math
import shutil

import numpy as np
import pytest
from conftest import ELC180, ELC270, package_record

from rocking.config import ensemble as spec_module
from rocking.config.checks import check_config
from rocking.config.ensemble import EnsembleSpec, RecordSpec
from rocking.config.study import StudySpec
from rocking.constants import G
from rocking.motions.build import HIGHPASS_KINDS, build_ensemble, build_suite, cut
from rocking.motions.catalogue import load_record
from rocking.motions.measures import (
    intensity_measure,
    parse_measure,
    peak_vector_velocity,
    vector_sa,
)
from rocking.motions.motion import GroundMotion
from rocking.motions.principal import rotate
from rocking.motions.response_spectrum import pseudo_acceleration


def _suite_config() -> dict:
    return {"ensembles": {"s": {"n_synthetic": 0, "highpass": "butterworth", "fc_hz": 0.1,
                                "records": [
                                    {"record": "el-centro-1940", "n_synthetic": 2},
                                    {"record": "san-fernando-pacoima-dam-1971",
                                     "highpass": "none", "rotation_deg": "none"},
                                    {"record": "loma-prieta-corralitos", "fc_hz": None,
                                     "highpass": "oscillator", "seed": 5}]}},
            "studies": {"st": {"ensemble": "s", "R": [1.0], "intensity_measures":
                               ["pga", "pgv", "sa:0.5"],
                               "runs": [{"modes": ["3d"], "tan_alpha": [0.2],
                                         "limit_states": ["overturning"]}]}}}


# --- spec ---------------------------------------------------------------------------------

def test_suite_records_take_the_ensembles_settings_unless_they_set_their_own():
    ens = EnsembleSpec.from_config(_suite_config(), "s")
    assert ens.is_suite and [r.record for r in ens.records] == [
        "el-centro-1940", "san-fernando-pacoima-dam-1971", "loma-prieta-corralitos"]
    elc, sfe, lpc = ens.records
    assert (elc.n_synthetic, elc.highpass, elc.fc_hz, elc.rotation_deg) == \
        (2, "butterworth", 0.1, "auto")
    assert (sfe.n_synthetic, sfe.highpass, sfe.rotation_deg) == (0, "none", "none")
    assert (lpc.highpass, lpc.fc_hz, lpc.seed) == ("oscillator", None, 5)
    assert ens.n_motions == 3 + 2
    back = EnsembleSpec.from_attrs(json.loads(json.dumps(ens.to_attrs())))
    assert back == ens and back.records == ens.records
    study = StudySpec.from_config(_suite_config(), "st")
    assert study.intensity_measures == ("pga", "pgv", "sa:0.5")
    assert StudySpec.from_attrs(json.loads(json.dumps(study.to_attrs()))) == study


def test_attributes_of_stores_made_before_the_processing_keys_still_read():
    cfg = {"ensembles": {"e": {"record": "el-centro-1940"}}}
    ens = EnsembleSpec.from_config(cfg, "e")
    old = {k: v for k, v in ens.to_attrs().items()
           if k not in ("units", "dt", "highpass", "fc_hz")}
    assert EnsembleSpec.from_attrs(old) == ens


def test_one_record_is_a_suite_of_one():
    cfg = {"ensembles": {"e": {"record": "el-centro-1940", "highpass": "butterworth",
                               "fc_hz": 0.2}}}
    ens = EnsembleSpec.from_config(cfg, "e")
    assert not ens.is_suite and ens.records == (RecordSpec(
        "el-centro-1940", None, "g", None, 10, 2017, None, "auto", "butterworth", 0.2),)
    assert "records" not in ens.to_attrs()


@pytest.mark.parametrize("path, value", [
    ("highpass", "none"), ("fc_hz", 0.3), ("records.1.highpass", "oscillator"),
    ("records.2.fc_hz", 0.5), ("records.0.n_synthetic", 3), ("records.2.rotation_deg", 10.0),
    ("vertical", True), ("records.1.vertical", True),
])
def test_every_processing_setting_changes_the_stores_hash(path, value):
    before = StudySpec.from_config(_suite_config(), "st").spectra.digest
    cfg = _suite_config()
    node = cfg["ensembles"]["s"]
    *keys, last = path.split(".")
    for k in keys:
        node = node[int(k)] if k.isdigit() else node[k]
    node[last] = value
    assert StudySpec.from_config(cfg, "st").spectra.digest != before


@pytest.mark.parametrize("change, message", [
    (lambda e: e.update(record="el-centro-1940"), "ensembles.s needs record (one record) or "
                                                  "records (a suite), not both"),
    (lambda e: e.pop("records"), "not neither"),
    (lambda e: e["records"][1].update(highpass="bessel"),
     "ensembles.s.records[1].highpass must be one of"),
    (lambda e: e["records"][0].update(rotation_deg=60), "ensembles.s.records[0].rotation_deg "
                                                        "must be auto, none or a number"),
    (lambda e: e["records"][0].update(rotation_deg="none"),
     "ensembles.s.records[0].rotation_deg=none with n_synthetic=2"),
    (lambda e: e["records"][2].update(record="el-centro-1940"),
     "ensembles.s.records: repeated record names ['el-centro-1940']"),
    (lambda e: e["records"][2].update(fc_hz=-1.0),
     "ensembles.s.records[2].fc_hz must be a finite number > 0, got -1.0"),
    (lambda e: e.update(paths=["x.AT2", "y.AT2"]),
     "ensembles.s.paths=['x.AT2', 'y.AT2'] with records: give each record its own paths"),
    (lambda e: e["records"][2].update(colour="red"),
     "ensembles.s.records[2] has unknown key(s) ['colour']"),
])
def test_bad_suite_settings_name_the_key_and_value(change, message):
    cfg = _suite_config()
    change(cfg["ensembles"]["s"])
    with pytest.raises(ValueError) as err:
        EnsembleSpec.from_config(cfg, "s")
    assert message in str(err.value)


@pytest.mark.parametrize("value, message", [
    (["pga", "sa:x"], "studies.st.intensity_measures[1]='sa:x'"),
    (["pgd"], "an intensity measure is pga, pgv or 'sa:<T in s>'"),
    ([], "must be a non-empty list"),
])
def test_bad_intensity_measures_are_named(value, message):
    cfg = _suite_config()
    cfg["studies"]["st"]["intensity_measures"] = value
    with pytest.raises(ValueError, match=message.replace("[", r"\[").replace("(", r"\(")):
        StudySpec.from_config(cfg, "st")


def test_highpass_kinds_are_the_builders():
    assert spec_module.HIGHPASS_KINDS == HIGHPASS_KINDS


def _user_pair(tmp_path):
    paths = []
    for f in (ELC270, ELC180):
        p = tmp_path / f"my_{f}"
        shutil.copy(package_record(f), p)
        paths.append(str(p))
    return paths


def test_mw_is_checked_only_where_the_highpass_needs_it(tmp_path):
    from snakemake.utils import validate

    from rocking.config.checks import validate_config

    schema = spec_module.__file__.replace("src/rocking/config/ensemble.py",
                                          "workflow/schemas/config.schema.yaml")
    cfg = _suite_config()
    # the ensemble's fc_hz is every record's default: this one asks for the Brune corner
    cfg["ensembles"]["s"]["records"].append({"record": "my-pair", "paths": _user_pair(tmp_path),
                                            "highpass": "oscillator", "fc_hz": None})
    with pytest.raises(ValueError) as err:
        validate_config(copy.deepcopy(cfg), schema, validate)
    assert "ensembles.s.records[3].mw is needed: record 'my-pair' is not in the catalogue" \
        in str(err.value)
    for fix in ({"mw": 6.5}, {"fc_hz": 0.1}, {"highpass": "none"}):
        ok = copy.deepcopy(cfg)
        ok["ensembles"]["s"]["records"][3].update(fix)
        validate_config(ok, schema, validate)
        check_config(ok)


# --- intensity measures -------------------------------------------------------------------

def test_parse_measure():
    assert parse_measure("pga") == ("pga", None) and parse_measure("SA:0.5") == ("sa", 0.5)
    for bad in ("sa:0", "sa:-1", "pgd", 3):
        with pytest.raises(ValueError):
            parse_measure(bad)


def test_pgv_of_a_sine_is_its_closed_form():
    # a = A sin(wt) from rest: v = (A/w)(1 - cos wt), peak 2A/w at half periods
    A, f, dt = 3.0, 2.0, 1e-4
    t = np.arange(0.0, 2.0 + dt / 2, dt)
    a = A * np.sin(2 * np.pi * f * t)
    w = 2 * np.pi * f
    assert peak_vector_velocity(GroundMotion(a, None, dt, "x")) == \
        pytest.approx(2 * A / w, rel=1e-6)
    # both components equal: the vector is sqrt(2) times longer
    assert peak_vector_velocity(GroundMotion(a, a, dt, "xy")) == \
        pytest.approx(math.sqrt(2) * 2 * A / w, rel=1e-6)


def test_vector_sa_is_the_largest_sa_over_every_direction():
    m = cut(load_record("el-centro-1940"), 12.0)
    for T in (0.3, 1.0):
        directions = np.linspace(0.0, 180.0, 721)[:-1]
        per_angle = [pseudo_acceleration(rotate(m, th).ax, m.dt, [T])[0] / G
                     for th in directions]
        got = vector_sa(m, T)
        assert got >= max(per_angle) * (1 - 1e-12)
        assert got == pytest.approx(max(per_angle), rel=1e-5)  # 0.25 deg grid


def test_every_measure_is_linear_in_the_scale():
    m = cut(load_record("loma-prieta-corralitos"), 8.0)
    for name in ("pga", "pgv", "sa:0.5"):
        assert intensity_measure(m.scaled(2.5), name) == \
            pytest.approx(2.5 * intensity_measure(m, name), rel=1e-12)


# --- building a suite ---------------------------------------------------------------------

def test_suite_file_order_and_per_record_processing():
    settings = {"n_synthetic": 0, "seed": 1, "mw": None, "rotation_deg": "auto",
                "highpass": "oscillator", "fc_hz": None}
    elc, sfe = load_record("el-centro-1940"), load_record("san-fernando-pacoima-dam-1971")
    build = build_suite([(elc, {**settings, "n_synthetic": 1}),
                         (sfe, {**settings, "rotation_deg": "none", "highpass": "butterworth",
                                "fc_hz": 0.2})], max_duration=5.0)
    names = [m.name for m in build.motions]
    assert names == ["el-centro-1940", "san-fernando-pacoima-dam-1971",
                     "el-centro-1940-rdk-000"]
    # each record exactly as one record's ensemble with its own settings
    alone = build_ensemble(elc, 1, 1, max_duration=5.0).motions
    np.testing.assert_array_equal(build.motions[0].ax, alone[0].ax)
    np.testing.assert_array_equal(build.motions[2].ay, alone[1].ay)
    own = build_ensemble(sfe, 0, 1, rotation="none", highpass="butterworth", fc_hz=0.2,
                         max_duration=5.0).motions[0]
    np.testing.assert_array_equal(build.motions[1].ax, own.ax)
    assert build.motions[1].metadata["recorded_pga_g"] == sfe.pga_g
    assert [p["record"] for p in build.info["records"]] == [elc.name, sfe.name]
    with pytest.raises(ValueError, match="repeated"):
        build_suite([(elc, settings), (elc, settings)])


def test_rotation_none_keeps_the_recorded_axes_and_a_cut_keeps_the_record():
    sfe = load_record("san-fernando-pacoima-dam-1971")
    kept = build_ensemble(sfe, 0, 0, rotation="none", highpass="none", max_duration=3.0)
    n = kept.motions[0].npts
    np.testing.assert_array_equal(kept.motions[0].ax, sfe.ax[:n])
    np.testing.assert_array_equal(kept.motions[0].ay, sfe.ay[:n])
    with pytest.raises(ValueError, match="rotation='none' with n=2"):
        build_ensemble(sfe, 2, 0, rotation="none")
    # an acausal filter pads the front with zeros: a cut counts from the record's start
    bw = build_ensemble(sfe, 0, 0, rotation="none", highpass="butterworth", fc_hz=0.2,
                        max_duration=3.0).motions[0]
    whole = build_ensemble(sfe, 0, 0, rotation="none", highpass="butterworth",
                           fc_hz=0.2).motions[0]
    front = next(s["pad_front"] for s in whole.metadata["processing"]
                 if s["step"] == "highpass")
    assert front > 0 and bw.npts == front + 301  # 3 s at 0.01 s, both ends
    np.testing.assert_array_equal(bw.ax, whole.ax[:bw.npts])
    # a 0.2 Hz high-pass hardly moves the acceleration peak of the first 3 s
    assert np.max(np.abs(bw.ax[front:])) == pytest.approx(np.max(np.abs(sfe.ax[:301])),
                                                          rel=0.1)


# --- through Snakemake, Dask and zarr -----------------------------------------------------

SUITE = {
    "accuracy": "fast",
    "motions": {"max_duration": 3.0},
    "ensembles": {"three": {"n_synthetic": 0, "records": [
        {"record": "el-centro-1940", "n_synthetic": 1, "seed": 7},
        {"record": "san-fernando-pacoima-dam-1971", "highpass": "butterworth", "fc_hz": 0.2},
        {"record": "northridge-05-sylmar-1994", "rotation_deg": "none", "highpass": "none"},
    ]}},
    "studies": {"three": {"ensemble": "three", "R": [1.0, 3.0], "chunk_R": 1,
                          "intensity_measures": ["pga", "pgv", "sa:0.5"],
                          "runs": [{"modes": ["3d"], "tan_alpha": [0.2],
                                    "limit_states": ["overturning", "tilt:1/3"]}]}},
    "dask": {"progress_interval": 0},
}
RECORDS = [r["record"] for r in SUITE["ensembles"]["three"]["records"]]


def _write(tmp_path, cfg) -> object:
    import yaml

    path = tmp_path / "suite.yaml"
    path.write_text(yaml.safe_dump(cfg))
    return path


@pytest.mark.slow
def test_suite_dry_run_names_a_missing_mw(tmp_path, monkeypatch):
    """The workflow's one check of the configuration (the Snakefile calls it before any job:
    test_workflow.test_the_snakefile_refuses_a_bad_config_with_the_one_check)."""
    from snakemake.utils import validate
    from test_workflow import REPO

    from rocking.config.checks import check_workflow_config

    cfg = copy.deepcopy(SUITE)
    cfg["ensembles"]["three"]["records"].append({"record": "my-pair",
                                                 "paths": _user_pair(tmp_path)})
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError, match=r"^ensembles.three.records\[3\].mw is needed: "
                                         r"record 'my-pair' is not in the catalogue"):
        check_workflow_config(cfg, REPO, validate)
    assert not (tmp_path / "results").exists()


@pytest.mark.slow
def test_suite_study_through_snakemake_matches_the_library(tmp_path):
    """Three shipped records, each processed its own way (one with a synthetic pair), run
    on Dask into zarr; records.csv against critical_intensity on the same motions."""
    import xarray as xr
    from test_workflow import snakemake

    from rocking.config.ensemble import EnsembleSpec
    from rocking.dynamics.analysis import ground_response
    from rocking.dynamics.bodies import Cylinder
    from rocking.motions.ensemble_io import load_ensemble
    from rocking.spectra.accuracy import Accuracy
    from rocking.spectra.critical import critical_intensity
    from rocking.units import read_table

    snakemake(tmp_path, "results/three/records.csv", configfile=_write(tmp_path, SUITE))
    # the ensemble file is keyed by the digest of its settings
    digest = EnsembleSpec.from_config(SUITE, "three").digest
    ensemble = tmp_path / f"results/motions/three-{digest}.nc"
    motions = {m.name: m for m in load_ensemble(ensemble)}
    assert list(motions) == [*RECORDS, "el-centro-1940-rdk-000"]  # records first
    from rocking.motions.ensemble_io import open_netcdf

    with open_netcdf(ensemble) as ds:  # which record, what kind
        assert list(ds["source_record"].values) == [*RECORDS, "el-centro-1940"]
        assert list(ds["kind"].values) == ["record"] * 3 + ["synthetic"]
    # each record processed as configured
    sfe, nr = motions["san-fernando-pacoima-dam-1971"], motions["northridge-05-sylmar-1994"]
    assert sfe.metadata["highpass"] == {"kind": "butterworth", "fc_hz": 0.2, "order": 4}
    raw = load_record("northridge-05-sylmar-1994")
    np.testing.assert_array_equal(nr.ax, raw.ax[:nr.npts])  # recorded axes, no filter
    store = xr.open_zarr(tmp_path / "results/three/spectra.zarr", consolidated=True)
    attrs = {k: json.loads(v) if isinstance(v, str) and v[:1] in "{[" else v
             for k, v in store.attrs.items()}
    acc = Accuracy.of(attrs["tolerances"])
    table = read_table(tmp_path / "results/three/records.csv")
    assert sorted(set(table["motion"])) == sorted(RECORDS)  # recorded motions only
    assert len(table) == 3 * 2 * 2  # records x limit states x R
    states = ["overturning", "tilt:1/3"]
    for name in RECORDS:
        m = motions[name]
        for R in (1.0, 3.0):
            want = critical_intensity(Cylinder(R, 0.2), m, states, "3d",
                                      accuracy=attrs["tolerances"], **attrs["search_options"])
            for k, ls in enumerate(states):
                row = table[(table.motion == name) & (table.R == R) & (table.limit_state == ls)]
                assert len(row) == 1
                row = row.iloc[0]
                assert row.pga_recorded_g == pytest.approx(load_record(name).pga_g, rel=1e-9)
                assert row.pga_g == pytest.approx(m.pga_g, rel=1e-9)
                assert row.not_reached == bool(want.not_reached[k])
                assert row.plateau == bool(want.plateau[k])
                # exceeds_as_recorded: an independent analysis at scale 1
                r = ground_response(Cylinder(R, 0.2), m, model="3d", scale=1.0,
                                    history=False, rtol=acc.rtol_for("3d"),
                                    rest_tilt=acc.rest_tilt)
                hit = r.overturned or (ls == "tilt:1/3" and r.theta_max > math.atan(0.2) / 3)
                assert row.exceeds_as_recorded == hit
                if want.not_reached[k]:
                    assert math.isnan(row.pga_crit)
                    assert row.as_recorded_disagrees == hit
                    continue
                assert row.pga_crit == pytest.approx(want.intensity[k], rel=1e-9)
                assert row.pga_crit_g == pytest.approx(want.pga_g[k], rel=1e-9)
                scale = want.pga_g[k] / m.pga_g
                assert row.scale_factor == pytest.approx(scale, rel=1e-9)
                assert row.as_recorded_disagrees == (hit != (scale <= 1.0))
                assert row.pgv_crit == pytest.approx(scale * peak_vector_velocity(m),
                                                     rel=1e-9)
                assert row["sa_0.5s_crit"] == pytest.approx(scale * vector_sa(m, 0.5),
                                                            rel=1e-9)
    # the suite's fragility: records and the synthetic pair apart; closed form without
    # censoring: median exp(mean ln x), beta std(ln x)
    frag = read_table(tmp_path / "results/three/suite_fragility.csv")
    assert set(frag["motions"]) == {"records", "synthetic"}
    checked = 0
    for ls in states:
        for R in (1.0, 3.0):
            cell = table[(table.R == R) & (table.limit_state == ls)]
            fit = frag[(frag.motions == "records") & (frag.R == R) & (frag.limit_state == ls)
                       & (frag.measure == "pga")].iloc[0]
            if cell.not_reached.any() or cell.failed.any():
                continue
            x = np.log(cell.pga_crit_g.to_numpy())
            assert fit["n"] == 3 and fit["status"] == "ok"
            assert fit["median"] == pytest.approx(math.exp(x.mean()), rel=1e-8)
            assert fit["beta"] == pytest.approx(x.std(), rel=1e-8)
            checked += 1
    assert checked >= 2


# --- docs/records.md ----------------------------------------------------------------------

DOC = spec_module.__file__.replace("src/rocking/config/ensemble.py", "docs/records.md")


def test_records_page_config_is_valid_and_its_columns_are_the_tables():
    import re

    import yaml

    from rocking.config.checks import schema_error
    from rocking.study.records import RECORD_COLUMNS

    text = open(DOC, encoding="utf-8").read()
    blocks = [yaml.safe_load(b) for b in re.findall(r"```yaml\n(.*?)```", text, re.S)]
    assert blocks
    schema_path = spec_module.__file__.replace("src/rocking/config/ensemble.py",
                                               "workflow/schemas/config.schema.yaml")
    schema = yaml.safe_load(open(schema_path, encoding="utf-8"))
    for config in blocks:
        assert schema_error(config, schema) is None
        for study in config["studies"]:
            spec = StudySpec.from_config(config, study)
            assert spec.ensemble.is_suite and len(spec.ensemble.records) == 4
    for column in RECORD_COLUMNS:
        assert f"`{column}" in text, column


def test_records_page_processing_numbers_hold():
    """docs/records.md: 1.23 g as recorded, 1.76 g (Mw 6.69), 3.43 g (Mw 5.13, past the
    default bound: searched to PGA/(g tan α) = 40), within the answers' stated error."""
    import rocking
    from rocking.study.verify import answer_tolerance

    raw = load_record("northridge-05-sylmar-1994")
    cyl = rocking.Cylinder(R=3.0, tan_alpha=0.15)
    for kw, upper, want in ((dict(rotation=None, highpass="none"), 20.0, 1.23),
                            (dict(rotation="auto", highpass="oscillator", mw=6.69), 20.0, 1.76),
                            (dict(rotation="auto", highpass="oscillator", mw=5.13), 40.0, 3.43)):
        res = rocking.critical_intensity(cyl, rocking.process_motion(raw, **kw),
                                         ["overturning"], mode="3d", upper=upper)
        assert float(res.pga_g[0]) == pytest.approx(want, rel=answer_tolerance("default")[0]), kw
    bound = rocking.critical_intensity(cyl, rocking.process_motion(
        raw, rotation="auto", highpass="oscillator", mw=5.13), ["overturning"], mode="3d")
    assert bool(bound.not_reached[0])  # by 3.0 g: the table's "not reached"


# --- the per-record table on a hand-made store --------------------------------------------

def _store_of(motions, crit_g, not_reached, requested):
    """A spectra store's variables over (mode, limit_state, motion, tan_alpha, R)."""
    import xarray as xr

    dims = ("mode", "limit_state", "motion", "tan_alpha", "R")
    crit_g = np.asarray(crit_g, dtype=float).reshape(1, 2, len(motions), 1, 1)
    nr = np.asarray(not_reached, dtype=bool).reshape(crit_g.shape)
    zeros = np.zeros(crit_g.shape, dtype=bool)
    return xr.Dataset(
        {"pga_crit": (dims, crit_g / 0.2), "pga_crit_g": (dims, crit_g),
         "not_reached": (dims, nr), "plateau": (dims, zeros),
         "non_monotonic": (dims, zeros), "failed": (dims, zeros),
         "requested": (("mode", "limit_state", "tan_alpha"),
                       np.asarray(requested, dtype=bool).reshape(1, 2, 1))},
        coords={"mode": ["3d"], "limit_state": ["tilt:1/3", "overturning"],
                "motion": [m.name for m in motions], "tan_alpha": [0.2], "R": [2.0]},
        attrs={"quantity": '{"name": "exceedance_quantile", "p": 0.1, "w": 0.02}',
               "tolerances": '{"scan_step": 0.03}'})


def _motions():
    """Three records (the third Corralitos at 0.8 of its scale), one synthetic pair."""
    a = cut(load_record("el-centro-1940"), 6.0)
    b = cut(load_record("loma-prieta-corralitos"), 6.0)
    b8 = GroundMotion(0.8 * b.ax, 0.8 * b.ay, b.dt, "lpc-0.8", {})
    c = GroundMotion(b.ax, b.ay, b.dt, "lpc-rdk-000",
                     {"generator": "rdk", "record": b.name, "realization": 0, "seed": 1})
    return [a, b, b8, c]


def test_record_table_scale_factor_and_requested_cells():
    from rocking.study.records import record_table

    motions = _motions()
    a, b, b8, _ = motions
    # a: exceeds tilt:1/3 at 0.5 g, overturning not reached; b: 0.3 g and 0.4 g
    store = _store_of(motions, [[0.5, 0.3, 0.3, 0.3], [np.nan, 0.4, 0.4, 0.4]],
                      [[False] * 4, [True, False, False, False]], [True, True])
    t = record_table(store, motions, ["pga", "pgv"])
    assert list(t["motion"]) == [a.name, a.name, b.name, b.name, b8.name, b8.name]
    assert list(t["limit_state"]) == ["tilt:1/3", "overturning"] * 3  # store order
    row = t.iloc[0]
    assert row["scale_factor"] == pytest.approx(0.5 / a.pga_g, rel=1e-12)
    assert row["pgv_crit"] == pytest.approx(0.5 / a.pga_g * peak_vector_velocity(a),
                                            rel=1e-12)
    lost = t.iloc[1]
    assert lost["not_reached"] and math.isnan(lost["scale_factor"])
    assert t.iloc[2]["scale_factor"] == pytest.approx(0.3 / b.pga_g, rel=1e-12)
    # a limit state no run asked for is not a row
    only = record_table(_store_of(motions, np.full((2, 4), 0.5), np.zeros(8), [False, True]),
                        motions, ["pga"])
    assert set(only["limit_state"]) == {"overturning"} and len(only) == 3


@pytest.mark.parametrize("R", [0.6, 2.0])
def test_exceeds_as_recorded_is_an_analysis_at_scale_one(R):
    """Every record row against its own ground_response at scale 1; the scale factors of the
    hand-made store are chosen so that some rows disagree with it."""
    from rocking.dynamics.analysis import ground_response
    from rocking.dynamics.bodies import Cylinder
    from rocking.spectra.accuracy import Accuracy
    from rocking.study.records import as_recorded, record_table

    motions = _motions()
    # crit PGA [g]: below and above each record's PGA (0.28-0.64 g); overturning of a lost
    store = _store_of(motions, [[0.1, 0.9, 0.3, 0.3], [np.nan, 0.4, 2.0, 0.4]],
                      [[False] * 4, [True, False, False, False]], [True, True])
    table = record_table(store.assign_coords(R=[R]), motions, ["pga"])
    acc = Accuracy.of("fast")
    t = as_recorded(table, motions, accuracy="fast")
    assert list(t.columns[list(t.columns).index("scale_factor") + 1:][:3]) == [
        "exceeds_as_recorded", "as_recorded_disagrees", "as_recorded_note"]
    by_name = {m.name: m for m in motions}
    alpha = math.atan(0.2)
    for row in t.itertuples():
        r = ground_response(Cylinder(R, 0.2), by_name[row.motion], model="3d", scale=1.0,
                            history=False, rtol=acc.rtol_for("3d"), rest_tilt=acc.rest_tilt)
        hit = bool(r.overturned or (row.limit_state == "tilt:1/3"
                                    and r.theta_max > alpha / 3))
        assert row.exceeds_as_recorded == hit, (row.motion, row.limit_state)
        implied = (not row.not_reached) and row.scale_factor <= 1.0
        assert row.as_recorded_disagrees == (hit != implied)
        assert (row.as_recorded_note != "") == (hit != implied)
        if hit and not implied:
            assert row.as_recorded_note.startswith("exceeds at scale 1 although")
        elif implied and not hit:
            assert row.as_recorded_note.startswith("survives at scale 1 although it exceeds "
                                                   f"at scale {row.scale_factor:.3g}")
    assert t["as_recorded_disagrees"].sum() >= 2  # the store was made to disagree


def test_suite_fragility_censors_at_the_bound_in_every_measure():
    from rocking.fragility.lognormal import fit_lognormal
    from rocking.study.records import record_table, suite_fragility

    motions = _motions()
    a, b, b8, _ = motions
    store = _store_of(motions, [[0.5, 0.3, 0.3, 0.35], [np.nan, 0.4, 0.6, 0.45]],
                      [[False] * 4, [True, False, False, False]], [True, True])
    table = record_table(store, motions, ["pgv"], kinds=("record", "synthetic"))
    frag = suite_fragility(table, ["pga", "pgv"], upper=20.0)
    assert set(frag["motions"]) == {"records", "synthetic"}
    over = frag[(frag.motions == "records") & (frag.limit_state == "overturning")]
    # a is censored at its record scaled to PGA = 20 g tan(alpha) = 4 g
    want = fit_lognormal([0.4, 0.6, 4.0], [False, False, True])
    got = over[over.measure == "pga"].iloc[0]
    assert got["n_censored"] == 1 and got["median"] == pytest.approx(want.median, rel=1e-12)
    pgv = [0.4 / b.pga_g * peak_vector_velocity(b), 0.6 / b8.pga_g * peak_vector_velocity(b8),
           4.0 / a.pga_g * peak_vector_velocity(a)]
    # Corralitos and its 0.8 copy have one PGV/PGA ratio: the same critical PGVs as PGAs
    assert pgv[1] / pgv[0] == pytest.approx(0.6 / 0.4, rel=1e-12)
    want = fit_lognormal(pgv, [False, False, True])
    got = over[over.measure == "pgv"].iloc[0]
    # the censored likelihood's optimum to the optimizer's tolerance (gtol 1e-9): the suite
    # hands the motions in the store's order, this list another
    assert got["median"] == pytest.approx(want.median, rel=1e-7)
    assert got["beta"] == pytest.approx(want.beta, rel=1e-7) and got["unit"] == "m/s"
    # one synthetic motion: no fit, said so
    syn = frag[frag.motions == "synthetic"]
    assert set(syn["status"]) == {"too-few-observed"} and set(syn["n"]) == {1}


def test_a_suite_carries_the_vertical_of_the_records_that_ask_for_it(tmp_path):
    """Per-record vertical: the motions rule's reading (read_motion) and build_suite keep
    the vertical of the records built with it, processed like x and y, and none elsewhere;
    the ensemble file round-trips both."""
    from rocking.motions.build import read_motion
    from rocking.motions.ensemble_io import load_ensemble, save_ensemble

    settings = {"n_synthetic": 0, "seed": 1, "mw": None, "rotation_deg": "auto",
                "highpass": "oscillator", "fc_hz": None}
    sfe = read_motion("san-fernando-pacoima-dam-1971", vertical=True)
    elc = read_motion("el-centro-1940")
    build = build_suite([(sfe, settings), (elc, settings)], max_duration=5.0)
    alone = build_ensemble(sfe, 0, 1, max_duration=5.0).motions[0]
    assert alone.has_vertical and build.motions[1].az is None
    np.testing.assert_array_equal(build.motions[0].az, alone.az)
    back = load_ensemble(save_ensemble(tmp_path / "s.nc", build.motions))
    assert [m.samples_sha256 for m in back] == [m.samples_sha256 for m in build.motions]
