"""An inventory exported as OpenQuake's exposure model + fragility model and pelicun's inputs.

Checked three ways: an independent reader of the files as both tools document them (element
order, cross-references, the lognormal given back from OpenQuake's mean/stddev); OpenQuake's
own readers and its scenario_damage calculator where the engine is installed; pelicun's
damage calculation where pelicun runs (its own interpreter may be named by
``ROCKING_PELICUN_PYTHON``: pelicun 3.10 needs scipy < 1.16 and pandas < 3). Each of them
against the lognormal CDF of the table's medians and β (scipy), not against this writer.
"""

from __future__ import annotations

import csv
import importlib.util
import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy import stats

from rocking.fragility.table import median_beta
from rocking.risk.exposure import component_of, write_exposure

NS = {"n": "http://openquake.org/xmlns/nrml/0.5"}
HERE = Path(__file__).parent
OQ = importlib.util.find_spec("openquake") is not None
OQ_REASON = ("OpenQuake's engine is not installed (pip install --no-deps openquake-engine "
             "pyzmq h5py toml decorator shapely pyproj fiona psutil numba docutils requests "
             "alpha-shapes h3 geopandas; docs/risk.md); the independent reader below checks "
             "the same files")


def portfolio(n: int = 5) -> pd.DataFrame:
    """A portfolio.csv in long form (the columns of rocking.risk.portfolio), n columns near
    Olympia, each with tilt:1/3, overturning and a sliding goal."""
    rows = []
    for k in range(n):
        R, tan = 2.0 + 1.5 * k, 0.10 + 0.03 * k
        for ls, f, beta in (("tilt:1/3", 0.55, 0.30), ("overturning", 1.0, 0.35),
                            ("sliding:0.7", 0.40, 0.5)):
            rows.append({"id": f"C{k + 1:02d}", "lon": 21.63 + 1e-3 * k, "lat": 37.64,
                         "site": "", "R": R, "tan_alpha": tan, "mode": "3d",
                         "limit_state": ls, "fragility": "critical_intensity", "measure": "pga",
                         "median": f * tan * (1.0 + 0.25 * R), "beta": beta + 0.01 * k,
                         "lambda": 1e-3, "rank": k + 1})
    return pd.DataFrame(rows)


def read_nrml_fragility(path: Path) -> tuple[list[str], dict[str, dict]]:
    """Independent reader: limit states and, per taxonomy, imls and (median, β) per limit
    state, from OpenQuake's arithmetic mean/stddev; element order as OpenQuake reads it."""
    model = ET.parse(path).getroot().find("n:fragilityModel", NS)
    assert model.get("lossCategory") == "structural"
    tags = [c.tag.split("}")[1] for c in model]
    assert tags[:2] == ["description", "limitStates"]
    assert set(tags[2:]) == {"fragilityFunction"}
    states = model.find("n:limitStates", NS).text.split()
    funcs = {}
    for f in model.findall("n:fragilityFunction", NS):
        assert (f.get("format"), f.get("shape")) == ("continuous", "logncdf")
        assert [c.tag.split("}")[1] for c in f] == ["imls"] + ["params"] * len(states)
        params = f.findall("n:params", NS)
        assert [p.get("ls") for p in params] == states
        funcs[f.get("id")] = {
            "imls": dict(f.find("n:imls", NS).attrib),
            "ls": [median_beta(float(p.get("mean")), float(p.get("stddev"))) for p in params]}
    return states, funcs


def read_exposure(folder: Path) -> pd.DataFrame:
    model = ET.parse(folder / "exposure.xml").getroot().find("n:exposureModel", NS)
    assert [c.tag.split("}")[1] for c in model] == [
        "description", "conversions", "tagNames", "assets"]
    cost = model.find("n:conversions/n:costTypes/n:costType", NS)
    assert cost.get("name") == "structural"
    table = pd.read_csv(folder / model.find("n:assets", NS).text, dtype={"id": str})
    assert {"id", "lon", "lat", "taxonomy", "number", "structural",
            *model.find("n:tagNames", NS).text.split()} == set(table.columns)
    return table


def test_one_taxonomy_per_column_cross_referenced_and_lognormals_kept(tmp_path):
    table = portfolio()
    out = write_exposure(table, tmp_path)
    assets = read_exposure(tmp_path)
    assert list(assets["id"]) == [f"C{k:02d}" for k in range(1, 6)]
    assert (assets["number"] == 1).all() and (assets["structural"] == 1).all()
    states, funcs = read_nrml_fragility(tmp_path / "fragility.xml")
    # every taxonomy of the exposure has a function and every function an asset
    assert set(assets["taxonomy"]) == set(funcs) == set(out.taxonomies)
    assert len(funcs) == 5
    # the tilt chain in increasing severity; sliding left out and named
    assert states == ["tilt_1over3", "overturning"]
    assert out.limit_states == ["tilt:1/3", "overturning"]
    assert out.left_out == ["sliding:0.7"]
    for a in assets.itertuples():
        rows = table[table["id"] == a.id].set_index("limit_state")
        for (median, beta), ls in zip(funcs[a.taxonomy]["ls"], out.limit_states, strict=True):
            assert median == pytest.approx(rows.at[ls, "median"], rel=1e-12)
            assert beta == pytest.approx(rows.at[ls, "beta"], rel=1e-12)
        imls = funcs[a.taxonomy]["imls"]
        assert imls["imt"] == "PGA"
        # uplift PGA g·tan α; maxIML leaves Φ(4) of the overturning capacity
        assert float(imls["noDamageLimit"]) == pytest.approx(rows.at["tilt:1/3", "tan_alpha"])
        top = rows.at["overturning", "median"] * np.exp(4 * rows.at["overturning", "beta"])
        assert float(imls["maxIML"]) >= top * (1 - 1e-12)


def test_extrapolated_columns_named_in_the_notes(tmp_path):
    table = portfolio(3).assign(extrapolated=False)
    table.loc[table["id"] == "C03", "extrapolated"] = True
    out = write_exposure(table, tmp_path)
    assert [n for n in out.notes if "extrapolated" in n] == [
        "1 column(s) with fragilities extrapolated beyond the surface's grid exported as they "
        "are: C03"]
    assert out.assets == 3


def test_pelicun_files_cross_referenced(tmp_path):
    table = portfolio(3)
    out = write_exposure(table, tmp_path)
    with (tmp_path / "pelicun" / "damage_model.csv").open() as fh:
        model = {r["ID"]: r for r in csv.DictReader(fh)}
    assets = pd.read_csv(tmp_path / "pelicun" / "assets.csv", dtype={"id": str})
    assert set(model) == {component_of(t) for t in out.taxonomies} == set(assets["component"])
    for a in assets.itertuples():
        rows = table[table["id"] == a.id].set_index("limit_state")
        r = model[a.component]
        assert (r["Demand-Type"], r["Demand-Unit"], r["Demand-Directional"]) == (
            "Peak Ground Acceleration", "g", "1")
        assert float(r["LS1-Theta_0"]) == rows.at["tilt:1/3", "median"]
        assert float(r["LS2-Theta_1"]) == rows.at["overturning", "beta"]
        assert "-" not in a.component  # pelicun joins component-location-direction with '-'
        marg = pd.read_csv(tmp_path / "pelicun" / a.marginals, index_col=0)
        assert list(marg.index) == [a.component]
        assert marg.iloc[0][["Units", "Location", "Direction", "Theta_0"]].tolist() == [
            "ea", 1, 1, 1]


def test_size_classes_take_their_most_fragile_member(tmp_path):
    table = portfolio(5)  # R 2, 3.5, 5, 6.5, 8 m; tan α 0.10 ... 0.22
    out = write_exposure(table, tmp_path, taxonomy_by="size_class",
                         R_edges=(1.0, 4.0, 9.0), tan_alpha_edges=(0.05, 0.15, 0.3))
    assets = read_exposure(tmp_path).set_index("id")
    assert assets["taxonomy"].to_dict() == {
        "C01": "R1-4m_tan0.05-0.15", "C02": "R1-4m_tan0.05-0.15",
        "C03": "R4-9m_tan0.15-0.3", "C04": "R4-9m_tan0.15-0.3", "C05": "R4-9m_tan0.15-0.3"}
    _, funcs = read_nrml_fragility(tmp_path / "fragility.xml")
    assert set(funcs) == set(assets["taxonomy"]) == set(out.taxonomies)
    for tax, f in funcs.items():
        members = table[table["id"].isin(assets.index[assets["taxonomy"] == tax])]
        for (median, beta), ls in zip(f["ls"], out.limit_states, strict=True):
            g = members[members["limit_state"] == ls]
            weakest = g.loc[g["median"].idxmin()]
            assert median == pytest.approx(weakest["median"], rel=1e-12)
            assert beta == pytest.approx(weakest["beta"], rel=1e-12)
        # the most slender member's uplift: the lowest PGA at which any member rocks
        assert float(f["imls"]["noDamageLimit"]) == pytest.approx(members["tan_alpha"].min())
        spread = max(g["median"].max() / g["median"].min()
                     for _, g in members.groupby("limit_state"))
        assert out.class_spread[tax] == pytest.approx(spread)
    assert out.class_spread["R4-9m_tan0.15-0.3"] > 1.5  # the coarse class says so


def _bad(table, row, col, value):
    t = table.copy()
    t[col] = t[col].astype(object)
    t.loc[row, col] = value
    return t


@pytest.mark.parametrize("edit, match", [
    (lambda t: _bad(t, 3, "lon", 21.7),
     r"row 4 of the table \(id 'C02'\): duplicate id with another lon"),
    (lambda t: pd.concat([t, t.iloc[[4]]], ignore_index=True),
     r"row 16 of the table \(id 'C02'\): duplicate id: limit state overturning"),
    (lambda t: _bad(t, 6, "lat", np.nan), r"row 7 of the table \(id 'C03'\): lat is missing"),
    (lambda t: t.drop(columns="lon"), r"lacks the column\(s\) lon"),
    (lambda t: _bad(t, 0, "lon", 200.0),
     r"row 1 of the table \(id 'C01'\): lon 200 is beyond 180: give it as -160"),
    (lambda t: _bad(t, 0, "median", 0.0),
     r"row 1 of the table \(id 'C01'\): median must be a finite number > 0, got 0.0$"),
    (lambda t: t.assign(id=t["id"].str.replace("C01", "C 01")),
     r"row 1 of the table \(id 'C 01'\): id 'C 01' is not an OpenQuake asset id"),
    (lambda t: t.drop(index=4), r"id 'C02': no row for limit state\(s\) overturning"),
    (lambda t: _bad(t, 0, "mode", "2d-x"), r"the table mixes modes \(2d-x, 3d\)"),
    (lambda t: _bad(t, 0, "limit_state", "tilted"),
     r"row 1 of the table \(id 'C01'\): limit_state"),
])
def test_bad_input_one_line_naming_row_and_column_nothing_written(tmp_path, edit, match):
    with pytest.raises(ValueError, match=match) as err:
        write_exposure(edit(portfolio()), tmp_path / "out")
    assert "\n" not in str(err.value)
    assert not (tmp_path / "out").exists()


def test_bad_options_refused(tmp_path):
    with pytest.raises(ValueError, match="imt 'SA.1.0.' is not the table's measure 'pga'"):
        write_exposure(portfolio(), tmp_path, imt="SA(1.0)")
    with pytest.raises(ValueError,
                       match=r"row 5 of the table \(id 'C05'\): R = 8 outside the class edges"):
        write_exposure(portfolio(), tmp_path, taxonomy_by="size_class", R_edges=(1, 4, 8))
    with pytest.raises(ValueError, match="unknown component 'rot50'"):
        write_exposure(portfolio(), tmp_path, component="rot50")
    with pytest.raises(ValueError, match="component 'rotd50' is not the table's"):
        write_exposure(portfolio().assign(component="vector_peak"), tmp_path,
                       component="rotd50")
    with pytest.raises(ValueError, match="taxonomy_by must be one of"):
        write_exposure(portfolio(), tmp_path, taxonomy_by="height")
    with pytest.raises(ValueError, match="R_edges must be at least two finite increasing"):
        write_exposure(portfolio(), tmp_path, taxonomy_by="size_class", R_edges=(4, 1))


def test_sa_fragility_without_uplift_limit_and_without_pelicun(tmp_path):
    table = portfolio(2).assign(measure="sa:1.0")
    out = write_exposure(table, tmp_path, component="rotd50")
    _, funcs = read_nrml_fragility(tmp_path / "fragility.xml")
    for f in funcs.values():
        assert f["imls"]["imt"] == "SA(1.0)"
        assert "noDamageLimit" not in f["imls"]  # the uplift bound is of the vector-peak PGA
    assert "pelicun_damage_model" not in out.paths
    assert not (tmp_path / "pelicun").exists()
    assert any("no pelicun files" in n for n in out.notes)
    text = ET.parse(tmp_path / "fragility.xml").getroot().find(
        "n:fragilityModel/n:description", NS).text
    assert "rotd50 horizontal component (RotD50)" in text


# ------------------------------------------------------------------ OpenQuake's own readers


OQ_PANDAS = "ignore:The inplace keyword in DataFrame.sort_values"  # the engine's, not ours


@pytest.mark.filterwarnings(OQ_PANDAS)
@pytest.mark.skipif(not OQ, reason=OQ_REASON)
@pytest.mark.parametrize("taxonomy_by", ["column", "size_class"])
def test_openquake_reads_exposure_and_fragility(tmp_path, taxonomy_by):
    import openquake.risklib.read_nrml  # noqa: F401  (registers the NRML converters)
    from openquake.hazardlib import nrml
    from openquake.risklib.asset import Exposure

    table = portfolio()
    out = write_exposure(table, tmp_path, taxonomy_by=taxonomy_by)
    exp = Exposure.read_all([str(tmp_path / "exposure.xml")])
    assert exp.loss_types == ["structural"]
    assert sorted(i.decode() for i in exp.assets["id"]) == sorted(set(table["id"]))
    taxonomies = set(exp.tagcol.taxonomy[1:])  # [0] is OpenQuake's '?'
    fm = nrml.to_python(str(tmp_path / "fragility.xml"))
    assert {tax for _, tax in fm} == taxonomies == set(out.taxonomies)
    assert list(fm.limitStates) == ["tilt_1over3", "overturning"]
    assets = read_exposure(tmp_path).set_index("id")
    pga = np.array([0.15, 0.25, 0.4, 0.6])
    for ident, rows in table.groupby("id"):
        tax = assets.at[ident, "taxonomy"]
        members = table[table["id"].isin(assets.index[assets["taxonomy"] == tax])]
        if taxonomy_by == "size_class":
            rows = members.loc[members.groupby("limit_state")["median"].idxmin()]
        rows = rows.set_index("limit_state")
        for func, ls in zip(fm[("PGA", tax)].build(fm.limitStates), out.limit_states,
                            strict=True):
            want = stats.norm.cdf(np.log(pga / rows.at[ls, "median"]) / rows.at[ls, "beta"])
            want[pga <= members["tan_alpha"].min()] = 0.0  # noDamageLimit: the uplift PGA
            np.testing.assert_allclose(func(pga), want, rtol=1e-9, atol=1e-12)


@pytest.mark.slow
@pytest.mark.skipif(not OQ, reason=OQ_REASON)
def test_openquake_scenario_damage_takes_the_files_as_they_are(tmp_path):
    table = portfolio(3)
    write_exposure(table, tmp_path / "export")
    pga = 0.3
    env = {**os.environ, "HOME": str(tmp_path / "home"), "OQ_DISTRIBUTE": "no"}
    run = subprocess.run([sys.executable, str(HERE / "_openquake_damage.py"),
                          str(tmp_path / "export"), str(pga)],
                         capture_output=True, text=True, env=env, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    damages = json.loads(run.stdout.strip().splitlines()[-1])["damages"]
    assert set(damages) == set(table["id"])
    for ident, rows in table.groupby("id"):
        rows = rows.set_index("limit_state")
        p = [stats.norm.cdf(np.log(pga / rows.at[ls, "median"]) / rows.at[ls, "beta"])
             for ls in ("tilt:1/3", "overturning")]
        # no damage, tilted beyond 1/3 of the slenderness but standing, overturned
        want = [1 - p[0], p[0] - p[1], p[1]]
        np.testing.assert_allclose(damages[ident], want, atol=1e-6)  # stored in float32


# ------------------------------------------------------------------ pelicun


def _pelicun_python() -> str | None:
    named = os.environ.get("ROCKING_PELICUN_PYTHON")
    if named:
        return named if shutil.which(named) or Path(named).is_file() else None
    try:
        import pelicun.assessment  # noqa: F401
    except Exception:  # noqa: BLE001  (pelicun 3.10 fails to import on scipy >= 1.16)
        return None
    return sys.executable


@pytest.mark.skipif(_pelicun_python() is None, reason=(
    "pelicun does not run in this environment (pelicun 3.10 pins scipy < 1.16 and "
    "pandas < 3); set ROCKING_PELICUN_PYTHON to an interpreter that has it"))
@pytest.mark.parametrize("taxonomy_by", ["column", "size_class"])
def test_pelicun_damage_of_one_asset(tmp_path, taxonomy_by):
    table = portfolio(3)
    write_exposure(table, tmp_path, taxonomy_by=taxonomy_by)
    pga, n = 0.3, 4000
    run = subprocess.run([_pelicun_python(), str(HERE / "_pelicun_damage.py"), str(tmp_path),
                          "C02", str(pga), str(n)], capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    got = json.loads(run.stdout.strip().splitlines()[-1])
    rows = table[table["id"] == "C02"].set_index("limit_state")
    if taxonomy_by == "size_class":
        assets = read_exposure(tmp_path).set_index("id")
        members = table[table["id"].isin(
            assets.index[assets["taxonomy"] == assets.at["C02", "taxonomy"]])]
        rows = members.loc[members.groupby("limit_state")["median"].idxmin()].set_index(
            "limit_state")
    states = ["tilt:1/3", "overturning"]
    # pelicun converts g to m/s² (standard gravity) and keeps β
    np.testing.assert_allclose(got["theta_0_si"], rows.loc[states, "median"] * 9.80665,
                               rtol=1e-9)
    np.testing.assert_allclose(got["theta_1"], rows.loc[states, "beta"], rtol=1e-12)
    p = stats.norm.cdf(np.log(pga / rows.loc[states, "median"]) / rows.loc[states, "beta"])
    # n realisations: binomial standard error ≤ 0.5/√n = 0.008; 4 of them
    np.testing.assert_allclose(got["p_ds_ge"], p, atol=4 * 0.5 / np.sqrt(n))


def test_a_taxonomy_column_of_the_table_is_used(tmp_path):
    """The docstring allows a ``taxonomy`` column: each column keeps its own (a KeyError
    before: the table's taxonomy and the assets' were merged twice)."""
    table = portfolio().assign(taxonomy=lambda t: "tx_" + t["id"].astype(str))
    out = write_exposure(table, tmp_path)
    assert sorted(out.taxonomies) == sorted("tx_" + table["id"].astype(str).unique())

