"""Small stores filled in the rule's own process: same values as a serial fill, no cluster.

Starting an embedded LocalCluster costs more than a few hundred analyses
(rocking.execution.cluster.IN_PROCESS_ANALYSES); fill_store then runs the same task bodies in
its own process. The stand-in engine is tests/_store_standins.py.
"""

from __future__ import annotations

import logging
from functools import partial

import _store_standins as standin
import pytest
from test_cluster import _spectra_store, _values

from rocking import store
from rocking.execution import cluster, products, tasks
from rocking.spectra.quantity import Quantity
from rocking.store import integrity


def test_small_store_is_filled_in_process_with_the_serial_values(tmp_path, caplog):
    path, ensemble, layout = _spectra_store(tmp_path)
    serial, _, _ = _spectra_store(tmp_path, "serial.zarr")
    for i in range(layout.n_regions):
        tasks.fill_spectra_region(serial, i, ensemble, batch=standin.batch)
    fn = partial(tasks.fill_spectra_region, batch=standin.batch)
    # 16 spectrum points, each a search of about SPECTRA_ANALYSES_PER_POINT analyses
    work = cluster.estimated_analyses(layout, range(layout.n_regions),
                                      products.SPECTRA_ANALYSES_PER_POINT)
    assert work == 16 * products.SPECTRA_ANALYSES_PER_POINT
    with caplog.at_level(logging.INFO, logger="rocking.execution.cluster"):
        summary = cluster.fill_store(store.StoreHandle.open(path, "r+"), fn, ensemble,
                                     config_digest="d1", n_workers=2,
                                     progress_interval=0.0, in_process_analyses=work,
                                     analyses_per_point=products.SPECTRA_ANALYSES_PER_POINT)
    assert summary["cluster"] == "in-process"
    assert summary["computed"] == 8 and summary["points_computed"] == 16
    assert "computed in this process" in caplog.text
    assert "dashboard" not in caplog.text and "worker pids" not in caplog.text
    assert _values(path) == _values(serial)


def test_a_store_above_the_threshold_is_not_filled_in_process(tmp_path, monkeypatch):
    path, ensemble, layout = _spectra_store(tmp_path)
    fn = partial(tasks.fill_spectra_region, batch=standin.batch)
    work = cluster.estimated_analyses(layout, range(layout.n_regions),
                                      products.SPECTRA_ANALYSES_PER_POINT)

    def no_cluster(*args, **kwargs):
        raise RuntimeError("a cluster was asked for")

    monkeypatch.setattr(cluster, "dask_client", no_cluster)
    with pytest.raises(RuntimeError, match="a cluster was asked for"):
        cluster.fill_store(store.StoreHandle.open(path, "r+"), fn, ensemble,
                           config_digest="d1", in_process_analyses=work - 1,
                           analyses_per_point=products.SPECTRA_ANALYSES_PER_POINT)
    assert store.pending_regions(path) == list(range(layout.n_regions))


def test_a_failing_region_in_process_is_named(tmp_path):
    path, ensemble, layout = _spectra_store(tmp_path)
    fn = partial(tasks.fill_spectra_region, batch=standin.failing_batch)
    with pytest.raises(RuntimeError, match=r"chunk 0 failed: stand-in failure"):
        cluster.fill_store(store.StoreHandle.open(path, "r+"), fn, ensemble,
                           config_digest="d1", in_process_analyses=10**6)


def test_the_workflow_passes_the_threshold():
    cfg = {"dask": {"scheduler_address": None, "scheduler_file": None,
                    "progress_interval": 10, "worker_timeout": 60}}
    assert cluster.dask_options(cfg)["in_process_analyses"] == cluster.IN_PROCESS_ANALYSES
    # a tilt-map or stripe point is one analysis
    layout = tasks.tilt_map_layout(["3d"], [1.0, 2.0], [1.0, 2.0, 3.0], 1)
    assert products.PRODUCTS["tilt_map"].analyses_per_point == 1
    assert cluster.estimated_analyses(layout, [0, 1]) == 6


def test_store_metadata_is_read_once_and_never_stale(tmp_path):
    """A worker reads a store's layout, attributes and requested cells once; a new store at
    the same path (another configuration) is read again."""
    path, ensemble, layout = _spectra_store(tmp_path)
    tasks._store_metadata.cache_clear()
    first = tasks.store_metadata(path)
    again = tasks.store_metadata(path)
    assert tasks._store_metadata.cache_info().hits == 1
    assert again[0] is first[0] and again[1] == first[1] and again[1] is not first[1]
    assert first[0].n_regions == layout.n_regions
    import shutil

    shutil.rmtree(path)
    other = tasks.spectra_layout(["3d"], ["overturning"], ["m0"], [0.2], [1.0, 2.0, 3.0], 1)
    store.create_store(path, other, {"tolerances": {"name": "fast"},
                                     "quantity": Quantity().to_dict(), "search_options": {},
                                     "ensemble": tasks.ensemble_attrs(ensemble, "test")}, "d2")
    assert tasks.store_metadata(path)[0].n_regions == other.n_regions == 3


def test_the_driver_of_a_fill_opens_its_store_once(tmp_path, monkeypatch):
    """fill_store works on the handle it is given: besides the task bodies (which take the
    path and write their regions), nothing reopens the store; the handle refuses to repair
    when opened read-only."""
    import traceback

    import zarr

    path, ensemble, layout = _spectra_store(tmp_path)
    opened = []
    real = zarr.open_group

    def counting(*args, **kwargs):
        in_task = any(f.name == "fill_spectra_region" for f in traceback.extract_stack())
        opened.append("task" if in_task else "driver")
        return real(*args, **kwargs)

    monkeypatch.setattr(zarr, "open_group", counting)
    handle = store.StoreHandle.open(path, "r+")
    assert opened == ["driver"]
    fn = partial(tasks.fill_spectra_region, batch=standin.batch)
    summary = cluster.fill_store(handle, fn, ensemble, config_digest="d1",
                                 in_process_analyses=10**6)
    assert summary["computed"] == layout.n_regions
    assert opened.count("driver") == 1  # the handle's own opening, before the fill
    assert opened.count("task") >= layout.n_regions  # each region written through its path
    with pytest.raises(ValueError, match="open read-only: open it with mode 'r\\+'"):
        integrity.verify_store(store.StoreHandle.open(path))
