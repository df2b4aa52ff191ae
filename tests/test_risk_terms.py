"""One fragility in the hazard's own terms (issue 47): the measure, component and unit of a
fragility reconciled with a hazard's in one place, the same answer in risk.csv and in
portfolio.csv, refusals before any work, hazard files and inventories as people have them,
and the site's answer."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from rocking.cli import main
from rocking.fragility.refit import MOTION_MEASURES
from rocking.risk.hazard import parse_hazard
from rocking.risk.portfolio import read_portfolio, site_portfolio, write_portfolio
from rocking.risk.risk_table import read_risk_table, risk_table

ROOT = Path(__file__).resolve().parents[1]
GALLERY = ROOT / "results/paper/elcentro"
HAZARD = str(ROOT / "config/hazard/example_hazard_curve.csv")
NODE = {"mode": "3d", "limit_state": "overturning", "tan_alpha": 0.2, "R": 3.0}


def _ratios(motions: list[str]) -> dict[str, float]:
    """Made-up RotD50/vector-peak PGA ratios, one per motion (0.70–0.80, as records have)."""
    return {m: 0.70 + 0.1 * k / max(len(motions) - 1, 1) for k, m in enumerate(motions)}


@pytest.fixture
def study(tmp_path):
    """The gallery's El Centro study (its critical.csv and fragility.csv) with a
    motion_measures.csv of known RotD50 ratios."""
    folder = tmp_path / "elcentro"
    folder.mkdir()
    for name in ("critical.csv", "fragility.csv"):
        shutil.copy(GALLERY / name, folder / name)
    motions = list(dict.fromkeys(pd.read_csv(folder / "critical.csv")["motion"]))
    ratios = _ratios(motions)
    rows = [{"motion": m, "kind": "synthetic", "pga_g": 0.3, "measure": "pga",
             "component": c, "unit": "g", "value": 0.3 * (ratios[m] if c == "rotd50" else 1.0)}
            for m in motions for c in ("vector_peak", "rotd50")]
    pd.DataFrame(rows).to_csv(folder / MOTION_MEASURES, index=False)
    return folder, ratios


def _node(frame, median="median_im", lam="maf"):
    row = frame[(frame["mode"] == NODE["mode"]) & (frame["limit_state"] == NODE["limit_state"])
                & np.isclose(frame["tan_alpha"], NODE["tan_alpha"])
                & np.isclose(frame["R"], NODE["R"])]
    assert len(row) == 1
    return float(row[median].iloc[0]), float(row["beta"].iloc[0]), float(row[lam].iloc[0])


def test_a_rotd50_study_under_a_rotd50_hazard_same_in_risk_and_portfolio(study, tmp_path):
    """risk.csv and portfolio.csv at a grid node: the same RotD50 median, β and λ (1e-9 as
    computed; to the printed digits as written), both the vector-peak answer moved by the
    records' ratio (the geometric mean of the motions' RotD50/vector-peak ratios)."""
    from rocking.risk.exports import write_risk_outputs

    folder, ratios = study
    entry = {"file": HAZARD, "site": {"lon": 0.0, "lat": 0.0}, "component": "RotD50"}
    hazard = parse_hazard(entry)
    assert (hazard.component, hazard.component_source) == ("rotd50", "declared")
    out = {k: tmp_path / f"o.{k}" for k in ("xml", "p.csv")}
    summary = write_risk_outputs(folder / "fragility.csv", hazard, nrml=out["xml"],
                                 pelicun=out["p.csv"], table=folder / "risk.csv",
                                 study_component="rotd50")
    assert summary["risk_component"] == "rotd50" and "refitted" in summary["terms_note"]
    computed = read_risk_table(risk_table(folder / "fragility.csv", hazard))
    written = read_risk_table(folder / "risk.csv")
    assert set(written["component"]) == {"rotd50"}
    assert set(written["component_source"]) == {"declared+refit"}
    inventory = tmp_path / "node.csv"
    inventory.write_text("id,R,tan_alpha,lon,lat\nnode,3,0.2,0,0\n")
    result = site_portfolio(folder, inventory, {"file": HAZARD, "component": "rotd50"},
                            limit_states=["overturning"], resamples=50,
                            study_component="rotd50")
    write_portfolio(result.table, tmp_path / "pf")
    port = result.table
    assert set(port["component"]) == {"rotd50"}
    m_risk, b_risk, lam_risk = _node(computed)
    got = port.iloc[0]
    assert got["median"] == pytest.approx(m_risk, rel=1e-9)
    assert got["beta"] == pytest.approx(b_risk, rel=1e-9)
    assert got["lambda"] == pytest.approx(lam_risk, rel=1e-9)
    m_w, _, lam_w = _node(written)
    back = read_portfolio(tmp_path / "pf" / "portfolio.csv").iloc[0]
    assert back["median"] == pytest.approx(m_w, rel=1e-5)
    assert back["lambda"] == pytest.approx(lam_w, rel=1e-5)
    # the vector-peak answer of the same study under the same curve declared vector peak
    vp = read_risk_table(risk_table(folder / "fragility.csv",
                                    parse_hazard({**entry, "component": "vector_peak"})))
    m_vp, b_vp, lam_vp = _node(vp)
    critical = pd.read_csv(folder / "critical.csv")
    cell = critical[(critical["mode"] == "3d") & (critical["limit_state"] == "overturning")
                    & np.isclose(critical["tan_alpha [-]"], 0.2)
                    & np.isclose(critical["R [m]"], 3.0)]
    assert not cell["not_reached"].any()  # no censoring: the closed form holds
    records_ratio = math.exp(np.mean(np.log([ratios[m] for m in cell["motion"]])))
    assert m_risk / m_vp == pytest.approx(records_ratio, rel=1e-9)
    assert lam_risk > lam_vp  # a smaller capacity in the smaller component: λ higher


def test_the_vector_peak_needs_no_refit_and_is_fragility_csv(study):
    folder, _ = study
    hazard = parse_hazard({"file": HAZARD, "site": 0})  # the file states vector_peak
    t = read_risk_table(risk_table(folder / "fragility.csv", hazard))
    assert set(t["component"]) == {"vector_peak"} and set(t["component_source"]) == {"file"}
    frag = pd.read_csv(folder / "fragility.csv")
    frag = frag.rename(columns=lambda c: c.split(" [")[0])
    m, _, _ = _node(frag, median="median_pga_g", lam="beta")
    assert _node(t)[0] == m


def _sa_file(path: Path) -> Path:
    im = np.geomspace(0.01, 3.0, 20)
    poe = -np.expm1(-1e-3 * (im / 0.2) ** -2.2)
    path.write_text("#,,,,,\"generated_by='OpenQuake engine 3.23', kind='mean', "
                    "investigation_time=1.0, imt='SA(1.0)'\"\n"
                    "lon,lat,depth," + ",".join(f"poe-{x:.7f}" for x in im) + "\n"
                    "0.0,0.0,0.0," + ",".join(f"{p:.6E}" for p in poe) + "\n")
    return path


def _refusal(capsys) -> list[str]:
    """The lines on stderr after the note on tables without a record (at most one)."""
    err = capsys.readouterr().err.strip().splitlines()
    notes = [line for line in err if "no record of what made" in line]
    assert len(notes) <= 1, err
    return [line for line in err if line not in notes]


def test_an_sa_hazard_against_a_pga_only_study_is_refused_on_the_command_line(study, tmp_path,
                                                                             capsys):
    folder, _ = study
    sa = _sa_file(tmp_path / "hazard_curve-mean-SA(1.0)_1.csv")
    assert main(["risk", "--fragility", str(folder / "fragility.csv"), "--hazard",
                 str(sa)]) == 2
    # the gallery's tables copied without their records: one note says they are read as
    # tables of one's own, then the one line of the refusal
    err = _refusal(capsys)
    assert len(err) == 1 and "is of SA(1.0)" in err[0] and "of pga only" in err[0]
    assert "add sa:1.0 to the study's intensity_measures" in err[0]
    inventory = tmp_path / "one.csv"
    inventory.write_text("id,R,tan_alpha\nA,3,0.2\n")
    assert main(["portfolio", "--surface", str(folder), "--inventory", str(inventory),
                 "--hazard", str(sa), "--out", str(tmp_path / "pf")]) == 2
    err = _refusal(capsys)
    assert len(err) == 1 and "is of SA(1.0)" in err[0]
    assert not (tmp_path / "pf" / "portfolio.csv").exists()


def _tiny_config(tmp_path, hazard, **extra):
    from test_workflow import TINY

    cfg = json.loads(json.dumps(TINY))
    cfg["studies"]["tiny"]["hazard"] = hazard
    cfg["studies"]["tiny"].update(extra)
    path = tmp_path / "cfg.yaml"
    path.write_text(yaml.safe_dump(cfg))
    return cfg, path


def test_an_sa_hazard_against_a_pga_only_study_is_refused_in_the_dry_run(tmp_path):
    """check_risk is the last step of the workflow's one check of the configuration, which
    the Snakefile runs before any job (test_workflow's subprocess case of the refusals)."""
    from snakemake.utils import validate
    from test_workflow import REPO

    from rocking.config.checks import check_risk, check_workflow_config

    sa = _sa_file(tmp_path / "hazard_curve-mean-SA(1.0)_1.csv")
    cfg, _ = _tiny_config(tmp_path, str(sa))
    refused = r"^studies.tiny.hazard: .* is of SA\(1.0\), study tiny of pga, pgv only: add sa:1.0"
    with pytest.raises(ValueError, match=refused):
        check_risk(cfg)
    with pytest.raises(ValueError, match=refused):
        check_workflow_config(json.loads(json.dumps(cfg)), REPO, validate)
    assert not (tmp_path / "results").exists()
    # with sa:1.0 among its measures the study fits it: the dry run passes that check
    cfg["studies"]["tiny"]["intensity_measures"] = ["pga", "sa:1.0"]
    check_risk(cfg)


def test_the_dry_run_checks_every_inventory_row_against_the_planned_grid(tmp_path):
    from rocking.config.checks import check_risk

    inventory = tmp_path / "park.csv"
    inventory.write_text("id,R,tan_alpha,lon,lat\nA,2,0.2,0,0\nB,9,0.2,0,0\n")
    cfg, _ = _tiny_config(tmp_path, {"file": HAZARD, "site": 0}, inventory=str(inventory))
    with pytest.raises(ValueError, match="no grid of R and tan α in 3d"):
        check_risk(cfg)  # the tiny study runs 3d at one tan α only
    cfg["studies"]["tiny"]["runs"][0]["tan_alpha"] = [0.1, 0.3]
    with pytest.raises(ValueError, match=r"^studies.tiny.inventory: .*park.csv: row 3 \(id B\), "
                                         r"column R: outside the surface's grid"):
        check_risk(cfg)
    inventory.write_text("id,R,tan_alpha,lon,lat\nA,2,0.2,0,0\n")
    check_risk(cfg)
    cfg["studies"]["tiny"]["inventory"] = {"file": str(inventory), "export": "column"}
    inventory.write_text("id,R,tan_alpha,lon,lat\nA col,2,0.2,0,0\n")
    with pytest.raises(ValueError, match="row 2: id 'A col' is not an OpenQuake asset id"):
        check_risk(cfg)


# ------------------------------------------------------------------------- hazard files
def _sites_file(path: Path, rows: list[tuple[str, float, float]], *, component="") -> Path:
    im = np.geomspace(0.01, 3.0, 12)
    said = f", component='{component}'" if component else ""
    lines = ["#,,,,,\"generated_by='OpenQuake engine 3.23', kind='mean', "
             f"investigation_time=1.0, imt='PGA'{said}\"",
             "custom_site_id,lon,lat,depth," + ",".join(f"poe-{x:.7f}" for x in im)]
    for k, (sid, lon, lat) in enumerate(rows):
        poe = -np.expm1(-(1 + k) * 1e-3 * (im / 0.2) ** -2.2)
        lines.append(f"{sid},{lon},{lat},0," + ",".join(f"{p:.6E}" for p in poe))
    path.write_text("\n".join(lines) + "\n")
    return path


def test_two_sites_at_one_place_or_one_id_twice_are_refused_naming_both_lines(tmp_path):
    same_place = _sites_file(tmp_path / "a.csv", [("A", 23.7, 37.9), ("B", 23.7, 37.9)])
    with pytest.raises(ValueError, match=r"lines 3 and 4 are two sites at the same lon 23.7, "
                                         r"lat 37.9"):
        parse_hazard({"file": str(same_place), "site": {"id": "A"}})
    same_id = _sites_file(tmp_path / "b.csv", [("A", 23.7, 37.9), ("A", 23.8, 37.9)])
    with pytest.raises(ValueError, match=r"custom_site_id 'A' is given twice, lines 3 and 4"):
        parse_hazard({"file": str(same_id), "site": {"lon": 23.8, "lat": 37.9}})


def test_the_measure_is_read_from_the_file_name_and_held_against_its_header(tmp_path):
    im = np.geomspace(0.01, 3.0, 12)
    poe = -np.expm1(-1e-3 * (im / 0.2) ** -2.2)
    body = ("lon,lat,depth," + ",".join(f"poe-{x:.7f}" for x in im) + "\n0,0,0,"
            + ",".join(f"{p:.6E}" for p in poe) + "\n")
    named = tmp_path / "hazard_curve-mean-SA(0.3)_7.csv"
    named.write_text("#,,,,,\"kind='mean', investigation_time=1.0\"\n" + body)
    assert parse_hazard(str(named)).measure == "sa:0.3"
    both = tmp_path / "hazard_curve-mean-PGA_7.csv"
    both.write_text("#,,,,,\"kind='mean', investigation_time=1.0, imt='SA(1.0)'\"\n" + body)
    with pytest.raises(ValueError, match=r"imt='SA\(1.0\)', its file name 'PGA'"):
        parse_hazard(str(both))


def test_an_openquake_file_without_a_component_is_rotd50_and_says_so(tmp_path):
    path = _sites_file(tmp_path / "h.csv", [("A", 23.7, 37.9)])
    h = parse_hazard(str(path))
    assert (h.component, h.component_source) == ("rotd50", "default")
    assert "taken as rotd50" in h.component_note and "safe side" in h.component_note
    stated = _sites_file(tmp_path / "s.csv", [("A", 23.7, 37.9)], component="RotD100")
    assert parse_hazard(str(stated)).component == "rotd100"
    # a table that says nothing has none: taken in the fragility's, said so
    table = tmp_path / "t.csv"
    table.write_text("pga,annual_rate\n0.1,1e-2\n0.5,1e-4\n")
    assert parse_hazard(str(table)).component is None


def test_component_names_in_any_case_in_the_configuration(tmp_path):
    from rocking.config.checks import schema_error
    from rocking.config.study import StudySpec

    cfg, _ = _tiny_config(tmp_path, {"file": HAZARD, "site": 0, "component": "RotD50"},
                          component="RotD50")
    schema = yaml.safe_load((ROOT / "workflow/schemas/config.schema.yaml").read_text())
    assert schema_error(cfg, schema) is None
    spec = StudySpec.from_config(cfg, "tiny")
    assert spec.component == "rotd50" and parse_hazard(spec.hazard).component == "rotd50"


# ---------------------------------------------------------------------------- inventories
def test_zero_padded_ids_and_full_coordinates_reach_the_openquake_exposure(study, tmp_path):
    from rocking.risk.exposure import write_exposure

    folder, _ = study
    inventory = tmp_path / "park.csv"
    inventory.write_text("id,height,diameter,lon,lat\n001,6,0.8,0.0012345678,-0.0009876543\n"
                         "002,8,1.0,0.0021,0.0011\n")
    out = tmp_path / "pf"
    assert main(["portfolio", "--surface", str(folder), "--inventory", str(inventory),
                 "--hazard", HAZARD, "--resamples", "0", "--out", str(out), "--export",
                 "column"]) == 0
    table = read_portfolio(out / "portfolio.csv")
    assert sorted(set(table["id"])) == ["001", "002"]
    assert (out / "portfolio.csv").read_text().count("0.0012345678") >= 2  # lon, both rows
    assets = pd.read_csv(out / "exposure" / "exposure.csv", dtype=str)
    assert sorted(assets["id"]) == ["001", "002"]
    assert "0.0012345678" in set(assets["lon"]) and "-0.0009876543" in set(assets["lat"])
    # the library, given the file: ids still text
    write_exposure(out / "portfolio.csv", tmp_path / "again")
    assert sorted(pd.read_csv(tmp_path / "again" / "exposure.csv", dtype=str)["id"]) == [
        "001", "002"]


def test_an_export_refusal_leaves_no_file_and_names_the_inventory_row(study, tmp_path, capsys):
    folder, _ = study
    inventory = tmp_path / "park.csv"
    inventory.write_text("# surveyed 2024\nid,height,diameter,lon,lat\nT 1,6,0.8,0,0\n")
    out = tmp_path / "pf"
    assert main(["portfolio", "--surface", str(folder), "--inventory", str(inventory),
                 "--hazard", HAZARD, "--resamples", "0", "--out", str(out), "--export",
                 "column"]) == 2
    err = capsys.readouterr().err
    assert "inventory row 3 (id 'T 1')" in err and "not an OpenQuake asset id" in err
    assert not (out / "portfolio.csv").exists()


def test_an_inventory_as_a_spreadsheet_exports_it(study, tmp_path):
    """Semicolons and decimal commas, unit suffixes, a notes column, mm: read, said, and
    the same columns as the plain file."""
    from rocking.risk.inventory import read_inventory

    plain = tmp_path / "plain.csv"
    plain.write_text("id,height,diameter,lon,lat\nA,6.5,0.8,0.001,0\nB,8,1.05,0,0.001\n")
    sheet = tmp_path / "sheet.csv"
    sheet.write_text("ID;Height [m];diameter_mm;Longitude;Latitude;notes\n"
                     "A;6,5;800;0,001;0;leaning\nB;8;1050;0;0,001;\n",
                     encoding="cp1252")
    a, b = read_inventory(plain), read_inventory(sheet)
    for col in ("id", "R", "tan_alpha", "lon", "lat"):
        assert a.columns[col].tolist() == pytest.approx(b.columns[col].tolist()) \
            if col != "id" else a.columns[col].tolist() == b.columns[col].tolist()
    assert b.extra["notes"].tolist() == ["leaning", ""]
    assert any("semicolon-separated with decimal commas" in n for n in b.notes)
    assert any("diameter read in mm, converted to m" in n for n in b.notes)
    result = site_portfolio(study[0], sheet, HAZARD, resamples=0)
    assert "notes" in result.table.columns
    assert result.table.set_index("id").loc["A", "notes"].tolist() == ["leaning"] * 2


@pytest.mark.parametrize("text, hint", [
    ("id,height,diameter\nA,0.8,6\n", "height 0.8 m is below diameter 6 m: swapped?"),
    ("id,height,diameter\nA,6500,800\n", "6500 m is no column's size: in mm or cm?"),
    ("id,height,diameter,lon,lat\nA,6,0.8,0,0.1\n", "lon and lat swapped?"),
    ("id,height,diameter,lon,lat\nA,6,0.8,200,10\n", "lon 200 is beyond 180: give it as -160"),
    ("id;height;diameter;lon;lat\nA;6,5;0,8;0;0\n", None),  # read: no error at all
    ("id,height,diameter\nA,6,5,0,8\n", "a decimal comma in a comma-separated file?"),
])
def test_each_hint_aims_at_the_likely_mistake(study, tmp_path, text, hint):
    from rocking.fragility.surface import FragilitySurface
    from rocking.risk.inventory import read_hazard_sites, read_inventory

    path = tmp_path / "park.csv"
    path.write_text(text)
    surface = FragilitySurface.from_study(study[0], n_resamples=0)
    sites = read_hazard_sites(HAZARD)
    if hint is None:
        assert read_inventory(path, surface=surface, hazard=sites).columns["R"].iloc[0] > 0
        return
    with pytest.raises(ValueError) as err:
        read_inventory(path, surface=surface, hazard=sites)
    assert hint in str(err.value) and "\n" not in str(err.value)


def test_swapped_lon_and_lat_near_a_site_are_named(tmp_path):
    from rocking.risk.inventory import read_hazard_sites, read_inventory

    sites = _sites_file(tmp_path / "h.csv", [("ATH", 23.7275, 37.9838),
                                             ("PIR", 23.6470, 37.9420)])
    path = tmp_path / "park.csv"
    path.write_text("id,R,tan_alpha,lon,lat\nA,3,0.2,37.9838,23.7275\n")
    with pytest.raises(ValueError, match=r"lon and lat swapped\? \(lon 23.7275, lat 37.9838 is "
                                         r"0 km from id ATH"):
        read_inventory(path, hazard=read_hazard_sites(str(sites)))


def test_mu_is_said_to_be_unused(study, tmp_path):
    path = tmp_path / "park.csv"
    path.write_text("id,R,tan_alpha,mu,lon,lat\nA,3,0.2,0.6,0,0\nB,4,0.2,,0,0\n")
    result = site_portfolio(study[0], path, HAZARD, resamples=0)
    assert any("mu of 1 column(s) carried into portfolio.csv and not used" in n
               for n in result.notes)


# ------------------------------------------------------------------------ the site's answer
def test_the_site_expects_the_sum_of_lambda_and_bounds_at_least_one(study, tmp_path):
    result = site_portfolio(study[0], ROOT / "config/inventory/example_columns.csv", HAZARD,
                            resamples=200)
    site = result.site.set_index("limit_state")
    for ls, part in result.table.groupby("limit_state"):
        lam = part["lambda"].to_numpy(float)
        row = site.loc[ls]
        assert row["expected_per_year"] == pytest.approx(lam.sum(), rel=1e-12)
        assert (row["any_lo"], row["any_hi"]) == pytest.approx((lam.max(), lam.sum()))
        assert row["expected_p05"] <= row["expected_per_year"] <= row["expected_p95"]
        assert row["p_any_50yr_hi"] == pytest.approx(-math.expm1(-50 * lam.sum()))
    write_portfolio(result.table, tmp_path)
    assert (tmp_path / "portfolio_site.csv").is_file()


def test_a_regional_file_is_parsed_once_and_only_the_sites_used_made(tmp_path, monkeypatch):
    from rocking.risk import hazard as module
    from rocking.risk.inventory import read_hazard_sites, read_inventory

    rows = [(f"s{k}", round(0.01 * (k % 50), 4), round(0.01 * (k // 50), 4))
            for k in range(400)]
    path = _sites_file(tmp_path / "region.csv", rows, component="vector_peak")
    calls = []
    real = module._text
    monkeypatch.setattr(module, "_text", lambda p: calls.append(p) or real(p))
    sites = read_hazard_sites(str(path))
    inv = tmp_path / "park.csv"
    inv.write_text("id,R,tan_alpha,lon,lat\nA,3,0.2,0.1,0.02\nB,3,0.2,0.2,0.05\n")
    columns = read_inventory(inv, hazard=sites)
    curves = [sites.curve(k) for k in columns.columns["hazard_index"]]
    assert len(calls) == 1 and len(sites._made) == 2
    assert curves[0].site.startswith("id s110 ")  # lon 0.1, lat 0.02
