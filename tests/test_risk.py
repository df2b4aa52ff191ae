"""From fragility to risk: hazard curves, mean annual frequency against the closed form, and the
NRML / pelicun exports read back by independent readers written to the tools' documented
formats.

pelicun is not installed here: `pip install pelicun` (3.10) pins pandas < 3 and scipy 1.15,
which would downgrade the project's pandas 3 and scipy 1.17; OpenQuake's engine does not
install from the package index on a plain machine (it builds GDAL). The readers below follow
the formats as both tools document and read them (docs/risk.md).
"""

from __future__ import annotations

import csv
import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy import stats

import rocking
from rocking.cli import main
from rocking.fragility import table as fragilities
from rocking.risk import nrml, pelicun
from rocking.risk.annual_frequency import annual_frequency_parts, probability_in
from rocking.risk.hazard import HazardCurve, parse_hazard
from rocking.risk.risk_table import risk_table

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(__file__).parent / "data"
OQ_TEST = DATA / "hazard_curve-mean-PGA_test.csv"
EXAMPLE = ROOT / "config/hazard/example_hazard_curve.csv"
NS = {"n": "http://openquake.org/xmlns/nrml/0.5"}


def closed_form(k0, k, median, beta):
    """λ_LS of a lognormal fragility under λ = k0·im^−k (Cornell et al. 2002)."""
    return k0 * median ** (-k) * math.exp(0.5 * k * k * beta * beta)


def table(rows) -> pd.DataFrame:
    """A fragility table as `to_frame` writes it (titles with units)."""
    cols = ["mode", "limit_state", "tan_alpha [-]", "R [m]", "median_pga_g [g]", "beta [-]",
            "status"]
    return pd.DataFrame(rows, columns=cols)


# Medians and betas with all their digits: the round trips must keep them to 1e-9.
ROWS = [
    ("3d", "overturning", 0.2, 2.0, 0.31234567891234, 0.21987654321, "ok"),
    ("3d", "tilt:1/3", 0.2, 2.0, 0.25111111111111, 0.1234567890123, "ok"),
    ("3d", "tilt:0.1", 0.2, 2.0, 0.20987654321987, 0.0876543210987, "ok"),
    ("3d", "overturning", 0.2, 6.0, 0.65432109876543, 0.3312345678901, "ok"),
    ("3d", "tilt:1/3", 0.2, 6.0, 0.33333333333333, 0.1455555555555, "ok"),
    ("3d", "tilt:0.1", 0.2, 6.0, 0.22222222222222, 0.0922222222222, "ok"),
    ("2d-x", "overturning", 0.2, 2.0, 0.41234567891234, 0.2598765432101, "ok"),
    ("2d-x", "tilt:1/3", 0.2, 2.0, 0.29876543219876, 0.1111111111111, "ok"),
    ("2d-x", "overturning", 0.2, 6.0, float("nan"), float("nan"), "too-few-observed"),
    ("2d-x", "tilt:1/3", 0.2, 6.0, 0.38765432198765, 0.1777777777777, "ok"),
    ("3d", "overturning", 0.1, 2.0, float("nan"), float("nan"), "not-computed"),
]


# ------------------------------------------------------------------ hazard and integration


@pytest.mark.parametrize("k0, k, median, beta", [
    (1e-4, 2.5, 0.5, 0.4), (1e-3, 3.0, 1.5, 0.6), (5e-4, 1.5, 0.1, 0.05),
    (2e-4, 2.0, 8.0, 0.8), (1e-4, 4.0, 0.3, 0.3),
])
def test_mean_annual_frequency_matches_the_power_law_closed_form(k0, k, median, beta):
    h = HazardCurve.from_power_law(k0, k)
    assert rocking.mean_annual_frequency(median, beta, h) == pytest.approx(
        closed_form(k0, k, median, beta), rel=1e-3)


def test_ends_of_the_curve_are_extrapolated_with_their_slopes():
    # A power law tabulated only on 0.1–0.4 g: a capacity far beyond the last level is still
    # integrated exactly (the last slope continues); truncating at 0.4 g would give ~0.
    k0, k = 2e-4, 2.7
    short = HazardCurve.from_power_law(k0, k, im_g=[0.1, 0.2, 0.4])
    parts = annual_frequency_parts(2.0, 0.3, short)
    assert parts["total"] == pytest.approx(closed_form(k0, k, 2.0, 0.3), rel=1e-3)
    assert parts["extrapolated"] / parts["total"] > 0.999
    # a capacity well inside the table: the motions beyond 0.4 g all exceed it, whatever the
    # tail (beyond_last = λ(0.4 g)), and nothing rests on the extrapolated slope
    inside = annual_frequency_parts(0.2, 0.1, short)
    assert inside["beyond_last"] == pytest.approx(k0 * 0.4 ** -k, rel=1e-3)
    assert (inside["below_first"] + inside["extrapolated"]) / inside["total"] < 1e-4
    assert inside["total"] == pytest.approx(closed_form(k0, k, 0.2, 0.1), rel=1e-3)


def test_on_a_curved_hazard_it_is_the_expected_rate_at_the_capacity():
    # Independent check off the closed form: Monte Carlo of capacities C ~ LN(θ, β),
    # λ_LS = E[λ(C)] (integration by parts of ∫ P(LS|im)|dλ|).
    h = HazardCurve.from_openquake_csv(EXAMPLE, site=0)
    rng = np.random.default_rng(1)
    c = 0.4 * np.exp(0.3 * rng.standard_normal(400_000))
    mc = float(np.mean(h.rate(c)))
    assert rocking.mean_annual_frequency(0.4, 0.3, h) == pytest.approx(mc, rel=5e-3)


def test_openquake_csv_gives_annual_rates_per_site():
    h = HazardCurve.from_openquake_csv(OQ_TEST, site=0)
    assert h.im_g.tolist() == [0.05, 0.1, 0.2, 0.4, 0.8]
    assert h.annual_rate == pytest.approx([2e-2, 5e-3, 1e-3, 1.5e-4, 1.2e-5], rel=1e-9)
    site1 = HazardCurve.from_openquake_csv(OQ_TEST, site=1)
    assert site1.annual_rate == pytest.approx(0.5 * h.annual_rate, rel=1e-9)
    assert site1.site == "row 1 (lon 10.1, lat 45)" and site1.site in site1.source
    # between levels: log-log interpolation, e.g. halfway in log between 0.1 and 0.2 g
    assert h.rate(math.sqrt(0.02)) == pytest.approx(math.sqrt(5e-3 * 1e-3), rel=1e-12)


def test_example_hazard_curve_is_what_its_readme_says():
    h = HazardCurve.from_openquake_csv(EXAMPLE, site=0)
    # 10 % in 50 years (475 yr) at 0.25 g, 2 % in 50 years (2475 yr) at 0.5 g
    assert h.rate(0.25) == pytest.approx(1 / 475, rel=1e-4)
    assert h.rate(0.5) == pytest.approx(1 / 2475, rel=1e-3)
    # power-law-like: log-log slope grows from ~1.4 at 0.05 g to ~3.3 at 2 g
    assert 1.2 < h.slope(0.05) < 1.6 and 3.0 < h.slope(1.9) < 3.5
    assert np.all(np.diff(h.slope(h.im_g[:-1])) > 0)


@pytest.mark.parametrize("text, match", [
    ("#,,,,,\"investigation_time=1.0, imt='PGV'\"\nlon,lat,poe-0.1,poe-0.2\n0,0,0.1,0.05\n",
     "PGV.* not supported"),
    ("lon,lat,poe-0.1\n0,0,0.1\n", "no investigation_time in a comment"),
    ("#,,,,,\"imt='PGA'\"\nlon,lat,poe-0.1,poe-0.2\n0,0,0.1,0.05\n", "no investigation_time "
     "in a comment"),
    ("#,,,,,\"investigation_time=50.0\"\nlon,lat,poe-0.1,poe-0.2\n0,0,0.1,0.05\n",
     "no imt in a comment"),
    ("#,,,,,\"investigation_time=1.0, imt='PGA'\"\nlon,lat,poe-0.1,poe-0.2\n0,0,1.5,0.1\n",
     r"must be in \[0, 1\]"),
    ("#,,,,,\"investigation_time=1.0, imt='PGA'\"\nlon,lat,poe-0.1,poe-0.2\n0,0,0.1,0.2\n",
     "must not increase"),
    ("#,,,,,\"investigation_time=1.0, imt='PGA'\"\nlon,lat,poe-0.1\n0,0,0.1\n",
     "at least 2 levels"),
    ("#,,,,,\"investigation_time=1.0, imt='PGA'\"\nlon,lat,poe-0.1,poe-0.2\n0,0,1.0,0.1\n",
     "at least 2 levels"),
    ("#,,,,,\"investigation_time=1.0, imt='PGA'\"\nlon,lat,depth\n0,0,0\n",
     "not a hazard file this reads"),
])
def test_bad_openquake_files_are_refused_with_the_reason(tmp_path, text, match):
    path = tmp_path / "h.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=match):
        HazardCurve.from_openquake_csv(path)


def test_a_site_beyond_the_file_is_refused():
    with pytest.raises(ValueError, match=r"site row 2 is not in the file: .* rows 0\.\.1"):
        HazardCurve.from_openquake_csv(OQ_TEST, site=2)


def test_parse_hazard_forms_and_im_factor():
    a = parse_hazard("1e-4,2.5")
    b = parse_hazard({"k0": 1e-4, "k": 2.5})
    assert a.annual_rate == pytest.approx(b.annual_rate)
    f = parse_hazard({"file": str(OQ_TEST), "site": 1, "im_factor": 1.1})
    assert f.im_g == pytest.approx(1.1 * np.array([0.05, 0.1, 0.2, 0.4, 0.8]))
    # scaling the hazard's PGA by f multiplies a power law's λ_LS by f^k
    lam1 = rocking.mean_annual_frequency(0.5, 0.3, b)
    lam2 = rocking.mean_annual_frequency(0.5, 0.3, b.scaled(1.1))
    assert lam2 / lam1 == pytest.approx(1.1 ** 2.5, rel=1e-3)
    with pytest.raises(ValueError, match="power law 'k0,k'"):
        parse_hazard("1e-4")
    with pytest.raises(ValueError, match="k0"):
        parse_hazard({"k0": -1, "k": 2})
    with pytest.raises(ValueError, match="keys"):
        parse_hazard({"k0": 1e-4})


def test_poisson_probability_and_bad_fragility_input():
    assert probability_in(1 / 475, 50) == pytest.approx(0.1, abs=2e-3)
    with pytest.raises(ValueError, match="beta"):
        rocking.mean_annual_frequency(0.5, 0.0, HazardCurve.from_power_law(1e-4, 2))
    with pytest.raises(ValueError, match="median_g"):
        rocking.mean_annual_frequency(float("nan"), 0.3, HazardCurve.from_power_law(1e-4, 2))


# ------------------------------------------------------------------ the fragility table


def test_fragility_rows_in_severity_order_and_skipped_rows_named():
    frag = fragilities.read_fragilities(table(ROWS))
    assert len(frag.rows) == 9 and frag.n_not_computed == 1
    assert frag.skipped[["mode", "R", "limit_state", "status"]].values.tolist() == [
        ["2d-x", 6.0, "overturning", "too-few-observed"]]
    assert "2d-x tan α=0.2 R=6 m overturning (too-few-observed)" in frag.skipped_note()
    body = frag.rows[(frag.rows["mode"] == "3d") & (frag.rows["R"] == 2.0)]
    assert body["limit_state"].tolist() == ["tilt:0.1", "tilt:1/3", "overturning"]
    with pytest.raises(ValueError, match="lacks the columns"):
        fragilities.read_fragilities(table(ROWS).drop(columns="beta [-]"))


def test_risk_table_columns_units_and_values():
    frag = fragilities.read_fragilities(table(ROWS))
    h = HazardCurve.from_power_law(1e-4, 2.5)
    t = risk_table(frag, h)
    assert list(t.columns) == ["fragility", "measure", "component", "component_source", "mode",
                               "tan_alpha [-]",
                               "R [m]",
                               "limit_state", "median_im [g]", "median_pga_g [g]", "beta [-]",
                               "n", "maf [1/yr]", "lambda_p05 [1/yr]", "lambda_p95 [1/yr]",
                               "lambda_lo [1/yr]", "lambda_hi [1/yr]", "return_period [yr]",
                               "p_50yr [-]", "share_extrapolated [-]",
                               "share_below_first [-]", "hazard_site", "hazard_kind",
                               "preset", "status"]
    assert set(t["fragility"]) == {"critical_intensity"} and set(t["measure"]) == {"pga"}
    # every requested row is present: the one without a fit with its status and λ NaN
    assert len(t) == len(ROWS) - 1  # the not-computed cell is not part of the study
    for r in t.to_dict(orient="records"):
        if r["status"] == "too-few-observed":
            assert math.isnan(r["maf [1/yr]"]) and math.isnan(r["median_pga_g [g]"])
            continue
        lam = closed_form(1e-4, 2.5, r["median_pga_g [g]"], r["beta [-]"])
        assert r["maf [1/yr]"] == pytest.approx(lam, rel=1e-3)
        assert r["return_period [yr]"] == pytest.approx(1 / r["maf [1/yr]"])
        assert r["p_50yr [-]"] == pytest.approx(1 - math.exp(-50 * r["maf [1/yr]"]))
        # the power law is tabulated from 1e-3 g: nothing below it reaches these capacities
        assert 0.0 <= r["share_below_first [-]"] < 1e-9
    assert "too-few-observed" in t.attrs["skipped"]


# ------------------------------------------------------------------ NRML 0.5


def read_nrml(path):
    """Independent reader of an NRML 0.5 continuous fragility model (OpenQuake's documented
    schema): element order checked, mean/stddev turned into median and β as OpenQuake does
    (σ = √ln(1 + (stddev/mean)²), median = mean²/√(stddev² + mean²))."""
    root = ET.parse(path).getroot()
    assert root.tag == "{http://openquake.org/xmlns/nrml/0.5}nrml"
    (model,) = list(root)
    assert model.tag.endswith("fragilityModel")
    assert {"id", "assetCategory", "lossCategory"} <= set(model.attrib)
    kids = list(model)
    assert [k.tag.split("}")[1] for k in kids[:2]] == ["description", "limitStates"]
    states = kids[1].text.split()
    out = {}
    for func in kids[2:]:
        assert func.tag.endswith("fragilityFunction")
        assert func.get("format") == "continuous" and func.get("shape") == "logncdf"
        imls, *params = list(func)
        assert imls.tag.endswith("imls") and imls.get("imt") == "PGA"
        assert [p.get("ls") for p in params] == states  # one per limit state, in order
        lims = {k: float(imls.get(k)) for k in ("minIML", "maxIML", "noDamageLimit")}
        for p in params:
            mean, std = float(p.get("mean")), float(p.get("stddev"))
            sigma = math.sqrt(math.log(1.0 + (std / mean) ** 2))
            median = mean ** 2 / math.sqrt(std ** 2 + mean ** 2)
            out[(func.get("id"), p.get("ls"))] = (median, sigma, lims)
    return states, out


def openquake_poe(iml, median, sigma, lims):
    """PoE as OpenQuake's continuous function evaluates it: clip to [minIML, maxIML], zero at
    or below noDamageLimit."""
    x = np.clip(np.asarray(iml, float), lims["minIML"], lims["maxIML"])
    poe = stats.norm.cdf(np.log(x / median) / sigma)
    return np.where(np.asarray(iml) <= lims["noDamageLimit"], 0.0, poe)


def test_nrml_round_trip_of_median_and_beta(tmp_path):
    frag = fragilities.read_fragilities(table(ROWS))
    exp = nrml.write_nrml(frag, tmp_path / "f.xml", search_upper=20.0)
    states, got = read_nrml(tmp_path / "f.xml")
    assert states == ["tilt_1over3", "overturning"]  # common to every (mode, tan α)
    assert exp.left_out == ["2d-x/tan0.2/R6m (no fit for overturning)"]
    assert exp.functions == ["2d-x/tan0.2/R2m", "3d/tan0.2/R2m", "3d/tan0.2/R6m"]
    n = 0
    for r in frag.rows.itertuples():
        key = (nrml.taxonomy(r.mode, r.tan_alpha, r.R), nrml.nrml_limit_state(r.limit_state))
        if key not in got:
            continue
        median, sigma, lims = got[key]
        assert median == pytest.approx(r.median_g, rel=1e-9)
        assert sigma == pytest.approx(r.beta, rel=1e-9)
        # maxIML at or above the search bound in g: no probability is capped in the range
        assert lims["maxIML"] >= 20.0 * r.tan_alpha
        x = np.geomspace(1.01 * lims["minIML"], 20.0 * r.tan_alpha, 50)
        assert openquake_poe(x, median, sigma, lims) == pytest.approx(
            stats.norm.cdf(np.log(x / r.median_g) / r.beta), abs=1e-9)
        n += 1
    assert n == 6


def test_a_median_written_as_mean_fails_the_round_trip(tmp_path, monkeypatch):
    # The mistake OpenQuake's convention invites: writing median and β·median as mean and
    # stddev. The reader then sees a smaller median (mean²/√(σ²+μ²) < μ) and the check fails.
    frag = fragilities.read_fragilities(table(ROWS))
    monkeypatch.setattr(nrml, "lognormal_moments", lambda m, b: (m, m * b))
    nrml.write_nrml(frag, tmp_path / "wrong.xml")
    _, got = read_nrml(tmp_path / "wrong.xml")
    r = frag.rows.iloc[0]
    median, sigma, _ = got[(nrml.taxonomy(r["mode"], r.tan_alpha, r.R),
                            nrml.nrml_limit_state(r.limit_state))]
    assert abs(median / r.median_g - 1.0) > 1e-3
    with pytest.raises(AssertionError):
        assert median == pytest.approx(r.median_g, rel=1e-9)


def test_lognormal_moments_invert():
    mean, std = fragilities.lognormal_moments(0.4, 0.3)
    assert mean == pytest.approx(0.4 * math.exp(0.045))
    assert std == pytest.approx(mean * math.sqrt(math.exp(0.09) - 1))
    assert fragilities.median_beta(mean, std) == pytest.approx((0.4, 0.3), rel=1e-12)


# ------------------------------------------------------------------ pelicun


def read_pelicun(path):
    """Independent reader of pelicun's damage model CSV (documented columns)."""
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    out = {}
    for row in rows:
        assert row["Demand-Type"] == "Peak Ground Acceleration" and row["Demand-Unit"] == "g"
        assert row["Incomplete"] == "0" and row["Demand-Offset"] == "0"
        # directional: pelicun would multiply a non-directional PGA by 1.2, and the vector
        # peak is already the peak over all orientations
        assert row["Demand-Directional"] == "1"
        ls = []
        i = 1
        while row.get(f"LS{i}-Family"):
            assert row[f"LS{i}-Family"] == "lognormal"
            ls.append((float(row[f"LS{i}-Theta_0"]), float(row[f"LS{i}-Theta_1"])))
            i += 1
        assert all(not row.get(f"LS{j}-Family") for j in range(i, 20))  # no gaps
        out[row["ID"]] = ls
    return out


def test_pelicun_round_trip_and_limit_states_in_increasing_severity(tmp_path):
    frag = fragilities.read_fragilities(table(ROWS))
    comps = pelicun.write_pelicun_csv(frag, tmp_path / "f.csv")
    header = (tmp_path / "f.csv").read_text().splitlines()[0].split(",")
    assert header == pelicun.columns(3)
    assert header[:10] == ["ID", "Incomplete", "Demand-Type", "Demand-Unit", "Demand-Offset",
                           "Demand-Directional", "LS1-Family", "LS1-Theta_0", "LS1-Theta_1",
                           "LS1-DamageStateWeights"]
    got = read_pelicun(tmp_path / "f.csv")
    cid = pelicun.component_id("3d", 0.2, 2.0)
    assert cid == "rocking.3d.tan0.2.R2m.critical_intensity"
    assert comps[cid] == ["tilt:0.1", "tilt:1/3", "overturning"]  # overturning last
    for (mode, ta, R), rows in frag.groups():
        pairs = got[pelicun.component_id(mode, ta, R)]
        assert len(pairs) == len(rows)
        for (m, b), r in zip(pairs, rows.itertuples(), strict=True):
            assert m == pytest.approx(r.median_g, rel=1e-9)
            assert b == pytest.approx(r.beta, rel=1e-9)
    # damage state i = limit state i exceeded: medians increase with severity here
    assert [m for m, _ in got[cid]] == sorted(m for m, _ in got[cid])


# ------------------------------------------------------------------ front ends


def test_lazy_exports_and_cli(tmp_path, capsys):
    assert rocking.HazardCurve is HazardCurve
    path = tmp_path / "fragility.csv"
    table(ROWS).to_csv(path, index=False)
    assert main(["risk", "--fragility", str(path), "--hazard", "1e-4,2.5", "--mode", "3d",
                 "--limit-states", "overturning"]) == 0
    out = capsys.readouterr().out
    assert "λ [1/yr]" in out and "return period [yr]" in out and "P(50 yr) [-]" in out
    assert "critical-intensity fragility" in out
    assert "too-few-observed" not in out  # the 2d-x row without a fit is not asked for
    lam = closed_form(1e-4, 2.5, 0.31234567891234, 0.21987654321)
    assert f"{lam:.4g}" in out
    # the median in g and as PGA/(g tan α)
    assert "0.3123" in out and f"{0.31234567891234 / 0.2:.4g}" in out
    assert main(["risk", "--fragility", str(path), "--hazard", str(OQ_TEST), "--site", "0",
                 "--component", "vector_peak",
                 "-o", str(tmp_path / "r.csv"), "--nrml", str(tmp_path / "f.xml"),
                 "--pelicun", str(tmp_path / "f.p.csv")]) == 0
    written = pd.read_csv(tmp_path / "r.csv")
    assert len(written) == 10  # 9 fits and the row without one, with its status
    assert list(written["status"]).count("too-few-observed") == 1
    assert (tmp_path / "f.xml").exists() and (tmp_path / "f.p.csv").exists()
    assert main(["risk", "--fragility", str(path), "--hazard", "0.5"]) == 2
    assert "power law 'k0,k'" in capsys.readouterr().err


def test_report_section_states_the_assumptions_and_tabulates_lambda():
    from rocking.report.risk import risk_section_html, summary_table

    t = risk_table(fragilities.read_fragilities(table(ROWS)),
                   HazardCurve.from_openquake_csv(EXAMPLE, site=0))
    s = summary_table(t)
    assert list(s.columns) == ["R [m]", "overturning, 3d [1/yr]", "overturning, 2d-x [1/yr]",
                               "tilt θ > α/3, 3d [1/yr]", "tilt θ > α/3, 2d-x [1/yr]"]
    assert math.isnan(s.loc[s["R [m]"] == 6.0, "overturning, 2d-x [1/yr]"].item())
    text = risk_section_html(t, hazard=str(EXAMPLE))
    for needle in ("RotD100", "RotD50", "im_factor", "EXAMPLE", "Poisson", "extrapolated"):
        assert needle in text


def test_risk_figure_data_plot_and_sidecar(tmp_path):
    import json

    from rocking.plot import render
    from rocking.plot import risk as fig

    t = risk_table(fragilities.read_fragilities(table(ROWS)),
                   HazardCurve.from_power_law(1e-4, 2.5))
    path = tmp_path / "risk.csv"
    t.to_csv(path, index=False)
    d = fig.data(path)
    over = d["panels"][0]
    assert over["limit_state"] == "overturning"
    assert over["curves"]["3d"]["R"].tolist() == [2.0, 6.0]
    # R = 6 m has no fit: present, λ NaN (a gap in the line, never a line across it)
    assert over["curves"]["2d-x"]["R"].tolist() == [2.0, 6.0]
    assert np.isnan(over["curves"]["2d-x"]["maf"][1])
    assert any("2d-x overturning R = 6 m (too-few-observed)" in g for g in d["gaps"])
    ratio = d["measured"]["ratio 2d-x/3d overturning R=2 m [-]"]
    assert ratio == pytest.approx(closed_form(1e-4, 2.5, 0.41234567891234, 0.2598765432101)
                                  / closed_form(1e-4, 2.5, 0.31234567891234, 0.21987654321),
                                  rel=1e-3)
    # a mode the study did not run is not a gap of the figure (it follows the study)
    assert not any("3d-damped" in s for s in d["missing"])
    axes = fig.plot(d).axes
    assert axes[0].get_yscale() == "log"
    render("risk", [tmp_path / "risk.png"], tmp_path / "risk.json", risk=path, hazard="x")
    notes = json.loads((tmp_path / "risk.json").read_text())
    assert notes["figure"] == "risk" and "3d overturning R=6 m [1/yr]" in notes["measured"]


def _legend_and_drawn(figure):
    """The figure legend's labels, and per axes the labels of what it actually drew."""
    from matplotlib.container import ErrorbarContainer

    legends = [ax.get_legend() for ax in figure.axes if ax.get_legend()]
    assert len(legends) == 1
    labels = [t.get_text() for t in legends[0].get_texts()]
    drawn = []
    for ax in figure.axes:
        for artist in [*ax.lines, *ax.collections, *ax.containers]:
            if isinstance(artist, ErrorbarContainer):
                drawn.append(artist.get_label())
            elif artist.get_label() and not artist.get_label().startswith("_"):
                empty = (hasattr(artist, "get_paths") and not any(
                    len(p.vertices) for p in artist.get_paths()))
                if not empty:
                    drawn.append(artist.get_label())
    return labels, drawn


def test_risk_figure_legend_covers_no_curve_and_names_an_example_hazard(tmp_path):
    from rocking.plot import risk as fig

    t = risk_table(fragilities.read_fragilities(table(ROWS)),
                   HazardCurve.from_openquake_csv(EXAMPLE, site=0))
    d = fig.data(t, hazard=f"{EXAMPLE}, site row 0", study="study s")
    figure = fig.plot(d)
    # one legend, in a row of its own below the panels: no panel has one over its curves
    holder = [ax for ax in figure.axes if ax.get_legend()]
    assert len(holder) == 1 and not holder[0].axison and not holder[0].lines
    labels, drawn = _legend_and_drawn(figure)
    assert {"2D, x component", "3D"} <= set(labels)  # the 2D curves are in it
    assert set(labels) - {" "} <= set(drawn)  # every entry is something drawn
    title = figure.get_suptitle()
    assert "EXAMPLE" in title and "component vector_peak" in title
    # a real hazard file is not called an example
    d = fig.data(t, hazard="my_site/hazard_curve-mean-PGA.csv", study="study s")
    assert "EXAMPLE" not in fig.plot(d).get_suptitle()


def test_risk_figure_of_one_size_lists_only_intervals_it_draws():
    from matplotlib.container import ErrorbarContainer

    from rocking.plot import risk as fig

    t = risk_table(fragilities.read_fragilities(table(ROWS)),
                   HazardCurve.from_openquake_csv(EXAMPLE, site=0))
    one = t[np.isclose(t["R [m]"], 2.0)].copy()
    one["lambda_p05 [1/yr]"] = 0.5 * one["maf [1/yr]"]  # an interval, as a bootstrap gives
    one["lambda_p95 [1/yr]"] = 2.0 * one["maf [1/yr]"]
    d = fig.data(one)
    figure = fig.plot(d)
    labels, _ = _legend_and_drawn(figure)
    bands = [lab for lab in labels if lab.endswith("90 % interval")]
    for ax, panel in zip(figure.axes, d["panels"], strict=False):
        # one size: no band (it would draw nothing), a bar per mode, side by side
        assert not [c for c in ax.collections if c.get_label().endswith("interval")]
        bars = [c for c in ax.containers if isinstance(c, ErrorbarContainer)]
        assert len(bars) == len(panel["curves"]) >= 2
        xs = [float(b.lines[2][0].get_segments()[0][0][0]) for b in bars]
        assert len(set(xs)) == len(xs)
    assert sorted(bands) == sorted({b.get_label() for ax in figure.axes
                                    for b in ax.containers})


# ------------------------------------------------------------------ the stripe fragility


def stripe_store(tan_alpha=0.2, seed=7):
    """A stripes store as the workflow writes it (one mode, two sizes, two limit states):
    each motion exceeds a limit state at and above its own capacity, capacities drawn from
    known lognormals, so the stripe fits are finite and different from the critical-intensity
    rows of ROWS."""
    import xarray as xr

    x = np.geomspace(1.1, 15.0, 12)
    motions = [f"m{i}" for i in range(30)]
    states = ["overturning", "tilt:1/3"]
    Rs = [2.0, 6.0]
    rng = np.random.default_rng(seed)
    exc = np.zeros((1, len(states), len(motions), len(Rs), x.size), bool)
    for j, (theta, beta) in enumerate(((3.0, 0.4), (1.8, 0.3))):
        for k, R in enumerate(Rs):
            caps = theta * (R / 2.0) ** 0.5 * np.exp(beta * rng.standard_normal(len(motions)))
            exc[0, j, :, k, :] = x[None, :] >= caps[:, None]
    failed = np.zeros((1, len(motions), len(Rs), x.size), bool)
    return xr.Dataset(
        {"exceeded": (STRIPE_DIMS, exc),
         "failed": (("mode", "motion", "R", "intensity"), failed),
         "n_analyses": (("mode", "motion", "R"), np.full((1, len(motions), len(Rs)), x.size)),
         "done": (("chunk",), np.ones(1, bool))},
        coords={"mode": ["3d"], "limit_state": states, "motion": motions, "R": Rs,
                "intensity": x},
        attrs={"tan_alpha": tan_alpha})


STRIPE_DIMS = ("mode", "limit_state", "motion", "R", "intensity")


@pytest.fixture()
def stripe_csv(tmp_path):
    """stripe_fragility.csv as the workflow's rule writes it (rocking.execution.stripes)."""
    from rocking.execution.stripes import STRIPES_DIMS, stripe_table
    from rocking.units import header

    assert STRIPES_DIMS == STRIPE_DIMS  # the layout this stand-in store follows
    path = tmp_path / "stripe_fragility.csv"
    stripe_table(stripe_store()).rename(columns=header).to_csv(path, index=False,
                                                                float_format="%.10g")
    return path


def analytic_hazard(im):
    """The example curve's formula: λ = (1/475)·exp(−2.2 L − 0.262 L²), L = ln(PGA/0.25 g),
    and |dλ/d im| [1/yr per g]."""
    L = np.log(np.asarray(im, float) / 0.25)
    lam = np.exp(-2.2 * L - 0.262 * L * L) / 475.0
    return lam, lam * (2.2 + 0.524 * L) / np.asarray(im, float)


def independent_maf(median_g, beta):
    """λ_LS = ∫ Φ(ln(im/θ)/β) |dλ/d im| d im by adaptive quadrature over the analytic curve
    (no log-log table, no grid: another integrator on another representation)."""
    from scipy import integrate

    def f(u):  # im = e^u: Φ · |dλ/d im| · im
        im = math.exp(u)
        return stats.norm.cdf((u - math.log(median_g)) / beta) * analytic_hazard(im)[1] * im

    lo, hi = math.log(0.005), math.log(1e3)
    centre = math.log(median_g)
    val, _ = integrate.quad(f, lo, hi, points=[centre - 3 * beta, centre, centre + 3 * beta],
                            limit=400, epsabs=0.0, epsrel=1e-10)
    return val


def test_stripe_maf_matches_an_independent_numerical_integration(stripe_csv):
    # the hazard as a site gives it: a table (300 levels, 0.005–20 g) of the analytic curve
    # (it is non-increasing above 0.0037 g, where its log-log slope 2.2 + 0.524 L is > 0)
    im = np.geomspace(0.005, 20.0, 300)
    h = HazardCurve(im, analytic_hazard(im)[0], source="analytic example curve")
    frag = fragilities.read_fragilities(stripe_csv)
    assert frag.kind == "stripes" and len(frag.rows) == 4  # told by its columns
    t = risk_table(frag, h)
    assert set(t["fragility"]) == {"stripes"}
    for r in t.to_dict(orient="records"):
        assert r["maf [1/yr]"] == pytest.approx(independent_maf(r["median_pga_g [g]"],
                                                                r["beta [-]"]), rel=1e-3)
    # the medians are the binomial fits of the stripes (PGA in g = median · tan α)
    table_ = pd.read_csv(stripe_csv)
    keys = zip(t["R [m]"], t["limit_state"], strict=True)
    got = dict(zip(keys, t["median_pga_g [g]"], strict=True))
    for row in table_.itertuples(index=False):
        assert got[(row[3], row[1])] == pytest.approx(row[4] * 0.2, rel=1e-9)


def test_risk_csv_holds_both_fragilities_each_row_saying_which(stripe_csv, tmp_path):
    from rocking.risk.exports import write_risk_outputs

    first = tmp_path / "fragility.csv"
    table(ROWS).to_csv(first, index=False)
    h = HazardCurve.from_openquake_csv(EXAMPLE, site=0)
    summary = write_risk_outputs(first, h, nrml=tmp_path / "f.xml", pelicun=tmp_path / "f.csv",
                                 table=tmp_path / "risk.csv", search_upper=20.0,
                                 study="mine", stripes=stripe_csv)
    risk = pd.read_csv(tmp_path / "risk.csv")
    assert summary["risk_fragilities"] == ["critical_intensity", "stripes"]
    assert risk["fragility"].value_counts().to_dict() == {"critical_intensity": 10, "stripes": 4}
    # each row's λ is that of its own fragility
    stripe_rows = risk[risk["fragility"] == "stripes"]
    for r in stripe_rows.to_dict(orient="records"):
        assert r["maf [1/yr]"] == pytest.approx(rocking.mean_annual_frequency(
            r["median_pga_g [g]"], r["beta [-]"], h), rel=1e-5)
    with pytest.raises(ValueError, match="one table per kind"):
        from rocking.risk.risk_table import risk_tables

        risk_tables([stripe_csv, stripe_csv], h)


def test_tables_of_an_earlier_version_read_under_todays_estimator_name(stripe_csv, tmp_path):
    """Tables written when the critical-intensity fragility was named after the first
    exceedance (the committed gallery until it is regenerated) are read as today's estimator
    (rocking.fragility.table.RENAMED), and nothing is written under the old name."""
    from rocking.risk.risk_table import read_risk_table

    today = fragilities.CRITICAL_INTENSITY
    (old,) = [o for o, new in fragilities.RENAMED.items() if new == today]
    frag_csv = tmp_path / "fragility.csv"
    plain = table(ROWS)
    plain.insert(0, "estimator", old)
    plain.to_csv(frag_csv, index=False)
    assert fragilities.read_fragilities(frag_csv).kind == today
    assert fragilities.read_fragilities(table(ROWS), old).kind == today
    risk = risk_table(frag_csv, HazardCurve.from_power_law(1e-4, 2.5))
    assert set(risk["fragility"]) == {today}
    # risk.csv of an earlier version
    risk.assign(fragility=old).to_csv(tmp_path / "risk.csv", index=False)
    assert set(read_risk_table(tmp_path / "risk.csv")["fragility"]) == {today}
    # stripe_fragility.csv of an earlier version: its critical-intensity columns
    stripes = pd.read_csv(stripe_csv)
    before = stripes.rename(columns={new: o for o, new in fragilities.RENAMED_COLUMNS.items()})
    assert set(before.columns) != set(stripes.columns)
    assert list(fragilities.renamed(before).columns) == list(stripes.columns)
    # a pelicun export of an earlier version: the estimator ending each component id
    ids = pd.DataFrame({"ID": [f"rocking.3d.tan0.2.R2m.{old}", "rocking.3d.tan0.2.R2m.stripes"]})
    assert fragilities.renamed(ids)["ID"].tolist() == [
        f"rocking.3d.tan0.2.R2m.{today}", "rocking.3d.tan0.2.R2m.stripes"]
    # today's tables are left as they are
    assert fragilities.renamed(stripes) is stripes
    with pytest.raises(ValueError, match="estimator must be one of"):
        fragilities.write_fragilities(table(ROWS), tmp_path / "x.csv", estimator=old,
                                      measure="pga")


def test_stripe_exports_say_which_fragility_and_round_trip(stripe_csv, tmp_path):
    import re

    from rocking.risk.exports import write_fragility_exports

    first = tmp_path / "fragility.csv"
    table(ROWS).to_csv(first, index=False)
    out = {}
    for name, src in (("first", first), ("stripes", stripe_csv)):
        out[name] = write_fragility_exports(src, nrml=tmp_path / f"{name}.xml",
                                            pelicun=tmp_path / f"{name}.csv",
                                            search_upper=20.0, study="elcentro")
    assert out["stripes"]["fragility"] == "stripes"
    # NRML: model id and description name the fragility; the id is one OpenQuake reads
    ids = {}
    for name in out:
        model = ET.parse(tmp_path / f"{name}.xml").getroot()[0]
        ids[name] = model.get("id")
        assert re.fullmatch(r"[A-Za-z0-9_-]{1,60}", ids[name])  # OpenQuake's simple_id
        desc = model.find("n:description", NS).text
        assert desc.startswith({"first": "Critical-intensity fragility",
                                "stripes": "Multiple-stripe fragility"}[name])
    assert ids == {"first": "elcentro-critical-intensity", "stripes": "elcentro-stripes"}
    states, got = read_nrml(tmp_path / "stripes.xml")
    assert states == ["tilt_1over3", "overturning"]
    frag = fragilities.read_fragilities(stripe_csv)
    for r in frag.rows.itertuples():
        median, sigma, lims = got[(nrml.taxonomy(r.mode, r.tan_alpha, r.R),
                                   nrml.nrml_limit_state(r.limit_state))]
        assert median == pytest.approx(r.median_g, rel=1e-9)
        assert sigma == pytest.approx(r.beta, rel=1e-9)
        assert lims["maxIML"] >= r.median_g * math.exp(4 * r.beta)
    # pelicun: ids say the fragility, so both files can be loaded together without clashes
    p_first, p_stripes = (read_pelicun(tmp_path / f"{n}.csv") for n in ("first", "stripes"))
    assert all(i.endswith(".critical_intensity") for i in p_first)
    assert sorted(p_stripes) == ["rocking.3d.tan0.2.R2m.stripes", "rocking.3d.tan0.2.R6m.stripes"]
    assert not set(p_first) & set(p_stripes)
    for (mode, ta, R), rows in frag.groups():
        pairs = p_stripes[pelicun.component_id(mode, ta, R, "stripes")]
        assert [m for m, _ in pairs] == pytest.approx(rows["median_g"].tolist(), rel=1e-9)
        assert [b for _, b in pairs] == pytest.approx(rows["beta"].tolist(), rel=1e-9)
    with pytest.raises(ValueError, match="model_id must be"):
        nrml.write_nrml(frag, tmp_path / "x.xml", model_id="my study")  # OpenQuake refuses it


def test_report_and_figure_set_the_two_mafs_side_by_side(stripe_csv, tmp_path):
    from rocking.plot import risk as fig
    from rocking.report.risk import WHICH_TO_USE, comparison_table, risk_section_html
    from rocking.risk.risk_table import risk_tables

    h = HazardCurve.from_openquake_csv(EXAMPLE, site=0)
    risk = risk_tables([table(ROWS), stripe_csv], h)
    both = comparison_table(risk)
    assert len(both) == 4  # 3d, tan α 0.2, R 2 and 6 m, two limit states: in both tables
    lam = {(r["fragility"], r["R [m]"], r["limit_state"]): r["maf [1/yr]"]
           for _, r in risk.iterrows() if r["mode"] == "3d"}
    for _, r in both.iterrows():
        key = (r["R [m]"], r["limit state"])
        assert r["λ critical intensity [1/yr]"] == lam[("critical_intensity", *key)]
        assert r["λ stripes [1/yr]"] == lam[("stripes", *key)]
        assert r["stripes / critical intensity [-]"] == pytest.approx(
            lam[("stripes", *key)] / lam[("critical_intensity", *key)])
    text = risk_section_html(risk, hazard=str(EXAMPLE))
    assert "Which λ risk uses: the lognormal" in text and WHICH_TO_USE[:40] in text
    ratio = both["stripes / critical intensity [-]"]
    assert f"{ratio.min():.2g}–{ratio.max():.2g} times" in text
    # without stripe rows: no comparison, the critical-intensity table as before
    assert comparison_table(risk_table(table(ROWS), h)).empty
    assert "Which λ" not in risk_section_html(risk_table(table(ROWS), h))
    d = fig.data(risk)
    over = d["panels"][0]
    assert list(over["stripes"]) == ["3d"] and over["stripes"]["3d"]["R"].tolist() == [2.0, 6.0]
    assert d["measured"]["ratio stripes/critical intensity 3d overturning R=6 m [-]"] == (
        pytest.approx(lam[("stripes", 6.0, "overturning")]
                      / lam[("critical_intensity", 6.0, "overturning")]))
    legend = next(ax.get_legend() for ax in fig.plot(d).axes if ax.get_legend())
    labels = [t.get_text() for t in legend.get_texts()]
    assert "3D, stripes" in labels and "3D, critical intensities" in labels


def test_docs_quote_the_two_mafs_of_the_committed_gallery():
    """docs/risk.md's stripe / critical-intensity numbers are those of results/paper/elcentro
    under the example hazard (recomputed here from the two committed fragility tables)."""
    from rocking.report.risk import comparison_table
    from rocking.risk.risk_table import risk_tables

    gallery = ROOT / "results/paper/elcentro"
    risk = risk_tables([gallery / "fragility.csv", gallery / "stripe_fragility.csv"],
                       HazardCurve.from_openquake_csv(EXAMPLE, site=0))
    both = comparison_table(risk).set_index(["mode", "tan α [-]", "R [m]", "limit state"])
    text = " ".join((ROOT / "docs/risk.md").read_text(encoding="utf-8").split())
    quote = re.search(r"BEGIN gallery:risk-stripe-critical -->(.*?)<!-- END", text).group(1)
    # the six ratios in the order the sentence gives them: overturning, then excessive tilt
    quoted = re.findall(r"(\d\.\d\d)×", quote)
    recomputed = [f"{both.loc[('3d', 0.2, R, ls), 'stripes / critical intensity [-]']:.2f}"
                  for ls in ("overturning", "tilt:1/3") for R in (2.0, 6.0, 10.0)]
    assert quoted == recomputed, (quoted, recomputed)
    over6 = both.loc[("3d", 0.2, 6.0, "overturning")]
    assert f"{over6['λ stripes [1/yr]'] * 1e4:.2f}·10⁻⁴ against " \
           f"{over6['λ critical intensity [1/yr]'] * 1e4:.2f}·10⁻⁴" in text


@pytest.mark.slow
def test_workflow_plans_the_stripe_exports_and_feeds_the_stripes_to_risk(tmp_path):
    """Dry run of the default configuration (a study with stripes and a hazard): the risk
    rule reads stripe_fragility.csv, and the stripe exports are planned under their names."""
    import re
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-m", "snakemake", "-s", str(ROOT / "Snakefile"),
                          "--directory", str(tmp_path), "--configfile",
                          str(ROOT / "config/config.yaml"), "-n", "--cores", "1"],
                         capture_output=True, text=True, cwd=tmp_path)
    assert out.returncode == 0, out.stderr[-3000:]
    jobs = out.stdout
    assert re.search(r"^stripe_risk_exports\s+1$", jobs, re.MULTILINE)
    block = jobs[jobs.index("rule risk:"):]
    inputs = block.splitlines()[1]
    assert "results/elcentro/stripe_fragility.csv" in inputs and "fragility.csv" in inputs
    exports = jobs[jobs.index("rule stripe_risk_exports:"):]
    assert "results/elcentro/stripe_fragility.nrml.xml" in exports
    assert "results/elcentro/stripe_fragility.pelicun.csv" in exports
