"""Writing benchmark tables: one CSV for machines, one Markdown table for people."""

from __future__ import annotations

import os
import platform
from pathlib import Path

import pandas as pd


def results_dir() -> Path:
    """``$ROCKING_RESULTS`` or ``./results``; the benchmarks folder is created inside it."""
    out = Path(os.environ.get("ROCKING_RESULTS", "results")) / "benchmarks"
    out.mkdir(parents=True, exist_ok=True)
    return out


def write_table(name: str, df: pd.DataFrame, title: str, notes: str = "") -> Path:
    """Write ``<name>.csv`` and ``<name>.md`` under :func:`results_dir`; return the CSV path."""
    out = results_dir()
    csv = out / f"{name}.csv"
    df.to_csv(csv, index=False)
    cpu = platform.processor() or platform.machine()
    machine = f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}"
    md = [f"# {title}", "", f"Machine: {machine}", ""]
    if notes:
        md += [notes, ""]
    md.append(df.to_markdown(index=False))
    (out / f"{name}.md").write_text("\n".join(md) + "\n")
    return csv

