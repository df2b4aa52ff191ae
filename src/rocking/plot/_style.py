"""Shared look of the paper figures and the one way they are written to disk.

Every figure module calls :func:`new_figure` and :func:`save`, so sizes, fonts and file formats
stay the same across figures (PNG for the HTML report, PDF for print).
"""

from __future__ import annotations

import functools
import textwrap
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, ParamSpec

from rocking import _json
from rocking._validate import positive_finite
from rocking.spectra.limit_states import TILT_AXIS, severity
from rocking.spectra.modes import (
    MODE_2D_X,
    MODE_2D_Y,
    MODE_3D,
    MODE_3D_DAMPED,
    MODE_3D_X,
    MODE_3D_Y,
)

if TYPE_CHECKING:
    from matplotlib.figure import Figure

P = ParamSpec("P")


@functools.cache
def _pyplot():
    """matplotlib.pyplot, on the Agg backend (chosen before pyplot is first imported: figures
    are built on headless CI machines and in Snakemake jobs)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt

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

class _ModeStyles(dict):
    """A dict whose missing mode is one clear error (not a bare KeyError in a figure)."""

    def __missing__(self, mode):
        raise KeyError(f"mode {mode!r} has no plot style in rocking.plot._style.MODE_STYLE: "
                       f"add its colour, linestyle and label (docs/design.md, 'Adding a model')")


MODE_STYLE = _ModeStyles({
    MODE_3D: {"color": "black", "linestyle": "-", "label": "3D"},
    MODE_3D_DAMPED: {"color": "black", "linestyle": "--", "label": "3D damped"},
    MODE_3D_X: {"color": "tab:green", "linestyle": (0, (6, 2)), "label": "3D, x component"},
    MODE_3D_Y: {"color": "tab:purple", "linestyle": (0, (6, 2, 1, 2)),
                "label": "3D, y component"},
    MODE_2D_X: {"color": "tab:blue", "linestyle": "-.", "label": "2D, x component"},
    MODE_2D_Y: {"color": "tab:orange", "linestyle": ":", "label": "2D, y component"},
})
"""Line style per analysis mode, used wherever modes are compared; every mode of
:data:`rocking.spectra.modes.MODES` has one (``tests/test_design_registries.py``)."""

GOAL_COLORS = {0.1: "#9ecae1", 0.2: "#e6ab02", 1 / 3: "#2ca02c", 0.5: "#1f77b4",
               0.75: "#9467bd", 1.0: "#d62728", float("inf"): "black"}
"""Colour of each of the paper's goals θ > r·α (by r; overturning: inf), the same in every
figure that colours by goal."""


def goal_color(limit_state: str) -> str:
    """The colour of a performance goal, the same in every figure and study: the paper's
    goals from :data:`GOAL_COLORS`, another ratio r a shade of purple-to-yellow by r; a goal
    of the sliding axis a shade of brown by μ."""
    import matplotlib

    axis, r = severity(limit_state)
    if axis != TILT_AXIS:
        return matplotlib.colors.to_hex(matplotlib.colormaps["copper"](
            0.3 + 0.6 * min(r, 1.0)))
    for ratio, color in GOAL_COLORS.items():
        if abs(r - ratio) <= 1e-3 or r == ratio:
            return color
    return matplotlib.colors.to_hex(matplotlib.colormaps["plasma"](min(r, 1.0) * 0.85))


def paper_tag(d: dict, figure: str) -> str:
    """``" (Fig 9)"`` in the title of a reproduction of the paper (``d["paper"]``, default
    true), nothing for a study of one's own: its figures are named by what they show."""
    return f" ({figure})" if d.get("paper", True) else ""


def r_axis(ax, R, label: bool = True) -> None:
    """The x axis of a spectrum over sizes R [m], scaled to the study's range (from 0 when
    the study starts near it, as the paper's 0.5–10 m)."""
    import numpy as np

    r = np.asarray(R, dtype=float)
    r = r[np.isfinite(r)]
    if r.size:
        lo, hi = float(r.min()), float(r.max())
        pad = 0.04 * (hi - lo) if hi > lo else 0.5
        ax.set_xlim(0.0 if lo <= 0.1 * hi else lo - pad, hi + pad)
    if label:
        ax.set_xlabel("R [m]")


def plateau_suffix(k: int, n: int, what: str = "answers") -> str:
    """Legend suffix counting a curve's answers flagged ``plateau`` (``"; 3 of 20 answers
    on a plateau"``), empty when none: the count a reader can use, instead of a ring on
    every point."""
    return f"; {k} of {n} {what} on a plateau" if k else ""


def validity_suffix(slides: int, n: int) -> str:
    """Legend suffix counting a curve's answers whose analyses up to them needed more
    friction than the study's μ (``"; 2 of 20 slide"``), empty when none or without μ
    (docs/models.md, the validity flags). ``lifts_off`` is not counted here: nearly every
    overturning answer carries it (a body falling over leaves its support), so in a legend it
    would say nothing."""
    return f"; {slides} of {n} slide" if slides else ""


def styled(plot: Callable[P, Figure]) -> Callable[P, Figure]:
    """Decorator: run a ``plot`` function under the project's rc settings.

    Text sizes are read from rcParams when artists are created, so the whole plotting
    function (not only figure creation) must run inside the context; the global rcParams
    of the caller stay untouched.
    """

    @functools.wraps(plot)
    def wrapper(*args: P.args, **kwargs: P.kwargs) -> Figure:
        with _pyplot().rc_context(RC):
            return plot(*args, **kwargs)

    return wrapper


def new_figure(width: float = 7.0, height: float = 4.5, **subplot_kw) -> tuple[Figure, object]:
    """A figure of ``width`` × ``height`` inches [in] with constrained layout.

    Extra keywords go to :meth:`Figure.subplots` (``nrows``, ``ncols``, ``sharex``, ...).
    Not attached to pyplot, so figures are garbage-collected and never shown.
    """
    from matplotlib.figure import Figure

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
        # no creation date in a PDF or SVG: the same figure gives the same bytes, so a run
        # resumed after a kill ends with files identical to an uninterrupted run's
        dateless = {".pdf": {"CreationDate": None}, ".svg": {"Date": None}}
        with _pyplot().rc_context(RC):
            fig.savefig(path, metadata=dateless.get(path.suffix.lower()))
    return paths


def write_notes(path: str | Path, notes: dict) -> Path:
    """Write a figure's measured numbers and missing-data notes as JSON (read by the report)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    # strict JSON: a NaN measurement (e.g. a limit state not reached) is written as null
    path.write_text(_json.dumps(notes, indent=2, sort_keys=True) + "\n")
    return path


def footnote(fig: Figure, lines: Sequence[str], size: float = 7.0) -> None:
    """Write ``lines`` under the axes of ``fig`` (constrained layout keeps room for them).

    For what every figure must say but no axis label holds: which physical direction x and
    y are, and what a reduced run left out.
    """
    # ~0.6 font sizes per character (DejaVu Sans, with margins): wrap to the figure's width
    width = int(fig.get_figwidth() * 72.0 / (0.6 * size))
    lines = [w for line in lines if line for w in textwrap.wrap(str(line), width)]
    if not lines:
        return
    height = fig.get_figheight()
    # one text line is ~1.45 font sizes high [pt]; 72 pt per inch
    share = min(0.4, (len(lines) * 1.45 * size + 4.0) / 72.0 / height)
    engine = fig.get_layout_engine()
    if engine is not None and hasattr(engine, "set"):
        engine.set(rect=(0.0, share, 1.0, 1.0 - share))
    fig.text(0.01, share - 2.0 / 72.0 / height, "\n".join(lines), fontsize=size, ha="left",
             va="top", wrap=False)


def suptitle_and_notes(fig: Figure, d: dict, title: str, *,
                        reduced: str = "not everything the paper shows was computed (note below)",
                        intensity: str = "; PGA = vector peak.") -> None:
    """Suptitle of figure data ``d`` (a reduced run flagged), footnote of its gaps and axes."""
    if d["missing"]:
        title += "\nreduced run: " + reduced
    fig.suptitle(title)
    missing_and_axes_note(fig, d, intensity)


def missing_and_axes_note(fig: Figure, d: dict, intensity: str = "; PGA = vector peak.") -> None:
    """Footnote of what a reduced run left out of ``d`` and of the motions' principal axes."""
    footnote(fig, ["Not computed in this run: " + "; ".join(d["missing"]) + "."
                   if d["missing"] else "",
                   f"Motions on their principal axes: {d['axes']['text']}{intensity}"])


RECORD_COLOR = "black"
SYNTHETIC_COLORS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b",
                    "#e377c2", "#7f7f7f", "#bcbd22", "#17becf")
"""The record's colour and those of synthetic motions 1–10 (tab10): 11 distinct colours."""


def motion_label(index: int) -> str:
    """Reader's name of the ``index``-th motion of an ensemble (the record first)."""
    return "record" if index == 0 else f"synthetic {index}"


def motion_styles(names: Sequence[str],
                  sources: Sequence[str] | None = None) -> dict[str, dict[str, str]]:
    """One colour and label per motion, the same in every figure (Figs 8 and 9).

    ``names`` are the ensemble's motions in its order, the record first. Up to 10 synthetic
    motions get distinct colours; beyond that the cycle repeats (said by the caller's legend).
    ``sources`` (each motion's ``source_record``) tell a suite, whose recorded motions are
    their own source: those are labelled by name, the others "synthetic i".

    Returns
    -------
    dict
        name → {``label``: "record" / "synthetic i" (a suite: the record's name),
        ``color``: hex colour}.
    """
    recorded = [sources is not None and n == s for n, s in zip(names, sources or names,
                                                                  strict=True)]
    if sum(recorded) <= 1:
        return {n: {"label": motion_label(i),
                    "color": RECORD_COLOR if i == 0 else SYNTHETIC_COLORS[(i - 1) % 10]}
                for i, n in enumerate(names)}
    out, k = {}, 0
    for i, n in enumerate(names):
        k += not recorded[i]
        out[n] = {"label": n if recorded[i] else f"synthetic {k}",
                  "color": SYNTHETIC_COLORS[i % 10]}
    return out


def pga_g_axis(ax, tan_alpha: float, which: str = "y"):
    """A secondary axis in PGA [g] beside an axis in PGA/(g tan α) [-] (one slenderness).

    PGA [g] = tan α · PGA/(g tan α), so the secondary axis is a linear rescaling.
    """
    t = positive_finite("tan_alpha", tan_alpha)
    funcs = (lambda v: v * t, lambda v: v / t)
    sec = (ax.secondary_yaxis("right", functions=funcs) if which == "y"
           else ax.secondary_xaxis("top", functions=funcs))
    sec.set_ylabel(f"PGA [g] (tan α = {t:g})") if which == "y" else sec.set_xlabel(
        f"PGA [g] (tan α = {t:g})")
    return sec


def with_legend_row(width: float, height: float, ncols: int = 1,
                    legend_share: float = 0.2) -> tuple[Figure, list, object]:
    """A figure with ``ncols`` panels in one row and, below them, an empty row that holds
    the legend (an outside legend and a :func:`footnote` would share the bottom edge).

    Returns
    -------
    (Figure, list of Axes, Axes)
        The figure, its panels and the (axis-less) legend row.
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), layout="constrained")
    grid = fig.add_gridspec(2, ncols, height_ratios=(1.0, legend_share))
    axes = [fig.add_subplot(grid[0, i]) for i in range(ncols)]
    row = fig.add_subplot(grid[1, :])
    row.axis("off")
    return fig, axes, row
