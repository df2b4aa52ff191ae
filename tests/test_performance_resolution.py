"""Resolution of the critical intensity: the ``unresolved`` flag and the window-seeking scan
on synthetic responses whose every window is known, and the flag's way into the store.

The fake analysis (tests/test_performance_search.py) maps I to θ_max/α piecewise and honours
``stop_at`` like the engine, so the first exceedance is known exactly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import _store_standins as standin
import numpy as np
import pytest
import xarray as xr
from test_performance_search import ALPHA, fake_analysis, smooth_response

from rocking import store
from rocking.execution import tasks
from rocking.motions.ensemble_io import save_ensemble
from rocking.spectra.accuracy import PRESETS
from rocking.spectra.limit_states import parse_limit_states
from rocking.spectra.quantity import Quantity
from rocking.spectra.search import search_critical, window_warning
from rocking.study.aggregate import critical_frame

FIXED = PRESETS["default"].with_(scan="fixed", scan_step=0.01, refine_budget=0)
"""A fixed 1 % scan without refinement (the study's default scan before the refinement of
near misses, tests/test_search_refine.py): what the flag alone says."""
SEEK = PRESETS["default"].with_(name="seek", scan="seek", scan_step=0.001,
                                scan_step_max=0.03, seek_near=0.5)
GOALS = ["tilt:0.5", "overturning"]
P69, P70 = 1.01 ** 69, 1.01 ** 70
"""Two neighbouring points of the fixed 1 % scan from I = 1."""


def stepped_over_response(I):
    """θ/α (None: overturned): a peak near tilt:0.5 with a window 0.3 % wide between two
    points of the 1 % scan. The scan sees 0.45 α at P69 (90 % of the goal), then 0.3 α at
    P70: the shoulders of the window. Robust exceedance from 2.5, overturning from 3."""
    if I >= 3.0:
        return None
    if I >= 2.5 or P69 * 1.003 <= I < P69 * 1.006:
        return 0.6
    if P69 * 0.995 <= I < P70 * 0.995:
        return 0.45
    return 0.3 if I >= 1.3 else 1e-6 * I


def test_window_stepped_over_is_flagged_unresolved():
    res = search_critical(fake_analysis(stepped_over_response, []), GOALS, ALPHA, lower=1.0,
                          upper=10.0, accuracy=FIXED)
    k = res.limit_states.index("tilt:0.5")
    # the scan stepped over the window: the answer is the robust exceedance, 20 % too high
    assert res.intensity[k] > 2.49
    assert bool(res.unresolved[k])
    assert res.to_records()[k]["unresolved"] is True
    assert "unresolved" in repr(res)
    # overturning: the response stays far below α up to its robust exceedance
    assert not res.unresolved[res.limit_states.index("overturning")]


def test_monotone_response_is_not_flagged():
    states = ["tilt:0.1", "tilt:1/3", "tilt:0.5", "overturning"]
    for acc in (FIXED, SEEK, PRESETS["precise"]):
        res = search_critical(fake_analysis(smooth_response, []), states, ALPHA, lower=1.0,
                              upper=10.0, accuracy=acc)
        assert not res.unresolved.any(), acc.name
        assert not res.not_reached.any()


def test_window_warning_needs_a_close_peak_or_a_spike_that_falls_back():
    assert window_warning(np.array([0.1, 0.6, 0.3, 0.4]), 0.5, 3.0)  # close peak fell back
    assert not window_warning(np.array([0.1, 0.4, 0.3, 0.45]), 0.5, 3.0)  # peak far, mild
    assert window_warning(np.array([1e-4, 0.02, 1e-3, 0.3]), 0.5, 3.0)  # far, but a spike
    assert not window_warning(np.array([0.1, 0.5, 0.7, 0.9]), 0.5, 3.0)  # rising to the goal
    assert not window_warning(np.array([0.9]), 0.5, 3.0)  # one point: nothing to compare
    assert not window_warning(np.array([]), 0.5, 3.0)


def hidden_window_response(I):
    """Far from tilt:0.5 (0.1 α) except a plateau at 0.45 α on [1.9, 2.05) holding a window
    0.2 % wide at [1.98, 1.984), between the 1 % scan's points 1.01^68 and 1.01^69."""
    if I >= 3.0:
        return None
    if I >= 2.5 or 1.98 <= I < 1.984:
        return 0.6
    if 1.9 <= I < 2.05:
        return 0.45
    return 0.1 if I >= 1.05 else 1e-6 * I


def test_seek_scan_finds_the_window_the_fixed_scan_misses():
    assert 1.01 ** 68 < 1.98 and 1.984 < 1.01 ** 69
    found = {}
    fine = FIXED.with_(scan_step=SEEK.scan_step)
    for acc in (FIXED, SEEK, fine):
        calls = []
        res = search_critical(fake_analysis(hidden_window_response, calls), GOALS, ALPHA,
                              lower=1.0, upper=10.0, accuracy=acc)
        found[acc.scan, acc.scan_step] = (float(res.intensity[0]), len(calls))
    assert found["fixed", 0.01][0] > 2.49  # stepped over
    assert 1.98 <= found["seek", SEEK.scan_step][0] <= 1.984 * (1 + SEEK.bisection_tol)
    # a fixed scan at the seeking scan's finest step finds it too, at a higher cost: the
    # seeking scan is coarse far from the goals
    assert found["fixed", SEEK.scan_step][0] == pytest.approx(found["seek", SEEK.scan_step][0],
                                                              rel=SEEK.bisection_tol)
    assert found["seek", SEEK.scan_step][1] < 0.6 * found["fixed", SEEK.scan_step][1]


def test_seek_step_follows_the_closeness():
    goal = 0.1
    assert SEEK.seek_step(0.0, goal) == SEEK.scan_step_max
    assert SEEK.seek_step(goal * SEEK.seek_near, goal) == SEEK.scan_step
    assert SEEK.seek_step(float("nan"), goal) == SEEK.scan_step
    assert SEEK.seek_step(2 * goal, goal) == SEEK.scan_step
    steps = [SEEK.seek_step(goal * r, goal) for r in (0.45, 0.3, 0.1, 0.0)]
    assert steps == sorted(steps)
    half = SEEK.seek_step(goal * SEEK.seek_near / 2, goal)  # geometric mean of the two
    assert half == pytest.approx(math.sqrt(SEEK.scan_step * SEEK.scan_step_max), rel=1e-12)


def test_seek_settings_are_checked_and_written():
    with pytest.raises(ValueError, match="seek_near"):
        SEEK.with_(seek_near=1.5)
    with pytest.raises(ValueError, match="scan_relative"):
        SEEK.with_(scan_relative=False)
    assert SEEK.to_dict()["seek_near"] == SEEK.seek_near
    assert "seek_near" not in FIXED.to_dict()  # other scans keep their attributes


# ------------------------------------------------------------------------ store round trip
@dataclass(frozen=True)
class FlaggedResult(standin.FakeResult):
    unresolved: np.ndarray | None = None


def flagged_batch(tasks, limit_states, **kw):
    """The store stand-in, with ``unresolved`` set where R = 4 and the goal is a tilt."""
    out = []
    for r, (R, *_rest) in zip(standin.batch(tasks, limit_states, **kw), tasks, strict=True):
        flags = np.array([R == 4.0 and s.name != "overturning"
                          for s in parse_limit_states(r.limit_states)])
        out.append(FlaggedResult(*(getattr(r, f) for f in (
            "limit_states", "intensity", "not_reached", "non_monotonic", "failed",
            "n_analyses")), unresolved=flags))
    return out


def _store(tmp_path, drop_unresolved: bool):
    ensemble = tmp_path / "motions.nc"
    save_ensemble(ensemble, standin.motions())
    names = [m.name for m in standin.motions()]
    states = [s.name for s in parse_limit_states(["overturning", "tilt:1/3"])]
    layout = tasks.spectra_layout(["3d"], states, names, [0.2], [1.0, 4.0], 1)
    if drop_unresolved:  # a store made before the variable existed
        del layout.variables["unresolved"]
    path = tmp_path / "s.zarr"
    attrs = {"tolerances": {"name": "fast"}, "quantity": Quantity().to_dict(),
             "search_options": {"upper": 20.0},
             "ensemble": tasks.ensemble_attrs(ensemble, "test"), "config": {"x": 1}}
    store.create_store(path, layout, attrs, "h0")
    for i in range(layout.n_regions):
        tasks.fill_spectra_region(path, i, ensemble, batch=flagged_batch)
    store.StoreHandle.open(path).finalize()
    return path


def test_unresolved_round_trips_through_store_and_critical_frame(tmp_path):
    path = _store(tmp_path, drop_unresolved=False)
    with xr.open_zarr(path, consolidated=True) as ds:
        frame = critical_frame(ds)
    col = [c for c in frame.columns if c.startswith("unresolved")]
    assert len(col) == 1
    want = (frame["R [m]"] == 4.0) & (frame["limit_state"] != "overturning")
    assert want.sum() == 2 and (frame[col[0]].astype(bool) == want).all()


def test_store_without_unresolved_stays_readable(tmp_path):
    path = _store(tmp_path, drop_unresolved=True)
    with xr.open_zarr(path, consolidated=True) as ds:
        assert "unresolved" not in ds
        frame = critical_frame(ds)
    assert not any(c.startswith("unresolved") for c in frame.columns)
    assert frame["pga_crit [g tan(alpha)]"].notna().any()


def test_unresolved_is_a_column_of_the_cli_and_of_critical_csv():
    from rocking.cli.spectra import COLUMNS
    from rocking.study.aggregate import CRITICAL_COLUMNS
    from rocking.units import header

    assert "unresolved" in COLUMNS and "unresolved" in CRITICAL_COLUMNS
    assert "unresolved" in tasks.spectra_layout(["3d"], ["overturning"], ["m"], [0.2], [1.0],
                                                1).variables
    assert header("unresolved") == "unresolved"  # a flag: no unit
