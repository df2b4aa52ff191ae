"""Figures: the data handed to matplotlib equals the store/aggregate/engine values, closed
forms and invariants hold, partially computed stores and reduced runs degrade into notes the
figure shows, files are written, and the Snakemake rules build them under one name each."""

from __future__ import annotations

import json
import math
import re
import shutil
import subprocess
import sys
from pathlib import Path

import figures_synthetic as fs
import numpy as np
import pandas as pd
import pytest
import xarray as xr
import yaml

from rocking import Cylinder, GroundMotion
from rocking import plot as figures
from rocking.config.study import StudySpec
from rocking.constants import G
from rocking.execution.prepare import keyed
from rocking.motions.principal import rotate
from rocking.plot import (
    _axes,
    _style,
    fig03_wobbling_period,
    fig04_free_vibration,
    fig06_el_centro,
    fig06_theta_max_sensitivity,
    fig07_tilt_map,
    fig08_motions,
    fig09_spectra,
    fig10_goals,
    fig11_slenderness,
    fig12_2d_vs_3d,
    render,
)
from rocking.plot.registry import SCOPES, caption
from rocking.plot.registry import figures as registered
from rocking.spectra.limit_states import limit_state_title

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


@pytest.fixture(scope="module")
def partial(tmp_path_factory):
    """Per-mode configuration: damped and 2D only at tan α = 0.2, canonical limit-state names,
    a tilt map whose first dimension is called "mode"."""
    only = [0.2]
    return fs.write_study(tmp_path_factory.mktemp("partial"), tilt_dim="mode",
                          requested={"3d-damped": only, "2d-x": only, "2d-y": only},
                          limit_states=["tilt:0.1", "tilt:1/3", "tilt:0.6", "overturning"])


def _lines(ax):
    return [(np.asarray(ln.get_xdata(), float), np.asarray(ln.get_ydata(), float))
            for ln in ax.get_lines()]


def _same(a, b):
    np.testing.assert_array_equal(np.asarray(a, float), np.asarray(b, float))


def _texts(fig) -> str:
    """Every text of a figure (titles, labels, notes, legends) in one string."""
    from matplotlib.text import Text

    return "\n".join(t.get_text() for t in fig.findobj(Text))


# ---------------------------------------------------------------- names, captions, axes


def test_every_figure_is_one_entry_in_its_own_module():
    entries = registered()
    assert list(entries) == list(figures.FIGURES)
    # the paper's order is the entries' numbers
    assert [e.number for e in entries.values()] == sorted(e.number for e in entries.values())
    modules = set()
    for name, entry in entries.items():
        mod = figures.module(name)
        short = mod.__name__.rsplit(".", 1)[1]
        assert mod.__name__ == entry.module and name.startswith(short), name
        assert entry in (mod.FIGURE if isinstance(mod.FIGURE, tuple) else (mod.FIGURE,))
        assert hasattr(mod, "data") and hasattr(mod, entry.plot), name
        assert entry.scope in SCOPES and caption(name), name
        modules.add(short)
    # one rule loop and one script draw every figure (the stripe, risk and portfolio ones
    # too): no other rule writes a file under figures/, and no rule, script, report or
    # command-line module imports a figure's module, so adding a figure is its module and
    # its test (docs/design.md, "Adding a figure")
    rules = (ROOT / "workflow/rules/figures.smk").read_text()
    assert "for fig in figures().values():" in rules
    assert 'script:\n            "../scripts/figure.py"' in rules
    for smk in (ROOT / "workflow/rules").glob("*.smk"):
        if smk.name not in ("figures.smk", "figures_common.smk"):
            assert "figures/" not in smk.read_text(), smk.name
    plumbing = [*(ROOT / "workflow").rglob("*.py"), *(ROOT / "workflow/rules").glob("*.smk"),
                *(ROOT / "src/rocking/cli").glob("*.py"), *(ROOT / "src/rocking/config").glob(
                    "*.py"), ROOT / "src/rocking/report/html.py",
                ROOT / "src/rocking/report/entries.py", ROOT / "src/rocking/plot/__init__.py",
                ROOT / "src/rocking/plot/registry.py", ROOT / "Snakefile"]
    for path in plumbing:
        text = path.read_text()
        for short in modules:
            assert not re.search(rf"rocking\.plot\.{short}\b|from rocking\.plot import "
                                 rf"[\w, ]*\b{short}\b|plot import {short} as", text), \
                (path.relative_to(ROOT), short)
    for name, entry in entries.items():
        assert f"rule {entry.rule_name}:" not in rules, name
    assert sorted(p.stem for p in (ROOT / "workflow/report").glob("*.rst")) == [
        "figure", "fragility_table", "linear_fit", "mean_spectra", "records_table", "run_config",
        "stripe_fragility", "workflow"]
    assert figures.figure_name("results/figures/fig08_motions_lomaprieta.png") == "fig08_motions"
    assert figures.figure_name("fig06_theta_max_sensitivity.png") == (
        "fig06_theta_max_sensitivity")
    with pytest.raises(ValueError, match="must start with"):
        figures.figure_name("plot.png")


def test_axes_are_named_by_azimuth_and_principal_axis():
    assert _axes.bearing(340.46) == "N19.5°W"
    assert _axes.bearing(250.46) == "S70.5°W"
    assert _axes.bearing(90.0) == "E" and _axes.bearing(135.0) == "S45.0°E"
    raw = _axes.describe({"x_azimuth": 270.0, "y_azimuth": 180.0})
    assert raw["x"] == "E–W (270°)" and raw["y"] == "N–S (180°)"
    principal = _axes.describe({"x_azimuth": 340.46, "y_azimuth": 250.46,
                                "axes": "principal (x = major)"})
    assert principal["x"] == "major principal axis, az 340.5° (N19.5°W)"
    assert "unknown" not in principal["text"] and principal["principal"] == "yes"
    assert "not recorded" in _axes.describe({})["text"]


def test_limit_state_titles_in_either_spelling():
    assert limit_state_title("tilt:1/3") == limit_state_title("tilt:0.3333") == (
        "Tilt θ > α/3 (excessive tilt)")
    assert limit_state_title("tilt:0.75") == "Tilt θ > 3α/4"
    assert limit_state_title("tilt:1") == "Tilt θ > α"
    assert limit_state_title("tilt:0.37") == "Tilt θ > 0.37·α"
    assert limit_state_title("excessive-tilt") == limit_state_title("tilt:1/3")


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


def test_fig03_shows_the_two_slender_curves_apart():
    d = fig03_wobbling_period.data(n=199)
    gap = np.max(np.abs(d["wobbling"][0.1] / d["wobbling"][0.2] - 1))
    assert d["measured"]["max_rel_gap_slender_pair"] == pytest.approx(gap)
    assert 0.0 < gap < 0.01  # the curves nearly coincide: why the figure needs the inset
    fig = fig03_wobbling_period.plot(d)
    main = fig.axes[0]
    inset = main.child_axes[0]
    lines = _lines(main)
    expected = [*d["wobbling"].values(), d["housner"]]
    for (x, y), e in zip(lines, expected, strict=True):
        _same(x, d["theta_over_alpha"])
        _same(y, e)
    styles = [(ln.get_linestyle(), ln.get_marker()) for ln in main.get_lines()[:2]]
    assert styles[0] != styles[1]  # tan α = 0.1 and 0.2 drawn differently
    # the inset holds both curves, separated by more than a line width at its scale
    (x1, y1), (x2, y2) = _lines(inset)
    lo, hi = inset.get_ylim()
    assert np.min(np.abs(y1 - y2)) / (hi - lo) > 0.02
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


def test_symlog_ticks_are_few_and_decades():
    from matplotlib.figure import Figure

    ax = Figure().subplots()
    ax.set_yscale("symlog", linthresh=1.0)
    fig04_free_vibration.symlog_ticks(ax, [0.0, 3.0, 2e8])
    ticks = ax.yaxis.get_major_locator()()
    assert 3 <= len(ticks) <= 6 and ticks[0] == 0.0
    assert all(math.log10(t).is_integer() for t in ticks[1:])


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
    # Damped: Housner's e = 1 − 2 sin²α/κo (Eq 31), the paper's 0.942 (Eq 32), for all pairs
    assert m["restitution_damped"] == pytest.approx(body.e, abs=2e-3)
    lo, hi = m["restitution_damped_range"]
    assert body.e - 2e-3 <= lo <= hi <= body.e + 2e-3
    # First approach speed from energy: p √(2 (cos(α − θ0) − cos α)) = 0.190 (paper's 0.19)
    assert m["approach_speeds_damped"][0] == pytest.approx(pred["first_approach_speed"],
                                                           rel=1e-3)
    wob = d["runs"]["wobbling"]
    assert len(wob) == 1 + len(fig04_free_vibration.PAIRS)  # undamped + the paper's 8 pairs
    for run in wob.values():
        # Pure wobbling (corrected Eq 24) keeps the tilt and spin constant
        np.testing.assert_allclose(run["theta"], 0.1, atol=1e-6)
        np.testing.assert_allclose(run["phi_dot"], body.wobbling_rate(0.1), rtol=1e-6)
    mixed = d["runs"]["mixed"]["3d"]
    assert mixed["theta"].min() > 0.02  # "the tilt never comes close to zero"
    # the paper's §3: the eight contact parameters give overlapping responses
    for case in ("quasi-rocking", "wobbling", "mixed"):
        assert m[f"max_gap_theta_damped_pairs_{case}"] < 0.002


def test_fig04_plot_draws_every_run_and_names_the_pairs(fig04_data):
    fig = fig04_free_vibration.plot(fig04_data)
    run = fig04_data["runs"]["mixed"][fig04_free_vibration.damped_key(200.0, 50.0)]
    drawn = [ln for ax in fig.axes for ln in ax.get_lines()]
    ys = [np.asarray(ln.get_ydata(), float) for ln in drawn]
    for key in ("theta", "theta_dot", "phi", "phi_dot", "y"):
        assert any(y.shape == run[key].shape and np.array_equal(y, run[key]) for y in ys), key
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert legend[0] == "undamped" and len(legend) == 9
    assert "ωn = 200, ζ = 0.05" in legend and "ωn = 2000, ζ = 50" in legend
    # the symlog of φ̇ is explained under the figure, not in a box over its spikes
    assert not [t for ax in fig.axes for t in ax.texts if t.get_text()]
    assert "symmetric log scale" in fig.legends[0].get_title().get_text()


def test_fig06_says_the_clipped_spikes_above_their_panel():
    """Where φ̇'s spikes are clipped, the panel's title says so and how far they reach; no
    text is drawn over the axes."""
    from rocking.plot._style import new_figure

    t = np.linspace(0.0, 10.0, 1001)
    spiky = np.where(np.abs(t - 5.0) < 0.02, 900.0, np.sin(t))
    run = {"t": t, "phi_dot": spiky, "theta": np.where(np.abs(t - 5.0) < 0.02, 0.0, 0.02)}
    fig, ax = new_figure(4.0, 2.0)
    fig06_el_centro._clip_spikes(ax, [run], 10.0)
    assert ax.get_ylim()[1] == pytest.approx(1.2) and not ax.texts
    assert "reach 900 rad/s" in ax.get_title(loc="left")


# ---------------------------------------------------------------- Fig 6: El Centro response


def _pulse_pair(duration=3.0, dt=0.01, meta=None, name="pulse-pair"):
    t = np.arange(0.0, duration, dt)
    env = np.sin(np.pi * t / duration) ** 2
    return GroundMotion(4.0 * env * np.sin(2 * np.pi * 1.5 * t),
                        3.0 * env * np.cos(2 * np.pi * 1.1 * t), dt, name, meta or {})


def test_fig06_passes_the_engine_response_and_ground_unchanged():
    from rocking.dynamics.analysis import ground_response

    meta = {"x_azimuth": 340.46, "y_azimuth": 250.46, "axes": "principal (x = major)",
            "processing": [{"step": "highpass", "pad_front": 0, "pad_end": 50}],
            "title": "pulse pair record"}
    motion = _pulse_pair(meta=meta)
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
    # the padding of the high-pass is not drawn: the time axis ends with the record
    assert d["ground"]["t_end"] == pytest.approx((motion.npts - 1 - 50) * motion.dt)
    fig = fig06_el_centro.plot(d)
    assert len(fig.axes) == 8
    shown = run["t"] <= d["ground"]["t_end"]
    _same(_lines(fig.axes[0])[0][1], run["theta"][shown])
    assert fig.axes[-1].get_xlim()[1] == pytest.approx(d["ground"]["t_end"])
    text = _texts(fig)
    assert "pulse pair record" in text and "N19.5°W" in text and "0.0838" in text
    assert "el-centro-1940" not in text
    with pytest.raises(ValueError, match="zero component"):
        fig06_el_centro.data(motion.component("x"))


def test_fig06_quotes_the_sensitivity_evidence(tmp_path):
    notes = {"measured": {"band": 0.05, "versions": ["as recorded", "processed"],
                          "band_range|as recorded|3d": [0.046, 0.091],
                          "band_range|processed|3d": [0.022, 0.068]}}
    path = tmp_path / "s.json"
    path.write_text(json.dumps(notes))
    d = fig06_el_centro.data(_pulse_pair(), R=2.0, sensitivity=path)
    assert "as recorded: 0.046–0.091" in d["explanation"]
    assert "processed: 0.022–0.068" in d["explanation"]
    assert d["measured"]["t_part_theta"] is None or d["measured"]["t_part_theta"] >= 0


def test_fig06_sensitivity_rotation_leaves_theta_max_unchanged():
    from rocking.dynamics.analysis import ground_response

    motion = _pulse_pair(meta={"x_azimuth": 270.0, "y_azimuth": 180.0})
    versions = {fig06_theta_max_sensitivity.AS_RECORDED: motion,
                fig06_theta_max_sensitivity.STUDY: motion.scaled(1.1),
                fig06_theta_max_sensitivity.PAPER_ROTATION: rotate(motion.scaled(1.1), 22.33)}
    scales = np.array([0.9, 1.0, 1.1])
    d = fig06_theta_max_sensitivity.data(versions=versions, scales=scales, R=1.0,
                                         models=("3d",))
    direct = [ground_response(Cylinder(1.0, 0.2), motion, scale=s).theta_max for s in scales]
    np.testing.assert_allclose(d["theta_max"][fig06_theta_max_sensitivity.AS_RECORDED]["3d"],
                               direct, rtol=1e-9)
    # axisymmetry, independent of the figure: a rotated pair gives the same peak tilt
    assert d["measured"]["rotation_check"]["3d"] < 1e-8
    m = d["measured"]
    band = m[f"band_range|{fig06_theta_max_sensitivity.AS_RECORDED}|3d"]
    assert band == [min(direct), max(direct)]
    assert m[f"component_pga_g|{fig06_theta_max_sensitivity.AS_RECORDED}"][0] == pytest.approx(
        np.max(np.abs(motion.ax)) / G)
    fig = fig06_theta_max_sensitivity.plot(d)
    assert "0.0838" in _texts(fig) and "22.33°" in _texts(fig)
    # all three versions are drawn (the rotated one at scale 1), as markers without lines
    drawn = [ln for ln in fig.axes[0].get_lines() if ln.get_label() and
             not ln.get_label().startswith(("_", "paper"))]
    assert any(fig06_theta_max_sensitivity.PAPER_ROTATION in ln.get_label() for ln in drawn)
    assert all(ln.get_linestyle() == "None" for ln in drawn)


# ---------------------------------------------------------------- Figs 7–12 from a store


def test_fig07_with_one_size_colours_its_points(study):
    # One R (a small test study) has no contour: the map shows the grid points' classes.
    d = fig07_tilt_map.data(study["tilt_map"], motions=study["motions"])
    d = {**d, "R": d["R"][3:4],  # a size with points below α, standing above it, overturned
         "theta_over_alpha": {m: z[3:4] for m, z in d["theta_over_alpha"].items()}}
    fig = fig07_tilt_map.plot(d)
    colours = np.asarray(fig.axes[0].collections[0].get_array())
    z = d["theta_over_alpha"]["3d"][0]
    over = np.isclose(z, np.pi / 2 / np.arctan(0.2))
    standing = (z >= 1.0) & ~over
    assert over.any() and standing.any() and (z < 1.0).any()
    # below α its own value; standing above α and overturned: two classes apart
    np.testing.assert_array_equal(colours[z < 1.0], z[z < 1.0])
    assert set(colours[standing]) == {0.5 * (1.0 + fig07_tilt_map._TOP_LEVELS[0])}
    assert set(colours[over]) == {0.5 * (fig07_tilt_map._TOP_LEVELS[0] + fig07_tilt_map.TOP)}


def test_fig07_gives_overturning_its_own_class(study):
    # Overturned points (θ = π/2, stored as π/(2α)) are one class, points standing above α
    # another: the colour bar names both, the overturned area is filled in its own colour,
    # the standing points are marked where they are, the footnote counts both.
    d = fig07_tilt_map.data(study["tilt_map"], motions=study["motions"])
    fig = fig07_tilt_map.plot(d)
    cbar = fig.axes[-1]
    labels = [t.get_text() for t in cbar.get_yticklabels()]
    assert labels[-2:] == ["θmax > α, standing", "overturned"]
    z = d["theta_over_alpha"]["3d"]
    over = np.isclose(z, np.pi / 2 / np.arctan(0.2))
    standing = (z > 1.0) & ~over
    from matplotlib.colors import to_rgba
    filled = [c for c in fig.axes[0].collections if type(c).__name__ == "QuadContourSet"
              and len(c.get_facecolor())
              and np.allclose(c.get_facecolor()[0], to_rgba(fig07_tilt_map.TOP_COLOR))]
    assert len(filled) == 1  # the overturned area, one layer of its own
    marks = [c for c in fig.axes[0].collections if type(c).__name__ == "PathCollection"]
    RR, II = np.meshgrid(d["R"], d["intensity"])
    np.testing.assert_array_equal(
        np.asarray(marks[0].get_offsets()),
        np.column_stack([RR[standing.T], II[standing.T]]))
    text = _texts(fig)
    total_over = sum(int(np.isclose(m, np.pi / 2 / np.arctan(0.2)).sum())
                     for m in d["theta_over_alpha"].values())
    assert f"overturned, θ reached π/2 ({total_over} grid points" in text.replace("\n", " ")


@pytest.mark.parametrize("which", ["study", "partial"])
def test_fig07_data_equal_the_tilt_map_store(which, study, partial):
    paths = {"study": study, "partial": partial}[which]
    d = fig07_tilt_map.data(paths["tilt_map"], motions=paths["motions"])
    dim = "model" if which == "study" else "mode"
    with xr.open_zarr(paths["tilt_map"], consolidated=False) as ds:
        for model in ("3d", "3d-damped"):
            _same(d["theta_over_alpha"][model], ds["theta_max_over_alpha"].sel({dim: model}))
        _same(d["R"], ds["R"])
    z = d["theta_over_alpha"]["3d"]
    first = fig07_tilt_map.first_above(z, d["intensity"])
    for i in range(len(d["R"])):
        above = d["intensity"][z[i] >= 1.0]
        assert first[i] == (above.min() if above.size else np.nan) or np.isnan(first[i])
    assert d["measured"]["first_intensity_theta_above_alpha_3d"] == pytest.approx(
        first.tolist(), nan_ok=True)
    # the damped map is 0.8 × the undamped one below θmax = α (formula): gap measured
    assert d["measured"]["mean_abs_gap_below_alpha"] > 0
    assert d["grid"]["R"] == d["R"].tolist()
    fig = fig07_tilt_map.plot(d)
    assert len(fig.axes) == 3  # two maps and the colour bar
    text = _texts(fig)
    assert "7 sizes R = 1–10 m × 15 intensities" in text and "N19.5°W" in text


def test_fig09_lines_are_the_store_and_the_aggregate(study):
    d = fig09_spectra.data(study["store"], study["means"], motions=study["motions"])
    assert [p["limit_state"] for p in d["panels"]] == ["overturning", "tilt:0.3333"]
    ds = xr.open_zarr(study["store"], consolidated=False).load()
    agg = xr.open_dataset(study["means"]).load()
    fig = fig09_spectra.plot(d)
    for ax, panel in zip(fig.axes[:2], d["panels"], strict=True):
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
    # the record is drawn over the means (broad, grey, under every motion), not hidden
    # beneath them where it runs along them
    ax = fig.axes[0]
    record = [ln for ln in ax.get_lines()[:8] if ln.get_color() == "black"]
    means = ax.get_lines()[8:10]
    assert len(record) == 2 and all(ln.get_color() != "black" for ln in means)
    assert min(ln.get_zorder() for ln in record) > max(ln.get_zorder() for ln in means)
    assert min(ln.get_linewidth() for ln in means) > 3 * max(ln.get_linewidth() for ln in record)


def _canvas(fig):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    return canvas.get_renderer()


def _one_size(d: dict) -> dict:
    """Figure data of a study of one size R (the first of ``d``)."""
    panels = [{**p, "curves": {m: {k: v[:1] for k, v in c.items()}
                               for m, c in p["curves"].items()},
               "means": {m: v[:1] for m, v in p["means"].items()},
               "plateau": {}, "slides": {}, "damping": None} for p in d["panels"]]
    return {**d, "R": d["R"][:1], "R_mean": d["R_mean"][:1], "panels": panels,
            "modes": d["modes"][:1]}


@pytest.mark.parametrize("sizes", ["all", "one"])
def test_fig09_axis_follows_the_data_and_the_legend_covers_no_curve(study, sizes):
    d = fig09_spectra.data(study["store"], study["means"], motions=study["motions"])
    if sizes == "one":
        d = _one_size(d)
    fig = fig09_spectra.plot(d)
    renderer = _canvas(fig)
    for ax, panel in zip(fig.axes, d["panels"], strict=False):
        ys = [*(y for c in panel["curves"].values() for y in c.values()),
              *panel["means"].values()]
        top = max(float(np.nanmax(y)) for y in ys if np.isfinite(y).any())
        # the axis stops just above the data, not at twice their height
        assert top < ax.get_ylim()[1] <= 1.06 * top + 1e-9
        legend = ax.get_legend()
        assert legend is not None
        assert not legend.get_window_extent(renderer).overlaps(ax.get_window_extent(renderer))


def test_fig09_footer_of_a_suite_gives_every_records_axes(study, tmp_path):
    from rocking.motions.ensemble_io import save_ensemble
    from rocking.plot import _axes

    t = np.arange(0.0, 2.0, 0.01)
    a = np.sin(2 * np.pi * t)
    records = [GroundMotion(a, 0.5 * a, 0.01, name, {"axes": "principal (x = major)",
                                                     "x_azimuth": az, "y_azimuth": az - 90.0})
               for name, az in (("site-a", 340.5), ("site-b", 20.0))]
    synthetic = GroundMotion(a, a, 0.01, "site-a-rdk-000", {"record": "site-a"})
    save_ensemble(tmp_path / "suite.nc", [*records, synthetic])
    axes = _axes.of_records(tmp_path / "suite.nc")
    assert "site-a: x = major principal axis, az 340.5° (N19.5°W)" in axes["text"]
    assert "site-b: x = major principal axis, az 20.0° (N20.0°E)" in axes["text"]
    assert "rdk" not in axes["text"]
    d = fig09_spectra.data(study["store"], study["means"], motions=study["motions"])
    assert d["motion_axes"]["text"] == ""  # one record: the record's axes, as before
    text = _texts(fig09_spectra.plot({**d, "motion_axes": axes})).replace("\n", " ")
    assert "N19.5°W" in text and "N20.0°E" in text


def test_damping_effect_of_a_known_ratio(study):
    # the synthetic damped spectra are exactly 5 % above the undamped ones
    d = fig09_spectra.data(study["store"], study["means"])
    eff = d["measured"]["damping|tilt:0.3333"]
    np.testing.assert_allclose(eff["rel_diff_means"], 0.05, rtol=1e-9)
    np.testing.assert_allclose(eff["paired_mean"], 0.05, rtol=1e-9)
    np.testing.assert_allclose(eff["paired_std"], 0.0, atol=1e-12)
    assert eff["paired_n"] == [4] * len(fs.R)
    # spread among motions: std/mean of the factors 1, 0.8, 1.25, 1.1
    f = np.array([1.0, 0.8, 1.25, 1.1])
    np.testing.assert_allclose(eff["cov_undamped"], np.std(f, ddof=1) / np.mean(f), rtol=1e-9)
    # d − u = 0.05 u: the standard error of the difference of the means is 0.05 · CoV / √n
    np.testing.assert_allclose(eff["se_rel_diff_means"],
                               0.05 * np.std(f, ddof=1) / np.mean(f) / 2.0, rtol=1e-9)
    assert d["measured"]["max_rel_diff_damped_tilt:0.3333"] == pytest.approx(0.05, rel=1e-9)
    bottom = fig09_spectra.plot(d).axes[3]
    _same(_lines(bottom)[-1][1], 100 * np.asarray(eff["rel_diff_means"]))


def test_fig10_fig11_lines_are_the_aggregate(study):
    agg = xr.open_dataset(study["means"]).load()
    d10 = fig10_goals.data(study["means"])
    assert list(d10["curves"]) == ["tilt:0.1", "tilt:0.3333", "tilt:0.6", "overturning"]
    ax10 = fig10_goals.plot(d10).axes[0]
    data_lines = [ln for ln in ax10.get_lines() if ln.get_marker() == "o"]
    fit_lines = [ln for ln in ax10.get_lines()
                 if ln.get_linestyle() == "--" and len(ln.get_xdata())]
    assert len(data_lines) == len(fit_lines) == len(d10["curves"])
    for ln, fit_ln, ls in zip(data_lines, fit_lines, d10["curves"], strict=True):
        _same(ln.get_xdata(), agg["R"])
        _same(ln.get_ydata(), agg["mean"].sel(mode="3d", limit_state=ls, tan_alpha=0.2))
        # the drawn straight line is the fit whose R² the legend quotes
        fit = d10["measured"][f"line|{ls}"]
        np.testing.assert_allclose(fit_ln.get_ydata(),
                                   fit["slope"] * agg["R"].values + fit["intercept"])
    # the synthetic means are exactly linear in R except where a cut-off motion drops out
    assert d10["measured"]["line|tilt:0.1"]["r_squared"] == pytest.approx(1.0, abs=1e-12)
    assert d10["measured"]["line|tilt:0.1"]["slope"] == pytest.approx(
        0.4 * 1.2 * np.mean([1.0, 0.8, 1.25, 1.1]), rel=1e-12)
    absent = d10["measured"]["absent_goals"]
    assert absent == ["tilt:0.2", "tilt:0.5", "tilt:0.75", "tilt:1"]
    assert "4 of the paper's 7 goals not computed" in d10["missing"][0]
    d11 = fig11_slenderness.data(study["means"])
    fig = fig11_slenderness.plot(d11)
    for ax, panel in zip(fig.axes, d11["panels"], strict=True):
        for (_, y), t in zip(_lines(ax), (0.1, 0.2, 0.3), strict=True):
            _same(y, agg["mean"].sel(mode="3d", limit_state=panel["limit_state"], tan_alpha=t))
    # slenderness factors 1.02, 1.00, 0.97 of the synthetic store
    spread = (1.02 - 0.97) / np.mean([1.02, 1.0, 0.97])
    assert d11["measured"]["max_rel_spread_tilt:0.3333"] == pytest.approx(spread, rel=1e-9)


def test_fig12_compares_modes_across_ensembles(study, reduced):
    d = fig12_2d_vs_3d.data([("elcentro", study["means"], study["store"], study["motions"]),
                             ("lomaprieta", reduced["means"], reduced["store"])])
    labels = [(e["label"], e["stand_in"]) for e in d["ensembles"]]
    assert labels == [("El Centro 1940 ensemble: mean of 4 motions", False),
                      ("Loma Prieta 1989 (stand-in: Corralitos): mean of 4 motions", True)]
    m = d["measured"]
    # R = 10 m is on the grid and every motion reaches θ > α/3 there: each one-component
    # mean is exactly its MODE_FACTOR times the 3D one
    for mode, factor in (("3d-x", 1.9), ("3d-y", 1.6), ("2d-x", 2.0), ("2d-y", 1.8)):
        ratio = m[f"elcentro|excessive tilt|{mode}"] / m["elcentro|excessive tilt|3d"]
        assert ratio == pytest.approx(factor, rel=1e-12)
    assert m["elcentro|overturning|3d|count"] == 4
    for mode in ("3d-x", "3d-y", "2d-x", "2d-y"):
        assert f"Loma Prieta 1989 (stand-in: Corralitos): mode {mode} not computed" in d["missing"]
    fig = fig12_2d_vs_3d.plot(d)
    legend = [t.get_text() for ax in fig.axes if ax.get_legend()
              for t in ax.get_legend().get_texts()]
    assert any("stand-in" in t for t in legend)
    assert any("mean of 4 motions" in t for t in legend)
    assert "3D cylinder, x (major axis) component only" in legend
    assert "Housner 2D block (e = 0.942), y component only" in legend
    text = _texts(fig)
    assert "N19.5°W" in text and "E–W" in text and "not computed in this run" in text.lower()
    assert "(the paper's comparison, §5.4)" in text and "a further comparator" in text
    # one row per ensemble, one column per limit state, each row on its own scale
    panels = [ax for ax in fig.axes if ax.get_title()]
    assert [ax.get_title().split("\n")[0] for ax in panels] == [
        "Overturning", "Tilt θ > α/3 (excessive tilt)"] * 2
    assert "El Centro 1940 ensemble" in panels[0].get_title()
    assert "Loma Prieta" in panels[2].get_title()
    agg = xr.open_dataset(study["means"]).load()
    _same(_lines(panels[0])[0][1], agg["mean"].sel(mode="3d", limit_state="overturning",
                                                    tan_alpha=0.2))
    top = agg["mean"].sel(limit_state="overturning", tan_alpha=0.2).max()
    assert panels[0].get_ylim()[1] == pytest.approx(1.06 * float(top), rel=0.05)
    # the ratios to the 3D model under both, the paper's comparator and Housner's
    ratios = sorted(t.get_text() for t in panels[1].texts)
    assert ratios == ["×1.60 3D y", "×1.80 2D y", "×1.90 3D x", "×2.00 2D x"]
    # open circles exactly where a mean leaves out motions not reached at the search bound
    ens = d["ensembles"][0]
    for title, curves in ens["panels"].items():
        for mode in curves:
            count = ens["spread"][f"{title}|{mode}|count"]
            np.testing.assert_array_equal(fig12_2d_vs_3d.fewer_motions(ens, title, mode),
                                          count < ens["n_motions"])
    opened = [ln for ax in panels for ln in ax.get_lines() if ln.get_markersize() == 7]
    n_few = sum(int(fig12_2d_vs_3d.fewer_motions(e, t, mo).sum()) for e in d["ensembles"]
                for t, c in e["panels"].items() for mo in c)
    assert n_few > 0 and sum(len(ln.get_xdata()) for ln in opened) == n_few
    assert any("fewer motions than the ensemble" in t for t in legend)


def test_fig12_marks_a_censored_ratio_as_a_bound():
    # a one-component mean over fewer motions (the others not reached) is too low: its ratio
    # to the 3D mean at the largest R is a lower bound, written "≥"; a censored 3D mean "≤"
    from matplotlib.figure import Figure

    ax = Figure().subplots()
    ax.set_ylim(0.0, 10.0)
    R = np.array([2.0, 6.0, 10.0])
    curves = {"3d": np.array([1.0, 2.0, 4.0]), "3d-x": np.array([2.0, 5.0, 8.0]),
              "2d-y": np.array([2.0, 4.0, 6.0])}
    censored = {"3d": np.zeros(3, bool), "3d-x": np.array([False, False, True]),
                "2d-y": np.zeros(3, bool)}
    fig12_2d_vs_3d._write_ratios(ax, R, curves, "red", censored)
    assert sorted(t.get_text() for t in ax.texts) == ["×1.50 2D y", "≥×2.00 3D x"]
    for t in list(ax.texts):
        t.remove()
    censored = {"3d": np.array([False, False, True]), "3d-x": np.zeros(3, bool)}
    fig12_2d_vs_3d._write_ratios(ax, R, curves, "red", censored)
    assert sorted(t.get_text() for t in ax.texts) == ["≤×1.50 2D y", "≤×2.00 3D x"]
    # labels of curves ending close together are spread apart, never above the axes
    curves = {"3d": np.array([1.0, 2.0, 4.0]), "3d-x": np.full(3, 9.9),
              "3d-y": np.full(3, 9.85), "2d-x": np.full(3, 9.8)}
    for t in list(ax.texts):
        t.remove()
    fig12_2d_vs_3d._write_ratios(ax, R, curves, "red")
    ys = sorted(t.xy[1] for t in ax.texts)
    assert np.all(np.diff(ys) >= 0.05 * 10.0 - 1e-9) and ys[-1] <= 9.7 + 1e-9


def test_partially_computed_store_builds_every_figure(partial, tmp_path):
    """Damped and 2D only at tan α = 0.2, limit states spelt canonically: every figure that
    reads a store builds, draws no empty curve and names what is missing."""
    d9 = fig09_spectra.data(partial["store"], partial["means"], tan_alpha=0.1)
    assert "mode 3d-damped not computed at tan α = 0.1" in d9["missing"]
    assert [p["limit_state"] for p in d9["panels"]] == ["overturning", "tilt:1/3"]
    assert all(p["damping"] is None for p in d9["panels"])
    d9 = fig09_spectra.data(partial["store"], partial["means"])
    assert d9["missing"] == []
    d11 = fig11_slenderness.data(partial["means"], mode="3d-damped")
    assert "tan α = 0.1, 0.3 not computed" in d11["missing"]
    assert all(list(p["curves"]) == [0.2] for p in d11["panels"])
    d12 = fig12_2d_vs_3d.data([("p", partial["means"], partial["store"])], tan_alpha=0.3)
    assert any("mode 2d-x not computed" in s for s in d12["missing"])
    out = tmp_path / "figs"
    for name, kw in (("fig07_tilt_map", {"path": partial["tilt_map"]}),
                     ("fig09_spectra", {"store": partial["store"], "means": partial["means"],
                                        "tan_alpha": 0.3}),
                     ("fig10_goals", {"means": partial["means"]}),
                     ("fig11_slenderness", {"means": partial["means"], "mode": "2d-y"}),
                     ("fig12_2d_vs_3d", {"studies": [("p", partial["means"], partial["store"])],
                                         "tan_alpha": 0.1})):
        render(name, [out / f"{name}.png"], out / f"{name}.json", **kw)
        notes = json.loads((out / f"{name}.json").read_text())
        assert notes["figure"] == name
        assert (out / f"{name}.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert json.loads((out / "fig09_spectra.json").read_text())["missing"] == [
        "mode 3d-damped not computed at tan α = 0.3"]


def test_reduced_run_degrades_gracefully(reduced, tmp_path):
    d9 = fig09_spectra.data(reduced["store"], reduced["means"], modes=("3d", "3d-damped"))
    assert "mode 3d-damped not computed" in d9["missing"]
    # by default Fig 9 follows the store: no damped model ran, so no damped row and no gap
    d9 = fig09_spectra.data(reduced["store"], reduced["means"])
    assert d9["modes"] == ["3d"] and d9["missing"] == []
    assert len(fig09_spectra.plot(d9).axes) == 2  # one row: two panels, no difference row
    out = [tmp_path / "f9.png", tmp_path / "f9.pdf"]
    render("fig09_spectra", out, tmp_path / "f9.json", store=reduced["store"],
           means=reduced["means"], modes=("3d", "3d-damped"))
    notes = json.loads((tmp_path / "f9.json").read_text())
    assert notes["missing"] == ["mode 3d-damped not computed"]
    assert out[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert out[1].read_bytes()[:5] == b"%PDF-"
    d11 = fig11_slenderness.data(reduced["means"], tan_alphas=(0.2, 0.5))
    assert "tan α = 0.5 not computed" in d11["missing"]
    assert "not computed" in _texts(fig11_slenderness.plot(d11))


def _scaled(motion, factors, method):
    return [GroundMotion(f * motion.ax, f * motion.ay, motion.dt, f"syn-{f:g}",
                         {"fit_method": method}) for f in factors]


def test_fig08_traces_spectra_and_fit_quality():
    dt = 0.005
    t = np.arange(0.0, 20.0, dt)
    env = np.sin(np.pi * t / 20.0) ** 2  # smooth, slow: no energy near 50 Hz
    record = GroundMotion(3.0 * env * np.sin(2 * np.pi * t), 2.0 * env * np.cos(2.6 * np.pi * t),
                          dt, "record", {"principal_offset_deg": 19.5, "x_azimuth": 340.5,
                                         "y_azimuth": 250.5})
    # Scaled copies of the record: every PSA ratio is the scale factor, so the geometric
    # mean ratio is known exactly and the record's place in the range is known.
    motions = [record, *_scaled(record, (2.0, 2.5, 3.0), "spectrum")]
    comparison = [record, *_scaled(record, (0.9, 1.0, 1.1), "counts")]
    d = fig08_motions.data(motions, comparison, periods=np.array([0.02, 0.5, 2.0]))
    first = d["motions"][0]
    _same(first["ax"], record.ax / G)
    # a stiff oscillator (T = 0.02 s, 50 Hz ≫ 1 Hz input) follows the ground: PSA → PGA
    assert first["psa_x"][0] == pytest.approx(np.max(np.abs(first["ax"])), rel=2e-3)
    assert first["psa_y"][0] == pytest.approx(np.max(np.abs(first["ay"])), rel=2e-3)
    spectrum, counts = d["groups"]
    assert spectrum["method"] == "spectrum" and counts["method"] == "counts"
    np.testing.assert_allclose(spectrum["median_x"], 15.0 ** (1 / 3) * first["psa_x"], rtol=1e-12)
    q = d["measured"]["fit_quality"]
    for key in ("x", "y"):
        assert all(r == pytest.approx(15.0 ** (1 / 3)) for r in q["spectrum"][key]["band_ratio"]
                   .values())
        assert q["spectrum"][key]["inside_5_95"] == 0.0  # the record is below every copy
        assert q["counts"][key]["inside_5_95"] == 1.0
        assert q["counts"][key]["ratio_max"] == pytest.approx(0.99 ** (1 / 3))
    assert d["measured"]["fit_method"] == "spectrum"
    assert fig08_motions.bearing(340.5) == "N 19.5° W"
    assert fig08_motions.bearing(250.5) == "S 70.5° W"
    fig = fig08_motions.plot(d)
    spectra_axes = [ax for ax in fig.axes if ax.get_xscale() == "log"]
    assert len(spectra_axes) == 4  # (x, y) × (counts, spectrum)
    for ax in spectra_axes:
        assert ax.get_xlabel() == "T [s]" and "[g]" in ax.get_ylabel()
        drawn = [y for label, y in ((ln.get_label(), ln.get_ydata()) for ln in ax.get_lines())
                 if label == "record"]
        assert any(np.array_equal(y, first["psa_x"]) or np.array_equal(y, first["psa_y"])
                   for y in drawn)
    with pytest.raises(ValueError, match="motions"):
        fig08_motions.data([])
    alone = fig08_motions.data(motions[:2], periods=np.array([0.5]))
    assert alone["groups"][0]["fit_quality"] is None  # one pair: no range to compare with
    assert any("comparison" in m for m in alone["missing"])
    # a stand-in record is said of what was drawn, never "not computed in this run"
    from rocking.report.entries import FigureEntry, measured_lines

    stand_in = GroundMotion(record.ax, record.ay, dt, "stand-in",
                            {**record.metadata, "stand_in": True})
    d = fig08_motions.data([stand_in, *motions[1:]], comparison,
                           periods=np.array([0.5]))
    assert d["remarks"][0] == "stand-in is a stand-in" and d["missing"] == []
    assert "only 3 synthetic pairs" in d["remarks"][1]
    lines = measured_lines(FigureEntry("fig08_motions", Path("f.png"),
                                       {k: d[k] for k in ("remarks", "missing")}))
    assert len(lines) == 1 and lines[0].startswith("Note: stand-in is a stand-in; only 3")


# ---------------------------------------------------------------- the Snakemake rules


def _workdir(tmp_path: Path) -> tuple[Path, Path, dict[str, Path]]:
    """A work directory whose results/ holds the upstream products of a tiny study."""
    wd = tmp_path / "wd"
    paths = fs.write_study(wd / "results/synth", with_motions=False)
    cfg = {
        # the Fig 6 companion reads the El Centro record itself: 3 s of it keep this test short
        "motions": {"max_duration": 3.0},
        "ensembles": {"elcentro": {"record": "el-centro-1940", "n_synthetic": 1}},
        "studies": {"synth": {
            "ensemble": "elcentro", "R": fs.R, "reproduces": "vassiliou2017",
            "runs": [{"modes": fs.MODES, "tan_alpha": fs.TAN_ALPHA,
                      "limit_states": fs.LIMIT_STATES}],
            "tilt_map": {"R": [1.0, 2.0], "intensity": [1.0, 2.0]},
        }},
    }
    # the stores and the ensemble files where the workflow looks: named after their digests
    spec = StudySpec.from_config(cfg, "synth")
    for name, part in (("spectra", spec.spectra), ("tilt_map", spec.tilt_map)):
        store = wd / f"results/synth/{name}.zarr"
        store.rename(keyed(store, part.digest))
    paths["store"] = keyed(paths["store"], spec.spectra.digest)
    stem = f"results/motions/elcentro-{spec.ensemble.digest}"
    fs.write_motions(wd / f"{stem}.nc")
    fs.write_motions(wd / f"{stem}.compare.nc")
    (wd / f"{stem}.json").write_text(json.dumps(
        {"ensemble": "elcentro", "label": "synthetic record", "rotation_deg": -70.46,
         "principal_offset_deg": 19.54, "highpass": {"kind": "oscillator", "fc_hz": 0.0946},
         "n_synthetic": 1, "seed": 2017, "timings": {"fit_s": 1.0}}))
    for name in ("spectra", "tilt_map"):
        (wd / f"results/synth/{name}.done.json").write_text(json.dumps(
            {"wall_seconds": 12.0, "chunks": 3, "computed": 3, "cluster": "local"}))
    config = tmp_path / "config.yaml"
    config.write_text(yaml.safe_dump(cfg))
    assert paths["store"].exists()
    return wd, config, paths


@pytest.mark.slow
def test_snakemake_rules_build_every_figure_and_the_report(tmp_path):
    wd, config, paths = _workdir(tmp_path)
    # numba_cache: the figures that run analyses load the kernels it compiled
    mine = [*(f.rule_name for f in registered().values()), "fragility", "report",
            "numba_cache", "run_config"]
    # the per-record tables the report shows, as their rule writes them for a study whose
    # motions are no record (the stand-in store has none): headers only
    (wd / "results/synth/records.csv").write_text(
        "motion,source_record,mode,tan_alpha [-],limit_state,R [m],pga_g [g],"
        "pga_crit_g [g],scale_factor [-],exceeds_as_recorded,as_recorded_disagrees\n")
    (wd / "results/synth/suite_fragility.csv").write_text(
        "motions,mode,tan_alpha,limit_state,R,measure,unit,median,beta,n,n_censored,status\n")
    # the headline rule's table (rocking.study.headline), as it writes it: each motion's
    # first exceedance at R = 10 m on four grids, above its answer, falling with the grid
    answers = xr.open_zarr(paths["store"])["pga_crit"].sel(
        mode="3d", limit_state="overturning", tan_alpha=0.2, R=10.0).values
    rows = [{"motion": m, "mode": "3d", "limit_state": "overturning", "tan_alpha": 0.2,
             "R": 10.0, "scan_step": h, "first_exceedance": a * (1 + 10 * h),
             "not_reached": False, "answer": a, "quantity": "I10", "analyses": 100,
             "cpu_s": 1.0}
            for m, a in zip(fs.MOTIONS, answers, strict=True)
            for h in (0.01, 0.005, 0.002, 0.001)]
    pd.DataFrame(rows).to_csv(wd / "results/synth/headline.csv", index=False)
    snakemake = shutil.which("snakemake", path=str(Path(sys.executable).parent))
    # the target first: --allowed-rules and --rerun-triggers take several values each
    cmd = [snakemake or "snakemake", "results/synth/report.html", "results/synth/config.yaml",
           "-s", str(ROOT / "Snakefile"),
           "-d", str(wd), "--configfile", str(config), "--cores", "2",
           "--rerun-triggers", "mtime", "--allowed-rules", *mine]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    logs = "\n".join(p.read_text() for p in (wd / "results/logs").rglob("*.log"))
    assert proc.returncode == 0, proc.stderr[-4000:] + logs[-4000:]
    out = wd / "results/figures"
    # figures not tied to one study: named after the ensemble or studies they are drawn from
    for stem in ("fig03_wobbling_period", "fig04_free_vibration", "fig06_el_centro_elcentro",
                 "fig06_theta_max_sensitivity_elcentro", "fig08_motions_elcentro",
                 "fig12_2d_vs_3d_synth"):
        for suffix in (".png", ".pdf", ".json"):
            assert (out / f"{stem}{suffix}").stat().st_size > 0, stem + suffix
    for stem in ("fig07_tilt_map", "fig09_spectra", "fig10_goals", "fig11_slenderness",
                 "fragility_curves"):
        assert (wd / f"results/synth/figures/{stem}.png").stat().st_size > 10_000
    # the rule's figure notes are those of the library on the same store
    notes = json.loads((wd / "results/synth/figures/fig09_spectra.json").read_text())
    assert notes["measured"]["max_rel_diff_damped_tilt:0.3333"] == pytest.approx(0.05)
    assert "N19.5°W" in notes["axes"]["text"]
    sens = json.loads((out / "fig06_theta_max_sensitivity_elcentro.json").read_text())
    assert sens["measured"]["rotation_check"]["3d"] < 1e-6
    html = (wd / "results/synth/report.html").read_text()
    assert html.count("<figure") == 11
    # the title names the paper; the headline: the mean I10 and the same cells' mean first
    # exceedance on each grid (here 10·h above each answer)
    assert "Reproduction of Vassiliou, Burger, Egger, Bachmann, Broccardo &amp; Stojadinović " \
           "(2017)" in html
    mean = float(np.mean(answers))
    assert f"mean I10 of {mean:.2f}" in html
    assert f"{mean * 1.1:.2f} (1 %)" in html
    assert f"{mean * 1.01:.2f} (0.1 %)" in html
    assert "What was run" in html and "12 s wall" in html
    frag = xr.open_dataset(wd / "results/synth/fragility.nc")
    assert set(frag.dims) == {"mode", "limit_state", "tan_alpha", "R"}
    # the gallery of this run: found by the digests of its configuration, the ensemble's
    # parameters under their unkeyed name as in the committed gallery
    import zarr

    zarr.consolidate_metadata(str(paths["store"]))  # as a finished store of the workflow
    gallery = _gallery_module()
    run_config = yaml.safe_load((wd / "results/synth/config.yaml").read_text())
    # another configuration's figures in the same root (the main job's before the paper's)
    for stray in ("fig12_2d_vs_3d_synth+other", "fig08_motions_otherensemble"):
        shutil.copy(wd / "results/figures/fig12_2d_vs_3d_synth.png",
                    wd / f"results/figures/{stray}.png")
    files = gallery.collect(wd / "results", tmp_path / "gallery", run_config)
    names = {str(f.relative_to(tmp_path / "gallery")) for f in files}
    assert {"motions/elcentro.json", "synth/critical.csv", "synth/report.html",
            "figures/fig12_2d_vs_3d_synth.png", "config.yaml"} <= names
    assert not {n for n in names if "other" in n}, names
    for stray in ("fig12_2d_vs_3d_synth+other", "fig08_motions_otherensemble"):
        (wd / f"results/figures/{stray}.png").unlink()
    critical = pd.read_csv(tmp_path / "gallery/synth/critical.csv")
    assert len(critical) == xr.open_zarr(paths["store"]).pga_crit.size
    # no retired name in the tables, report and figures' notes of the run, or its gallery
    from test_retired import retired_names_in

    found = retired_names_in([*(wd / "results").rglob("*"), *files])
    assert not found, found[:10]


def _gallery_module():
    import importlib.util

    spec = importlib.util.spec_from_file_location("gallery", ROOT / "workflow/gallery.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


# ---------------------------------------------------------------- one look across figures


def test_figs_8_and_9_share_one_colour_per_motion(study, tmp_path):
    """The sidecars of Figs 8 and 9 give every motion the same colour and label: record
    black, synthetic 1–10 in ten further distinct colours."""
    names = fs.MOTIONS
    record = _pulse_pair(duration=4.0, name=names[0])
    motions = [record] + [GroundMotion(f * record.ax, f * record.ay, record.dt, n,
                                       {"fit_method": "spectrum"})
                          for f, n in zip((0.8, 1.1, 1.3), names[1:], strict=True)]
    render("fig08_motions", [tmp_path / "f8.png"], tmp_path / "f8.json", motions=motions,
           periods=np.array([0.1, 1.0]))
    render("fig09_spectra", [tmp_path / "f9.png"], tmp_path / "f9.json", store=study["store"],
           means=study["means"])
    c8 = json.loads((tmp_path / "f8.json").read_text())["colors"]
    c9 = json.loads((tmp_path / "f9.json").read_text())["colors"]
    assert c8 == c9
    assert [c8[n]["label"] for n in names] == ["record", "synthetic 1", "synthetic 2",
                                               "synthetic 3"]
    # eleven motions (the paper's ensemble) get eleven distinct colours
    eleven = _style.motion_styles([f"m{i}" for i in range(11)])
    assert len({s["color"] for s in eleven.values()}) == 11
    # the traces are drawn in those colours, and Fig 9's legend uses the same labels
    fig9 = fig09_spectra.plot(fig09_spectra.data(study["store"], study["means"]))
    legend = [t.get_text() for t in fig9.axes[0].get_legend().get_texts()]
    assert {"record", "synthetic 1", "synthetic 3"} <= set(legend)


def test_fig08_time_axis_ends_with_the_motion():
    """Zero padding after the motion does not stretch the time axis."""
    dt = 0.01
    t = np.arange(0.0, 30.0, dt)
    a = np.where(t < 12.0, np.sin(2 * np.pi * t) * np.sin(np.pi * t / 12.0), 0.0)
    padded = GroundMotion(a, 0.5 * a, dt, "record", {})
    end = fig08_motions.motion_end(t, a, 0.5 * a)
    assert 11.0 < end <= 12.0
    fig = fig08_motions.plot(fig08_motions.data([padded], periods=np.array([0.5, 1.0])))
    assert fig.axes[0].get_xlim()[1] == pytest.approx(15.0)  # 12 s rounded up to 5 s


@pytest.mark.parametrize("record", ["el-centro-1940", "loma-prieta-corralitos"])
def test_fig10_of_another_record_is_beyond_the_paper_not_a_reduced_run(study, tmp_path,
                                                                        record):
    # the paper draws Fig 10 for El Centro only: a reproduction study on another record
    # is not "a reduced run" of it, and its figure names no paper's goal as missing
    from rocking.store.attrs import decode_attrs

    with xr.open_dataset(study["means"]) as ds:
        agg = ds.load()
    ens = decode_attrs(dict(agg.attrs))["ensemble"]
    ens["motions"] = [{**m, "name": m["name"].replace("el-centro-1940", record),
                       "source_record": record} for m in ens["motions"]]
    agg.attrs["ensemble"] = json.dumps(ens)
    keep = ["overturning", "tilt:0.3333"]  # two of the paper's seven goals
    agg.sel(limit_state=keep).to_netcdf(tmp_path / "mean_spectra.nc")
    d = fig10_goals.data(tmp_path / "mean_spectra.nc", paper=True)
    title = fig10_goals.plot(d).axes[0].get_title()
    if record == "el-centro-1940":
        assert d["in_paper"] and "(Fig 10)" in title and "reduced run: 2 of the paper's 7" \
            in title and any("paper's 7 goals" in m for m in d["missing"])
    else:
        assert not d["in_paper"] and "reduced run" not in title and "Fig 10)" not in title
        assert "beyond the paper" in title
        assert not any("paper's" in m for m in d["missing"])


def test_fig10_says_when_two_goals_coincide(tmp_path):
    """θ > α and overturning with identical statistics: said in the sidecar and the figure,
    and the flat-then-rise shape measured."""
    R = np.array([1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 10.0])
    flat_rise = np.where(R <= 3.0, 1.1, 1.1 + 0.5 * (R - 3.0))
    states = ["tilt:0.5", "tilt:1", "overturning"]
    mean = np.stack([0.8 * flat_rise, flat_rise, flat_rise])[None, :, None, :]
    agg = xr.Dataset(
        {"mean": (("mode", "limit_state", "tan_alpha", "R"), mean),
         "median": (("mode", "limit_state", "tan_alpha", "R"), mean),
         "std": (("mode", "limit_state", "tan_alpha", "R"), 0.1 * mean),
         "count": (("mode", "limit_state", "tan_alpha", "R"), np.full(mean.shape, 11.0))},
        coords={"mode": ["3d"], "limit_state": states, "tan_alpha": [0.2], "R": R},
        attrs={"quantity": json.dumps(fs.QUANTITY)})
    path = tmp_path / "means.nc"
    agg.to_netcdf(path)
    d = fig10_goals.data(path)
    assert d["answer"] == "I10" and d["measured"]["answer"] == "I10"
    assert d["measured"]["coincide"] == [{"goals": ["tilt:1", "overturning"], "n_R": 7,
                                          "n_motions": 11}]
    line = d["measured"]["line|overturning"]
    assert line["flat_to_R"] == 3.0 and line["flat_level"] == pytest.approx(1.1)
    assert line["end_value"] == pytest.approx(4.6)
    assert line["residual_signs"].startswith("+") and "−" in line["residual_signs"]
    assert "coincide" in _texts(fig10_goals.plot(d))


def test_fig10_calls_a_stretch_flat_only_where_the_data_are_flat(tmp_path):
    """The shape said under Fig 10 and in its verdict comes from the data: a spectrum that
    rises from its first size on is "rising, bending upward", never "flat up to" its first
    R; one flat over three sizes or more is said flat there; nothing is written over the
    axes (the legend and the notes sit under them)."""
    R = np.linspace(0.5, 10.0, 20)
    convex = 1.0 + 0.2 * R**2                       # +14 % from the first to the second R
    slope, intercept = np.polyfit(R, convex, 1)
    fit = fig10_goals.shape(R, convex, slope, intercept)
    assert fit["flat_sizes"] == 1 and fit["curvature"] == pytest.approx(0.2)
    text = fig10_goals.shape_text(fit)
    assert "flat" not in text and "bending upward" in text
    assert text.startswith("rising from 1.05 at R = 0.5 m to 21.00 at R = 10 m")
    worst = R[np.argmax(np.abs(convex - slope * R - intercept))]
    assert f"misses it most at R = {worst:g} m" in text
    knee = np.maximum(1.1, 0.5 * R)                 # flat up to R = 2 m (4 sizes)
    fit = fig10_goals.shape(R, knee, *np.polyfit(R, knee, 1))
    assert "within 10 % of 1.10 up to R = 2 m (4 sizes)" in fig10_goals.shape_text(fit)
    # the figure: notes under it, the legend under the axes
    agg = xr.Dataset(
        {k: (("mode", "limit_state", "tan_alpha", "R"), convex[None, None, None, :])
         for k in ("mean", "median", "std", "count")},
        coords={"mode": ["3d"], "limit_state": ["overturning"], "tan_alpha": [0.2], "R": R},
        attrs={"quantity": json.dumps(fs.QUANTITY)})
    agg.to_netcdf(tmp_path / "means.nc")
    d = fig10_goals.data(tmp_path / "means.nc")
    fig = fig10_goals.plot(d)
    ax = fig.axes[0]
    fig.canvas.draw()
    inside = [t for t in ax.texts if t.get_text()]
    assert inside == []
    assert ax.get_legend().get_window_extent().y1 <= ax.get_window_extent().y0
    assert any("bending upward" in t.get_text() for t in fig.texts)
    # the title in whole lines (what, from what), never wrapped inside the ensemble's name
    assert ax.get_title().splitlines()[1] == d["title"]


def test_fragility_figure_names_its_ensemble_and_stops_at_the_search_bound(study, tmp_path):
    from rocking.fragility import lognormal as fragility
    from rocking.plot import _load, fragility_curves

    table = fragility.fragility_table(_load.open_store(study["store"]), upper=fs.UPPER)
    table.to_netcdf(tmp_path / "f.nc")
    d = fragility_curves.data(tmp_path / "f.nc", study["store"])
    assert d["upper"] == fs.UPPER
    fig = fragility_curves.plot(d)
    text = _texts(fig)
    assert "El Centro 1940 ensemble" in text and "IM₅₀" in text and "θ̂" not in text
    panels = [ax for ax in fig.axes if ax.get_xlabel() == "PGA/(g tan α) [-]"]
    assert panels and all(0 < ax.get_xlim()[1] <= fs.UPPER for ax in panels)
    # what is drawn: the distribution of the motions' critical intensities, not P(exceeded at x)
    assert all(ax.get_ylabel() == "share of motions whose critical intensity ≤ PGA/(g tan α) [-]"
               for ax in panels)
    # one colour bar for R instead of a legend entry per size; its ticks the named sizes
    bar = [ax for ax in fig.axes if ax.get_ylabel() == "cylinder size R [m]"]
    assert bar
    named = fragility_curves._highlighted(sorted(d["panels"][0]["curves"]))
    assert [float(t) for t in bar[0].get_yticks()] == pytest.approx(named)
    # a few sizes named on their curves and drawn thick with their points, the others thin
    for ax, panel in zip(panels, d["panels"], strict=True):
        names = sorted(t.get_text() for t in ax.texts if t.get_text().startswith("R = "))
        assert names == sorted(f"R = {R:g} m" for R in named if R in panel["curves"])
        thick = [ln for ln in ax.get_lines() if ln.get_linewidth() > 1.5]
        assert len(thick) == len(names) <= len(panel["curves"])
    # twenty sizes: five named, the smallest and the largest among them, evenly spread
    twenty = [0.5 * k for k in range(1, 21)]
    assert fragility_curves._highlighted(twenty) == [0.5, 3.0, 5.0, 7.5, 10.0]
    # one legend, below the panels (none inside one)
    assert all(ax.get_legend() is None for ax in panels)
    assert len([ax for ax in fig.axes if ax.get_legend()]) == 1


def test_fig09_counts_plateau_answers_per_motion_and_names_the_quantity(study, tmp_path):
    """A ``plateau`` flag (P rises near p below the answer without crossing: I10
    ill-conditioned) is counted per motion (its answers in every mode drawn) in the legend,
    not ringed on every point; a store without a flag set counts none. The axis and the
    legend say the curves are I10."""
    from rocking.plot import _load

    ds = _load.open_store(study["store"])
    flag = xr.zeros_like(ds["not_reached"], dtype=bool)
    flag.loc[{"mode": "3d", "motion": fs.MOTIONS[2], "tan_alpha": 0.2}] = True
    ds = ds.assign(plateau=flag & ~ds["not_reached"].astype(bool))
    path = tmp_path / "flagged.zarr"
    ds.to_zarr(path, mode="w", consolidated=False)
    d = fig09_spectra.data(path, study["means"])
    panel = d["panels"][0]
    assert list(panel["plateau"]["3d"]) == [fs.MOTIONS[2]]
    fig = fig09_spectra.plot(d)
    k = int(panel["plateau"]["3d"][fs.MOTIONS[2]].sum())
    n = sum(int(np.isfinite(c[fs.MOTIONS[2]]).sum()) for c in panel["curves"].values())
    legend = fig.axes[0].get_legend()
    texts = [t.get_text() for t in legend.get_texts()]
    label = d["colors"][fs.MOTIONS[2]]["label"]
    assert f"{label}; {k} of {n} answers on a plateau" in texts
    assert sum("plateau" in t for t in texts) == 1  # the other motions: none
    assert legend.get_title().get_text().startswith(
        "I10 = lowest PGA/(g tan α) at which ≥ 10 % of the intensities within ±2 % exceed")
    assert fig.axes[0].get_ylabel() == "I10 PGA/(g tan α) [-]"
    rings = [ln for ln in fig.axes[0].get_lines() if ln.get_marker() == "o"
             and ln.get_mfc() == "none" and len(ln.get_xdata())]
    assert not rings
    plain = fig09_spectra.data(study["store"], study["means"])
    assert all(not any(p["plateau"].values()) for p in plain["panels"])


def test_fig09_counts_answers_that_slide_when_the_study_gave_mu(study, tmp_path):
    """``slides`` (an analysis up to the answer needed more friction than the study's μ) is
    counted per motion in the legend; NaN (no μ) counts none."""
    from rocking.plot import _load

    ds = _load.open_store(study["store"])
    reached = ~ds["not_reached"].astype(bool)
    slides = xr.zeros_like(ds["pga_crit"])
    slides.loc[{"mode": "3d", "motion": fs.MOTIONS[1], "tan_alpha": 0.2}] = 1.0
    path = tmp_path / "slides.zarr"
    ds.assign(slides=slides.where(reached, 0.0)).to_zarr(path, mode="w", consolidated=False)
    d = fig09_spectra.data(path, study["means"])
    panel = d["panels"][0]
    assert list(panel["slides"]["3d"]) == [fs.MOTIONS[1]]
    k = int(panel["slides"]["3d"][fs.MOTIONS[1]].sum())
    n = sum(int(np.isfinite(c[fs.MOTIONS[1]]).sum()) for c in panel["curves"].values())
    legend = [t.get_text() for t in fig09_spectra.plot(d).axes[0].get_legend().get_texts()]
    assert f"{d['colors'][fs.MOTIONS[1]]['label']}; {k} of {n} slide" in legend
    assert sum("slide" in t for t in legend) == 1
    nothing = tmp_path / "no_mu.zarr"
    ds.assign(slides=xr.full_like(ds["pga_crit"], np.nan)).to_zarr(nothing, mode="w",
                                                                   consolidated=False)
    assert not any(fig09_spectra.data(nothing, study["means"])["panels"][0]["slides"].values())


def test_a_suite_is_labelled_by_its_records_not_as_record_and_synthetics():
    """A suite's recorded motions (each its own source record) keep their names in the
    legends, and the suite is named after itself, not after its first record."""
    from rocking.plot import _load
    from rocking.plot._style import motion_styles

    names = ["site-a", "site-b", "site-b-rdk-000", "sylmar"]
    sources = ["site-a", "site-b", "site-b", "sylmar"]
    labels = {n: s["label"] for n, s in motion_styles(names, sources).items()}
    assert labels == {"site-a": "site-a", "site-b": "site-b",
                      "site-b-rdk-000": "synthetic 1", "sylmar": "sylmar"}
    assert len({s["color"] for s in motion_styles(names, sources).values()}) == 4
    # one record and its pairs: the paper's labels, with or without the sources
    paper = motion_styles(["elc", "elc-rdk-000"], ["elc", "elc"])
    assert [s["label"] for s in paper.values()] == ["record", "synthetic 1"]
    assert paper == motion_styles(["elc", "elc-rdk-000"])
    attrs = {"ensemble": {"name": "mine", "motions": [
        {"name": n, "source_record": s, "label": n}
        for n, s in zip(names, sources, strict=True)]}}
    assert _load.ensemble_label(attrs, "x") == ("suite mine (3 records)", False)
    one = {"ensemble": {"name": "elcentro", "motions": [
        {"name": "elc", "source_record": "elc", "label": "El Centro"},
        {"name": "elc-rdk-000", "source_record": "elc", "label": "elc-rdk-000"}]}}
    assert _load.ensemble_label(one, "x") == ("El Centro", False)


def test_adding_a_figure_in_the_design_names_the_registry():
    """docs/design.md, "Adding a figure": its list names every required field of the entry,
    nothing the entry type does not have, and exactly the registry's scopes, logical inputs
    and parameters."""
    import dataclasses

    from rocking.plot import registry

    text = (ROOT / "docs" / "design.md").read_text(encoding="utf-8")
    section = text.split("\n## Adding a figure\n", 1)[1].split("\n## ", 1)[0]
    items = re.findall(r"^\d+\. (.*?)(?=^\d+\. |\Z)", section, re.MULTILINE | re.DOTALL)
    # one module and its test
    assert len(items) == 2, items
    assert items[0].startswith("`src/rocking/plot/<name>.py`") and items[1].startswith("`tests/`")
    entry = items[0].split("`FIGURE = FigureSpec(...)` with", 1)[1]  # the entry's fields
    named = set(re.findall(r"`([a-z_]+)`", entry))
    fields = {f.name for f in dataclasses.fields(registry.FigureSpec)}
    required = {f.name for f in dataclasses.fields(registry.FigureSpec)
                if f.default is dataclasses.MISSING
                and f.default_factory is dataclasses.MISSING}
    assert required <= named, required - named

    def listed(after: str) -> set[str]:
        part = re.search(rf"{after}(.*?)\)", entry, re.DOTALL)[1]
        return set(re.findall(r"`([a-z_0-9]+)`", part))

    assert listed(r"one of ") == set(registry.SCOPES)
    assert listed(r"logical input: ") == set(registry.INPUTS)
    assert listed(r"logical parameters: ") == set(registry.PARAMS)
    words = fields | set(registry.SCOPES) | set(registry.INPUTS) | set(registry.PARAMS)
    assert named <= words | {"__name__"}, named - words
    # the loop and its helpers the section names exist
    assert "FIGURE_INPUTS = {" in (ROOT / "workflow/rules/figures_common.smk").read_text()
    assert (ROOT / "workflow/scripts/figure.py").exists()


def test_a_bad_figure_entry_is_refused_naming_the_field():
    from rocking.plot import registry

    entry = dict(name="fig99_x", module=__name__, number=99, label="x", caption="x",
                 wanted=lambda subject: True)
    with pytest.raises(ValueError, match=r"figure 'fig99_x': scope must be one of .* 'planet'"):
        registry.FigureSpec(**entry, scope="planet")
    with pytest.raises(ValueError, match=r"params \['store'\] are not among"):
        registry.FigureSpec(**entry, scope="study", params={"store": "store"})
    with pytest.raises(ValueError, match="figure must be one of .*got 'fig99_x'"):
        registry.figure("fig99_x")
    # a figure of a reproduction only has no caption of a study of one's own
    with pytest.raises(ValueError, match="drawn only for a reproduction"):
        registry.caption("fig03_wobbling_period", paper=False)


def test_fig12_plateau_note_names_each_record_once_and_footnotes_fit_the_figure():
    from matplotlib.text import Text

    from rocking.plot._style import footnote, new_figure
    from rocking.plot.fig12_2d_vs_3d import _plateau_note

    counts = [("El Centro", "3D overturning", 17, 20), ("El Centro", "2D, x overturning", 20, 20),
              ("Loma Prieta", "3D overturning", 20, 20)]
    note = _plateau_note(counts)
    assert note.count("El Centro") == 1 and note.count("Loma Prieta") == 1
    assert "3D overturning 17/20" in note and "2D, x overturning 20/20" in note
    assert _plateau_note([("A", "3D", 5, 5)]).endswith("every size of all 1 curves.")
    # a long footnote is wrapped inside the figure's width
    fig, _ = new_figure(8.0, 4.0)
    footnote(fig, [note * 4])
    fig.canvas.draw()
    width = fig.bbox.width
    for t in fig.findobj(Text):
        if t.get_text() and t.get_window_extent().x1 > 0:
            assert t.get_window_extent().x1 <= width + 1, t.get_text()[:60]
