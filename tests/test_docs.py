"""The documentation stands on its own: citations of docs/equations.md and docs/design.md
resolve, nothing points outside the repository, and the library never imports Snakemake
(docs/design.md, "Layers").

A docstring or comment cites a section as ``docs/equations.md, "<heading>"`` (the heading may
wrap over lines, also inside ``#`` comments; the file name may be in backticks) or, for
equations.md only, ``docs/equations.md, <heading>`` (unquoted: up to the first unbalanced
``)``, a ``;``, ``]``, a sentence end or the end of the line; headings with parentheses or
colons should be quoted). The heading must be one of that page's headings, compared
case-insensitively with whitespace collapsed.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
EQUATIONS = ROOT / "docs" / "equations.md"
PAGES = ("equations", "design")

TEXT_SUFFIXES = {".py", ".md", ".smk", ".yaml", ".yml", ".rst", ".txt", ".toml", ".cfg", ".json",
                 ".sh", ".html"}
SKIP_DIRS = {"__pycache__", ".ipynb_checkpoints"}

CITATION = re.compile(r"(?:docs/)?(equations|design)\.md`{0,2},\s*")
# Built from pieces so that this file does not match itself.
OUTSIDE = ("shared" + "/spec", "../" + "shared")


def _files(*parts: str) -> list[Path]:
    """Text files under the given paths of the repository (files or directories)."""
    out = []
    for part in parts:
        path = ROOT / part
        if path.is_file():
            out.append(path)
            continue
        if not path.is_dir():
            continue
        for f in sorted(path.rglob("*")):
            rel = f.relative_to(ROOT).parts
            if (f.is_file() and f.suffix in TEXT_SUFFIXES
                    and not any(p in SKIP_DIRS or p.endswith(".egg-info") for p in rel)):
                out.append(f)
    return out


def _normalize(text: str) -> str:
    """Lower case, comment markers of wrapped lines removed, whitespace collapsed."""
    text = re.sub(r"\n\s*#+\s*", " ", text)
    return " ".join(text.split()).casefold()


def headings(markdown: str) -> set[str]:
    """Normalized ATX headings of a Markdown text (fenced code blocks skipped)."""
    found, fenced = set(), False
    for line in markdown.splitlines():
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        m = re.match(r"^(#{1,6})\s+(.*?)\s*#*\s*$", line)
        if m and not fenced:
            found.add(_normalize(m.group(2)))
    return found


def _unquoted(text: str) -> str:
    """The heading of an unquoted citation that starts ``text``."""
    depth = 0
    for i, ch in enumerate(text):
        if ch == "(":
            depth += 1
        elif ch == ")":
            if depth == 0:
                return text[:i]
            depth -= 1
        elif ch in ";]\n" or (ch == "." and text[i + 1 : i + 2] in ("", " ", "\n")):
            return text[:i]
    return text


def citations(text: str) -> list[tuple[str, str]]:
    """(page, heading) cited in ``text`` (heading normalized)."""
    out = []
    for m in CITATION.finditer(text):
        page = m.group(1)
        rest = text[m.end():]
        if rest[:1] in "\"“":
            close = "”" if rest[0] == "“" else '"'
            end = rest.find(close, 1)
            if end < 0:
                out.append((page, _normalize(rest[1:80])))  # unterminated: reported
                continue
            out.append((page, _normalize(rest[1:end])))
        elif page == "equations":  # design.md is cited by quoted headings only
            heading = _unquoted(rest).strip().rstrip(",")
            if heading:
                out.append((page, _normalize(heading)))
    return out


def test_citation_parser():
    text = ('x (docs/equations.md, "3D undamped\n    model") y\n'
            "# see docs/equations.md, \"Back at\n# rest\"\n"
            "(docs/equations.md, cancellation-free form) [-]\n"
            "docs/equations.md, Eq (24) corrected; more\n"
            "equations.md, Back at rest.\n"
            '(``docs/design.md``, "Study store")\n'
            "layouts of docs/design.md, for tests\n"
            "no citation: docs/equations.md (a page) or equations.md's damped pair\n")
    assert citations(text) == [
        ("equations", "3d undamped model"), ("equations", "back at rest"),
        ("equations", "cancellation-free form"), ("equations", "eq (24) corrected"),
        ("equations", "back at rest"), ("design", "study store")]
    assert headings("# A\n```\n# not a heading\n```\n## Back  at rest ##\n") == {
        "a", "back at rest"}


def test_equations_page_exists_with_its_sections():
    found = headings(EQUATIONS.read_text(encoding="utf-8"))
    for heading in ("3D undamped model", "3D damped model", "2D Housner model", "Back at rest",
                    "Corrections to the printed paper", "Stochastic ground-motion model"):
        assert _normalize(heading) in found


def test_every_cited_heading_exists():
    found = {p: headings((ROOT / "docs" / f"{p}.md").read_text(encoding="utf-8"))
             for p in PAGES}
    missing = []
    for f in _files("src", "tests", "workflow", "Snakefile", "README.md", "docs", "config"):
        if f == Path(__file__).resolve():  # this file's examples are not citations
            continue
        text = f.read_text(encoding="utf-8")
        for page, heading in citations(text):
            if heading not in found[page]:
                missing.append(f"{f.relative_to(ROOT)}: docs/{page}.md, {heading!r}")
    assert not missing, "cited headings missing:\n" + "\n".join(missing)


@pytest.mark.parametrize("needle", OUTSIDE)
def test_nothing_points_outside_the_repository(needle):
    hits = []
    for f in _files("src", "tests", "workflow", "Snakefile", "README.md", "docs", "config"):
        for n, line in enumerate(f.read_text(encoding="utf-8").splitlines(), 1):
            if needle in line:
                hits.append(f"{f.relative_to(ROOT)}:{n}: {line.strip()}")
    assert not hits, f"{needle!r} points outside the repository:\n" + "\n".join(hits)


def test_library_never_imports_snakemake():
    offenders = []
    for f in _files("src"):
        if f.suffix != ".py":
            continue
        for node in ast.walk(ast.parse(f.read_text(encoding="utf-8"))):
            names = ([a.name for a in node.names] if isinstance(node, ast.Import)
                     else [node.module or ""] if isinstance(node, ast.ImportFrom) and not node.level
                     else [])
            if any(n.split(".")[0] == "snakemake" for n in names):
                offenders.append(f"{f.relative_to(ROOT)}:{node.lineno}")
    assert not offenders, "the library imports Snakemake: " + ", ".join(offenders)
