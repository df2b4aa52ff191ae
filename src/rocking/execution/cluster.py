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

Compilation is paid once per machine (:mod:`rocking.execution.warmup`); a rule's output goes to
its log (:mod:`rocking.execution.logs`), progress also to the terminal.
"""

from __future__ import annotations

import contextlib
import logging
import os
import time
import warnings
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from distributed import Client, LocalCluster, wait

from rocking._progress import Progress
from rocking.execution.logs import terminal
from rocking.provenance import scratch_path

if TYPE_CHECKING:  # the store module loads zarr: only its type is needed here
    from rocking.store import StoreHandle

log = logging.getLogger("rocking.execution.cluster")

DEFAULT_WORKER_TIMEOUT = 60.0
"""Seconds to wait for a first worker of a joined cluster that has none [s]."""

ENV_ADDRESS = "DASK_SCHEDULER_ADDRESS"
"""Environment variable naming an existing scheduler (``tcp://host:port``)."""


def dask_options(config: Mapping[str, Any]) -> dict[str, Any]:
    """The keyword arguments of :func:`fill_store` set by a workflow configuration's ``dask``
    section (``scheduler_address``, ``scheduler_file``, ``progress_interval`` [s],
    ``worker_timeout`` [s]).

    None of them can change a number of a store, so the compute rules read them from the
    configuration inside their script, never as rule ``params``: Snakemake reruns a rule
    whose params changed, and a new progress interval must not recompute a study.
    """
    d = config["dask"]
    return {"scheduler_address": d["scheduler_address"], "scheduler_file": d["scheduler_file"],
            "dashboard_address": d.get("dashboard_address", DASHBOARD_ADDRESS),
            "progress_interval": float(d["progress_interval"]),
            "worker_timeout": float(d["worker_timeout"]),
            "in_process_analyses": IN_PROCESS_ANALYSES}


DASHBOARD_ADDRESS = "127.0.0.1:0"
"""Where an embedded cluster's dashboard listens by default: the loopback interface only (it
has no login; reach it from elsewhere through an SSH tunnel), on a free port (several runs
on one machine never clash). ``dask.dashboard_address`` changes it; null: no dashboard."""


def dashboard_url(cluster) -> str | None:
    """``http://<host>:<port>/status`` of the dashboard ``cluster``'s scheduler actually
    listens on (host as bound: 127.0.0.1, or 0.0.0.0 for every interface), or None."""
    server = getattr(cluster.scheduler, "http_server", None)
    sockets = getattr(server, "_sockets", {}) if server is not None else {}
    if "dashboard" not in getattr(cluster.scheduler, "services", {}) or not sockets:
        return None
    hosts = sorted({sock.getsockname()[0] for sock in sockets.values()})
    port = next(iter(sockets.values())).getsockname()[1]
    host = hosts[0] if len(hosts) == 1 else "+".join(hosts)
    return f"http://{host}:{port}/status"


IN_PROCESS_ANALYSES = 400
"""Analyses (estimated) up to which a workflow rule without a cluster to join fills its store
in its own process instead of starting an embedded LocalCluster [-]. Starting one, loading the
kernels in each worker and closing it took 8–12 s of wall time on the 2-core machine (the
stripes rule of the paper run: 27 s, 14.6 s of them chunks on 2 workers), while 400
analyses take 2–6 s in one process (5–15 ms each): the default run's Fig 7 map (168
analyses) and stripes (120) run faster without Dask, the paper run's (1560 and 1320) do not."""

def estimated_analyses(layout, indices: Sequence[int], per_point: int = 1) -> int:
    """Analyses the regions ``indices`` are expected to run: ``per_point`` per point (a
    spectrum point is a search, :data:`rocking.execution.products.Product.analyses_per_point`;
    a tilt-map or stripe point one analysis)."""
    from rocking.store.layout import region_points

    return per_point * sum(region_points(layout, i) for i in indices)


@dataclass(frozen=True)
class Target:
    """Where the tasks run.

    Attributes
    ----------
    kind : str
        ``"local"`` (embedded LocalCluster), ``"address"`` or ``"scheduler_file"``; a
        summary of :func:`fill_store` says ``"in-process"`` where no cluster was started.
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
                dashboard_address: str | None = DASHBOARD_ADDRESS,
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
    dashboard_address : str or None
        ``host:port`` the embedded cluster's dashboard listens on (default
        :data:`DASHBOARD_ADDRESS`, loopback only); None, "" or "off": no dashboard.
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
            off = dashboard_address is None or str(dashboard_address).strip().lower() in (
                "", "off", "none", "false")
            # scheduler and workers on loopback; the dashboard where asked (loopback
            # by default: distributed's own default, ":0", is every interface)
            cluster = LocalCluster(n_workers=n_workers, threads_per_worker=1, processes=True,
                                   host="127.0.0.1", scheduler_port=0,
                                   dashboard_address=None if off else str(dashboard_address),
                                   local_directory=local_directory,
                                   silence_logs=logging.WARNING)
        try:
            with Client(cluster) as client:
                say(f"embedded Dask LocalCluster: {n_workers} worker processes, 1 thread "
                    f"each; dashboard: {'off' if off else dashboard_url(cluster)}"
                    + (f"; worker scratch space {local_directory}" if local_directory
                       else ""))
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
        check_workers(client)  # workers of another environment: said now, by name
        yield client


CHECKED_PACKAGES = ("rocking", "numpy", "numba")
"""Packages whose version a worker must share with the client: another ``rocking`` or a
numpy/numba that rounds or compiles differently could change a number."""

# The probe runs on workers that may lack rocking itself, so it must not be pickled as a
# reference to this module (cloudpickle sends functions of unimportable modules by value).
_PROBE_SOURCE = """
def probe(names):
    import importlib
    out = {}
    for name in names:
        try:
            out[name] = str(importlib.import_module(name).__version__)
        except Exception as exc:
            out[name] = "cannot import: %s: %s" % (type(exc).__name__, exc)
    return out
"""


def _probe():
    namespace: dict[str, Any] = {"__name__": "rocking_worker_probe"}
    exec(_PROBE_SOURCE, namespace)  # noqa: S102 - fixed source, see above
    return namespace["probe"]


def environment_problems(client_versions: Mapping[str, str],
                         workers: Mapping[str, Any]) -> list[str]:
    """What differs between the client's packages and each worker's.

    Parameters
    ----------
    client_versions : mapping
        Package → version of this process (the probe's answer here).
    workers : mapping
        Worker address → the probe's answer there, or the exception it raised.

    Returns
    -------
    list of str
        One phrase per worker and package ("cannot import rocking: ...", "numpy 2.0 where
        this run has 2.1"), empty when they all agree.
    """
    out = []
    for address, found in sorted(workers.items()):
        if isinstance(found, BaseException):
            out.append(f"worker {address} could not run a version check "
                       f"({type(found).__name__}: {found})")
            continue
        for name, want in client_versions.items():
            got = found.get(name)
            if isinstance(got, str) and got.startswith("cannot import: "):
                out.append(f"worker {address} cannot import {name} "
                           f"({got.removeprefix('cannot import: ')})")
            elif got != want:
                out.append(f"worker {address} has {name} {got!r} where this run has {want!r}")
    return out


def check_workers(client: Client, addresses: Sequence[str] | None = None) -> None:
    """Check that workers (all, or ``addresses``) import rocking, numpy and numba at the
    client's versions (:data:`CHECKED_PACKAGES`).

    Raises
    ------
    RuntimeError
        In one line naming each worker and what differs, and the remedy; a worker whose
        environment lacks the package is reported as such, not as "no worker".
    """
    probe = _probe()
    here = probe(CHECKED_PACKAGES)
    kw = {"workers": list(addresses)} if addresses is not None else {}
    if addresses is not None and not addresses:
        return
    there = client.run(probe, CHECKED_PACKAGES, on_error="return", **kw)
    problems = environment_problems(here, there)
    if problems:
        raise RuntimeError(f"Dask workers differ from this run's environment: "
                           f"{'; '.join(problems)}; start the workers from this run's "
                           f"environment (the same rocking, numpy and numba)")


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
        Importable task body, e.g. :func:`rocking.execution.tasks.fill_spectra_region`.
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
            if progress is not None and not done:  # a chunk that finished has said it
                progress.update(0)
            last = now
    return reports


class _WorkerWatch:
    """Counts the cluster's workers; raises when there were none for too long."""

    def __init__(self, client: Client, timeout: float, n: int) -> None:
        self.client, self.timeout, self.n = client, float(timeout), n
        self.workers = -1
        self._none_since: float | None = None
        self._seen = set(client.nthreads())  # checked when the client joined

    def check(self, now: float, left: int, futures: Mapping) -> None:
        current = set(self.client.nthreads())
        self.workers = len(current)
        joined = current - self._seen
        if joined:
            # a worker that joins later is checked too, before its results are trusted
            self._seen |= joined
            try:
                check_workers(self.client, sorted(joined))
            except RuntimeError:
                for f in futures:
                    f.cancel()
                raise
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


def run_in_process(fn: Callable[..., dict], indices: Sequence[int], path: str, motions: str,
                   progress: Progress | None = None) -> list[dict]:
    """``fn(path, index, motions=motions)`` for every region, in order, in this process.

    Raises
    ------
    RuntimeError
        Naming the region, when a task fails (as :func:`run_regions` does).
    """
    reports = []
    for i in indices:
        try:
            reports.append(fn(path, i, motions=motions))
        except Exception as exc:
            raise RuntimeError(f"chunk {i} failed: {exc}") from exc
        if progress is not None:
            progress.update(int(reports[-1].get("points", 1)))
    log.info("%d/%d chunks done in this process", len(reports), len(indices))
    return reports


@contextlib.contextmanager
def scratch_space(folder: str | Path) -> Iterator[str]:
    """A temporary folder ``.dask.scratch-*`` in ``folder`` (the run's output, beside the
    store) for embedded workers' spill and scratch files, removed when the block ends (or,
    after a kill, by the next run's): never /tmp/dask-scratch-space, shared by every user
    of the machine."""
    import shutil

    tmp = scratch_path(Path(folder) / "dask", "scratch")
    tmp.mkdir()
    try:
        yield str(tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def fill_store(store: StoreHandle, fn: Callable[..., dict], motions: str | Path, *,
               config_digest: str, n_workers: int = 1, scheduler_address: str | None = None,
               scheduler_file: str | None = None, progress_interval: float = 10.0,
               key: str = "region", worker_timeout: float = DEFAULT_WORKER_TIMEOUT,
               label: str | None = None, in_process_analyses: int = 0,
               analyses_per_point: int = 1,
               dashboard_address: str | None = DASHBOARD_ADDRESS) -> dict[str, Any]:
    """Verify the finished regions of a store, compute the others on Dask, consolidate it.

    Every finished region is re-read first (:func:`rocking.store.integrity.verify_store`):
    damaged ones (checksum mismatch, truncated or missing chunk, inconsistent values) are
    computed again, so ``snakemake --forcerun spectra`` repairs a damaged store.

    Parameters
    ----------
    store : StoreHandle
        A store made by :func:`rocking.store.create_store`, opened once with mode
        ``"r+"`` (:func:`rocking.store.integrity.open_checked`); the task bodies get its path.
    fn : callable
        Task body ``fn(path, index, motions=...)``, e.g.
        :func:`rocking.execution.tasks.fill_spectra_region`.
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
    in_process_analyses : int
        Without a cluster to join, regions expected to run at most this many analyses
        (:func:`estimated_analyses`) are computed one after the other in this process, with
        no cluster started (0: always a cluster; the workflow passes
        :data:`IN_PROCESS_ANALYSES`). The results are the same: the same task bodies run.
    analyses_per_point : int
        Analyses a point of the store costs, for that estimate (the product's
        :attr:`~rocking.execution.products.Product.analyses_per_point`).
    dashboard_address : str or None
        Where an embedded cluster's dashboard listens (:func:`dask_client`). Its workers'
        scratch space is a temporary folder beside the store (under the run's output),
        removed afterwards.

    Returns
    -------
    dict
        Summary: regions in total, already done before this run, computed now, per-chunk
        compute seconds (min, median, max), wall seconds, where it ran.
    """
    from rocking.execution import tasks
    from rocking.store import integrity
    from rocking.store.layout import region_points

    t0 = time.perf_counter()
    # absolute paths: workers of an external cluster may run in another directory
    path, motions = store.path.resolve(), Path(motions).resolve()
    store.check_config_hash(config_digest)
    tasks.check_ensemble(store, motions)
    layout = store.layout
    # every run re-reads what earlier runs finished: damaged chunks become pending again
    damaged = integrity.verify_store(store, say=log.warning)
    pending = tasks.costliest_first(layout, store.pending_regions())
    n = layout.n_regions
    log.info("store %s: %d chunks, %d already done and verified, %d damaged, %d to compute",
             path, n, n - len(pending), len(damaged), len(pending))
    target = resolve_target(scheduler_address, scheduler_file)
    reports: list[dict] = []
    if pending:
        total = sum(region_points(layout, i) for i in pending)
        with Progress(total, label or key, stream=terminal(), log=log,
                      interval=progress_interval) as bar:
            bar.message(f"{label or key}: {total} points in {len(pending)} chunks to compute "
                        f"({n - len(pending)} of {n} chunks already done)")
            work = estimated_analyses(layout, pending, analyses_per_point)
            if target.kind == "local" and work <= in_process_analyses:
                bar.message(f"{label or key}: about {work} analyses, computed in this "
                            f"process (starting a Dask cluster would cost more)")
                reports = run_in_process(fn, pending, str(path), str(motions), bar)
                target = Target("in-process")
            else:
                with scratch_space(path.parent) as scratch, \
                        dask_client(target, n_workers, worker_timeout=worker_timeout,
                                    dashboard_address=dashboard_address,
                                    local_directory=scratch, say=bar.message) as client:
                    log.info("worker pids: %s", sorted(worker_pids(client).values()))
                    reports = run_regions(client, fn, pending, (str(path),),
                                          {"motions": str(motions)},
                                          key=f"{key}-{config_digest}",
                                          interval=progress_interval, progress=bar,
                                          worker_timeout=worker_timeout)
    store.finalize()
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
