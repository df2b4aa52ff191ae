"""``rocking motions``: the ensemble file holds the processed record first, then its pairs."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from rocking.cli import main
from rocking.motions.build import build_ensemble, read_motion
from rocking.motions.catalogue import load_record
from rocking.motions.ensemble_io import ensemble_attrs, load_ensemble
from rocking.motions.highpass import brune_corner, highpass_motion, residuals
from rocking.motions.principal import correlation, to_principal_axes


def test_cli_writes_record_then_pairs(tmp_path: Path, capsys: pytest.CaptureFixture) -> None:
    out = tmp_path / "motions" / "elcentro.nc"
    recorded = tmp_path / "elcentro.params.json"
    assert main(["motions", "--record", "el-centro-1940", "-n", "2", "--seed", "5",
                 "--compare", "-o", str(out), "--write-params", str(recorded)]) == 0
    printed = capsys.readouterr()
    assert "rocking motions:" in printed.err  # progress on stderr
    # The fit quality of both identifications on stdout, per component and band.
    assert "spectrum fit" in printed.out and "counts fit" in printed.out
    assert printed.out.count("x (major): median PSA / record 0.1-0.3 s") == 2
    motions = load_ensemble(out)
    assert len(motions) == 3
    # The record, processed independently here, is stored first and unchanged.
    rotated, angle = to_principal_axes(load_record("el-centro-1940"))
    expected = highpass_motion(rotated, "oscillator", brune_corner(6.95))
    np.testing.assert_array_equal(motions[0].ax, expected.ax)
    np.testing.assert_array_equal(motions[0].ay, expected.ay)
    assert motions[0].name == "el-centro-1940"
    params = json.loads(out.with_suffix(".json").read_text())
    assert params["rotation_deg"] == pytest.approx(angle, abs=1e-12)
    assert params["highpass"]["fc_hz"] == pytest.approx(0.0946, abs=1e-4)
    assert 0.0 < params["fit"]["major"]["zeta_f"] < 1.0
    assert params["fit_method"] == "spectrum" and params["fit"]["major"]["f_low"] > 0.0
    attrs = ensemble_attrs(out)
    assert attrs["n_synthetic"] == 2 and attrs["fit_method"] == "spectrum"
    assert attrs["fit_quality"] == params["fit_quality"]
    assert set(attrs["fit_quality"]["x"]["band_ratio"]) == {"0.1-0.3 s", "0.3-1 s", "1-4 s"}
    other = load_ensemble(out.with_name("elcentro.compare.nc"))
    assert [m.metadata.get("fit_method") for m in other[1:]] == ["counts", "counts"]
    np.testing.assert_array_equal(other[0].ax, motions[0].ax)  # the same record
    assert ensemble_attrs(out.with_name("elcentro.compare.nc"))["fit_method"] == "counts"
    for syn in motions[1:]:
        assert syn.dt == 0.01 and syn.metadata["seed"] == 5
        # High-passed like the record: no residual velocity or displacement.
        for comp in (syn.ax, syn.ay):
            res = residuals(comp, syn.dt)
            assert res.v_rel < 1e-6 and res.d_rel < 1e-6
        assert abs(correlation(syn.ax, syn.ay)) < 0.3
    # The recorded parameters: the pairs' digests, and the same pairs made again from them
    # without a fit (what ensembles.<name>.params of a study does)
    from rocking.motions.stochastic.recorded import read_params_file

    entry = read_params_file(recorded)["records"]["el-centro-1940"]
    assert entry["pairs_sha256"] == [m.samples_sha256 for m in motions[1:]]
    assert entry["settings"]["rotation_deg"] == "auto" and entry["seed"] == 5
    again = build_ensemble(load_record("el-centro-1940"), 2, 5, recorded=entry)
    assert [m.samples_sha256 for m in again.motions[1:]] == entry["pairs_sha256"]
    assert again.info["motions_match"] is True and "fit_s" not in again.info["timings"]


def test_stand_in_label_reaches_the_ensemble(tmp_path: Path) -> None:
    build = build_ensemble(read_motion("loma-prieta-sjte"), 0, 1, highpass="none")
    assert len(build.motions) == 1 and build.fit is None
    info = build.parameters()
    assert info["stand_in"] is True and "RSN801" in info["stand_in_for"]
    assert "stand-in" in info["label"]
    # Corralitos on principal axes: x carries the larger Arias intensity.
    rec = build.motions[0]
    assert rec.ax @ rec.ax > rec.ay @ rec.ay
    assert abs(correlation(rec.ax, rec.ay)) < 1e-12


def test_bad_arguments(tmp_path: Path) -> None:
    motion = load_record("el-centro-1940")
    with pytest.raises(ValueError, match="highpass"):
        build_ensemble(motion, 0, 1, highpass="fir")
    with pytest.raises(ValueError, match="n must be"):
        build_ensemble(motion, -1, 1)
    with pytest.raises(ValueError, match="fit_method"):
        build_ensemble(motion, 0, 1, fit_method="zeros")
    assert main(["motions", "-o", str(tmp_path / "x.csv")]) == 2


def test_cli_vertical_keeps_the_records_vertical(tmp_path: Path) -> None:
    """``--vertical``: the record is stored with its UP file, rotated about z and high-passed
    like x and y (checked against the same steps done here); three files say the same."""
    out = tmp_path / "v.nc"
    assert main(["motions", "--record", "el-centro-1940", "--vertical", "-n", "0",
                 "--max-duration", "3", "-q", "-o", str(out)]) == 0
    (record,) = load_ensemble(out)
    rotated, _ = to_principal_axes(load_record("el-centro-1940", vertical=True))
    expected = highpass_motion(rotated, "oscillator", brune_corner(6.95))
    n = record.npts
    np.testing.assert_array_equal(record.az, expected.az[:n])
    np.testing.assert_array_equal(record.ax, expected.ax[:n])
    with pytest.raises(ValueError, match="three files"):
        read_motion("el-centro-1940", ["x.AT2", "y.AT2"], vertical=True)
