"""``import rocking`` and ``rocking --help`` stay light (the heavy parts load where used)."""

from __future__ import annotations

import json
import subprocess
import sys

HEAVY = ("dask", "distributed", "xarray", "matplotlib", "numba", "pandas", "scipy", "zarr")


def _modules_after(code: str) -> set[str]:
    out = subprocess.run([sys.executable, "-c", f"{code}\nimport sys, json\n"
                          "print(json.dumps(sorted(sys.modules)))"],
                         capture_output=True, text=True, check=True)
    return set(json.loads(out.stdout.splitlines()[-1]))


def test_import_rocking_loads_no_heavy_library():
    loaded = _modules_after("import rocking")
    assert not {m for m in loaded if m.split(".")[0] in HEAVY}
    # a public name is still one attribute away
    loaded = _modules_after("import rocking; rocking.Cylinder(1.0, 0.2)")
    assert not {m for m in loaded if m.split(".")[0] in ("dask", "distributed", "xarray",
                                                          "matplotlib")}


def test_cli_help_loads_neither_numpy_nor_the_engine():
    loaded = _modules_after("from rocking.cli import build_parser\n"
                            "build_parser([]).format_help()")
    assert not {m for m in loaded if m.split(".")[0] in (*HEAVY, "numpy")}
    # a command's own help needs only its option lists
    loaded = _modules_after("from rocking.cli import build_parser\n"
                            "build_parser(['spectra', 'simulate', 'motions']).format_help()")
    assert not {m for m in loaded if m.split(".")[0] in (*HEAVY, "numpy")}


def test_listing_the_figures_loads_no_heavy_library():
    """Snakemake imports every figure module each time it plans a run (the registry reads
    their ``FIGURE``): they import the heavy libraries inside the functions that draw."""
    loaded = _modules_after("from rocking.plot.registry import figures\nfigures()")
    assert sorted({m.split(".")[0] for m in loaded} & set(HEAVY)) == []
