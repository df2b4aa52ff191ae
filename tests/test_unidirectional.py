"""The 3D model under one component (modes ``3d-x``, ``3d-y``; paper §5.4), checked against
what is independent of it: invariants of free rocking, Housner's restitution (Eq 31) for the
damped model, the angle of turn per quasi-impact, the mirror symmetry of the motion, and the
plain ``ground_response`` it is meant to be."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal import find_peaks

from rocking.constants import G
from rocking.dynamics import cylinder3d
from rocking.dynamics.analysis import MAX_UPLIFT_SPIN, THETA_EPS, ground_response
from rocking.dynamics.bodies import Cylinder
from rocking.motions.motion import GroundMotion
from rocking.spectra.critical import critical_intensity, make_analysis, uplift_intensity
from rocking.spectra.modes import (
    MODE_3D_X,
    MODE_3D_Y,
    MODES,
    UNIDIRECTIONAL_MODES,
    UNIDIRECTIONAL_SPIN,
    excitation,
)

BODY = Cylinder(0.5, 0.2)
PULSE_S = 0.5


def pulse(amplitude: float = 1.2, duration: float = 12.0, sign: float = 1.0) -> GroundMotion:
    """One sine of 0.5 s along x, ``amplitude`` × g tan α, then rest: free rocking after it."""
    dt = 0.005
    t = np.arange(0.0, duration, dt)
    a = np.where(t < PULSE_S, sign * amplitude * G * BODY.tan_alpha
                 * np.sin(2.0 * math.pi * t / PULSE_S), 0.0)
    return GroundMotion(a, None, dt, "one-sine pulse")


def pair(n: int = 1500) -> GroundMotion:
    """A short two-component record: the first 15 s of a seeded filtered noise pair."""
    from scipy.signal import butter, sosfiltfilt

    rng = np.random.default_rng(46)
    sos = butter(4, (0.5, 8.0), btype="bandpass", fs=100.0, output="sos")
    env = np.sin(np.pi * np.arange(n) / (n - 1)) ** 2
    ax, ay = (sosfiltfilt(sos, rng.standard_normal(n)) * env for _ in range(2))
    m = GroundMotion(ax, 0.6 * ay, 0.01, "noise pair")
    return m.scaled(0.3 * G / m.pga)


def free_part(r, after: float = PULSE_S + 0.01):
    keep = r.t > after
    return r.t[keep], r.theta[keep], r.theta_dot[keep], r.phi[keep], r.phi_dot[keep]


# ------------------------------------------------------------------------------ the mode
@pytest.mark.parametrize("mode", UNIDIRECTIONAL_MODES)
def test_the_mode_is_ground_response_of_one_component_with_the_spin(mode):
    """Bit for bit: the search's analysis is ``ground_response`` of the 3D model on
    ``motion.component(c)``, scaled by the pair's vector PGA, started with the modes' spin."""
    motion, body = pair(), Cylinder(1.0, 0.2)
    component = MODES[mode].component
    analyze = make_analysis(body, motion, mode, rest_tilt=None)
    for intensity in (1.3 * uplift_intensity(motion, mode), 3.0):
        got = analyze(intensity, None, 1e-8)
        ref = ground_response(body, motion.component(component), model="3d",
                              scale=intensity * (G * body.tan_alpha / motion.pga), rtol=1e-8,
                              history=False, stop_when_decided=True, monitors=False,
                              phi_dot0=UNIDIRECTIONAL_SPIN)
        assert got.theta_max == ref.theta_max  # to the bit
        assert got.status is ref.status
        assert got.theta_max > 0.0


def test_uplift_is_that_of_the_one_component():
    motion = pair()
    for mode in UNIDIRECTIONAL_MODES:
        a = motion.ax if MODES[mode].component == "x" else motion.ay
        assert uplift_intensity(motion, mode) == motion.pga / np.abs(a).max()
    assert uplift_intensity(motion, MODE_3D_Y) > uplift_intensity(motion, MODE_3D_X) > 1.0


def test_a_search_runs_and_finds_both_limit_states():
    res = critical_intensity(Cylinder(1.0, 0.2), pair(), ["overturning", "tilt:1/3"],
                             MODE_3D_X, accuracy="fast")
    assert not res.failed.any()
    assert res.intensity[1] <= res.intensity[0]  # θ > α/3 comes first
    assert res.intensity[1] >= uplift_intensity(pair(), MODE_3D_X)


# ---------------------------------------------------------------------------- bad input
def test_a_record_given_as_one_component_is_refused_naming_it_and_the_mode():
    one = GroundMotion(pair().ax, None, 0.01, "RSN6_IMPVALL.I_I-ELC180.AT2")
    for mode in UNIDIRECTIONAL_MODES:
        with pytest.raises(ValueError, match=rf"RSN6_IMPVALL.*no y component.*'{mode}'"):
            critical_intensity(Cylinder(1.0, 0.2), one, ["overturning"], mode)
    no_x = GroundMotion(np.zeros(1500), pair().ay, 0.01, "only-y")
    with pytest.raises(ValueError, match=r"'only-y' has no x component.*'3d-x'"):
        make_analysis(Cylinder(1.0, 0.2), no_x, MODE_3D_X)


@pytest.mark.parametrize("spin", [-1e-6, math.nan, math.inf, 10.0])
def test_a_bad_spin_is_one_line_naming_the_key(spin):
    with pytest.raises(ValueError, match=r"^phi_dot0 \(the spin at uplift\) must") as err:
        ground_response(Cylinder(6.0, 0.2), pulse(), phi_dot0=spin)
    assert "\n" not in str(err.value)


def test_the_spin_bound_is_a_thousandth_of_the_wobbling_rate_at_uplift():
    body = Cylinder(6.0, 0.2)
    top = MAX_UPLIFT_SPIN * float(body.wobbling_rate(THETA_EPS))
    assert top == pytest.approx(1.58, abs=0.01)  # rad/s, as documented
    ground_response(body, pulse(duration=1.0), phi_dot0=top, history=False)
    with pytest.raises(ValueError, match="at most 1.58 rad/s"):
        ground_response(body, pulse(duration=1.0), phi_dot0=1.001 * top)


def test_spin_where_it_has_no_meaning_is_refused():
    with pytest.raises(ValueError, match="the 2D model has no spin"):
        ground_response(BODY, pulse(), model="2d", phi_dot0=1e-6)
    for mode in ("3d", "2d-x"):
        with pytest.raises(ValueError, match=rf"applies to the modes .*not to mode '{mode}'"):
            excitation(mode, pair(), spin=1e-6)
    with pytest.raises(ValueError, match=r"a spin at uplift, phi_dot0 > 0"):
        ground_response(BODY, pulse())  # a planar 3D analysis would reach θ = 0


# ------------------------------------------------------------------------------ physics
def test_undamped_free_rocking_under_one_component_keeps_its_energy():
    """After the pulse the undamped 3D model rocks freely: its energy stays, over 41 changes
    of pivot (measured drift 1.5e-6 at the default rtol 1e-8, 3e-8 at 1e-10: the integration
    error), where Housner's block with e = 0.942 loses (1 − e²) of it at each."""
    rest = G * BODY.R * math.cos(BODY.alpha)
    drift = {}
    for rtol in (1e-8, 1e-10):
        r = ground_response(BODY, pulse(), model="3d", history=True, free_tail=False,
                            rtol=rtol, phi_dot0=UNIDIRECTIONAL_SPIN)
        t, th, thd, _, phd = free_part(r)
        rocking = cylinder3d.energy(BODY, th, thd, phd) - rest
        assert np.sum(r.quasi_impacts.t > PULSE_S) >= 20
        drift[rtol] = float(np.max(np.abs(rocking - rocking[0])) / rocking[0])
    assert drift[1e-8] < 2e-5
    assert drift[1e-10] < drift[1e-8] / 10
    # the 2D block on the same pulse: its peaks decay as e² per impact in energy
    r2 = ground_response(BODY, pulse(), model="2d", history=True, free_tail=False)
    th2 = np.abs(r2.theta[r2.t > PULSE_S])
    peaks = th2[find_peaks(th2)[0]]
    assert peaks[20] < 0.5 * peaks[0]


def test_damped_model_under_one_component_decays_as_housner():
    """The damped 3D model after the pulse: θ̇ before successive quasi-impacts falls by
    Housner's e = 0.942169 (Eq 31) per impact (paper Eq 32, Fig 4b). Measured over five
    impacts: 0.942170–0.942335 for seven of the paper's eight (ωn, ζ); (200, 0.05), a soft
    spring ringing between impacts, 0.9434."""
    for omega_n, zeta, tol in ((2000.0, 5.0, 1e-5), (2000.0, 50.0, 1e-5), (200.0, 0.5, 3e-4)):
        r = ground_response(BODY, pulse(), model="3d-damped", history=True,
                            phi_dot0=UNIDIRECTIONAL_SPIN, omega_n=omega_n, zeta=zeta)
        _, th, thd, _, _ = free_part(r)
        top = find_peaks(th, prominence=0.2 * th.max())[0]
        speed = np.array([-thd[a:b].min() for a, b in zip(top[:-1], top[1:], strict=True)])
        assert len(speed) >= 6
        assert (speed[5] / speed[0]) ** 0.2 == pytest.approx(BODY.e, abs=tol)
    assert BODY.e == pytest.approx(0.942169, abs=1e-6)


def test_quasi_impacts_turn_the_pivot_by_nearly_pi():
    """Between tilt maxima of the free rocking after the pulse the contact point turns by
    3.205 rad: close to π and to the small-spin asymptote π√(κo/κt) = 3.188 (the spin the
    pulse left is finite: tilt minima 7e-5 rad); the paper computes 3.058, Srinivasan–Ruina
    give 2π − 3.188 = 3.095 measured the other way round."""
    r = ground_response(BODY, pulse(), model="3d", history=True, free_tail=False,
                        phi_dot0=UNIDIRECTIONAL_SPIN)
    _, th, _, phi, _ = free_part(r)
    top = find_peaks(th)[0]
    turns = np.abs(np.diff(phi[top]))
    assert len(turns) >= 20
    np.testing.assert_allclose(turns, BODY.turn_angle, atol=0.03)
    assert np.all(np.abs(turns - math.pi) < 0.07)
    assert BODY.turn_angle == pytest.approx(3.18802, abs=1e-5)


def test_the_answer_does_not_hinge_on_the_spin_or_on_round_off():
    """The peak tilt is the same for spins 1e-8 … 1e-2 rad/s, for the mirrored motion (whose
    uplift direction φ0 = 0 has an exact sine where the original's −π has 1.2e-16) and
    with every sample moved by one unit in the last place."""
    base = pulse(duration=6.0)
    ref = ground_response(BODY, base, history=False, phi_dot0=UNIDIRECTIONAL_SPIN).theta_max
    others = [ground_response(BODY, base, history=False, phi_dot0=s).theta_max
              for s in (1e-8, 1e-4, 1e-2)]
    others.append(ground_response(BODY, pulse(duration=6.0, sign=-1.0), history=False,
                                  phi_dot0=UNIDIRECTIONAL_SPIN).theta_max)
    nudged = GroundMotion(np.nextafter(base.ax, np.where(np.arange(base.ax.size) % 2, 1, -1)
                                       * np.inf), None, base.dt, "nudged")
    others.append(ground_response(BODY, nudged, history=False,
                                  phi_dot0=UNIDIRECTIONAL_SPIN).theta_max)
    np.testing.assert_allclose(others, ref, rtol=1e-6)
    assert 0.05 * BODY.alpha < ref < BODY.alpha


# ------------------------------------------------------------------------ command line
def test_simulate_runs_the_mode_and_refuses_one_file_naming_it(tmp_path, capsys):
    import json

    from conftest import ELC180, package_record

    from rocking.cli import main

    out = tmp_path / "run"
    assert main(["simulate", "--R", "2", "--tan-alpha", "0.2", "--record", "el-centro-1940",
                 "--mode", "3d-x", "--pga-ratio", "2", "--json", "-o", str(out)]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["mode"] == "3d-x" and summary["phi_dot0"] == UNIDIRECTIONAL_SPIN
    assert summary["n_quasi_impacts"] > 0
    capsys.readouterr()
    one = str(package_record(ELC180))
    assert main(["simulate", "--R", "2", "--tan-alpha", "0.2", "--files", one, "--mode", "3d-y",
                 "-o", str(tmp_path / "one")]) == 2
    err = [line for line in capsys.readouterr().err.strip().splitlines()
           if not line.startswith("rocking simulate: compiling")]
    assert len(err) == 1 and "ELC180" in err[0] and "'3d-y'" in err[0], err
    assert main(["simulate", "--R", "2", "--tan-alpha", "0.2", "--record", "el-centro-1940",
                 "--mode", "3d", "--phi-dot0", "1e-4", "-o", str(tmp_path / "both")]) == 2
    assert "--phi-dot0 (the spin at uplift) applies to the modes" in capsys.readouterr().err
