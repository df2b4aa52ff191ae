"""The refinement sample (rocking.study.refinement) and what the report and the verdicts make
of it: the sample is stated and seeded, the refined answer is the first exceedance of an
independent 0.05 % scan, the headline numbers carry the measured shift, and the verdict
criteria (rocking.plot.criteria) follow from the scatter they state."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from rocking.dynamics.bodies import Cylinder
from rocking.motions.motion import GroundMotion
from rocking.plot import comparisons as cmp
from rocking.plot import criteria, fig09_spectra, fig12_2d_vs_3d, refined
from rocking.spectra.accuracy import PRESETS
from rocking.spectra.critical import critical_intensity, uplift_intensity
from rocking.study import refinement


def _cells() -> pd.DataFrame:
    rows = []
    for mode in ("3d", "2d-x"):
        for ls in ("overturning", "tilt:1/3"):
            for motion in ("a", "b", "c"):
                for R in (1.0, 5.0, 10.0):
                    rows.append((mode, ls, motion, 0.2, R, 1.0 + R / 10))
    return pd.DataFrame(rows, columns=["mode", "limit_state", "motion", "tan_alpha", "R",
                                       "answer"])


def test_the_sample_is_seeded_stated_and_holds_every_headline_cell():
    cells = _cells()
    spec = refinement.SampleSpec(k=2, seed=3)
    a = refinement.choose_cells(cells, spec)
    b = refinement.choose_cells(cells.sample(frac=1.0, random_state=1), spec)
    pd.testing.assert_frame_equal(a, b)  # the draw does not depend on the table's order
    head = a[a["why"] == "headline"]
    assert len(head) == 3 and set(head["R"]) == {10.0} and set(head["mode"]) == {"3d"}
    assert set(head["limit_state"]) == {"overturning"}
    drawn = a[a["why"] == "sample"].groupby(["mode", "limit_state"]).size()
    # k per (mode, limit state), fewer where a headline cell was drawn again
    assert drawn.max() == 2 and len(a) <= 3 + 2 * 4
    assert not refinement.choose_cells(cells, refinement.SampleSpec(k=0, headline=False)).size


@pytest.mark.parametrize("bad", [{"k": -1}, {"max_analyses": 0}, {"k": 1.5}, {"depth": 2}])
def test_a_bad_refinement_setting_is_named(bad):
    with pytest.raises(ValueError, match=next(iter(bad))):
        refinement.SampleSpec.from_config(bad)


def _pulse_pair(duration=3.0, dt=0.01):
    t = np.arange(0.0, duration, dt)
    env = np.sin(np.pi * t / duration) ** 2
    return GroundMotion(4.0 * env * np.sin(2 * np.pi * 1.5 * t),
                        3.0 * env * np.cos(2 * np.pi * 1.1 * t), dt, "pulse", {})


def test_refined_answer_is_the_first_exceedance_of_an_independent_fine_search():
    """The refining scan against the library's own search run with the same fixed 0.05 % scan
    and a fine bisection (a separate code path: rocking.spectra.search): the refined answer is
    the lattice point that closes the search's scan bracket (at most one step above the
    bisected answer), and never above the run's coarse answer."""
    motion, body, mode = _pulse_pair(), Cylinder(0.5, 0.2), "2d-x"
    states = ["tilt:1/3", "overturning"]
    coarse = critical_intensity(body, motion, states, mode, accuracy="default", upper=20.0)
    answers = dict(zip(states, map(float, coarse.intensity), strict=True))
    assert all(np.isfinite(list(answers.values())))
    got = refinement.refine_point(motion, mode, 0.5, 0.2, answers, PRESETS["default"],
                                  upper=20.0, max_analyses=5000)
    fine = PRESETS["default"].with_(scan_step=refinement.REFINED_STEP, bisection_tol=1e-4)
    ref = critical_intensity(body, motion, states, mode, accuracy=fine,
                             upper=max(answers.values()) * 1.001)
    assert not got["truncated"] and got["analyses"] > 10
    lower = uplift_intensity(motion, mode)
    moved = 0
    for ls, fine_answer in zip(states, map(float, ref.intensity), strict=True):
        mine = got["refined"][ls]
        assert mine <= answers[ls]
        if fine_answer < answers[ls] / (1 + refinement.REFINED_STEP):  # found lower
            moved += 1
            assert fine_answer <= mine <= fine_answer * (1 + refinement.REFINED_STEP) + 1e-12
            n = math.log(mine / lower) / math.log1p(refinement.REFINED_STEP)
            assert n == pytest.approx(round(n), abs=1e-6)  # a point of the 0.05 % lattice
    assert moved >= 1  # the pulse has answers the 1 % scan overshoots


def test_a_point_beyond_the_cost_cap_is_truncated_not_guessed():
    got = refinement.refine_point(_pulse_pair(), "2d-x", 0.5, 0.2, {"overturning": 19.0},
                                  PRESETS["default"], upper=20.0, max_analyses=5)
    assert got["truncated"] and math.isnan(got["refined"]["overturning"])
    assert got["analyses"] == 0  # known before the first analysis: nothing spent


def _sample() -> pd.DataFrame:
    rows = [("3d", "overturning", m, 0.2, 10.0, "headline", a, r, 0, False)
            for m, a, r in (("a", 4.0, 3.6), ("b", 6.0, 6.0))]
    rows += [("2d-x", "overturning", "a", 0.2, 2.0, "sample", 5.0, 4.5, 0, False),
             ("2d-x", "overturning", "b", 0.2, 4.0, "sample", 8.0, np.nan, 5000, True)]
    df = pd.DataFrame(rows, columns=["mode", "limit_state", "motion", "tan_alpha", "R", "why",
                                     "answer", "refined", "analyses", "truncated"])
    return df.assign(shift=(df["refined"] - df["answer"]) / df["answer"])


def test_a_mean_whose_cells_were_all_refined_moves_exactly():
    df = _sample()
    delta, n, exact = refined.cell_shift(df, "3d", "overturning", 10.0, 2)
    assert exact and n == 2 and delta == pytest.approx(9.6 / 10.0 - 1.0)
    # with more motions behind the mean than refined: the sample's mean shift, stated as such
    delta, n, exact = refined.cell_shift(df, "3d", "overturning", 10.0, 11)
    assert not exact and delta == pytest.approx(np.mean([-0.1, 0.0]))
    # a ratio moves by (1 + δ2D)/(1 + δ3D) − 1; the truncated cell is left out
    delta, n, _ = refined.ratio_shift(df, "2d-x", "overturning")
    assert n == 3 and delta == pytest.approx(0.9 / 0.95 - 1.0)
    assert refined.shift_text((-0.04, 2, True)) == \
        "refinement moves it by −4.0 % [all 2 cells refined]"


# ------------------------------------------------------------------ verdict criteria


def test_about_value_tolerance_is_two_sd_of_two_ensembles_and_the_rounding():
    ok, tol = criteria.about_value(4.75, 0.41, 4.0)
    assert tol == pytest.approx(2 * math.sqrt(2 * 0.41 ** 2 + 0.5 ** 2 / 3))
    assert ok and not criteria.about_value(4.0 + tol * 1.01, 0.41, 4.0)[0]


def _m12(ratio_2d: float, censored_2d: int = 0, n: int = 11) -> dict:
    m = {"R": 10.0, "e|label": "El Centro: mean of 11 motions", "e|n_motions": n}
    R = [2.0, 6.0, 10.0]
    for title in ("overturning", "excessive tilt"):
        for mode, f, c in (("3d", 1.0, 0), ("3d-x", ratio_2d, censored_2d),
                           ("3d-y", ratio_2d, 0), ("2d-x", ratio_2d, 0), ("2d-y", ratio_2d, 0)):
            m[f"e|{title}|{mode}"] = 4.0 * f
            m[f"e|{title}|{mode}|count"], m[f"e|{title}|{mode}|std"] = float(n), 1.0
            m[f"e|{title}|{mode}|n_not_reached"] = 0.0
            m[f"e|{title}|{mode}|mle"] = {
                "R": R, "median": [r * f for r in R], "se_log": [0.05] * 3,
                "beta": [0.3] * 3, "n": [n] * 3,
                "n_censored": [0, 0, c] if mode == "3d-x" else [0] * 3}
    return {"fig12_2d_vs_3d": {"figure": "fig12_2d_vs_3d", "measured": m}}


def test_ratios_come_from_censoring_aware_medians_across_R():
    rows = fig12_2d_vs_3d.compare(_m12(2.1))
    over = [r for r in rows if "El Centro, overturning" in r.statement]
    paper = [r for r in over if "Housner" not in r.statement]
    assert len(paper) == 2 and all(r.verdict == cmp.REPRODUCED for r in paper)
    assert all("across R" in r.statement and "over 3 sizes" in r.ours for r in over)
    assert all("second component alone" in r.reason for r in paper)
    # Housner's block: the same ratios quoted, named and not judged
    housner = [r for r in over if "Housner" in r.statement]
    assert len(housner) == 2 and all(r.verdict == cmp.NOT_IN_PAPER for r in housner)
    assert all("e = 0.942" in r.reason for r in housner)
    # 1.5× is outside "about twice" at this scatter: ln(2/1.5) = 0.29 > 2·√(2·0.07² + 0.068²)
    assert all(r.verdict == cmp.DIFFERS for r in fig12_2d_vs_3d.compare(_m12(1.5))
               if "El Centro, overturning" in r.statement and "Housner" not in r.statement)
    # a size with more than half the motions censored is left out, and said
    ev = fig12_2d_vs_3d.ratio_evidence(_m12(2.0, censored_2d=6)["fig12_2d_vs_3d"]["measured"],
                                       "e", "overturning", "3d-x")
    assert ev["R"] == [2.0, 6.0] and ev["dropped"] == [10.0]
    assert ev["pooled"] == pytest.approx(2.0) and ev["pooled_se"] == pytest.approx(
        math.sqrt(2) * 0.05)


def test_a_censored_mean_never_supports_reproduced():
    notes = _m12(2.0)
    m = notes["fig12_2d_vs_3d"]["measured"]
    m["e|overturning|3d|count"], m["e|overturning|3d|n_not_reached"] = 9.0, 2.0
    r10 = fig12_2d_vs_3d.compare(notes)[0]
    assert m["e|overturning|3d"] == 4.0 and r10.verdict == cmp.DIFFERS
    assert "censored" in r10.reason
    # without fitted medians the ratio of censored means is not reproduced either
    for k in [k for k in m if k.endswith("|mle")]:
        del m[k]
    m["e|overturning|3d-x|count"], m["e|overturning|3d-x|n_not_reached"] = 8.0, 3.0
    row = next(r for r in fig12_2d_vs_3d.compare(notes)
               if "overturning: the 3D model under the x" in r.statement)
    assert row.verdict == cmp.DIFFERS and "not reached at the search bound" in row.reason


def test_fig9_per_motion_claim_is_judged_per_motion():
    tol, share = criteria.PER_MOTION_TOL, criteria.PER_MOTION_SHARE
    n = 20
    inside = int(math.ceil(share * n))
    per = {f"m{i}": [0.01 if i < inside else 3 * tol] for i in range(n)}
    ok = fig09_spectra.per_motion_row("overturning", {"per_motion": per})
    assert ok.verdict == cmp.REPRODUCED and f"{inside} of {n}" in ok.ours
    per["m0"] = [-2 * tol]
    bad = fig09_spectra.per_motion_row("overturning", {"per_motion": per})
    assert bad.verdict == cmp.DIFFERS and f"{inside - 1} of {n}" in bad.ours
    rows = fig09_spectra.compare({"fig09_spectra": {"measured": {
        "R": [1.0], "damping|overturning": {"per_motion": per, "rel_diff_means": [0.0]},
        "damping|tilt:1/3": {"per_motion": per, "rel_diff_means": [0.0]}}}})
    # the per-motion claim is the paper's for overturning; for θ > α/3 it speaks of means
    assert sum("per motion" in r.statement for r in rows) == 1


def test_the_report_quotes_the_shift_beside_its_headline_numbers(tmp_path):
    """The committed gallery's tables and figures with a refinement sample: the findings carry
    "refinement moves it by" beside the R = 10 m mean (all its cells refined: exact) and the
    fragility medians (the sample's shift), and say what the sample was."""
    from pathlib import Path

    from rocking.plot import FIGURES
    from rocking.report import html as report

    root = Path(__file__).resolve().parents[1] / "results" / "paper"
    study = root / "elcentro"
    pngs = sorted(p for p in [*root.glob("figures/*.png"), *study.glob("figures/*.png")]
                  if p.stem.startswith(tuple(FIGURES)))
    critical = refinement.cells_from_table(study / "critical.csv")
    head = refinement.headline_cells(critical)
    assert len(head) == 11 and set(head["R"]) == {10.0}
    sample = head.assign(why="headline", refined=head["answer"] * 0.9, analyses=3000,
                         truncated=False)
    tilt = critical[(critical["mode"] == "3d") & (critical["limit_state"] == "tilt:1/3")]
    tilt = tilt.head(2).assign(why="sample", refined=lambda d: d["answer"] * 0.98,
                               analyses=100, truncated=False)
    sample = pd.concat([sample, tilt]).assign(
        shift=lambda d: (d["refined"] - d["answer"]) / d["answer"])
    csv = tmp_path / "refinement_sample.csv"
    sample.to_csv(csv, index=False)
    page = report.build(tmp_path / "report.html", title="paper", figures=pngs,
                        fragility=study / "fragility.csv", risk=study / "risk.csv",
                        study="elcentro", refinement=csv).read_text()
    findings = page.split("<h2 id='what-was-run'>")[0]
    assert "4.75 ± 0.41 (standard error, 11 motions) (refinement moves it by −10.0 % " \
           "[all 11 cells refined])" in findings
    assert "θ &gt; α/3" in findings or "tilt" in findings
    assert "refinement moves it by −2.0 % [sample of 2 cells]" in findings
    assert "13 of this study&#x27;s cells (11 of the headline mean" in findings
    assert "e = 0.942" in findings
    # without a sample the report says so instead of quoting nothing
    bare = report.build(tmp_path / "bare.html", title="paper", figures=pngs,
                        fragility=study / "fragility.csv", study="elcentro").read_text()
    assert "No refinement sample in this run" in bare


def test_the_rule_reads_the_store_and_names_a_motion_its_ensemble_lacks(tmp_path):
    """write_refinement_sample on a written store: its cells and tolerances are read, and a
    store whose motions are not those of the ensemble file stops before any analysis, naming
    the motion (the synthetic store's motions are labels without records)."""
    import figures_synthetic as fs

    paths = fs.write_study(tmp_path / "study", with_tilt_map=False)
    with pytest.raises(ValueError, match="motion 'synthetic-0"):
        refinement.write_refinement_sample(paths["store"], paths["motions"],
                                           tmp_path / "s.csv",
                                           refinement.SampleSpec(k=1, max_analyses=10))
    assert not (tmp_path / "s.csv").exists()


# ------------------------------------------------------------------ λ under refinement


def _point(theta: float, beta: float, z: np.ndarray, motions, R=10.0) -> pd.DataFrame:
    """Cells of one point whose lognormal fit is exactly (θ, β): x = θ·exp(β z), z of mean 0
    and standard deviation 1 (ddof 0, the fit's)."""
    return pd.DataFrame({"mode": "3d", "limit_state": "overturning", "motion": motions,
                         "tan_alpha": 0.2, "R": R, "answer": theta * np.exp(beta * z),
                         "censored": False})


def test_lambda_moves_as_the_closed_form_of_a_lognormal_against_a_power_law(tmp_path):
    """Against a power-law hazard λ_H = k0·im^−k, a lognormal fragility (θ, β) has
    λ = k0·θ^−k·exp(k²β²/2); refining every cell of a point from (θ, β) to (θ', β') moves λ
    by (θ'/θ)^−k·exp(k²(β'² − β²)/2) − 1, whatever tan α (θ in g = θ·tan α cancels)."""
    from rocking.risk.hazard import HazardCurve
    from rocking.units import read_table

    rng = np.random.default_rng(5)
    z = rng.standard_normal(11)
    z = (z - z.mean()) / z.std()
    motions = [f"m{i}" for i in range(11)]
    cells = _point(5.0, 0.35, z, motions)
    refined_x = 4.2 * np.exp(0.30 * z)
    sample = cells.assign(why="headline", refined=refined_x, analyses=100, truncated=False)
    # one more point with one refined cell of eleven: a part of the move, stated as such
    other = _point(2.0, 0.2, z, motions, R=4.0)
    cells = pd.concat([cells, other], ignore_index=True)
    sample = pd.concat([sample, other.head(1).assign(
        why="sample", refined=other["answer"].iloc[0] * 0.8, analyses=50, truncated=False)])
    sample["shift"] = sample["refined"] / sample["answer"] - 1.0
    csv = tmp_path / "refinement_sample.csv"
    sample.drop(columns="censored").to_csv(csv, index=False)
    k0, k = 1e-4, 2.5
    hazard = HazardCurve.from_power_law(k0=k0, k=k)
    out = tmp_path / "refinement_risk.csv"
    assert refinement.write_refinement_risk(cells, csv, hazard, out) == 2
    table = read_table(out)
    head = table[table["R"] == 10.0].iloc[0]
    assert (head["n"], head["n_refined"]) == (11, 11)
    assert head["median"] == pytest.approx(5.0, rel=1e-9)
    assert head["beta_refined"] == pytest.approx(0.30, rel=1e-9)
    closed = k0 * (5.0 * 0.2) ** -k * math.exp(k * k * 0.35 ** 2 / 2)
    assert head["maf"] == pytest.approx(closed, rel=1e-3)
    expected = (4.2 / 5.0) ** -k * math.exp(k * k * (0.30 ** 2 - 0.35 ** 2) / 2) - 1.0
    assert head["shift"] == pytest.approx(expected, rel=1e-3)
    part = table[table["R"] == 4.0].iloc[0]
    assert (part["n"], part["n_refined"]) == (11, 1) and part["shift"] > 0
    # the sentence the report prints beside λ
    found = refined.lambda_shift(table, "3d", "overturning", 10.0, 0.2)
    assert refined.lambda_text(found) == \
        f"refinement moves it by +{100 * expected:.1f} % [all 11 cells refined, fragility " \
        "refitted]"
    # the median's own move, exact where all its cells were refined: θ'/θ − 1
    delta, k_, n_ = refined.lambda_shift(table, "3d", "overturning", 10.0, 0.2, "median")
    assert (k_, n_) == (11, 11) and delta == pytest.approx(4.2 / 5.0 - 1.0, rel=1e-9)
    assert "[1 of its 11 cells refined" in refined.lambda_text(
        refined.lambda_shift(table, "3d", "overturning", 4.0, 0.2))
    # a hazard of another measure or component: the header only, never a wrong λ, and the
    # findings then say nothing of λ's move
    assert refinement.write_refinement_risk(cells, csv, hazard, out, applies=False) == 0
    from rocking.report.findings import study_findings

    risk = tmp_path / "risk.csv"
    risk.write_text("fragility,mode,tan_alpha [-],R [m],limit_state,median_pga_g [g],beta [-],"
                    "maf [1/yr],status\nfirst_exceedance,3d,0.2,10,overturning,1.0,0.35,"
                    "1e-4,ok\n")
    lam, = [f.text for f in study_findings(risk=risk, refinement_risk=out)]
    assert "refinement" not in lam


def test_a_censored_cell_stays_censored_and_the_store_refit_is_the_studys_fit(tmp_path):
    """The refit reads the cells as the study's fragility table does (the store's
    not-reached cells censored at the bound): unrefined, it gives fragility_table's median
    and β; a sampled cell that was censored is not substituted."""
    import figures_synthetic as fs

    from rocking.fragility.lognormal import fragility_table
    from rocking.plot import open_store
    from rocking.spectra.limit_states import parse_limit_state

    paths = fs.write_study(tmp_path / "study", with_tilt_map=False)
    store = open_store(paths["store"])
    cells = refinement.store_cells(store, fs.UPPER)
    cens = cells[cells["censored"]]
    assert len(cens) >= 2
    row = cens.iloc[0]
    table = fragility_table(store, upper=fs.UPPER).sel(mode=row["mode"])
    at = cells[(cells["mode"] == row["mode"]) & (cells["limit_state"] == row["limit_state"])
               & (cells["tan_alpha"] == row["tan_alpha"]) & (cells["R"] == row["R"])]
    sample = at.assign(why="sample", refined=at["answer"], analyses=1, truncated=False)
    sample.loc[sample["censored"], "refined"] = 0.5 * sample["answer"]
    fits = refinement.refit_points(cells, sample)
    assert len(fits) == 1 and fits["n_refined"].iloc[0] == int((~at["censored"]).sum())
    ls = next(str(v) for v in store["limit_state"].values
              if parse_limit_state(str(v)).name == row["limit_state"])
    want = float(table.sel(limit_state=ls, tan_alpha=row["tan_alpha"], R=row["R"])["median"])
    assert np.isfinite(want)
    assert fits["median"].iloc[0] == pytest.approx(want, rel=1e-9)
    assert fits["median_refined"].iloc[0] == pytest.approx(want, rel=1e-9)


def test_the_combined_fig12_finding_moves_each_study_by_its_own_sample():
    """Fig 12's finding quotes every study it draws: each study's R = 10 m mean and ratios
    carry the shift of that study's own sample (here −10 % and −20 %, every cell of each
    mean refined), and the note says which sample each rests on, with its k and seed."""
    from rocking.report.findings import paper_findings

    notes = {"R": 10.0}
    for ens in ("elcentro", "lomaprieta"):
        notes[f"{ens}|label"] = ens
        for ls in ("overturning", "excessive tilt"):
            for mode, f in (("3d", 1.0), ("2d-x", 2.2), ("2d-y", 1.9)):
                notes[f"{ens}|{ls}|{mode}"] = 4.0 * f
                notes[f"{ens}|{ls}|{mode}|count"] = 2.0
                notes[f"{ens}|{ls}|{mode}|std"] = 1.0
    samples = {}
    for ens, factor in (("elcentro", 0.9), ("lomaprieta", 0.8)):
        rows = [("3d", "overturning", m, 0.2, 10.0, "headline", 5.0, 5.0 * factor, 10, False,
                 1, 7) for m in ("a", "b")]
        rows.append(("2d-x", "overturning", "a", 0.2, 4.0, "sample", 9.0, 9.0, 10, False, 1, 7))
        df = pd.DataFrame(rows, columns=[*refinement.COLUMNS[:6], "answer", "refined",
                                         "analyses", "truncated", "k", "seed"])
        samples[ens] = df.assign(shift=(df["refined"] - df["answer"]) / df["answer"])
    entries = [_entry("fig12_2d_vs_3d", notes)]
    found = paper_findings(entries, {}, "elcentro", samples)
    text = {f.text.split(",")[0]: f.text for f in found}
    assert "4.00 ± 0.71 (standard error, 2 motions) (refinement moves it by −10.0 % [all 2 " \
        "cells refined])" in text["elcentro"]
    assert "(refinement moves it by −20.0 % [all 2 cells refined])" in text["lomaprieta"]
    # the ratio 2D/3D moves by (1 + 0)/(1 + δ3D) − 1 of each study's own sample
    assert "x 2.20× (means at R = 10 m only) (refinement moves it by +11.1 % [sample of 3 " \
        "cells])" in text["elcentro"]
    assert "(refinement moves it by +25.0 % [sample of 3 cells])" in text["lomaprieta"]
    note = refined.refinement_note(samples["elcentro"], samples, "elcentro")
    assert "3 of this study's cells (2 of the headline mean, 1 drawn: k = 1 per mode and " \
        "limit state, seed 7)" in note
    assert "The numbers of the study lomaprieta rest on its own sample: 3 of its cells" in note


def _entry(name: str, measured: dict):
    """A figure of kind ``name`` as the findings read it (name, anchor, notes)."""
    from types import SimpleNamespace

    return SimpleNamespace(name=name, stem=name, notes={"measured": measured})


def test_the_gallery_report_moves_lambda_and_both_studies_by_their_own_samples(tmp_path):
    """The committed gallery's tables: the refit of the headline point, unrefined, gives
    risk.csv's λ (same fit, same integral, to the tables' rounding); the El Centro report
    quotes λ's measured move beside it and Loma Prieta's numbers with Loma Prieta's sample."""
    import re
    from pathlib import Path

    from rocking.plot import FIGURES
    from rocking.report import html as report
    from rocking.risk.hazard import parse_hazard
    from rocking.units import read_table

    repo = Path(__file__).resolve().parents[1]
    root, study = repo / "results" / "paper", repo / "results" / "paper" / "elcentro"
    hazard = parse_hazard({"file": str(repo / "config/hazard/example_hazard_curve.csv"),
                           "site": {"lon": 0.0, "lat": 0.0}})
    moves = tmp_path / "refinement_risk.csv"
    refinement.write_refinement_risk(refinement.critical_cells(study / "critical.csv", 20.0),
                                     study / "refinement_sample.csv", hazard, moves)
    table = read_table(moves)
    risk = read_table(study / "risk.csv")
    risk = risk[risk["fragility"] == "first_exceedance"]
    both = table.merge(risk, on=["mode", "limit_state", "tan_alpha", "R"],
                       suffixes=("", "_risk"))
    assert len(both) == len(table) > 0
    np.testing.assert_allclose(both["maf"], both["maf_risk"], rtol=1e-4)
    pngs = sorted(p for p in [*root.glob("figures/*.png"), *study.glob("figures/*.png")]
                  if p.stem.startswith(tuple(FIGURES)))
    page = report.build(tmp_path / "report.html", title="paper", figures=pngs,
                        fragility=study / "fragility.csv", risk=study / "risk.csv",
                        study="elcentro",
                        refinement=[study / "refinement_sample.csv",
                                    root / "lomaprieta" / "refinement_sample.csv"],
                        refinement_risk=moves).read_text()
    findings = page.split("<h2 id='what-was-run'>")[0]
    assert re.search(r"at R = 10 m \(5–95 %: [^)]+\) \(refinement moves it by \+\d+\.\d % "
                     r"\[all 11 cells refined, fragility refitted\]\)", findings)
    # the median at R = 10 m refitted from its 11 refined cells: its exact move beside it
    assert re.search(r"\(β \d\.\d\d\) at R = 10 m \(refinement moves it by −\d+\.\d % \[all "
                     r"11 cells refined, fragility refitted\]\)", findings)
    loma = next(li for li in re.findall(r"<li>(.*?)</li>", findings) if "Loma" in li)
    assert "(standard error, 11 motions) (refinement moves it by" in loma
    assert re.search(r"rest on its own sample: \d+ of its cells", findings)


def test_the_sample_table_states_its_k_and_seed(tmp_path, monkeypatch):
    """refinement_sample.csv carries the draw's k and seed on every row, so the report can
    say how the sample was chosen (the refining itself is replaced here: no analyses)."""
    import figures_synthetic as fs

    paths = fs.write_study(tmp_path / "study", with_tilt_map=False)
    monkeypatch.setattr(refinement, "refine_sample", lambda sample, *a, **k: sample.assign(
        refined=sample["answer"], shift=0.0, analyses=0, truncated=False)[
            list(refinement.COLUMNS)])
    out = tmp_path / "s.csv"
    n = refinement.write_refinement_sample(paths["store"], paths["motions"], out,
                                           refinement.SampleSpec(k=1, seed=11))
    table = pd.read_csv(out)
    assert len(table) == n > 0 and set(table["k"]) == {1} and set(table["seed"]) == {11}
    assert "drawn: k = 1 per mode and limit state, seed 11" in refined.refinement_note(table)
