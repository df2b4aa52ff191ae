"""The micro-uplift rest criterion of the undamped 3D model against the exact treatment.

Below a rim lift of REST_LIFT an undamped 3D rocking episode may end (docs/equations.md,
"Micro-uplift: when a rocking episode ends"); ``rest_tilt=0`` keeps the exact treatment. The
checks: the default is the stated rim lift; an analysis whose only motion is micro-uplift has
the exact peak at a fraction of the exact cost; an analysis that rocks keeps the exact answer;
an episode ends only with less energy than the rest tilt's; bad values name the field.
"""

import math

import numpy as np
import pytest

import rocking
from rocking.constants import G
from rocking.dynamics import analysis, bodies, codes, models
from rocking.dynamics.contact import Contact


@pytest.fixture(scope="module")
def el_centro():
    from rocking.motions.catalogue import load_record

    return load_record("el-centro-1940")


@pytest.mark.parametrize("R,tan_alpha", [(0.5, 0.2), (4.0, 0.2), (10.0, 0.3)])
def test_default_rest_tilt_is_the_stated_rim_lift(R, tan_alpha):
    body = rocking.Cylinder(R, tan_alpha)
    theta = analysis.default_rest_tilt("3d", body)
    # rim of the base (diameter 2R sin α) lifted by the chord of θ
    lift = 2.0 * body.R * math.sin(body.alpha) * math.sin(theta)
    assert lift == pytest.approx(models.REST_LIFT, rel=1e-9)
    assert theta < 1e-3 * body.alpha  # far below the smallest limit state (0.1 α)
    assert analysis.default_rest_tilt("3d-damped", body) == models.THETA_REST_DAMPED
    assert analysis.default_rest_tilt("2d", body) == models.THETA_REST_2D


def test_micro_uplift_keeps_the_exact_peak_at_a_fraction_of_the_cost(el_centro):
    """R = 4 m, I = 1.01: the cylinder lifts by < 1e-6 rad; the exact treatment follows the
    chatter through ~1.5 M steps."""
    body = rocking.Cylinder(4.0, 0.2)
    exact = analysis.ground_response(body, el_centro, pga_ratio=1.01, history=False,
                                     rest_tilt=0.0)
    rest = analysis.ground_response(body, el_centro, pga_ratio=1.01, history=False)
    assert exact.theta_max < analysis.default_rest_tilt("3d", body)
    assert rest.theta_max == exact.theta_max  # the first episode's peak is the same
    assert exact.n_steps > 100_000
    assert rest.n_steps < exact.n_steps / 100


@pytest.mark.parametrize("intensity", [1.1, 1.5, 2.0])
def test_rocking_answers_do_not_move(el_centro, intensity):
    body = rocking.Cylinder(4.0, 0.2)
    exact = analysis.ground_response(body, el_centro, pga_ratio=intensity, history=False,
                                     rest_tilt=0.0)
    rest = analysis.ground_response(body, el_centro, pga_ratio=intensity, history=False)
    assert exact.theta_max > 0.1 * body.alpha
    assert rest.theta_max == pytest.approx(exact.theta_max, rel=1e-6)
    assert rest.status == exact.status


def test_an_episode_ends_only_below_the_rest_energy(el_centro):
    """The state where the kernel reports AT_REST has less energy than lifting the body to
    the rest tilt takes (energy written here from the equations, not the model's hook)."""
    body = rocking.Cylinder(4.0, 0.2)
    theta_rest = analysis.default_rest_tilt("3d", body)
    runner = analysis._Runner("3d", body, 1e-8, True, Contact(), theta_rest)
    a = el_centro.scaled(1.01 * G * body.tan_alpha / el_centro.pga)
    up = analysis.next_uplift(a.ax, a.ay, a.dt, G * body.tan_alpha,
                          np.flatnonzero(np.hypot(a.ax, a.ay) > G * body.tan_alpha))
    k, tau, ax, ay = up
    y0, side = analysis._start_state("3d", math.atan2(-ay, -ax))
    out = runner(a.ax, a.ay, a.dt, k, tau, 0.0, y0, a.duration, -1.0, side)
    assert int(out[0]) == codes.AT_REST
    theta, _, theta_dot, phi_dot = out[2][-1][:4]  # the row ends with the monitors (N, mu)
    mu = float(bodies.mu(theta, body.alpha))
    kinetic = 0.5 * body.R**2 * (body.kappa_o * theta_dot**2 + mu * phi_dot**2)
    potential = G * body.R * (math.cos(body.alpha - theta) - math.cos(body.alpha))
    e_rest = G * body.R * (math.cos(body.alpha - theta_rest) - math.cos(body.alpha))
    assert kinetic + potential < e_rest
    assert models.rest_criterion(body, theta_rest)[1] == pytest.approx(e_rest, rel=1e-9)


@pytest.mark.parametrize("value", [-1e-6, math.nan, math.inf, 0.05])
def test_bad_rest_tilt_names_the_field(el_centro, value):
    with pytest.raises(ValueError, match="rest_tilt"):
        analysis.ground_response(rocking.Cylinder(4.0, 0.2), el_centro, pga_ratio=1.2,
                                 rest_tilt=value)


def test_accuracy_carries_the_exact_treatment():
    from rocking.spectra.accuracy import Accuracy

    acc = Accuracy.of({"preset": "default", "rest_tilt": 0})
    assert acc.rest_tilt == 0.0 and acc.to_dict()["rest_tilt"] == 0.0
    assert Accuracy.of("default").rest_tilt is None
    for bad in (-1, 2e-4, float("nan")):
        with pytest.raises(ValueError, match="rest_tilt"):
            Accuracy.of({"preset": "default", "rest_tilt": bad})
    # every accepted value is accepted by the engine too, for tan α above tan(0.01) ≈ 0.0100003
    body = rocking.Cylinder(1.0, 0.0101)
    assert analysis._check_rest_tilt(1e-4, "3d", body) == 1e-4
