"""The documentation stands on its own: citations of docs/equations.md and docs/design.md
resolve, nothing points outside the repository, and the library never imports Snakemake
(docs/design.md, "Layers"). The README is a short entry whose claims hold: its links resolve,
its commands parse and install what exists, its library block prints what it shows, its
configuration is valid (the numbers it and the pages it links quote from the committed
gallery are held by tests/test_docs_numbers.py).

A docstring or comment cites a section as ``docs/equations.md, "<heading>"`` (the heading may
wrap over lines, also inside ``#`` comments; the file name may be in backticks) or, for
equations.md only, ``docs/equations.md, <heading>`` (unquoted: up to the first unbalanced
``)``, a ``;``, ``]``, a sentence end or the end of the line; headings with parentheses or
colons should be quoted). The heading must be one of that page's headings, compared
case-insensitively with whitespace collapsed.
"""

from __future__ import annotations

import ast
import importlib
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


# Layers of docs/design.md, "Layers", from the ground up; packages on one floor do not import
# each other. A module of src/rocking outside these packages is a shared helper (floor 0).
LAYERS = (("motions",), ("dynamics",), ("spectra",), ("fragility",), ("risk",), ("store",),
          ("config",), ("execution",), ("study",), ("plot",), ("report",), ("cli",))


def _import_graph() -> dict[str, set[str]]:
    """Module -> the modules of src/rocking it imports (at the top or inside a function)."""
    src = ROOT / "src"
    files = {}
    for f in _files("src/rocking"):
        if f.suffix == ".py":
            parts = f.relative_to(src).with_suffix("").parts
            files[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = f
    graph = {}
    for name, f in files.items():
        package = name if f.name == "__init__.py" else name.rpartition(".")[0]
        graph[name] = set()
        for node in ast.walk(ast.parse(f.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    up = package.split(".")[:len(package.split(".")) - node.level + 1]
                    base = ".".join(up + ([node.module] if node.module else []))
                # `from pkg import mod` imports the module pkg.mod, `from mod import name` mod
                targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in files else base
                           for a in node.names]
            else:
                continue
            for t in targets:
                while t not in files and "." in t:
                    t = t.rpartition(".")[0]
                if t in files and t != name:
                    graph[name].add(t)
    return graph


def _floor(module: str) -> int:
    package = module.split(".")[1] if module.count(".") else ""
    return next((i + 1 for i, floor in enumerate(LAYERS) if package in floor), 0)


def test_layers_import_only_downward():
    """Every import of a module of another package goes to a lower floor (docs/design.md,
    "Layers"), the library's face ``rocking/__init__.py`` aside (it imports on first use)."""
    upward = [f"{a} -> {b}" for a, targets in _import_graph().items() if a != "rocking"
              for b in targets if a.split(".")[:2] != b.split(".")[:2]
              and _floor(a) <= _floor(b) and _floor(b) > 0]
    assert not upward, "imports that do not go down a layer:\n" + "\n".join(sorted(upward))


def test_no_import_circle():
    """No module reaches itself through imports (inside functions too)."""
    graph = _import_graph()
    state: dict[str, int] = {}  # 1 = on the current path, 2 = done

    def visit(m: str, path: list[str]) -> list[str] | None:
        state[m] = 1
        for t in sorted(graph[m]):
            if state.get(t) == 1:
                return path + [m, t]
            if t not in state and (circle := visit(t, path + [m])):
                return circle
        state[m] = 2
        return None

    for m in sorted(graph):
        if m not in state and (circle := visit(m, [])):
            raise AssertionError("import circle: " + " -> ".join(circle))


def imports_table() -> str:
    """The table of docs/design.md, "Layers": per package, the packages it imports (measured)."""
    graph = _import_graph()
    packages = [p for floor in LAYERS for p in floor]
    rows = ["| package | imports from |", "|---|---|"]
    for pkg in reversed(packages):
        used = {b.split(".")[1] for a, targets in graph.items() if a.split(".")[1:2] == [pkg]
                for b in targets if b.count(".") and b.split(".")[1] != pkg
                and b.split(".")[1] in packages}
        below = [p for p in reversed(packages) if p in used]
        rows.append(f"| `rocking.{pkg}` | " + (", ".join(f"`{p}`" for p in below) or "—")
                    + " and the shared helpers |")
    return "\n".join(rows)


def test_design_imports_table_is_measured():
    """docs/design.md's table of who imports whom is the tree's (regenerate: the block is
    ``imports_table()`` of this module)."""
    text = (ROOT / "docs" / "design.md").read_text(encoding="utf-8")
    block = text.split("<!-- BEGIN imports-table -->\n", 1)[1].split("<!-- END", 1)[0]
    assert block.strip() == imports_table(), "docs/design.md, imports-table:\n" + imports_table()


def same_names() -> dict[str, set[str]]:
    """Every module or package name that occurs in more than one package of src/rocking:
    name → where (``package.module`` or ``package/``; the shared helpers at the top, and
    ``__init__``/``__main__``, left out)."""
    where: dict[str, set[str]] = {}
    src = ROOT / "src" / "rocking"
    for path in src.rglob("*.py"):
        rel = path.relative_to(src)
        if len(rel.parts) > 1 and path.stem not in ("__init__", "__main__"):
            where.setdefault(path.stem, set()).add(".".join(rel.with_suffix("").parts))
    for pkg in src.iterdir():
        if (pkg / "__init__.py").is_file():
            where.setdefault(pkg.name, set()).add(f"{pkg.name}/")
    return {name: places for name, places in where.items()
            if len({p.split(".")[0].rstrip("/") for p in places}) > 1}


def test_one_name_is_one_concept_and_the_design_lists_every_shared_name():
    """docs/design.md, "One name, one concept": its table names exactly the modules and
    packages whose name occurs in more than one package, each where it occurs."""
    text = (ROOT / "docs" / "design.md").read_text(encoding="utf-8")
    block = text.split("<!-- BEGIN same-names -->\n", 1)[1].split("<!-- END", 1)[0]
    rows = [line.split("|")[1:3] for line in block.splitlines()[2:] if line.startswith("| `")]
    listed = {name.strip().strip("`"): {w.strip().strip("`") for w in where.split(",")}
              for name, where in rows}
    assert listed == same_names()


def _package_tables() -> dict[str, list[tuple[list[str], list[str]]]]:
    """docs/design.md, "Packages": per package (``""`` for the shared helpers) its table's
    rows as (modules, names in backticks of the "holds" column)."""
    text = (ROOT / "docs" / "design.md").read_text(encoding="utf-8")
    section = text.split("\n## Packages\n", 1)[1].split("\n## ", 1)[0]
    out = {}
    for part in section.split("\n### ")[1:]:
        title, _, body = part.partition("\n")
        hit = re.match(r"`rocking\.(\w+)`", title)
        if not hit and not title.startswith("Shared helpers"):
            continue
        rows = []
        for line in body.splitlines():
            if line.startswith("| `"):
                first, holds = line.split("|")[1:3]
                rows.append((re.findall(r"`([\w/]+)`", first),
                             re.findall(r"`([A-Za-z_][A-Za-z0-9_]*)`", holds)))
        out[hit[1] if hit else ""] = rows
    return out


def test_design_package_tables_are_the_tree():
    """Every package's table in docs/design.md lists exactly its modules (and subpackages),
    and every name in backticks beside a module is one that module (or, for a subpackage,
    the subpackage) defines: the tables cannot go stale after a move."""
    src = ROOT / "src" / "rocking"
    tables = _package_tables()
    packages = sorted(p.name for p in src.iterdir() if (p / "__init__.py").is_file())
    assert sorted(k for k in tables if k) == packages
    unknown = []
    for pkg, rows in tables.items():
        base = src / pkg if pkg else src
        modules = {p.stem for p in base.glob("*.py")}
        if pkg:  # its subpackages (of the top: the packages, each a table of its own)
            modules |= {f"{p.name}/" for p in base.iterdir() if (p / "__init__.py").is_file()}
        else:
            modules -= {"__init__"}
        listed = [m for mods, _ in rows for m in mods]
        assert sorted(listed) == sorted(modules - ({"__init__", "__main__"} - set(listed))), pkg
        for mods, names in rows:
            found = []
            for m in mods:
                if m == "__main__":  # runs the command line when imported
                    continue
                dotted = "rocking" + (f".{pkg}" if pkg else "") + f".{m.rstrip('/')}"
                mod = importlib.import_module(dotted.removesuffix(".__init__"))
                if m.endswith("/"):  # a subpackage: its modules are its names
                    for sub in (src / pkg / m).glob("*.py"):
                        importlib.import_module(f"{dotted}.{sub.stem}")
                found.append(mod)
            unknown += [f"{pkg or 'shared'} {mods}: {n}" for n in names
                        if not any(hasattr(mod, n) for mod in found) and n not in mods]
    assert not unknown, f"docs/design.md names what its modules do not define: {unknown}"


def test_every_dotted_name_of_the_documents_resolves():
    """Every ``rocking.x.y`` README.md, config/README.md and docs/*.md name is a module or a
    name in one (the entry-point group ``rocking.figures`` is a name of the packaging, not
    of the code): no name left behind by a move or a rename."""
    text = "\n".join(p.read_text(encoding="utf-8") for p in _pages())
    stale = []
    for ref in sorted(set(re.findall(r"\b(rocking(?:\.[A-Za-z_]\w*)+)", text)) -
                      {"rocking.figures"}):
        parts = ref.split(".")
        for i in range(len(parts), 0, -1):
            try:
                obj = importlib.import_module(".".join(parts[:i]))
            except ImportError:
                continue
            for name in parts[i:]:
                obj = getattr(obj, name, None)
            break
        if obj is None:
            stale.append(ref)
    assert not stale, f"the documents name what does not exist: {stale}"


def test_design_lists_the_layers():
    """The diagram of docs/design.md, "Layers", names the packages in the order of LAYERS."""
    text = (ROOT / "docs" / "design.md").read_text(encoding="utf-8")
    block = text.split("## Layers", 1)[1].split("```", 2)[1]
    drawn = re.findall(r"^\s*(rocking\.\w+(?:\s+rocking\.\w+)*)", block, re.M)
    floors = [tuple(n.removeprefix("rocking.") for n in line.split()) for line in drawn]
    assert floors == list(reversed(LAYERS))


# ----------------------------------------------------------------------------- README and pages
README = ROOT / "README.md"
MOVED = {  # page: headings that left the README for it
    "performance": ("The whole workflow", "Start-up of the command line", "One analysis",
                    "Performance spectra: speed versus accuracy"),
    "models": ("The three models", "Validation", "Limits of the models",
               "Where this implementation departs from the printed paper",
               "The paper regenerated"),
    "motions": ("Records", "Synthetic ensembles share the record's elastic spectrum"),
}
LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")


def _fenced(markdown: str, lang: str) -> list[str]:
    """Bodies of the fenced code blocks of one language, in order."""
    return re.findall(rf"^```{lang}\n(.*?)^```", markdown, flags=re.S | re.M)


def _slug(heading: str) -> str:
    """GitHub's anchor of a heading."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def _pages() -> list[Path]:
    return [README, ROOT / "config" / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def test_readme_is_short_and_links_every_moved_page():
    text = README.read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 200
    for page, moved in MOVED.items():
        assert f"](docs/{page}.md)" in text, f"README does not link docs/{page}.md"
        found = headings((ROOT / "docs" / f"{page}.md").read_text(encoding="utf-8"))
        missing = [h for h in moved if _normalize(h) not in found]
        assert not missing, f"docs/{page}.md lacks {missing}"
    for section in ("Fresh machine", "Library in five lines", "Command line", "Your own records",
                    "Where results go and how to read them"):
        assert _normalize(section) in headings(text)


def test_links_resolve():
    broken = []
    for page in _pages():
        for target in LINK.findall(page.read_text(encoding="utf-8")):
            if re.match(r"[a-z]+:", target):  # http(s), mailto: not checked here
                continue
            path, _, anchor = target.partition("#")
            dest = (page.parent / path).resolve() if path else page
            if not dest.exists():
                broken.append(f"{page.relative_to(ROOT)}: {target}")
            elif anchor and dest.suffix == ".md":
                slugs = {_slug(h) for h in re.findall(r"^#{1,6}\s+(.*?)\s*$",
                                                      dest.read_text(encoding="utf-8"), re.M)}
                if anchor not in slugs:
                    broken.append(f"{page.relative_to(ROOT)}: {target} (no such heading)")
    assert not broken, "broken links:\n" + "\n".join(broken)


BENCHMARK_TABLES = ROOT / "docs" / "benchmarks"
_BENCHMARK_REF = re.compile(r"(?:docs/|\]\()benchmarks/([\w.]+?)\.(csv|md|\{csv,md\}|\{md,csv\})")


def test_benchmark_tables_are_those_the_documents_link():
    """docs/benchmarks/ holds only tables a document names (README.md, config/README.md,
    docs/*.md; the folder's own README lists them and does not count), each name resolves to
    a file there, and no document points at a benchmark's uncommitted output
    (``results/benchmarks/``): the benchmarks write where the documents link."""
    named, missing = set(), []
    for page in _pages():
        text = page.read_text(encoding="utf-8")
        checked = text
        if page.name == "performance.md":  # sections being rewritten by issue 45: drop then
            checked = re.sub(r"^## (Performance spectra: speed versus accuracy|Resolution of "
                             r"the critical intensity)\n.*?(?=^## )", "", text,
                             flags=re.S | re.M)
        assert "results/benchmarks/" not in checked, f"{page.relative_to(ROOT)} points at " \
            "results/benchmarks/, which is not committed: quote docs/benchmarks/ or the command"
        for stem, ext in _BENCHMARK_REF.findall(text):
            exts = ("csv", "md") if "{" in ext else (ext,)
            for e in exts:
                named.add(f"{stem}.{e}")
                if not (BENCHMARK_TABLES / f"{stem}.{e}").is_file():
                    missing.append(f"{page.relative_to(ROOT)}: docs/benchmarks/{stem}.{e}")
    assert not missing, missing
    held = {p.name for p in BENCHMARK_TABLES.iterdir()} - {"README.md"}
    # a table's CSV twin (the same numbers for machines) goes with its linked Markdown
    unlinked = sorted(f for f in held if f not in named
                      and f"{f.rsplit('.', 1)[0]}.md" not in named)
    assert not unlinked, f"docs/benchmarks/ holds tables no document names: {unlinked}"
    assert "benchmarks/README.md" in (ROOT / "docs" / "performance.md").read_text()


def test_fresh_machine_commands_install_what_exists():
    import tomllib

    text = README.read_text(encoding="utf-8")
    venv = "python3 -m venv .venv && . .venv/bin/activate && "
    assert f'{venv}pip install -e ".[workflow]" && snakemake --cores 2' in text
    assert f'{venv}pip install -e ".[test]" && python -m pytest' in text
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"][
        "optional-dependencies"]
    assert {"workflow", "test"} <= set(extras)
    assert (ROOT / "Snakefile").is_file() and (ROOT / "config" / "config.yaml").is_file()
    assert '-e ".[test]"' in (ROOT / ".ci" / "run").read_text()  # CI runs the same install


def test_workflow_extra_can_write_the_report():
    """``snakemake --report`` needs what snakemake's own ``reports`` extra lists (pygments)."""
    import tomllib
    from importlib.metadata import requires

    from packaging.requirements import Requirement

    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"][
        "optional-dependencies"]
    for extra in ("workflow", "test"):
        reqs = [Requirement(r) for r in extras[extra]]
        names = {r.name.lower() for r in reqs}
        snakemake_extras = {e for r in reqs if r.name == "snakemake" for e in r.extras}
        needed = [Requirement(r) for r in requires("snakemake") or []]
        needed = [r for r in needed if r.marker and r.marker.evaluate({"extra": "reports"})
                  and not r.marker.evaluate({"extra": ""})]
        assert needed, "snakemake no longer lists a 'reports' extra: recheck what it needs"
        missing = [r.name for r in needed
                   if r.name.lower() not in names and "reports" not in snakemake_extras]
        assert not missing, f"extra {extra!r} lacks {missing} for snakemake --report"
        assert "pygments" in names  # named even if a snakemake version drops the extra


def _command_lines(markdown: str) -> list[str]:
    """``rocking ...`` command lines of the bash blocks, continuation lines joined."""
    out = []
    for block in _fenced(markdown, "bash"):
        for line in block.replace("\\\n", " ").splitlines():
            if line.strip().startswith("rocking "):
                out.append(line.strip())
    return out


def test_every_command_shown_parses():
    import shlex

    from rocking.cli import build_parser

    lines = [(p, c) for p in _pages() for c in _command_lines(p.read_text(encoding="utf-8"))]
    assert len([c for p, c in lines if p == README]) >= 5
    bad = []
    for page, line in lines:
        argv = shlex.split(line)[1:]
        try:
            build_parser([argv[0]]).parse_args(argv)
        except SystemExit:
            bad.append(f"{page.relative_to(ROOT)}: {line}")
    assert not bad, "commands that do not parse:\n" + "\n".join(bad)


def test_own_records_config_is_valid():
    import yaml

    from rocking.config.checks import schema_error
    from rocking.config.study import StudySpec

    blocks = [yaml.safe_load(b) for b in _fenced(README.read_text(encoding="utf-8"), "yaml")]
    def reads_files(e: dict) -> bool:
        return bool(e.get("paths")) or any(r.get("paths") for r in e.get("records") or [])

    mine = [b for b in blocks if any(reads_files(e) for e in b.get("ensembles", {}).values())]
    assert mine, "the README shows no ensemble read from the user's files"
    schema = yaml.safe_load((ROOT / "workflow/schemas/config.schema.yaml").read_text())
    for config in mine:
        assert schema_error(config, schema) is None
        for name, study in config["studies"].items():
            assert study["ensemble"] in config["ensembles"]
            spec = StudySpec.from_config(config, name)   # the typed study accepts it too
            assert spec.reproduces is None               # a study of one's own


def test_library_block_prints_what_is_shown(capsys):
    """The README's library block prints what is shown under it: the same words, its
    numbers within the answers' stated error (another CPU need not give the same bits)."""
    from conftest import assert_prints_within

    from rocking.study.verify import answer_tolerance

    text = README.read_text(encoding="utf-8")
    code = _fenced(text, "python")[0]
    shown = _fenced(text, "text")[0]
    exec(compile(code, "README.md", "exec"), {})
    assert_prints_within(capsys.readouterr().out, shown, answer_tolerance("default")[0])


def test_readme_names_no_internal_tool():
    text = README.read_text(encoding="utf-8").casefold()
    assert not any(name in text for name in ("farm-" + "studio", "farm-" + "bench"))
