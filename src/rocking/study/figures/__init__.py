"""The paper's figures (and the fragility curves), one module per figure.

Every module has ``data(...)``, which extracts exactly the arrays to plot (plain dicts of numpy
arrays, from the study store, its aggregates or fresh analyses), and ``plot(data) -> Figure``.
:func:`render` runs both and writes the image files plus a JSON sidecar with what the figure
measured and what was missing, which the report quotes.
"""

from __future__ import annotations

import importlib
from collections.abc import Sequence
from pathlib import Path

from ._load import open_means, open_store
from ._style import save, write_notes

FIGURES = {
    "fig03": "fig03_wobbling_period",
    "fig04": "fig04_free_vibration",
    "fig06": "fig06_el_centro",
    "fig07": "fig07_tilt_map",
    "fig08": "fig08_motions",
    "fig09": "fig09_spectra",
    "fig10": "fig10_goals",
    "fig11": "fig11_slenderness",
    "fig12": "fig12_2d_vs_3d",
    "fragility": "fragility_curves",
}
"""Short name → module of :mod:`rocking.study.figures`."""


def module(name: str):
    """The module of figure ``name`` (a key of :data:`FIGURES`)."""
    if name not in FIGURES:
        raise ValueError(f"figure must be one of {sorted(FIGURES)}, got {name!r}")
    return importlib.import_module(f".{FIGURES[name]}", __name__)


def render(name: str, outputs: Sequence[str | Path], notes: str | Path | None = None,
           **data_kw) -> dict:
    """Build figure ``name`` from ``data(**data_kw)`` and write it to every path of ``outputs``.

    Parameters
    ----------
    name : str
        Key of :data:`FIGURES`.
    outputs : sequence of path
        Image files (.png, .pdf, .svg).
    notes : path, optional
        JSON sidecar: the figure's ``measured``, ``paper``, ``predicted`` numbers and
        ``missing`` notes (whichever its data has).

    Returns
    -------
    dict
        The data handed to ``plot``.
    """
    mod = module(name)
    d = mod.data(**data_kw)
    save(mod.plot(d), outputs)
    if notes is not None:
        keys = ("measured", "paper", "predicted", "missing", "body", "motion")
        write_notes(notes, {"figure": name, **{k: d[k] for k in keys if k in d}})
    return d


__all__ = ["FIGURES", "module", "open_means", "open_store", "render"]
