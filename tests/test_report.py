"""The HTML report: what was run, every figure with its caption, and per figure the paper's
statements against this run's numbers with verdicts that follow from the numbers."""

from __future__ import annotations

import json
import math
from pathlib import Path

import figures_synthetic as fs
import numpy as np
import pandas as pd
import pytest

from rocking.fragility import lognormal as fragility
from rocking.plot import (
    FIGURES,
    _load,
    _style,
    fig08_motions,
    fig09_spectra,
    fig10_goals,
    figure_name,
    render,
)
from rocking.plot import comparisons as cmp
from rocking.plot.registry import caption, figures
from rocking.report import entries, run_summary, tables
from rocking.report import html as report

CAPTIONS = {name: caption(name) for name, f in figures().items() if not f.section}
"""Every figure's caption in a reproduction of the paper, in the paper's order (those of the
report's own sections: their tests)."""


def _quality(ratio: float, inside: float) -> dict:
    comp = {"band_ratio": {"0.1-0.3 s": ratio, "0.3-1 s": ratio, "1-4 s": ratio},
            "ratio_min": ratio, "ratio_max": ratio, "inside_5_95": inside, "n": 3}
    return {"x": comp, "y": comp}


QUALITY = {"spectrum": _quality(0.93, 0.9), "counts": _quality(0.43, 0.12)}


@pytest.fixture(scope="module")
def outputs(tmp_path_factory):
    root = tmp_path_factory.mktemp("report")
    paths = fs.write_study(root / "study")
    out = root / "figures"
    pngs = []

    def fig(name, stem=None, **kw):
        stem = stem or name
        render(name, [out / f"{stem}.png"], out / f"{stem}.json", **kw)
        pngs.append(out / f"{stem}.png")

    fig("fig03_wobbling_period", n=40)
    fig("fig07_tilt_map", path=paths["tilt_map"], motions=paths["motions"])
    fig("fig09_spectra", store=paths["store"], means=paths["means"])
    fig("fig10_goals", means=paths["means"])
    fig("fig11_slenderness", means=paths["means"])
    fig("fig12_2d_vs_3d", studies=[("elcentro", paths["means"], paths["store"])])
    table = fragility.fragility_table(_load.open_store(paths["store"]))
    table.to_netcdf(root / "fragility.nc")
    fragility.to_frame(table).to_csv(root / "fragility.csv", index=False)
    lines = fragility.linear_fit_table(_load.open_means(paths["means"]))
    fragility.to_frame(lines).to_csv(root / "linear_fit.csv", index=False)
    fig("fragility_curves", fragility=root / "fragility.nc", store=paths["store"])
    # Figures of analyses (4, 6, 8) as the report receives them: a PNG and its notes
    notes = {
        "fig04_free_vibration": {"turn_angle_first": 3.1881, "turn_angle_mean": 3.1880,
                                 "n_turns": 6, "restitution_damped": 0.9422,
                                 "restitution_undamped": 1.0,
                                 "restitution_damped_range": [0.9421, 0.9423],
                                 "max_gap_theta_damped_pairs_quasi-rocking": 7e-4,
                                 "max_gap_theta_damped_pairs_wobbling": 0.0,
                                 "max_gap_theta_damped_pairs_mixed": 0.01,
                                 "max_gap_theta_damped_undamped_wobbling": 0.0,
                                 "max_gap_theta_damped_undamped_mixed": 1e-5},
        "fig06_el_centro": {"theta_max_3d": 0.048, "theta_max_3d-damped": 0.0479,
                            "t_part_theta": 15.8},
        "fig06_theta_max_sensitivity": {
            "band": 0.05, "versions": ["as recorded", "processed"],
            "band_range|as recorded|3d": [0.046, 0.091],
            "band_range|processed|3d": [0.022, 0.068],
            "component_pga_g|as recorded (x E–W, y N–S), unfiltered": [0.211, 0.281],
            "pga_g|as recorded (x E–W, y N–S), unfiltered": 0.2865,
            "rotation_check": {"3d": 1e-11}},
        "fig08_motions_elcentro": {"record": "el-centro-1940", "record_pga_g": 0.2753,
                                   "principal_offset_deg": 19.54, "n_motions": 4,
                                   "fit_method": "spectrum", "fit_quality": QUALITY},
    }
    for stem, measured in notes.items():
        f, _ = _style.new_figure(2.0, 2.0)
        _style.save(f, [out / f"{stem}.png"])
        _style.write_notes(out / f"{stem}.json", {"measured": measured, "missing": [],
                                                 "body": {"theta0": 0.1, "omega_n": 2000.0,
                                                          "zeta": 5.0}})
        pngs.append(out / f"{stem}.png")
    ensemble_json = root / "elcentro.json"
    ensemble_json.write_text(json.dumps(
        {"ensemble": "elcentro", "label": "El Centro", "rotation_deg": -70.46,
         "principal_offset_deg": 19.54, "highpass": {"kind": "oscillator", "fc_hz": 0.0946,
                                                     "mw": 6.95},
         "n_synthetic": 3, "seed": 2017, "timings": {"fit_s": 7.4}}))
    done = root / "study" / "spectra.done.json"
    done.write_text(json.dumps({"wall_seconds": 638.4, "chunks": 48, "computed": 48,
                                "cluster": "local", "done_before": 0}))
    run = run_summary.what_was_run(
        stores=[paths["store"]], tilt_maps=[paths["tilt_map"]], ensembles=[ensemble_json],
        done=[done], elapsed_seconds=840.0)
    page = report.build(root / "report.html", title="synthetic study", figures=pngs,
                        linear_fit=root / "linear_fit.csv", fragility=root / "fragility.csv",
                        notes=["The Loma Prieta record is a stand-in."], run=run,
                        verdicts_csv=root / "verdicts.csv")
    return {"root": root, "pngs": pngs, "html": page, "run": dict(run), "paths": paths}


def test_report_shows_every_figure_with_its_caption(outputs):
    text = outputs["html"].read_text()
    assert text.count("<figure") == len(outputs["pngs"]) == 11
    assert text.count("data:image/png;base64,") == 11
    docs = report.docs_href(outputs["html"].parent)
    for name, text_of in CAPTIONS.items():
        assert report.link_docs(text_of, docs) in text, name
    # the derivations cited are links that reach docs/equations.md
    assert f"<a class='doc' href='{docs}#eq-24-the-wobbling-period'>" in text
    assert (outputs["html"].parent / docs).resolve().is_file()
    # figures in the paper's order
    positions = [text.index(f"id='{n}") for n in CAPTIONS]
    assert positions == sorted(positions)
    assert "The Loma Prieta record is a stand-in." in text
    assert text.index("What was run") < text.index("figure by figure") < text.index("<figure")


def test_what_was_run_says_config_grids_modes_contact_seeds_version_and_time(outputs):
    run = outputs["run"]
    assert run["study synth: sizes R"] == "1, 2, 4, 6, 10 m"
    assert run["study synth: slenderness tan α"] == "0.1, 0.2, 0.3"
    assert "Tilt θ > α/3 (excessive tilt)" in run["study synth: limit states"]
    assert run["study synth: modes per tan α"].startswith(
        "tan α = 0.1: 3d, 3d-damped, 3d-x, 3d-y, 2d-x, 2d-y;")
    assert "ωn = 2000 rad/s, ζ = 5" in run["study synth: damped contact (3d-damped)"]
    assert "{0.05, 0.5, 5, 50}" in run["study synth: damped contact (3d-damped)"]
    assert "seed 2017" in run["ensemble elcentro"] and "0.0946 Hz" in run["ensemble elcentro"]
    assert run["study synth: package version"] == "rocking 0.1.0"
    assert "intensity_rtol = 0.01" in run["study synth: accuracy"]
    assert run["run time: study/spectra"].startswith("638 s wall for 48 of 48 chunks")
    assert run["run time: workflow"].startswith("14.0 min")
    # one PGA, with what it is; the unprocessed numbers only for reference
    pga = run["record PGA"]
    assert pga.startswith(f"{2.7 / 9.80665:.3f} g: vector peak")
    assert "high-pass" in pga
    # the Fig 6 companion adds the unprocessed record's peaks through its run_rows hook
    text = outputs["html"].read_text()
    assert "record PGA, unprocessed" in text and "y (N–S) 0.281 g" in text


def test_fig09_damping_is_quantified_per_R(outputs):
    entry = next(e for e in entries.load_figures(outputs["pngs"]) if e.name == "fig09_spectra")
    tables = dict(fig09_spectra.report_tables(entry.notes))
    assert len(tables) == 2
    tilt = next(df for title, df in tables.items() if "α/3" in title)
    # the synthetic damped spectra are 5 % above the undamped ones for every motion
    assert tilt["R [m]"].tolist() == fs.R
    assert tilt["Δ of the means [%]"].tolist() == pytest.approx([5.0] * len(fs.R))
    # d − u = 0.05 u scatters with the motion factors f: SE of Δ = 0.05 · std(f)/mean(f)/√n
    f = np.array([1.0, 0.8, 1.25, 1.1])
    se = 0.05 * np.std(f, ddof=1) / np.mean(f) / np.sqrt(f.size)
    assert tilt["± 2 SE of Δ [%]"].tolist() == pytest.approx([200 * se] * len(fs.R), abs=6e-3)
    assert set(tilt["essentially identical"]) == {"yes"}
    assert "spread among motions, std/mean undamped [%]" in outputs["html"].read_text()


def test_modes_per_tan_alpha_of_a_partial_store(tmp_path):
    paths = fs.write_study(tmp_path, requested={"3d-damped": [0.2], "3d-x": [0.2],
                                                "3d-y": [0.2], "2d-x": [0.2], "2d-y": [0.2]},
                           with_tilt_map=False)
    text = run_summary.modes_text(_load.open_store(paths["store"]))
    assert text.startswith("tan α = 0.1: 3d; tan α = 0.2: 3d, 3d-damped, 3d-x, 3d-y, 2d-x, "
                           "2d-y; tan α = 0.3: 3d")
    # 5 modes × 2 slendernesses × 4 limit states × 4 motions × 5 sizes left empty
    assert f"{5 * 2 * 4 * 4 * 5} of {6 * 3 * 4 * 4 * 5} cells not computed" in text
    assert run_summary.grid_text([0.5 + 0.5 * i for i in range(20)], "m") == (
        "20 values, 0.5–10 m (step 0.5)")


def test_every_figure_has_a_verdict(outputs):
    figures = entries.load_figures(outputs["pngs"])
    verdicts = entries.figure_comparisons(figures)
    assert set(verdicts) == set(CAPTIONS)
    for name, rows in verdicts.items():
        assert rows, name
        assert all(r.verdict in cmp.VERDICTS for r in rows)
    text = outputs["html"].read_text()
    for verdict in ("reproduced", "differs because", "not computed in this run"):
        assert verdict in text
    # the verdict table as data: the page's rows, in its order
    table = pd.read_csv(outputs["root"] / "verdicts.csv", keep_default_na=False)
    assert list(table.columns) == list(entries.VERDICT_COLUMNS)
    shown = [c for rows in verdicts.values() for c in rows]
    assert [tuple(r) for r in table.itertuples(index=False)] == [
        (c.figure, c.statement, c.paper, c.ours, c.verdict, c.reason) for c in shown]
    page = text[text.index("<h2 id='verdicts'>"):]
    assert page[:page.index("</table>")].count("<tr><td>") == len(table) > 20


def test_verdicts_follow_from_the_numbers(outputs):
    figures = entries.load_figures(outputs["pngs"])
    rows = {(r.figure, r.statement): r for r in cmp.compare({f.stem: f.notes for f in figures})}

    def find(figure, words):
        return next(r for (f, s), r in rows.items() if f == figure and words in s)

    # Eq 32: 0.9422 against 0.942 within 0.002
    assert find("fig04_free_vibration", "restitution").verdict == cmp.REPRODUCED
    # Eq 27: ours is 2π minus the printed value: differs, and says so with the number
    eq27 = find("fig04_free_vibration", "Eq (27)")
    assert eq27.verdict == cmp.DIFFERS and f"{2 * math.pi - 3.1881:.4g}" in eq27.reason
    # the mixed case's pairs are 0.01 rad apart (> 2 % of θ0): differs, one row for 3 cases
    pairs = find("fig04_free_vibration", "Damped responses for")
    assert pairs.verdict == cmp.DIFFERS and "mixed 0.01 rad" in pairs.ours
    assert "quasi-rocking 0.0007 rad" in pairs.ours
    # Fig 6: 0.048 against 0.0838; the paper's value inside the as-recorded band only
    peak = find("fig06_el_centro", "undamped, R = 6 m")
    assert peak.verdict == cmp.DIFFERS and "inside the range of as recorded" in peak.reason
    assert find("fig06_el_centro", "first 15 s").verdict == cmp.REPRODUCED
    # synthetic damped spectra are exactly 5 % above the undamped: at the tolerance
    damp = find("fig09_spectra", "Tilt θ > α/3")
    assert damp.verdict == cmp.REPRODUCED
    # synthetic means are linear in R (R² = 1 where all motions count)
    assert find("fig10_goals", "Tilt θ > α/10").verdict == cmp.REPRODUCED
    assert find("fig10_goals", "Seven").verdict == cmp.NOT_COMPUTED
    # slenderness spread of the synthetic store: (1.02 − 0.97)/mean ≈ 5 % ≤ 15 %
    assert find("fig11_slenderness", "Overturning").verdict == cmp.REPRODUCED
    # Fig 12 at R = 10 m: 3D overturning 4·(0.5 + 4)·mean(1, 0.8, 1.25, 1.1) (cut-offs aside)
    r10 = find("fig12_2d_vs_3d", "Overturning of an R = 10 m")
    assert r10.verdict == cmp.DIFFERS
    # every motion reaches θ > α/3 at R = 10 m: 3D-x is exactly MODE_FACTOR = 1.9 × 3D
    # no fragility table beside the means: the means at R = 10 m, judged against their
    # standard errors (ln 1.9 far above 2 SE) and never without saying so
    ratio = find("fig12_2d_vs_3d", "El Centro, excessive tilt: the 3D model under the x")
    assert ratio.verdict == cmp.REPRODUCED and ratio.ours.startswith("3D x/3D = 1.9 (")
    assert "no fragility table" in ratio.statement and "second component alone" in ratio.reason
    # Housner's block beside it, quoted and named, not judged against the paper
    housner = find("fig12_2d_vs_3d", "El Centro, excessive tilt: Housner's 2D block")
    assert housner.verdict == cmp.NOT_IN_PAPER and housner.ours.startswith("2D x/3D = 2 (")
    assert "e = 0.942" in housner.reason and "a further comparator" in housner.statement
    assert find("fig12_2d_vs_3d", "Loma Prieta, overturning").verdict == cmp.NOT_COMPUTED
    assert find("fig08_motions", "Rotation").verdict == cmp.DIFFERS
    assert find("fragility_curves", "fragility").verdict == cmp.NOT_IN_PAPER


def test_fig09_judges_the_difference_of_means_against_its_standard_error():
    """A large difference that the scatter explains is "identical"; a small systematic one
    too; a large one beyond 2 SE is not, and the reason names where."""
    eff = {"rel_diff_means": [0.012, 0.13, 0.002, 0.30], "se_rel_diff_means": [0.001, 0.10,
                                                                                0.01, 0.05],
           "paired_mean": [0.012, 0.17, 0.0, 0.3], "paired_se": [0.001, 0.1, 0.01, 0.05],
           "paired_n": [11, 11, 11, 11], "cov_undamped": [0.05, 0.25, 0.1, 0.3],
           "max_abs_rel_diff_means": 0.30, "R_index_of_max": 3}
    j = fig09_spectra.damping_judgement(eff)
    assert j["ok"] == [True, True, True, False]
    assert j["noise"] == [1] and j["small_systematic"] == [0] and j["failed"] == [3]
    row = fig09_spectra.compare({"fig09_spectra": {"measured": {"R": [0.5, 1.0, 8.0, 10.0],
                                                    "damping|overturning": eff}}})[-1]
    assert row.verdict == cmp.DIFFERS and "R = 10 m" in row.reason and "R = 8" not in row.reason
    eff.update(rel_diff_means=[0.012, 0.13, 0.002, 0.04], max_abs_rel_diff_means=0.13,
               R_index_of_max=1)
    row = fig09_spectra.compare({"fig09_spectra": {"measured": {"R": [0.5, 1.0, 8.0, 10.0],
                                                    "damping|overturning": eff}}})[-1]
    assert row.verdict == cmp.REPRODUCED
    assert "at R = 1 m Δ exceeds 5 % but lies within 2 SE" in row.reason
    assert "at R = 0.5 m a small systematic Δ" in row.reason


RECORDS = {"elcentro": ("El Centro", "el-centro", "RSN 6", "22.33"),
           "lomaprieta": ("Loma Prieta", "loma-prieta", "Corralitos", "RSN 753")}


def _two_ensembles() -> dict:
    """Notes of Figs 8 and 12 for an El Centro and a Loma Prieta ensemble, the latter with
    motions not reached at the search bound at R = 10 m."""
    m12 = {"R": 10.0}
    for ens, label, censored in (("elcentro", "El Centro 1940: mean of 11 motions", 0),
                                 ("lomaprieta", "Loma Prieta 1989 (stand-in: Corralitos RSN "
                                                "753): mean of 11 motions", 4)):
        m12[f"{ens}|label"], m12[f"{ens}|n_motions"] = label, 11
        m12[f"{ens}|stand_in"], m12[f"{ens}|upper"] = ens == "lomaprieta", 20.0
        for title, base in (("overturning", 4.7), ("excessive tilt", 1.9)):
            # censored means of Loma Prieta overturning: 2D hardly above 3D (the paper run)
            factors = (1.07, 1.13) if censored and title == "overturning" else (2.4, 1.8)
            for mode, f in (("3d", 1.0), ("3d-x", factors[0]), ("3d-y", factors[1]),
                            ("2d-x", factors[0]), ("2d-y", factors[1])):
                short = censored if title == "overturning" else 0
                short += 3 if short and mode != "3d" else 0
                m12[f"{ens}|{title}|{mode}"] = base * f * (3 if censored else 1)
                m12[f"{ens}|{title}|{mode}|count"] = 11 - short
                m12[f"{ens}|{title}|{mode}|std"] = 0.3 * base * f
                m12[f"{ens}|{title}|{mode}|n_not_reached"] = short
    return {"fig12_2d_vs_3d": {"measured": m12},
            "fig08_motions_elcentro": {"measured": {"record": "el-centro-1940",
                                                    "principal_offset_deg": 19.54,
                                                    "n_motions": 11}},
            "fig08_motions_lomaprieta": {"measured": {"record": "loma-prieta-corralitos",
                                                      "principal_offset_deg": 9.37,
                                                      "n_motions": 11}}}


def test_no_verdict_names_another_studys_record():
    rows = cmp.compare(_two_ensembles(), ["fig08_motions", "fig12_2d_vs_3d"])
    about = {"elcentro": 0, "lomaprieta": 0}
    for r in rows:
        text = f"{r.statement} | {r.paper} | {r.ours} | {r.verdict_text}"
        mine = [e for e, names in RECORDS.items()
                if e in r.statement or names[0] in r.statement]
        if len(mine) != 1:
            continue
        about[mine[0]] += 1
        other = next(e for e in RECORDS if e != mine[0])
        for name in RECORDS[other]:
            assert name not in text, (name, text)
    assert about["elcentro"] >= 5 and about["lomaprieta"] >= 5
    # Loma Prieta: no paper angle to compare with; tilt rows judged; censored overturning said
    loma = [r for r in rows if "lomaprieta" in r.statement or "Loma Prieta" in r.statement]
    assert any(r.verdict == cmp.NOT_IN_PAPER and "9.37" in r.ours for r in loma)
    tilt = [r for r in loma if "excessive tilt" in r.statement]
    assert [r.verdict for r in tilt] == [cmp.REPRODUCED] * 2 + [cmp.NOT_IN_PAPER] * 2
    over = [r for r in loma if "overturning" in r.statement]
    assert len(over) == 4
    assert all("not reached at the search bound PGA/(g tan α) = 20" in r.reason for r in over)
    assert "means over 7 (3D) and 4 (3D x) of 11 motions" in over[0].ours
    assert "means over 7 (3D) and 4 (2D x) of 11 motions" in over[2].ours
    # ten pairs as in the paper: no padding row "10 = 10"
    assert not any("Synthetic pairs" in r.statement for r in rows)


def test_report_on_the_paper_run_is_small():
    """The report built from the committed paper gallery (its figures, sidecars and tables),
    with images linked as the gallery does, stays under 150 KB and keeps the numbers."""
    root = Path(__file__).resolve().parents[1] / "results" / "paper"
    study = root / "elcentro"
    # the report's figures (those of its own sections, the stripe, risk and portfolio ones,
    # are shown there without verdicts)
    pngs = sorted(p for p in [*root.glob("figures/*.png"), *study.glob("figures/*.png")]
                  if p.stem.startswith(tuple(FIGURES)))
    beside = {n for n, f in figures().items() if f.section}
    assert len(pngs) >= 11, "the committed paper gallery is incomplete"
    out = Path(report.build(Path("/tmp") / f"paper_report_{id(root)}.html", title="paper",
                            figures=pngs, linear_fit=study / "linear_fit.csv",
                            fragility=study / "fragility.csv"))
    page = report.link_images(out.read_text(), lambda stem: f"figures/{stem}.png")
    out.unlink()
    assert len(page.encode()) < 150 * 1024
    # the numbers that matter are still there: every computed fragility median, every fit
    frag = tables.fragility_pivot(study / "fragility.csv")
    computed = int((~frag.iloc[:, 3:].isna()).to_numpy().sum())
    table = pd.read_csv(study / "fragility.csv")
    assert computed == int(table["median [g tan(alpha)]"].notna().sum())
    assert ">not-computed<" not in page  # the empty fragility points are left out
    assert page.count("<a href='#verdicts'>") == len({figure_name(p) for p in pngs} - beside)


def test_missing_figures_are_said_not_invented(outputs):
    rows = cmp.compare({}, ["fig06_el_centro", "fig12_2d_vs_3d", "fig09_spectra"])
    assert all(r.verdict == cmp.NOT_COMPUTED for r in rows)
    assert rows[0].ours == "—"


def test_a_comparison_refuses_an_unknown_verdict_and_figure():
    with pytest.raises(ValueError, match="verdict"):
        cmp.Comparison("fig03_wobbling_period", "s", "p", "o", "close enough")
    with pytest.raises(ValueError, match="figure"):
        cmp.compare({}, ["fig05"])


def test_bad_inputs_name_the_file(tmp_path):
    with pytest.raises(ValueError, match="must start with"):
        entries.load_figures([tmp_path / "plot.png"])
    with pytest.raises(ValueError, match="does not exist"):
        entries.load_figures([tmp_path / "fig03_wobbling_period.png"])


def test_fit_quality_of_fig08_is_tabulated(outputs):
    entry = next(e for e in entries.load_figures(outputs["pngs"]) if e.name == "fig08_motions")
    table = fig08_motions.fit_quality_table(entry.notes)
    assert len(table) == 4  # 2 methods × 2 components
    used = table[table["identification"] == "spectrum *"]
    assert list(used["component"]) == ["x (major)", "y (minor)"]
    assert (used["median/record 0.3-1 s"] == 0.93).all()
    other = table[table["identification"] == "counts"]
    assert (other["record inside 5–95 %"] == "12 % of periods").all()
    text = outputs["html"].read_text()
    assert "Fit quality of the synthetic ensembles" in text and "counts" in text


def test_link_images_replaces_every_embedded_png_and_nothing_else():
    from rocking.report.html import link_images

    page = ("<p>x</p><figure id='fig03_wobbling_period'><img alt='fig03_wobbling_period' "
            "src='data:image/png;base64,iVBORw0KGgo='><figcaption>c</figcaption></figure>"
            "<figure id='fig09_spectra'><img alt='fig09_spectra' "
            "src='data:image/png;base64,AAAA'><figcaption>d</figcaption></figure>")
    out = link_images(page, lambda stem: f"figures/{stem}.png")
    assert "base64" not in out
    assert "src='figures/fig03_wobbling_period.png'" in out
    assert "src='figures/fig09_spectra.png'" in out
    assert out.count("<figcaption>") == 2 and out.startswith("<p>x</p>")


def test_fig10_verdicts_say_the_bend_and_the_coinciding_goals():
    """Flat-then-rise stated with numbers; θ > α = overturning said once with its physics;
    no claim about other motions without evidence."""
    line = {"slope": 0.40, "intercept": 0.26, "r_squared": 0.93, "n": 20, "flat_to_R": 3.0,
            "flat_level": 1.1, "end_R": 10.0, "end_value": 5.4, "max_rel_deviation": 0.25,
            "residual_signs": "++++" + "−" * 12 + "++++"}
    notes = {"fig10_goals": {"measured": {
        "n_goals": 2, "n_paper_goals": 7, "absent_goals": [],
        "line|tilt:1": line, "line|overturning": line,
        "coincide": [{"goals": ["tilt:1", "overturning"], "n_R": 20, "n_motions": 11}]}}}
    rows = fig10_goals.compare(notes)
    assert len(rows) == 2  # the coinciding goal is not judged twice
    same, over = rows
    assert same.verdict == cmp.NOT_IN_PAPER and "all 20 sizes (11 motions each)" in same.ours
    assert "centre of mass" in same.reason and "sin(α − θ)" in same.reason
    assert over.verdict == cmp.DIFFERS and "25.0 %" in over.ours
    assert "within 10 % of 1.10 up to R = 3 m, then up to 5.40 at R = 10 m" in over.reason
    assert "a bend" in over.reason
    assert not any("not the paper's" in r.verdict_text for r in rows)


def test_links_to_the_derivations_follow_the_page(tmp_path):
    """A copy of the report in another folder (the gallery) still reaches docs/equations.md."""
    page = "<td>" + report.link_docs("see docs/equations.md#eq-27-the-angle-of-turn here",
                                     report.docs_href(tmp_path / "a")) + "</td>"
    assert "href='" in page and "#eq-27-the-angle-of-turn'" in page
    deeper = tmp_path / "b" / "c"
    moved = report.relink_docs(page, deeper)
    href = moved.split("href='")[1].split("#")[0]
    assert (deeper / href).resolve() == (report.DOCS / "equations.md").resolve()
    assert (report.DOCS / "equations.md").is_file()


def test_a_suite_is_reported_record_by_record(tmp_path):
    """A suite's ensemble file: one row per record with its own processing, not one record
    'and n synthetic pairs'."""
    suite = {"ensemble": "mine", "suite": True, "label": "suite of 2 records: a, b",
             "records": [
                 {"record": "a", "label": "a", "rotation_deg": 48.63,
                  "principal_offset_deg": 3.4, "n_synthetic": 0,
                  "highpass": {"kind": "oscillator", "fc_hz": 0.14, "mw": 6.61}},
                 {"record": "b", "label": "b", "rotation_deg": None, "n_synthetic": 2,
                  "seed": 7, "highpass": {"kind": "none"}}]}
    path = tmp_path / "mine-0123.json"
    path.write_text(json.dumps(suite))
    rows = dict(run_summary.ensemble_rows(path))
    assert rows["ensemble mine"] == "suite of 2 records: a, b"
    assert "rotated by 48.63° to principal axes" in rows["ensemble mine: record a"]
    # no synthetic pairs: no words for them
    assert rows["ensemble mine: record a"].endswith("oscillator at 0.14 Hz (Mw 6.61)")
    assert rows["ensemble mine: record b"] == ("b; recorded axes kept; no high-pass; "
                                               "2 synthetic pairs, seed 7")
