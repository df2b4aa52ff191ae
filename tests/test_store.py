"""The zarr study store: layout, region writes, done mask, resume, invalidation.

The engine is replaced by closed-form stand-ins (tests/_store_standins.py), so every stored
number can be compared with a direct evaluation at its coordinates.
"""

from __future__ import annotations

import math
from functools import partial

import _store_standins as standin
import numpy as np
import pytest
import xarray as xr
import zarr

from rocking import store
from rocking.execution import tasks
from rocking.motions.ensemble_io import save_ensemble
from rocking.spectra.limit_states import parse_limit_states
from rocking.spectra.quantity import Quantity
from rocking.store import integrity
from rocking.store.attrs import config_hash
from rocking.store.layout import region_coords

MODES = ["3d", "2d-x"]
LIMIT_STATES = [s.name for s in parse_limit_states(["overturning", "tilt:1/3", "tilt:0.5"])]
R_VALUES = [0.5, 1.0, 2.0, 4.0, 9.0]
TAN_ALPHA = [0.1, 0.2]


@pytest.fixture()
def ensemble(tmp_path):
    path = tmp_path / "motions.nc"
    save_ensemble(path, standin.motions())
    return path


def make_spectra_store(path, ensemble, chunk_R=2, digest="h0"):
    names = [m.name for m in standin.motions()]
    layout = tasks.spectra_layout(MODES, LIMIT_STATES, names, TAN_ALPHA, R_VALUES, chunk_R)
    attrs = {"tolerances": {"name": "fast"}, "quantity": Quantity().to_dict(),
             "search_options": {"upper": 20.0},
             "ensemble": tasks.ensemble_attrs(ensemble, "test"), "config": {"x": 1}}
    store.create_store(path, layout, attrs, digest)
    return layout


def fill(path, ensemble, indices, batch=standin.batch):
    for i in indices:
        tasks.fill_spectra_region(path, i, ensemble, batch=batch)


def test_regions_tile_the_grid_and_match_the_chunks(tmp_path, ensemble):
    path = tmp_path / "s.zarr"
    layout = make_spectra_store(path, ensemble, chunk_R=2)
    # 2 modes x 2 motions x 2 tan_alpha x ceil(5/2) = 24 regions
    assert layout.n_regions == 24
    hits = np.zeros(layout.shape(layout.task_dims), dtype=int)
    for i in range(layout.n_regions):
        region = layout.region(i)
        hits[layout.selection(layout.task_dims, region)] += 1
        assert region["R"].stop - region["R"].start in (1, 2)
    assert np.all(hits == 1)
    group = zarr.open_group(path, mode="r")
    assert group["pga_crit"].chunks == (1, len(LIMIT_STATES), 1, 1, 2)
    assert group["done"].chunks == (1, 1, 1, 2)
    # no chunk file exists before any task ran: creation writes metadata and coordinates only
    assert not (path / "pga_crit" / "c").exists()


def test_filled_store_matches_direct_evaluation(tmp_path, ensemble):
    path = tmp_path / "s.zarr"
    layout = make_spectra_store(path, ensemble)
    fill(path, ensemble, range(layout.n_regions))
    store.StoreHandle.open(path).finalize()
    ds = xr.open_zarr(path, consolidated=True)
    assert list(ds["pga_crit"].dims) == list(tasks.SPECTRA_DIMS)
    assert bool(ds["done"].all())
    by_name = {m.name: m for m in standin.motions()}
    states = parse_limit_states(LIMIT_STATES)
    n_nan = 0
    for mode in MODES:
        for name, motion in by_name.items():
            for ta in TAN_ALPHA:
                for R in R_VALUES:
                    for s in states:
                        point = dict(mode=mode, motion=name, tan_alpha=ta, R=R,
                                     limit_state=s.name)
                        got = float(ds["pga_crit"].sel(point))
                        want = standin.expected_intensity(R, ta, motion, mode, s.severity[1])
                        if math.isnan(want):
                            n_nan += 1
                            assert math.isnan(got) and bool(ds["not_reached"].sel(point))
                        else:
                            assert got == want
                            assert not bool(ds["not_reached"].sel(point))
                        # I50, the first exceedance and the plateau flag of each answer
                        np.testing.assert_equal(float(ds["i50"].sel(point)),
                                                standin.I50_FACTOR * want)
                        np.testing.assert_equal(float(ds["first_exceedance"].sel(point)),
                                                standin.FIRST_FACTOR * want)
                        assert bool(ds["plateau"].sel(point)) == (
                            R == 4.0 and not math.isnan(want))
                        assert bool(ds["non_monotonic"].sel(point)) == (
                            R == 2.0 and s.severity[1] < 1)
                        assert int(ds["n_analyses"].sel(point)) == int(3 + 2 * R)
    assert n_nan == 2 * 2 * 2  # overturning at R = 9 for every mode, motion and tan_alpha
    attrs = store.read_attrs(path)
    assert attrs["config_hash"] == "h0"
    assert attrs["ensemble"]["stand_in"] is True  # motion m1 is flagged a stand-in
    assert [m["label"] for m in attrs["ensemble"]["motions"]] == ["motion 0", "motion 1"]


def _bits(path):
    ds = xr.open_zarr(path, consolidated=False)
    return {k: ds[k].values.view(np.uint8).tobytes() for k in ds.data_vars}


def test_interrupted_fill_resumes_to_identical_bytes(tmp_path, ensemble):
    full, cut = tmp_path / "full.zarr", tmp_path / "cut.zarr"
    layout = make_spectra_store(full, ensemble)
    make_spectra_store(cut, ensemble)
    fill(full, ensemble, range(layout.n_regions))
    # a crashed run: some regions done, one half-written (results on disk, done not set)
    fill(cut, ensemble, range(0, layout.n_regions, 3))
    region = layout.region(1)
    group = zarr.open_group(cut, mode="r+")
    group["pga_crit"][layout.selection(tasks.SPECTRA_DIMS, region)] = -1.0
    pending = store.pending_regions(cut)
    assert pending == [i for i in range(layout.n_regions) if i % 3]
    fill(cut, ensemble, pending)
    assert store.pending_regions(cut) == []
    assert _bits(cut) == _bits(full)


def test_done_is_written_after_the_results(tmp_path, ensemble, monkeypatch):
    path = tmp_path / "s.zarr"
    layout = make_spectra_store(path, ensemble)
    order = []
    original = zarr.Array.__setitem__

    def recording(self, key, value):
        order.append(self.path)
        return original(self, key, value)

    monkeypatch.setattr(zarr.Array, "__setitem__", recording)
    fill(path, ensemble, [0])
    assert order[-1] == "done"
    assert sorted(order[:-1]) == sorted(layout.variables)


def test_failed_task_leaves_region_pending(tmp_path, ensemble):
    path = tmp_path / "s.zarr"
    layout = make_spectra_store(path, ensemble, chunk_R=1)
    failing = [i for i in range(layout.n_regions)
               if list(region_coords(layout, i)["R"]) == [2.0]]
    with pytest.raises(ValueError, match="R=2.0"):
        fill(path, ensemble, failing[:1], batch=standin.failing_batch)
    assert failing[0] in store.pending_regions(path)
    with pytest.raises(ValueError, match="points not done"):
        store.StoreHandle.open(path).finalize()


def test_unexplained_nan_and_bad_shapes_are_refused(tmp_path, ensemble):
    path = tmp_path / "s.zarr"
    layout = make_spectra_store(path, ensemble)
    shape = (1, len(LIMIT_STATES), 1, 1, 2)
    good = {"pga_crit": np.ones(shape), "pga_crit_g": np.full(shape, 0.2),
            "not_reached": np.zeros(shape, bool),
            "non_monotonic": np.zeros(shape, bool), "failed": np.zeros(shape, bool),
            "i50": np.full(shape, 1.2), "first_exceedance": np.full(shape, 0.98),
            "plateau": np.zeros(shape, bool), "n_analyses": np.ones(shape, np.int32),
            "slides": np.zeros(shape), "lifts_off": np.zeros(shape, bool)}
    with pytest.raises(ValueError, match="unexplained NaN"):
        store.write_region(path, layout, 0, {**good, "pga_crit": np.full(shape, np.nan)})
    # slides may say nothing (NaN) only where the writer says why (no mu)
    with pytest.raises(ValueError, match="slides holds an unexplained NaN"):
        store.write_region(path, layout, 0, {**good, "slides": np.full(shape, np.nan)})
    with pytest.raises(ValueError, match=r"pga_crit has shape \(1, 3\)"):
        store.write_region(path, layout, 0, {**good, "pga_crit": np.ones((1, 3))})
    with pytest.raises(ValueError, match=r"missing variables \['failed'\]"):
        store.write_region(path, layout, 0, {k: v for k, v in good.items() if k != "failed"})
    assert store.pending_regions(path)[0] == 0  # nothing was marked done
    store.write_region(path, layout, 0, {**good, "pga_crit": np.full(shape, np.nan)},
                       nan_allowed={"pga_crit": np.ones(shape, bool)})
    assert 0 not in store.pending_regions(path)


def test_other_configuration_or_ensemble_is_refused(tmp_path, ensemble):
    path = tmp_path / "s.zarr"
    make_spectra_store(path, ensemble, digest="aaaa")
    handle = store.StoreHandle.open(path)
    handle.check_config_hash("aaaa")
    with pytest.raises(ValueError, match="config_hash='aaaa'.*config_hash='bbbb'"):
        handle.check_config_hash("bbbb")
    other = tmp_path / "other.nc"
    save_ensemble(other, standin.motions(npts=150))
    tasks.check_ensemble(handle, ensemble)
    with pytest.raises(ValueError, match="other.nc.*made from sha256.*delete the store"):
        tasks.check_ensemble(handle, other)


def test_config_hash_is_canonical():
    a = {"R": [1.0, 2.0], "modes": ["3d"], "accuracy": "fast"}
    b = {"accuracy": "fast", "modes": ["3d"], "R": [1.0, 2.0]}
    assert config_hash(a) == config_hash(b)
    assert config_hash(a) != config_hash({**a, "R": [1.0, 2.5]})
    assert config_hash({"x": np.float64(0.2)}) == config_hash({"x": 0.2})


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"R": [1.0, -2.0]}, r"R must hold finite numbers > 0, got -2.0 at sample 1"),
        ({"R": [1.0, 1.0]}, "R has duplicate values"),
        ({"tan_alpha": []}, "tan_alpha must be a non-empty list"),
        ({"motions": ["a", "a"]}, r"motion has duplicate labels \['a'\]"),
        ({"chunk_R": 0}, "task chunk along 'R' must be an integer >= 1, got 0"),
    ],
)
def test_bad_layouts_name_the_field(kwargs, message):
    args = {"modes": ["3d"], "limit_states": ["overturning"], "motions": ["a"],
            "tan_alpha": [0.2], "R": [1.0], "chunk_R": 1, **kwargs}
    with pytest.raises(ValueError, match=message):
        tasks.spectra_layout(**args)


def test_auto_chunk_sizes_tasks_for_the_target_work():
    point = tasks.ANALYSES_PER_POINT * 5000 * tasks.SECONDS_PER_SAMPLE  # one search [s]
    assert tasks.auto_chunk_R(20, 5000, 0.5 * point) == 1
    assert tasks.auto_chunk_R(20, 5000, 4.5 * point) == 5
    assert tasks.auto_chunk_R(3, 5000, 100 * point) == 3  # never more than the grid


def test_tilt_map_store_matches_direct_evaluation(tmp_path, ensemble):
    path = tmp_path / "t.zarr"
    models, R, intensity = ["3d", "3d-damped"], [1.0, 2.0, 3.0], [0.5, 1.5, 2.5, 3.5]
    layout = tasks.tilt_map_layout(models, R, intensity, chunk_R=2)
    attrs = {"motion": "m0", "tan_alpha": 0.2, "tolerances": {"name": "fast"},
             "model_options": {}, "ensemble": tasks.ensemble_attrs(ensemble, "test")}
    store.create_store(path, layout, attrs, "t0")
    assert layout.n_regions == 4
    fill_one = partial(tasks.fill_tilt_map_region, tilt_map=standin.tilt_map)
    for i in store.pending_regions(path):
        fill_one(path, i, ensemble)
    store.StoreHandle.open(path).finalize()
    ds = xr.open_zarr(path, consolidated=True)
    assert ds["theta_max_over_alpha"].dims == tasks.TILT_MAP_DIMS
    want = np.array([[[standin.expected_theta(r, i, m, 0.2) for i in intensity] for r in R]
                     for m in models])
    np.testing.assert_array_equal(ds["theta_max_over_alpha"].values, want)
    np.testing.assert_array_equal(ds["overturned"].values, want > 3.0)


def test_costliest_regions_are_scheduled_first():
    layout = tasks.spectra_layout(["2d-x", "3d"], ["overturning"], ["a"], [0.2],
                                  [1.0, 2.0, 8.0, 9.0], 2)
    order = tasks.costliest_first(layout, range(layout.n_regions))
    described = [(str(region_coords(layout, i)["mode"][0]),
                  list(region_coords(layout, i)["R"])) for i in order]
    # 3d before 2d at equal sizes; large bodies (more analyses per search) first
    assert described == [("3d", [8.0, 9.0]), ("2d-x", [8.0, 9.0]), ("3d", [1.0, 2.0]),
                         ("2d-x", [1.0, 2.0])]


# --------------------------------------------------------------------------------------------
# Integrity: checksums and the verification pass
# --------------------------------------------------------------------------------------------

def _chunk_bytes(path):
    """Every chunk file of a store, by relative path (metadata left out)."""
    return {str(p.relative_to(path)): p.read_bytes() for p in sorted(path.rglob("*"))
            if p.is_file() and "/c/" in f"/{p.relative_to(path)}"}


def _flip_bit(p):
    data = bytearray(p.read_bytes())
    data[len(data) // 2] ^= 0x10
    p.write_bytes(bytes(data))


def _truncate(p):
    p.write_bytes(p.read_bytes()[: len(p.read_bytes()) // 2])


DAMAGES = {
    "bit flip": ("pga_crit", _flip_bit),
    "truncation": ("pga_crit", _truncate),
    "deleted chunk": ("pga_crit_g", lambda p: p.unlink()),
    "deleted flag chunk": ("not_reached", lambda p: p.unlink()),
    "damaged done mask": ("done", _truncate),
}


@pytest.mark.parametrize("damage", sorted(DAMAGES))
def test_verification_repairs_a_damaged_chunk_to_identical_bytes(tmp_path, ensemble, damage):
    full, hurt = tmp_path / "full.zarr", tmp_path / "hurt.zarr"
    layout = make_spectra_store(full, ensemble)
    make_spectra_store(hurt, ensemble)
    for p in (full, hurt):
        fill(p, ensemble, range(layout.n_regions))
        store.StoreHandle.open(p).finalize()
    assert integrity.has_checksums(hurt)
    name, hurt_it = DAMAGES[damage]
    # region 2 is (3d, m0, 0.1, R = 9): overturning not reached there, so its not_reached
    # chunk holds a True a deleted file would silently turn to False
    region = layout.region(2)
    group = zarr.open_group(hurt, mode="r")
    dims = tasks.SPECTRA_TASK_DIMS if name == "done" else tasks.SPECTRA_DIMS
    chunk = integrity.chunk_file(hurt, group[name], layout.selection(dims, region))
    hurt_it(chunk)
    said = []
    assert integrity.verify_store(integrity.open_checked(hurt, "r+"), say=said.append) == [2]
    assert "chunk 2 damaged" in said[0] and str(hurt) in said[0]
    assert store.pending_regions(hurt) == [2]
    fill(hurt, ensemble, [2])
    store.StoreHandle.open(hurt).finalize()
    assert integrity.verify_store(integrity.open_checked(hurt, "r+")) == []
    assert _chunk_bytes(hurt) == _chunk_bytes(full)
    assert _bits(hurt) == _bits(full)


def test_verification_finds_pga_crit_g_inconsistent_with_pga_crit(tmp_path, ensemble):
    path = tmp_path / "s.zarr"
    layout = make_spectra_store(path, ensemble)
    fill(path, ensemble, range(layout.n_regions))
    group = zarr.open_group(path, mode="r+")
    sel = layout.selection(tasks.SPECTRA_DIMS, layout.region(5))
    group["pga_crit_g"][sel] = group["pga_crit_g"][sel] * 1.01  # a valid chunk, wrong values
    said = []
    assert integrity.verify_store(integrity.open_checked(path, "r+"), say=said.append) == [5]
    assert "pga_crit_g differs from pga_crit" in said[0]


def test_unreadable_done_mask_names_the_store_and_the_remedy(tmp_path, ensemble):
    path = tmp_path / "s.zarr"
    layout = make_spectra_store(path, ensemble)
    fill(path, ensemble, range(layout.n_regions))
    group = zarr.open_group(path, mode="r")
    _truncate(integrity.chunk_file(path, group["done"],
                                layout.selection(tasks.SPECTRA_TASK_DIMS, layout.region(0))))
    with pytest.raises(ValueError, match=r"s\.zarr.*done mask is unreadable.*--forcerun"):
        store.done_mask(path)


def test_store_without_checksums_is_reported_and_verified_by_decoding(tmp_path, ensemble,
                                                                      monkeypatch):
    path = tmp_path / "old.zarr"
    from rocking.store import write as store_write

    monkeypatch.setattr(store_write, "chunk_codecs", lambda: [zarr.codecs.ZstdCodec(level=0)])
    layout = make_spectra_store(path, ensemble)
    fill(path, ensemble, range(layout.n_regions))
    assert not integrity.has_checksums(path)
    group = zarr.open_group(path, mode="r+")
    sel = layout.selection(tasks.SPECTRA_DIMS, layout.region(3))
    group["pga_crit"][sel] = np.nan  # what a damaged old chunk decodes to, unflagged
    said = []
    assert integrity.verify_store(integrity.open_checked(path, "r+"), say=said.append) == [3]
    assert "without chunk checksums" in said[0] and "rebuild" in said[0]


def test_a_damaged_store_is_refused_before_its_numbers_are_read(tmp_path, ensemble):
    """`require_intact` (the aggregate and table rules' check) names the store, the damaged
    region and the remedy, and changes nothing: the store stays damaged for --forcerun."""
    path = tmp_path / "s.zarr"
    layout = make_spectra_store(path, ensemble)
    fill(path, ensemble, range(layout.n_regions))
    store.StoreHandle.open(path).finalize()
    integrity.require_intact(path)  # an intact store passes
    group = zarr.open_group(path, mode="r")
    chunk = integrity.chunk_file(path, group["pga_crit"],
                                 layout.selection(tasks.SPECTRA_DIMS, layout.region(2)))
    _flip_bit(chunk)
    with pytest.raises(ValueError, match=r"1 damaged chunks \[2\]; .*forcerun"):
        integrity.require_intact(path, say=lambda s: None)
    assert store.pending_regions(path) == []  # read-only: the done flags are kept
