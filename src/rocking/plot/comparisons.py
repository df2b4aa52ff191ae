"""Verdicts of the paper against a run: the row type, the verdicts and shared helpers.

Every figure writes what it measured into its JSON sidecar (:func:`rocking.plot.render`)
and owns its comparison with the paper: ``compare(notes)`` in its module, beside ``data`` and
``plot``, turns the notes into :class:`Comparison` rows (the paper's words or number, this
run's number, and a verdict that follows from the two and a stated tolerance). :func:`compare`
here only collects them, figure by figure. The verdicts:

- ``reproduced``: within the tolerance;
- ``differs``: outside it, with the reason where the cause is known (and measured where the
  run can measure it);
- ``not reproducible``: the paper's number cannot be recomputed from what it states;
- ``not computed in this run``: a reduced run left the quantity out;
- ``not in the paper``: figures beyond the paper, shown for their own numbers.
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Mapping
from dataclasses import dataclass

EQUATIONS = "docs/equations.md"
"""The derivations the verdicts cite (the report links ``docs/equations.md#anchor``)."""

REPRODUCED = "reproduced"
DIFFERS = "differs"
NOT_REPRODUCIBLE = "not reproducible"
NOT_COMPUTED = "not computed in this run"
NOT_IN_PAPER = "not in the paper"
VERDICTS = (REPRODUCED, DIFFERS, NOT_REPRODUCIBLE, NOT_COMPUTED, NOT_IN_PAPER)

@dataclass(frozen=True)
class Comparison:
    """One statement of the paper set against this run.

    Attributes
    ----------
    figure : str
        Figure name (a name of :func:`rocking.plot.registry.figures`).
    statement : str
        What is compared, with where the paper says it.
    paper : str
        The paper's number or words.
    ours : str
        This run's number(s).
    verdict : str
        One of :data:`VERDICTS`.
    reason : str
        The tolerance that was met, or why the numbers differ.
    """

    figure: str
    statement: str
    paper: str
    ours: str
    verdict: str
    reason: str = ""

    def __post_init__(self) -> None:
        if self.verdict not in VERDICTS:
            raise ValueError(f"verdict must be one of {VERDICTS}, got {self.verdict!r}")

    @property
    def verdict_text(self) -> str:
        """``"reproduced (within …)"``, ``"differs because …"`` and so on."""
        if not self.reason:
            return self.verdict
        if self.verdict == REPRODUCED:
            return f"{self.verdict} ({self.reason})"
        if self.verdict in (DIFFERS, NOT_REPRODUCIBLE):
            return f"{self.verdict} because {self.reason}"
        return f"{self.verdict}: {self.reason}"


def judged(figure: str, statement: str, paper: str, ours: str, ok: bool | None,
           tolerance: str, reason: str, missing: str = "") -> Comparison:
    """A comparison whose verdict follows from ``ok`` (None: not computed in this run).

    ``tolerance`` is quoted when reproduced, ``reason`` when it differs, ``missing`` (what the
    run left out) when nothing could be measured.
    """
    if ok is None:  # nothing was measured: the reason says what the run left out
        return Comparison(figure, statement, paper, "—", NOT_COMPUTED, missing)
    if ok:
        return Comparison(figure, statement, paper, ours, REPRODUCED, tolerance)
    return Comparison(figure, statement, paper, ours, DIFFERS, reason)


def fmt(value, digits: int = 4) -> str:
    """A number for a table; "not measured" for None/NaN."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "not measured"
    if isinstance(value, float):
        return f"{value:.{digits}g}"
    return str(value)


def finite(*values) -> bool:
    """Whether every value is a finite number (None and NaN are not)."""
    return all(v is not None and isinstance(v, int | float) and math.isfinite(v) for v in values)


def close(ours, paper: float, rtol: float) -> bool | None:
    """``|ours − paper| ≤ rtol·|paper|``; None when ``ours`` was not measured."""
    return abs(ours - paper) <= rtol * abs(paper) if finite(ours) else None


def value_range(pair) -> str:
    """``"0.0460–0.0910"`` of a (low, high) pair; "not measured" when empty."""
    return "not measured" if not pair else f"{pair[0]:.4f}–{pair[1]:.4f}"


def rank_correlation(x, y) -> float | None:
    """Spearman rank correlation of two equal-length sequences (None values dropped)."""
    from scipy.stats import spearmanr

    if not x or not y:
        return None
    pairs = [(a, b) for a, b in zip(x, y, strict=False) if a is not None and b is not None]
    if len(pairs) < 3:
        return None
    return float(spearmanr(*zip(*pairs, strict=True)).statistic)


def notes_of(notes: Mapping[str, Mapping], name: str) -> list[tuple[str, Mapping]]:
    """Every sidecar of figure ``name`` among ``notes``, as (file stem, notes) pairs.

    A sidecar is found by the figure it names (its ``"figure"`` entry, written by
    :func:`rocking.plot.render`), else by its key: the figure name itself or a file
    stem that starts with it (``fig12_2d_vs_3d_elcentro+lomaprieta``). Keyed by the figure's
    kind, not its file name, so that renaming a file cannot detach its verdicts.
    """
    out = []
    for key, d in notes.items():
        if not isinstance(d, Mapping):
            continue
        kind = d.get("figure")
        if kind == name or (kind is None and (key == name or key.startswith(name + "_"))):
            out.append((key, d))
    return out


def first_notes(notes: Mapping[str, Mapping], name: str) -> Mapping:
    """The notes of figure ``name`` (the first sidecar of that kind; empty when none)."""
    found = notes_of(notes, name)
    return found[0][1] if found else {}


def compare(notes: Mapping[str, Mapping], figures: list[str] | None = None) -> list[Comparison]:
    """Comparisons of the figures in ``figures`` (default all), from their sidecar notes.

    Parameters
    ----------
    notes : mapping
        Figure file stem (``fig08_motions_elcentro``) or name → its JSON notes; a figure's
        notes are found by the kind they name (:func:`notes_of`), whatever the file is
        called. A figure without notes yields rows "not computed in this run".
    figures : list of str, optional
        Figure names to compare, in order (default: every figure of
        :func:`rocking.plot.registry.figures`); each module's ``compare(notes)`` gives the
        rows (a figure without ``compare`` none).
    """
    from rocking.plot.registry import figure
    from rocking.plot.registry import figures as registered

    out = []
    for name in figures or list(registered()):
        hook = getattr(importlib.import_module(figure(name).module), "compare", None)
        out += [] if hook is None else hook(notes)
    return out
