"""Shared by the benchmarks: best-of timing, and tables written as one CSV for machines and one
Markdown table for people."""

from __future__ import annotations

import math
import os
import platform
import time
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

import pandas as pd

from rocking.units import CSV_FLOAT_FORMAT

_T = TypeVar("_T")


def best_of(fn: Callable[[], _T], repeat: int) -> tuple[float, _T]:
    """Shortest wall time [s] of ``repeat`` calls of ``fn`` after a warm-up, and the last result."""
    out = fn()  # warm-up: compilation, caches, imports
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


REPOSITORY = Path(__file__).resolve().parents[1]


def tables_dir() -> Path:
    """Where the tables go: ``$ROCKING_BENCHMARKS`` or the repository's ``docs/benchmarks/``,
    where the documents link them. A table no document links is not kept there
    (``tests/test_docs.py``): link it from the text that quotes it, or delete it."""
    out = Path(os.environ.get("ROCKING_BENCHMARKS", REPOSITORY / "docs" / "benchmarks"))
    out.mkdir(parents=True, exist_ok=True)
    return out


def results_dir() -> Path:
    """What a benchmark keeps between its runs and no document quotes (cached references,
    traces, searches to reuse): ``$ROCKING_RESULTS/benchmarks`` or ``./results/benchmarks``."""
    out = Path(os.environ.get("ROCKING_RESULTS", "results")) / "benchmarks"
    out.mkdir(parents=True, exist_ok=True)
    return out


def write_table(name: str, df: pd.DataFrame, title: str, notes: str = "") -> Path:
    """Write ``<name>.csv`` and ``<name>.md`` under :func:`tables_dir`; return the CSV path."""
    out = tables_dir()
    csv = out / f"{name}.csv"
    df.to_csv(csv, index=False, float_format=CSV_FLOAT_FORMAT)
    cpu = platform.processor() or platform.machine()
    machine = f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}"
    md = [f"# {title}", "", f"Machine: {machine}", ""]
    if notes:
        md += [notes, ""]
    md.append(df.to_markdown(index=False))
    (out / f"{name}.md").write_text("\n".join(md) + "\n")
    return csv
