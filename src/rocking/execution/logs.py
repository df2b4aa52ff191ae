"""A job's output sent to its log file: stdout, stderr, logging, and worker processes too.

One block for every workflow script (compute, figure and report jobs): :func:`job`, the log
redirector :func:`log_to` with the provenance of the job's files (every input checked, every
output recorded: :mod:`rocking.provenance`). The terminal stays reachable (:func:`terminal`)
for progress; :func:`heartbeat` says a long step is still working.
"""

from __future__ import annotations

import contextlib
import logging
import os
import sys
import time
import traceback
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path

_terminal: list = []  # the stream the user sees while output is sent to a log (log_to)


def terminal():
    """The user's terminal (stderr before :func:`log_to` redirected it), else stderr."""
    return _terminal[-1] if _terminal else sys.stderr


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
def log_to(path: str | Path, level: int = logging.INFO, *,
           outputs: Sequence[str | Path] | None = None) -> Iterator[None]:
    """Send this process's and its children's output (stdout, stderr, logging) to ``path``.

    Both the Python streams and the file descriptors 1 and 2 are redirected, so worker
    processes started inside the block (a LocalCluster) write there too. The terminal stays
    reachable through :func:`terminal` (progress goes there as well as to the log). An
    exception leaving the block is written to the log with its traceback, then re-raised:
    the log Snakemake points to says what went wrong. An error of known cause
    (:func:`one_line_error`: a full disk, a damaged or foreign derived file) is said in one
    line on the terminal and in the log, and ends the job with exit status 1 (SystemExit),
    without a traceback on the terminal. ``outputs``: the job's output files, named by a
    full disk's line when the error does not say which file (PIL, HDF5).
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
    line = None
    try:
        yield
    except BaseException as exc:
        line = one_line_error(exc, _written(outputs) or path)
        with contextlib.suppress(OSError):  # a full disk: the log cannot take it either
            fh.write("".join(traceback.format_exception(exc)))
            fh.write(f"error: {line or f'{type(exc).__name__}: {exc}'}\n")
        if line is None:
            raise
        with contextlib.suppress(OSError):  # said where the user sees it, in one line
            _terminal[-1].write(f"error: {line}\n")
    finally:
        with contextlib.suppress(OSError):
            _terminal.pop().close()
        with contextlib.suppress(OSError):
            fh.flush()
        root.removeHandler(handler)
        root.setLevel(old_level)
        sys.stdout, sys.stderr = saved_streams
        os.dup2(saved_fds[0], 1)
        os.dup2(saved_fds[1], 2)
        os.close(saved_fds[0])
        os.close(saved_fds[1])
        with contextlib.suppress(OSError):
            fh.close()
    if line is not None:
        raise SystemExit(1)


ORDERING_ONLY = ("numba",)
"""Inputs a rule takes for their order alone (the compiled kernels, ``ancient()``): not
recorded, so that compiling them again remakes nothing."""


@contextlib.contextmanager
def job(snakemake, level: int = logging.INFO) -> Iterator[None]:
    """The block of a workflow script: its output to its log (:func:`log_to`), every input
    checked against its record before the block (a derived file edited, cut short or made
    from other inputs stops the job in one line naming it), every output recorded after it
    (what made it: the job's inputs, its other outputs, the digest of its parameters; paths
    under the output root written relative to it). ``snakemake``: the script's object."""
    from rocking import provenance

    skip = {f for name in ORDERING_ONLY for f in _files(getattr(snakemake.input, name, []))}
    inputs = [f for f in snakemake.input if f not in skip]
    outputs = list(snakemake.output)
    with log_to(snakemake.log[0], level, outputs=outputs):
        for f in inputs:
            provenance.check(f)
        yield
        settings = provenance.settings_digest(dict(snakemake.params.items()),
                                              snakemake.config.get("output"))
        for f in outputs:
            provenance.record(f, inputs=inputs, together=outputs, settings=settings,
                              rule=snakemake.rule)


def _files(value) -> list[str]:
    return [value] if isinstance(value, str) else [str(v) for v in value]


def _written(outputs: Sequence[str | Path] | None) -> str | None:
    """The one output file, or the folder common to several (None: none given)."""
    files = [str(f) for f in (outputs or [])]
    if not files:
        return None
    if len(files) == 1:
        return files[0]
    return os.path.commonpath([os.path.abspath(f) for f in files])


NEARLY_FULL = 1 << 20
"""Free bytes below which a failed write is put down to a full disk [B]: libraries that wrap
the operating system's error (netCDF/HDF5: "HDF error") do not say ENOSPC themselves."""


def one_line_error(exc: BaseException, near: str | Path) -> str | None:
    """The one line a job's error is said in, for the errors whose cause is known, else None
    (then the traceback is kept): a derived file damaged or of another study
    (:class:`rocking.provenance.ProvenanceError`, naming the file and the way out), a full
    disk (``no space left on <path>``: the file the error names, else ``near``, the job's
    output)."""
    import errno

    from rocking.provenance import ProvenanceError

    if isinstance(exc, ProvenanceError):
        return str(exc)
    seen, e = set(), exc
    while e is not None and id(e) not in seen:  # ENOSPC anywhere in the chain
        seen.add(id(e))
        if isinstance(e, OSError) and e.errno == errno.ENOSPC:
            where = e.filename or near
            return f"no space left on {where}: free space there and run again (nothing " \
                   f"half-written was kept)"
        e = e.__cause__ or e.__context__
    if isinstance(exc, Exception) and not isinstance(exc, KeyboardInterrupt):
        where = mount_point(near)
        try:
            free = __import__("shutil").disk_usage(where).free
        except OSError:
            return None
        if free < NEARLY_FULL:
            return (f"no space left on {near} ({free} bytes free on {where}; the error: "
                    f"{type(exc).__name__}: {str(exc).splitlines()[0][:120] if str(exc) else ''}"
                    f"): free space there and run again (nothing half-written was kept)")
    return None


def mount_point(path: str | Path) -> str:
    """The mount point of the filesystem holding ``path`` (or its nearest existing parent)."""
    p = Path(path).resolve()
    while not p.exists() and p != p.parent:
        p = p.parent
    while not os.path.ismount(p) and p != p.parent:
        p = p.parent
    return str(p)
