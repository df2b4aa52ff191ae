"""Issue 38, item 5: one stripe list for the command line and the workflow, the help text,
height and diameter swapped, each report describing its own studies, the Sa column's name."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from rocking.cli import SUBCOMMANDS, build_parser, main
from rocking.dynamics.dimensions import swap_warning

ROOT = Path(__file__).resolve().parents[1]


def _cli_stripes(monkeypatch, *options: str) -> np.ndarray:
    """The stripes ``rocking stripes`` hands to the library (stopped before any analysis)."""
    import rocking.fragility.stripes as stripes

    seen = {}

    def record(body, motions, states, **kw):
        seen["x"] = np.asarray(kw["intensities"], dtype=float)
        raise RuntimeError("stop before the analyses")

    monkeypatch.setattr(stripes, "stripe_fragility", record)
    with pytest.raises(RuntimeError, match="stop before"):
        main(["stripes", "--R", "1", "--tan-alpha", "0.2", "--record", "el-centro-1940",
              "-q", *options])
    return seen["x"]


def _workflow_stripes(grid: dict) -> np.ndarray:
    """The stripes a study's ``stripes.intensity`` gives the workflow."""
    from rocking.config.study import StudySpec

    config = {"ensembles": {"e": {"record": "el-centro-1940"}},
              "studies": {"s": {"ensemble": "e", "R": [1.0],
                                "runs": [{"modes": ["3d"], "tan_alpha": [0.2],
                                          "limit_states": ["overturning"]}],
                                "stripes": {"R": [1.0], "intensity": grid}}}}
    return np.asarray(StudySpec.from_config(config, "s").stripes.intensity, dtype=float)


@pytest.mark.parametrize("lower, upper, n", [(0.5, 20.0, 40), (1.0, 20.0, 40),
                                             (1.0778, 12.5, 7), (0.3, 3.0, 1)])
def test_cli_and_workflow_stripes_are_bit_identical(monkeypatch, lower, upper, n):
    cli = _cli_stripes(monkeypatch, "--lower", str(lower), "--upper", str(upper),
                       "--stripes", str(n))
    flow = _workflow_stripes({"start": lower, "stop": upper, "num": n, "spacing": "log"})
    assert cli.tobytes() == flow.tobytes()
    assert cli[0] == lower  # the first stripe is --lower / start, on both sides
    if n > 1:
        assert cli[-1] == upper and np.all(np.diff(np.log(cli)) > 0)
        # geometric to the 12 digits of a grid value
        np.testing.assert_allclose(np.diff(np.log(cli)), np.log(upper / lower) / (n - 1),
                                   rtol=1e-9)


def test_help_prints_single_percent_signs():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    seen = 0
    for name in SUBCOMMANDS:
        text = sub.choices[name].format_help()
        assert "%%" not in text, name
        seen += len(re.findall(r"\d %", text))
    assert seen >= 3  # "95 %" and "90 %" are written and printed once each


def test_height_below_diameter_warns_naming_both(capsys):
    assert swap_warning(6.0, 0.66) is None and swap_warning(1.0, 1.0) is None
    line = swap_warning(0.66, 6.0, ("--height", "--diameter"))
    assert line == ("warning: --height 0.66 m is below --diameter 6 m (tan α = 9.091): "
                    "did you swap them?")
    # the command line prints it with the body, before any work, and goes on
    argv = ["spectra", "--height", "0.66", "--diameter", "6", "--record", "el-centro-1940",
            "--R", "1"]
    assert main(argv) == 2  # --R beside the dimensions disagrees: stopped before any work
    err = capsys.readouterr().err
    assert "did you swap" not in err  # refused first: nothing was derived
    from rocking.config.dimensions import resolve_dimensions

    said = []
    config = {"studies": {"col": {"height": 0.4, "diameter": 2.0, "runs": [{}]}}}
    resolved = resolve_dimensions(config, say=said.append)
    assert resolved["studies"]["col"]["runs"][0]["tan_alpha"] == [5.0]
    assert said[1] == ("warning: studies.col.height 0.4 m is below studies.col.diameter 2 m "
                       "(tan α = 5): did you swap them?")
    assert len(said) == 2 and "\n" not in said[1]


def test_cli_prints_the_swap_warning_and_continues(capsys, monkeypatch):
    x = _cli_stripes(monkeypatch, "--stripes", "2")  # a body by R: no warning
    assert x.size == 2 and "swap" not in capsys.readouterr().err
    import rocking.fragility.stripes as stripes

    monkeypatch.setattr(stripes, "stripe_fragility",
                        lambda *a, **k: (_ for _ in ()).throw(RuntimeError("stop")))
    with pytest.raises(RuntimeError, match="stop"):
        main(["stripes", "--height", "0.4", "--diameter", "2", "--record", "el-centro-1940",
              "-q", "--stripes", "2"])
    err = capsys.readouterr().err.splitlines()
    assert "rocking stripes: warning: --height 0.4 m is below --diameter 2 m (tan α = 5): " \
           "did you swap them?" in err


def test_each_report_describes_only_its_own_studies():
    from rocking.config.study import report_studies

    def study(ensemble, modes):
        return {"ensemble": ensemble, "R": [1.0],
                "runs": [{"modes": modes, "tan_alpha": [0.2], "limit_states": ["overturning"]}]}

    config = {"ensembles": {"a": {"record": "el-centro-1940"},
                            "b": {"record": "el-centro-1940", "n_synthetic": 1}},
              "studies": {"one": study("a", ["3d"]), "two": study("b", ["3d"]),
                          "x": study("a", ["3d", "2d-x"]), "y": study("b", ["3d", "2d-y"])}}
    assert report_studies(config, "one") == ["one"]
    assert report_studies(config, "two") == ["two"]
    # a report showing Fig 12 describes every study Fig 12 draws
    assert report_studies(config, "x") == ["x", "y"]
    rules = (ROOT / "workflow/rules/figures_common.smk").read_text()
    body = rules[rules.index("def report_run_files"):rules.index("def report_inputs")]
    assert "report_studies(config, study)" in body and 'config["studies"]' not in body
    assert "study_ensembles()" not in body


def test_the_sa_column_is_named_as_the_docs_say():
    from rocking.study.records import measure_column

    assert measure_column("sa:1.0") == ("sa_1s", "g")
    assert measure_column("sa:0.30", critical=True) == ("sa_0.3s_crit", "g")
    docs = (ROOT / "docs/records.md").read_text()
    assert "`sa_<T>s [g]`" in docs and "`sa:1.0` → `sa_1s`" in docs


def _fresh(cache: Path, *argv: str) -> tuple[str, set[str]]:
    """``rocking`` in a new process on the numba cache ``cache``: (stderr, the modules whose
    kernels that cache holds)."""
    import os
    import subprocess
    import sys

    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    out = subprocess.run([sys.executable, "-m", "rocking.cli", *argv], env=env,
                         capture_output=True, text=True, timeout=900)
    assert out.returncode == 0, out.stderr[-2000:]
    held = {p.name.split(".")[0] for p in cache.rglob("*.nbi")}
    return out.stderr, held


@pytest.mark.slow
def test_the_first_compile_says_so_once_and_compiles_only_the_model_asked_for(tmp_path):
    cache = tmp_path / "numba"
    argv = ["simulate", "--R", "1", "--tan-alpha", "0.2", "--mode", "2d-x", "--theta0",
            "0.05", "--duration", "0.5", "--out", str(tmp_path / "run")]
    first, held = _fresh(cache, *argv)
    line = "rocking simulate: compiling the 2d model once, ~30 s; cached afterwards"
    assert first.splitlines().count(line) == 1
    assert "housner2d" in held and not held & {"cylinder3d", "cylinder3d_damped"}
    again, _ = _fresh(cache, *argv)
    assert "compiling" not in again  # loaded from the cache: nothing said


_PROBE = """
import numba

@numba.njit(cache=True)
def twice(x):
    return 2.0 * x
"""


def _probe_module(path: Path, name: str):
    """A module of ``rocking`` (by name) from ``path``: its compiled function counts as the
    library's for :func:`announcing_compile`."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_a_compile_is_said_once_as_numba_starts_it_and_a_cached_load_not_at_all(tmp_path):
    """numba's event of a compilation, not its cache files: the first compilation of a
    function of rocking says the model's line once; the same function loaded from numba's
    on-disk cache (a new process's view of it) says nothing; a compilation outside rocking
    says nothing."""
    import numba

    from rocking.dynamics.compiled import announcing_compile, compile_notice

    path = tmp_path / "probe.py"
    path.write_text(_PROBE)
    said = []
    with announcing_compile("2d", said.append) as compiled:
        first = _probe_module(path, "rocking._probe_first")
        assert first.twice(1.5) == 3.0 and first.twice(2.5) == 5.0
    assert said == [compile_notice("2d")]
    assert compiled == ["rocking._probe_first.twice"]
    said.clear()
    with announcing_compile("3d", said.append) as compiled:
        again = _probe_module(path, "rocking._probe_again")  # the same source: cached
        assert again.twice(1.5) == 3.0
        outside = numba.njit(lambda x: x + 1.0)                 # not rocking's
        assert outside(1.0) == 2.0
    assert said == [] and compiled == []
    with pytest.raises(ValueError, match="model must be one of"):
        compile_notice("4d")
