"""A study of one's own, through the real workflow: the figures and report follow the study.

The study is an engineer's, not the paper's: tan α = 0.15 (the paper's figures assume 0.2),
limit states [overturning, tilt:1/3], one mode, and no ``reproduces`` key. Its figure targets
come from its StudySpec (a dry run plans no paper model figure, no Fig 11 or 12), every figure
it draws has data on every panel at its own tan α, and its report shows what was computed
without a single verdict of the paper against the run.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

REPO = Path(__file__).resolve().parents[1]
SNAKEFILE = REPO / "Snakefile"
TAN_ALPHA = 0.15
OWN = {
    "accuracy": "fast",
    "motions": {"max_duration": 3.0},
    "ensembles": {"own": {"record": "el-centro-1940", "n_synthetic": 1, "seed": 11}},
    "studies": {"column": {
        "ensemble": "own",
        "R": [1.0, 3.0],
        "chunk_R": 1,
        "runs": [{"modes": ["3d"], "tan_alpha": [TAN_ALPHA],
                  "limit_states": ["overturning", "tilt:1/3"]}],
    }},
    "dask": {"progress_interval": 0},
}
OWN_FIGURES = {"fig08_motions", "fig09_spectra", "fig10_goals", "fragility_curves"}
"""The figures of that study: its motions, its spectra, its mean spectra, its fragility."""
PAPER_ONLY = {"fig03_wobbling_period", "fig04_free_vibration", "fig06_el_centro",
              "fig06_theta_max_sensitivity", "fig11_slenderness", "fig12_2d_vs_3d"}


def snakemake(workdir: Path, config: Path, *args: str, timeout: float = 900):
    # targets first: --configfile takes several values
    cmd = [sys.executable, "-m", "snakemake", *args, "-s", str(SNAKEFILE), "--directory",
           str(workdir), "--cores", "2", "--nocolor", "--configfile", str(config)]
    env = {k: v for k, v in os.environ.items() if k != "DASK_SCHEDULER_ADDRESS"}
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout)
    assert out.returncode == 0, out.stderr[-4000:]
    return out


def planned_rules(workdir: Path, config: Path) -> set[str]:
    """Rules a dry run plans (its job table: ``rule  count``)."""
    dry = snakemake(workdir, config, "-n")
    return set(re.findall(r"^(\w+)\s+\d+$", dry.stdout, re.MULTILINE)) - {"total"}


def write(path: Path, config: dict) -> Path:
    path.write_text(yaml.safe_dump(config))
    return path


@pytest.mark.slow
def test_figure_targets_follow_the_study_spec(tmp_path):
    own = planned_rules(tmp_path / "own", write(tmp_path / "own.yaml", OWN))
    assert OWN_FIGURES | {"report"} <= own
    assert not own & PAPER_ONLY, own & PAPER_ONLY
    # the same study declared a reproduction of the paper gets the paper's model figures
    # (Figs 3, 4, 6); Fig 12 needs a 2D mode beside 3D, Fig 11 several tan α
    paper = json.loads(json.dumps(OWN))
    paper["studies"]["column"]["reproduces"] = "vassiliou2017"
    paper["studies"]["column"]["runs"].append(
        {"modes": ["2d-x"], "tan_alpha": [TAN_ALPHA], "limit_states": ["overturning"]})
    planned = planned_rules(tmp_path / "paper", write(tmp_path / "paper.yaml", paper))
    assert PAPER_ONLY - {"fig11_slenderness"} <= planned
    assert "fig11_slenderness" not in planned
    # the paper's configuration plans the paper's figures, as it always did
    full = planned_rules(tmp_path / "full", REPO / "config/paper.yaml")
    assert PAPER_ONLY | OWN_FIGURES | {"fig07_tilt_map", "report"} <= full


@pytest.fixture(scope="module")
def own_run(tmp_path_factory) -> Path:
    """The study's report and everything it needs, by the real workflow."""
    work = tmp_path_factory.mktemp("own")
    snakemake(work, write(work / "own.yaml", OWN), "results/column/report.html")
    return work


def _figures(run: Path) -> dict[str, Path]:
    pngs = [*run.glob("results/figures/*.png"), *run.glob("results/column/figures/*.png")]
    from rocking.plot import figure_name

    return {figure_name(p): p for p in pngs}


@pytest.mark.slow
def test_own_study_draws_no_empty_figure(own_run):
    from rocking.plot import fig09_spectra, fig10_goals, fragility_curves

    assert set(_figures(own_run)) == OWN_FIGURES
    for name, png in _figures(own_run).items():
        missing = json.loads(png.with_suffix(".json").read_text()).get("missing", [])
        # nothing the study asked for is missing; Fig 8 only cautions that one synthetic
        # pair is few, and nothing is measured against the paper
        assert missing == [] or name == "fig08_motions", (name, missing)
        assert not any("paper" in s for s in missing), (name, missing)
    res = own_run / "results/column"
    from rocking.config.ensemble import EnsembleSpec

    motions = own_run / f"results/motions/own-{EnsembleSpec.from_config(OWN, 'own').digest}.nc"
    # every panel of every spectrum figure holds the study's numbers at its own tan α
    d9 = fig09_spectra.data(res / "spectra.zarr", res / "mean_spectra.nc", motions=motions)
    assert d9["tan_alpha"] == TAN_ALPHA and d9["modes"] == ["3d"]
    assert [p["limit_state"] for p in d9["panels"]] == ["overturning", "tilt:1/3"]
    assert all(np.isfinite(p["means"]["3d"]).any() for p in d9["panels"])
    d10 = fig10_goals.data(res / "mean_spectra.nc", motions=motions, paper=False)
    assert d10["tan_alpha"] == TAN_ALPHA and set(d10["curves"]) == {"overturning", "tilt:1/3"}
    assert d10["missing"] == []
    df = fragility_curves.data(res / "fragility.nc", res / "spectra.zarr", motions=motions)
    assert df["tan_alpha"] == TAN_ALPHA and len(df["panels"]) == 2
    assert all(p["curves"] for p in df["panels"])
    for mod, d in ((fig09_spectra, d9), (fig10_goals, d10), (fragility_curves, df)):
        fig = mod.plot(d)
        # no empty axes: every data panel draws a line with finite values, and the secondary
        # PGA [g] axis is at the study's tan α
        panels = [ax for ax in fig.axes if ax.get_lines()]
        assert panels, mod.__name__
        for ax in panels:
            assert any(np.isfinite(np.asarray(ln.get_ydata(), float)).any()
                       for ln in ax.get_lines()), (mod.__name__, ax.get_title())
        labels = [t.get_text() for ax in fig.axes for t in ax.findobj(
            lambda a: hasattr(a, "get_text"))]
        assert any("tan α = 0.15" in s for s in labels), mod.__name__


@pytest.mark.slow
def test_own_study_report_has_no_paper_verdict(own_run):
    html = (own_run / "results/column/report.html").read_text()
    assert html.count("<figure") == len(OWN_FIGURES)
    assert "The paper against this run" not in html and "href='#verdicts'" not in html
    for verdict in ("reproduced", "differs", "not reproducible", "not in the paper"):
        assert f"class='{verdict.replace(' ', '-')}'" not in html
    # captions say what the figure shows, not what the paper reports
    assert "The paper reports" not in html and "The paper's Fig" not in html
    # what was computed is there: the study's grids, its fragility and line fits
    assert re.search(r"slenderness tan α</td>\s*<td>0.15</td>", html)
    assert "Lognormal fragility parameters" in html
    # two sizes R: no line fitted through them, in the report or the figure
    assert "Linear fits" not in html
    notes = json.loads((own_run / "results/column/figures/fig10_goals.json").read_text())
    assert not any(k.startswith("line|") for k in notes["measured"])


THROWAWAY = '''"""A figure added by a test: its module with its entry, and nothing else."""

from matplotlib.figure import Figure

from rocking.plot import open_means
from rocking.plot.registry import FigureSpec


def data(means):
    ds = open_means(means)
    return {"R": ds["R"].values, "measured": {"sizes": int(ds.sizes["R"])}}


def plot(d):
    fig = Figure(figsize=(4, 3))
    ax = fig.add_subplot()
    ax.plot(d["R"], d["R"], "o-")
    ax.set_xlabel("cylinder size R [m]")
    ax.set_ylabel("cylinder size R [m]")
    return fig


FIGURE = FigureSpec(
    name="fig99_throwaway", module=__name__, number=99, label="throwaway",
    caption="A throwaway figure: the sizes R of the study's mean spectra.",
    scope="study", wanted=lambda subject: bool(subject.plan.modes),
    inputs={"means": "means"}, category="Beyond the paper")
'''


def _installed_figure(site: Path) -> dict[str, str]:
    """A figure module outside the package, named under the entry-point group
    ``rocking.figures`` of a distribution on ``site``; the environment that finds it."""
    site.mkdir()
    (site / "throwaway_figure.py").write_text(THROWAWAY)
    meta = site / "throwaway_figure-0.1.dist-info"
    meta.mkdir()
    (meta / "METADATA").write_text("Metadata-Version: 2.1\nName: throwaway-figure\n"
                                   "Version: 0.1\n")
    (meta / "entry_points.txt").write_text("[rocking.figures]\nthrowaway = throwaway_figure\n")
    env = {k: v for k, v in os.environ.items() if k != "DASK_SCHEDULER_ADDRESS"}
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(site), env.get("PYTHONPATH")) if p)
    return env


@pytest.mark.slow
def test_a_figure_module_with_its_entry_is_enough(own_run, tmp_path, monkeypatch):
    """A new figure is its module and its entry: the workflow plans and draws it and the
    report shows it with its caption, with no rule, script, caption table or list edited
    (the study's run is reused: only the new figure and the report are made)."""
    import shutil

    from rocking.plot import registry

    work = tmp_path / "run"
    shutil.copytree(own_run, work, symlinks=True)
    env = _installed_figure(tmp_path / "site")
    cmd = [sys.executable, "-m", "snakemake", "results/column/report.html", "-s",
           str(SNAKEFILE), "--directory", str(work), "--cores", "2", "--nocolor",
           "--configfile", str(work / "own.yaml")]
    dry = subprocess.run([*cmd, "-n"], env=env, capture_output=True, text=True, timeout=300)
    assert dry.returncode == 0, dry.stderr[-4000:]
    planned = set(re.findall(r"^(\w+)\s+\d+$", dry.stdout, re.MULTILINE)) - {"total"}
    assert planned == {"fig99_throwaway", "report"}, planned
    run = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-4000:]
    figure = work / "results/column/figures/fig99_throwaway"
    assert figure.with_suffix(".png").stat().st_size > 1000
    assert json.loads(figure.with_suffix(".json").read_text())["measured"] == {"sizes": 2}
    html = (work / "results/column/report.html").read_text()
    assert html.count("<figure") == len(OWN_FIGURES) + 1
    assert "<figure id='fig99_throwaway'>" in html
    assert "A throwaway figure: the sizes R of the study&#x27;s mean spectra." in html
    # after the study's own figures: its number places it
    assert html.index("id='fragility_curves'") < html.index("id='fig99_throwaway'")
    # in this process too, once the entry point is on the path
    monkeypatch.syspath_prepend(str(tmp_path / "site"))
    registry.refresh()
    try:
        assert list(registry.figures())[-1] == "fig99_throwaway"
    finally:
        monkeypatch.undo()
        registry.refresh()
    assert "fig99_throwaway" not in registry.figures()


SUITE = {
    "accuracy": "fast",
    "motions": {"max_duration": 3.0},
    "ensembles": {"mine": {"n_synthetic": 0, "records": [
        {"record": "el-centro-1940"}, {"record": "loma-prieta-corralitos"}]}},
    "studies": {"column": {
        "ensemble": "mine", "R": [2.5, 4.0], "chunk_R": 1,
        "runs": [{"modes": ["3d"], "tan_alpha": [0.15],
                  "limit_states": ["overturning", "tilt:1/3"]}],
    }},
    "dask": {"progress_interval": 0},
}


@pytest.mark.slow
def test_a_suite_study_speaks_its_own_language(tmp_path):
    """Shipped records, no synthetic pairs: no paper numbering in a title or caption, no
    caption describing what is not drawn, x axes on the study's sizes, the per-record table
    and the findings in the report."""
    from rocking.plot import fig09_spectra, fig10_goals

    wd = tmp_path / "suite"
    snakemake(wd, write(tmp_path / "suite.yaml", SUITE), "results/column/report.html")
    html = (wd / "results/column/report.html").read_text()
    each = re.findall(r"<figcaption[^>]*>(.*?)</figcaption>", html, re.S)
    assert len(each) == html.count("<figure ") and all(c.strip() for c in each)
    captions = " ".join(each)
    assert captions and "synthetic" not in captions and "damped" not in captions
    assert not re.search(r"\bFig \d", captions)
    assert "the 2 recorded motions" in captions
    assert html.index("id='findings'") < html.index("id='what-was-run'")
    assert "The most dangerous of the 2 records" in html and "id='records'" in html
    assert "0 synthetic pairs" not in html
    res = wd / "results/column"
    for mod, d in ((fig09_spectra, fig09_spectra.data(res / "spectra.zarr",
                                                      res / "mean_spectra.nc", paper=False)),
                   (fig10_goals, fig10_goals.data(res / "mean_spectra.nc", paper=False))):
        fig = mod.plot(d)
        texts = [t.get_text() for t in fig.findobj(lambda a: hasattr(a, "get_text"))]
        assert not any(re.search(r"\(Fig \d+\)", t) for t in texts), mod.__name__
        assert any("suite mine (2 records)" in t for t in texts), mod.__name__
        for ax in (a for a in fig.axes if a.get_xlabel() == "R [m]"):
            assert ax.get_xlim()[0] > 2.0  # the study's sizes, not from R = 0


# ------------------------------------------------------- the choices, without the workflow


def test_reproduces_is_checked_and_decides_no_store():
    from rocking.config.study import StudySpec

    config = yaml.safe_load((REPO / "config/paper.yaml").read_text())
    spec = StudySpec.from_config(config, "lomaprieta")
    assert spec.reproduces == "vassiliou2017"
    assert StudySpec.from_attrs(spec.to_attrs()).reproduces == "vassiliou2017"
    del config["studies"]["lomaprieta"]["reproduces"]
    own = StudySpec.from_config(config, "lomaprieta")
    assert own.reproduces is None and own.spectra.digest == spec.spectra.digest
    config["studies"]["lomaprieta"]["reproduces"] = "housner1963"
    with pytest.raises(ValueError, match=r"studies\.lomaprieta\.reproduces must be one of "
                                         r"\['vassiliou2017'\] or null, got 'housner1963'"):
        StudySpec.from_config(config, "lomaprieta")


def test_panels_and_slenderness_follow_the_study():
    import xarray as xr

    from rocking.plot import _load

    # the paper's two panels where computed, else the study's own most severe goals
    assert _load.panel_limit_states(["tilt:0.1", "tilt:1/3", "overturning"]) == [
        "overturning", "tilt:1/3"]
    assert _load.panel_limit_states(["tilt:0.5", "overturning"]) == ["overturning", "tilt:0.5"]
    assert _load.panel_limit_states(["tilt:0.2", "tilt:0.75", "tilt:0.5"]) == [
        "tilt:0.75", "tilt:0.5"]
    assert _load.panel_limit_states(["overturning"]) == ["overturning"]
    # the slenderness with the most goals of every mode drawn; among equals the middle one
    req = np.zeros((2, 3, 3), bool)  # mode, limit state, tan α
    req[0, :, 1] = True  # "3d": three goals at 0.2, one at 0.1 and 0.3
    req[0, 0, [0, 2]] = True
    req[1, 0, 2] = True  # "3d-damped": one goal at 0.3 only
    ds = xr.Dataset({"requested": (("mode", "limit_state", "tan_alpha"), req)},
                    coords={"mode": ["3d", "3d-damped"],
                            "limit_state": ["overturning", "tilt:1/3", "tilt:0.1"],
                            "tan_alpha": [0.1, 0.2, 0.3]})
    assert _load.main_tan_alpha(ds, ["3d"]) == 0.2
    assert _load.main_tan_alpha(ds, ["3d", "3d-damped"]) == 0.3
    assert _load.primary_mode(ds) == "3d"
    ds["requested"][:] = True
    assert _load.main_tan_alpha(ds, ["3d"]) == 0.2  # all equal: the middle


def test_risk_summary_follows_the_table():
    import pandas as pd

    from rocking.report.risk import main_tan_alpha, risk_section_html, summary_table

    rows = [{"mode": "3d", "limit_state": ls, "tan_alpha": TAN_ALPHA, "R": R,
             "maf": 1e-3 / R / (2 if ls == "overturning" else 1)}
            for ls in ("overturning", "tilt:0.5") for R in (1.0, 3.0)]
    frame = pd.DataFrame(rows)
    assert main_tan_alpha(frame) == TAN_ALPHA
    table = summary_table(frame)
    assert list(table.columns) == ["R [m]", "overturning, 3d [1/yr]", "tilt:0.5, 3d [1/yr]"]
    assert table["overturning, 3d [1/yr]"].tolist() == [5e-4, 1e-3 / 6]
    assert "at tan α = 0.15" in risk_section_html(frame)


def test_figs_10_and_12_count_means_over_answers_on_a_plateau(tmp_path):
    """``n_plateau`` of mean_spectra (answers where P rises near p without crossing it) is
    counted per curve, exactly the sizes where it is > 0: in Fig 10's legend and Fig 12's
    note, not ringed on every point; none without."""
    import figures_synthetic as fs
    import xarray as xr

    from rocking.plot import fig10_goals, fig12_2d_vs_3d

    paths = fs.write_study(tmp_path / "s", with_tilt_map=False)
    agg = xr.open_dataset(paths["means"]).load()
    flag = xr.zeros_like(agg["count"])
    flag.loc[{"mode": "3d", "limit_state": "overturning", "tan_alpha": 0.2}] = [2, 0, 0, 1, 0]
    flagged = tmp_path / "flagged.nc"
    agg.assign(n_plateau=flag).to_netcdf(flagged)
    where = np.array([True, False, False, True, False])

    d10 = fig10_goals.data(flagged)
    assert list(d10["plateau"]) == ["overturning"]
    np.testing.assert_array_equal(d10["plateau"]["overturning"], where)
    fig = fig10_goals.plot(d10)
    assert not [ln for ln in fig.axes[0].get_lines() if ln.get_mfc() == "white"
                and len(ln.get_xdata())]
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    counted = [s for s in legend if "plateau" in s]
    assert len(counted) == 1 and counted[0].startswith("Overturning")
    assert counted[0].endswith(f"; 2 of {len(fs.R)} means on a plateau")
    plain = fig10_goals.data(paths["means"])
    assert plain["plateau"] == {}

    d12 = fig12_2d_vs_3d.data([("own", flagged, paths["store"])], paper=False)
    fig = fig12_2d_vs_3d.plot(d12)
    assert not [ln for ax in fig.axes[:2] for ln in ax.get_lines()
                if ln.get_marker() == "D" and len(ln.get_xdata())]
    note = "".join(t.get_text() for t in fig.texts)
    assert "on a plateau" in note and f"overturning 2/{len(fs.R)}" in note
    # a study of one's own: no paper ensembles asked for, no paper axes note, no Fig number
    assert d12["missing"] == [] and "22.33" not in note and "Fig 12" not in note
    assert "(Fig 12)" not in fig._suptitle.get_text()


def test_fig11_of_a_study_of_ones_own_draws_its_own_slendernesses(tmp_path):
    import figures_synthetic as fs

    from rocking.plot import fig11_slenderness

    paths = fs.write_study(tmp_path, requested={"3d": [0.1, 0.3]}, with_tilt_map=False)
    own = fig11_slenderness.data(paths["means"], paper=False)
    assert own["missing"] == []
    assert [sorted(p["curves"]) for p in own["panels"]] == [[0.1, 0.3], [0.1, 0.3]]
    # a reproduction of the paper names the paper's slenderness the run left out
    paper = fig11_slenderness.data(paths["means"])
    assert "tan α = 0.2 not computed" in paper["missing"]


SITE_INVENTORY = """id,R,tan_alpha,lon,lat
node,1.0,0.15,0.001,0.001
between,2.0,0.175,0.002,-0.001
far-node,3.0,0.2,-0.001,0.002
"""
"""Three columns on the grid of the study ``site``: two at grid nodes, one between."""


@pytest.mark.slow
def test_a_study_with_an_inventory_gets_its_portfolio_and_an_inventory_change_reruns_only_it(
        own_run, tmp_path):
    """``inventory:`` in a study: portfolio.csv, its figures and its report section, by the
    workflow (a study of two R × two tan α beside the shared run's, on its motions); a
    column at a grid node gets the study's own median and β; an edited inventory reruns
    only the portfolio and the report, no search."""
    import shutil

    import pandas as pd

    work = tmp_path / "run"
    shutil.copytree(own_run, work, symlinks=True)
    (work / "columns.csv").write_text(SITE_INVENTORY)
    cfg = json.loads(json.dumps(OWN))
    cfg["studies"]["site"] = {
        "ensemble": "own", "R": [1.0, 3.0], "chunk_R": 1,
        "hazard": {"file": str(REPO / "config/hazard/example_hazard_curve.csv"),
                   "site": {"lon": 0.0, "lat": 0.0}, "component": "vector_peak"},
        "inventory": {"file": "columns.csv", "export": "column", "resamples": 50},
        "runs": [{"modes": ["3d"], "tan_alpha": [0.15, 0.2],
                  "limit_states": ["overturning", "tilt:1/3"]}]}
    config = write(work / "site.yaml", cfg)
    snakemake(work, config, "results/site/report.html", "results/site/exposure")
    out = work / "results/site"
    table = pd.read_csv(out / "portfolio.csv")
    assert sorted(table["id"].unique()) == ["between", "far-node", "node"]
    assert set(table["limit_state"]) == {"overturning", "tilt:1/3"}
    assert (table["component"] == "vector_peak").all()
    assert table["hazard_site"].nunique() == 1 and (table["hazard_lon"] == 0.0).all()
    frag = pd.read_csv(out / "fragility.csv")
    for ident, R, ta in (("node", 1.0, 0.15), ("far-node", 3.0, 0.2)):
        for ls in ("overturning", "tilt:1/3"):
            row = table[(table["id"] == ident) & (table["limit_state"] == ls)].iloc[0]
            node = frag[(frag["mode"] == "3d") & (frag["limit_state"] == ls)
                        & np.isclose(frag["tan_alpha [-]"], ta) & np.isclose(frag["R [m]"], R)]
            # to the 6 digits portfolio.csv is written with (in-process to 1e-9:
            # tests/test_surface.py)
            assert row["median"] == pytest.approx(node["median_pga_g [g]"].iloc[0], rel=5e-6)
            assert row["beta"] == pytest.approx(node["beta [-]"].iloc[0], rel=5e-6)
    for stem in ("portfolio_map", "portfolio_ranked"):
        assert (out / "figures" / f"{stem}.png").stat().st_size > 10_000
    html = (out / "report.html").read_text()
    assert "Every column of the site" in html and "<figure id='portfolio_map'>" in html
    assert (out / "exposure" / "exposure.xml").is_file()
    # a new column: the portfolio, its export, its two figures and the report again, nothing
    # else
    (work / "columns.csv").write_text(SITE_INVENTORY + "extra,1.5,0.16,0.0,0.0\n")
    dry = snakemake(work, config, "results/site/report.html", "results/site/exposure", "-n")
    planned = set(re.findall(r"^(\w+)\s+\d+$", dry.stdout, re.MULTILINE)) - {"total"}
    assert planned == {"portfolio", "exposure", "portfolio_map", "portfolio_ranked",
                       "report"}, planned
