"""Figures: the data handed to matplotlib equals the store/aggregate/engine values, closed
forms and invariants hold, files are written, and the Snakemake rules build them."""

from __future__ import annotations

import json
import math
import shutil
import subprocess
import sys
from pathlib import Path

import figures_synthetic as fs
import numpy as np
import pytest
import xarray as xr
import yaml

from rocking import Cylinder, GroundMotion
from rocking.constants import G
from rocking.study.figures import (
    fig03_wobbling_period,
    fig04_free_vibration,
    fig06_el_centro,
    fig07_tilt_map,
    fig08_motions,
    fig09_spectra,
    fig10_goals,
    fig11_slenderness,
    fig12_2d_vs_3d,
    render,
)

ROOT = Path(__file__).parents[1]


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    return fs.write_study(tmp_path_factory.mktemp("study"))


@pytest.fixture(scope="module")
def reduced(tmp_path_factory):
    """A reduced run: undamped 3D only, no tilt map, a Loma Prieta stand-in label."""
    return fs.write_study(tmp_path_factory.mktemp("reduced"), modes=["3d"], stand_in=True,
                          ensemble="Loma Prieta 1989 (stand-in: Corralitos)",
                          with_tilt_map=False)


def _lines(ax):
    return [(np.asarray(ln.get_xdata(), float), np.asarray(ln.get_ydata(), float))
            for ln in ax.get_lines()]


def _same(a, b):
    np.testing.assert_array_equal(np.asarray(a, float), np.asarray(b, float))


# ---------------------------------------------------------------- Fig 3: closed forms


def test_fig03_small_tilt_asymptotes_and_size_independence():
    d = fig03_wobbling_period.data(n=400)
    r = d["theta_over_alpha"]
    small = r < 2e-3
    for tan_alpha, tp in d["wobbling"].items():
        body = Cylinder(1.0, tan_alpha)
        # θ → 0: μ'(θ) → 2κt θ, so T·p → 2π √(κt θ /(κo sin α)) (independent of Eq 24's form)
        limit = 2 * np.pi * np.sqrt(body.kappa_t * r[small] * body.alpha
                                    / (body.kappa_o * math.sin(body.alpha)))
        np.testing.assert_allclose(tp[small], limit, rtol=5e-3)
        assert np.all(np.diff(tp) > 0)  # period grows with amplitude, like rocking
    # Housner: 4 arccosh(1/(1 − r)) → 4 √(2r) for small r
    np.testing.assert_allclose(d["housner"][small], 4 * np.sqrt(2 * r[small]), rtol=2e-3)
    other = fig03_wobbling_period.data(n=400, R=7.5)
    for tan_alpha in d["wobbling"]:
        np.testing.assert_allclose(other["wobbling"][tan_alpha], d["wobbling"][tan_alpha],
                                   rtol=1e-12)


def test_fig03_plot_hands_the_data_to_matplotlib():
    d = fig03_wobbling_period.data(n=50)
    lines = _lines(fig03_wobbling_period.plot(d).axes[0])
    expected = [*d["wobbling"].values(), d["housner"]]
    assert len(lines) == len(expected)
    for (x, y), e in zip(lines, expected, strict=True):
        _same(x, d["theta_over_alpha"])
        _same(y, e)
    with pytest.raises(ValueError, match="theta_over_alpha"):
        fig03_wobbling_period.housner_period_times_p([1.2])


# ---------------------------------------------------------------- Fig 4: measurement helpers


def test_centre_of_mass_stays_at_distance_R_from_the_contact_point():
    body = Cylinder(6.0, 0.2)
    theta = np.linspace(0.0, body.alpha + 0.5, 50)
    phi = np.linspace(-3.0, 9.0, 50)
    x, y = fig04_free_vibration.centre_of_mass_orbit(body, theta, phi)
    # contact point on the rim at radius b along φ; centre of mass at height b sinθ + h cosθ
    dx, dy = x - body.b * np.cos(phi), y - body.b * np.sin(phi)
    z = body.b * np.sin(theta) + body.h * np.cos(theta)
    np.testing.assert_allclose(np.sqrt(dx**2 + dy**2 + z**2), body.R, rtol=1e-12)
    np.testing.assert_allclose(np.arctan2(y[theta > 0], x[theta > 0]),
                               np.angle(np.exp(1j * phi[theta > 0])), atol=1e-12)


def test_turn_angle_and_restitution_of_a_known_signal():
    # |sin| arches whose amplitude falls by e per impact; φ turns by a known angle per impact
    e, turn, omega = 0.93, 3.1, 2.0
    t = np.linspace(0.0, 8 * np.pi / omega, 80001)[:-1]
    k = np.floor((t * omega + np.pi / 2) / np.pi)  # impacts where cos(ωt) = 0
    theta = 0.1 * e**k * np.abs(np.cos(omega * t))
    theta_dot = np.gradient(theta, t)
    phi = turn * k
    angles = fig04_free_vibration.turn_angles(theta, phi)
    np.testing.assert_allclose(angles, turn, rtol=1e-12)
    assert fig04_free_vibration.restitution(theta, theta_dot) == pytest.approx(e, rel=1e-3)
    with pytest.raises(ValueError, match="n_impacts"):
        fig04_free_vibration.restitution(theta, theta_dot, n_impacts=20)


@pytest.fixture(scope="module")
def fig04_data():
    return fig04_free_vibration.data(duration=15.0)


def test_fig04_against_closed_forms_and_invariants(fig04_data):
    d = fig04_data
    body = Cylinder(6.0, 0.2)
    m, pred = d["measured"], d["predicted"]
    # Small-spin asymptote of the turn per quasi-impact (corrected Eq 27), φ̇0 = 1e-8
    assert m["turn_angle_first"] == pytest.approx(body.turn_angle, abs=1e-3)
    # Undamped: energy conserved, so every approach speed is the first one
    assert m["restitution_undamped"] == pytest.approx(1.0, abs=1e-4)
    # Damped: Housner's e = 1 − 2 sin²α/κo (Eq 31), the paper's 0.942 (Eq 32)
    assert m["restitution_damped"] == pytest.approx(body.e, abs=2e-3)
    # First approach speed from energy: p √(2 (cos(α − θ0) − cos α)) = 0.190 (paper's 0.19)
    assert m["approach_speeds_damped"][0] == pytest.approx(pred["first_approach_speed"],
                                                           rel=1e-3)
    wob = d["runs"]["wobbling"]
    for model in ("3d", "3d-damped"):
        # Pure wobbling (corrected Eq 24) keeps the tilt and spin constant
        np.testing.assert_allclose(wob[model]["theta"], 0.1, atol=1e-6)
        np.testing.assert_allclose(wob[model]["phi_dot"], body.wobbling_rate(0.1), rtol=1e-6)
    mixed = d["runs"]["mixed"]["3d"]
    assert mixed["theta"].min() > 0.02  # "the tilt never comes close to zero"


def test_fig04_plot_draws_the_histories(fig04_data):
    fig = fig04_free_vibration.plot(fig04_data)
    run = fig04_data["runs"]["mixed"]["3d-damped"]
    drawn = [ln for ax in fig.axes for ln in ax.get_lines()]
    ys = [np.asarray(ln.get_ydata(), float) for ln in drawn]
    for key in ("theta", "theta_dot", "phi", "phi_dot", "y"):
        assert any(y.shape == run[key].shape and np.array_equal(y, run[key]) for y in ys), key


# ---------------------------------------------------------------- Fig 6: El Centro response


def test_fig06_passes_the_engine_response_and_ground_unchanged():
    from rocking.dynamics.analysis import ground_response

    dt = 0.01
    t = np.arange(0.0, 3.0, dt)
    env = np.sin(np.pi * t / 3.0) ** 2
    motion = GroundMotion(4.0 * env * np.sin(2 * np.pi * 1.5 * t),
                          3.0 * env * np.cos(2 * np.pi * 1.1 * t), dt, "pulse-pair")
    d = fig06_el_centro.data(motion, R=2.0, tan_alpha=0.2, models=("3d",))
    direct = ground_response(Cylinder(2.0, 0.2), motion, model="3d")
    run = d["runs"]["3d"]
    _same(run["theta"], direct.theta)
    _same(run["phi_dot"], direct.phi_dot)
    assert run["w"] is None
    assert d["measured"]["theta_max_3d"] == direct.theta_max
    # the engine's peak is located between output samples: never below the sampled maximum
    assert np.max(run["theta"]) <= direct.theta_max <= np.max(run["theta"]) * (1 + 1e-4)
    _same(d["ground"]["ax"], motion.ax)
    fig = fig06_el_centro.plot(d)
    assert len(fig.axes) == 8
    _same(_lines(fig.axes[0])[0][1], run["theta"])
    _same(_lines(fig.axes[-1])[0][1], motion.ay)
    with pytest.raises(ValueError, match="zero component"):
        fig06_el_centro.data(motion.component("x"))


# ---------------------------------------------------------------- Figs 7–12 from a store


def test_fig07_data_equal_the_tilt_map_store(study):
    d = fig07_tilt_map.data(study["tilt_map"])
    with xr.open_zarr(study["tilt_map"], consolidated=False) as ds:
        for model in ("3d", "3d-damped"):
            _same(d["theta_over_alpha"][model], ds["theta_max_over_alpha"].sel(model=model))
        _same(d["R"], ds["R"])
    z = d["theta_over_alpha"]["3d"]
    first = fig07_tilt_map.first_above(z, d["intensity"])
    for i in range(len(d["R"])):
        above = d["intensity"][z[i] >= 1.0]
        assert first[i] == (above.min() if above.size else np.nan) or np.isnan(first[i])
    assert d["measured"]["first_intensity_theta_above_alpha_3d"] == pytest.approx(
        first.tolist(), nan_ok=True)
    fig = fig07_tilt_map.plot(d)
    assert len(fig.axes) == 3  # two maps and the colour bar


def test_fig09_lines_are_the_store_and_the_aggregate(study):
    d = fig09_spectra.data(study["store"], study["means"])
    assert [p["limit_state"] for p in d["panels"]] == ["overturning", "tilt:0.3333"]
    ds = xr.open_zarr(study["store"], consolidated=False).load()
    agg = xr.open_dataset(study["means"]).load()
    fig = fig09_spectra.plot(d)
    for ax, panel in zip(fig.axes, d["panels"], strict=True):
        ls = panel["limit_state"]
        lines = _lines(ax)
        per_motion, means = lines[:8], lines[8:10]
        k = 0
        for mode in ("3d", "3d-damped"):
            for motion in fs.MOTIONS:
                point = ds.sel(mode=mode, limit_state=ls, motion=motion, tan_alpha=0.2)
                expected = point["pga_crit"].where(~point["not_reached"]).values
                _same(per_motion[k][1], expected)
                k += 1
        for (x, y), mode in zip(means, ("3d", "3d-damped"), strict=True):
            _same(x, agg["R"])
            _same(y, agg["mean"].sel(mode=mode, limit_state=ls, tan_alpha=0.2))
    # two cut-off motions leave NaN, never the search bound, in the drawn overturning curves
    assert np.isnan(d["panels"][0]["curves"]["3d"]["synthetic-01"][0])
    # synthetic damped spectra are 5 % above the undamped ones wherever all motions count
    assert d["measured"]["max_rel_diff_damped_tilt:0.3333"] == pytest.approx(0.05, rel=1e-9)


def test_fig10_fig11_lines_are_the_aggregate(study):
    agg = xr.open_dataset(study["means"]).load()
    d10 = fig10_goals.data(study["means"])
    assert list(d10["curves"]) == ["tilt:0.1", "tilt:0.3333", "tilt:0.6", "overturning"]
    for (x, y), ls in zip(_lines(fig10_goals.plot(d10).axes[0]), d10["curves"], strict=True):
        _same(x, agg["R"])
        _same(y, agg["mean"].sel(mode="3d", limit_state=ls, tan_alpha=0.2))
    d11 = fig11_slenderness.data(study["means"])
    fig = fig11_slenderness.plot(d11)
    for ax, panel in zip(fig.axes, d11["panels"], strict=True):
        for (_, y), t in zip(_lines(ax), (0.1, 0.2, 0.3), strict=True):
            _same(y, agg["mean"].sel(mode="3d", limit_state=panel["limit_state"], tan_alpha=t))
    # slenderness factors 1.02, 1.00, 0.97 of the synthetic store
    spread = (1.02 - 0.97) / np.mean([1.02, 1.0, 0.97])
    assert d11["measured"]["max_rel_spread_tilt:0.3333"] == pytest.approx(spread, rel=1e-9)


def test_fig12_compares_modes_across_ensembles(study, reduced):
    d = fig12_2d_vs_3d.data([("elcentro", study["means"], study["store"]),
                             ("lomaprieta", reduced["means"], reduced["store"])])
    labels = [(e["label"], e["stand_in"]) for e in d["ensembles"]]
    assert labels == [("El Centro 1940 ensemble", False),
                      ("Loma Prieta 1989 (stand-in: Corralitos)", True)]
    m = d["measured"]
    # R = 10 m is on the grid and every motion reaches θ > α/3 there: the 2D-x mean is
    # exactly MODE_FACTOR = 2 times the 3D one
    ratio = m["elcentro|excessive tilt|2d-x"] / m["elcentro|excessive tilt|3d"]
    assert ratio == pytest.approx(2.0, rel=1e-12)
    assert "Loma Prieta 1989 (stand-in: Corralitos): mode 2d-x not computed" in d["missing"]
    fig = fig12_2d_vs_3d.plot(d)
    assert any("stand-in" in t.get_text() for t in fig.legends[0].get_texts())
    agg = xr.open_dataset(study["means"]).load()
    _same(_lines(fig.axes[0])[0][1], agg["mean"].sel(mode="3d", limit_state="overturning",
                                                      tan_alpha=0.2))


def test_reduced_run_degrades_gracefully(reduced, tmp_path):
    d9 = fig09_spectra.data(reduced["store"], reduced["means"])
    assert "mode 3d-damped not computed" in d9["missing"]
    out = [tmp_path / "f9.png", tmp_path / "f9.pdf"]
    render("fig09", out, tmp_path / "f9.json", store=reduced["store"], means=reduced["means"])
    notes = json.loads((tmp_path / "f9.json").read_text())
    assert notes["missing"] == ["mode 3d-damped not computed"]
    assert out[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert out[1].read_bytes()[:5] == b"%PDF-"
    d11 = fig11_slenderness.data(reduced["means"], tan_alphas=(0.2, 0.5))
    assert "tan α = 0.5 not computed" in d11["missing"]
    fig11_slenderness.plot(d11)


def test_fig08_traces_and_spectra():
    dt = 0.005
    t = np.arange(0.0, 20.0, dt)
    env = np.sin(np.pi * t / 20.0) ** 2  # smooth, slow: no energy near 50 Hz
    motions = [GroundMotion(3.0 * env * np.sin(2 * np.pi * f * t),
                            2.0 * env * np.cos(2 * np.pi * 1.3 * f * t), dt, name,
                            {"principal_offset_deg": 19.5} if i == 0 else {})
               for i, (f, name) in enumerate([(1.0, "record"), (1.4, "synthetic-01")])]
    d = fig08_motions.data(motions, periods=np.array([0.02, 0.5, 2.0]))
    first = d["motions"][0]
    _same(first["ax"], motions[0].ax / G)
    # a stiff oscillator (T = 0.02 s, 50 Hz ≫ 1 Hz input) follows the ground: PSA → PGA
    assert first["psa_x"][0] == pytest.approx(np.max(np.abs(first["ax"])), rel=2e-3)
    assert first["psa_y"][0] == pytest.approx(np.max(np.abs(first["ay"])), rel=2e-3)
    assert d["measured"]["principal_offset_deg"] == 19.5
    fig = fig08_motions.plot(d)
    spectra_ax = fig.axes[-1]
    _same(_lines(spectra_ax)[0][1], first["psa_x"])
    _same(_lines(spectra_ax)[1][1], first["psa_y"])
    with pytest.raises(ValueError, match="motions"):
        fig08_motions.data([])


# ---------------------------------------------------------------- the Snakemake rules


def _workdir(tmp_path: Path) -> tuple[Path, Path]:
    """A work directory whose results/ holds the upstream products of a tiny study."""
    from rocking.motions.ensemble_io import save_ensemble

    wd = tmp_path / "wd"
    dt = 0.01
    t = np.arange(0.0, 3.0, dt)
    env = np.sin(np.pi * t / 3.0) ** 2
    motions = [GroundMotion(4.0 * env * np.sin(2 * np.pi * f * t),
                            3.0 * env * np.cos(2 * np.pi * 0.8 * f * t), dt, name)
               for f, name in ((1.5, "el-centro-1940"), (1.2, "synthetic-01"))]
    save_ensemble(wd / "results/motions/elcentro.nc", motions)
    paths = fs.write_study(wd / "results/synth")
    for name in ("spectra", "tilt_map"):
        (wd / f"results/synth/{name}.done.json").write_text("{}")
    cfg = {
        "ensembles": {"elcentro": {"record": "el-centro-1940", "n_synthetic": 1}},
        "studies": {"synth": {
            "ensemble": "elcentro", "R": fs.R, "tan_alpha": fs.TAN_ALPHA,
            "limit_states": fs.LIMIT_STATES, "modes": fs.MODES,
            "tilt_map": {"R": [1.0, 2.0], "intensity": [1.0, 2.0]},
        }},
    }
    config = tmp_path / "config.yaml"
    config.write_text(yaml.safe_dump(cfg))
    assert paths["store"].exists()
    return wd, config


@pytest.mark.slow
def test_snakemake_rules_build_every_figure_and_the_report(tmp_path):
    wd, config = _workdir(tmp_path)
    mine = ["fig03_wobbling_period", "fig04_free_vibration", "fig06_el_centro", "fig08_motions",
            "fig07_tilt_map", "fig09_spectra", "fig10_goals", "fig11_slenderness",
            "fig12_2d_vs_3d", "fragility", "report_html"]
    snakemake = shutil.which("snakemake", path=str(Path(sys.executable).parent))
    # the target first: --allowed-rules and --rerun-triggers take several values each
    cmd = [snakemake or "snakemake", "results/synth/report.html", "-s", str(ROOT / "Snakefile"),
           "-d", str(wd), "--configfile", str(config), "--cores", "2",
           "--rerun-triggers", "mtime", "--allowed-rules", *mine]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    logs = "\n".join(p.read_text() for p in (wd / "logs").rglob("*.log"))
    assert proc.returncode == 0, proc.stderr[-4000:] + logs[-4000:]
    figures = wd / "results/figures"
    for stem in ("fig03_wobbling_period", "fig04_free_vibration", "fig06_el_centro",
                 "fig08_motions_elcentro", "fig12_2d_vs_3d"):
        for suffix in (".png", ".pdf", ".json"):
            assert (figures / f"{stem}{suffix}").stat().st_size > 0, stem + suffix
    for stem in ("fig07_tilt_map", "fig09_spectra", "fig10_goals", "fig11_slenderness",
                 "fragility_curves"):
        assert (wd / f"results/synth/figures/{stem}.png").stat().st_size > 10_000
    # the rule's figure notes are those of the library on the same store
    notes = json.loads((wd / "results/synth/figures/fig09_spectra.json").read_text())
    assert notes["measured"]["max_rel_diff_damped_tilt:0.3333"] == pytest.approx(0.05)
    html = (wd / "results/synth/report.html").read_text()
    assert html.count("<figure") == 10
    frag = xr.open_dataset(wd / "results/synth/fragility.nc")
    assert set(frag.dims) == {"mode", "limit_state", "tan_alpha", "R"}
