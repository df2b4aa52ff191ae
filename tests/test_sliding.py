"""The sliding limit state and the slides / lifts_off flags of every answer (issues 32, 33),
checked against direct runs of the engine (ground_response), not against the search."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from rocking.constants import G
from rocking.dynamics.analysis import ground_response
from rocking.dynamics.bodies import Cylinder
from rocking.motions.motion import GroundMotion
from rocking.spectra.critical import critical_intensity, uplift_intensity
from rocking.spectra.limit_states import (
    Sliding,
    match_limit_state,
    parse_limit_state,
    parse_limit_states,
    severity,
)
from rocking.spectra.quantity import Quantity

TAN_ALPHA = 0.2


def _pulse() -> GroundMotion:
    """A smooth two-second burst: the friction the body needs grows with the intensity."""
    dt = 0.005
    t = np.arange(0.0, 4.0, dt)
    env = np.where(t < 2.0, np.sin(np.pi * t / 2.0) ** 2, 0.0)
    return GroundMotion(env * np.sin(2 * np.pi * 1.5 * t),
                        0.6 * env * np.cos(2 * np.pi * 1.1 * t), dt, name="burst")


def _direct(body, motion, intensity):
    """ground_response of the 2D model under x at normalized intensity I, with its defaults
    (history kept: the run is never ended early)."""
    return ground_response(body, motion.component("x"), model="2d",
                           scale=intensity * G * body.tan_alpha / motion.pga)


# --- parsing, printing, order ---------------------------------------------------------------


@pytest.mark.parametrize("text", ["sliding:0.6", " Sliding:0.60 ", "sliding:6e-1"])
def test_sliding_parses_and_prints_one_canonical_name(text):
    ls = parse_limit_state(text)
    assert ls == Sliding("sliding:0.6", 0.6)
    assert str(ls) == "sliding:0.6" and parse_limit_state(str(ls)) == ls
    assert ls.title == "Sliding at μ = 0.6"
    assert ls.quantity == "mu_required_max" and ls.threshold(math.atan(0.2)) == 0.6
    assert match_limit_state("sliding:0.6001", ["tilt:0.6", "sliding:0.6"]) == "sliding:0.6"


def test_sliding_is_its_own_severity_axis_after_the_tilt_goals():
    names = ["sliding:0.6", "overturning", "sliding:0.3", "tilt:1/3"]
    assert [s.name for s in parse_limit_states(names)] == [
        "tilt:1/3", "overturning", "sliding:0.3", "sliding:0.6"]
    assert severity("sliding:0.3") < severity("sliding:0.6")  # a smaller μ slides first


@pytest.mark.parametrize("bad", ["sliding:0", "sliding:-1", "sliding:abc", "sliding:",
                                 "sliding:inf", "sliding:nan"])
def test_bad_friction_is_one_line_naming_the_text(bad):
    with pytest.raises(ValueError) as err:
        parse_limit_state(bad)
    message = str(err.value)
    assert "limit_state" in message and repr(bad) in message and "\n" not in message


def test_exceedance_is_contact_sliding_only():
    """sliding:<μ> is exceeded by μ_req > μ in an analysis that did not overturn; leaving
    the support (N ≤ 0) is not sliding, and an overturned analysis decides nothing."""
    from rocking.spectra.limit_states import classify, lifts_off, slides_in_contact

    ls, alpha = parse_limit_state("sliding:0.6"), math.atan(0.2)
    peaks = {"theta_max": 0.01, "overturned": False, "normal_force_min": 0.9}
    assert ls.exceeded({**peaks, "mu_required_max": 0.61}, alpha)
    assert not ls.exceeded({**peaks, "mu_required_max": 0.59}, alpha)
    # leaving the support is its own question (lifts_off), not sliding
    off = {**peaks, "mu_required_max": 0.1, "normal_force_min": -0.01}
    assert not ls.exceeded(off, alpha) and lifts_off(off)
    assert lifts_off({**off, "normal_force_min": 0.0}) and not lifts_off(peaks)
    # the fall of an overturning body needs unbounded friction: it says nothing
    fall = {**peaks, "overturned": True, "theta_max": 1.5, "mu_required_max": 60.0}
    assert not ls.exceeded(fall, alpha) and not ls.decides(fall)
    assert slides_in_contact(fall, 0.6) is None and slides_in_contact(peaks, None) is None
    known, exceeded = classify(fall, parse_limit_states(["overturning", "sliding:0.6"]),
                               alpha, None, stopped=False)
    assert known.tolist() == [True, False] and exceeded.tolist() == [True, False]
    with pytest.raises(ValueError, match="sliding:0.6.*'mu_required_max'"):
        ls.exceeded({"theta_max": 0.0, "overturned": False, "normal_force_min": 1.0}, alpha)


# --- the search against direct runs ----------------------------------------------------------


def test_sliding_answer_is_I10_of_where_the_body_first_needs_more_friction():
    """The friction a body needs grows steadily with the intensity here, so each sliding
    goal is a clean step at the smallest intensity s* needing more than μ, and its I10 is
    s*·exp(−w(1 − 2p)) (rocking.spectra.quantity): below uplift (μ = 0.15) s* is the
    closed form of a body at rest, μ_req = I·tan α·max|a_x|/PGA; above it (μ = 0.22) a
    direct scan of the engine brackets s*. Every analysis the search ran says what a direct
    run at its intensity says."""
    motion, body = _pulse(), Cylinder(1.0, TAN_ALPHA)
    res = critical_intensity(body, motion, ["overturning", "sliding:0.22", "sliding:0.15"],
                             "2d-x", accuracy="fast")
    q, acc = res.quantity, res.accuracy
    factor = math.exp(-q.w * (1 - 2 * q.p))
    tol = 1.5 * acc.local_step  # the crossing is judged within a stratum and a half
    # at rest: the body needs |a_x|·s/g, linear in I
    ax = np.max(np.abs(motion.ax))
    rest = 0.15 * motion.pga / (TAN_ALPHA * ax)
    assert rest < uplift_intensity(motion, "2d-x")
    assert res["sliding:0.15"]["intensity"] == pytest.approx(rest * factor, rel=tol)
    # rocking: a direct scan of the engine, where mu_required_max grows with I
    grid = np.arange(1.0, 2.0, 0.05)  # it grows steadily here; not above 2.3
    mu = np.array([_direct(body, motion, i).mu_required_max for i in grid])
    assert np.all(np.diff(mu) > 0)  # one crossing, between first - 0.05 and first
    first = grid[np.argmax(mu > 0.22)]
    answer = res["sliding:0.22"]["intensity"]
    assert (first - 0.05) * factor * (1 - tol) <= answer <= first * factor * (1 + tol)
    k = res.index("sliding:0.22")
    for x, e in zip(res.samples.intensity, res.samples.exceeded[:, k], strict=True):
        if not math.isnan(e):
            assert bool(e) == (_direct(body, motion, x).mu_required_max > 0.22), x


def test_flags_are_those_of_direct_runs_at_the_search_intensities():
    """slides / lifts_off of each answer = whether a direct run at one of the search's
    intensities up to the answer's window (I_p·e^w) slid in contact (did not overturn,
    μ_req > μ) / had N ≤ 0; slides is NaN without μ."""
    motion = _pulse()
    states = ["tilt:1/3", "overturning", "sliding:0.22"]
    with_mu = critical_intensity(Cylinder(1.0, TAN_ALPHA, mu=0.22), motion, states, "2d-x",
                                 accuracy="fast")
    body = Cylinder(1.0, TAN_ALPHA)
    direct = {e.intensity: _direct(body, motion, e.intensity) for e in with_mu.evaluations
              if e.status != "failed"}
    top = math.exp(with_mu.quantity.w)  # the flags see the analyses of the answer's window
    for name in states:
        row = with_mu[name]
        upto = [r for i, r in direct.items() if i <= row["intensity"] * top]
        # sliding in contact: a run that did not overturn needed more than μ
        assert row["slides"] == any(not r.overturned and r.mu_required_max > 0.22
                                    for r in upto), name
        assert row["lifts_off"] == any(r.normal_force_min <= 0.0 for r in upto), name
    # the sliding answer of μ = the body's μ slides by definition, milder answers below it not
    assert with_mu["sliding:0.22"]["slides"]
    assert with_mu["overturning"]["lifts_off"]  # near π/2 the support would have to pull
    # without μ: nothing said about sliding, lift-off still; the answers do not move
    without = critical_intensity(body, motion, states, "2d-x", accuracy="fast")
    assert np.isnan(without.slides).all() and without["tilt:1/3"]["slides"] is None
    np.testing.assert_array_equal(without.lifts_off, with_mu.lifts_off)
    np.testing.assert_array_equal(without.intensity, with_mu.intensity)


# --- a study with a sliding goal and mu ------------------------------------------------------


def _study_config(mu=0.6):
    return {"ensembles": {"e": {"record": "el-centro-1940", "n_synthetic": 2}},
            "studies": {"s": {"ensemble": "e", "R": [1.0, 2.0], "mu": mu,
                              "runs": [{"modes": ["3d"], "tan_alpha": [0.2],
                                        "limit_states": ["overturning", "tilt:1/3",
                                                         "sliding:0.6"]}]}}}


def test_a_study_with_a_sliding_goal_and_mu_passes_the_config_checks():
    import yaml

    from rocking.config.checks import schema_error
    from rocking.config.study import StudySpec

    schema_path = __file__.replace("tests/test_sliding.py", "workflow/schemas/config.schema.yaml")
    schema = yaml.safe_load(open(schema_path, encoding="utf-8"))
    config = _study_config()
    assert schema_error(config, schema) is None
    spec = StudySpec.from_config(config, "s").spectra
    assert "sliding:0.6" in spec.plan.limit_states
    assert spec.search_options()["mu"] == 0.6
    assert type(spec).from_attrs(spec.to_attrs()) == spec
    # without mu the store's description (its hash) is as before: no mu key
    plain = copy.deepcopy(config)
    del plain["studies"]["s"]["mu"]
    assert "mu" not in StudySpec.from_config(plain, "s").spectra.search_options()


@pytest.mark.parametrize("mu", [0, -1, float("inf")])
def test_a_study_mu_at_or_below_zero_is_one_line_naming_the_key(mu):
    from rocking.config.study import StudySpec

    with pytest.raises(ValueError) as err:
        StudySpec.from_config(_study_config(mu), "s")
    assert str(err.value) == f"studies.s.mu must be a finite number > 0, got {mu!r}"


def test_a_store_with_a_sliding_goal_carries_the_flags_to_its_tables(tmp_path):
    """A small spectra store filled by the real search: slides / lifts_off per answer in the
    store, critical.csv's frame and mean_spectra's counts, equal to the library's answers."""
    import xarray as xr

    from rocking import store
    from rocking.execution import tasks
    from rocking.motions.ensemble_io import save_ensemble
    from rocking.study import aggregate

    motion = _pulse()
    ensemble = tmp_path / "motions.nc"
    save_ensemble(ensemble, [motion])
    states = ["tilt:1/3", "overturning", "sliding:0.22"]
    layout = tasks.spectra_layout(["2d-x"], states, [motion.name], [TAN_ALPHA], [1.0], 1)
    attrs = {"tolerances": {"name": "fast"}, "quantity": Quantity().to_dict(),
             "search_options": {"upper": 20.0, "mu": 0.22},
             "ensemble": tasks.ensemble_attrs(ensemble, "test")}
    path = tmp_path / "s.zarr"
    store.create_store(path, layout, attrs, "d1")
    tasks.fill_spectra_region(path, 0, ensemble)
    ds = xr.open_zarr(path, consolidated=False)
    want = critical_intensity(Cylinder(1.0, TAN_ALPHA, mu=0.22), motion, states, "2d-x",
                              accuracy="fast")
    for name in states:
        cell = ds.sel(mode="2d-x", limit_state=name, motion=motion.name, tan_alpha=TAN_ALPHA,
                      R=1.0)
        assert float(cell["slides"]) == float(want[name]["slides"])
        assert bool(cell["lifts_off"]) == want[name]["lifts_off"]
    frame = aggregate.critical_frame(ds)
    assert {"slides", "lifts_off"} <= set(frame.columns)
    stats = aggregate.ensemble_statistics(ds)
    n = stats["n_slides"].sel(mode="2d-x", limit_state="sliding:0.22", tan_alpha=TAN_ALPHA,
                              R=1.0)
    assert int(n) == 1


def test_the_report_counts_the_answers_that_slide_or_lift_off():
    import xarray as xr

    from rocking.report.run_summary import validity_text

    dims = ("mode", "limit_state", "motion")
    lifts = np.zeros((2, 2, 3), dtype=bool)
    lifts[0, 1, :] = True  # 3d overturning: every motion
    slides = np.zeros((2, 2, 3))
    slides[1, 0, 0] = 1.0
    ds = xr.Dataset({"lifts_off": (dims, lifts), "slides": (dims, slides)},
                    coords={"mode": ["3d", "2d-x"], "limit_state": ["tilt:1/3", "overturning"],
                            "motion": ["a", "b", "c"]})
    text = validity_text(ds, 0.6)
    assert "μ = 0.6" in text and "3d: slides 0, lifts off 3 of 6" in text
    assert "2d-x: slides 1, lifts off 0 of 6" in text
    no_mu = ds.assign(slides=xr.full_like(ds["slides"], np.nan))
    # no μ and no sliding goal: the kernels ran without the monitors, nothing was looked at
    plain = validity_text(no_mu, None)
    assert "neither sliding nor lift-off was looked at" in plain and "3 of 6" not in plain
    # a sliding goal runs the monitors: lift-off is counted, sliding is not judged without μ
    watched = validity_text(no_mu.assign_coords(limit_state=["sliding:0.5", "overturning"]),
                            None)
    assert "sliding not checked" in watched and "3d: lifts off 3 of 6" in watched
    assert "slides" not in watched.split("—")[1]


def test_tables_leave_lifts_off_empty_where_nothing_was_monitored():
    import xarray as xr

    from rocking.study.aggregate import critical_frame, monitored

    dims = ("mode", "limit_state", "motion", "tan_alpha", "R")
    shape = (2, 2, 2, 1, 1)
    ds = xr.Dataset({"pga_crit": (dims, np.full(shape, 2.0)),
                     "pga_crit_g": (dims, np.full(shape, 0.4)),
                     "lifts_off": (dims, np.ones(shape, dtype=bool)),
                     "requested": (("mode", "limit_state", "tan_alpha"),
                                   np.array([[[True], [False]], [[True], [True]]]))},
                    coords={"mode": ["3d", "2d-x"], "limit_state": ["overturning",
                                                                   "sliding:0.5"],
                            "motion": ["a", "b"], "tan_alpha": [0.2], "R": [1.0]},
                    attrs={"quantity": '{"name": "exceedance_quantile", "p": 0.1, "w": 0.02}'})
    # 3d asked overturning only (no monitors), 2d-x also the sliding goal (monitored)
    assert monitored(ds).sel(tan_alpha=0.2).values.tolist() == [False, True]
    frame = critical_frame(ds)
    by_mode = {m: frame.loc[frame["mode"] == m, "lifts_off"] for m in ("3d", "2d-x")}
    assert by_mode["3d"].isna().all() and len(by_mode["3d"]) == 2
    assert by_mode["2d-x"].eq(True).all() and len(by_mode["2d-x"]) == 4


def test_stripes_mu_adds_the_sliding_fragility_and_refuses_zero(capsys, monkeypatch):
    import rocking.fragility.stripes as stripes
    from rocking.cli import main

    seen = {}

    def record(body, motions, states, **kw):
        seen["states"] = [s.name for s in states]
        raise RuntimeError("stop before the analyses")

    monkeypatch.setattr(stripes, "stripe_fragility", record)
    argv = ["stripes", "--R", "1", "--tan-alpha", "0.2", "--record", "el-centro-1940", "-q"]
    with pytest.raises(RuntimeError, match="stop before"):
        main([*argv, "--mu", "0.6"])
    assert seen["states"] == ["overturning", "tilt:1/3", "sliding:0.6"]
    assert main([*argv, "--mu", "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--mu must be a finite number > 0, got 0.0" in err[0]


def test_exports_keep_sliding_out_of_the_damage_chain(tmp_path):
    """NRML and pelicun hold the tilt axis only (tilt goals, overturning last): a sliding
    goal after overturning would read as a worse damage state; the summary says it was left
    out, the risk table keeps it."""
    import csv
    import xml.etree.ElementTree as ET

    import pandas as pd

    from rocking.fragility import table as fragilities
    from rocking.risk.exports import write_fragility_exports
    from rocking.risk.nrml import NAMESPACE, write_nrml

    cols = ["mode", "limit_state", "tan_alpha [-]", "R [m]", "median_pga_g [g]", "beta [-]",
            "status"]
    table = pd.DataFrame([("3d", "overturning", 0.2, 2.0, 0.31, 0.22, "ok"),
                          ("3d", "sliding:0.6", 0.2, 2.0, 0.45, 0.30, "ok"),
                          ("3d", "tilt:1/3", 0.2, 2.0, 0.25, 0.12, "ok")], columns=cols)
    frag = fragilities.read_fragilities(table)
    assert frag.rows["limit_state"].tolist() == ["tilt:1/3", "overturning", "sliding:0.6"]
    chain, off = frag.damage_chain()
    assert chain.rows["limit_state"].tolist() == ["tilt:1/3", "overturning"]
    assert off == ["sliding:0.6"]
    summary = write_fragility_exports(frag, nrml=tmp_path / "f.xml",
                                      pelicun=tmp_path / "f.csv", study="col")
    assert summary["nrml_limit_states"] == ["tilt:1/3", "overturning"]
    assert summary["left_out_of_chain"].startswith("sliding:0.6 left out of the NRML and pelicun")
    root = ET.parse(tmp_path / "f.xml").getroot()
    ns = {"n": NAMESPACE}
    assert root.find(".//n:limitStates", ns).text == "tilt_1over3 overturning"
    assert "Left out: sliding:0.6" in root.find(".//n:description", ns).text
    assert [p.get("ls") for p in root.findall(".//n:params", ns)] == ["tilt_1over3",
                                                                      "overturning"]
    rows = list(csv.DictReader(open(tmp_path / "f.csv", encoding="utf-8")))
    assert len(rows) == 1 and "LS3-Theta_0" not in rows[0]
    assert float(rows[0]["LS2-Theta_0"]) == 0.31  # overturning is the last damage state
    # asked for explicitly, a sliding goal still stays out
    exp = write_nrml(frag, tmp_path / "g.xml", limit_states=["overturning", "sliding:0.6"])
    assert exp.limit_states == ["overturning"] and exp.off_chain == ["sliding:0.6"]
    # a table of the tilt axis only is exported as before, with nothing said
    plain = write_fragility_exports(fragilities.read_fragilities(table.iloc[[0, 2]]),
                                    nrml=tmp_path / "p.xml", pelicun=tmp_path / "p.csv")
    assert plain["left_out_of_chain"] == ""


def test_the_fall_of_an_overturning_body_is_not_sliding():
    """Against direct runs: every overturned run needs more friction than μ in its fall
    (N → 0⁺), yet sliding:<μ> is the smallest intensity at which a run that did *not*
    overturn needed more; here it lies above overturning (the body overturns first) for
    μ = 0.3 and below it for μ = 0.25."""
    motion = _pulse()
    states = ["overturning", "sliding:0.3", "sliding:0.25"]
    res = critical_intensity(Cylinder(1.0, TAN_ALPHA, mu=0.3), motion, states, "2d-x",
                             accuracy="fast")
    body = Cylinder(1.0, TAN_ALPHA, mu=0.3)
    direct = {e.intensity: _direct(body, motion, e.intensity) for e in res.evaluations}
    falls = [r for r in direct.values() if r.overturned]
    assert falls and all(r.mu_required_max > 0.3 and r.slides is None for r in falls)
    for name, mu in (("sliding:0.3", 0.3), ("sliding:0.25", 0.25)):
        # the search's sample says of each analysis what the direct run says: exceeded
        # where it did not overturn and needed more than μ, nothing where it overturned
        k = res.index(name)
        for x, e in zip(res.samples.intensity, res.samples.exceeded[:, k], strict=True):
            r = direct[x]
            if r.overturned:
                assert math.isnan(e), (name, x)
            elif not math.isnan(e):
                assert bool(e) == (r.mu_required_max > mu), (name, x)
    over = res["overturning"]["intensity"]
    assert res["sliding:0.3"]["intensity"] > over > res["sliding:0.25"]["intensity"]
    # the flags: the overturning answer slides only by a run below it that slid in contact
    assert res["overturning"]["slides"] == any(
        r.slides for i, r in direct.items() if i <= over * math.exp(res.quantity.w))
    assert res["overturning"]["lifts_off"]  # its fall left the support (N <= 0)


def test_the_report_says_in_words_whether_the_column_slides_before_it_overturns():
    import xarray as xr

    from rocking.report.run_summary import sliding_text

    dims = ("mode", "limit_state", "motion", "tan_alpha", "R")
    g = np.full((1, 2, 3, 1, 1), np.nan)
    g[0, :, 0, 0, 0] = (0.5, 0.3)  # a: overturning 0.5 g, slides at 0.3 g: slides first
    g[0, :, 1, 0, 0] = (0.4, 0.7)  # b: overturns at 0.4 g, slides above: overturns first
    # c: neither up to the search bound
    coords = {"mode": ["3d"], "limit_state": ["overturning", "sliding:0.6"],
              "motion": ["a", "b", "c"], "tan_alpha": [0.11], "R": [3.02]}
    ds = xr.Dataset({"pga_crit_g": (dims, g), "slides": (dims, np.zeros(g.shape))},
                    coords=coords)
    text = sliding_text(ds, 0.6)
    assert text.startswith("at μ = 0.6 the column slides before it overturns for 1 of 3 "
                           "motion answers, overturns first for 1, neither up to the search "
                           "bound for 1 — ")
    assert "3d, tan α = 0.11, R = 3.02 m: slides first for 1 of 3 motions at PGA 0.3 g " \
           "(overturning at PGA 0.4–0.5 g (median 0.45 g))" in text
    only_b = ds.isel(motion=[1])
    assert sliding_text(only_b, 0.6).startswith(
        "at μ = 0.6 the column overturns before it slides for every motion that overturns "
        "(1 of 1)")
    # without a sliding goal at the study's μ: the overturning answers' flags, no intensity
    flagged = ds.sel(limit_state=["overturning"]).copy(deep=True)
    flagged["slides"][0, 0, 0, 0, 0] = 1.0
    assert sliding_text(flagged, 0.6).startswith(
        "at μ = 0.6: 1 of 3 overturning answers had an analysis below them that slid")
