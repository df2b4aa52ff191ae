"""The study's stripes store: made, filled region by region (as the Dask tasks do) and fitted;
each stored flag is the library's own analysis, and the table sets the first-exceedance fit
beside the stripe fit."""

from __future__ import annotations

import _store_standins as standin
import numpy as np
import pytest
import xarray as xr

from rocking.dynamics.bodies import Cylinder
from rocking.motions.ensemble_io import save_ensemble
from rocking.spectra.stripes import stripe_fragility
from rocking.study import store
from rocking.study import stripes as st
from rocking.study.layout import region_coords
from rocking.study.spec import StudySpec

SPEC = StudySpec.from_config({
    "ensembles": {"test": {"record": "el-centro-1940"}},
    "studies": {"t": {"ensemble": "test", "R": [1.0],
                      "runs": [{"modes": ["3d"], "tan_alpha": [0.2],
                                "limit_states": ["overturning"]}],
                      "stripes": {"modes": ["3d", "2d-x"], "R": [0.5, 1.0, 2.0],
                                  "intensity": [1.2, 2.0, 3.5, 6.0], "chunk_R": 2}}}},
    "t").stripes


@pytest.fixture()
def filled(tmp_path):
    ens = tmp_path / "motions.nc"
    save_ensemble(ens, standin.motions(3, npts=300))
    path = tmp_path / "stripes.zarr"
    assert st.prepare_store(path, SPEC, "h1", ens) == "created"
    layout = store.open_layout(path)
    assert layout.n_regions == 2 * 3 * 2  # modes x motions x ceil(3 R / 2)
    for i in store.pending_regions(path, layout):
        rep = st.fill_stripes_region(path, i, ens)
        assert rep["points"] == len(region_coords(layout, i)["R"]) * 4
    store.finalize(path)
    assert st.prepare_store(path, SPEC, "h1", ens) == "resumed"
    return path, ens


def test_store_holds_the_library_answers(filled):
    path, ens = filled
    ds = xr.open_zarr(path, consolidated=True)
    assert ds["exceeded"].dims == st.STRIPES_DIMS
    motions = standin.motions(3, npts=300)
    fits = st.stripe_fits(ds)
    assert set(fits) == {(m, R) for m in ("3d", "2d-x") for R in (0.5, 1.0, 2.0)}
    for mode, R in [("3d", 1.0), ("2d-x", 2.0)]:
        direct = stripe_fragility(Cylinder(R, 0.2), motions, list(SPEC.limit_states), mode=mode,
                                  intensities=list(SPEC.intensity))
        got = fits[(mode, R)]
        np.testing.assert_array_equal(got.exceeded, direct.exceeded)
        assert got.n_analyses == direct.n_analyses
        for ls in direct.limit_states:
            assert got.status[ls] == direct.status[ls]
            np.testing.assert_equal(got.median[ls], direct.median[ls])
    # the stripes' PGA in g is stored beside the intensity
    np.testing.assert_allclose(ds["pga_g"].values, np.array(SPEC.intensity) * 0.2)


def test_table_sets_first_exceedance_beside(filled):
    path, _ = filled
    ds = xr.open_zarr(path, consolidated=True)
    first = xr.Dataset(
        {"median": (("mode", "limit_state", "tan_alpha", "R"), np.full((1, 1, 1, 1), 2.0)),
         "beta": (("mode", "limit_state", "tan_alpha", "R"), np.full((1, 1, 1, 1), 0.3)),
         "status": (("mode", "limit_state", "tan_alpha", "R"), np.full((1, 1, 1, 1), "ok"))},
        coords={"mode": ["3d"], "limit_state": ["overturning"], "tan_alpha": [0.2],
                "R": [1.0]})
    table = st.stripe_table(ds, first)
    assert list(table.columns) == list(st.TABLE_COLUMNS)
    assert len(table) == 2 * 2 * 3
    row = table[(table["mode"] == "3d") & (table["limit_state"] == "overturning")
                & (table["R"] == 1.0)].iloc[0]
    assert row["first_median"] == 2.0 and row["first_status"] == "ok"
    if np.isfinite(row["median"]):
        assert row["ratio"] == pytest.approx(row["median"] / 2.0)
    other = table[(table["mode"] == "2d-x")].iloc[0]
    assert other["first_status"] == "not computed" and np.isnan(other["ratio"])
    # every row either has a finite median or says why not
    for r in table.itertuples():
        assert np.isfinite(r.median) or (r.status != "ok" and r.reason)
    assert set(table["n_motions"]) == {3} and set(table["stripes"]) == {4}


def test_incomplete_store_refused(tmp_path):
    ens = tmp_path / "motions.nc"
    save_ensemble(ens, standin.motions(2, npts=200))
    path = tmp_path / "stripes.zarr"
    st.prepare_store(path, SPEC, "h1", ens)
    with pytest.raises(ValueError, match="incomplete"):
        st.stripe_fits(xr.open_zarr(path, consolidated=False))
    with pytest.raises(ValueError, match="strictly increasing"):
        st.stripes_layout(["3d"], ["overturning"], ["a"], [1.0], [2.0, 1.0], 1)


def test_figure_per_mode(filled, tmp_path):
    from rocking.study.figures import stripe_fragility as fig
    from rocking.study.figures._style import save

    path, _ = filled
    d = fig.data(path, None, mode="2d-x")
    assert {p["R"] for p in d["panels"]} == {0.5, 1.0, 2.0}
    assert len(d["panels"]) == 2 * 3 and d["mode"] == "2d-x"
    for key, m in d["measured"].items():
        assert m["stripe_status"] == "ok" or f"{key}: {m['stripe_status']}" in d["missing"]
    out = save(fig.plot(d), [tmp_path / "s.png"])
    assert out[0].stat().st_size > 10_000
    with pytest.raises(ValueError, match="not in the stripes store"):
        fig.data(path, None, mode="3d-damped")


def test_verification_reads_a_stripes_store_and_finds_a_damaged_chunk(filled):
    # a stripes store has no (mode, limit_state, tan_alpha) mask: the verification pass that
    # every run starts with must still read it (it once failed on the missing tan_alpha)
    from rocking.study import integrity

    path, _ = filled
    said = []
    assert integrity.verify_store(path, say=said.append) == []
    assert said == []
    layout = store.open_layout(path)
    group = store.open_group(path, "r")
    name = next(iter(layout.variables))
    var = layout.variables[name]
    chunk = integrity.chunk_file(path, group[name], layout.selection(var.dims, layout.region(0)))
    data = bytearray(chunk.read_bytes())
    data[len(data) // 2] ^= 0x10
    chunk.write_bytes(bytes(data))
    assert integrity.verify_store(path, say=said.append) == [0]
    assert "chunk 0 damaged" in said[0]
