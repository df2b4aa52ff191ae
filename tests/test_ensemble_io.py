"""NetCDF ensembles: lossless round trip, layout of docs/design.md, bad input."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from rocking.motions.catalogue import RECORDS, _package_file, load_record
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
    assert not list(tmp_path.glob(".*"))  # the temporary file is gone


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


def _vertical_motions() -> list[GroundMotion]:
    """A record with its vertical (El Centro's UP file, rotated), a horizontal pair (as a
    synthetic pair is), and a shorter motion whose vertical is all zeros (not None)."""
    record, _ = to_principal_axes(load_record("el-centro-1940", vertical=True))
    t = np.arange(301) * 0.01
    pair = GroundMotion(np.sin(t), np.cos(2 * t), 0.01, "syn-001", {"generator": "rdk"})
    flat = GroundMotion(np.sin(t[:50]), None, 0.01, "flat", {}, np.zeros(50))
    return [record, pair, flat]


def test_vertical_component_round_trips_bit_for_bit(tmp_path):
    """The format holds az where a motion has one, and None stays None (a synthetic pair
    is horizontal); every motion reads back with the samples_sha256 it was written with."""
    motions = _vertical_motions()
    assert motions[0].has_vertical
    path = save_ensemble(tmp_path / "v.nc", motions)
    loaded = load_ensemble(path)
    for got, want in zip(loaded, motions, strict=True):
        assert (got.az is None) == (want.az is None), want.name
        if want.az is not None:
            np.testing.assert_array_equal(got.az, want.az)
        assert got.samples_sha256 == want.samples_sha256
    with xr.open_dataset(path) as ds:
        assert ds["az"].attrs["units"] == "m s-2"
        assert list(ds["has_az"].values) == [1, 0, 1]
        assert "vertical component" in str(ds["processing"].values[0])


def test_horizontal_ensembles_keep_their_layout(tmp_path):
    """A file of horizontal motions has no az: its bytes are what they always were, and
    an older reader's layout is the layout."""
    path = save_ensemble(tmp_path / "h.nc", _motions())
    with xr.open_dataset(path) as ds:
        assert "az" not in ds and "has_az" not in ds
    assert all(m.az is None for m in load_ensemble(path))


def test_the_motions_digest_covers_the_vertical(tmp_path):
    """Two ensembles that differ only in the last bit of one vertical sample are two files
    with two digests; a file whose az was changed after it was made is refused."""
    from rocking.motions.ensemble_io import MotionsDigestError, digest_path

    motions = _vertical_motions()
    record = motions[0]
    az = record.az.copy()
    k = int(np.argmax(np.abs(az)))
    az[k] = np.nextafter(az[k], np.inf)
    nudged = GroundMotion(record.ax, record.ay, record.dt, record.name, record.metadata, az)
    a = save_ensemble(tmp_path / "a.nc", motions)
    b = save_ensemble(tmp_path / "b.nc", [nudged, *motions[1:]])
    assert digest_path(a).read_text().split()[0] != digest_path(b).read_text().split()[0]
    digest_path(b).write_text(digest_path(a).read_text().replace("a.nc", "b.nc"))
    with pytest.raises(MotionsDigestError, match="b.nc"):
        load_ensemble(b)


def test_load_motion_of_an_ensemble_keeps_its_vertical_and_refuses_one_for_a_synthetic_pair(
        tmp_path):
    """A motion of an ensemble comes as stored (the record with its vertical); asking for
    the vertical of a synthetic pair, whose horizontals are simulated, is one line."""
    from rocking.motions.source import load_motion

    motions = _vertical_motions()
    path = save_ensemble(tmp_path / "v.nc", motions)
    got = load_motion(ensemble=path)
    assert got.samples_sha256 == motions[0].samples_sha256 and got.has_vertical
    assert load_motion(ensemble=path, vertical=True).samples_sha256 == got.samples_sha256
    assert load_motion(ensemble=path, motion="syn-001").az is None
    with pytest.raises(ValueError, match="'syn-001' .* is a synthetic pair, whose horizontals "
                                         "are simulated: it has no vertical component"):
        load_motion(ensemble=path, motion="syn-001", vertical=True)
    with pytest.raises(ValueError, match="not both"):
        load_motion(ensemble=path, motion="syn-001", files=["z.AT2"])


def test_a_motions_file_does_not_depend_on_where_its_records_lay(tmp_path):
    """The same record read from two folders gives the same motions file, byte for byte (it
    held each component's absolute path before: a clone elsewhere wrote other bytes)."""
    source = RECORDS["el-centro-1940"]
    written = []
    for where in ("a", "b/deeper"):
        folder = tmp_path / where
        folder.mkdir(parents=True)
        paths = [shutil.copy(_package_file(source, f), folder) for f in source.files]
        motion = load_record("el-centro-1940", paths)
        written.append(save_ensemble(tmp_path / f"{where.replace('/', '-')}.nc",
                                     [motion]).read_bytes())
        assert str(folder) not in json.dumps(motion.metadata)
    assert written[0] == written[1]
