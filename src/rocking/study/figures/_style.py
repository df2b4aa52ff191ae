"""Shared look of the paper figures and the one way they are written to disk.

Every figure module calls :func:`new_figure` and :func:`save`, so sizes, fonts and file formats
stay the same across figures (PNG for the HTML report, PDF for print).
"""

from __future__ import annotations

import functools
import json
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import ParamSpec

import matplotlib

from ...spectra.limit_states import parse_limit_state

# Agg before pyplot: figures are built on headless CI machines and in Snakemake jobs.
matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

P = ParamSpec("P")

RC = {
    "font.size": 9,
    "axes.titlesize": 9,
    "axes.labelsize": 9,
    "legend.fontsize": 7.5,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "lines.linewidth": 1.0,
    "savefig.dpi": 150,
}

MODE_STYLE = {
    "3d": {"color": "black", "linestyle": "-", "label": "3D"},
    "3d-damped": {"color": "black", "linestyle": "--", "label": "3D damped"},
    "2d-x": {"color": "tab:blue", "linestyle": "-.", "label": "2D, x component"},
    "2d-y": {"color": "tab:orange", "linestyle": ":", "label": "2D, y component"},
}
"""Line style per analysis mode, used wherever modes are compared."""

LIMIT_STATE_TITLES = {"overturning": "Overturning"}


def limit_state_title(limit_state: str) -> str:
    """Human title of a limit-state string (``"overturning"`` or ``"tilt:<r>"``)."""
    if limit_state in LIMIT_STATE_TITLES:
        return LIMIT_STATE_TITLES[limit_state]
    if limit_state.startswith("tilt:"):
        r = limit_state.split(":", 1)[1]
        return f"Tilt θ > {r}·α" if "/" in r else f"Tilt θ > {float(r):.3g}·α"
    return limit_state


def limit_state_sort_key(limit_state: str) -> float:
    """Order limit states from the mildest tilt to overturning (ratio r; inf for overturning)."""
    return parse_limit_state(limit_state).ratio


def styled(plot: Callable[P, Figure]) -> Callable[P, Figure]:
    """Decorator: run a ``plot`` function under the project's rc settings.

    Text sizes are read from rcParams when artists are created, so the whole plotting
    function (not only figure creation) must run inside the context; the global rcParams
    of the caller stay untouched.
    """

    @functools.wraps(plot)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> Figure:
        with plt.rc_context(RC):
            return plot(*args, **kwargs)

    return wrapper


def new_figure(width: float = 7.0, height: float = 4.5, **subplot_kw) -> tuple[Figure, object]:
    """A figure of ``width`` × ``height`` inches [in] with constrained layout.

    Extra keywords go to :meth:`Figure.subplots` (``nrows``, ``ncols``, ``sharex``, ...).
    Not attached to pyplot, so figures are garbage-collected and never shown.
    """
    fig = Figure(figsize=(width, height), layout="constrained")
    axes = fig.subplots(**subplot_kw) if subplot_kw else fig.subplots()
    return fig, axes


def save(fig: Figure, outputs: Sequence[str | Path]) -> list[Path]:
    """Write ``fig`` to every path in ``outputs`` (format from the suffix); return the paths."""
    paths = [Path(p) for p in outputs]
    if not paths:
        raise ValueError("outputs must name at least one file, got an empty list")
    for path in paths:
        if path.suffix.lower() not in {".png", ".pdf", ".svg"}:
            raise ValueError(f"output suffix must be .png, .pdf or .svg, got {str(path)!r}")
        path.parent.mkdir(parents=True, exist_ok=True)
        with plt.rc_context(RC):
            fig.savefig(path)
    return paths


def write_notes(path: str | Path, notes: dict) -> Path:
    """Write a figure's measured numbers and missing-data notes as JSON (read by the report)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(notes, indent=2, sort_keys=True, default=_jsonable) + "\n")
    return path


def _jsonable(value):
    # numpy scalars and arrays are the usual non-JSON values in the notes.
    if hasattr(value, "tolist"):
        return value.tolist()
    raise TypeError(f"not JSON serialisable: {type(value).__name__}")
