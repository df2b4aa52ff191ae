"""What made a derived file, recorded with it and checked before it is read.

Every file the workflow writes (tables, NetCDF, JSON sidecars, figures, caches) has a record
beside it, ``<dir>/.provenance/<name>.json``: the sha256 and size of the file, the rule that
wrote it, the digest of the settings that decided it (the rule's parameters), and the digests
of what it was made from (``inputs``) and made together with (``together``: the other outputs
of the same job). Paths in a record are relative to the file's folder, so a record copied
with another study's file points at this study's inputs and no longer matches them.

A reader calls :func:`check` (or, in the workflow, runs inside
:func:`rocking.execution.logs.job`, which checks every input and records every output): a
file that was edited or cut short, or whose inputs are no longer the files in front of it, is
refused in one line naming the file and the command that rebuilds it
(:class:`ProvenanceError`). Before any job runs, the workflow asks :func:`problem` of every
output of every job it plans (``workflow/rules/provenance.smk``) and remakes the stale ones
itself. A table without a record, handed to the command line, is taken as the user's own.

Digests: a file's sha256 (computed once per size and modification time in a process); a
zarr store's identity, its ``config_hash`` and its motions' sha256 (what names and decides
it; its chunks carry their own checksums, :mod:`rocking.store.integrity`), never a hash of
its chunks; a folder's, the sha256 of its files' names and digests.
"""

from __future__ import annotations

import glob
import hashlib
import json
import os
import posixpath
import re
import shutil
import socket
from collections.abc import Callable, Iterable, Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any

RECORDS = ".provenance"
"""The folder of records, beside the files they describe."""

NEARLY_FULL = 1 << 20
"""Free bytes below which an output folder is taken as full [B]."""

_SKIPPED = (".snakemake", RECORDS)  # Snakemake's timestamp in a directory output, records
_sha_cache: dict[tuple[str, int, int], str] = {}


class ProvenanceError(ValueError):
    """A derived file that was edited, cut short, or made from something else than what is in
    front of it; the message is one line naming the file and the command that rebuilds it."""


# -- digests ------------------------------------------------------------------------------

def file_sha256(path: str | Path) -> str:
    """sha256 (hex) of a file's bytes, read in 1 MiB blocks."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _cached_sha256(path: Path, st: os.stat_result) -> str:
    key = (str(path.resolve()), st.st_size, st.st_mtime_ns)
    if key not in _sha_cache:
        _sha_cache[key] = file_sha256(path)
    return _sha_cache[key]


def store_identity(attrs: Mapping[str, Any]) -> str:
    """A zarr store's identity from its attributes: its ``config_hash`` (the settings that
    decide it) and the sha256 of the motions it was made from."""
    ensemble = attrs.get("ensemble") or {}
    if isinstance(ensemble, str):
        try:
            ensemble = json.loads(ensemble)
        except ValueError:
            ensemble = {}
    motions = ensemble.get("file_sha256", "") if isinstance(ensemble, Mapping) else ""
    return f"zarr:{attrs.get('config_hash', '')}:{motions}"


def _store_attrs(path: Path) -> dict:
    for meta in ("zarr.json", ".zattrs"):
        try:
            body = json.loads((path / meta).read_text())
        except (OSError, ValueError):
            continue
        return body.get("attributes", {}) if meta == "zarr.json" else body
    return {}


def digest(path: str | Path, *, fast: bool = False) -> str | None:
    """The digest of a file, a zarr store or a folder (None when ``path`` does not exist).

    ``fast``: a file whose size and modification time are those its record holds has the
    record's sha256 (the planning of a run; a reader hashes the file).
    """
    path = Path(path)
    try:
        st = path.stat()
    except OSError:
        return None
    if path.is_dir():
        if path.suffix == ".zarr":
            return store_identity(_store_attrs(path))
        h = hashlib.sha256()
        for f in sorted(path.rglob("*")):
            rel = f.relative_to(path)
            if f.is_file() and not any(p.startswith(_SKIPPED) for p in rel.parts):
                h.update(f"{rel.as_posix()}\0{file_sha256(f)}\n".encode())
        return h.hexdigest()
    if fast:
        rec = read_record(path)
        if rec and rec.get("size") == st.st_size and rec.get("mtime_ns") == st.st_mtime_ns:
            return rec.get("sha256")
    return _cached_sha256(path, st)


def settings_digest(settings: Mapping[str, Any], root: str | None = None) -> str:
    """sha256 (16 hex digits) of the canonical JSON of a rule's settings (its parameters),
    paths under the output ``root`` written relative to it (a folder copied elsewhere keeps
    its settings)."""
    from rocking._json import json_default

    root = posixpath.normpath(root) if root else "."
    prefix = None if root == "." else root + "/"

    def plain(v: Any) -> Any:
        if isinstance(v, Mapping):
            return {str(k): plain(x) for k, x in v.items()}
        if isinstance(v, list | tuple):
            return [plain(x) for x in v]
        if isinstance(v, Path):
            v = str(v)
        if isinstance(v, str) and prefix and (v + "/").startswith(prefix):
            return "<output>/" + v[len(prefix):]
        return v

    text = json.dumps(plain(dict(settings)), sort_keys=True, separators=(",", ":"),
                      default=json_default)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


# -- records ------------------------------------------------------------------------------

def record_path(path: str | Path) -> Path:
    """``<dir>/.provenance/<name>.json`` of ``<dir>/<name>``."""
    path = Path(path)
    return path.parent / RECORDS / f"{path.name}.json"


def read_record(path: str | Path) -> dict | None:
    """The record of ``path`` (None without one; ``{"damaged": True}`` when unreadable)."""
    try:
        text = record_path(path).read_text()
    except FileNotFoundError:
        return None
    except OSError:
        return {"damaged": True}
    try:
        rec = json.loads(text)
    except ValueError:
        return {"damaged": True}
    return rec if isinstance(rec, dict) else {"damaged": True}


def _relative(paths: Iterable[str | Path] | Mapping[str | Path, str | None], base: Path,
              fast: bool = False) -> dict[str, str | None]:
    """``{path relative to base: digest}`` of paths (a mapping: digests given); ``base`` is
    the recorded file's folder, so that a record copied with a file into another study's
    folder names that study's inputs."""
    items = paths.items() if isinstance(paths, Mapping) else ((p, None) for p in paths)
    return {os.path.relpath(os.path.abspath(p), os.path.abspath(base)):
            (d if d is not None else digest(p, fast=fast)) for p, d in items}


def record(path: str | Path, *, inputs: Iterable | Mapping = (),
           together: Iterable[str | Path] = (), settings: str | None = None,
           rule: str | None = None, sha256: str | None = None) -> Path:
    """Record what made ``path`` (the write side; call it after ``path`` is complete).

    ``inputs``: the files (or stores) it was made from (a mapping: path → digest, when the
    caller knows it); ``together``: the files written with it; ``settings``: the digest of
    the settings that decided it (:func:`settings_digest`); ``rule``: the workflow rule that
    writes it; ``sha256``: the file's, when the caller knows it (an appended cache). A record
    already there for these very bytes (a library function recorded its own inputs while the
    job ran) keeps its inputs. Written under a temporary name and renamed.
    """
    path = Path(path)
    st = path.stat()
    sha = sha256 or (digest(path) if path.is_dir() else _cached_sha256(path, st))
    base = path.parent
    found = {} if sha256 else (read_record(path) or {})
    # the record a library function wrote for this very write (same bytes, same modification
    # time) keeps its inputs; one of an earlier run whose bytes came out the same does not
    # (its inputs are not this job's: another hazard, say)
    same_write = found.get("sha256") == sha and found.get("mtime_ns") == st.st_mtime_ns
    rec = {"file": path.name, "sha256": sha, "size": st.st_size, "mtime_ns": st.st_mtime_ns,
           "rule": rule or found.get("rule"), "settings": settings or found.get("settings"),
           "inputs": {**((found.get("inputs") or {}) if same_write else {}),
                      **_relative(inputs, base)},
           "together": _relative([t for t in together if Path(t) != path], base)}
    text = json.dumps(rec, sort_keys=True, indent=1) + "\n"
    out = record_path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    return write_atomic(out, lambda tmp: Path(tmp).write_text(text))


def forget(path: str | Path) -> None:
    """Remove ``path`` and its record (a cache started anew)."""
    Path(path).unlink(missing_ok=True)
    record_path(path).unlink(missing_ok=True)


# -- checks -------------------------------------------------------------------------------

def problem(path: str | Path, *, expect: Iterable[str | Path] = (), settings: str | None = None,
            rule: str | None = None, fast: bool = False, own: bool = False,
            partial: bool = False, prefix: bool = False) -> str | None:
    """Why ``path`` is not what its record says made it (None: it is).

    ``expect``: paths (or digests) it must have been made from or with; ``settings``, ``rule``:
    what the workflow would make it with now; ``fast``: files whose size and modification
    time are those recorded are not hashed (planning); ``own``: a file without a record is
    a source (a configuration file, a table of the user's own), not a derived file that lost
    it; ``partial``: recorded inputs that are not there are not asked for (a study's folder
    handed on without its stores); ``prefix``: the record describes the file's first bytes
    (an append-only cache killed between a line and its record).
    """
    path = Path(path)
    rec = read_record(path)
    if rec is None:
        return None if own else "no record of what made it"
    if rec.get("damaged") or not isinstance(rec.get("inputs", {}), dict) \
            or not isinstance(rec.get("size"), int):
        return f"its record {record_path(path)} is damaged"
    if rule is not None and rec.get("rule") != rule:
        return f"its record says rule {rec.get('rule')} wrote it, not rule {rule}"
    try:
        st = path.stat()
    except OSError:
        return "missing"
    size = rec.get("size")
    if path.is_dir():
        if digest(path) != rec.get("sha256"):
            return "changed since it was written"
    elif st.st_size < (size or 0) or (st.st_size != size and not prefix):
        return (f"cut short ({st.st_size} of its {size} bytes)" if st.st_size < size else
                f"changed since it was written ({st.st_size} bytes, {size} recorded)")
    elif not (fast and st.st_mtime_ns == rec.get("mtime_ns")):
        found = _prefix_sha256(path, size) if prefix else _cached_sha256(path, st)
        if found != rec.get("sha256"):
            return (f"changed since it was written (sha256 {found[:12]}, recorded "
                    f"{str(rec.get('sha256'))[:12]})")
    base = path.parent
    for kind, entries in (("made from", rec.get("inputs") or {}),
                          ("made with", rec.get("together") or {})):
        for rel, want in entries.items():
            other = base / rel
            found = digest(other, fast=fast)
            if found is None:
                if partial:
                    continue
                return f"{kind} {os.path.normpath(other)}, which is missing"
            if found != want:
                return f"{kind} another {os.path.normpath(other)} than the one there"
    recorded = {*(rec.get("inputs") or {}).values(), *(rec.get("together") or {}).values()}
    for want in expect:
        d = str(want) if isinstance(want, str) and want.startswith("zarr:") else digest(want)
        if d not in recorded:
            return f"not made from {want}"
    # last: a file that is what it was and is made from what is there, only with other
    # settings (a changed configuration), is the one case Snakemake's params trigger sees
    if settings is not None and rec.get("settings") != settings:
        return f"made with other settings of rule {rule or rec.get('rule')}"
    return None


def _prefix_sha256(path: Path, size: int) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        h.update(fh.read(size))
    return h.hexdigest()


def remake(path: str | Path) -> str:
    """The command that rebuilds a derived file: the workflow, asked for it, remakes a file
    that does not match its record."""
    return (f"remake it with `snakemake --cores 2 {path}` (and the run's --configfile), "
            f"or delete it")


def check(path: str | Path, *, expect: Iterable[str | Path] = (), own: bool = True,
          partial: bool = False, say: Callable[[str], None] | None = None) -> dict | None:
    """Refuse ``path`` unless it is what its record says made it (the read side; one call
    before a file is used; ``own``, ``partial``: as :func:`problem`). Returns the record
    (None: a file without one, taken as a source or a table of the user's own, which
    ``say`` is told).

    Raises
    ------
    ProvenanceError
        One line: the file, what is wrong, the command that rebuilds it.
    """
    why = problem(path, expect=expect, own=own, partial=partial)
    if why is not None:
        raise ProvenanceError(f"{path}: {why}: {remake(path)}")
    rec = read_record(path)
    if rec is None and say is not None:
        say(f"{path} has no record of what made it: read as a table of your own (a table "
            f"the workflow wrote carries one in {RECORDS}/)")
    return rec


# -- writing ------------------------------------------------------------------------------

_HOST = re.sub(r"[^A-Za-z0-9]", "_", socket.gethostname()) or "host"


def scratch_path(path: str | Path, kind: str = "part") -> Path:
    """A name beside ``path`` that only this process writes to, hidden and telling who made
    it: ``.<name>.<kind>-<host>-<pid>-<token><suffix>`` (the suffix kept, so a writer that
    reads the format from it still can). What a writer of ``path`` killed before it could
    clean up left under such a name is removed first (:func:`_sweep_scratch`): a write cut by
    ``kill -9`` leaves nothing behind once ``path`` is written again."""
    path = Path(path)
    if not kind.isalpha():
        raise ValueError(f"scratch kind {kind!r}: letters only")
    _sweep_scratch(path)
    return path.with_name(f".{path.name}.{kind}-{_HOST}-{os.getpid()}-"
                          f"{os.urandom(4).hex()}{path.suffix}")


def _sweep_scratch(path: Path) -> None:
    """Remove the scratch files and folders beside ``path`` (:func:`scratch_path`) whose
    process ran on this machine and runs no more; another machine's, or a live process's,
    are left alone (they may be writing)."""
    pattern = re.compile(rf"\.{re.escape(path.name)}\.[A-Za-z]+-(?P<host>[A-Za-z0-9_]+)-"
                         rf"(?P<pid>\d+)-[0-9a-f]+{re.escape(path.suffix)}")
    try:
        found = list(path.parent.glob(f".{glob.escape(path.name)}.*"))
    except OSError:
        return
    for p in found:
        m = pattern.fullmatch(p.name)
        if m is None or m["host"] != _HOST or _running(int(m["pid"])):
            continue
        if p.is_dir() and not p.is_symlink():
            shutil.rmtree(p, ignore_errors=True)
        else:
            p.unlink(missing_ok=True)


def _running(pid: int) -> bool:
    """Whether process ``pid`` runs on this machine (where that cannot be asked: yes)."""
    if os.name != "posix" or pid == os.getpid():
        return True  # Windows' os.kill would end the process, not ask about it
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:
        return True  # another user's process
    return True


@contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """A temporary name beside ``path`` to write to (:func:`scratch_path`); renamed onto
    ``path`` when the block ends without an error, deleted otherwise (a full disk leaves
    nothing half-written), and what a killed writer of ``path`` left swept first."""
    path = Path(path)
    tmp = scratch_path(path)
    # as open() would make it: created here, so a writer that appends or opens by name works
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
    os.close(fd)
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def write_atomic(path: str | Path, write: Callable[[Path], Any]) -> Path:
    """``write(tmp)`` then ``tmp`` renamed onto ``path`` (:func:`atomic_path`)."""
    with atomic_path(path) as tmp:
        write(tmp)
    return Path(path)


def require_writable(folder: str | Path, what: str = "output folder") -> Path:
    """Refuse, in one line naming ``folder``, a folder a run cannot write in: read-only, not
    a folder, or full (under :data:`NEARLY_FULL` bytes free). The folder is made if missing.

    Raises
    ------
    ValueError
    """
    folder = Path(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = scratch_path(folder / "rocking", "probe")
        probe.touch(exist_ok=False)
        probe.unlink()
    except OSError as exc:
        raise ValueError(f"{what} {folder}: cannot write in it ({exc.strerror or exc}): "
                         f"make it writable or choose another") from None
    free = shutil.disk_usage(folder).free
    if free < NEARLY_FULL:
        raise ValueError(f"{what} {folder}: no space left ({free} bytes free): free space "
                         f"there or choose another")
    return folder


__all__ = ["NEARLY_FULL", "RECORDS", "ProvenanceError", "atomic_path", "check", "digest",
           "file_sha256", "forget", "problem", "read_record", "record", "record_path",
           "remake", "require_writable", "scratch_path", "settings_digest", "store_identity",
           "write_atomic"]
