"""Symmetries of the isotropic cylinder, checked on a real record.

The cylinder is axisymmetric, so rotating the ground motion about the vertical axis (or
reflecting it) must leave the tilt history unchanged: an independent check of the 3D kernel's
coupling between φ and the two ground components, and of the uplift direction of Eq (26).
"""

import numpy as np
import pytest

import rocking
from rocking.motions.catalogue import load_record
from rocking.motions.principal import rotate


@pytest.fixture(scope="module")
def el_centro():
    m = load_record("el-centro-1940")
    n = int(12.0 / m.dt)  # the first 12 s hold the strong motion; enough for the check
    return rocking.GroundMotion(m.ax[:n], m.ay[:n], m.dt, m.name)


@pytest.mark.parametrize("model", ["3d", "3d-damped"])
@pytest.mark.parametrize("angle", [22.33, -70.46, 135.0])
def test_rotated_record_gives_same_tilt(el_centro, model, angle):
    cyl = rocking.Cylinder(2.0, 0.2)
    ref = rocking.ground_response(cyl, el_centro, model=model, scale=1.6, rtol=1e-10)
    rot = rocking.ground_response(cyl, rotate(el_centro, angle), model=model, scale=1.6,
                                  rtol=1e-10)
    assert ref.uplifted and ref.theta_max > 0.2 * cyl.alpha
    assert rot.theta_max == pytest.approx(ref.theta_max, rel=1e-6)
    # Rotating the axes by +angle turns every direction, the contact point's included, by
    # -angle in the new axes: φ differs by -angle at the peak.
    i, j = np.argmax(ref.theta), np.argmax(rot.theta)
    assert rot.t[j] == pytest.approx(ref.t[i], abs=1e-6)
    dphi = np.angle(np.exp(1j * (rot.phi[j] - ref.phi[i] + np.deg2rad(angle))))
    assert dphi == pytest.approx(0.0, abs=1e-5)


def test_reflected_record_mirrors_spin(el_centro):
    cyl = rocking.Cylinder(2.0, 0.2)
    ref = rocking.ground_response(cyl, el_centro, model="3d", scale=1.6, rtol=1e-10)
    mir = rocking.GroundMotion(el_centro.ax, -el_centro.ay, el_centro.dt)
    out = rocking.ground_response(cyl, mir, model="3d", scale=1.6, rtol=1e-10)
    assert out.theta_max == pytest.approx(ref.theta_max, rel=1e-6)
    k = min(ref.t.size, out.t.size) // 2
    # Compare at the reference's times; where an episode ends (back at rest) a time appears
    # twice, once with the last rocking state and once at rest, and interpolation could pick
    # either: those instants are compared by the episode ends themselves.
    ends = np.flatnonzero(np.diff(ref.t[:k]) == 0.0)
    np.testing.assert_array_equal(ends, np.flatnonzero(np.diff(out.t[:k]) == 0.0))
    keep = np.ones(k, dtype=bool)
    keep[ends] = keep[ends + 1] = False
    np.testing.assert_allclose(np.interp(ref.t[:k][keep], out.t, out.phi_dot),
                               -ref.phi_dot[:k][keep],
                               rtol=1e-4, atol=1e-6 * np.abs(ref.phi_dot).max())
