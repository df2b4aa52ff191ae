"""The HTML report: every figure with its caption, and the headline table quoting the paper
and this run (numbers known from the synthetic study's formula)."""

from __future__ import annotations

import html
import json
import math

import figures_synthetic as fs
import numpy as np
import pandas as pd
import pytest

from rocking import Cylinder
from rocking.spectra import fragility
from rocking.study import report
from rocking.study.figures import _load, _style, render


@pytest.fixture(scope="module")
def outputs(tmp_path_factory):
    root = tmp_path_factory.mktemp("report")
    paths = fs.write_study(root / "study")
    out = root / "figures"
    pngs = []

    def fig(name, stem, **kw):
        render(name, [out / f"{stem}.png"], out / f"{stem}.json", **kw)
        pngs.append(out / f"{stem}.png")

    fig("fig03", "fig03_wobbling_period", n=40)
    fig("fig07", "fig07_tilt_map", path=paths["tilt_map"])
    fig("fig09", "fig09_spectra", store=paths["store"], means=paths["means"])
    fig("fig10", "fig10_goals", means=paths["means"])
    fig("fig11", "fig11_slenderness", means=paths["means"])
    fig("fig12", "fig12_2d_vs_3d", studies=[("synth", paths["means"], paths["store"])])
    table = fragility.fragility_table(_load.open_store(paths["store"]))
    table.to_netcdf(root / "fragility.nc")
    fragility.to_frame(table).to_csv(root / "fragility.csv", index=False)
    lines = fragility.linear_fit_table(_load.open_means(paths["means"]))
    fragility.to_frame(lines).to_csv(root / "linear_fit.csv", index=False)
    fig("fragility", "fragility_curves", fragility=root / "fragility.nc", store=paths["store"])
    # Figures of analyses (4, 6, 8) as the report receives them: a PNG and its notes
    notes = {
        "fig04_free_vibration": {"turn_angle_first": 3.1881, "turn_angle_mean": 3.1880,
                                 "n_turns": 6, "restitution_damped": 0.9422,
                                 "restitution_undamped": 1.0},
        "fig06_el_centro": {"theta_max_3d": 0.048, "theta_max_3d-damped": 0.0479},
        "fig08_motions_elcentro": {"record": "el-centro-1940", "record_pga_g": 0.28,
                                   "principal_offset_deg": 19.54, "n_motions": 4},
    }
    for stem, measured in notes.items():
        f, _ = _style.new_figure(2.0, 2.0)
        _style.save(f, [out / f"{stem}.png"])
        _style.write_notes(out / f"{stem}.json", {"measured": measured, "missing": []})
        pngs.append(out / f"{stem}.png")
    html = report.build(root / "report.html", title="synthetic study", figures=pngs,
                        linear_fit=root / "linear_fit.csv", fragility=root / "fragility.csv",
                        notes=["The Loma Prieta record is a stand-in."])
    return {"root": root, "pngs": pngs, "html": html}


def test_report_shows_every_figure_with_its_caption(outputs):
    text = outputs["html"].read_text()
    assert text.count("<figure") == len(outputs["pngs"]) == 10
    assert text.count("data:image/png;base64,") == 10
    for key, caption in report.CAPTIONS.items():
        assert f"id='{key}'" in text
        assert html.escape(caption) in text
    # figures in the paper's order
    positions = [text.index(f"id='{k}'") for k in report.CAPTIONS]
    assert positions == sorted(positions)
    assert "The Loma Prieta record is a stand-in." in text
    assert "Peak tilt undamped 0.048 rad, damped 0.0479 rad." in text


def test_headline_table_quotes_paper_and_run(outputs):
    figures = report.load_figures(outputs["pngs"])
    lin = pd.read_csv(outputs["root"] / "linear_fit.csv")
    table = report.headline_table(figures, lin).set_index("quantity")
    body = Cylinder(6.0, 0.2)
    turn = table.loc["Angle of turn per quasi-impact [rad]"]
    assert turn["paper"].startswith("3.058")
    assert f"{body.turn_angle:.5f}" == "3.18802" and "3.18802" in turn["this run"]
    assert f"{2 * math.pi - 3.1881:.4f}" in turn["this run"]
    rest = table.loc["Restitution, damped quasi-rocking [-]"]
    assert "0.942169" in rest["this run"] and "0.9422" in rest["this run"]
    assert table.loc["Fig 6 peak tilt, undamped / damped [rad]", "paper"] == "0.0838 / 0.0668"
    angle = table.loc["Principal-axis angle of the record (el-centro-1940) [deg]"]
    assert angle["this run"] == "19.54" and angle["paper"] == "22.33 (El Centro)"
    # synthetic means of θ > α/3: 1.5 (0.5 + 0.4 R) · mean motion factor 1.0375, exactly linear
    row = table.loc["Mean spectrum linear in R, tilt:0.3333 (3d, tan α = 0.2)", "this run"]
    assert "slope 0.6225 1/m" in row and "intercept 0.7781" in row and "R² 1 " in row
    r10 = table.loc["Overturning at R = 10 m, synth: 3D mean PGA/(g tan α); 2D-x, 2D-y "
                    "relative to 3D", "this run"]
    expected = 4.0 * (0.5 + 0.4 * 10.0) * np.mean([1.0, 0.8, 1.25, 1.1])
    assert r10.startswith(f"{expected:.4g};")
    assert all(len(r) > 40 for r in table["reason for difference"])


def test_missing_measurements_are_said_not_invented(outputs):
    figures = [f for f in report.load_figures(outputs["pngs"]) if f.key != "fig06"]
    table = report.headline_table(figures, None).set_index("quantity")
    assert table.loc["Fig 6 peak tilt, undamped / damped [rad]", "this run"] == (
        "not measured / not measured")


def test_bad_inputs_name_the_file(tmp_path):
    with pytest.raises(ValueError, match="figNN_"):
        report.figure_key(tmp_path / "plot.png")
    with pytest.raises(ValueError, match="does not exist"):
        report.load_figures([tmp_path / "fig03_missing.png"])
    notes = json.dumps({"measured": {}})
    (tmp_path / "fig09_x.json").write_text(notes)
    with pytest.raises(ValueError, match="fig09_x.png"):
        report.load_figures([tmp_path / "fig09_x.png"])
