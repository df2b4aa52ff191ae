"""The paper's figures (and the fragility curves), one module per figure, and the study's HTML
report (:mod:`.report`): what reads the study's stores and tables and draws or writes them.

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

FIGURES = (
    "fig03_wobbling_period",
    "fig04_free_vibration",
    "fig06_el_centro",
    "fig06_theta_max_sensitivity",
    "fig07_tilt_map",
    "fig08_motions",
    "fig09_spectra",
    "fig10_goals",
    "fig11_slenderness",
    "fig12_2d_vs_3d",
    "fragility_curves",
)
"""Figure names in the paper's order. A name is also its module here, its Snakemake rule and
script (``workflow/scripts/<name>.py``) and its key in :data:`.captions.CAPTIONS`."""

EXTRA_FIGURES = ("risk",)
"""Figures the workflow makes beyond those of the report (same name = module = rule = script
convention; the caption is the module's ``CAPTION``): ``risk``, :mod:`rocking.risk`."""

NOTE_KEYS = ("measured", "paper", "predicted", "missing", "body", "motion", "axes", "grid",
             "colors")
"""Entries of a figure's data copied into its JSON sidecar (whichever it has)."""


def module(name: str):
    """The module of figure ``name`` (one of :data:`FIGURES` or :data:`EXTRA_FIGURES`)."""
    if name not in FIGURES + EXTRA_FIGURES:
        raise ValueError(f"figure must be one of {list(FIGURES + EXTRA_FIGURES)}, "
                         f"got {name!r}")
    return importlib.import_module(f".{name}", __name__)


def figure_name(path: str | Path) -> str:
    """The figure a file belongs to, from its stem (``fig08_motions_elcentro`` → fig08_motions).

    Raises
    ------
    ValueError
        If no figure name starts the stem.
    """
    stem = Path(path).stem
    hits = [n for n in FIGURES if stem == n or stem.startswith(n + "_")]
    if not hits:
        raise ValueError(f"figure file name must start with one of {list(FIGURES)}, "
                         f"got {stem!r}")
    return max(hits, key=len)


def render(name: str, outputs: Sequence[str | Path], notes: str | Path | None = None,
           **data_kw) -> dict:
    """Build figure ``name`` from ``data(**data_kw)`` and write it to every path of ``outputs``.

    Parameters
    ----------
    name : str
        One of :data:`FIGURES`.
    outputs : sequence of path
        Image files (.png, .pdf, .svg).
    notes : path, optional
        JSON sidecar: the figure's :data:`NOTE_KEYS` entries (what it measured, the paper's
        numbers, what this run did not compute, which directions x and y are).

    Returns
    -------
    dict
        The data handed to ``plot``.
    """
    mod = module(name)
    d = mod.data(**data_kw)
    save(mod.plot(d), outputs)
    if notes is not None:
        write_notes(notes, {"figure": name, **{k: d[k] for k in NOTE_KEYS if k in d}})
    return d


__all__ = ["EXTRA_FIGURES", "FIGURES", "NOTE_KEYS", "figure_name", "module",
           "open_means", "open_store", "render"]
