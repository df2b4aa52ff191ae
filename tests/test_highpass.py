"""High-pass filters: closed forms, scipy's lsim, residuals and energy loss."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate, signal

from rocking.motions.catalogue import load_record
from rocking.motions.highpass import (
    brune_corner,
    butterworth_acausal,
    highpass_motion,
    oscillator,
    oscillator_pad,
    oscillator_transfer,
    residuals,
)
from rocking.motions.motion import GroundMotion
from rocking.motions.principal import to_principal_axes


@pytest.fixture(scope="module")
def el_centro() -> GroundMotion:
    return load_record("el-centro-1940")


def _oscillator_lsim(u: np.ndarray, dt: float, fc: float):
    """The filter as a continuous state space solved by scipy (first-order hold)."""
    wc = 2.0 * math.pi * fc
    sys = signal.StateSpace(
        [[0.0, 1.0], [-wc * wc, -2.0 * wc]], [[0.0], [1.0]], [[-wc * wc, -2.0 * wc]], [[1.0]]
    )
    _, y, x = signal.lsim(sys, u, np.arange(u.size) * dt, interp=True)
    return y, x


@pytest.mark.parametrize(
    ("mw", "stress", "expected"),
    # Spec section 6 (beta = 3.5 km/s), three decimals.
    [(6.95, 30, 0.080), (6.95, 50, 0.095), (6.95, 100, 0.119),
     (6.9, 30, 0.085), (6.9, 50, 0.100), (6.9, 100, 0.126)],
)
def test_brune_corner_published_values(mw: float, stress: float, expected: float) -> None:
    assert brune_corner(mw, stress, 3.5) == pytest.approx(expected, abs=6e-4)


def test_brune_corner_scaling_and_input() -> None:
    # f_c ∝ β Δσ^(1/3) M0^(-1/3) and M0 ∝ 10^(1.5 Mw): exact ratios.
    assert brune_corner(6.5, 400) / brune_corner(6.5, 50) == pytest.approx(2.0, rel=1e-12)
    assert brune_corner(7.0, 50) / brune_corner(6.0, 50) == pytest.approx(10 ** -0.5, rel=1e-12)
    with pytest.raises(ValueError, match="stress_bar"):
        brune_corner(6.9, -1.0)
    with pytest.raises(ValueError, match="mw"):
        brune_corner(float("nan"))


def test_oscillator_matches_scipy_lsim(el_centro: GroundMotion) -> None:
    fc = brune_corner(6.95)
    out = oscillator(el_centro.ax, el_centro.dt, fc)
    u = np.concatenate([el_centro.ax, np.zeros(out.size - el_centro.npts)])
    ref, states = _oscillator_lsim(u, el_centro.dt, fc)
    # The record starts at a non-zero value, so this also checks the start from rest.
    assert el_centro.ax[0] != 0.0
    np.testing.assert_allclose(out, ref, rtol=0, atol=1e-10 * np.max(np.abs(ref)))
    # Padding 25/ω_c: the exact filter states (velocity, displacement of the output) vanish.
    assert out.size - el_centro.npts == round(oscillator_pad(fc) / el_centro.dt)
    assert abs(states[-1, 1]) < 1e-10 * np.max(np.abs(states[:, 1]))
    assert abs(states[-1, 0]) < 1e-10 * np.max(np.abs(states[:, 0]))
    # Batched rows give the same result as single rows.
    both = oscillator(np.vstack([el_centro.ax, el_centro.ay]), el_centro.dt, fc)
    np.testing.assert_array_equal(both[0], out)


def _modulated_noise(dt: float = 0.01, n: int = 4000, seed: int = 7) -> np.ndarray:
    """Noise under a gamma-like envelope that starts at 0 and is still 4 % of its peak at the
    end, like a simulated record before padding."""
    t = np.arange(n) * dt
    q = t**2 * np.exp(-t / 10.0)
    return q * np.random.default_rng(seed).standard_normal(n)


@pytest.mark.parametrize("fc", [0.2, 0.095])
def test_oscillator_residuals_vanish(fc: float) -> None:
    x = _modulated_noise()
    before = residuals(x, 0.01)
    assert before.v_rel > 1e-3  # the raw noise drifts: the test can fail
    after = residuals(oscillator(x, 0.01, fc), 0.01)
    assert after.v_rel < 1e-8
    assert after.d_rel < 1e-8


def test_short_padding_leaves_residuals() -> None:
    after = residuals(oscillator(_modulated_noise(), 0.01, 0.2, pad=5.0), 0.01)
    assert max(after.v_rel, after.d_rel) > 1e-6


def test_record_residuals_follow_trapezoid_error(el_centro: GroundMotion) -> None:
    # The exact output velocity ends at 0 (lsim test above). The trapezoid rule adds
    # (Euler-Maclaurin) v_err = 2 ω_c dt² a(0)/12 because the record starts at a(0) != 0,
    # and the displacement picks up v_err over the whole padded duration T.
    fc, dt = brune_corner(6.95), el_centro.dt
    out = oscillator(el_centro.ax, dt, fc)
    res = residuals(out, dt)
    v_err = 2.0 * (2.0 * math.pi * fc) * dt**2 * el_centro.ax[0] / 12.0
    assert res.v_end == pytest.approx(v_err, rel=0.02)
    assert res.d_end == pytest.approx(v_err * (out.size - 1) * dt, rel=0.02)
    assert res.v_rel < 1e-6 and res.d_rel < 1e-4


@pytest.mark.parametrize("ratio", [0.1, 1.0, 10.0])
def test_oscillator_transfer_function(ratio: float) -> None:
    fc, dt = 0.2, 0.001
    f = ratio * fc
    t = np.arange(int(round((20.0 + 2.0 / f) / dt))) * dt
    y = oscillator(np.sin(2 * math.pi * f * t), dt, fc, pad=0.0)
    # Steady state after 20 s (transient (1 + ω_c t) e^(-ω_c t) < 1e-9): fit sin and cos.
    keep = t > 20.0
    basis = np.column_stack([np.sin(2 * math.pi * f * t[keep]), np.cos(2 * math.pi * f * t[keep])])
    (c_sin, c_cos), *_ = np.linalg.lstsq(basis, y[keep], rcond=None)
    h = oscillator_transfer(f, fc)
    # sin -> Im(H e^{iωt}) = Re(H) sin + Im(H) cos.
    assert complex(c_sin, c_cos) == pytest.approx(complex(h), rel=1e-4)
    assert abs(h) == pytest.approx(f**2 / (f**2 + fc**2), rel=1e-12)


def test_stationary_energy_loss_matches_quadrature() -> None:
    # Stationary RDK-like process (f = 4.78 Hz, ζ = 0.176): the fraction of Arias intensity
    # removed is 1 - ∫|H_f|²|H_hp|² / ∫|H_f|², by quadrature.
    wf, zeta, fc, dt = 2 * math.pi * 4.78, 0.176, 0.2, 0.01
    wc = 2 * math.pi * fc

    def spec(w):
        return wf**4 / ((wf**2 - w**2) ** 2 + 4 * zeta**2 * wf**2 * w**2)

    lost = integrate.quad(lambda w: spec(w) * (1 - (w**2 / (w**2 + wc**2)) ** 2), 0, np.inf,
                          limit=400)[0]
    expected = lost / integrate.quad(spec, 0, np.inf, limit=400)[0]
    assert 0.01 < expected < 0.03  # the 1-3 % of the spec
    b, a, _ = signal.cont2discrete(([wf * wf], [1.0, 2 * zeta * wf, wf * wf]), dt, method="zoh")
    x = signal.lfilter(b[0], a, np.random.default_rng(11).standard_normal(200_000))
    y = oscillator(x, dt, fc)
    # Six seeds measured: sd 0.0004 of the loss; 4 sd tolerance.
    assert 1.0 - (y @ y) / (x @ x) == pytest.approx(expected, abs=0.0016)


def test_el_centro_arias_loss_at_brune_corner(el_centro: GroundMotion) -> None:
    principal, _ = to_principal_axes(el_centro)
    filtered = highpass_motion(principal, "oscillator", brune_corner(6.95))
    loss_x = 1.0 - (filtered.ax @ filtered.ax) / (principal.ax @ principal.ax)
    loss_y = 1.0 - (filtered.ay @ filtered.ay) / (principal.ay @ principal.ay)
    print(f"\nEl Centro Arias loss at f_c = {brune_corner(6.95):.4f} Hz: "
          f"major {100 * loss_x:.2f} %, minor {100 * loss_y:.2f} %")
    assert 0.01 < loss_x < 0.03 and 0.01 < loss_y < 0.03
    step = filtered.metadata["processing"][-1]
    assert step["step"] == "highpass" and step["kind"] == "oscillator"
    assert filtered.npts == principal.npts + step["pad_end"]


def test_butterworth_zero_phase_and_residuals(el_centro: GroundMotion) -> None:
    dt, fc = el_centro.dt, 0.2
    out, front = butterworth_acausal(el_centro.ax, dt, fc, order=4)
    res = residuals(out, dt)
    # Spec tolerance |d_end| < 1e-3 PGD for the acausal filter.
    assert res.d_rel < 1e-3 and res.v_rel < 1e-4
    assert front == round(0.5 * 3 * 4 / fc / dt)


@pytest.mark.parametrize("ratio", [1.0, 2.0, 10.0])
def test_butterworth_zero_phase_gain(ratio: float) -> None:
    # Forward-backward: |H|² = 1 / (1 + (f_c/f)^(2N)) and no phase shift. A 400 s sine,
    # fitted on its middle 100 s (far from the truncation transients).
    dt, fc, order = 0.01, 0.2, 4
    f = ratio * fc
    t = np.arange(40_000) * dt
    y, k = butterworth_acausal(np.sin(2 * math.pi * f * t), dt, fc, order)
    keep = (t > 150.0) & (t < 250.0)
    basis = np.column_stack([np.sin(2 * math.pi * f * t[keep]), np.cos(2 * math.pi * f * t[keep])])
    (c_sin, c_cos), *_ = np.linalg.lstsq(basis, y[k : k + t.size][keep], rcond=None)
    # scipy designs by the bilinear transform, which maps f to tan(π f dt) (prewarped at f_c).
    warped = math.tan(math.pi * fc * dt) / math.tan(math.pi * f * dt)
    assert c_sin == pytest.approx(1.0 / (1.0 + warped ** (2 * order)), rel=1e-7)
    assert abs(c_cos) < 1e-6


def test_bad_input() -> None:
    with pytest.raises(ValueError, match="fc_hz"):
        oscillator(np.ones(10), 0.01, 0.0)
    with pytest.raises(ValueError, match="dt"):
        oscillator(np.ones(10), -0.01, 0.2)
    with pytest.raises(ValueError, match="non-finite"):
        oscillator(np.array([0.0, np.nan, 1.0]), 0.01, 0.2)
    with pytest.raises(ValueError, match="pad"):
        oscillator(np.ones(10), 0.01, 0.2, pad=-1.0)
    with pytest.raises(ValueError, match="Nyquist"):
        butterworth_acausal(np.ones(10), 0.01, 60.0)
    with pytest.raises(ValueError, match="order"):
        butterworth_acausal(np.ones(10), 0.01, 0.2, order=0)
    motion = GroundMotion(np.ones(10), np.ones(10), 0.01)
    with pytest.raises(ValueError, match="kind"):
        highpass_motion(motion, "chebyshev", 0.2)
    with pytest.raises(ValueError, match="fc_hz"):
        highpass_motion(motion, "oscillator")


@pytest.mark.parametrize("kind", ["oscillator", "butterworth"])
def test_corner_at_or_above_nyquist_is_refused_naming_the_value(kind: str) -> None:
    """dt = 0.01 s: Nyquist 50 Hz. A corner there or above cannot high-pass anything the
    samples hold; both kinds refuse it with the field and its value, before filtering."""
    motion = GroundMotion(np.sin(np.arange(200) * 0.3), np.cos(np.arange(200) * 0.2), 0.01)
    for fc in (50.0, 80.0):
        with pytest.raises(ValueError, match=rf"fc_hz={fc!r} must be below the Nyquist "
                                             r"frequency 50 Hz \(time step 0.01 s\)"):
            highpass_motion(motion, kind, fc)
    # just below Nyquist still filters (the check is not a blanket refusal)
    out = highpass_motion(motion, kind, 49.0)
    assert np.all(np.isfinite(out.ax)) and out.npts >= motion.npts
