"""Time-varying RDK filter and its normalized impulse-response band (spec §2.3, §2.4, §7.2)."""

import math

import numpy as np
import pytest
from scipy import signal

from rocking.motions.stochastic.filter import (
    filter_poles,
    impulse_response,
    normalized_irf,
    omega_f,
    unit_psd,
)


def _dense_reference(omega, zeta, dt):
    """S[k, i] straight from the definition, with numpy broadcasting (no band, no recurrence)."""
    n = omega.size
    k = np.arange(n)[:, None]
    i = np.arange(n)[None, :]
    c = math.sqrt(1 - zeta**2)
    tau = (k - i) * dt
    w = np.broadcast_to(omega[None, :], (n, n))
    h = w / c * np.exp(-zeta * w * np.abs(tau)) * np.sin(w * c * tau)
    h[k < i] = 0.0
    norm = np.sqrt((h**2).sum(axis=1))
    norm[0] = 1.0  # row 0 is 0/0: defined as zero
    return h / norm[:, None]


def test_impulse_response_is_the_pseudo_acceleration_of_the_oscillator():
    # Independent: scipy's impulse response of ω²/(s² + 2ζωs + ω²).
    w, z = 2 * math.pi * 3.0, 0.15
    t = np.linspace(0, 3, 3001)
    _, ref = signal.impulse(([w**2], [1, 2 * z * w, w**2]), T=t)
    np.testing.assert_allclose(impulse_response(t, w, z), ref, atol=1e-6 * np.abs(ref).max())
    assert impulse_response(-0.1, w, z) == 0.0


@pytest.mark.parametrize("zeta", [0.05, 0.3, 0.9])
def test_band_matches_the_dense_definition_and_rows_have_unit_norm(zeta):
    dt = 0.01
    t = np.arange(400) * dt
    om = omega_f(t, 5.0, -2.0, 1.0, hold=(0.5, 3.0))
    s = normalized_irf(om, zeta, dt, band_tol=1e-300)  # no truncation
    dense = s.to_dense()
    np.testing.assert_allclose(dense, _dense_reference(om, zeta, dt), rtol=0, atol=1e-12)
    rows = np.sum(dense**2, axis=1)
    assert rows[0] == 0.0
    np.testing.assert_allclose(rows[1:], 1.0, rtol=0, atol=1e-12)
    assert np.all(np.triu(dense, 1) == 0.0)


def test_truncated_band_is_close_to_the_full_matrix_and_still_normalized():
    dt = 0.01
    om = np.full(1500, 2 * math.pi * 4.0)
    full = normalized_irf(om, 0.2, dt, band_tol=1e-300)
    cut = normalized_irf(om, 0.2, dt, band_tol=1e-8)
    # τ_max = ln(1e8)/(ζω) = 3.66 s → 368 lags instead of all 1500.
    assert cut.width == math.ceil(math.log(1e8) / (0.2 * om[0]) / dt) + 1
    assert cut.width < full.width
    d = (full.to_sparse() - cut.to_sparse()).toarray()
    assert np.abs(d).max() < 1e-8 * np.abs(cut.diagonals).max()
    np.testing.assert_allclose(np.sum(cut.to_dense()[1:] ** 2, axis=1), 1.0, atol=1e-12)


def test_apply_is_the_matrix_product():
    dt = 0.02
    om = omega_f(np.arange(300) * dt, 3.0, 0.5, 2.0)
    s = normalized_irf(om, 0.25, dt)
    u = np.random.default_rng(0).standard_normal((300, 4))
    np.testing.assert_allclose(s.apply(u), s.to_dense() @ u, atol=1e-12)


def test_omega_is_linear_held_and_floored():
    t = np.array([0.0, 1.0, 5.0, 10.0, 30.0, 50.0])
    w = omega_f(t, 4.0, -0.2, 5.0, hold=(1.0, 30.0), floor_hz=0.3)
    f = w / (2 * math.pi)
    # Held at t=1 before it, floored at 0.3 Hz where 4 − 0.2 (t − 5) drops below it (t > 23.5).
    np.testing.assert_allclose(f, [4.8, 4.8, 4.0, 3.0, 0.3, 0.3], rtol=1e-14)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: omega_f([0.0, 1.0], -1.0, 0.0, 1.0), "f_mid"),
        (lambda: omega_f([0.0, 1.0], 1.0, float("nan"), 1.0), "f_slope"),
        (lambda: omega_f([0.0, 1.0], 1.0, 0.0, 1.0, hold=(2.0, 1.0)), "hold"),
        (lambda: omega_f([0.0, 100.0], 1.0, -1.0, 1.0, floor_hz=0.0), "floor_hz"),
        (lambda: normalized_irf(np.ones(10), 1.0, 0.01), "zeta_f"),
        (lambda: normalized_irf(np.ones(10), 0.0, 0.01), "zeta_f"),
        (lambda: normalized_irf(np.ones(10), 0.1, -0.01), "dt"),
        (lambda: normalized_irf(-np.ones(10), 0.1, 0.01), "omega"),
        (lambda: normalized_irf(np.ones(10), 0.1, 0.01, band_tol=2.0), "band_tol"),
    ],
)
def test_bad_input_is_named(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_cascade_impulse_response_is_the_fourth_order_system():
    # Independent reference: scipy's impulse response of ω_f² s² / [(s² + 2ζω_f s + ω_f²)
    # (s² + 2ζ_l ω_l s + ω_l²)] against the partial fractions of filter_poles.
    wf, z, wl, zl = 20.0, 0.3, 2.5, 0.6
    lti = signal.lti([wf**2, 0.0, 0.0], np.polymul([1, 2 * z * wf, wf**2], [1, 2 * zl * wl, wl**2]))
    tau = np.linspace(0.0, 6.0, 601)
    _, ref = signal.impulse(lti, T=tau)
    c, p = filter_poles([wf], z, (wl, zl))
    h = 2.0 * np.real((c[0] * np.exp(np.outer(tau, p[0]))).sum(axis=1))
    np.testing.assert_allclose(h, ref, atol=1e-12 * np.abs(ref).max())
    # The oscillator alone: the closed form of impulse_response.
    c1, p1 = filter_poles([wf], z)
    h1 = 2.0 * np.real(c1[0, 0] * np.exp(tau * p1[0, 0]))
    np.testing.assert_allclose(h1, impulse_response(tau, wf, z), atol=1e-12 * wf)


@pytest.mark.parametrize("low", [None, (2.5, 0.6)])
def test_unit_psd_integrates_to_one_and_is_the_sampled_response(low):
    dt, wf, z = 0.01, 2 * np.pi * 4.0, 0.25
    f = np.linspace(0.0, 0.5 / dt, 200001)
    phi = unit_psd(f, [wf], z, dt, low)[0]
    assert np.trapezoid(phi, f) == pytest.approx(1.0, abs=1e-6)
    # Against the FFT of the sampled impulse response (long enough to have decayed).
    c, p = filter_poles([wf], z, low)
    h = 2.0 * np.real((c[0] * np.exp(np.outer(np.arange(2**15) * dt, p[0]))).sum(axis=1))
    fr = np.fft.rfftfreq(h.size, dt)
    ref = 2.0 * dt * np.abs(np.fft.rfft(h)) ** 2 / np.sum(h * h)
    sel = (fr > 0.05) & (fr < 20.0)
    np.testing.assert_allclose(unit_psd(fr[sel], [wf], z, dt, low)[0], ref[sel], rtol=1e-8)


def test_cascade_band_has_unit_rows_and_matches_the_dense_definition():
    dt, n = 0.02, 300
    om = np.linspace(25.0, 15.0, n)
    low = (3.0, 0.5)
    s = normalized_irf(om, 0.2, dt, band_tol=1e-300, low=low).to_dense()
    c, p = filter_poles(om, 0.2, low)
    k, i = np.arange(n)[:, None], np.arange(n)[None, :]
    lag = np.maximum(k - i, 0) * dt
    h = 2.0 * np.real(c[None, :, 0] * np.exp(lag * p[None, :, 0])
                      + c[None, :, 1] * np.exp(lag * p[None, :, 1]))
    h[k < i] = 0.0
    norm = np.sqrt((h**2).sum(axis=1))
    norm[0] = 1.0
    np.testing.assert_allclose(s, h / norm[:, None], atol=1e-12)
    np.testing.assert_allclose(np.sum(s[1:] ** 2, axis=1), 1.0, rtol=1e-12)


def test_bad_low_frequency_filter_is_named():
    with pytest.raises(ValueError, match="zeta_low"):
        normalized_irf(np.ones(10) * 20.0, 0.2, 0.01, low=(2.0, 1.0))
    with pytest.raises(ValueError, match="omega_low"):
        normalized_irf(np.ones(10) * 20.0, 0.2, 0.01, low=(-2.0, 0.5))
    with pytest.raises(ValueError, match="coincides"):
        filter_poles([20.0], 0.2, (20.0, 0.2))
