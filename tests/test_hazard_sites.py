"""Hazard files as regional runs write them (issue 38, item 3): an OpenQuake hazard_curve CSV
of several sites, one chosen by its custom_site_id or by the nearest lon/lat within a stated
distance (great-circle), refused without a choice; the file's kind read, a quantile used only
when the configuration names it; site and kind carried into risk.csv and the report."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from rocking.cli import main
from rocking.config.checks import schema_error
from rocking.fragility.table import read_fragilities
from rocking.report.risk import risk_section_html
from rocking.risk.annual_frequency import mean_annual_frequency
from rocking.risk.hazard import MAX_DISTANCE_KM, HazardCurve, parse_hazard
from rocking.risk.risk_table import risk_table

ROOT = Path(__file__).resolve().parents[1]


def table() -> pd.DataFrame:
    """A small fragility table as `to_frame` writes it (titles with units)."""
    rows = [("3d", "overturning", 0.2, 2.0, 0.31, 0.22, "ok"),
            ("3d", "tilt:1/3", 0.2, 2.0, 0.25, 0.12, "ok"),
            ("2d-x", "overturning", 0.2, 2.0, 0.41, 0.26, "ok")]
    return pd.DataFrame(rows, columns=["mode", "limit_state", "tan_alpha [-]", "R [m]",
                                       "median_pga_g [g]", "beta [-]", "status"])

IML = np.geomspace(0.005, 4.0, 30)
K = 2.4
# custom_site_id, lon, lat [deg], k0 [1/yr] of λ = k0 im^-K: three sites near Athens
SITES = [("ATH", 23.7275, 37.9838, 2e-4), ("PIR", 23.6470, 37.9420, 1e-4),
         ("ELE", 23.5380, 38.0410, 5e-5)]
YEARS = 50.0


def write_sites(path, sites=SITES, *, kind="mean", ids=True):
    """An OpenQuake hazard_curve CSV of several sites as the engine writes it: the quoted
    comment line, custom_site_id first (where the site model has one), lon, lat, depth,
    poe-<iml> with seven decimals, probabilities in YEARS with %.6E."""
    head = ",".join(f"poe-{x:.7f}" for x in IML)
    lines = [f"#,,,,,\"generated_by='OpenQuake engine 3.23.1', start_date='2026-11-27T10:00:00', "
             f"checksum=3141, kind='{kind}', investigation_time={YEARS}, imt='PGA'\"",
             ("custom_site_id," if ids else "") + f"lon,lat,depth,{head}"]
    for sid, lon, lat, k0 in sites:
        poe = -np.expm1(-YEARS * k0 * IML ** (-K))
        lines.append((f"{sid}," if ids else "") + f"{lon:.5f},{lat:.5f},0.00000,"
                     + ",".join(f"{p:.6E}" for p in poe))
    path.write_text("\n".join(lines) + "\n")
    return path


def expected_rates(k0):
    """The annual rates a reader must find for a site: the file's rounded poe, −ln(1 − poe)/T."""
    poe = np.array([float(f"{p:.6E}") for p in -np.expm1(-YEARS * k0 * IML ** (-K))])
    iml = np.array([float(f"{x:.7f}") for x in IML])
    keep = (poe > 0) & (poe < 1)
    return iml[keep], -np.log1p(-poe[keep]) / YEARS


def haversine_km(lon1, lat1, lon2, lat2):
    """Great-circle distance by the spherical law of cosines (not the reader's haversine)."""
    p1, p2, dl = map(math.radians, (lat1, lat2, lon2 - lon1))
    c = math.sin(p1) * math.sin(p2) + math.cos(p1) * math.cos(p2) * math.cos(dl)
    return 6371.0 * math.acos(min(1.0, c))


@pytest.fixture
def three(tmp_path):
    return write_sites(tmp_path / "hazard_curve-mean-PGA_77.csv")


@pytest.mark.parametrize("i", range(3))
def test_a_site_chosen_by_id_and_by_lon_lat_is_that_row(three, i):
    sid, lon, lat, k0 = SITES[i]
    by_id = parse_hazard({"file": str(three), "site": {"id": sid}})
    # 1 km off the site, in latitude: the nearest is still this one
    near = parse_hazard({"file": str(three), "site": {"lon": lon, "lat": lat + 0.009}})
    im, lam = expected_rates(k0)
    for h in (by_id, near):
        assert h.im_g.tolist() == im.tolist()
        assert h.annual_rate == pytest.approx(lam, rel=1e-12)
        assert f"id {sid}" in h.site and h.kind == "mean"
        # λ against the closed form of the site's own power law (Cornell et al. 2002)
        closed = k0 * 0.4 ** (-K) * math.exp(0.5 * (K * 0.3) ** 2)
        assert mean_annual_frequency(0.4, 0.3, h) == pytest.approx(closed, rel=0.01)
    assert f"{haversine_km(lon, lat, lon, lat + 0.009):.3g} km" in near.site


def test_several_sites_without_site_is_one_line_listing_them(three):
    with pytest.raises(ValueError) as err:
        parse_hazard(str(three))
    text = str(err.value)
    assert "\n" not in text and str(three) in text and "has 3 sites" in text
    for sid, lon, lat, _ in SITES:
        assert f"id {sid} (lon {lon:g}, lat {lat:g})" in text
    assert "site: {id: ...}" in text and "--site-lon" in text


def test_a_long_list_of_sites_is_cut_with_its_count(tmp_path):
    many = [(f"S{i}", 20.0 + 0.1 * i, 38.0, 1e-4) for i in range(12)]
    path = write_sites(tmp_path / "h.csv", many)
    with pytest.raises(ValueError, match=r"has 12 sites: .*id S4 .*\.\.\. \(7 more\)$") as err:
        parse_hazard(str(path))
    assert "S5" not in str(err.value)


def test_no_site_within_the_distance_names_the_nearest(three):
    sid, lon, lat, _ = SITES[0]
    far_lat = lat + 0.1  # 11 km north of ATH
    d = haversine_km(lon, lat, lon, far_lat)
    assert d > MAX_DISTANCE_KM
    with pytest.raises(ValueError) as err:
        parse_hazard({"file": str(three), "site": {"lon": lon, "lat": far_lat}})
    text = str(err.value)
    assert "\n" not in text and str(three) in text
    assert f"no site within {MAX_DISTANCE_KM:g} km of lon {lon:g}, lat {far_lat:g}" in text
    assert f"nearest is id {sid}" in text and f"{d:.3g} km away" in text
    # a stated distance accepts it
    h = parse_hazard({"file": str(three),
                      "site": {"lon": lon, "lat": far_lat, "max_distance_km": 12}})
    assert f"id {sid}" in h.site


@pytest.mark.parametrize("site, match", [
    ({"id": "THE"}, r"site id 'THE' is not in the file \(its ids: ATH, PIR, ELE\)"),
    (3, r"site row 3 is not in the file: it has 3 site\(s\), rows 0\.\.2"),
    ({"lon": 23.7, "lat": 95.0}, "not a point on Earth"),
    ({"lon": 23.7}, r"site must be .* got keys \['lon'\]"),
    ("ATH", "site must be"),
])
def test_a_site_not_in_the_file_is_one_line(three, site, match):
    with pytest.raises(ValueError, match=match) as err:
        parse_hazard({"file": str(three), "site": site})
    assert "\n" not in str(err.value) and str(three) in str(err.value)


def test_an_id_asked_of_a_file_without_ids_is_refused(tmp_path):
    path = write_sites(tmp_path / "h.csv", ids=False)
    with pytest.raises(ValueError, match="has no custom_site_id column"):
        parse_hazard({"file": str(path), "site": {"id": "ATH"}})
    h = parse_hazard({"file": str(path), "site": 1})
    assert h.site == f"row 1 (lon {SITES[1][1]:g}, lat {SITES[1][2]:g})"


def test_a_quantile_is_used_only_when_named(tmp_path):
    path = write_sites(tmp_path / "hazard_curve-quantile_0.85-PGA.csv", kind="quantile-0.85")
    with pytest.raises(ValueError) as err:
        parse_hazard({"file": str(path), "site": {"id": "ATH"}})
    text = str(err.value)
    assert "\n" not in text and str(path) in text
    assert "'quantile-0.85' hazard curve, not the mean" in text
    assert "hazard.kind: quantile-0.85" in text
    h = parse_hazard({"file": str(path), "site": {"id": "ATH"}, "kind": "quantile-0.85"})
    assert h.kind == "quantile-0.85"
    with pytest.raises(ValueError, match="holds the 'quantile-0.85' hazard curve, the hazard "
                                         "entry names kind 'quantile-0.15'"):
        parse_hazard({"file": str(path), "site": {"id": "ATH"}, "kind": "quantile-0.15"})
    with pytest.raises(ValueError, match="kind must be mean, quantile-<q>"):
        parse_hazard({"file": str(path), "site": {"id": "ATH"}, "kind": "quantile-85"})
    # a mean file with kind: mean named is the mean
    mean = write_sites(tmp_path / "m.csv")
    assert parse_hazard({"file": str(mean), "site": 0, "kind": "mean"}).kind == "mean"


def test_a_realisation_is_not_the_mean_either(tmp_path):
    path = write_sites(tmp_path / "h.csv", kind="rlz-003")
    with pytest.raises(ValueError, match="'rlz-003' hazard curve, not the mean"):
        parse_hazard({"file": str(path), "site": 0})
    assert parse_hazard({"file": str(path), "site": 0, "kind": "rlz-003"}).kind == "rlz-003"


def test_site_and_kind_reach_risk_csv_and_the_report(tmp_path):
    path = write_sites(tmp_path / "h.csv", kind="quantile-0.85")
    h = parse_hazard({"file": str(path), "site": {"id": "PIR"}, "kind": "quantile-0.85",
                      "im_factor": 1.2})
    assert h.site.startswith("id PIR") and h.kind == "quantile-0.85"  # scaled keeps them
    risk = risk_table(read_fragilities(table()), h)
    assert set(risk["hazard_site"]) == {h.site} and set(risk["hazard_kind"]) == {"quantile-0.85"}
    csv = tmp_path / "risk.csv"
    risk.to_csv(csv, index=False)
    html = risk_section_html(csv, hazard=str(path))
    assert f"site {h.site}" in html and "kind quantile-0.85" in html


def test_the_command_line_chooses_site_and_kind(tmp_path, capsys):
    path = write_sites(tmp_path / "h.csv", kind="quantile-0.85")
    frag = tmp_path / "fragility.csv"
    table().to_csv(frag, index=False)
    out = tmp_path / "risk.csv"
    base = ["risk", "--fragility", str(frag), "--hazard", str(path), "--component",
            "vector_peak"]
    assert main([*base, "--site-id", "ELE"]) == 2
    assert "not the mean" in capsys.readouterr().err
    assert main([*base, "--kind", "quantile-0.85"]) == 2
    # a table of one's own (no record of what made it) is said in a note beside the refusal
    err = "\n".join(line for line in capsys.readouterr().err.strip().splitlines()
                    if "no record of what made" not in line)
    assert "has 3 sites" in err and len(err.splitlines()) == 1
    assert main([*base, "--site-lon", str(SITES[2][1]), "--site-lat", str(SITES[2][2]),
                 "--kind", "quantile-0.85", "-o", str(out)]) == 0
    printed = capsys.readouterr().out
    written = pd.read_csv(out)
    assert set(written["hazard_kind"]) == {"quantile-0.85"}
    assert all(s.startswith("id ELE") for s in written["hazard_site"])
    assert "id ELE" in printed and "quantile-0.85" in printed
    assert main([*base, "--site-id", "ELE", "--site", "1", "--kind", "quantile-0.85"]) == 2
    assert "give one of --site-id" in capsys.readouterr().err
    assert main([*base, "--site-lon", "23.5", "--kind", "quantile-0.85"]) == 2
    assert "--site-lon and --site-lat go together" in capsys.readouterr().err


def test_the_schema_takes_the_site_forms_and_refuses_others():
    schema = yaml.safe_load((ROOT / "workflow/schemas/config.schema.yaml").read_text())
    cfg = yaml.safe_load((ROOT / "config/config.yaml").read_text())
    study = next(iter(cfg["studies"]))
    good = [{"file": "h.csv", "site": {"id": "ATH"}, "kind": "quantile-0.85"},
            {"file": "h.csv", "site": {"lon": 23.7, "lat": 37.9, "max_distance_km": 2}},
            {"file": "h.csv", "site": 2, "unit": "cm/s2"}]
    bad = [({"file": "h.csv", "site": {"lon": 23.7}}, "site"),
           ({"file": "h.csv", "kind": "median"}, "kind"),
           ({"file": "h.csv", "unit": "mg"}, "unit")]
    for hazard in good:
        cfg["studies"][study]["hazard"] = hazard
        assert schema_error(cfg, schema) is None, hazard
    for hazard, key in bad:
        cfg["studies"][study]["hazard"] = hazard
        text = schema_error(cfg, schema)
        assert text is not None and f"studies.{study}.hazard.{key}=" in text, (hazard, text)


def test_the_shipped_example_names_its_site():
    cfg = yaml.safe_load((ROOT / "config/config.yaml").read_text())
    spec = next(s["hazard"] for s in cfg["studies"].values() if "hazard" in s)
    h = parse_hazard({**spec, "file": str(ROOT / spec["file"])})
    assert h.site == "row 0 (lon 0, lat 0), 0 km from lon 0, lat 0"
    assert h.annual_rate == pytest.approx(
        HazardCurve.from_openquake_csv(ROOT / spec["file"], site=0).annual_rate)


def test_the_dry_run_refuses_a_file_of_sites_without_site_and_takes_one_with_it(tmp_path):
    """Before any work: the workflow parses each study's hazard at parse time."""
    import json

    from test_workflow import TARGETS, TINY, snakemake

    path = write_sites(tmp_path / "hazard_curve-mean-PGA.csv")
    runs = {}
    for name, hazard in (("bare", str(path)),
                         ("chosen", {"file": str(path), "site": {"id": "PIR"}})):
        cfg = json.loads(json.dumps(TINY))
        cfg["studies"]["tiny"]["hazard"] = hazard
        cfg_path = tmp_path / f"{name}.yaml"
        cfg_path.write_text(yaml.safe_dump(cfg))
        runs[name] = snakemake(tmp_path, "-n", *TARGETS, configfile=cfg_path, check=False)
    bare = runs["bare"].stdout + runs["bare"].stderr
    assert runs["bare"].returncode != 0
    assert f"studies.tiny.hazard: {path} has 3 sites: choose one" in bare
    assert runs["chosen"].returncode == 0, runs["chosen"].stderr[-2000:]
    assert not (tmp_path / "results").exists()


def test_a_hazard_file_is_read_once_per_parse(three, monkeypatch):
    """Issue 40: the file was read twice by from_file (once to tell the format, once to
    parse); its format is told from its first lines, then site, kind and unit come from the
    one parse."""
    from rocking.risk import hazard as module

    calls = []
    real = module._text
    monkeypatch.setattr(module, "_text", lambda path: calls.append(path) or real(path))
    h = parse_hazard({"file": str(three), "site": {"id": "ELE"}, "im_factor": 1.1})
    assert len(calls) == 1 and h.site.startswith("id ELE") and h.kind == "mean"


def test_a_table_says_its_kind_in_a_comment_and_takes_no_site(tmp_path):
    path = tmp_path / "p85.csv"
    path.write_text("# kind=quantile-0.85\npga [g],annual_rate\n0.1,1e-2\n0.2,2e-3\n0.4,3e-4\n")
    with pytest.raises(ValueError, match="'quantile-0.85' hazard curve, not the mean"):
        parse_hazard(str(path))
    assert parse_hazard({"file": str(path), "kind": "quantile-0.85"}).kind == "quantile-0.85"
    with pytest.raises(ValueError, match="site applies to an OpenQuake hazard-curve CSV"):
        parse_hazard({"file": str(path), "kind": "quantile-0.85", "site": {"id": "ATH"}})
    # a table that states no kind takes the one the entry declares
    path.write_text("pga,annual_rate\n0.1,1e-2\n0.2,2e-3\n")
    assert parse_hazard({"file": str(path), "kind": "quantile-0.5"}).kind == "quantile-0.5"
    assert parse_hazard(str(path)).kind == ""


def test_the_risk_rule_writes_site_kind_and_warning(tmp_path):
    """What workflow/scripts/risk.py runs: risk.csv's columns and the log's summary."""
    from rocking.risk.exports import write_risk_outputs

    path = write_sites(tmp_path / "h.csv", kind="quantile-0.85")
    h = parse_hazard({"file": str(path), "site": {"lon": SITES[0][1], "lat": SITES[0][2]},
                      "kind": "quantile-0.85", "component": "vector_peak"})
    frag = tmp_path / "fragility.csv"
    table().to_csv(frag, index=False)
    summary = write_risk_outputs(frag, h, nrml=tmp_path / "f.xml", pelicun=tmp_path / "f.csv",
                                 table=tmp_path / "risk.csv", search_upper=20.0, study="s")
    risk = pd.read_csv(tmp_path / "risk.csv", keep_default_na=False)
    assert set(risk["hazard_site"]) == {h.site} and h.site.startswith("id ATH")
    assert set(risk["hazard_kind"]) == {"quantile-0.85"}
    assert summary["hazard_site"] == h.site and summary["hazard_kind"] == "quantile-0.85"
    assert summary["hazard_unit"] == "g" and "quantile-0.85" in summary["hazard"]
    # this hazard's levels reach down to 0.005 g: nothing rests below them
    assert summary["below_first_warning"] == ""
    assert (risk["share_below_first [-]"].astype(float) < 1e-6).all()
