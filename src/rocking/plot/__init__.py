"""The figures: the paper's, the fragility curves, and those of the stripes, the risk and the
portfolio, one module per figure (or per ``data`` drawn twice), each read from the study's
stores and tables.

Each figure module declares its entry ``FIGURE`` (:class:`.registry.FigureSpec`: number, caption,
scope, when a study wants it, logical inputs, where the report shows it);
:func:`.registry.figures` lists them in the paper's order (``FIGURES``: their names).

Every module has ``data(...)``, which extracts exactly the arrays to plot (plain dicts of numpy
arrays, from the study store, its aggregates or fresh analyses), and ``plot(data) -> Figure``
(its entry may name another drawing function). :func:`render` runs both and writes the image
files plus a JSON sidecar with what the figure measured and what was missing, which the report
quotes.

Snakemake imports every figure module each time it plans a run (to read its ``FIGURE``), so a
figure module and the helpers it imports at their top (``_style``, ``_load``, ``_axes``,
``comparisons``, ``criteria``, ``captions``) import there nothing heavier than numpy: matplotlib,
pandas, xarray, zarr, dask, scipy and numba, and the modules of rocking that load them, are
imported inside the functions that read or draw (``tests/test_import.py`` holds it).
"""

from __future__ import annotations

import importlib
from collections.abc import Mapping, Sequence
from pathlib import Path

# both light: they import xarray and matplotlib inside the functions that read or draw
from rocking.plot._load import open_means, open_store
from rocking.plot._style import save, write_notes


def __getattr__(name: str):
    # FIGURES is read from the registry when first asked for: the figure modules import
    # this package, so it cannot list them while it is being imported
    if name == "FIGURES":
        from rocking.plot.registry import figures

        return tuple(figures())
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


NOTE_KEYS = ("measured", "paper", "predicted", "missing", "remarks", "body", "motion", "axes",
             "grid", "colors", "mode")
"""Entries of a figure's data copied into its JSON sidecar (whichever it has)."""


def module(name: str):
    """The module of figure ``name`` (a name of :func:`.registry.figures`)."""
    from rocking.plot.registry import figure

    return importlib.import_module(figure(name).module)


def figure_name(path: str | Path) -> str:
    """The figure a file belongs to, from its stem (``fig08_motions_elcentro`` → fig08_motions).

    Raises
    ------
    ValueError
        If no figure name starts the stem.
    """
    from rocking.plot.registry import figures

    stem = Path(path).stem
    names = list(figures())
    hits = [n for n in names if stem == n or stem.startswith(n + "_")]
    if not hits:
        raise ValueError(f"figure file name must start with one of {names}, got {stem!r}")
    return max(hits, key=len)


def render(name: str, outputs: Sequence[str | Path], notes: str | Path | None = None,
           **data_kw) -> dict:
    """Build figure ``name`` from ``data(**data_kw)`` and write it to every path of ``outputs``.

    Parameters
    ----------
    name : str
        A figure of :func:`.registry.figures`.
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
    from rocking.plot.registry import figure

    mod = module(name)
    d = mod.data(**data_kw)
    save(getattr(mod, figure(name).plot)(d), outputs)
    if notes is not None:
        write_notes(notes, {"figure": name, **{k: d[k] for k in NOTE_KEYS if k in d}})
    return d


def draw(name: str, inputs: Mapping, params: Mapping,
         outputs: Mapping[str, str | Path]) -> dict:
    """Draw figure ``name`` from the workflow's resolved ``inputs`` and ``params`` into
    ``outputs`` (``png``, ``pdf``, ``notes``): the body of the one figure script
    (``workflow/scripts/figure.py``); its entry turns them into ``data()``'s keywords."""
    from rocking.plot.registry import figure

    return render(name, [outputs["png"], outputs["pdf"]], outputs["notes"],
                  **figure(name).data_kwargs(inputs, params))


__all__ = ["NOTE_KEYS", "draw", "figure_name", "module", "open_means", "open_store", "render"]
