"""Squat bodies: where Housner's restitution formula changes sign, impacts end the rocking.

The restitution formulas come from the balance of angular momentum about the new pivot at
the impact. The checks below write that balance independently (vectors, textbook inertias
of the solid block and cylinder, no κo from the package), find where it changes sign, check
that stopping flat is the outcome compatible with compressive impulses beyond it (and not
before), and that every 2D analysis applies it: θ̇ = 0 after the first impact, θ = 0 after.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from rocking import Block, Cylinder, GroundMotion, Status, free_vibration, ground_response
from rocking.cli import main
from rocking.constants import G


def _cross(u, v) -> float:
    return float(u[0] * v[1] - u[1] * v[0])


def _impact(kind: str, tan_alpha: float, R: float = 1.0, m: float = 1.0) -> dict:
    """Impact of a body falling back flat while rocking on its right corner O.

    Frame: base centre at the origin, O = (b, 0), the corner that lands O' = (−b, 0),
    centre of mass G = (0, h); the body turns counterclockwise at ω⁻ = 1 rad/s about O.
    Returns the restitution of rocking on about O' with the impulse at O' only, and the
    corner impulses that would stop the body flat instead.
    """
    alpha = math.atan(tan_alpha)
    b, h = R * math.sin(alpha), R * math.cos(alpha)
    if kind == "block":  # solid rectangle 2b × 2h about its centroid
        i_g = m * ((2 * b) ** 2 + (2 * h) ** 2) / 12.0
    else:  # solid cylinder of radius b, height 2h, about a horizontal diameter
        i_g = m * (3 * b**2 + (2 * h) ** 2) / 12.0
    O, O2, Gc = np.array([b, 0.0]), np.array([-b, 0.0]), np.array([0.0, h])
    w = 1.0
    v_g = w * np.array([-(Gc - O)[1], (Gc - O)[0]])  # ω ẑ × (G − O)
    h_before = i_g * w + m * _cross(Gc - O2, v_g)  # angular momentum about O'
    i_new = i_g + m * float((Gc - O2) @ (Gc - O2))
    w_after = h_before / i_new  # the only impulse acts at O': H about O' is kept
    # Stopped flat: v⁺ = 0, ω⁺ = 0, vertical impulses J at O and J' at O' (friction takes
    # the horizontal momentum): 0 − H = (O − O') × J ŷ, 0 − m v_G = J + J' (vertical).
    j_o = -h_before / _cross(O - O2, np.array([0.0, 1.0]))
    j_o2 = -m * v_g[1] - j_o
    v_o_after = w_after * np.array([-(O - O2)[1], (O - O2)[0]])  # O when turning about O'
    return {"e": w_after / w, "j_old": j_o, "j_new": j_o2, "v_old_corner_y": v_o_after[1],
            "friction_ratio": abs(m * v_g[0]) / (j_o + j_o2)}


BODIES = {"block": Block, "cylinder": Cylinder}


@pytest.mark.parametrize("kind", ["block", "cylinder"])
@pytest.mark.parametrize("tan_alpha", [0.05, 0.2, 0.5, 1.0, 1.3, 1.5, 2.0, 5.0, 100.0])
def test_formula_is_the_momentum_balance(kind, tan_alpha):
    body = BODIES[kind](2.0, tan_alpha)
    e = _impact(kind, tan_alpha, R=2.0)["e"]
    assert body.e_formula == pytest.approx(e, rel=1e-12, abs=1e-14)
    if e > 0:  # slender: the formula is used as it is
        assert body.e == body.e_formula and not body.restitution_clipped
    else:
        assert body.e == 0.0 and body.restitution_clipped


@pytest.mark.parametrize("kind, expected", [("block", math.sqrt(2.0)),
                                            ("cylinder", 4.0 / 3.0)])
def test_sign_change_of_the_balance_is_the_squat_limit(kind, expected):
    root = brentq(lambda ta: _impact(kind, ta)["e"], 0.5, 5.0, xtol=1e-14)
    assert root == pytest.approx(expected, rel=1e-12)
    assert BODIES[kind].SQUAT_TAN_ALPHA == pytest.approx(root, rel=1e-12)
    assert BODIES[kind](1.0, 0.999 * root).e > 0.0
    assert BODIES[kind](1.0, 1.001 * root).e == 0.0


@pytest.mark.parametrize("kind", ["block", "cylinder"])
@pytest.mark.parametrize("tan_alpha", [0.2, 1.0, 1.3, 1.5, 2.0, 5.0])
def test_stopping_flat_is_the_consistent_outcome_exactly_when_the_formula_is_negative(
        kind, tan_alpha):
    """Unilateral contact: impulses push (≥ 0) and no corner moves into the ground. Rocking
    on about O' (Housner) needs ω⁺ ≥ 0, else the old corner O goes down; stopping flat needs
    a pushing impulse at O. Exactly one of the two holds on each side of the limit."""
    imp = _impact(kind, tan_alpha)
    housner_ok = imp["v_old_corner_y"] >= 0.0
    flat_ok = imp["j_old"] >= 0.0 and imp["j_new"] >= 0.0
    assert housner_ok != flat_ok
    assert flat_ok == BODIES[kind](1.0, tan_alpha).restitution_clipped
    if flat_ok:  # the friction the flat stop needs, h/b, is below the μ > tan α of rocking
        assert imp["friction_ratio"] == pytest.approx(1.0 / tan_alpha, rel=1e-12)
        assert imp["friction_ratio"] < tan_alpha


@pytest.mark.parametrize("body", [Block(1.0, 2.0), Cylinder(1.0, 2.0), Block(0.3, 5.0),
                                  Cylinder(10.0, 1.5)])
def test_free_rocking_of_a_squat_body_stops_at_the_first_impact(body):
    th0 = 0.6 * body.alpha
    duration = 30.0 / body.p
    res = free_vibration(body, th0, duration=duration, model="2d")
    assert res.status is Status.OK and "came back to rest" in res.reason
    assert len(res.quasi_impacts) == 1
    t_imp, (th_imp, thd_imp) = res.quasi_impacts.t[0], res.quasi_impacts.state[0]
    # the approach has the whole energy of the release: ½κoR²θ̇² = gR(cos(α − θ0) − cos α)
    approach = body.p * math.sqrt(2.0 * (math.cos(body.alpha - th0) - math.cos(body.alpha)))
    assert th_imp == 0.0 and thd_imp == pytest.approx(-approach, rel=1e-6)
    after = res.t > t_imp
    assert np.any(res.t == t_imp) and res.t[-1] == pytest.approx(duration)
    rows = np.flatnonzero(res.t == t_imp)
    assert res.theta_dot[rows[0]] == thd_imp and np.all(res.theta_dot[rows[1:]] == 0.0)
    assert np.all(res.theta[after] == 0.0) and np.all(res.theta_dot[after] == 0.0)
    assert not np.signbit(res.theta_dot[rows[1:]]).any()  # +0, not −0
    assert res.theta_max == pytest.approx(th0)
    assert res.extras["restitution_clipped"] is True and res.extras["restitution"] == 0.0
    assert f"tan α = {body.tan_alpha:g}" in res.extras["restitution_note"]
    assert res.summary()["restitution_clipped"] is True


def test_slender_body_still_rocks_on_and_is_not_flagged():
    body = Block(1.0, 0.2)
    res = free_vibration(body, 0.5 * body.alpha, duration=30.0 / body.p, model="2d")
    assert len(res.quasi_impacts) > 5
    assert res.extras["restitution_clipped"] is False
    assert res.extras["restitution"] == pytest.approx(1 - 1.5 * math.sin(body.alpha) ** 2)
    assert "restitution_note" not in res.extras
    # the 3D models use no restitution and carry no flag
    cyl = Cylinder(1.0, 2.0)
    r3 = free_vibration(cyl, 0.5, 1e-8, duration=0.2, model="3d")
    assert "restitution_clipped" not in r3.extras


@pytest.mark.parametrize("body", [Block(1.0, 2.0), Cylinder(1.0, 2.0)])
def test_ground_motion_every_episode_ends_at_its_first_impact(body):
    """Under shaking the squat body rests after each impact and uplifts again later (the
    rest / next-uplift machinery), never bounces on the same corner."""
    dt = 0.002
    t = np.arange(0.0, 3.0 + dt / 2, dt)
    a = 1.3 * G * body.tan_alpha * np.sin(2 * np.pi * 2.0 * t) * (t < 2.0)
    res = ground_response(body, GroundMotion(a, None, dt), model="2d")
    assert res.status is Status.OK and res.uplifted
    n_imp = len(res.quasi_impacts)
    assert n_imp >= 6  # one per half cycle of the sine above the uplift level
    uplifts = np.sum(np.diff((res.theta != 0.0).astype(int)) == 1)
    assert uplifts == n_imp
    for t_imp, (_, thd) in zip(res.quasi_impacts.t, res.quasi_impacts.state, strict=True):
        rows = np.flatnonzero(res.t == t_imp)
        assert abs(thd) > 0.1 and np.all(res.theta_dot[rows[1:]] == 0.0)
        nxt = rows[-1] + 1
        if nxt < res.t.size:  # at rest until the next uplift
            assert res.theta[nxt] == 0.0 and res.theta_dot[nxt] == 0.0
    assert res.extras["restitution_clipped"] is True


def test_explicit_restitution_is_kept_and_not_flagged():
    body = Block(1.0, 2.0, restitution=0.3)
    assert body.e == 0.3 and not body.restitution_clipped
    assert body.e_formula == pytest.approx(-0.2)
    assert body.restitution_note == ""
    res = free_vibration(body, 0.5, duration=2.0, model="2d")
    assert len(res.quasi_impacts) >= 2 and res.extras["restitution_clipped"] is False
    rows = np.flatnonzero(res.t == res.quasi_impacts.t[0])
    assert res.theta_dot[rows[1]] == pytest.approx(0.3 * res.theta_dot[rows[0]], rel=1e-15)


@pytest.mark.parametrize("cls", [Block, Cylinder])
@pytest.mark.parametrize("value", [-0.2, 1.5, float("nan"), float("inf")])
def test_explicit_restitution_outside_unit_interval_raises(cls, value):
    with pytest.raises(ValueError, match=r"restitution must be within \[0, 1\], got") as err:
        cls(1.0, 2.0, restitution=value)
    assert repr(value) in str(err.value)


def _no_nan(name):
    raise ValueError(f"non-strict JSON constant {name}")


def test_cli_squat_block_does_not_bounce(tmp_path, capsys):
    out = tmp_path / "sq"
    assert main(["simulate", "--R", "1", "--tan-alpha", "2", "--mode", "2d-x", "--body",
                 "block", "--theta0", "0.5", "--duration", "5", "--out", str(out), "--json"]) == 0
    cap = capsys.readouterr()
    printed = json.loads(cap.out, parse_constant=_no_nan)  # stdout stays one JSON document
    summary = json.loads((out / "summary.json").read_text(), parse_constant=_no_nan)
    assert printed == summary
    assert summary["restitution_clipped"] is True and summary["restitution"] == 0.0
    assert summary["n_impacts"] == 1 and summary["status"] == "ok"
    note = ("restitution formula gives e = −0.20 for tan α = 2 (squat body, tan α > 1.41): "
            "impacts end the rocking (e = 0)")
    assert summary["restitution_note"] == note
    assert cap.err.strip().splitlines() == [f"rocking simulate: note: {note}"]
    hist = np.loadtxt(out / "history.csv", delimiter=",", skiprows=1)
    t, th, thd = hist.T[:3]  # then the monitor columns N, mu_req
    i_imp = int(np.flatnonzero(th == 0.0)[0])
    assert thd[i_imp] == pytest.approx(-2.3457, abs=1e-4)  # the approach, as before
    assert np.all(th[i_imp:] == 0.0) and np.all(thd[i_imp + 1:] == 0.0)
    assert t[-1] == 5.0


def test_cli_slender_body_has_no_note(tmp_path, capsys):
    assert main(["simulate", "--R", "1", "--tan-alpha", "0.2", "--mode", "2d-x", "--body",
                 "block", "--theta0", "0.1", "--duration", "1", "--out",
                 str(tmp_path / "s"), "--json"]) == 0
    cap = capsys.readouterr()
    assert cap.err == ""
    assert json.loads(cap.out)["restitution_clipped"] is False


@pytest.mark.parametrize("omega_n, zeta", [(2000.0, 5.0), (2000.0, 50.0), (200.0, 5.0)])
def test_damped_model_dissipates_a_squat_cylinders_rocking_at_the_first_quasi_impact(
        omega_n, zeta):
    """The damped 3D model has no restitution parameter. For tan α = 2 a burst of
    quasi-impacts right after the first one leaves the rocking energy at the rest level
    within 20/ωn (the e = 0 of the 2D model; measured √(E/E0) ≈ 0.002–0.004, the resting
    tilt's ~1e-6 rad); for tan α = 1 its apparent restitution is Eq (31)'s 0.2258."""
    for tan_alpha in (2.0, 1.0):
        cyl = Cylinder(1.0, tan_alpha)
        a = cyl.alpha
        res = free_vibration(cyl, 0.5 * a, 1e-8, duration=1.0, model="3d-damped",
                             omega_n=omega_n, zeta=zeta)
        assert res.status is Status.OK and res.extras["n_tension"] == 0
        e_rock = (0.5 * cyl.R**2 * (cyl.kappa_o * res.theta_dot**2
                                    + cyl.spin_inertia(res.theta) * res.phi_dot**2)
                  + G * cyl.R * (np.cos(a - res.theta) - np.cos(a)))
        t1 = res.quasi_impacts.t[0]
        i = np.searchsorted(res.t, t1 + 20.0 / omega_n)
        apparent = math.sqrt(e_rock[i] / e_rock[0])
        later_peak = np.max(res.theta[res.t > t1])
        if cyl.restitution_clipped:
            assert cyl.e_formula == pytest.approx(-0.263158, abs=1e-6)
            assert apparent < 0.01 and later_peak < 1e-3 * a
        else:
            assert apparent == pytest.approx(cyl.e, abs=2e-3)
            assert later_peak > 0.01 * a
