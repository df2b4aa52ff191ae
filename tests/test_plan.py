"""Per-mode study plans: runs united into one grid, cells nobody asks for never computed.

The store side uses the closed-form engine stand-ins (tests/_store_standins.py), so every
computed cell is compared with its direct evaluation and every other cell must stay empty.
"""

from __future__ import annotations

import math

import _store_standins as standin
import numpy as np
import pytest
import xarray as xr

from rocking import store
from rocking.config.plan import plan_study
from rocking.execution import tasks
from rocking.motions.ensemble_io import save_ensemble
from rocking.spectra.limit_states import parse_limit_states
from rocking.spectra.quantity import Quantity
from rocking.study.aggregate import ensemble_statistics

RUNS = [
    {"purpose": "Fig 10", "modes": ["3d"], "tan_alpha": [0.2],
     "limit_states": ["overturning", "tilt:1/3", "tilt:0.5"]},
    {"purpose": "Fig 11", "modes": ["3d"], "tan_alpha": [0.1, 0.3],
     "limit_states": ["overturning", "tilt:1/3"]},
    {"purpose": "Fig 12", "modes": ["2d-y", "2d-x"], "tan_alpha": [0.2],
     "limit_states": ["overturning"]},
]


def test_union_grid_and_requested_cells():
    plan = plan_study(RUNS, "studies.s.runs")
    assert plan.modes == ("3d", "2d-x", "2d-y")  # the order of MODES, not of the runs
    assert plan.limit_states == ("tilt:1/3", "tilt:0.5", "overturning")
    assert plan.tan_alpha == (0.1, 0.2, 0.3)
    assert plan.limit_states_of("3d", 0.2) == ["tilt:1/3", "tilt:0.5", "overturning"]
    assert plan.limit_states_of("3d", 0.3) == ["tilt:1/3", "overturning"]
    assert plan.limit_states_of("2d-x", 0.2) == ["overturning"]
    assert plan.limit_states_of("2d-y", 0.1) == []
    assert int(plan.requested.sum()) == 3 + 2 * 2 + 2 * 1
    # cost: one search per requested (mode, tan α) and point, whatever its limit states
    assert plan.points(n_motions=11, n_R=20) == {"3d": 660, "2d-x": 220, "2d-y": 220}
    # the purpose is a label: it does not enter what a store hashes
    assert "purpose" not in str(plan.to_dict())


def _study_figures(runs) -> list[str]:
    """The figures of a study's own (scope ``study``) its entries want for these runs (no
    tilt map)."""
    from types import SimpleNamespace

    from rocking.plot.registry import figures

    subject = SimpleNamespace(plan=plan_study(runs),
                              spec=lambda: SimpleNamespace(tilt_map=None))
    return [n for n, f in figures().items() if f.scope == "study" and f.wanted(subject)]


def test_figures_drawn_only_where_the_runs_give_them_data():
    assert _study_figures(RUNS) == ["fig09_spectra", "fig10_goals", "fig11_slenderness",
                                    "fragility_curves"]
    # the paper's Loma Prieta study: 3D and 2D at one tan α, two goals: no Fig 11
    loma = [{"modes": ["3d", "2d-x", "2d-y"], "tan_alpha": [0.2],
             "limit_states": ["overturning", "tilt:1/3"]}]
    assert _study_figures(loma) == ["fig09_spectra", "fig10_goals", "fragility_curves"]
    assert plan_study(loma).compares_2d_with_3d()
    # a study of one's own: one mode, one tan α, two goals still has its spectrum figures
    own = [{"modes": ["3d"], "tan_alpha": [0.15], "limit_states": ["overturning", "tilt:1/3"]}]
    assert _study_figures(own) == ["fig09_spectra", "fig10_goals", "fragility_curves"]
    assert not plan_study(own).compares_2d_with_3d()
    # 2D at a tan α where 3d is not computed cannot be compared with it
    apart = [{"modes": ["3d"], "tan_alpha": [0.2], "limit_states": ["overturning"]},
             {"modes": ["2d-x"], "tan_alpha": [0.3], "limit_states": ["overturning"]}]
    assert not plan_study(apart).compares_2d_with_3d()
    # a 2D-only study draws its own mode's figures
    assert _study_figures([{"modes": ["2d-x"], "tan_alpha": [0.2],
                            "limit_states": ["overturning"]}]) == [
        "fig09_spectra", "fig10_goals", "fragility_curves"]


def test_one_goal_spelt_two_ways_is_one_cell():
    plan = plan_study([{"modes": ["3d"], "tan_alpha": [0.2], "limit_states": ["tilt:1/2"]},
                       {"modes": ["2d-x"], "tan_alpha": [0.2], "limit_states": ["tilt:0.5"]}])
    assert plan.limit_states == ("tilt:0.5",)  # the canonical spelling
    assert plan.requested.all()


@pytest.mark.parametrize(
    ("runs", "message"),
    [
        ([], "studies.s.runs must be a non-empty list"),
        ([{"modes": ["4d"], "tan_alpha": [0.2], "limit_states": ["overturning"]}],
         r"studies.s.runs\[0\].modes: unknown mode\(s\) \['4d'\]"),
        ([{"modes": ["3d"], "tan_alpha": [0.0], "limit_states": ["overturning"]}],
         r"studies.s.runs\[0\].tan_alpha must hold finite numbers > 0, got 0.0"),
        ([{"modes": ["3d"], "tan_alpha": [0.2], "limit_states": []}],
         r"studies.s.runs\[0\].limit_states must be a non-empty list"),
        ([{"modes": ["3d"], "tan_alpha": [0.2], "limit_states": ["tilt:0.5", "tilt:1/2"]}],
         "names one tilt goal twice"),
        ([RUNS[0], {"modes": ["3d"], "tan_alpha": [5.0], "limit_states": ["tilt:1.5"]}],
         r"studies.s.runs\[1\].limit_states: limit state 'tilt:1.5'"),
        ([{"modes": ["3d"], "tan_alpha": [0.2], "limit_states": ["overturning"], "mode": 1}],
         r"studies.s.runs\[0\] has unknown key\(s\) \['mode'\]"),
    ],
    ids=["empty", "mode", "tan-alpha", "no-limit-state", "goal-twice", "goal-beyond-pi/2",
         "unknown-key"],
)
def test_bad_runs_name_the_field_and_value(runs, message):
    with pytest.raises(ValueError, match=message):
        plan_study(runs, "studies.s.runs")


@pytest.fixture()
def planned_store(tmp_path):
    """A store of RUNS over the stand-in motions, chunked one size R per task."""
    ensemble = tmp_path / "motions.nc"
    save_ensemble(ensemble, standin.motions())
    plan = plan_study(RUNS)
    names = [m.name for m in standin.motions()]
    layout = tasks.spectra_layout(plan.modes, plan.limit_states, names, plan.tan_alpha,
                                  [1.0, 9.0], 1)
    attrs = {"tolerances": {"name": "fast"}, "quantity": Quantity().to_dict(),
             "search_options": {"upper": 20.0},
             "ensemble": tasks.ensemble_attrs(ensemble, "test")}
    path = tmp_path / "s.zarr"
    store.create_store(path, layout, attrs, "h", static={store.REQUESTED: plan.requested})
    return path, ensemble, plan, layout


def test_store_computes_only_requested_cells(planned_store):
    path, ensemble, plan, layout = planned_store
    asked = []

    def recording_batch(tasks, limit_states, **kw):
        asked.append((tasks[0][3], tasks[0][1], list(limit_states)))
        return standin.batch(tasks, limit_states, **kw)

    # (mode, tan α) pairs nobody asked for (2D at 0.1 and 0.3) are done before any task
    pending = store.pending_regions(path)
    skipped = store.regions_not_requested(layout, plan.requested)
    assert len(skipped) == 2 * 2 * 2 * 2 and sorted(pending + skipped) == \
        list(range(layout.n_regions))
    for i in pending:
        tasks.fill_spectra_region(path, i, ensemble, batch=recording_batch)
    # each search is handed only the limit states requested for its mode and tan α
    for mode, tan_alpha, states in asked:
        assert states == plan.limit_states_of(mode, tan_alpha)
    store.StoreHandle.open(path).finalize()
    ds = xr.open_zarr(path, consolidated=True)
    np.testing.assert_array_equal(ds[store.REQUESTED].transpose(*store.REQUESTED_DIMS).values,
                                  plan.requested)
    motions = {m.name: m for m in standin.motions()}
    ratio = {s.name: s.severity[1] for s in parse_limit_states(plan.limit_states)}
    for idx in np.ndindex(plan.requested.shape):
        mode, ls, ta = (plan.modes[idx[0]], plan.limit_states[idx[1]], plan.tan_alpha[idx[2]])
        cell = ds.sel(mode=mode, limit_state=ls, tan_alpha=ta)
        if not plan.requested[idx]:
            # not computed: NaN with every flag false and no analyses
            assert bool(cell["pga_crit"].isnull().all()), (mode, ls, ta)
            for flag in ("not_reached", "non_monotonic", "failed"):
                assert not bool(cell[flag].any()), (mode, ls, ta, flag)
            assert int(cell["n_analyses"].max()) == 0
            continue
        for name, motion in motions.items():
            for R in (1.0, 9.0):
                want = standin.expected_intensity(R, ta, motion, mode, ratio[ls])
                got = float(cell["pga_crit"].sel(motion=name, R=R))
                assert (math.isnan(got) and math.isnan(want)) or got == want
                assert bool(cell["not_reached"].sel(motion=name, R=R)) == math.isnan(want)
    # the aggregate keeps "not requested" apart from "not reached"
    stats = ensemble_statistics(ds)
    skipped_cells = ~stats["requested"]
    assert bool(stats["mean"].where(skipped_cells).isnull().all())
    assert int(stats["count"].where(skipped_cells, 0).max()) == 0
    over = stats.sel(mode="3d", limit_state="overturning", tan_alpha=0.2)
    assert over["n_not_reached"].values.tolist() == [0, 2]  # R = 9 never overturns


def test_planned_store_resumes_to_identical_bytes(planned_store, tmp_path):
    path, ensemble, plan, layout = planned_store
    other = tmp_path / "again.zarr"
    attrs = {k: v for k, v in store.read_attrs(path).items()
             if k not in ("layout", "config_hash")}
    store.create_store(other, layout, attrs, "h", static={store.REQUESTED: plan.requested})
    for i in store.pending_regions(path):
        tasks.fill_spectra_region(path, i, ensemble, batch=standin.batch)
    pending = store.pending_regions(other)
    for i in pending[::2]:  # a run killed after every other task, then resumed
        tasks.fill_spectra_region(other, i, ensemble, batch=standin.batch)
    assert store.pending_regions(other) == pending[1::2]
    for i in store.pending_regions(other):
        tasks.fill_spectra_region(other, i, ensemble, batch=standin.batch)

    def bits(p):
        ds = xr.open_zarr(p, consolidated=False)
        return {k: ds[k].values.view(np.uint8).tobytes() for k in ds.data_vars}

    assert bits(other) == bits(path)
