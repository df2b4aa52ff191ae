"""Intensity measures as objects and their horizontal components (rocking.motions.measures).

RotD50/RotD100 of the shipped records are checked against pyrotd's own oscillator (frequency
domain, independent of the time-domain recurrence used here) and against a plain rotation
loop written in the test; the registry against the config schema and the CLI help.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pyrotd
import pytest
import yaml

from rocking.constants import G
from rocking.motions.catalogue import load_record
from rocking.motions.measures import (
    COMPONENTS,
    DEFAULT_COMPONENT,
    MEASURE_PATTERN,
    MEASURES,
    VECTOR_PEAK,
    component_ratio,
    intensity_measure,
    measure_imt,
    parse_component,
    parse_measure,
)
from rocking.motions.response_spectrum import sdof_response

ROOT = Path(__file__).resolve().parents[1]
SHIPPED = ("el-centro-1940", "loma-prieta-corralitos", "northridge-05-sylmar-1994")


@pytest.fixture(scope="module")
def records():
    return {name: load_record(name) for name in SHIPPED}


def _rotated_peaks(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """max_t |x cos θ + y sin θ| for θ = 0..179°, one angle at a time (no pyrotd)."""
    out = []
    for deg in range(180):
        th = math.radians(deg)
        out.append(np.max(np.abs(x * math.cos(th) + y * math.sin(th))))
    return np.array(out)


@pytest.mark.parametrize("name", SHIPPED)
def test_rotd_pga_against_a_rotation_loop(records, name):
    m = records[name]
    peaks = _rotated_peaks(m.ax / G, m.ay / G)
    assert intensity_measure(m, "pga", "rotd100") == pytest.approx(peaks.max(), rel=1e-12)
    assert intensity_measure(m, "pga", "rotd50") == pytest.approx(np.median(peaks), rel=1e-12)
    # RotD100 is the vector peak sampled every degree: at most cos(0.5°) below it
    vp = intensity_measure(m, "pga", "vector_peak")
    assert vp * math.cos(math.radians(0.5)) <= peaks.max() <= vp * (1 + 1e-12)


@pytest.mark.parametrize("name", SHIPPED)
def test_rotd_sa1_against_pyrotd_and_a_rotation_loop(records, name):
    m = records[name]
    # pyrotd's oscillator (frequency domain) is independent of the recurrence: within 1 %
    ref = pyrotd.calc_rotated_spec_accels(m.dt, m.ax / G, m.ay / G, [1.0], 0.05,
                                          percentiles=[50, 100])
    rotd50, rotd100 = (float(v) for v in ref.spec_accel)
    got50 = intensity_measure(m, "sa:1.0", "rotd50")
    got100 = intensity_measure(m, "sa:1.0", "rotd100")
    assert got50 == pytest.approx(rotd50, rel=0.01)
    assert got100 == pytest.approx(rotd100, rel=0.01)
    # the same oscillator as ours, rotated in a loop here: exact
    w2 = (2 * math.pi) ** 2 / G
    ux, _ = sdof_response(m.ax, m.dt, 1.0)
    uy, _ = sdof_response(m.ay, m.dt, 1.0)
    peaks = _rotated_peaks(w2 * ux, w2 * uy)
    assert got50 == pytest.approx(np.median(peaks), rel=1e-12)
    assert got100 == pytest.approx(peaks.max(), rel=1e-12)


def test_as_recorded_components_and_their_order(records):
    m = records["el-centro-1940"]
    px, py = np.max(np.abs(m.ax)) / G, np.max(np.abs(m.ay)) / G
    assert intensity_measure(m, "pga", "geometric_mean") == pytest.approx(math.sqrt(px * py))
    assert intensity_measure(m, "pga", "larger") == pytest.approx(max(px, py))
    for measure in ("pga", "pgv", "sa:1.0"):
        v = {c: intensity_measure(m, measure, c) for c in COMPONENTS}
        assert v["rotd50"] <= v["rotd100"] <= v["vector_peak"] * (1 + 1e-12)
        assert v["larger"] <= v["rotd100"] * (1 + 1e-12)


def test_every_component_is_linear_in_the_scale(records):
    m = records["loma-prieta-corralitos"]
    for c in COMPONENTS:
        for measure in ("pga", "pgv", "sa:0.5"):
            assert intensity_measure(m.scaled(2.5), measure, c) == \
                pytest.approx(2.5 * intensity_measure(m, measure, c), rel=1e-12)
            assert component_ratio(m.scaled(0.3), measure, c, "vector_peak") == \
                pytest.approx(component_ratio(m, measure, c, "vector_peak"), rel=1e-12)


def test_vector_peak_is_the_default_and_the_spectra_pga(records):
    m = records["el-centro-1940"]
    assert DEFAULT_COMPONENT == "vector_peak"
    assert intensity_measure(m, "pga") == m.pga_g  # bit for bit: the tables do not move


def test_unknown_component_is_refused_in_one_line():
    with pytest.raises(ValueError, match=r"^studies.a.component: unknown component 'rotd60'; "
                                         r"known: vector_peak, rotd100, rotd50"):
        parse_component("rotd60", "studies.a.component")
    assert parse_component("RotD50") == "rotd50"


def test_registry_names_units_scaling_and_openquake_imts():
    assert {k: m.unit for k, m in MEASURES.items()} == {"pga": "g", "pgv": "m/s", "sa": "g"}
    assert all(m.scaling == "linear" for m in MEASURES.values())
    assert [measure_imt(x) for x in ("pga", "pgv", "sa:1", "sa:0.25")] == \
        ["PGA", "PGV", "SA(1.0)", "SA(0.25)"]
    assert parse_measure("SA:0.5") == ("sa", 0.5)
    for bad in ("sa", "pga:1", "pgd", "sa:-1"):
        with pytest.raises(ValueError):
            parse_measure(bad)


def _schema():
    return yaml.safe_load((ROOT / "workflow/schemas/config.schema.yaml").read_text())


def _find(node, key):
    """Every value under ``key`` anywhere in a nested mapping."""
    if isinstance(node, dict):
        for k, v in node.items():
            if k == key:
                yield v
            yield from _find(v, key)
    elif isinstance(node, list):
        for v in node:
            yield from _find(v, key)


def test_schema_patterns_and_enums_come_from_the_registries():
    schema = _schema()
    assert schema["definitions"]["intensity_measure"]["pattern"] == MEASURE_PATTERN
    # every other pattern that spells a measure is the registry's
    for pattern in _find(schema, "pattern"):
        if "pgv" in pattern:
            assert pattern == MEASURE_PATTERN
    assert schema["definitions"]["component"]["pattern"] == (
        "(?i)^(" + "|".join(COMPONENTS) + ")$")  # any case: RotD50


def test_cli_help_lists_the_registry():
    from rocking.cli.stripes import COMPONENT_NAMES, measure_help

    assert COMPONENT_NAMES == tuple(COMPONENTS)
    assert COMPONENT_NAMES[0] == DEFAULT_COMPONENT == VECTOR_PEAK  # --component's default
    text = measure_help()
    for kind, m in MEASURES.items():
        assert kind in text and m.unit in text
    for c in COMPONENTS:
        assert c in text


# --- a study in RotD50 under a RotD50 hazard ----------------------------------------------

def _motions():
    from rocking.motions.build import cut
    from rocking.motions.motion import GroundMotion

    out = [cut(load_record(n), 8.0) for n in SHIPPED]
    b = out[1]
    out.append(GroundMotion(0.8 * b.ax, 0.8 * b.ay, b.dt, "lpc-0.8", {}))
    return out


def _store(motions, crit_g):
    """A spectra store of one (mode, limit state, tan α, R) with the critical vector PGAs."""
    import xarray as xr

    dims = ("mode", "limit_state", "motion", "tan_alpha", "R")
    crit = np.asarray(crit_g, dtype=float).reshape(1, 1, len(motions), 1, 1)
    zeros = np.zeros(crit.shape, dtype=bool)
    return xr.Dataset(
        {"pga_crit": (dims, crit / 0.11), "pga_crit_g": (dims, crit),
         "not_reached": (dims, zeros), "plateau": (dims, zeros),
         "non_monotonic": (dims, zeros), "failed": (dims, zeros),
         "requested": (("mode", "limit_state", "tan_alpha"), np.ones((1, 1, 1), bool))},
        coords={"mode": ["3d"], "limit_state": ["overturning"],
                "motion": [m.name for m in motions], "tan_alpha": [0.11], "R": [3.02]},
        attrs={"quantity": '{"name": "exceedance_quantile", "p": 0.1, "w": 0.02}'})


def _analytic(im):
    """λ = exp(−2.2 L − 0.262 L²)/475, L = ln(im/0.25 g), and |dλ/d im|."""
    L = np.log(np.asarray(im, float) / 0.25)
    lam = np.exp(-2.2 * L - 0.262 * L * L) / 475.0
    return lam, lam * (2.2 + 0.524 * L) / np.asarray(im, float)


def _quadrature(median, beta):
    from scipy import integrate, stats

    def f(u):
        im = math.exp(u)
        return stats.norm.cdf((u - math.log(median)) / beta) * _analytic(im)[1] * im

    c = math.log(median)
    return integrate.quad(f, math.log(0.005), math.log(1e3), points=[c - 3 * beta, c,
                          c + 3 * beta], limit=400, epsabs=0.0, epsrel=1e-10)[0]


@pytest.fixture(scope="module")
def rotd50_suite():
    from rocking.study.records import record_table, suite_fragilities

    motions = _motions()
    crit = [0.21, 0.33, 0.12, 0.27]  # critical vector PGA [g] of each motion
    store = _store(motions, crit)
    tables = {c: record_table(store, motions, ["pga", "sa:1.0"], component=c)
              for c in ("rotd50", "vector_peak")}
    both = suite_fragilities(tables, ["pga", "sa:1.0"], None)
    # one row per measure and component (records only), resamples in the same order
    assert list(zip(both["component"], both["measure"], strict=True)) == [
        ("rotd50", "pga"), ("rotd50", "sa:1.0"), ("vector_peak", "pga"),
        ("vector_peak", "sa:1.0")]
    assert both.attrs["bootstrap"][0].shape[0] == len(both)
    assert list(tables["rotd50"]["component"].unique()) == ["rotd50"]
    assert "pga_im_g" in tables["rotd50"] and "pga_im_g" not in tables["vector_peak"]
    both.attrs.clear()  # the resamples are checked above; the rows are what follows needs
    fits = {c: both[both["component"] == c].reset_index(drop=True) for c in tables}
    return motions, crit, fits


def test_rotd50_study_under_a_rotd50_hazard_gives_the_independent_quadrature(rotd50_suite):
    from rocking.fragility.table import read_fragilities
    from rocking.risk.hazard import HazardCurve
    from rocking.risk.risk_table import risk_table

    motions, crit, fits = rotd50_suite
    # independent of the library: each motion's critical RotD50 PGA is its critical scale
    # times its RotD50 PGA by the rotation loop; the lognormal MLE of uncensored data is the
    # mean and the (population) standard deviation of the logs
    own = [np.median(_rotated_peaks(m.ax / G, m.ay / G)) for m in motions]
    x = np.log([c / m.pga_g * o for c, m, o in zip(crit, motions, own, strict=True)])
    median, beta = math.exp(x.mean()), x.std()
    im = np.geomspace(0.005, 20.0, 300)
    hazard = HazardCurve(im, _analytic(im)[0], source="analytic RotD50 curve",
                         component="RotD50")  # any case
    frag = read_fragilities(fits["rotd50"], measure="pga", component="rotd50", bootstrap=False)
    assert frag.component == "rotd50"
    (row,) = risk_table(frag, hazard).to_dict(orient="records")
    assert row["component"] == "rotd50"
    assert row["median_im [g]"] == pytest.approx(median, rel=1e-9)
    assert row["beta [-]"] == pytest.approx(beta, rel=1e-6)
    assert row["maf [1/yr]"] == pytest.approx(_quadrature(median, beta), rel=1e-3)


def test_the_same_fits_in_two_components_differ_by_each_motions_ratio(rotd50_suite):
    motions, crit, fits = rotd50_suite
    a, b = (f[(f["measure"] == "pga") & (f["motions"] == "records")].iloc[0]
            for f in (fits["rotd50"], fits["vector_peak"]))
    ratios = [component_ratio(m, "pga", "rotd50", "vector_peak") for m in motions]
    assert 0.7 < min(ratios) and max(ratios) < 0.9
    # the median moves by the geometric mean of the per-motion ratios
    assert a["median"] / b["median"] == pytest.approx(math.exp(np.mean(np.log(ratios))),
                                                      rel=1e-9)


def test_a_hazard_in_another_component_is_refused_in_one_line(rotd50_suite):
    from rocking.fragility.table import read_fragilities
    from rocking.risk.hazard import parse_hazard
    from rocking.risk.risk_table import risk_table

    _, _, fits = rotd50_suite
    hazard = parse_hazard({"k0": 1e-4, "k": 2.2, "component": "rotd50"})
    frag = read_fragilities(fits["vector_peak"], measure="pga", bootstrap=False)
    with pytest.raises(ValueError) as err:  # no study folder: nothing to refit it from
        risk_table(frag, hazard)
    text = str(err.value)
    assert "\n" not in text and "in the component rotd50" in text
    assert "pga in vector_peak only" in text and "--component" in text
    with pytest.raises(ValueError, match="has no fit in the component geometric_mean"):
        read_fragilities(fits["vector_peak"], measure="pga", component="geometric_mean")
    with pytest.raises(ValueError, match="^hazard: give component .* or im_factor"):
        parse_hazard({"k0": 1e-4, "k": 2.2, "component": "rotd50", "im_factor": 1.2})
    with pytest.raises(ValueError, match="^hazard.component: unknown component 'rot50'"):
        parse_hazard({"file": "x.csv", "component": "rot50"})


def test_a_hazard_file_may_state_its_component(tmp_path):
    from rocking.risk.hazard import parse_hazard

    path = tmp_path / "h.csv"
    path.write_text("# component='RotD50', investigation_time=1\npga,annual_rate\n"
                    "0.1,1e-2\n0.5,1e-4\n")
    assert parse_hazard(str(path)).component == "rotd50"
    assert parse_hazard({"file": str(path)}).component_source == "file"
    declared = parse_hazard({"file": str(path), "component": "larger"})
    assert (declared.component, declared.component_source) == ("larger", "declared")
    assert parse_hazard({"k0": 1e-4, "k": 2.2}).component is None


# --- stripes in a component ---------------------------------------------------------------

def test_stripes_scale_each_motion_to_its_measure_in_the_component(records):
    from rocking.fragility.stripes import from_outcomes, measure_ratio

    m = records["el-centro-1940"]
    tan_alpha, x = 0.2, 1.5
    for measure, component in (("sa:1.0", "rotd50"), ("pga", "geometric_mean"),
                               ("pga", "vector_peak")):
        ratio = measure_ratio(m, measure, component)  # PGA/(g tan α) per stripe unit
        scaled = m.scaled(x * ratio * tan_alpha / m.pga_g)
        assert intensity_measure(scaled, measure, component) == \
            pytest.approx(x * tan_alpha, rel=1e-12)
    assert measure_ratio(m, "pga", "vector_peak") == 1.0
    r = from_outcomes([1.0, 2.0], ["overturning"], ["a", "b"],
                      np.array([[[False], [False]], [[True], [False]]]),
                      np.zeros((2, 2), bool), tan_alpha=0.2, measure="sa:1.0",
                      component="rotd50")
    frame = r.summary_frame()
    assert list(frame["component"]) == ["rotd50"] and list(frame["measure"]) == ["sa:1.0"]
    # PGA in another component than the spectra's is not the spectra's PGA
    r = from_outcomes([1.0, 2.0], ["overturning"], ["a", "b"],
                      np.array([[[False], [False]], [[True], [False]]]),
                      np.zeros((2, 2), bool), tan_alpha=0.2, component="rotd50")
    assert np.isnan(r.summary_frame()["median_pga_g"]).all()


def test_a_study_component_reaches_its_stripes_and_their_store_hash():
    from rocking.config.study import StudySpec

    cfg = yaml.safe_load((ROOT / "config/config.yaml").read_text())
    name = next(s for s, v in cfg["studies"].items() if v.get("stripes"))
    base = StudySpec.from_config(cfg, name)
    assert base.component == "vector_peak" and base.stripes.component == "vector_peak"
    assert "component" not in base.stripes.to_attrs()  # the committed stores keep their hash
    cfg["studies"][name]["component"] = "rotd50"
    other = StudySpec.from_config(cfg, name)
    assert other.component == "rotd50" and other.stripes.component == "rotd50"
    assert other.stripes.digest != base.stripes.digest
    assert other.spectra.digest == base.spectra.digest  # the spectra are the vector PGA
    cfg["studies"][name]["component"] = "rot50"
    with pytest.raises(ValueError, match=rf"^studies.{name}.component: unknown component"):
        StudySpec.from_config(cfg, name)


def test_cli_risk_takes_the_hazard_component_or_refuses(rotd50_suite, tmp_path, capsys):
    from rocking.cli import main

    _, _, fits = rotd50_suite
    both = tmp_path / "suite_fragility.csv"
    import pandas as pd

    pd.concat([fits["vector_peak"], fits["rotd50"]]).to_csv(both, index=False)
    out = tmp_path / "r.csv"
    assert main(["risk", "--fragility", str(both), "--hazard", "1e-4,2.2", "--component",
                 "rotd50", "-o", str(out)]) == 0
    table = pd.read_csv(out)
    assert set(table["component"]) == {"rotd50"}
    median = fits["rotd50"].query("measure == 'pga' and motions == 'records'")["median"]
    assert table["median_im [g]"].iloc[0] == pytest.approx(float(median.iloc[0]), rel=1e-5)
    only = tmp_path / "vp.csv"
    fits["vector_peak"].to_csv(only, index=False)
    assert main(["risk", "--fragility", str(only), "--hazard", "1e-4,2.2", "--component",
                 "rotd50"]) == 2
    # the tables beside it have no record of what made them: said in a note, not the refusal
    err = [line for line in capsys.readouterr().err.strip().splitlines()
           if "no record of what made" not in line]
    assert len(err) == 1 and "in the component rotd50" in err[0]
    assert "no motion measures to refit it" in err[0]
    assert main(["risk", "--fragility", str(only), "--hazard", "1e-4,2.2", "--component",
                 "rotd50", "--im-factor", "1.2"]) == 2
    assert "not both" in capsys.readouterr().err


def test_the_vector_peak_is_named_in_one_place():
    """Library code compares with and defaults to the constants (VECTOR_PEAK,
    DEFAULT_COMPONENT), never the spelled name: it is written once, in the registry's module
    (and in the command line's light mirror of the registry, held equal above)."""
    import ast

    spelled = []
    for path in sorted((ROOT / "src" / "rocking").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Constant) and node.value == VECTOR_PEAK:
                spelled.append(str(path.relative_to(ROOT / "src" / "rocking")))
    assert spelled == ["cli/stripes.py", "motions/measures.py"]
