"""Ensemble statistics of a spectra store, checked against numpy on hand-made values."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from rocking.motions.ensemble_io import open_netcdf
from rocking.study.aggregate import STAT_DIMS, ensemble_statistics, write_statistics

QUANTITY = '{"name": "exceedance_quantile", "p": 0.1, "w": 0.02}'


def spectra(values, not_reached=None, done=True, quantity=QUANTITY):
    """A spectra dataset with one mode, one limit state, one tan α, motions x R (none
    flagged plateau), of the default quantity."""
    v = np.asarray(values, dtype=float)[None, None, :, None, :]
    nr = np.isnan(v) if not_reached is None else np.asarray(not_reached)[None, None, :, None, :]
    dims = ("mode", "limit_state", "motion", "tan_alpha", "R")
    coords = {"mode": ["3d"], "limit_state": ["overturning"],
              "motion": [f"m{i}" for i in range(v.shape[2])], "tan_alpha": [0.2],
              "R": [1.0, 2.0, 3.0][: v.shape[4]]}
    return xr.Dataset(
        {"pga_crit": (dims, v), "not_reached": (dims, nr),
         "plateau": (dims, np.zeros(v.shape, dtype=bool)),
         "done": (("mode", "motion", "tan_alpha", "R"),
                  np.full((1, v.shape[2], 1, v.shape[4]), done))},
        coords=coords, attrs={"config_hash": "abc", "layout": "{}",
                              "tolerances": '{"scan_step": 0.03}', "quantity": quantity})


def test_statistics_over_motions_leave_out_not_reached():
    values = [[2.0, 3.0, 4.0],
              [4.0, np.nan, 5.0],
              [9.0, np.nan, 6.0]]
    stats = ensemble_statistics(spectra(values))
    assert stats["mean"].dims == STAT_DIMS
    got = {k: stats[k].values.ravel() for k in ("mean", "std", "median", "count",
                                                 "n_not_reached")}
    np.testing.assert_allclose(got["mean"], [5.0, 3.0, 5.0], rtol=0, atol=1e-15)
    # sample standard deviation; a single value has none
    np.testing.assert_allclose(got["std"], [np.std([2, 4, 9], ddof=1), np.nan, 1.0],
                               rtol=1e-15)
    np.testing.assert_array_equal(got["median"], [4.0, 3.0, 5.0])
    np.testing.assert_array_equal(got["count"], [3, 1, 3])
    np.testing.assert_array_equal(got["n_not_reached"], [0, 2, 0])
    assert stats.attrs["motions"] == "m0, m1, m2" and "layout" not in stats.attrs


def test_incomplete_store_is_refused():
    with pytest.raises(ValueError, match="incomplete: 6 points not done"):
        ensemble_statistics(spectra([[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]], done=False))


def test_nan_without_flag_is_refused():
    values = [[1.0, np.nan], [3.0, 4.0]]
    with pytest.raises(ValueError, match="NaN at a point whose limit state was reached"):
        ensemble_statistics(spectra(values, not_reached=np.zeros((2, 2), bool)))


def test_netcdf_and_csv_round_trip(tmp_path):
    stats = ensemble_statistics(spectra([[2.0, 3.0], [4.0, np.nan]]))
    nc, csv = tmp_path / "mean_spectra.nc", tmp_path / "mean_spectra.csv"
    write_statistics(stats, nc, csv)
    with open_netcdf(nc) as back:
        np.testing.assert_array_equal(back["mean"].values, stats["mean"].values)
        assert list(back["mode"].values) == ["3d"]
        # CF attributes survive the file: every variable and coordinate
        for name in back.variables:
            assert {"units", "long_name"} <= set(back[name].attrs), name
        assert back["mean_pga_g"].attrs["units"] == "gravity"
        np.testing.assert_allclose(back["mean_pga_g"].values,
                                   back["mean"].values * back["tan_alpha"].values[:, None])
    table = pd.read_csv(csv)
    assert list(table.columns) == ["mode", "limit_state", "tan_alpha [-]", "R [m]",
                                   "quantity", "quantity_p [-]", "quantity_w [-]",
                                   "scan_step [-]",
                                   "mean [g tan(alpha)]", "mean_pga_g [g]",
                                   "std [g tan(alpha)]", "median [g tan(alpha)]",
                                   "median_all [g tan(alpha)]", "count", "n_not_reached",
                                   "n_plateau", "censoring", "requested"]
    # the quantity on every row, and in the netCDF's attributes
    assert set(table["quantity"]) == {"exceedance_quantile"}
    assert set(table["quantity_p [-]"]) == {0.1} and set(table["quantity_w [-]"]) == {0.02}
    with open_netcdf(nc) as back:
        assert "exceedance_quantile" in back.attrs["quantity"]
    assert table["mean [g tan(alpha)]"].tolist() == [3.0, 3.0]
    assert table["count"].tolist() == [2, 1]


def test_cells_not_requested_are_not_computed_not_not_reached():
    """A (mode, limit state, tan α) cell no run asked for holds NaN with every flag false:
    its statistics are NaN with count 0 and n_not_reached 0, and ``requested`` says why."""
    ds = spectra([[2.0, 3.0], [4.0, 5.0]])
    both = xr.concat([ds, ds.assign_coords(limit_state=["tilt:1/3"])], "limit_state",
                     data_vars="all")
    both["pga_crit"].loc[{"limit_state": "tilt:1/3"}] = np.nan
    both["not_reached"].loc[{"limit_state": "tilt:1/3"}] = False
    both["done"] = ds["done"]
    both["requested"] = (("mode", "limit_state", "tan_alpha"), np.array([[[True], [False]]]))
    stats = ensemble_statistics(both)
    asked = stats.sel(limit_state="overturning")
    np.testing.assert_allclose(asked["mean"].values.ravel(), [3.0, 4.0])
    other = stats.sel(limit_state="tilt:1/3")
    assert np.isnan(other["mean"].values).all()
    assert (other["count"].values == 0).all() and (other["n_not_reached"].values == 0).all()
    assert stats["requested"].sel(limit_state="overturning").all()
    assert not stats["requested"].sel(limit_state="tilt:1/3").any()
    # Without the mask the same NaN would be an unexplained hole: refused.
    with pytest.raises(ValueError, match="NaN"):
        ensemble_statistics(both.drop_vars("requested"))


def test_censoring_is_marked_and_median_all_counts_every_motion(tmp_path):
    """A store with motions not reached at the bound: each row says how many were left out
    of mean/std/median, and median_all ranks them above every reached value (Kaplan-Meier
    with censoring at the bound), NaN when half or more were not reached."""
    values = [[2.0, 3.0, 1.0],
              [4.0, np.nan, 6.0],
              [9.0, np.nan, np.nan],
              [5.0, np.nan, np.nan],
              [7.0, 8.0, np.nan]]
    stats = ensemble_statistics(spectra(values))
    got = stats["median_all"].values.ravel()
    # R=1: no censoring, the ordinary median; R=2: [3, 8, inf, inf, inf] -> inf -> NaN;
    # R=3: [1, 6, inf, inf, inf] -> NaN
    np.testing.assert_array_equal(got[0], np.median([2, 4, 9, 5, 7]))
    assert np.isnan(got[1]) and np.isnan(got[2])
    # the reached-only median would claim 3, 8 and 3.5 for them
    np.testing.assert_array_equal(stats["median"].values.ravel(), [5.0, 5.5, 3.5])
    notes = stats["censoring"].values.ravel().tolist()
    assert notes[0] == "none"
    assert notes[1].startswith("excluded 3 of 5: mean, std, median over the 2 reached only")
    assert notes[1].endswith("median_all above the search bound")
    # one of five not reached: the full-sample median is still determined
    one = ensemble_statistics(spectra([[2.0], [4.0], [np.nan], [5.0], [7.0]]))
    assert float(one["median_all"].values.ravel()[0]) == 5.0  # [2, 4, 5, 7, inf]
    assert float(one["median"].values.ravel()[0]) == 4.5      # reached only: biased low
    assert one["censoring"].values.ravel()[0].endswith("median_all over all motions")
    every = ensemble_statistics(spectra([[np.nan], [np.nan]]))
    assert every["censoring"].values.ravel()[0] == "all 2 not reached: no statistic"
    nc, csv = tmp_path / "m.nc", tmp_path / "m.csv"
    write_statistics(stats, nc, csv)
    table = pd.read_csv(csv)
    assert table["censoring"].tolist() == notes
    assert table["count"].tolist() == [5, 2, 2] and table["n_not_reached"].tolist() == [0, 3, 3]


def test_censoring_of_cells_not_requested():
    ds = spectra([[2.0, 3.0], [4.0, np.nan]])
    both = xr.concat([ds, ds.assign_coords(limit_state=["tilt:1/3"])], "limit_state",
                     data_vars="all")
    both["pga_crit"].loc[{"limit_state": "tilt:1/3"}] = np.nan
    both["not_reached"].loc[{"limit_state": "tilt:1/3"}] = False
    both["done"] = ds["done"]
    both["requested"] = (("mode", "limit_state", "tan_alpha"), np.array([[[True], [False]]]))
    stats = ensemble_statistics(both)
    assert set(stats["censoring"].sel(limit_state="tilt:1/3").values.ravel()) == {
        "not computed"}
    assert np.isnan(stats["median_all"].sel(limit_state="tilt:1/3").values).all()


def test_plateau_answers_are_counted_among_reached_ones_only(tmp_path):
    values = [[2.0, 3.0, 4.0],
              [4.0, np.nan, 5.0],
              [9.0, np.nan, 6.0]]
    ds = spectra(values)
    flag = np.array([[True, False, False],
                     [True, True, False],     # the not-reached flag must not count
                     [False, True, True]])[None, None, :, None, :]
    ds["plateau"] = (ds["pga_crit"].dims, flag)
    stats = ensemble_statistics(ds)
    np.testing.assert_array_equal(stats["n_plateau"].values.ravel(), [2, 0, 1])
    write_statistics(stats, tmp_path / "s.nc", tmp_path / "s.csv")
    assert pd.read_csv(tmp_path / "s.csv")["n_plateau"].tolist() == [2, 0, 1]


def test_a_store_without_its_quantity_is_refused():
    """A store made before the quantity was recorded held first exceedances of an older
    search: its statistics are refused, never set beside I10 under one name."""
    ds = spectra([[2.0, 3.0]])
    del ds.attrs["quantity"]
    with pytest.raises(ValueError, match="without a 'quantity' attribute"):
        ensemble_statistics(ds)


def test_the_tables_name_the_first_exceedance_and_its_grid(tmp_path):
    """Under quantity: first_exceedance the tables say so, with the grid's step."""
    ds = spectra([[2.0, 3.0]], quantity='{"name": "first_exceedance", "p": 0.1, "w": 0.02}')
    write_statistics(ensemble_statistics(ds), tmp_path / "s.nc", tmp_path / "s.csv")
    table = pd.read_csv(tmp_path / "s.csv")
    assert set(table["quantity"]) == {"first_exceedance"}
    assert set(table["scan_step [-]"]) == {0.03}
