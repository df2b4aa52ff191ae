"""Dask machinery: choosing the cluster, filling a store on worker processes, failures.

One embedded LocalCluster of two worker processes is started for the module; the engine is a
closed-form stand-in (tests/_store_standins.py) shipped to the workers by value.
"""

from __future__ import annotations

import logging
import os
import subprocess
import sys
from functools import partial

import _store_standins as standin
import cloudpickle
import numpy as np
import pytest
import xarray as xr

from rocking import store
from rocking.execution import cluster, logs, tasks
from rocking.motions.ensemble_io import save_ensemble
from rocking.spectra.quantity import Quantity

# the workers cannot import the tests folder: send the stand-ins' code along
cloudpickle.register_pickle_by_value(standin)


def test_target_precedence_config_then_file_then_environment(tmp_path):
    sched = tmp_path / "scheduler.json"
    sched.write_text("{}")
    env = {cluster.ENV_ADDRESS: "tcp://10.0.0.1:8786"}
    assert cluster.resolve_target(environ={}) == cluster.Target("local")
    assert cluster.resolve_target(environ=env) == cluster.Target("address", "tcp://10.0.0.1:8786")
    assert cluster.resolve_target(scheduler_file=str(sched), environ=env) == \
        cluster.Target("scheduler_file", str(sched))
    assert cluster.resolve_target("tcp://127.0.0.1:1", environ=env) == \
        cluster.Target("address", "tcp://127.0.0.1:1")
    with pytest.raises(ValueError, match="scheduler_address='tcp://a:1'.*scheduler_file="):
        cluster.resolve_target("tcp://a:1", str(sched))
    with pytest.raises(ValueError, match="dask.scheduler_file '/nonexistent.json' does not"):
        cluster.resolve_target(scheduler_file="/nonexistent.json")
    with pytest.raises(ValueError, match="n_workers must be >= 1, got 0"):
        with cluster.dask_client(cluster.Target("local"), 0):
            pass


def _spectra_store(tmp_path, name="s.zarr", digest="d1"):
    ensemble = tmp_path / "motions.nc"
    if not ensemble.exists():
        save_ensemble(ensemble, standin.motions())
    layout = tasks.spectra_layout(["3d", "2d-y"], ["overturning", "tilt:0.5"], ["m0", "m1"],
                                  [0.2], [1.0, 2.0, 3.0, 9.0], 2)
    attrs = {"tolerances": {"name": "fast"}, "quantity": Quantity().to_dict(),
             "search_options": {},
             "ensemble": tasks.ensemble_attrs(ensemble, "test")}
    store.create_store(tmp_path / name, layout, attrs, digest)
    return tmp_path / name, ensemble, layout


def _values(path):
    ds = xr.open_zarr(path, consolidated=False)
    return {k: ds[k].values.view(np.uint8).tobytes() for k in ds.data_vars}


def test_store_filled_by_worker_processes_equals_serial_fill(tmp_path, caplog):
    path, ensemble, layout = _spectra_store(tmp_path)
    serial, _, _ = _spectra_store(tmp_path, "serial.zarr")
    for i in range(layout.n_regions):
        tasks.fill_spectra_region(serial, i, ensemble, batch=standin.batch)
    fn = partial(tasks.fill_spectra_region, batch=standin.batch)
    with caplog.at_level(logging.INFO, logger="rocking.execution.cluster"):
        summary = cluster.fill_store(store.StoreHandle.open(path, "r+"), fn, ensemble,
                                     config_digest="d1", n_workers=2,
                                     progress_interval=0.0, scheduler_address=None)
    assert summary["cluster"] == "local"
    assert summary["chunks"] == layout.n_regions == 8
    assert summary["computed"] == 8 and summary["done_before"] == 0
    assert summary["points_computed"] == 16
    text = caplog.text
    assert "8/8 chunks done" in text
    assert "dashboard: http://" in text
    pids = [int(p) for p in text.split("worker pids: [")[1].split("]")[0].split(",")]
    assert len(set(pids)) == 2 and os.getpid() not in pids  # real separate processes
    assert _values(path) == _values(serial)
    assert (path / "zarr.json").read_text().count("consolidated_metadata") == 1
    # a second run finds every chunk done and starts no cluster at all
    again = cluster.fill_store(store.StoreHandle.open(path, "r+"), fn, ensemble,
                               config_digest="d1", n_workers=2)
    assert again["computed"] == 0 and again["done_before"] == 8
    with pytest.raises(ValueError, match="config_hash='d1'.*config_hash='other'"):
        cluster.fill_store(store.StoreHandle.open(path, "r+"), fn, ensemble, config_digest="other")


def test_failing_chunk_is_reported_by_name(tmp_path):
    path, ensemble, layout = _spectra_store(tmp_path)
    fn = partial(tasks.fill_spectra_region, batch=standin.failing_batch)
    with cluster.dask_client(cluster.Target("local"), 1) as client:
        with pytest.raises(RuntimeError, match=r"chunk spectra-0 failed: stand-in failure"):
            cluster.run_regions(client, fn, [0], (str(path),), {"motions": str(ensemble)},
                                key="spectra", retries=0)
    # region 0 holds R = 1, 2: it failed, so it is still pending; nothing else was touched
    assert store.pending_regions(path) == list(range(layout.n_regions))


def test_log_to_captures_this_and_child_processes(tmp_path):
    log = tmp_path / "logs" / "rule.log"
    with logs.log_to(log):
        print("from the parent", flush=True)
        logging.getLogger("rocking.execution.cluster").info("a log record")
        subprocess.run([sys.executable, "-c", "import sys; sys.stderr.write('from a child\\n')"],
                       check=True)
    text = log.read_text()
    assert "from the parent" in text and "from a child" in text and "a log record" in text


def test_scheduler_without_workers_is_reported_then_given_up(caplog):
    from distributed import LocalCluster

    with LocalCluster(n_workers=0, scheduler_port=0, dashboard_address=":0",
                      processes=False) as empty:
        said = []
        with pytest.raises(RuntimeError, match=r"no Dask worker joined scheduler "
                           r"\S+ within 1 s \(dask.worker_timeout\)"):
            with cluster.dask_client(cluster.Target("address", empty.scheduler_address),
                                     worker_timeout=1.0, say=said.append):
                pass
    assert "with 0 workers" in said[0] and "dashboard:" in said[0]
    assert "has no workers: waiting up to 1 s" in said[1]


def _slow_point(index):
    import time

    time.sleep(0.2)
    return {"index": index, "points": 1, "seconds": 0.2}


def test_cluster_without_workers_mid_run_fails_within_the_timeout_with_heartbeats(caplog):
    """An external scheduler whose workers are gone: heartbeat lines at every interval though
    no chunk finishes, then one error line once worker_timeout has passed."""
    import time

    from distributed import Client, LocalCluster

    from rocking._progress import Progress

    caplog.set_level(logging.INFO, logger="rocking.execution.cluster")
    with LocalCluster(n_workers=0, scheduler_port=0, dashboard_address=":0",
                      processes=False) as empty, Client(empty.scheduler_address) as client:
        lines = []

        class Stream:
            def write(self, text):
                lines.append(text)

            def flush(self):
                pass

        t0 = time.monotonic()
        with pytest.raises(RuntimeError, match=r"^no Dask worker on scheduler \S+ for \d+ s "
                           r"\(dask.worker_timeout 2 s\) with 3 of 3 chunks left"), \
                Progress(3, "stalled", stream=Stream(), interval=0.5) as bar:
            cluster.run_regions(client, _slow_point, [0, 1, 2], interval=0.5,
                                worker_timeout=2.0, progress=bar)
        elapsed = time.monotonic() - t0
    assert 2.0 < elapsed < 2.0 + 3.0
    beats = [r.getMessage() for r in caplog.records if "chunks done" in r.getMessage()]
    assert len(beats) >= 3 and all(b.startswith("0/3 chunks done") for b in beats)
    assert sum("stalled: 0/3 points done" in x for x in lines) >= 3


def test_heartbeat_speaks_while_a_long_step_runs():
    import time

    said = []
    with logs.heartbeat(said.append, 0.2, "building e") as stage:
        stage[0] = "synthesis"
        time.sleep(0.9)
    n = len(said)
    time.sleep(0.4)
    assert n >= 3 and len(said) == n  # lines while it ran, none after
    assert said[0].startswith("building e: still working (synthesis), elapsed 0 s")
