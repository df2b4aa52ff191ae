"""Provenance of derived files: what made a sidecar or cache, checked when it is read.

A sidecar (``*_bootstrap.nc`` beside its fragility table) or a cache
(``stripes-<digest>.refined.jsonl`` beside its store) records the digests of what made it:
the sha256 of the table it belongs to, the store's ``config_hash``, the motions' sha256. A
reader compares them with the files in front of it; a file of another study, another
configuration or another table (copied over, or left from an earlier run) is never used, and
a damaged one is never half-read. The one-line error (:class:`ProvenanceError`) names the file
and the way out: the ``snakemake --forcerun <rule>`` that remakes it (:data:`REMAKE`).
"""

from __future__ import annotations

import hashlib
import os
import tempfile
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any

REMAKE = {
    "fragility_bootstrap.nc": "fragility",
    "suite_fragility_bootstrap.nc": "records_table",
    "stripe_fragility_bootstrap.nc": "stripe_fragility",
    "suite_fragility.csv": "records_table",
    ".refined.jsonl": "stripe_fragility",
    "stripe_fragility_refined.jsonl": "stripe_fragility",
}
"""The workflow rule that writes a derived file, by the end of its name."""


class ProvenanceError(ValueError):
    """A derived file that is damaged, or made from something else than what is in front of
    it; the message is one line naming the file and the way out."""


def remake_hint(path: str | Path) -> str:
    """``"rerun with snakemake --forcerun <rule>"`` for a derived file (or a generic way out
    for a file no rule writes)."""
    name = Path(path).name
    rule = next((REMAKE[end] for end in sorted(REMAKE, key=len, reverse=True)
                 if name.endswith(end)), None)  # the longest ending: stripe_fragility_...
    if rule is None:
        return "remake it from its inputs"
    return f"rerun with `snakemake --forcerun {rule}`"


def file_sha256(path: str | Path) -> str:
    """sha256 (hex) of a file's bytes."""
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def mismatches(recorded: Mapping[str, Any], expected: Mapping[str, Any]) -> list[str]:
    """``"key: recorded X, expected Y"`` for every key of ``expected`` the record lacks or
    holds another value of (empty: the provenance matches)."""
    out = []
    for key, want in expected.items():
        got = recorded.get(key)
        if got != want:
            out.append(f"{key} {_short(got)} (expected {_short(want)})")
    return out


def _short(value: Any) -> str:
    text = "none recorded" if value is None else str(value)
    return text[:16] if len(text) == 64 else text  # a sha256: its first 16 hex digits


@contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """A temporary name beside ``path`` to write to; renamed onto ``path`` when the block
    ends without an error, deleted otherwise (a full disk leaves nothing half-written)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.",
                               suffix=f".part{path.suffix}")
    os.close(fd)
    tmp = Path(tmp)
    umask = os.umask(0)
    os.umask(umask)
    tmp.chmod(0o666 & ~umask)  # as open() would make it (mkstemp makes it private)
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


def write_stamp(path: str | Path, what: Mapping[str, Any]) -> Path:
    """Write ``what`` as JSON to ``path`` unless the file already holds exactly that.

    The file's modification time is then when ``what`` last changed: a workflow rule that
    takes it as input is rerun when what made its outputs changes, by dates alone (which a
    copied output folder keeps).
    """
    import json

    path = Path(path)
    text = json.dumps(what, sort_keys=True, indent=1) + "\n"
    try:
        if path.read_text() == text:
            return path
    except (OSError, UnicodeDecodeError):
        pass
    path.parent.mkdir(parents=True, exist_ok=True)
    return write_atomic(path, lambda tmp: Path(tmp).write_text(text))


__all__ = ["REMAKE", "ProvenanceError", "atomic_path", "file_sha256", "mismatches",
           "remake_hint", "write_atomic", "write_stamp"]
