"""The fragility surface over (R, tan α): exact at the study's nodes, its bootstrap the study's,
an exactly smooth study interpolated exactly, no overshoot, columns beyond the grid refused,
a study without a grid refused."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from rocking.fragility.surface import FragilitySurface, OutsideGrid
from rocking.fragility.table import read_fragilities
from rocking.units import read_table

STUDY = "results/paper/elcentro"
STATES = ("overturning", "tilt:1/3")


@pytest.fixture(scope="module")
def surface():
    return FragilitySurface.from_study(STUDY)


@pytest.fixture(scope="module")
def fragility():
    f = read_table(f"{STUDY}/fragility.csv")
    return f[(f["mode"] == "3d") & (f["status"] == "ok") & f["limit_state"].isin(STATES)]


def test_the_gallery_has_a_grid_in_R_and_tan_alpha(surface):
    assert set(surface.grids) == {("3d", "overturning"), ("3d", "tilt:1/3")}
    assert surface.bounds() == (0.5, 10.0, 0.1, 0.3)
    # the tilt goals computed at tan α 0.2 only have no surface, and are said to have none
    assert any("tilt:0.1" in s for s in surface.skipped)


@pytest.mark.parametrize("ls", STATES)
def test_at_every_node_the_study_own_median_and_beta(surface, fragility, ls):
    """The nodes are refitted from critical.csv (10 digits of each motion's answer): the
    study's own median to 1e-9 and β to 1e-9 absolute (a β of 0.02 is the spread of
    answers kept to 1e-10, so its relative digits go first)."""
    rows = fragility[fragility["limit_state"] == ls]
    got = surface.evaluate(rows["R"], rows["tan_alpha"], "3d", ls)
    np.testing.assert_allclose(got["median"], rows["median_pga_g"], rtol=1e-9)
    np.testing.assert_allclose(got["beta"], rows["beta"], rtol=0, atol=1e-9)
    assert not got["extrapolated"].any()


@pytest.mark.parametrize("ls", STATES)
def test_the_bootstrap_is_the_study_own(surface, fragility, ls):
    """Refitted from critical.csv with the study's seed, the nodes' resamples give the
    study's own interval of the median (fragility.csv's median_p05/p95, to its digits)."""
    rows = fragility[fragility["limit_state"] == ls]
    got = surface.evaluate(rows["R"], rows["tan_alpha"], "3d", ls)
    np.testing.assert_allclose(got["median_p05"], rows["median_p05"], rtol=1e-8)
    np.testing.assert_allclose(got["median_p95"], rows["median_p95"], rtol=1e-8)
    assert got["median_resamples"].shape == (len(rows), 1000)


def test_between_nodes_no_overshoot(surface):
    """Bilinear interpolation stays between the bracketing nodes."""
    g = surface.grids[("3d", "overturning")]
    R = np.sqrt(g.R[:-1] * g.R[1:])  # midpoints in ln R
    for i, ta in enumerate(g.tan_alpha):
        got = surface.evaluate(R, np.full(R.size, ta), "3d", "overturning")["median"]
        lo = np.minimum(g.median[i, :-1], g.median[i, 1:])
        hi = np.maximum(g.median[i, :-1], g.median[i, 1:])
        assert np.all(got >= lo * (1 - 1e-12)) and np.all(got <= hi * (1 + 1e-12))


def _synthetic(tmp_path, tan_alphas, Rs, median, beta):
    rows = [{"mode": "3d", "limit_state": "overturning", "tan_alpha [-]": t, "R [m]": R,
             "median_pga_g [g]": median(R, t), "beta [-]": beta(R, t), "n": 11,
             "status": "ok"} for t in tan_alphas for R in Rs]
    pd.DataFrame(rows).to_csv(tmp_path / "fragility.csv", index=False)
    return tmp_path


def _surface(study):
    """The surface of a fragility table without per-motion answers: no intervals."""
    return FragilitySurface.from_fragilities(read_fragilities(study / "fragility.csv",
                                                              bootstrap=False))


def test_a_surface_of_the_paper_structure_is_reproduced_exactly(tmp_path):
    """θ/(g tan α) = a·R^p (the paper's growth with R, no slenderness effect in the
    normalized intensity) and β linear in tan α: the surface between the nodes is exact
    (both are linear in ln R and tan α), and so is leave-one-out."""
    def median(R, t):
        return 0.9 * R**0.4 * t

    def beta(R, t):
        return 0.1 + 0.5 * t

    study = _synthetic(tmp_path, [0.1, 0.2, 0.3], np.geomspace(0.5, 10, 8), median, beta)
    s = _surface(study)
    R, t = np.array([0.7, 2.2, 5.5, 9.9]), np.array([0.13, 0.27, 0.21, 0.1])
    got = s.evaluate(R, t, "3d", "overturning")
    np.testing.assert_allclose(got["median"], median(R, t), rtol=1e-12)
    np.testing.assert_allclose(got["beta"], beta(R, t), rtol=1e-12)
    loo = s.leave_one_out()
    assert np.abs(loo["err_ln_median"]).max() < 1e-12
    assert np.abs(loo["err_beta"]).max() < 1e-12


def test_a_study_without_a_grid_is_refused_in_one_line(tmp_path):
    study = _synthetic(tmp_path, [0.2], [1.0, 2.0, 3.0], lambda R, t: 0.2 * R, lambda R, t: 0.3)
    with pytest.raises(ValueError, match=r"no grid in R and tan α in mode 3d.*tan α \[0.2\]"
                       ) as err:
        _surface(study)
    assert "\n" not in str(err.value)


def test_a_grid_with_a_node_without_fit_is_refused(tmp_path):
    study = _synthetic(tmp_path, [0.1, 0.2], [1.0, 2.0], lambda R, t: 0.2 * R,
                       lambda R, t: 0.3)
    f = pd.read_csv(study / "fragility.csv")
    f.loc[0, "median_pga_g [g]"] = np.nan
    f.loc[0, "status"] = "too-few-observed"
    f.to_csv(study / "fragility.csv", index=False)
    with pytest.raises(ValueError, match="1 node.*without a fit"):
        _surface(study)


def test_a_column_outside_is_refused_or_marked_only_when_asked(surface):
    with pytest.raises(OutsideGrid, match=r"R outside the surface's grid.*0.5–10 m") as err:
        surface.evaluate([12.0], [0.2], "3d", "overturning")
    assert "\n" not in str(err.value)
    with pytest.raises(OutsideGrid, match="tan_alpha outside"):
        surface.evaluate([3.0], [0.05], "3d", "overturning")
    got = surface.evaluate([12.0, 3.0], [0.2, 0.2], "3d", "overturning", extrapolate=True)
    assert got["extrapolated"].tolist() == [True, False]
    assert np.isfinite(got["median"]).all()


def test_leave_one_out_is_stated_per_direction(surface):
    s = surface.loo_summary()
    assert set(s["left_out"]) == {"R", "tan_alpha"}
    # R: 3 rows × 18 interior nodes; tan α: the 0.2 row's 20 nodes
    assert sorted(s["nodes"].unique()) == [20, 54]
    # what docs/risk.md quotes: every leave-one-out error of ln θ within 0.1
    assert 0 < s["max_ln_median"].max() < 0.1
    err = surface.interpolation_error()
    assert err[("3d", "overturning")] == pytest.approx(
        s[s["limit_state"] == "overturning"]["max_ln_median"].max())


def test_a_two_by_two_grid_states_no_interpolation_error_rather_than_inventing_one():
    from rocking.fragility.surface import LimitStateGrid
    from rocking.risk.portfolio import error_words

    ta, R = np.array([0.15, 0.2]), np.array([1.0, 3.0])
    median = np.array([[0.2, 0.4], [0.25, 0.5]])
    grid = LimitStateGrid(ta, R, median, np.full((2, 2), 0.3), np.empty((2, 2, 0)),
                          np.empty((2, 2, 0)))
    surface = FragilitySurface({("3d", "overturning"): grid})
    assert surface.leave_one_out().empty
    err = surface.interpolation_error()[("3d", "overturning")]
    assert np.isnan(err)
    assert error_words(err) == "not measured (no interior grid node to leave out)"
    assert error_words(0.051) == "±5.1 % (leave-one-out)"
    # the surface still answers at its nodes
    out = surface.evaluate(np.array([3.0]), np.array([0.2]), "3d", "overturning")
    assert out["median"][0] == pytest.approx(0.5, rel=1e-12)
