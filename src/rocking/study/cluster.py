"""Dask for the workflow: which cluster to use, and running store regions on it.

By default a run starts an embedded :class:`distributed.LocalCluster` of worker *processes*
(one thread each: the kernels are compiled numba code that holds the GIL), with its dashboard
on a free port. A run can instead join a cluster that is already running, named by
``scheduler_address`` or ``scheduler_file`` (from the configuration) or by the
``DASK_SCHEDULER_ADDRESS`` environment variable, in that order of precedence.

Progress is reported in points (one spectrum point: a search for all limit states; one tilt
map point: one analysis) done / total, with the rate and the time left, in the rule's log and
on the terminal Snakemake runs in (a live bar there when it is a TTY), with the Dask
dashboard address once at the start, and a line at every ``progress_interval`` even when no
point finished (a stalled run is told from a slow one). A cluster without workers, at the
start or later (the only worker died), is waited for ``worker_timeout`` seconds, then the
run stops with one line that says so; finished chunks stay in the store.

Compilation is paid once per machine: the kernels are numba functions cached on disk
(``cache=True``), so :func:`warm_numba_cache` run once before any worker starts (the
workflow's first step) compiles them, and every later process, worker or rule loads them
from the cache instead of compiling its own copy.
"""

from __future__ import annotations

import contextlib
import logging
import os
import sys
import time
import traceback
import warnings
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from distributed import Client, LocalCluster, wait

from .._progress import Progress

log = logging.getLogger("rocking.study.cluster")

DEFAULT_WORKER_TIMEOUT = 60.0
"""Seconds to wait for a first worker of a joined cluster that has none [s]."""

_terminal: list = []  # the stream the user sees while output is sent to a log (log_to)


def terminal():
    """The user's terminal (stderr before :func:`log_to` redirected it), else stderr."""
    return _terminal[-1] if _terminal else sys.stderr

ENV_ADDRESS = "DASK_SCHEDULER_ADDRESS"
"""Environment variable naming an existing scheduler (``tcp://host:port``)."""


@dataclass(frozen=True)
class Target:
    """Where the tasks run.

    Attributes
    ----------
    kind : str
        ``"local"`` (embedded LocalCluster), ``"address"`` or ``"scheduler_file"``.
    value : str
        Scheduler address or scheduler-file path; empty for ``"local"``.
    """

    kind: str
    value: str = ""


def resolve_target(scheduler_address: str | None = None, scheduler_file: str | None = None,
                   environ: Mapping[str, str] | None = None) -> Target:
    """Choose the cluster: config address, then config scheduler file, then environment.

    Parameters
    ----------
    scheduler_address : str, optional
        ``tcp://host:port`` of a running ``dask scheduler``.
    scheduler_file : str, optional
        JSON file written by ``dask scheduler --scheduler-file`` (or ``SLURMCluster``).
    environ : mapping, optional
        Environment to read ``DASK_SCHEDULER_ADDRESS`` from (default ``os.environ``).

    Returns
    -------
    Target

    Raises
    ------
    ValueError
        If both are given, or the scheduler file does not exist.
    """
    environ = os.environ if environ is None else environ
    if scheduler_address and scheduler_file:
        raise ValueError(
            f"give dask.scheduler_address or dask.scheduler_file, not both; got "
            f"scheduler_address={scheduler_address!r}, scheduler_file={scheduler_file!r}"
        )
    if scheduler_address:
        return Target("address", str(scheduler_address))
    if scheduler_file:
        path = Path(scheduler_file).expanduser()
        if not path.is_file():
            raise ValueError(f"dask.scheduler_file {scheduler_file!r} does not exist")
        return Target("scheduler_file", str(path))
    env = environ.get(ENV_ADDRESS, "").strip()
    if env:
        return Target("address", env)
    return Target("local")


@contextlib.contextmanager
def dask_client(target: Target, n_workers: int = 1, *,
                local_directory: str | None = None,
                worker_timeout: float = DEFAULT_WORKER_TIMEOUT,
                say=None) -> Iterator[Client]:
    """A client on ``target``; a LocalCluster is started and stopped around the block.

    Parameters
    ----------
    target : Target
        From :func:`resolve_target`.
    n_workers : int
        Worker processes of an embedded LocalCluster (the rule's threads); ignored when
        joining an existing cluster.
    local_directory : str, optional
        Scratch space of embedded workers.
    worker_timeout : float
        Seconds to wait for a worker when a joined cluster has none [s].
    say : callable, optional
        Where the cluster and dashboard lines go (default: the log).

    Yields
    ------
    distributed.Client

    Raises
    ------
    RuntimeError
        When a joined cluster still has no worker after ``worker_timeout`` seconds.
    """
    say = say or log.info
    if n_workers < 1:
        raise ValueError(f"n_workers must be >= 1, got {n_workers!r}")
    if target.kind == "local":
        with warnings.catch_warnings():
            # distributed warns when ":0" picks a port other than its default 8787; that is
            # the point of ":0" (several runs on one machine never clash)
            warnings.simplefilter("ignore", UserWarning)
            cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                                   dashboard_address=":0", scheduler_port=0,
                                   local_directory=local_directory,
                                   silence_logs=logging.WARNING)
        try:
            with Client(cluster) as client:
                say(f"embedded Dask LocalCluster: {n_workers} worker processes, 1 thread "
                    f"each; dashboard: {client.dashboard_link}")
                yield client
        finally:
            cluster.close()
        return
    if target.kind == "address":
        client = Client(target.value, timeout="30s")
    elif target.kind == "scheduler_file":
        client = Client(scheduler_file=target.value, timeout="30s")
    else:
        raise ValueError(f"target.kind must be local, address or scheduler_file, "
                         f"got {target.kind!r}")
    with client:
        address = client.scheduler.address
        n = len(client.scheduler_info().get("workers", {}))
        say(f"joined Dask scheduler {address} with {n} workers; dashboard: "
            f"{client.dashboard_link}")
        if n == 0:
            _wait_for_a_worker(client, address, worker_timeout, say)
        yield client


def _wait_for_a_worker(client: Client, address: str, timeout: float, say) -> None:
    say(f"scheduler {address} has no workers: waiting up to {timeout:g} s "
        f"(dask.worker_timeout) for one to join")
    try:
        client.wait_for_workers(1, timeout=timeout)
    except (TimeoutError, OSError):
        raise RuntimeError(
            f"no Dask worker joined scheduler {address} within {timeout:g} s "
            f"(dask.worker_timeout); start some, e.g. `dask worker {address} --nthreads 1`"
        ) from None
    say(f"a worker joined scheduler {address}")


WARM_R = 1.0
"""Size of the warm-up cylinder [m] (tan α 0.2): small enough to rock, tail and overturn
under :func:`_warm_motion` within a few analyses."""


def _warm_motion():
    """2 s of two half-sine pulses at 100 Hz: a cheap motion under which a search meets
    rest, rocking, the free tail after the record and overturning."""
    import numpy as np

    from ..motions.motion import GroundMotion

    t = np.arange(201) * 0.01
    pulse = np.where(t < 1.0, np.sin(np.pi * t), 0.0)
    return GroundMotion(3.0 * pulse, 2.0 * np.roll(pulse, 50), 0.01, "warm-up")


def _warm_mode(mode: str) -> float:
    """One cheap search of ``mode`` (compiles or loads its kernels); seconds it took [s]."""
    from ..dynamics.bodies import Cylinder
    from ..spectra.critical import critical_intensity

    t0 = time.perf_counter()
    critical_intensity(Cylinder(WARM_R, 0.2), _warm_motion(), ["tilt:0.5", "overturning"],
                       mode, accuracy="fast", upper=8.0)
    return time.perf_counter() - t0


def warm_numba_cache(modes: Sequence[str] | None = None, processes: int = 1) -> dict[str, float]:
    """Compile the kernels of ``modes``, or load them from numba's cache.

    One critical-intensity search per mode on a 2 s motion runs every kernel a study's
    tasks call (the search's summary-only analyses, stop at a tilt, free tail, overturning).
    Compiled code is written to numba's on-disk cache, so processes started afterwards on
    this machine (Dask workers, other rules) load it in about a second instead of compiling
    for 10–20 s each, and each kernel is compiled once instead of once per process.

    Parameters
    ----------
    modes : sequence of str, optional
        Modes of :data:`rocking.spectra.critical.MODES` (default all).
    processes : int
        Compile the dynamics models (3d, 3d-damped, 2d) in up to this many fresh processes
        at once (1: one after the other in this process). The models share few kernels, so
        on an empty cache the wall time falls from their sum towards the slowest one.

    Returns
    -------
    dict
        Seconds per mode [s]: compilation on an empty cache, loading on a warm one.
    """
    from ..spectra.critical import MODES

    modes = list(dict.fromkeys(MODES if modes is None else modes))
    if processes < 1:
        raise ValueError(f"processes must be >= 1, got {processes!r}")
    # one representative mode per dynamics model first (2d-x and 2d-y share a kernel)
    first = list({MODES[m][0]: m for m in reversed(modes)}.values())[::-1]
    seconds: dict[str, float] = {}
    if processes > 1 and len(first) > 1:
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        ctx = multiprocessing.get_context("spawn")  # fresh interpreters, nothing inherited
        with ProcessPoolExecutor(min(processes, len(first)), mp_context=ctx) as pool:
            seconds.update(zip(first, pool.map(_warm_mode, first), strict=True))
    for mode in modes:  # in this process too: loads what the others compiled
        seconds[mode] = seconds.get(mode, 0.0) + _warm_mode(mode)
        log.info("numba kernels of mode %s ready in %.2f s", mode, seconds[mode])
    return seconds


def worker_pids(client: Client) -> dict[str, int]:
    """Process id of every worker (written to the log: a stuck worker can be found)."""
    return client.run(os.getpid)


def run_regions(client: Client, fn: Callable[..., dict], indices: Sequence[int],
                args: Sequence[Any] = (), kwargs: Mapping[str, Any] | None = None, *,
                key: str = "region", interval: float = 10.0,
                retries: int = 2, progress: Progress | None = None,
                worker_timeout: float = DEFAULT_WORKER_TIMEOUT) -> list[dict]:
    """Run ``fn(*args, index, **kwargs)`` for every region index on the cluster.

    Tasks are independent and idempotent (each writes whole chunks, then its done flag),
    so a task lost with a worker is simply run again elsewhere.

    Parameters
    ----------
    client : distributed.Client
    fn : callable
        Importable task body, e.g. :func:`rocking.study.store.fill_spectra_region`.
    indices : sequence of int
        Regions to compute, in order of priority (first = started first).
    args, kwargs
        Further arguments; ``args`` come before the index.
    key : str
        Prefix of the task keys (shown on the dashboard).
    interval : float
        Seconds between progress lines [s], written whether or not a chunk finished (a
        heartbeat: a stalled run is told from a slow one); the last line is always written.
    retries : int
        Extra attempts of a task that raised (not counting worker losses, which the
        scheduler reschedules on its own).
    progress : Progress, optional
        Advanced by each task's ``points`` as it finishes (None: only the log's chunk lines).
    worker_timeout : float
        Seconds the cluster may have no worker at all while chunks are left [s]; then the
        run stops (finished chunks stay in the store).

    Returns
    -------
    list of dict
        What each task returned, in completion order.

    Raises
    ------
    RuntimeError
        Naming the region, when a task fails after its retries; or, in one line, when the
        cluster had no worker for longer than ``worker_timeout``.
    """
    kwargs = dict(kwargs or {})
    n = len(indices)
    if n == 0:
        log.info("0/0 chunks: nothing to do")
        return []
    # the first index gets the highest priority: callers pass the costliest regions first
    futures = {
        client.submit(fn, *args, i, **kwargs, key=f"{key}-{i}", pure=False,
                      retries=retries, priority=n - rank): i
        for rank, i in enumerate(indices)
    }
    log.info("submitted %d chunks", n)
    t0 = last = time.monotonic()
    reports: list[dict] = []
    pending = set(futures)
    watch = _WorkerWatch(client, worker_timeout, n)
    poll = min(max(interval, 0.1), 1.0)  # seconds between looks at the cluster
    while pending:
        try:
            done, pending = wait(pending, timeout=poll, return_when="FIRST_COMPLETED")
        except TimeoutError:
            done = set()
        for future in done:
            try:
                reports.append(future.result())
            except Exception as exc:
                for f in futures:
                    f.cancel()
                raise RuntimeError(f"chunk {key}-{futures[future]} failed: {exc}") from exc
            if progress is not None:
                progress.update(int(reports[-1].get("points", 1)))
        now = time.monotonic()
        if pending:
            watch.check(now, len(pending), futures)
        # a heartbeat at every interval, also when no chunk finished: a stalled run is seen
        if (now - last >= interval and (done or interval > 0)) or not pending:
            log.info("%d/%d chunks done, %.1f s elapsed, %d workers", len(reports), n,
                     now - t0, watch.workers)
            if progress is not None:
                progress.update(0)
            last = now
    return reports


class _WorkerWatch:
    """Counts the cluster's workers; raises when there were none for too long."""

    def __init__(self, client: Client, timeout: float, n: int) -> None:
        self.client, self.timeout, self.n = client, float(timeout), n
        self.workers = -1
        self._none_since: float | None = None

    def check(self, now: float, left: int, futures: Mapping) -> None:
        self.workers = len(self.client.nthreads())
        if self.workers:
            self._none_since = None
            return
        if self._none_since is None:
            self._none_since = now
            log.warning("the Dask cluster has no workers; %d of %d chunks left, waiting up to "
                        "%g s (dask.worker_timeout)", left, self.n, self.timeout)
        elif now - self._none_since > self.timeout:
            for f in futures:
                f.cancel()
            address = self.client.scheduler.address
            raise RuntimeError(
                f"no Dask worker on scheduler {address} for {now - self._none_since:.0f} s "
                f"(dask.worker_timeout {self.timeout:g} s) with {left} of {self.n} chunks left; "
                f"start workers (`dask worker {address} --nthreads 1`) and run again, "
                f"finished chunks are kept")


@contextlib.contextmanager
def heartbeat(say: Callable[[str], None], interval: float, what: str) -> Iterator[list]:
    """Say ``"<what>: still working (<stage>), elapsed <s> s"`` every ``interval`` seconds
    while the block runs (a long step without progress of its own, e.g. an ensemble's
    synthesis, is told from a stalled one).

    Yields a one-element list: the block puts the current stage in it (``stage[0] = ...``).
    ``interval`` <= 0 says nothing.
    """
    import threading

    stage = ["starting"]
    stop = threading.Event()
    t0 = time.monotonic()

    def beat() -> None:
        while not stop.wait(interval):
            say(f"{what}: still working ({stage[0]}), elapsed {time.monotonic() - t0:.0f} s")

    thread = threading.Thread(target=beat, daemon=True) if interval > 0 else None
    if thread is not None:
        thread.start()
    try:
        yield stage
    finally:
        stop.set()
        if thread is not None:
            thread.join()


@contextlib.contextmanager
def log_to(path: str | Path, level: int = logging.INFO) -> Iterator[None]:
    """Send this process's and its children's output (stdout, stderr, logging) to ``path``.

    Both the Python streams and the file descriptors 1 and 2 are redirected, so worker
    processes started inside the block (a LocalCluster) write there too. The terminal stays
    reachable through :func:`terminal` (progress goes there as well as to the log). An
    exception leaving the block is written to the log with its traceback, then re-raised:
    the log Snakemake points to says what went wrong.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    sys.stdout.flush()
    sys.stderr.flush()
    saved_fds = os.dup(1), os.dup(2)
    saved_streams = sys.stdout, sys.stderr
    fh = open(path, "a", buffering=1)  # noqa: SIM115 - closed in finally
    os.dup2(fh.fileno(), 1)
    os.dup2(fh.fileno(), 2)
    sys.stdout = sys.stderr = fh
    handler = logging.StreamHandler(fh)
    handler.setFormatter(logging.Formatter("%(asctime)s %(name)s %(levelname)s %(message)s"))
    root = logging.getLogger()
    old_level = root.level
    root.addHandler(handler)
    root.setLevel(level)
    _terminal.append(os.fdopen(os.dup(saved_fds[1]), "w", buffering=1))
    try:
        yield
    except BaseException as exc:
        fh.write("".join(traceback.format_exception(exc)))
        fh.write(f"error: {type(exc).__name__}: {exc}\n")
        raise
    finally:
        _terminal.pop().close()
        fh.flush()
        root.removeHandler(handler)
        root.setLevel(old_level)
        sys.stdout, sys.stderr = saved_streams
        os.dup2(saved_fds[0], 1)
        os.dup2(saved_fds[1], 2)
        os.close(saved_fds[0])
        os.close(saved_fds[1])
        fh.close()


def fill_store(path: str | Path, fn: Callable[..., dict], motions: str | Path, *,
               config_digest: str, n_workers: int = 1, scheduler_address: str | None = None,
               scheduler_file: str | None = None, progress_interval: float = 10.0,
               key: str = "region", worker_timeout: float = DEFAULT_WORKER_TIMEOUT,
               label: str | None = None) -> dict[str, Any]:
    """Verify the finished regions of a store, compute the others on Dask, consolidate it.

    Every finished region is re-read first (:func:`rocking.study.store.verify_store`):
    damaged ones (checksum mismatch, truncated or missing chunk, inconsistent values) are
    computed again, so ``snakemake --forcerun spectra`` repairs a damaged store.

    Parameters
    ----------
    path : str or Path
        A store made by :func:`rocking.study.store.create_store`.
    fn : callable
        Task body ``fn(path, index, motions=...)``, e.g.
        :func:`rocking.study.store.fill_spectra_region`.
    motions : str or Path
        Ensemble file of the store.
    config_digest : str
        Hash of this run's result-affecting configuration; must equal the store's.
    n_workers : int
        Worker processes of an embedded LocalCluster.
    scheduler_address, scheduler_file : str, optional
        An existing cluster (see :func:`resolve_target`).
    progress_interval : float
        Seconds between progress lines [s] (log, and terminal when it is not a TTY).
    key : str
        Task-key prefix.
    worker_timeout : float
        Seconds to wait for a first worker of a joined cluster without any, and the longest
        time the cluster may have no worker during the run [s].
    label : str, optional
        Name of the computation in progress lines (default ``key``).

    Returns
    -------
    dict
        Summary: regions in total, already done before this run, computed now, per-chunk
        compute seconds (min, median, max), wall seconds, where it ran.
    """
    from . import store

    t0 = time.perf_counter()
    # absolute paths: workers of an external cluster may run in another directory
    path, motions = Path(path).resolve(), Path(motions).resolve()
    store.check_config_hash(path, config_digest)
    store.check_ensemble(path, motions)
    layout = store.open_layout(path)
    # every run re-reads what earlier runs finished: damaged chunks become pending again
    damaged = store.verify_store(path, layout, say=log.warning)
    pending = store.costliest_first(layout, store.pending_regions(path, layout))
    n = layout.n_regions
    log.info("store %s: %d chunks, %d already done and verified, %d damaged, %d to compute",
             path, n, n - len(pending), len(damaged), len(pending))
    target = resolve_target(scheduler_address, scheduler_file)
    reports: list[dict] = []
    if pending:
        total = sum(store.region_points(layout, i) for i in pending)
        with Progress(total, label or key, stream=terminal(), log=log,
                      interval=progress_interval) as bar:
            bar.message(f"{label or key}: {total} points in {len(pending)} chunks to compute "
                        f"({n - len(pending)} of {n} chunks already done)")
            with dask_client(target, n_workers, worker_timeout=worker_timeout,
                             say=bar.message) as client:
                log.info("worker pids: %s", sorted(worker_pids(client).values()))
                reports = run_regions(client, fn, pending, (str(path),),
                                      {"motions": str(motions)},
                                      key=f"{key}-{config_digest}",
                                      interval=progress_interval, progress=bar,
                                      worker_timeout=worker_timeout)
    store.finalize(path)
    seconds = sorted(r["seconds"] for r in reports)
    summary = {
        "store": str(path),
        "config_hash": config_digest,
        "cluster": target.kind,
        "chunks": n,
        "done_before": n - len(pending),
        "damaged": len(damaged),
        "computed": len(reports),
        "points_computed": int(sum(r["points"] for r in reports)),
        "chunk_seconds": {"min": seconds[0], "median": seconds[len(seconds) // 2],
                          "max": seconds[-1]} if seconds else None,
        "wall_seconds": time.perf_counter() - t0,
    }
    log.info("finished: %s", summary)
    return summary
