"""Every units string is a valid CF (UDUNITS-2) unit; outputs carry units and long_name."""

from __future__ import annotations

import cf_units
import numpy as np
import pytest

from rocking.motions.ensemble_io import open_netcdf, save_ensemble
from rocking.motions.motion import GroundMotion
from rocking.motions.source import identity, load_motion, process_motion
from rocking.units import QUANTITIES, header, strip_units


@pytest.mark.parametrize("name", sorted(QUANTITIES))
def test_units_parse_as_udunits(name):
    unit = cf_units.Unit(QUANTITIES[name][0])
    if QUANTITIES[name][1] == "g":  # accelerations in g are g = 9.80665 m/s²
        assert unit.convert(1.0, "m s-2") == pytest.approx(9.80665, rel=1e-15)


def test_headers_round_trip():
    assert header("R") == "R [m]" and header("mode") == "mode"
    assert strip_units(header("pga_crit")) == "pga_crit"


def test_ensemble_file_says_where_each_motion_comes_from(tmp_path):
    rec = load_motion("el-centro-1940")
    processed = process_motion(rec, rotation="auto", highpass="oscillator", max_duration=60)
    t = np.arange(0, 2, 0.01)
    other = GroundMotion(np.sin(t), np.cos(t), 0.01, "plain")
    path = save_ensemble(tmp_path / "e.nc", [processed, other])
    with open_netcdf(path) as ds:
        for name in ds.variables:
            assert {"units", "long_name"} <= set(ds[name].attrs), name
        first = ds.sel(motion="el-centro-1940")
        assert str(first["source_record"].values) == "el-centro-1940"
        text = str(first["processing"].values)
        assert "rotated -70.46 deg" in text and "high-passed (oscillator, fc 0.09465 Hz)" in text
        assert "cut to 60 s" in text and "zero-padded" in text
        assert float(first["PGA"]) == pytest.approx(processed.pga_g, rel=1e-15)
        assert float(first["rotation_deg"]) == pytest.approx(-70.46, abs=0.01)
        assert np.isnan(float(ds.sel(motion="plain")["highpass_fc_hz"]))
    assert identity(rec)["processing"].endswith("as recorded")
