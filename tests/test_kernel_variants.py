"""The kernels' variants (issue 37 item 2): with or without the validity monitors, with or
without the vertical forcing, every model integrates the same motion to the same bits.

The monitors only read the state, and without a vertical component gravity is g + 0 = g
exactly, so dropping either from the compiled kernel must not move θmax, its time, the
status, the steps or the final state by one bit. Checked on 6 s of El Centro 1940 (the
strong part) scaled to rock, overturn or stop at a tilt, for "3d", "3d-damped" and "2d",
at the kernel (every variant, an all-zero a_z against none) and through the public analysis
(``monitors=False``; a motion whose a_z is all zeros against one without). The monitored
variants must still report the monitors, the others NaN.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocking.constants import G
from rocking.dynamics import Block, Cylinder, driver, ground_response, models
from rocking.motions.catalogue import load_record
from rocking.motions.motion import GroundMotion
from rocking.spectra.critical import make_analysis

# (model, body, PGA/(g tan α)): rocking, overturning, the damped model
CASES = [
    ("3d", Cylinder(2.0, 0.2), 1.6),
    ("3d", Cylinder(1.0, 0.2), 3.0),
    ("3d-damped", Cylinder(2.0, 0.2), 1.6),
    ("2d", Block(1.0, 0.2), 2.0),
]


@pytest.fixture(scope="module")
def segment() -> GroundMotion:
    """The strong part of El Centro 1940 (1–7 s), with and without an all-zero a_z."""
    m = load_record("el-centro-1940")
    i0, i1 = int(round(1.0 / m.dt)), int(round(7.0 / m.dt))
    return GroundMotion(m.ax[i0:i1], m.ay[i0:i1], m.dt, "el-centro-1940 1-7 s")


def _facts(r) -> tuple:
    """What must agree to the bit: θmax and its time (hex), status, steps."""
    return (float(r.theta_max).hex(), float(r.t_theta_max).hex(), r.status, r.n_steps,
            r.n_rejected)


@pytest.mark.parametrize("model,body,ratio", CASES)
def test_kernel_variants_agree_to_the_bit(segment, model, body, ratio):
    """Each of the four compiled variants of a model, run directly: the same code, steps,
    θmax, end time and final state; an all-zero a_z through the vertical variants."""
    scale = ratio * G * body.tan_alpha / segment.pga
    ax = segment.ax * scale
    ay = np.zeros_like(ax) if model == "2d" else segment.ay * scale
    m = models.MODELS[model]
    prep = models.prepare(m, body, m.rtol, models.rest_criterion(body, 0.0),
                          method=None if m.implicit else "dp5")
    k = int(np.argmax(np.hypot(ax, ay) > G * body.tan_alpha))  # first sample above uplift
    y0 = np.zeros(len(m.state))
    if model != "2d":
        y0[0] = 1e-7
    outs = {}
    for monitors, vertical in driver.VARIANTS:
        az = np.zeros(ax.size) if vertical else None
        outs[monitors, vertical] = models.run(prep, ax, ay, segment.dt, k, 0.0, 0.0, y0,
                                              segment.duration, -1.0, history=False,
                                              az=az, monitors=monitors)
    ref = outs[True, True]
    assert ref.n_steps > 100  # the body rocked
    for key, out in outs.items():
        assert (out.code, out.n_steps, out.n_rejected) == (ref.code, ref.n_steps,
                                                            ref.n_rejected), key
        assert float(out.theta_max).hex() == float(ref.theta_max).hex(), key
        assert float(out.t_stop).hex() == float(ref.t_stop).hex(), key
        assert out.y_end.tobytes() == ref.y_end.tobytes(), key
        assert out.ev_t.tobytes() == ref.ev_t.tobytes(), key
        width = len(m.state)
        assert out.ev_y[:, :width].tobytes() == ref.ev_y[:, :width].tobytes(), key
        if monitors := key[0]:
            assert out.monitor.tobytes() == ref.monitor.tobytes(), key
        else:
            assert np.isnan(out.monitor).all() and np.isnan(out.ev_y[:, width:]).all(), key
    # the monitors saw a real contact force: N about 1 weight, μ_req > 0
    assert 0.0 < ref.monitor[driver.M_MUMAX] and ref.monitor[driver.M_NMIN] < 1.0


@pytest.mark.parametrize("model,body,ratio", CASES)
def test_analysis_without_monitors_or_vertical_agrees(segment, model, body, ratio):
    """Through the public analysis: ``monitors=False`` and an all-zero vertical component
    (which takes the vertical path with ``vertical=True``... refused: a zero a_z is no
    vertical component) give the monitored answers to the bit; without monitors N and
    μ_req are NaN, with them finite."""
    body = type(body)(body.R, body.tan_alpha, mu=0.3)  # slides: None where not monitored
    zero_az = GroundMotion(segment.ax, segment.ay, segment.dt, "zero az",
                           az=np.zeros(segment.npts))
    mot = segment.component("x") if model == "2d" else segment
    zmot = zero_az.component("x") if model == "2d" else zero_az
    runs = {}
    for name, motion, monitors in (("mon", mot, True), ("bare", mot, False),
                                   ("zero-az", zmot, True), ("zero-az bare", zmot, False)):
        for history in (False, True):
            runs[name, history] = ground_response(body, motion, model=model,
                                                  pga_ratio=ratio, history=history,
                                                  monitors=monitors)
    ref = runs["mon", False]
    assert ref.uplifted and math.isfinite(ref.mu_required_max)
    for (name, history), r in runs.items():
        assert _facts(r) == _facts(runs["mon", history]), (name, history)
        if history:
            h = runs["mon", True]
            assert r.theta.tobytes() == h.theta.tobytes(), name
            assert r.t.tobytes() == h.t.tobytes(), name
        if name.endswith("bare"):
            assert math.isnan(r.mu_required_max) and math.isnan(r.normal_force_min)
            assert np.isnan(r.mu_required).all() and not r.lifts_off
            assert r.slides is None
        else:
            assert float(r.mu_required_max).hex() == float(
                runs["mon", history].mu_required_max).hex()


def test_vertical_motion_monitors_off_agrees(segment):
    """With a real vertical component the variants with and without the monitors agree to
    the bit (the vertical forcing is in both), and differ from the motion without it."""
    body = Cylinder(2.0, 0.2)
    az = 0.5 * np.roll(segment.ax, 37)
    vert = GroundMotion(segment.ax, segment.ay, segment.dt, "with az", az=az)
    on = ground_response(body, vert, pga_ratio=1.6, history=False)
    off = ground_response(body, vert, pga_ratio=1.6, history=False, monitors=False)
    level = ground_response(body, segment, pga_ratio=1.6, history=False, monitors=False)
    assert _facts(on) == _facts(off)
    assert _facts(on) != _facts(level)


def test_search_runs_the_monitors_only_when_asked(segment):
    """``make_analysis``: without ``whole`` no monitor reaches the search (and θmax is the
    monitored one's); with it both are there."""
    body = Cylinder(2.0, 0.2)
    bare = make_analysis(body, segment)(1.6, None, 1e-8)
    whole = make_analysis(body, segment, whole=True)(1.6, None, 1e-8)
    assert dict(bare.other_peaks) == {}
    assert set(whole.other_peaks) == {"mu_required_max", "normal_force_min"}
    ref = ground_response(body, segment, scale=1.6 * (G * body.tan_alpha / segment.pga),
                          history=False, rtol=1e-8)
    assert float(bare.theta_max).hex() == float(ref.theta_max).hex()


def test_monitors_must_be_a_bool(segment):
    with pytest.raises(ValueError, match="monitors must be True or False, got 'no'"):
        ground_response(Cylinder(2.0, 0.2), segment, monitors="no")


def test_warm_up_compiles_the_variants_a_configuration_asks_for():
    """The workflow's warm-up reads which variants a configuration may need: a study's
    ``mu`` or a sliding goal anywhere (monitors), ``vertical: true`` (vertical forcing)."""
    from rocking.execution.warmup import variants_asked

    plain = {"study": {"mu": None, "limit_states": ["overturning", "tilt:1/3"]},
             "ensemble": {"vertical": False}}
    assert variants_asked(plain) == (False, False)
    assert variants_asked({**plain, "study": {"mu": 0.4}}) == (True, False)
    assert variants_asked({**plain, "stripes": {"limit_states": ["Sliding:0.3"]}}) == (True,
                                                                                       False)
    assert variants_asked({**plain, "ensembles": [{"records": [{"vertical": True}]}]}) == (
        False, True)


def test_the_history_kernels_are_compiled_once_where_the_paper_s_figures_trace_them(
        tmp_path):
    """A reproduction of the paper draws Figs 4 and 6, which keep histories: the warm-up
    compiles those kernels once (into a fresh cache here), and an analysis keeping its
    history afterwards compiles nothing (numba's cache gains no file)."""
    import os
    import subprocess
    import sys

    from rocking.execution.warmup import histories_asked

    assert histories_asked({"studies": {"a": {"reproduces": "vassiliou2017"}, "b": {}}})
    assert not histories_asked({"studies": {"a": {"reproduces": None}}})
    code = ("import os\n"
            "from rocking.execution.warmup import warm_numba_cache, _warm_motion\n"
            "from rocking.dynamics.analysis import ground_response\n"
            "from rocking.dynamics.bodies import Cylinder\n"
            "warm_numba_cache(['3d'], history=True)\n"
            "root = os.environ['NUMBA_CACHE_DIR']\n"
            "files = lambda: {os.path.join(d, f) for d, _, fs in os.walk(root) for f in fs}\n"
            "before = files()\n"
            "ground_response(Cylinder(3.0, 0.15), _warm_motion(), model='3d', pga_ratio=1.5,"
            " history=True)\n"
            "print(len(files() - before))\n")
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, check=True, timeout=900)
    assert out.stdout.split()[-1] == "0"
