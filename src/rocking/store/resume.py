"""Resuming a grid store safely (:mod:`rocking.store`): its describing arrays compared
with a store made anew and restored from it, and one run per store at a time (:func:`locked`).
"""

from __future__ import annotations

import contextlib
import os
import shutil
from collections.abc import Iterator, Sequence
from pathlib import Path

import numpy as np

from rocking.store.read import describing_arrays, open_group


def differing_arrays(path: str | Path, reference: str | Path) -> list[str]:
    """The describing arrays of ``path`` (:func:`describing_arrays` of ``reference``) that
    are unreadable (checksum mismatch, truncated chunk), missing, or hold other values than
    in ``reference``, a store made anew for the same configuration. A missing chunk file of
    a coordinate reads as its fill value, so values are compared, not only read."""
    group, ref = open_group(path, "r"), open_group(reference, "r")
    out = []
    for name in describing_arrays(reference):
        expected = np.asarray(ref[name][...])
        try:
            found = np.asarray(group[name][...])
        except Exception:  # unreadable or absent
            out.append(name)
            continue
        same = found.shape == expected.shape and (
            np.array_equal(found, expected, equal_nan=True) if expected.dtype.kind == "f"
            else bool(np.all(found == expected)))
        if not same:
            out.append(name)
    return out


def restore_arrays(path: str | Path, reference: str | Path, names: Sequence[str]) -> None:
    """Replace the arrays ``names`` of store ``path`` by those of ``reference`` (each
    written whole to a sibling folder, then renamed into place)."""
    path, reference = Path(path), Path(reference)
    for name in names:
        tmp = path / f".{name}.restoring"
        shutil.rmtree(tmp, ignore_errors=True)
        shutil.copytree(reference / name, tmp)
        shutil.rmtree(path / name, ignore_errors=True)
        tmp.rename(path / name)


@contextlib.contextmanager
def locked(path: str | Path) -> Iterator[Path]:
    """Hold the lock of store ``path`` (``<path>.lock``, an exclusive ``flock``) for the
    block: two runs of one study (from two working directories sharing the results) can
    then never replace or delete a store the other is making or filling.

    Raises
    ------
    RuntimeError
        In one line naming the store, the lock file and the run holding it, when another
        process holds the lock (it is not waited for).
    """
    import fcntl
    import socket
    import time

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    lock = path.with_name(path.name + ".lock")
    fh = lock.open("a+")
    try:
        try:
            fcntl.flock(fh.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            fh.seek(0)
            holder = fh.read().strip() or "another process"
            raise RuntimeError(f"store {str(path)!r} is in use by {holder} (lock {lock}); "
                               f"wait for that run to end, then run again (it resumes "
                               f"from what that run finished)") from None
        # the lock file is never deleted (that would race with a waiting opener); it names
        # its holder for the message above
        fh.seek(0)
        fh.truncate()
        fh.write(f"pid {os.getpid()} on {socket.gethostname()} since "
                 f"{time.strftime('%Y-%m-%d %H:%M:%S %Z')} in {os.getcwd()}")
        fh.flush()
        yield path
    finally:
        fh.close()  # closing releases the flock
