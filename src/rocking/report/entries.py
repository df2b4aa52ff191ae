"""The figures of a report read back from disk: each image with its JSON sidecar
(:class:`FigureEntry`), in the paper's order, and what its module adds to the report: its
comparisons with the paper (:mod:`.comparisons`), its extra tables (``report_tables``) and its
rows of "what was run" (``run_rows``).
"""

from __future__ import annotations

import csv
import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from rocking.plot import figure_name, module
from rocking.plot.comparisons import Comparison, compare
from rocking.plot.registry import figures


@dataclass(frozen=True)
class FigureEntry:
    """One figure of the report: its name, image and sidecar notes."""

    name: str
    png: Path
    notes: dict

    @property
    def stem(self) -> str:
        """File stem (``fig08_motions_elcentro``): the key of its notes."""
        return self.png.stem


def load_figures(pngs: Sequence[str | Path]) -> list[FigureEntry]:
    """Figures in paper order, each with its JSON notes (empty when there is no sidecar)."""
    out = []
    for png in pngs:
        png = Path(png)
        name = figure_name(png)
        if not png.exists():
            raise ValueError(f"figure file does not exist: {str(png)!r}")
        sidecar = png.with_suffix(".json")
        notes = json.loads(sidecar.read_text()) if sidecar.exists() else {}
        # the notes are strict JSON: a NaN measurement was written as null
        measured = notes.get("measured")
        if isinstance(measured, dict):
            notes["measured"] = {k: math.nan if v is None else v for k, v in measured.items()}
        out.append(FigureEntry(name, png, notes))
    order = list(figures())  # the paper's order (the entries' numbers)
    return sorted(out, key=lambda f: (order.index(f.name), str(f.png)))


def figure_comparisons(entries: Sequence[FigureEntry]) -> dict[str, list[Comparison]]:
    """The comparisons of every figure in ``entries``, keyed by figure name."""
    notes = {e.stem: e.notes for e in entries}  # fig08 has one stem per ensemble
    names = list(dict.fromkeys(e.name for e in entries))
    out: dict[str, list[Comparison]] = {n: [] for n in names}
    for c in compare(notes, names):
        out[c.figure].append(c)
    return out


def figure_tables(entry: FigureEntry) -> list[tuple[str, pd.DataFrame]]:
    """The extra tables a figure shows under itself in the report: its module's
    ``report_tables(notes)`` (the common hook; a figure without one has none)."""
    hook = getattr(module(entry.name), "report_tables", None)
    return [] if hook is None else [(title, df) for title, df in hook(entry.notes)
                                    if not df.empty]


def figure_run_rows(entries: Sequence[FigureEntry]) -> list[tuple[str, str]]:
    """Rows a figure adds to the "what was run" section: its module's ``run_rows(notes)``
    (the common hook; e.g. the unprocessed record's PGA measured for the Fig 6 companion)."""
    rows = []
    for entry in entries:
        hook = getattr(module(entry.name), "run_rows", None)
        rows += [] if hook is None else list(hook(entry.notes))
    return rows


def comparison_table(rows: Sequence[Comparison], *, with_figure: bool = True) -> pd.DataFrame:
    """Rows as a table: (figure,) statement, paper, this run, verdict."""
    data = [((c.figure,) if with_figure else ()) + (c.statement, c.paper, c.ours,
                                                   c.verdict_text) for c in rows]
    columns = (["figure"] if with_figure else []) + ["statement", "paper", "this run", "verdict"]
    return pd.DataFrame(data, columns=columns)


VERDICT_COLUMNS = ("figure", "statement", "paper", "this_run", "verdict", "reason")
"""The columns of ``verdicts.csv``: a :class:`~rocking.plot.comparisons.Comparison` each
(``this_run`` its ``ours``; ``reason`` the tolerance met or why it differs)."""


def write_verdicts(rows: Sequence[Comparison], path: str | Path) -> Path:
    """The report's verdict table as data (``<study>/verdicts.csv``), row for row as the page
    shows it: what the documents quoting the committed gallery read (no rows for a study that
    does not reproduce the paper)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="", encoding="utf-8") as fh:
        out = csv.writer(fh, lineterminator="\n")
        out.writerow(VERDICT_COLUMNS)
        out.writerows((c.figure, c.statement, c.paper, c.ours, c.verdict, c.reason)
                      for c in rows)
    return path


def measured_lines(entry: FigureEntry) -> list[str]:
    """What a figure's notes say beyond the comparisons: directions of x/y, its remarks (a
    stand-in record), what the run left out."""
    lines = []
    axes = entry.notes.get("axes")
    if isinstance(axes, dict) and "text" in axes:
        lines.append(f"Axes: {axes['text']}.")
    remarks, missing = entry.notes.get("remarks", []), entry.notes.get("missing", [])
    if remarks:  # what it drew, said (a stand-in record): not something left out
        lines.append("Note: " + "; ".join(remarks) + ".")
    if missing:
        lines.append("Not computed in this run: " + "; ".join(missing) + ".")
    return lines
