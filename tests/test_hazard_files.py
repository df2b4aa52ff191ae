"""Hazard files as the tools write them (issue 29): OpenQuake CSVs whose lowest levels read
PoE = 1 with six significant digits, SA(T) curves, plain two-column tables, and the bad inputs
refused in one line naming the file."""

from __future__ import annotations

import logging
import math

import numpy as np
import pandas as pd
import pytest

from rocking.motions.measures import same_measure
from rocking.risk.annual_frequency import annual_frequency_parts, mean_annual_frequency
from rocking.risk.hazard import HazardCurve, hazard_measure, parse_hazard


def closed_form(k0, k, median, beta):
    """λ_LS of a lognormal fragility under λ = k0·im^−k (Cornell et al. 2002)."""
    return k0 * median ** (-k) * math.exp(0.5 * k * k * beta * beta)


def write_openquake(path, iml, poe, *, years=50.0, imt="PGA"):
    """An OpenQuake hazard_curve CSV as the engine writes it (3.15+): a quoted comment line,
    lon,lat,depth, poe-<iml> columns with seven decimals, probabilities with %.6E."""
    head = ",".join(f"poe-{x:.7f}" for x in iml)
    row = ",".join(f"{p:.6E}" for p in poe)
    path.write_text(f"#,,,,,\"generated_by='OpenQuake engine 3.23', start_date='2026-01-01', "
                    f"checksum=1, kind='mean', investigation_time={years}, imt='{imt}'\"\n"
                    f"lon,lat,depth,{head}\n10.00000,45.00000,0.00000,{row}\n")
    return path


K0, K = 1e-4, 2.5
IML = np.geomspace(0.002, 5.0, 40)


def power_law_poe(years=50.0):
    return -np.expm1(-years * K0 * IML ** (-K))


def test_six_digit_poe_one_levels_are_dropped_and_the_closed_form_holds(tmp_path, caplog):
    poe = power_law_poe()
    assert float(f"{poe[0]:.6E}") == 1.0  # the engine's six digits make these levels PoE = 1
    n_one = int(sum(float(f"{p:.6E}") == 1.0 for p in poe))
    assert n_one >= 5
    path = write_openquake(tmp_path / "hazard_curve-mean-PGA.csv", IML, poe)
    with caplog.at_level(logging.WARNING, logger="rocking.risk.hazard"):
        h = parse_hazard(str(path))
    assert h.n_dropped == n_one
    assert h.dropped_up_to == pytest.approx(IML[n_one - 1], rel=1e-6)
    lines = [r.getMessage() for r in caplog.records if "dropped" in r.getMessage()]
    assert len(lines) == 1 and "\n" not in lines[0] and str(path) in lines[0]
    assert f"{n_one} level(s)" in lines[0]
    for median, beta in ((0.3, 0.3), (0.6, 0.45), (1.2, 0.25)):
        lam = mean_annual_frequency(median, beta, h)
        assert lam == pytest.approx(closed_form(K0, K, median, beta), rel=0.01)
        # the part below the first kept level is what could rest on the dropped levels
        parts = annual_frequency_parts(median, beta, h)
        assert 0.0 <= parts["below_first"] / parts["total"] < 1e-6


def test_sa_curve_keeps_its_measure(tmp_path):
    path = write_openquake(tmp_path / "hazard_curve-mean-SA(1.0).csv", IML, power_law_poe(),
                           imt="SA(1.0)")
    h = HazardCurve.from_openquake_csv(path)
    assert h.imt == "SA(1.0)" and h.measure == "sa:1.0"
    assert same_measure(h.measure, "sa:1.0") and not same_measure(h.measure, "pga")
    assert not same_measure("sa:1.0", "sa:0.3")
    assert hazard_measure("PGA").name == "pga" and hazard_measure("sa:0.30").name == "sa:0.3"
    with pytest.raises(ValueError, match="'PGV' is not supported for a hazard"):
        hazard_measure("PGV")


@pytest.mark.parametrize("second, factor", [("annual_rate", None), ("poe", 50.0)])
def test_two_column_tables(tmp_path, second, factor):
    rate = K0 * IML ** (-K)
    value = rate if factor is None else -np.expm1(-factor * rate)
    text = f"pga [g],{second}\n" + "".join(f"{x:.7g},{v:.6E}\n" for x, v in zip(IML, value,
                                                                               strict=True))
    path = tmp_path / "site.csv"
    path.write_text(text)
    spec = {"file": str(path)} if factor is None else {"file": str(path),
                                                       "investigation_time": factor}
    h = parse_hazard(spec)
    assert h.measure == "pga"
    assert mean_annual_frequency(0.5, 0.4, h) == pytest.approx(closed_form(K0, K, 0.5, 0.4),
                                                               rel=0.01)
    if factor is not None:
        # stated in a comment line instead of the mapping
        path.write_text("# investigation_time=50\n" + text)
        assert parse_hazard(str(path)).n_dropped == h.n_dropped
        path.write_text(text)
        with pytest.raises(ValueError, match="needs its investigation time"):
            parse_hazard(str(path))


def test_sa_table_header_names_the_measure(tmp_path):
    path = tmp_path / "sa.csv"
    path.write_text("SA(1.0),annual_rate\n0.1,1e-2\n0.2,2e-3\n0.4,3e-4\n")
    assert HazardCurve.from_file(path).measure == "sa:1.0"


@pytest.mark.parametrize("text, match", [
    ("pga,annual_rate\n", "a header of two columns"),
    ("pga,annual_rate\n0.1,0.01\n", "at least 2 levels"),
    ("pga,annual_rate\n0.1,0.01\n0.2,0.02\n", "must not increase"),
    ("pga,annual_rate\n0.2,0.01\n0.1,0.001\n", "strictly increasing"),
    ("pgv,annual_rate\n0.1,0.01\n0.2,0.001\n", "not supported"),
    ("pga,frequency\n0.1,0.01\n0.2,0.001\n", "annual_rate .* or poe"),
    ("pga,annual_rate,poe\n0.1,0.01,0.1\n", "not a hazard file this reads"),
])
def test_bad_tables_are_one_line_naming_the_file(tmp_path, text, match):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=match) as err:
        parse_hazard(str(path))
    assert "\n" not in str(err.value) and str(path) in str(err.value)


@pytest.mark.parametrize("spec", ["1e-4,0", "1e-4,-2", {"k0": 1e-4, "k": 0.0},
                                  {"k0": 1e-4, "k": -1.0}])
def test_power_law_with_k_not_positive_is_refused(spec):
    with pytest.raises(ValueError, match="k must be a finite number > 0"):
        parse_hazard(spec)


def test_power_law_in_sa():
    h = parse_hazard({"k0": 1e-4, "k": 2.0, "measure": "sa:1.0"})
    assert h.measure == "sa:1.0" and h.imt == "SA(1.0)"
    assert parse_hazard("1e-4,2", measure="sa:0.5").imt == "SA(0.5)"


def test_openquake_non_monotonic_names_file_and_levels(tmp_path):
    path = write_openquake(tmp_path / "h.csv", [0.1, 0.2, 0.4], [0.5, 0.1, 0.2])
    with pytest.raises(ValueError, match=r"must not increase .* 0\.1 at 0\.2 g and 0\.2 at "
                                         r"0\.4 g") as err:
        HazardCurve.from_openquake_csv(path)
    assert str(path) in str(err.value) and "\n" not in str(err.value)


# ------------------------------------------------------- units, range, first level, BOM
# (issue 39): levels in cm/s² read as g gave λ 210× too high; a table starting above the
# fragility's median gave λ 81 % high with nothing said; a BOM named '\ufeffpga' unsupported.

G = 9.80665


def table_text(im, rate, head="pga [g]"):
    return f"{head},annual_rate\n" + "".join(f"{x:.12g},{v:.12g}\n" for x, v in zip(im, rate,
                                                                                 strict=True))


@pytest.mark.parametrize("head, factor", [("pga [cm/s2]", 100 * G), ("pga [cm/s²]", 100 * G),
                                          ("PGA [gal]", 100 * G), ("pga [m/s2]", G),
                                          ("SA(1.0) [m/s^2]", G), ("pga [g]", 1.0)])
def test_a_table_in_another_unit_is_converted_to_g(tmp_path, head, factor):
    rate = K0 * IML ** (-K)
    ref = tmp_path / "g.csv"
    ref.write_text(table_text(IML, rate, "pga [g]" if "pga" in head.lower() else "SA(1.0)"))
    path = tmp_path / "other.csv"
    path.write_text(table_text(IML * factor, rate, head))
    h, g = parse_hazard(str(path)), parse_hazard(str(ref))
    assert h.im_g == pytest.approx(g.im_g, rel=1e-11) and h.measure == g.measure
    assert mean_annual_frequency(0.5, 0.4, h) == pytest.approx(
        mean_annual_frequency(0.5, 0.4, g), rel=1e-9)
    assert h.unit == {1.0: "g", G: "m/s2"}.get(factor, "gal" if "gal" in head else "cm/s2")


def test_levels_in_cm_s2_without_a_unit_are_refused_not_read_as_g(tmp_path):
    rate = K0 * IML ** (-K)
    path = tmp_path / "site.csv"
    path.write_text(table_text(IML * 100 * G, rate, "pga"))
    with pytest.raises(ValueError) as err:
        parse_hazard(str(path))
    text = str(err.value)
    assert "\n" not in text and str(path) in text and "implausible" in text
    assert "hazard.unit: cm/s2" in text and "pga [cm/s2]" in text
    # declared in the hazard entry instead of the header: the same λ as in g
    h = parse_hazard({"file": str(path), "unit": "cm/s2"})
    assert mean_annual_frequency(0.5, 0.4, h) == pytest.approx(closed_form(K0, K, 0.5, 0.4),
                                                               rel=0.01)
    # a header and an entry that disagree
    path.write_text(table_text(IML * 100 * G, rate, "pga [cm/s2]"))
    with pytest.raises(ValueError, match=r"header gives the levels in 'cm/s2', the hazard "
                                         r"entry in 'm/s2'"):
        parse_hazard({"file": str(path), "unit": "m/s2"})


@pytest.mark.parametrize("head, match", [
    ("pga [cm/s]", r"unit 'cm/s' is not an acceleration unit .* g, m/s2, cm/s2, gal"),
    ("pga [g]", r"implausible .* the levels were given in g; check the unit declared"),
])
def test_a_unit_that_cannot_be_is_one_line(tmp_path, head, match):
    path = tmp_path / "site.csv"
    path.write_text(table_text(IML * 100 * G, K0 * IML ** (-K), head))
    with pytest.raises(ValueError, match=match) as err:
        parse_hazard(str(path))
    assert "\n" not in str(err.value) and str(path) in str(err.value)


def test_levels_in_g_declared_as_cm_s2_are_refused(tmp_path):
    path = tmp_path / "site.csv"
    path.write_text(table_text(IML, K0 * IML ** (-K), "pga [cm/s2]"))
    with pytest.raises(ValueError, match=r"highest level is 0\.0051 g, implausibly small"):
        parse_hazard(str(path))


def test_openquake_levels_in_cm_s2_are_refused_or_read_as_declared(tmp_path):
    # the file: poe- levels 4.9–3923, PGA in cm/s² (0.005–4 g)
    iml = np.geomspace(0.005, 4.0, 30)
    poe = -np.expm1(-50.0 * K0 * iml ** (-K))
    in_g = write_openquake(tmp_path / "g.csv", iml, poe)
    cms = write_openquake(tmp_path / "hazard_curve-mean-PGA.csv", iml * 100 * G, poe)
    assert cms.read_text().split("\n")[1].startswith("lon,lat,depth,poe-4.9033250,")
    with pytest.raises(ValueError) as err:
        parse_hazard(str(cms))
    text = str(err.value)
    assert "\n" not in text and str(cms) in text
    assert "OpenQuake writes PGA and SA in g" in text and "hazard.unit: cm/s2" in text
    h, g = parse_hazard({"file": str(cms), "unit": "cm/s2"}), parse_hazard(str(in_g))
    # the same levels but for the file's seven decimals (relative 4e-7 at 0.04 g)
    assert h.unit == "cm/s2" and h.im_g == pytest.approx(g.im_g, rel=1e-6)
    for median, beta in ((0.3, 0.3), (0.8, 0.5)):
        assert mean_annual_frequency(median, beta, h) == pytest.approx(
            mean_annual_frequency(median, beta, g), rel=1e-5)


def curved(im):
    """The shipped example's site 0 (config/hazard/README.md): slope 1.4 at 0.05 g, 3.3 at 2 g."""
    lx = np.log(np.asarray(im) / 0.25)
    return np.exp(-2.2 * lx - 0.262 * lx * lx) / 475.0


def test_a_table_starting_above_the_median_is_counted_and_warned(tmp_path):
    from rocking.fragility.table import read_fragilities
    from rocking.report.risk import risk_section_html
    from rocking.risk.risk_table import BELOW_FIRST_WARN, below_first_warning, risk_table

    im = np.geomspace(0.005, 4.0, 40)
    full = HazardCurve(im, curved(im))
    cut = HazardCurve(im[im >= 1.0], curved(im[im >= 1.0]))  # the table from 1 g
    assert 1.0 <= cut.im_g[0] < 1.05
    frag = pd.DataFrame([("3d", "overturning", 0.11, 3.0, 0.25, 0.3, "ok"),
                         ("3d", "overturning", 0.11, 9.0, 2.5, 0.3, "ok")],
                        columns=["mode", "limit_state", "tan_alpha [-]", "R [m]",
                                 "median_pga_g [g]", "beta [-]", "status"])
    tables = {name: risk_table(read_fragilities(frag), h) for name, h in (("full", full),
                                                                          ("cut", cut))}
    low = {name: t[t["R [m]"] == 3.0].iloc[0] for name, t in tables.items()}
    # the extrapolated first slope makes λ high (by +121 % here) and the share says so
    err = low["cut"]["maf [1/yr]"] / low["full"]["maf [1/yr]"] - 1.0
    assert err > 1.0
    share = low["cut"]["share_below_first [-]"]
    assert share > 0.9 and low["full"]["share_below_first [-]"] < 1e-6
    # the overestimate lies inside the part counted below the first level
    assert low["cut"]["maf [1/yr]"] - low["full"]["maf [1/yr]"] <= share * low["cut"][
        "maf [1/yr]"]
    # the median well inside the table: no share, whichever table
    high = tables["cut"][tables["cut"]["R [m]"] == 9.0].iloc[0]
    assert high["share_below_first [-]"] < BELOW_FIRST_WARN
    warning = below_first_warning(tables["cut"])
    assert warning.startswith("WARNING: 1 of 2 λ rest for more than 1 % on the hazard below "
                              "its first level") and "\n" not in warning
    assert "R = 3 m" in warning and "median 0.25 g" in warning
    assert below_first_warning(tables["full"]) == ""
    csv = tmp_path / "risk.csv"
    tables["cut"].to_csv(csv, index=False)
    assert warning in risk_section_html(csv)


def test_the_command_line_says_the_share_below_the_first_level(tmp_path, capsys):
    from rocking.cli import main

    im = np.geomspace(1.0, 4.0, 12)
    hazard = tmp_path / "from_1g.csv"
    hazard.write_text(table_text(im, curved(im)))
    frag = tmp_path / "fragility.csv"
    pd.DataFrame([("3d", "overturning", 0.11, 3.0, 0.25, 0.3, "ok")],
                 columns=["mode", "limit_state", "tan_alpha [-]", "R [m]", "median_pga_g [g]",
                          "beta [-]", "status"]).to_csv(frag, index=False)
    assert main(["risk", "--fragility", str(frag), "--hazard", str(hazard)]) == 0
    assert "WARNING: 1 of 1 λ rest for more than 1 %" in capsys.readouterr().out


@pytest.mark.parametrize("kind", ["table", "openquake"])
def test_a_byte_order_mark_is_stripped(tmp_path, kind):
    plain, bom = tmp_path / "plain.csv", tmp_path / "bom.csv"
    if kind == "table":
        plain.write_text(table_text(IML, K0 * IML ** (-K), "pga"))
    else:
        write_openquake(plain, IML, power_law_poe())
    bom.write_bytes(b"\xef\xbb\xbf" + plain.read_bytes())
    a, b = parse_hazard(str(plain)), parse_hazard(str(bom))
    assert a.im_g.tolist() == b.im_g.tolist() and a.annual_rate.tolist() == b.annual_rate.tolist()
    assert a.kind == b.kind


def test_a_file_not_in_utf8_is_one_line(tmp_path):
    path = tmp_path / "latin1.csv"
    path.write_bytes("pga [g],annual_rate\n0.1,1e-2\n0.2,1e-3\n# é\n".encode("utf-16"))
    with pytest.raises(ValueError, match="not a UTF-8 text file") as err:
        parse_hazard(str(path))
    assert "\n" not in str(err.value)
