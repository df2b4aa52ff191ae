"""NetCDF ensembles: lossless round trip, layout of docs/design.md, bad input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from rocking.motions.catalogue import load_record
from rocking.motions.ensemble_io import ensemble_attrs, load_ensemble, save_ensemble
from rocking.motions.motion import GroundMotion
from rocking.motions.principal import to_principal_axes


def _motions() -> list[GroundMotion]:
    record, _ = to_principal_axes(load_record("el-centro-1940"))
    rng = np.random.default_rng(5)
    # Values with full 53-bit mantissas, extreme exponents, and different lengths and dt.
    a = rng.standard_normal(301) * 10.0 ** rng.uniform(-300, 300, 301)
    b = np.nextafter(rng.standard_normal(301), np.inf)
    other = GroundMotion(a, b, 0.005, "syn-001", {"seed": np.int64(3), "tags": ("a", "é–ü"),
                                                  "fc_hz": np.float64(0.0946)})
    one_sided = GroundMotion(np.arange(7.0), None, 0.02, "unidirectional", {})
    return [record, other, one_sided]


def test_round_trip_is_lossless(tmp_path: Path) -> None:
    motions = _motions()
    path = save_ensemble(tmp_path / "motions" / "el-centro.nc", motions, attrs={"n": 2})
    loaded = load_ensemble(path)
    assert [m.name for m in loaded] == [m.name for m in motions]
    for got, want in zip(loaded, motions, strict=True):
        assert got.npts == want.npts
        assert got.dt == want.dt
        np.testing.assert_array_equal(got.ax, want.ax)  # bit for bit
        np.testing.assert_array_equal(got.ay, want.ay)
        # Metadata comes back as JSON would give it (tuples as lists, numpy as Python).
        assert got.metadata == json.loads(json.dumps(
            want.metadata, default=lambda o: o.item() if hasattr(o, "item") else list(o)))
    assert loaded[1].metadata["tags"] == ["a", "é–ü"]
    assert loaded[0].metadata["processing"][-1]["step"] == "rotation"
    assert ensemble_attrs(path) == {"n": 2}


def test_layout_follows_design(tmp_path: Path) -> None:
    motions = _motions()
    path = save_ensemble(tmp_path / "e.nc", motions)
    with xr.open_dataset(path) as ds:
        assert ds["ax"].dims == ("motion", "time") and ds["ay"].dims == ("motion", "time")
        assert ds.sizes["time"] == max(m.npts for m in motions)
        assert list(ds["npts"].values) == [m.npts for m in motions]
        assert list(ds["dt"].values) == [m.dt for m in motions]
        assert list(ds["motion"].values) == [m.name for m in motions]
        # Zero padding after each motion's own end.
        n1 = motions[1].npts
        assert not np.any(ds["ax"].values[1, n1:]) and not np.any(ds["ay"].values[1, n1:])
        json.loads(str(ds["metadata"].values[0]))
    assert not list(tmp_path.glob(".*.tmp"))  # the temporary file is gone


def test_bad_input(tmp_path: Path) -> None:
    m = GroundMotion(np.ones(3), np.ones(3), 0.01, "same")
    with pytest.raises(ValueError, match="unique"):
        save_ensemble(tmp_path / "e.nc", [m, m])
    with pytest.raises(ValueError, match="empty"):
        save_ensemble(tmp_path / "e.nc", [])
    with pytest.raises(ValueError, match=r"motions\[1\]"):
        save_ensemble(tmp_path / "e.nc", [m, np.ones(3)])
    bad = GroundMotion(np.ones(3), np.ones(3), 0.01, "bad", {"x": object()})
    with pytest.raises(ValueError, match="'bad'"):
        save_ensemble(tmp_path / "e.nc", [bad])
    assert not (tmp_path / "e.nc").exists()
    xr.Dataset({"ax": ("t", np.zeros(3))}).to_netcdf(tmp_path / "other.nc")
    with pytest.raises(ValueError, match="missing variables"):
        load_ensemble(tmp_path / "other.nc")
    with pytest.raises(FileNotFoundError):
        load_ensemble(tmp_path / "absent.nc")


def test_a_vertical_component_is_refused_not_dropped(tmp_path):
    """The ensemble format holds the horizontal pair: a motion with a vertical component is
    refused in one line (saving it would silently change every answer that uses az)."""
    import numpy as np
    import pytest

    from rocking.motions.ensemble_io import load_ensemble, save_ensemble
    from rocking.motions.motion import GroundMotion

    t = np.arange(200) * 0.01
    m = GroundMotion(np.sin(t), np.cos(t), 0.01, "v", az=0.5 * np.sin(3 * t))
    with pytest.raises(ValueError, match="'v' has a vertical component"):
        save_ensemble(tmp_path / "e.nc", [m])
    assert not (tmp_path / "e.nc").exists()
    save_ensemble(tmp_path / "e.nc", [m.horizontal()])
    (back,) = load_ensemble(tmp_path / "e.nc")
    np.testing.assert_array_equal(back.ax, m.ax)
    assert back.az is None
