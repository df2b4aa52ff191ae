"""docs/design.md held equal to the code: the kernel contract (run fields, result fields,
return codes) and the maintainer lists "Adding a ..." (a limit state, a model, a product, a
figure, an intensity measure, a hazard format): every file they name exists, and the
registries they cite are those they name."""

from __future__ import annotations

import ast
import importlib
import inspect
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DESIGN = (ROOT / "docs" / "design.md").read_text(encoding="utf-8")


def section(title: str) -> str:
    """The text of the ``##``/``###`` section ``title`` up to the next heading of any level."""
    hit = re.search(rf"^#+ {re.escape(title)}\n(.*?)(?=^#+ )", DESIGN + "\n# end", re.S | re.M)
    assert hit, f"docs/design.md has no section {title!r}"
    return hit.group(1)


def code_blocks(text: str) -> list[str]:
    return re.findall(r"```[a-z]*\n(.*?)```", text, re.S)


def names_in_tuple(text: str) -> list[str]:
    """The names of a documented tuple ``(a, b, ...)`` (line breaks allowed)."""
    inner = text[text.index("(") + 1:text.rindex(")")]
    return [n.strip() for n in inner.replace("\n", " ").split(",") if n.strip()]


def test_the_documented_run_tuple_is_what_the_driver_unpacks():
    from rocking.dynamics import driver

    tree = ast.parse(inspect.getsource(driver.integrate).lstrip())
    unpacked = [node for node in ast.walk(tree) if isinstance(node, ast.Assign)
                and isinstance(node.value, ast.Name) and node.value.id == "run"]
    assert len(unpacked) == 1, "driver.integrate unpacks `run` once"
    code = [elt.id for elt in unpacked[0].targets[0].elts]
    blocks = [b for b in code_blocks(section("Kernel contract")) if b.startswith("run = (")]
    assert len(blocks) == 1
    assert names_in_tuple(blocks[0]) == code
    assert len(code) == 19


def test_the_documented_result_is_the_kernel_result():
    from rocking.dynamics.models import KernelResult

    blocks = [b for b in code_blocks(section("Kernel contract")) if b.startswith("(code")]
    assert len(blocks) == 1
    assert tuple(names_in_tuple(blocks[0])) == KernelResult._fields
    assert len(KernelResult._fields) == 13


def test_the_documented_return_codes_are_the_codes_module():
    from rocking.dynamics import codes

    in_code = {name: value for name, value in vars(codes).items()
               if name.isupper() and isinstance(value, int) and not isinstance(value, bool)}
    text = section("Kernel contract").replace("−", "-")
    documented = {name: int(value) for value, name in re.findall(r"(-?\d+) `([A-Z_]+)`", text)}
    assert documented == in_code
    assert documented["DECIDED"] == 5


def test_the_stray_paragraph_is_gone():
    """The report's paragraph once repeated after the last section."""
    assert DESIGN.count("extra report tables through a module's `report_tables`") <= 1
    assert DESIGN.rstrip().endswith("`PGA` [g].")


def cited_paths(text: str) -> list[str]:
    return re.findall(r"`((?:src|workflow|tests|config)/[^`]+)`", text)


def cited_module_names(text: str, module) -> list[str]:
    """Backquoted identifiers of ``text`` that look like names of ``module``."""
    names = set(re.findall(r"`([A-Za-z_][A-Za-z0-9_]*)`", text))
    return sorted(n for n in names if hasattr(module, n))


@pytest.mark.parametrize("title", ["Adding a limit state", "Adding a model",
                                   "Adding a product", "Adding a figure",
                                   "Adding an intensity measure", "Adding a hazard format"])
def test_every_file_a_maintainer_list_names_exists(title):
    paths = cited_paths(section(title))
    assert paths, title
    for path in paths:
        path = path.replace("<model>", "cylinder3d").replace("<name>", "fig09_spectra")
        assert (ROOT / path).exists(), f"{title}: {path} does not exist"


def test_adding_a_model_names_every_registry_a_mode_needs():
    from rocking.execution.tasks import MODE_COST
    from rocking.plot._style import MODE_STYLE
    from rocking.spectra.modes import MODES

    text = section("Adding a model")
    for name in ("MODE_STYLE", "MODE_COST", "MODES", "HISTORY_COLUMNS", "Model"):
        assert f"`{name}`" in text, name
    assert set(MODE_COST) == set(MODES)
    assert set(MODE_STYLE) == set(MODES)
    for style in MODE_STYLE.values():
        assert {"color", "linestyle", "label"} <= set(style)


def test_a_mode_without_cost_or_style_is_an_error_naming_it():
    from rocking.execution.tasks import mode_cost
    from rocking.plot._style import MODE_STYLE

    with pytest.raises(KeyError, match="'3d-new' has no cost .*MODE_COST"):
        mode_cost("3d-new")
    with pytest.raises(KeyError, match="'3d-new' has no plot style .*MODE_STYLE"):
        MODE_STYLE["3d-new"]
    assert MODE_STYLE.get("3d-new") is None  # .get keeps its explicit default


def test_adding_an_intensity_measure_cites_the_registry():
    measures = importlib.import_module("rocking.motions.measures")
    hazard = importlib.import_module("rocking.risk.hazard")
    text = section("Adding an intensity measure")
    for name in ("MEASURES", "IntensityMeasure", "MEASURE_PATTERN", "MEASURE_UNITS",
                 "parse_measure", "measure_imt", "measure_series", "Measure"):
        assert f"`{name}`" in text and hasattr(measures, name), name
    assert "`hazard_measure`" in text and hasattr(hazard, "hazard_measure")
    # every field the list names is a field of the registry's entries
    fields = list(measures.IntensityMeasure.__dataclass_fields__)
    documented = re.search(r"\(fields (.*?)\);", text, re.S).group(1)
    assert re.findall(r"`([a-z_]+)`", documented) == fields
    assert "`intensity_measure` pattern" in text
    schema = (ROOT / "workflow/schemas/config.schema.yaml").read_text()
    assert "intensity_measure" in schema


def test_adding_a_hazard_format_cites_the_registry():
    hazard = importlib.import_module("rocking.risk.hazard")
    text = section("Adding a hazard format")
    for name in ("HAZARD_FORMATS", "HazardFormat", "parse_hazard", "check_plausible"):
        assert f"`{name}`" in text and hasattr(hazard, name), name
    assert "`HazardCurve.from_file`" in text and hasattr(hazard.HazardCurve, "from_file")
    fields = list(hazard.HazardFormat.__dataclass_fields__)
    assert fields == ["name", "recognizes", "read"]
    assert all(f"`{f}" in text for f in fields)
    # the documented signatures are the ones hazard_format and read_hazard_file call
    for name, params in (("recognizes", ["path", "head"]), ("read", ["path"])):
        sig = re.search(rf"`{name}\(([^)]*)\)`", text).group(1)
        assert [s.strip() for s in sig.split(",")] == params
    for fmt in hazard.HAZARD_FORMATS:
        assert list(inspect.signature(fmt.read).parameters) == ["path"]
    assert [f.name for f in hazard.HAZARD_FORMATS] == ["openquake", "table"]
    assert "`HazardFile`" in text and hasattr(hazard, "HazardFile")


def test_from_file_reads_a_hazard_file_once_with_its_component(tmp_path, monkeypatch):
    """The file is opened once for the levels and the component (issue 40: read four times
    a run before)."""
    from rocking.risk import hazard

    path = tmp_path / "h.csv"
    path.write_text("# component='rotd50', investigation_time=1\npga,annual_rate\n"
                    "0.1,1e-2\n0.5,1e-4\n")
    calls = []
    real = hazard._text
    monkeypatch.setattr(hazard, "_text", lambda p: calls.append(p) or real(p))
    curve = hazard.parse_hazard({"file": str(path)})
    assert curve.component == "rotd50" and len(calls) == 1
    assert hazard.parse_hazard({"file": str(path), "component": "larger"}).component == "larger"
    # im_factor: the user converted the levels to the fragility's component
    scaled = hazard.parse_hazard({"file": str(path), "im_factor": 1.2})
    assert scaled.component is None and scaled.component_source == "im_factor"
    assert hazard.parse_hazard("1e-4,2.2").component is None
