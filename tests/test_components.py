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
    assert schema["definitions"]["component"]["enum"] == list(COMPONENTS)


def test_cli_help_lists_the_registry():
    from rocking.cli.stripes import measure_help

    text = measure_help()
    for kind, m in MEASURES.items():
        assert kind in text and m.unit in text
    for c in COMPONENTS:
        assert c in text
