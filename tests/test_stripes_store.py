"""The study's stripes store: made, filled region by region (as the Dask tasks do) and fitted;
each stored flag is the library's own analysis, and the table sets the critical-intensity fit
beside the stripe fit."""

from __future__ import annotations

import _store_standins as standin
import numpy as np
import pytest
import xarray as xr

from rocking import store
from rocking.config.study import StudySpec
from rocking.dynamics.bodies import Cylinder
from rocking.execution import products
from rocking.execution import stripes as st
from rocking.fragility import stripe_table as table_of
from rocking.fragility.stripes import stripe_fragility
from rocking.motions.ensemble_io import save_ensemble
from rocking.store.layout import region_coords

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
    assert products.prepare_store("stripes", path, SPEC, "h1", ens) == "created"
    layout = store.open_layout(path)
    assert layout.n_regions == 2 * 3 * 2  # modes x motions x ceil(3 R / 2)
    for i in store.pending_regions(path, layout):
        rep = st.fill_stripes_region(path, i, ens)
        assert rep["points"] == len(region_coords(layout, i)["R"]) * 4
    store.StoreHandle.open(path).finalize()
    assert products.prepare_store("stripes", path, SPEC, "h1", ens) == "resumed"
    return path, ens


def test_store_holds_the_library_answers(filled):
    path, ens = filled
    ds = xr.open_zarr(path, consolidated=True)
    assert ds["exceeded"].dims == table_of.STRIPES_DIMS
    motions = standin.motions(3, npts=300)
    fits = table_of.stripe_fits(ds)
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


def test_table_sets_critical_intensity_beside(filled):
    path, _ = filled
    ds = xr.open_zarr(path, consolidated=True)
    critical = xr.Dataset(
        {"median": (("mode", "limit_state", "tan_alpha", "R"), np.full((1, 1, 1, 1), 2.0)),
         "beta": (("mode", "limit_state", "tan_alpha", "R"), np.full((1, 1, 1, 1), 0.3)),
         "status": (("mode", "limit_state", "tan_alpha", "R"), np.full((1, 1, 1, 1), "ok"))},
        coords={"mode": ["3d"], "limit_state": ["overturning"], "tan_alpha": [0.2],
                "R": [1.0]})
    table = table_of.stripe_table(ds, critical)
    assert list(table.columns) == list(table_of.TABLE_COLUMNS)
    assert len(table) == 2 * 2 * 3
    row = table[(table["mode"] == "3d") & (table["limit_state"] == "overturning")
                & (table["R"] == 1.0)].iloc[0]
    assert row["critical_median"] == 2.0 and row["critical_status"] == "ok"
    if np.isfinite(row["median"]):
        assert row["ratio"] == pytest.approx(row["median"] / 2.0)
    other = table[(table["mode"] == "2d-x")].iloc[0]
    assert other["critical_status"] == "not computed" and np.isnan(other["ratio"])
    # every row either has a finite median or says why not
    for r in table.itertuples():
        assert np.isfinite(r.median) or (r.status != "ok" and r.reason)
    assert set(table["n_motions"]) == {3} and set(table["stripes"]) == {4}


def test_incomplete_store_refused(tmp_path):
    ens = tmp_path / "motions.nc"
    save_ensemble(ens, standin.motions(2, npts=200))
    path = tmp_path / "stripes.zarr"
    products.prepare_store("stripes", path, SPEC, "h1", ens)
    with pytest.raises(ValueError, match="incomplete"):
        table_of.stripe_fits(xr.open_zarr(path, consolidated=False))
    with pytest.raises(ValueError, match="strictly increasing"):
        st.stripes_layout(["3d"], ["overturning"], ["a"], [1.0], [2.0, 1.0], 1)


def test_figure_per_mode(filled, tmp_path):
    from rocking.plot import stripe_fragility as fig
    from rocking.plot._style import save

    path, _ = filled
    d = fig.data(path, None, mode="2d-x")
    assert {p["R"] for p in d["panels"]} == {0.5, 1.0, 2.0}
    assert len(d["panels"]) == 2 * 3 and d["mode"] == "2d-x"
    for key, m in d["measured"].items():
        assert m["stripe_status"] == "ok" or f"{key}: {m['stripe_status']}" in d["missing"]
    f = fig.plot(d)
    out = save(f, [tmp_path / "s.png"])
    assert out[0].stat().st_size > 10_000
    # every panel's legend lies outside its panel (below it): it can cover no marker
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = FigureCanvasAgg(f)
    canvas.draw()
    renderer = canvas.get_renderer()
    for ax in f.axes:
        legend = ax.get_legend()
        assert legend is not None
        box, panel = legend.get_window_extent(renderer), ax.get_window_extent(renderer)
        assert box.y1 < panel.y0 and not box.overlaps(panel)
    with pytest.raises(ValueError, match="not in the stripes store"):
        fig.data(path, None, mode="3d-damped")


def test_verification_reads_a_stripes_store_and_finds_a_damaged_chunk(filled):
    # a stripes store has no (mode, limit_state, tan_alpha) mask: the verification pass that
    # every run starts with must still read it (it once failed on the missing tan_alpha)
    from rocking.store import integrity

    path, _ = filled
    said = []
    assert integrity.verify_store(integrity.open_checked(path, "r+"), say=said.append) == []
    assert said == []
    layout = store.open_layout(path)
    group = store.open_group(path, "r")
    name = next(iter(layout.variables))
    var = layout.variables[name]
    chunk = integrity.chunk_file(path, group[name], layout.selection(var.dims, layout.region(0)))
    data = bytearray(chunk.read_bytes())
    data[len(data) // 2] ^= 0x10
    chunk.write_bytes(bytes(data))
    assert integrity.verify_store(integrity.open_checked(path, "r+"), say=said.append) == [0]
    assert "chunk 0 damaged" in said[0]


def test_refinement_resumes_after_a_kill_and_gives_the_same_bytes(filled, tmp_path,
                                                                    monkeypatch):
    """stripe_fragility.csv with refinement and bootstrap: the stripes added are analysed as
    the library analyses them; a run killed part way (the refinement file cut mid-line)
    redoes only the analyses lost and writes the same bytes."""
    import rocking.fragility.stripes as lib

    path, ens = filled
    csv, nc = tmp_path / "a.csv", tmp_path / "a.nc"
    table = st.write_stripe_fragility(path, csv, nc, motions=ens, refine=4, resamples=60)
    cache = st.refine_cache_path(path)
    lines = cache.read_text().splitlines()
    refined = table[table["n_refined"] > 0]
    rows = st.stripe_rows(xr.open_zarr(path, consolidated=True), refine=4, cache=cache)
    # one line per motion and stripe added to a (mode, R), shared by its limit states
    added = {(m, R, x) for (m, _, R), r in rows.items()
             for x in set(r.intensities) - set(SPEC.intensity)}
    # (what made the file, the store, is in its record: rocking.provenance)
    assert len(refined) >= 1 and len(lines) == 3 * len(added)
    assert sum(r.n_refined for r in rows.values()) == refined["n_refined"].sum()
    # a refined row is what the library gives at the union of the stripes, directly
    motions = standin.motions(3, npts=300)
    for row in refined.itertuples():
        r = rows[(row.mode, row.limit_state, row.R)]
        direct = stripe_fragility(Cylinder(row.R, 0.2), motions, row.limit_state,
                                  mode=row.mode, intensities=r.intensities)
        np.testing.assert_array_equal(r.exceeded, direct.exceeded)
        assert row.status == direct.status[row.limit_state]
        np.testing.assert_equal(row.median, direct.median[row.limit_state])
    # rows still without a fit give the stripes around their median, in g; fitted rows NaN
    nofit = table[~np.isfinite(table["median"])]
    assert (nofit["bracket_lo"] < nofit["bracket_hi"]).all()
    fit = table[np.isfinite(table["median"])]
    assert fit["bracket_lo"].isna().all()
    assert (fit["median_p05"] <= fit["median_im"] + 1e-12).all()
    assert (fit["median_im"] <= fit["median_p95"] + 1e-12).all()
    np.testing.assert_allclose(fit["median_im"], fit["median"] * 0.2)
    # the kill: half the analyses kept (the record renewed after each), the next cut mid-line
    from rocking.provenance import record

    keep = len(lines) // 2
    cache.write_text("\n".join(lines[:keep]) + "\n")
    record(cache, inputs=[path])
    with open(cache, "a") as fh:
        fh.write(lines[keep][:17])
    calls = []
    real = lib.stripe_outcomes

    def counted(*a, **k):
        calls.append(1)
        return real(*a, **k)

    monkeypatch.setattr(lib, "stripe_outcomes", counted)
    csv2, nc2 = tmp_path / "b.csv", tmp_path / "b.nc"
    st.write_stripe_fragility(path, csv2, nc2, motions=ens, refine=4, resamples=60)
    assert len(calls) == len(lines) - keep
    assert csv2.read_bytes() == csv.read_bytes()
    assert cache.read_text().splitlines()[:keep] == lines[:keep]
    a, b = xr.open_dataset(nc), xr.open_dataset(nc2)
    xr.testing.assert_identical(a, b)
    assert a["median"].dims == ("row", "resample") and a.sizes["resample"] == 60
    assert list(a["limit_state"].values) == list(table["limit_state"])
    a.close()
    b.close()
    # nothing new to analyse: replaying the refinement (as the figure does) needs no motions
    st.stripe_rows(xr.open_zarr(path, consolidated=True), refine=4, cache=cache)
    assert len(calls) == len(lines) - keep


def test_figure_draws_a_row_without_fit_as_its_bracket(filled, tmp_path):
    from matplotlib.patches import Polygon, Rectangle

    from rocking.plot import stripe_fragility as fig

    path, ens = filled
    csv = tmp_path / "s.csv"
    st.write_stripe_fragility(path, csv, tmp_path / "s.nc", motions=ens, refine=0,
                              resamples=20, study="t")
    d = fig.data(path, None, mode="3d", table=csv)
    assert "study t" in fig.plot(d)._suptitle.get_text()
    f = fig.plot(d)
    sizes = sorted({p["R"] for p in d["panels"]})
    states = list(dict.fromkeys(p["limit_state"] for p in d["panels"]))
    axes = np.asarray(f.axes[:len(sizes) * len(states)]).reshape(len(states), len(sizes))
    seen = 0
    for p in d["panels"]:
        ax = axes[states.index(p["limit_state"])][sizes.index(p["R"])]
        curves = [ln for ln in ax.get_lines() if len(ln.get_xdata()) == 200]
        lo, hi = p["bracket"]
        if np.isfinite(p["stripe"][0]):
            assert len(curves) == 1 and "IM₅₀" in curves[0].get_label()
        else:
            assert curves == []  # never a line across the gap
            if 0 < lo < hi < np.inf:
                spans = [c for c in ax.patches if isinstance(c, Polygon | Rectangle)]
                assert spans and "IM₅₀ in" in spans[0].get_label()
                seen += 1
        assert ax.get_xlabel() == "PGA [g]"
    assert seen >= 1
    assert fig.CAPTION and "bracket" in fig.CAPTION


def test_stripes_in_sa(tmp_path):
    """A store of Sa(1 s) stripes: each flag as the library's own Sa analysis, the table in
    the measure (no PGA median, no critical-intensity comparison)."""
    config = {
        "ensembles": {"test": {"record": "el-centro-1940"}},
        "studies": {"t": {"ensemble": "test", "R": [1.0], "intensity_measures": ["pga",
                                                                                  "sa:1.0"],
                          "runs": [{"modes": ["3d"], "tan_alpha": [0.2],
                                    "limit_states": ["overturning"]}],
                          "stripes": {"modes": ["3d"], "R": [1.0, 2.0], "measure": "sa:1.0",
                                      "intensity": [1.5, 3.0, 6.0], "chunk_R": 2}}}}
    spec = StudySpec.from_config(config, "t").stripes
    assert spec.measure == "sa:1.0" and spec.to_attrs()["measure"] == "sa:1.0"
    assert "measure" not in SPEC.to_attrs()  # a PGA study keeps the hash it had
    ens = tmp_path / "motions.nc"
    motions = standin.motions(2, npts=300)
    save_ensemble(ens, motions)
    path = tmp_path / "stripes.zarr"
    products.prepare_store("stripes", path, spec, "h2", ens)
    layout = store.open_layout(path)
    for i in store.pending_regions(path, layout):
        st.fill_stripes_region(path, i, ens)
    store.StoreHandle.open(path).finalize()
    ds = xr.open_zarr(path, consolidated=True)
    for R in (1.0, 2.0):
        direct = stripe_fragility(Cylinder(R, 0.2), motions, list(spec.limit_states),
                                  intensities=[1.5, 3.0, 6.0], measure="sa:1.0")
        got = table_of.stripe_fits(ds)[("3d", R)]
        np.testing.assert_array_equal(got.exceeded, direct.exceeded)
        assert got.measure == "sa:1.0"
    table = table_of.stripe_table(ds)
    assert (table["measure"] == "sa:1.0").all() and table["median_pga_g"].isna().all()
    assert table["critical_median"].isna().all()
    np.testing.assert_allclose(ds["im"].values, [0.3, 0.6, 1.2])
    # the report's section names the measure and gives each row its answer or its bracket
    from rocking.report.tables import stripes_section

    csv = tmp_path / "s.csv"
    table = st.write_stripe_fragility(path, csv, tmp_path / "s.nc", motions=ens, refine=0,
                                      resamples=10)
    html = "\n".join(stripes_section(csv))
    assert "stripes are in sa:1.0" in html and "stripe median [sa:1.0, g]" in html
    for r in table.itertuples():
        assert (f"{r.median_im:.3g} (" if np.isfinite(r.median_im)
                else f"between {r.bracket_lo:.3g} and" if np.isfinite(r.bracket_lo)
                else "—") in html
    bad = {**config["studies"]["t"], "intensity_measures": ["pga", "pgv"]}
    with pytest.raises(ValueError, match="stripes.measure='sa:1.0' is not one of"):
        StudySpec.from_config({**config, "studies": {"t": bad}}, "t")
    for key, value in (("refine", -1), ("bootstrap", 2.5), ("refine", True)):
        bad = {**config["studies"]["t"],
               "stripes": {**config["studies"]["t"]["stripes"], key: value}}
        with pytest.raises(ValueError, match=f"studies.t.stripes.{key} must be an integer"):
            StudySpec.from_config({**config, "studies": {"t": bad}}, "t")
    # refine and bootstrap decide no store: the hash stays
    more = {**config["studies"]["t"],
            "stripes": {**config["studies"]["t"]["stripes"], "refine": 3, "bootstrap": 0}}
    other = StudySpec.from_config({**config, "studies": {"t": more}}, "t").stripes
    assert other.digest == spec.digest and (other.refine, other.bootstrap) == (3, 0)


def test_a_stripes_store_held_by_another_run_is_left_alone(filled):
    """Two working directories starting one study: the second stops naming the holder and
    neither replaces nor deletes the stripes store (as for the spectra, test_probes.py)."""
    import os
    import subprocess
    import sys
    import textwrap

    path, ens = filled
    hold = textwrap.dedent("""
        import sys, time
        from rocking import store
        with store.locked(sys.argv[1]):
            print("held", flush=True)
            time.sleep(30)
    """)
    proc = subprocess.Popen([sys.executable, "-c", hold, str(path)], stdout=subprocess.PIPE,
                            text=True, env={**os.environ,
                                            "PYTHONPATH": os.pathsep.join(sys.path)})
    try:
        assert proc.stdout.readline().strip() == "held"
        before = store.done_mask(path).copy()
        # another configuration's hash: a run that held the lock would replace the store
        with pytest.raises(RuntimeError, match=rf"{path.name}' is in use by pid {proc.pid}"):
            products.compute("stripes", path, SPEC, "other-hash", ens, n_workers=1)
        assert (store.done_mask(path) == before).all() and before.all()
    finally:
        proc.kill()
        proc.wait()
