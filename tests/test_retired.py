"""Every name retired with the first exceedance as the answer is gone: from the code, the
workflow, the configuration, the documents, and the tables and reports a run writes.

The refinement that chased the first exceedance (the near-miss refinement and its budget, the
window-seeking scan, the refinement sample and its risk table, the ``unresolved`` and
``budget_spent`` flags) was retired when the critical intensity became I10, which converges
(docs/models.md, "The critical intensity"). A document may tell that history under a heading
that says so ("... history"), and a benchmark table measured before the change says so in its
name (``docs/benchmarks/*_before.*``); nowhere else may a retired name stand.

The critical-intensity fragility (the lognormal of each motion's critical intensity, I10 by
default) was once named after the first exceedance; its old spellings (:data:`RENAMED`) are
retired too, save in the one place that maps them to today's for the tables written before
(``rocking.fragility.table``: ``RENAMED``, ``RENAMED_COLUMNS``). Only spellings that name the
estimator are listed: ``first_exceedance`` itself stays the name of a quantity (the first
exceedance on the scan grid, ``quantity: first_exceedance``) and of the search's result.
"""

from __future__ import annotations

import re
import subprocess
from collections.abc import Iterable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

RETIRED = (
    # the refinement sample and its risk table
    "rocking.study.refinement", "study/refinement.py", "rocking.plot.refined", "plot/refined.py",
    "refinement.smk", "refinement_sample", "refinement_risk", "refinement_not_measured",
    "moved by refinement", "refinement moves",
    # the flags of the near-miss refinement
    "unresolved", "budget_spent",
    # the near-miss refinement and the window-seeking scan (accuracy settings)
    "refine_budget", "refine_step", "refine_near", "seek_near", "window-seeking",
)
"""Retired names, matched case-insensitively as written (``n_unresolved`` holds one)."""

RENAMED = (
    # the estimator in prose, the report's and the figure's columns, labels and notes
    "first-exceedance fragility", "first-exceedance fit", "first-exceedance λ",
    "first-exceedance rows", "λ first exceedance", "stripes / first [", "ratio stripes/first",
    # the NRML model id (<study>-first-exceedance)
    "-first-exceedance",
    # the stripe table's columns of the critical-intensity fit, and a variable of its λ
    "first_median", "first_beta", "first_status", "maf_first",
)
"""The critical-intensity fragility's old spellings (none of them the quantity's)."""

MAPPED_IN = Path("src/rocking/fragility/table.py")
"""The one file that may spell them: it maps a table of before to today's names."""

PATTERN = re.compile("|".join(re.escape(n) for n in RETIRED), re.IGNORECASE)
RENAMED_PATTERN = re.compile("|".join(re.escape(n) for n in RENAMED), re.IGNORECASE)
SOURCES = ("src", "workflow", "docs", "config", "README.md", "Snakefile")
"""What the repository says about itself (tests name the retired names, by design)."""
TEXT = (".py", ".smk", ".md", ".yaml", ".yml", ".rst", ".csv", ".json", ".html", ".txt", "")


def _history_free(path: Path, text: str) -> str:
    """``text`` without the sections of a Markdown document whose heading names a history."""
    if path.suffix != ".md":
        return text
    out, skip = [], None
    for line in text.splitlines():
        m = re.match(r"^(#+)\s+(.*)", line)
        if m:
            level = len(m.group(1))
            if skip is not None and level <= skip:
                skip = None
            if skip is None and "history" in m.group(2).lower():
                skip = level
        if skip is None:
            out.append(line)
    return "\n".join(out)


def retired_names_in(paths: Iterable[Path], pattern: re.Pattern = PATTERN) -> list[str]:
    """``file:line: name`` of every retired name (``pattern``) in the text files ``paths``."""
    found = []
    for path in paths:
        if path.suffix not in TEXT or not path.is_file():
            continue
        if path.parent.name == "benchmarks" and path.stem.endswith("_before"):
            continue  # a measurement of the state before the retirement: history by name
        try:
            text = _history_free(path, path.read_text())
        except UnicodeDecodeError:
            continue
        name = path.relative_to(ROOT) if path.is_relative_to(ROOT) else path
        if pattern is RENAMED_PATTERN and name == MAPPED_IN:
            continue
        for i, line in enumerate(text.splitlines(), 1):
            for m in pattern.finditer(line):
                found.append(f"{name}:{i}: {m.group(0)}")
    return found


def _tracked(*where: str) -> list[Path]:
    """The repository's files under ``where``: git's list in a clone; in a copy without
    ``.git`` (CI's ``git archive``) every file there but the environment's and caches."""
    out = subprocess.run(["git", "ls-files", *where], cwd=ROOT, capture_output=True,
                         text=True, check=False)
    if out.returncode == 0:
        return [ROOT / p for p in out.stdout.split()]
    skip = {".git", ".venv", "__pycache__", ".snakemake", ".ruff_cache", ".pytest_cache"}
    files = []
    for w in where:
        top = ROOT / w
        candidates = [top] if top.is_file() else sorted(top.rglob("*"))
        files += [f for f in candidates if f.is_file()
                  and not skip.intersection(f.relative_to(ROOT).parts)
                  and not any(p.endswith(".egg-info") for p in f.relative_to(ROOT).parts)]
    return files


def test_the_pattern_finds_each_name():
    for name in RETIRED:
        assert PATTERN.search(f"x {name.upper()} y"), name
    assert not PATTERN.search("refine_stripes n_refined plateau first_exceedance")
    for name in RENAMED:
        assert RENAMED_PATTERN.search(f"x {name.upper()} y"), name
    # the quantity and the search's result keep their name
    for legit in ("quantity: first_exceedance", 'Quantity("first_exceedance")',
                  "res.first_exceedance[k]", "the first exceedance on the scan grid",
                  "the first-exceedance search", "mean first exceedance 2.23",
                  "critical-intensity fragility", "critical_median"):
        assert not RENAMED_PATTERN.search(legit), legit


def test_the_old_estimator_names_are_those_the_reader_maps():
    from rocking.fragility.table import CRITICAL_INTENSITY, RENAMED_COLUMNS
    from rocking.fragility.table import RENAMED as MAPPED

    assert MAPPED == {"first_exceedance": CRITICAL_INTENSITY}
    assert set(RENAMED_COLUMNS) <= set(RENAMED)


def test_no_retired_name_in_code_workflow_config_or_documents():
    found = retired_names_in(_tracked(*SOURCES))
    assert not found, "\n".join(found[:40])


def test_no_old_estimator_name_in_code_workflow_config_or_documents():
    found = retired_names_in(_tracked(*SOURCES), RENAMED_PATTERN)
    assert not found, "\n".join(found[:40])


def test_a_history_section_may_tell_the_retired_names(tmp_path):
    doc = tmp_path / "d.md"
    doc.write_text("# A\nnew\n## The resolution, a short history\nthe unresolved flag\n"
                   "### detail\nbudget_spent\n## Now\nplateau\n")
    assert retired_names_in([doc]) == []
    doc.write_text("# A\nthe unresolved flag\n")
    assert retired_names_in([doc]) == [f"{doc}:2: unresolved"]


def test_the_gallery_holds_no_retired_name():
    """The committed gallery (results/paper): tables, reports, figures' notes, READMEs. Holds
    once the gallery is regenerated with this code."""
    found = retired_names_in(_tracked("results/paper"))
    assert not found, "\n".join(found[:40])


def _gallery_before_the_rename() -> bool:
    """The committed gallery's risk tables still name the estimator the old way (until the
    gallery is regenerated with this code)."""
    import csv

    from rocking.fragility.table import RENAMED as MAPPED

    for path in _tracked("results/paper"):
        if path.name == "risk.csv" and path.is_file():
            with open(path, newline="", encoding="utf-8") as fh:
                if any(r.get("fragility") in MAPPED for r in csv.DictReader(fh)):
                    return True
    return False


def test_the_gallery_holds_no_old_estimator_name():
    """Holds once the gallery is regenerated with this code; skipped (saying so) while it
    was written before the critical-intensity fragility's rename, whose tables the readers
    map (rocking.fragility.table.RENAMED)."""
    import pytest

    if _gallery_before_the_rename():
        pytest.skip("results/paper was written before the critical-intensity fragility's "
                    "rename: regenerate it")
    found = retired_names_in(_tracked("results/paper"), RENAMED_PATTERN)
    assert not found, "\n".join(found[:40])
