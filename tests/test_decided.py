"""An analysis ends once the motion left cannot raise its peak tilt (code DECIDED).

The bound (docs/performance.md, "An analysis decided before its end"): the ground does work
−a_g·v_G per unit mass and ½|v_G|² is at most the kinetic energy, so d√E/dt ≤ |a_g|/√2. The
checks: the reserve bounds the integral it stands for; the integrated energy of both
undamped models obeys the bound (an independent check of the inequality on the trajectory);
an analysis that ends early keeps θmax, its time and the status of the run to the end, for
fewer steps; critical intensities and every analysis of their searches are byte-identical
with the test switched off (main's behaviour); bad values name the field.
"""

import dataclasses
import functools
import math

import numpy as np
import pytest

import rocking
from rocking.constants import G
from rocking.dynamics import analysis, codes, cylinder3d, cylinder3d_damped, housner2d
from rocking.motions.motion import GroundMotion


def _pulse_and_coda(amplitude: float, coda: float, seconds: float = 30.0,
                    seed: int = 1) -> GroundMotion:
    """A 1 s two-component pulse of ``amplitude`` [m/s²], then ``seconds`` of noise whose
    peak is ``coda`` [m/s²] (below uplift for the bodies here): a body set rocking by the
    pulse rocks on through a coda that cannot lift it from rest."""
    dt = 0.01
    t = np.arange(int((1.5 + seconds) / dt)) * dt
    pulse = np.where(t < 1.0, np.sin(np.pi * t), 0.0)
    rng = np.random.default_rng(seed)
    noise = np.where(t > 1.5, rng.standard_normal(t.size), 0.0)
    noise *= coda / np.max(np.abs(noise))
    return GroundMotion(amplitude * pulse + noise,
                        0.6 * amplitude * np.roll(pulse, 30) + np.roll(noise, 7), dt, "coda")


@pytest.fixture(scope="module")
def padded_el_centro():
    """El Centro as recorded plus 40 s of zeros (the study pads its high-passed records)."""
    m = rocking.load_motion("el-centro-1940")
    pad = np.zeros(4000)
    return GroundMotion(np.concatenate([m.ax, pad]), np.concatenate([m.ay, pad]), m.dt,
                        "el-centro-1940 padded")


def test_energy_reserve_bounds_the_integral_it_stands_for():
    rng = np.random.default_rng(3)
    decay = np.exp(-np.arange(400) / 60.0)  # a coda: only the early samples lift a body
    ax, ay = rng.standard_normal(400) * decay, rng.standard_normal(400) * decay
    dt, thr = 0.02, 1.5
    q = analysis.energy_reserve(ax, ay, dt, thr)
    last_up = np.flatnonzero(np.hypot(ax, ay) > thr)[-1]
    assert np.all(np.isinf(q[:last_up + 1])) and np.all(np.isfinite(q[last_up + 1:]))
    assert q[-1] == 0.0 and np.all(np.diff(q[last_up + 1:]) <= 0.0)
    # ∫|a| dt/√2 from each sample on, with |a| linear between samples, on a fine grid
    s = np.linspace(0.0, 1.0, 201)[None, :]
    a = np.hypot(ax[:-1, None] + s * np.diff(ax)[:, None],
                 ay[:-1, None] + s * np.diff(ay)[:, None])
    per = np.trapezoid(a, dx=dt / 200, axis=1) / math.sqrt(2.0)
    exact = np.append(np.cumsum(per[::-1])[::-1], 0.0)
    k = slice(last_up + 1, None)
    assert np.all(q[k] >= exact[k] * (1 - 1e-12))
    # and not a wild one: |a| is convex along an interval, so its largest end value is at
    # most twice its mean there
    assert np.all(q[k] <= exact[k] * 2.0 * (1 + 1e-9) + 1e-12)


def _energy_above_rest(model: str, body, res) -> np.ndarray:
    if model == "3d-damped":  # rocking, vertical motion and contact spring
        rows = np.column_stack([res.theta, res.phi, res.w, res.theta_dot, res.phi_dot,
                                res.w_dot])
        return cylinder3d_damped.energy(body, rows, 2000.0) - G * body.R * math.cos(body.alpha)
    if model == "2d":
        return housner2d.energy(body, res.theta, res.theta_dot)  # already above rest
    return (cylinder3d.energy(body, res.theta, res.theta_dot, res.phi_dot)
            - G * body.R * math.cos(body.alpha))


@pytest.mark.parametrize("model", ["3d", "3d-damped", "2d"])
def test_integrated_energy_obeys_the_bound(model):
    """√E(t) − √E(t0) ≤ ∫_{t0}^{t} |a_g| dt/√2 along the integrated trajectory (from every
    tenth output row to every later one), while the body rocks on through the coda."""
    body = rocking.Cylinder(4.0, 0.2)
    motion = _pulse_and_coda(2.6, 0.4, seconds=10.0)
    res = analysis.ground_response(body, motion, model=model, history=True)
    assert res.uplifted and res.status.value == "ok"
    t = res.t
    E = np.maximum(_energy_above_rest(model, body, res), 0.0)
    a = np.hypot(motion.ax, 0.0 if model == "2d" else motion.ay)
    ta = np.arange(a.size) * motion.dt
    fine = np.linspace(0.0, t[-1], 200_001)
    cum = np.concatenate([[0.0], np.cumsum(np.interp(fine[1:], ta, a) * np.diff(fine))])
    work = np.interp(t, fine, cum) / math.sqrt(2.0)
    rocking_rows = np.flatnonzero(E > 0.0)
    assert rocking_rows.size > 100
    slack = []
    for i in rocking_rows[::10]:
        later = t > t[i]
        gain = np.sqrt(E[later]) - math.sqrt(E[i]) - (work[later] - work[i])
        slack.append(gain.max())
    # integration error of E is ~rtol; the bound holds with a margin of that order
    assert max(slack) <= 1e-5 * math.sqrt(E.max())


@pytest.mark.parametrize("model,R,ratios,share", [
    ("3d", 4.0, (1.2, 1.6, 2.0, 2.5, 3.2), 0.9),
    ("3d-damped", 4.0, (1.6, 2.0, 2.5), 0.9),
    ("2d", 10.0, (2.5, 3.5, 5.0, 7.0), 1.0),  # its impacts end most episodes before the coda
])
def test_decided_run_keeps_the_answer_for_fewer_steps(model, R, ratios, share,
                                                      padded_el_centro):
    body = rocking.Cylinder(R, 0.2)
    early_steps = full_steps = 0
    for ratio in ratios:
        kw = dict(model=model, history=False, pga_ratio=ratio)
        early = analysis.ground_response(body, padded_el_centro, **kw)
        full = analysis.ground_response(body, padded_el_centro, stop_when_decided=False, **kw)
        assert early.uplifted
        assert early.theta_max == full.theta_max
        assert early.t_theta_max == full.t_theta_max
        assert early.status is full.status and early.overturned == full.overturned
        early_steps += early.n_steps
        full_steps += full.n_steps
    # the body rocks on through the 40 s of zeros in the full runs; the early ones stop
    assert early_steps < share * full_steps


def test_with_history_the_run_goes_to_the_end(padded_el_centro):
    body = rocking.Cylinder(4.0, 0.2)
    kw = dict(model="3d", pga_ratio=1.6)
    early = analysis.ground_response(body, padded_el_centro, history=False, **kw)
    full = analysis.ground_response(body, padded_el_centro, history=False,
                                    stop_when_decided=False, **kw)
    assert early.n_steps < full.n_steps  # decided in the zeros without history
    res = analysis.ground_response(body, padded_el_centro, history=True, **kw)
    assert res.t[-1] >= padded_el_centro.duration  # the whole record and the free tail
    assert res.theta_max == early.theta_max


def test_a_body_that_may_still_be_lifted_is_never_decided(padded_el_centro):
    """Up to the last sample above uplift the reserve is infinite: the run goes on."""
    body = rocking.Cylinder(4.0, 0.2)
    scale = 1.6 * G * body.tan_alpha / padded_el_centro.pga
    ax = padded_el_centro.ax.copy()
    ax[-5] = 1.01 * G * body.tan_alpha / scale  # a late spike that could lift a body at rest
    late = GroundMotion(ax, padded_el_centro.ay, padded_el_centro.dt, "late spike")
    q = analysis.energy_reserve(late.ax * scale, late.ay * scale, late.dt,
                                G * body.tan_alpha)
    assert np.all(np.isinf(q[:-4])) and np.all(np.isfinite(q[-4:]))
    kw = dict(model="3d", history=False, scale=scale)
    early = analysis.ground_response(body, late, **kw)
    full = analysis.ground_response(body, late, stop_when_decided=False, **kw)
    assert early.theta_max == full.theta_max and early.status is full.status
    assert early.n_steps >= full.n_steps - 50  # decided at most in the last 4 samples


def _counting(monkeypatch, decided: bool) -> list[int]:
    """Route every analysis of the searches through ground_response with the test on or off,
    counting integration steps."""
    steps: list[int] = []
    original = analysis.ground_response

    @functools.wraps(original)
    def counted(*args, **kwargs):
        r = original(*args, **{**kwargs, "stop_when_decided": decided})
        steps.append(r.n_steps + r.n_rejected)
        return r

    monkeypatch.setattr(analysis, "ground_response", counted)
    return steps


@pytest.mark.parametrize("mode,R,limit_states", [
    ("3d", 4.0, None),                            # the seven goals of Fig 10
    ("3d", 8.0, ["overturning", "tilt:1/3"]),
    ("2d-x", 4.0, ["overturning", "tilt:1/3"]),
    ("3d-damped", 4.0, ["overturning", "tilt:1/3"]),
])
def test_search_answers_are_byte_identical(monkeypatch, padded_el_centro, mode, R,
                                           limit_states):
    body = rocking.Cylinder(R, 0.2)
    with monkeypatch.context() as mp:
        off_steps = _counting(mp, False)
        off = rocking.critical_intensity(body, padded_el_centro, limit_states, mode)
    with monkeypatch.context() as mp:
        on_steps = _counting(mp, True)
        on = rocking.critical_intensity(body, padded_el_centro, limit_states, mode)
    assert on.intensity.tobytes() == off.intensity.tobytes()
    assert on.i50.tobytes() == off.i50.tobytes()
    for flag in ("not_reached", "non_monotonic", "failed", "plateau"):
        assert np.array_equal(getattr(on, flag), getattr(off, flag))
    # every analysis of the search: same intensity, peak tilt (to the bit) and status (the
    # validity monitors are not compared: an analysis decided early is monitored to there)
    def tilt(e):
        return dataclasses.replace(e, mu_required_max=0.0, normal_force_min=0.0)

    assert [dataclasses.astuple(tilt(e)) for e in on.evaluations] == \
        [dataclasses.astuple(tilt(e)) for e in off.evaluations]
    assert len(on_steps) == len(off_steps) == on.n_analyses
    assert sum(on_steps) < sum(off_steps)


def test_decided_code_is_an_ok_status():
    assert codes.status_of(codes.DECIDED, 12.0) == (rocking.Status.OK, "")


def test_bad_switch_names_the_field():
    body = rocking.Cylinder(1.0, 0.2)
    with pytest.raises(ValueError, match="stop_when_decided"):
        analysis.ground_response(body, _pulse_and_coda(4.0, 0.1), stop_when_decided="yes")


@pytest.mark.parametrize("planar", [False, True])
def test_uplift_samples_from_the_cached_motion_are_those_of_the_full_evaluation(planar):
    """The samples above uplift come from the cached unscaled |a| (candidates) and the scaled
    components there: exactly the full evaluation's, also for thresholds that sit on a
    sample's own scaled |a| (ties)."""
    rng = np.random.default_rng(7)
    m = GroundMotion(rng.standard_normal(3000), rng.standard_normal(3000), 0.01, "noise")
    cached = analysis._unscaled(m, planar)
    assert analysis._unscaled(m, planar) is cached  # computed once per motion
    for scale in rng.uniform(0.1, 10.0, 40):
        ax = m.ax * scale
        ay = np.zeros_like(ax) if planar else m.ay * scale
        full = np.hypot(ax, ay)
        for thr in (*np.quantile(full, [0.5, 0.9, 0.999]), *full[rng.integers(0, 3000, 5)]):
            want = np.flatnonzero(full > thr)
            assert np.array_equal(analysis._above(cached, ax, ay, scale, thr), want)
