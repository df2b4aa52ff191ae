"""No private name crosses a module boundary inside the library: a name starting with one
underscore is used only in the module that defines it (issue 40: 14 were imported across
modules). Private *modules* (``_json``, ``_style``, ``_common``) are the package's shared
helpers and may be imported; their private names may not. An ``import ... as _x`` of a public
name is allowed (a local alias)."""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src"
FILES = sorted((SRC / "rocking").rglob("*.py"))


def module_name(path: Path) -> str:
    parts = list(path.relative_to(SRC).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {module_name(p) for p in FILES}


def target(path: Path, node: ast.ImportFrom) -> str:
    """The absolute module an ``ImportFrom`` reads from."""
    here = module_name(path).split(".")
    if path.name != "__init__.py":
        here = here[:-1]
    if not node.level:
        return node.module or ""
    base = here[: len(here) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def crossings() -> list[str]:
    out = []
    for path in FILES:
        tree = ast.parse(path.read_text(encoding="utf-8"))
        modules = {}  # local name -> rocking module imported under it
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                where = target(path, node)
                for alias in node.names:
                    if f"{where}.{alias.name}" in MODULES:
                        modules[alias.asname or alias.name] = f"{where}.{alias.name}"
                    elif private(alias.name) and where.startswith("rocking"):
                        out.append(f"{path.name}:{node.lineno} from {where} import {alias.name}")
            elif isinstance(node, ast.Import):
                for alias in node.names:
                    if alias.name in MODULES and alias.asname:
                        modules[alias.asname] = alias.name
        for node in ast.walk(tree):
            if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                    and node.value.id in modules and private(node.attr)):
                out.append(f"{path.name}:{node.lineno} {modules[node.value.id]}.{node.attr}")
    return out


def test_no_private_name_is_imported_across_modules():
    assert crossings() == []


def test_the_check_sees_a_crossing(tmp_path, monkeypatch):
    """The walk finds both forms it forbids (it could otherwise pass vacuously)."""
    pkg = tmp_path / "rocking"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("def _hidden():\n    return 1\n")
    (pkg / "b.py").write_text("from .a import _hidden\nfrom . import a\nx = a._hidden()\n")
    monkeypatch.setattr(__import__(__name__), "SRC", tmp_path)
    files = sorted(pkg.rglob("*.py"))
    monkeypatch.setattr(__import__(__name__), "FILES", files)
    monkeypatch.setattr(__import__(__name__), "MODULES", {module_name(p) for p in files})
    assert crossings() == ["b.py:1 from rocking.a import _hidden", "b.py:3 rocking.a._hidden"]
