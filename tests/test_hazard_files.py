"""Hazard files as the tools write them (issue 29): OpenQuake CSVs whose lowest levels read
PoE = 1 with six significant digits, SA(T) curves, plain two-column tables, and the bad inputs
refused in one line naming the file."""

from __future__ import annotations

import logging
import math

import numpy as np
import pytest

from rocking.risk.annual_frequency import annual_frequency_parts, mean_annual_frequency
from rocking.risk.hazard import HazardCurve, imt_measure, parse_hazard, same_measure


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
    assert h.imt == "SA(1.0)" and h.measure == "sa:1"
    assert same_measure(h.measure, "sa:1.0") and not same_measure(h.measure, "pga")
    assert not same_measure("sa:1.0", "sa:0.3")
    assert imt_measure("PGA") == "pga" and imt_measure("sa:0.30") == "sa:0.3"


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
    assert HazardCurve.from_file(path).measure == "sa:1"


@pytest.mark.parametrize("text, match", [
    ("pga,annual_rate\n", "a header of two columns"),
    ("pga,annual_rate\n0.1,0.01\n", "at least 2 levels"),
    ("pga,annual_rate\n0.1,0.01\n0.2,0.02\n", "must not increase"),
    ("pga,annual_rate\n0.2,0.01\n0.1,0.001\n", "strictly increasing"),
    ("pgv,annual_rate\n0.1,0.01\n0.2,0.001\n", "not supported"),
    ("pga,frequency\n0.1,0.01\n0.2,0.001\n", "annual_rate .* or poe"),
    ("pga,annual_rate,poe\n0.1,0.01,0.1\n", "a header of two columns"),
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
    assert h.measure == "sa:1" and h.imt == "SA(1.0)"
    assert parse_hazard("1e-4,2", measure="sa:0.5").imt == "SA(0.5)"


def test_openquake_non_monotonic_names_file_and_levels(tmp_path):
    path = write_openquake(tmp_path / "h.csv", [0.1, 0.2, 0.4], [0.5, 0.1, 0.2])
    with pytest.raises(ValueError, match=r"must not increase .* 0\.1 at 0\.2 g and 0\.2 at "
                                         r"0\.4 g") as err:
        HazardCurve.from_openquake_csv(path)
    assert str(path) in str(err.value) and "\n" not in str(err.value)
