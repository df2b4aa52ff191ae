"""Scratch names beside an output: what a write cut by kill -9 leaves is swept by the next
write of that output (the kill-anywhere run once ended with a stray
``motions/.tiny-<digest>.nc.<pid>.tmp``), and nothing a live writer holds is touched."""
from __future__ import annotations

import os
import socket
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from rocking.execution.prepare import link_alias
from rocking.motions.ensemble_io import save_ensemble
from rocking.motions.motion import GroundMotion
from rocking.provenance import atomic_path, scratch_path, write_atomic

pytestmark = pytest.mark.skipif(os.name != "posix", reason="process ids asked with os.kill")


@pytest.fixture(scope="module")
def dead_pid() -> int:
    """The id of a process that has ended (and been reaped)."""
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


HOST = "".join(c if c.isalnum() else "_" for c in socket.gethostname())


def _as_if(path: Path, pid: int, kind: str = "part", host: str = HOST) -> Path:
    """The scratch name process ``pid`` on ``host`` would have written beside ``path``."""
    return path.with_name(f".{path.name}.{kind}-{host}-{pid}-0badf00d{path.suffix}")


def test_a_scratch_name_is_hidden_beside_its_file_and_keeps_its_suffix(tmp_path):
    p = scratch_path(tmp_path / "e.nc")
    assert p.parent == tmp_path and p.suffix == ".nc"
    assert p.name.startswith(f".e.nc.part-{HOST}-{os.getpid()}-")
    assert len(p.name) == len(_as_if(tmp_path / "e.nc", os.getpid()).name)
    with pytest.raises(ValueError, match="letters only"):
        scratch_path(tmp_path / "e.nc", "a-b")


def test_the_next_write_sweeps_a_dead_writers_file_and_folder_only(tmp_path, dead_pid):
    target = tmp_path / "e.nc"
    dead_file = _as_if(target, dead_pid)
    dead_dir = _as_if(target, dead_pid, kind="reference")
    live = _as_if(target, os.getpid())
    elsewhere = _as_if(target, dead_pid, host="another_machine")
    other = _as_if(tmp_path / "f.nc", dead_pid)  # another file's: not this write's to sweep
    for p in (dead_file, live, elsewhere, other):
        p.write_bytes(b"half")
    dead_dir.mkdir()
    (dead_dir / "chunk").write_bytes(b"x")

    write_atomic(target, lambda tmp: tmp.write_bytes(b"whole"))

    assert target.read_bytes() == b"whole"
    assert not dead_file.exists() and not dead_dir.exists()
    assert live.exists() and elsewhere.exists() and other.exists()
    # nothing left of the dead writer: the folder holds the file and the kept names only
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        p.name for p in (target, live, elsewhere, other))


def test_a_failed_write_leaves_neither_file_nor_scratch(tmp_path):
    target = tmp_path / "t.csv"
    with pytest.raises(RuntimeError), atomic_path(target) as tmp:
        tmp.write_text("half")
        raise RuntimeError("disk full")
    assert list(tmp_path.iterdir()) == []


def test_a_written_file_has_the_modes_open_gives(tmp_path):
    umask = os.umask(0o022)
    try:
        path = write_atomic(tmp_path / "t.csv", lambda tmp: tmp.write_text("a\n"))
    finally:
        os.umask(umask)
    assert path.stat().st_mode & 0o777 == 0o644


def test_a_motions_file_written_again_after_a_kill_leaves_no_debris(tmp_path, dead_pid):
    motions = [GroundMotion(np.sin(np.arange(50) / 5.0), np.cos(np.arange(50) / 5.0), 0.01,
                            "m")]
    out = tmp_path / "tiny.nc"
    _as_if(out, dead_pid).write_bytes(b"cut short")
    _as_if(out.with_name("tiny.nc.sha256"), dead_pid).write_bytes(b"cut")
    save_ensemble(out, motions)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["tiny.nc", "tiny.nc.sha256"]


def test_an_alias_relinked_after_a_kill_leaves_no_debris(tmp_path, dead_pid):
    store = tmp_path / "spectra-0123.zarr"
    store.mkdir()
    alias = tmp_path / "spectra.zarr"
    _as_if(alias, dead_pid, kind="link").symlink_to(store.name)
    assert link_alias(store, alias)
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([alias.name, store.name])
    assert alias.resolve() == store.resolve()
