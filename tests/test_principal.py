"""Principal axes and rotation: invariants, a known angle, and the El Centro record."""

from __future__ import annotations

import math
import os
import subprocess
import sys

import numpy as np
import pytest

from rocking.motions.catalogue import load_record
from rocking.motions.motion import GroundMotion
from rocking.motions.principal import (
    arias_tensor,
    correlation,
    principal_angle,
    rotate,
    rotate_components,
    to_principal_axes,
)

PAPER_ANGLE_DEG = 22.33


@pytest.fixture(scope="module")
def el_centro() -> GroundMotion:
    return load_record("el-centro-1940")


def _independent_pair(angle_deg: float, seed: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """Two exactly uncorrelated signals (major twice the minor) turned by ``-angle_deg``."""
    rng = np.random.default_rng(seed)
    u = rng.standard_normal((2, 4000))
    # Gram-Schmidt makes the raw cross product exactly zero, so the true angle is exact.
    u[1] -= (u[0] @ u[1]) / (u[0] @ u[0]) * u[0]
    major, minor = 2.0 * u[0] / np.linalg.norm(u[0]), u[1] / np.linalg.norm(u[1])
    th = math.radians(angle_deg)
    # Inverse rotation: the recording axes see the principal pair turned by -angle.
    a1 = math.cos(th) * major - math.sin(th) * minor
    a2 = math.sin(th) * major + math.cos(th) * minor
    return a1, a2


@pytest.mark.parametrize("angle", [-80.0, -22.33, 0.0, 10.0, 44.0, 75.0])
def test_known_angle_is_recovered(angle: float) -> None:
    a1, a2 = _independent_pair(angle)
    assert principal_angle(a1, a2) == pytest.approx(angle, abs=1e-9)


def test_rotation_invariants(el_centro: GroundMotion) -> None:
    rotated, applied = to_principal_axes(el_centro)
    # Uncorrelated to machine precision, major first.
    assert abs(correlation(rotated.ax, rotated.ay)) < 1e-12
    s_before = arias_tensor(el_centro.ax, el_centro.ay, el_centro.dt)
    s_after = arias_tensor(rotated.ax, rotated.ay, rotated.dt)
    assert abs(s_after[0, 1]) < 1e-12 * np.trace(s_after)
    eig = np.linalg.eigvalsh(s_before)
    assert s_after[0, 0] == pytest.approx(eig[1], rel=1e-12)
    assert s_after[1, 1] == pytest.approx(eig[0], rel=1e-12)
    # The trace (total Arias intensity) and the horizontal magnitude sample by sample.
    assert np.trace(s_after) == pytest.approx(np.trace(s_before), rel=1e-13)
    np.testing.assert_allclose(
        np.hypot(rotated.ax, rotated.ay), np.hypot(el_centro.ax, el_centro.ay),
        rtol=1e-13, atol=1e-15,
    )
    assert rotated.pga == pytest.approx(el_centro.pga, rel=1e-13)
    assert rotated.metadata["rotation_deg"] == applied


def test_el_centro_principal_angle_vs_paper(el_centro: GroundMotion) -> None:
    rotated, applied = to_principal_axes(el_centro)
    meta = rotated.metadata
    offset = meta["principal_offset_deg"]
    print(
        f"\nEl Centro RSN6 principal angle: {applied:.4f} deg from x=E-W(270) toward y=N-S(180);"
        f" major axis {offset:.4f} deg from the N-S axis, azimuth {meta['x_azimuth']:.2f};"
        f" paper 22.33 deg; difference {PAPER_ANGLE_DEG - abs(offset):.2f} deg"
    )
    # Regression numbers (not physics): x = E-W, y = N-S, major axis near N-S.
    assert applied == pytest.approx(-70.460, abs=1e-3)
    assert meta["principal_reference_axis"] == "y"
    assert offset == pytest.approx(19.540, abs=1e-3)
    assert meta["x_azimuth"] == pytest.approx(340.460, abs=1e-3)
    # Check the reported azimuth against a direct projection on north/east axes. With
    # a_270 = -a_east and a_180 = -a_north, the component toward azimuth az is
    # cos(az) a_north + sin(az) a_east.
    az = math.radians(meta["x_azimuth"])
    north, east = -el_centro.ay, -el_centro.ax
    np.testing.assert_allclose(rotated.ax, math.cos(az) * north + math.sin(az) * east,
                               atol=1e-12)
    # Ordering: the rotated x carries the larger Arias intensity.
    assert rotated.ax @ rotated.ax > rotated.ay @ rotated.ay


def test_forced_angle_takes_the_computed_sense(el_centro: GroundMotion) -> None:
    auto, _ = to_principal_axes(el_centro)
    for forced in (PAPER_ANGLE_DEG, -PAPER_ANGLE_DEG):
        rotated, applied = to_principal_axes(el_centro, forced)
        # Same axis and sense as the computed one, 22.33 deg from N-S instead of 19.54.
        assert applied == pytest.approx(-90.0 + PAPER_ANGLE_DEG, abs=1e-12)
        assert rotated.metadata["forced_angle_deg"] == forced
        # A 2.8 deg error leaves a small correlation, far below the record's own.
        rho = correlation(rotated.ax, rotated.ay)
        assert 1e-3 < abs(rho) < 0.03 < abs(correlation(el_centro.ax, el_centro.ay))
    # The wrong sense makes the components more correlated than the record: why the sign
    # must follow the computed angle.
    wrong = rotate(el_centro, -90.0 - PAPER_ANGLE_DEG)
    assert abs(correlation(wrong.ax, wrong.ay)) > abs(correlation(el_centro.ax, el_centro.ay))
    assert auto.metadata["forced_angle_deg"] is None
    with pytest.raises(ValueError, match="angle"):
        to_principal_axes(el_centro, 60.0)
    with pytest.raises(ValueError, match="angle"):
        to_principal_axes(el_centro, float("nan"))


def test_rotate_composes_and_inverts(el_centro: GroundMotion) -> None:
    back = rotate(rotate(el_centro, 33.0), -33.0)
    np.testing.assert_allclose(back.ax, el_centro.ax, atol=1e-15)
    np.testing.assert_allclose(back.ay, el_centro.ay, atol=1e-15)
    twice = rotate(rotate(el_centro, 20.0), 13.0)
    once = rotate(el_centro, 33.0)
    np.testing.assert_allclose(twice.ax, once.ax, atol=1e-14)
    assert [p["step"] for p in twice.metadata["processing"]][-2:] == ["rotation", "rotation"]


def test_bad_input() -> None:
    with pytest.raises(ValueError, match="equal length"):
        principal_angle([1.0, 2.0], [1.0])
    with pytest.raises(ValueError, match="non-finite"):
        principal_angle([1.0, np.nan], [1.0, 2.0])
    with pytest.raises(ValueError, match="zero"):
        principal_angle([0.0, 0.0], [0.0, 0.0])
    with pytest.raises(ValueError, match="angle_deg"):
        rotate_components([1.0, 2.0], [1.0, 2.0], np.inf)


def test_the_angle_is_exactly_rounded_and_blind_to_trailing_zeros(el_centro) -> None:
    """The sums σ_ij are exactly rounded (math.fsum), so the angle of a pair does not depend
    on how many zeros follow it: a record padded to its vertical file (El Centro: 6 more
    samples) keeps the bits of its angle, whatever BLAS kernel the machine runs."""
    from fractions import Fraction

    x, y = el_centro.ax, el_centro.ay
    exact = [sum(Fraction(a) * Fraction(b) for a, b in zip(p, q, strict=True))
             for p, q in ((x, x), (y, y), (x, y))]
    s11, s22, s12 = (float(v) for v in exact)
    want = math.degrees(0.5 * math.atan2(2.0 * s12, s11 - s22))
    assert principal_angle(x, y) == want
    for n in (1, 6, 37):
        pad = np.zeros(n)
        assert principal_angle(np.r_[x, pad], np.r_[y, pad]) == want


def _blas_kernels() -> list[str]:
    """OpenBLAS kernels this CPU can run (forcing one it lacks would stop the process)."""
    flags = open("/proc/cpuinfo").read().split() if os.path.exists("/proc/cpuinfo") else []
    return ["Prescott"] + (["Haswell"] if "avx2" in flags and "fma" in flags else []) + (
        ["SkylakeX"] if "avx512f" in flags else [])


def test_a_record_with_and_without_its_vertical_has_the_same_horizontals() -> None:
    """One machine, one promise: the horizontals of a record processed beside its vertical
    component are those processed alone, to the bit, under every OpenBLAS kernel of this
    CPU (before the sums were exactly rounded, AVX2's kernel gave the padded pair another
    last bit of the angle, 5e-10 relative in samples), and the kernel does not change the
    record's digest."""
    code = ("from rocking.motions.source import load_motion, process_motion\n"
            "import numpy as np\n"
            "v, h = (process_motion(load_motion('el-centro-1940', vertical=z), rotation='auto', "
            "highpass='oscillator') for z in (True, False))\n"
            "n = h.npts\n"
            "assert v.npts > n\n"
            "print(np.array_equal(v.ax[:n], h.ax) and np.array_equal(v.ay[:n], h.ay), "
            "h.samples_sha256)\n")
    seen = {}
    for kernel in _blas_kernels():
        env = {**os.environ, "OPENBLAS_CORETYPE": kernel}
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                             text=True, check=True).stdout.split()
        assert out[0] == "True", kernel
        seen[kernel] = out[1]
    assert len(set(seen.values())) == 1, seen
