"""Figure 11: mean performance spectra per slenderness (undamped 3D model).

The paper's tan α = 0.1, 0.2 and 0.3, or a study's own slendernesses. Normalized by g tan α
the spectra nearly coincide: slenderness acts mostly through PGA/(g tan α) (paper §5.3). In a
reproduction of the paper, slendernesses absent from a reduced run are named in the figure.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rocking.plot import _axes, _load
from rocking.plot._style import (
    MODE_STYLE,
    new_figure,
    paper_tag,
    r_axis,
    styled,
    suptitle_and_notes,
)
from rocking.plot.comparisons import NOT_COMPUTED, Comparison, finite, first_notes, fmt, judged
from rocking.spectra.limit_states import limit_state_title
from rocking.spectra.modes import MODE_3D

if TYPE_CHECKING:
    from matplotlib.figure import Figure

PAPER_TAN_ALPHAS = (0.1, 0.2, 0.3)
"""The slendernesses of the paper's Fig 11."""
TAN_ALPHAS_NOTE = "tan_alphas|"
"""Prefix of the measured key of the slendernesses drawn for one limit state."""
SPREAD_NOTE = "max_rel_spread_"
"""Prefix of the measured key of the largest spread across slendernesses."""
STYLES = {0.1: ("tab:blue", "s"), 0.2: ("black", "o"), 0.3: ("tab:red", "^")}
"""Colour and marker per slenderness (others cycle through the default colours)."""


def data(means: str | Path, *, tan_alphas: tuple[float, ...] | None = None,
         mode: str | None = None, motions: str | Path | None = None,
         paper: bool = True) -> dict:
    """``panels``: [{``limit_state``, ``curves`` {tan α: mean (R,)}}], ``R`` [m], ``missing``,
    ``measured``: spread across slendernesses and line fits per curve.

    ``tan_alphas`` default to the paper's (``paper``: a reproduction, absent ones named) or
    else to those the study computed for ``mode`` (default its primary mode).
    """
    agg = _load.open_means(means)
    mode = mode or _load.primary_mode(agg) or MODE_3D
    if tan_alphas is None:
        cells = _load.requested_cells(agg)
        own = tuple(float(t) for t in agg["tan_alpha"].values
                    if mode in _load.labels(agg, "mode")
                    and bool(cells.sel(mode=mode).sel(tan_alpha=t).any()))
        tan_alphas = PAPER_TAN_ALPHAS if paper else own
    states = _load.labels(agg, "limit_state")
    missing = []
    if mode not in _load.labels(agg, "mode"):
        missing.append(f"mode {mode} not computed")
    present = [t for t in tan_alphas if _load.has_value(agg, "tan_alpha", t)]
    panels = []
    for ls in (_load.panel_limit_states(states) if not paper else
               [ls for _title, ls in _load.paper_limit_states(states, missing)]):
        curves: dict[float, np.ndarray] = {}
        for t in present:
            y = _load.mean_curve(_load.select_value(agg, "tan_alpha", t), mode, ls)
            if y is not None:
                curves[float(t)] = y
        panels.append({"limit_state": ls, "curves": curves})
    shown = {t for p in panels for t in p["curves"]}
    absent = [t for t in tan_alphas if t not in shown]
    if absent and mode in _load.labels(agg, "mode"):
        missing.append("tan α = " + ", ".join(f"{t:g}" for t in absent) + " not computed")
    R = agg["R"].values.astype(float)
    return {"R": R, "panels": panels, "mode": mode, "missing": missing,
            "answer": _load.answer_label(agg.attrs),
            "answer_definition": _load.answer_definition(agg.attrs),
            "measured": {**measurements(R, panels), "answer": _load.answer_label(agg.attrs)},
            "axes": _axes.from_ensemble(motions),
            "paper": paper, "title": _load.ensemble_title(dict(agg.attrs),
                                                          Path(str(means)).parent.name)}


def measurements(R: np.ndarray, panels: list[dict]) -> dict:
    """Largest relative spread across slendernesses per limit state, and line fits."""
    from rocking.fragility.lognormal import fit_line

    measured: dict = {}
    for panel in panels:
        ls = panel["limit_state"]
        measured[TAN_ALPHAS_NOTE + ls] = sorted(panel["curves"])
        if len(panel["curves"]) >= 2:
            # Spread across slendernesses relative to their mean: the paper's "very small".
            y = np.vstack(list(panel["curves"].values()))
            spread = (np.nanmax(y, axis=0) - np.nanmin(y, axis=0)) / np.nanmean(y, axis=0)
            measured[SPREAD_NOTE + ls] = float(np.nanmax(spread))
        for t, y in panel["curves"].items():
            fit = fit_line(R, y)
            measured[f"line|{ls}|{t:g}"] = {"slope": fit.slope, "intercept": fit.intercept,
                                           "r_squared": fit.r_squared, "n": fit.n}
    return measured


@styled
def plot(d: dict) -> Figure:
    """Two panels (overturning, excessive tilt), one line per slenderness."""
    panels = d["panels"]
    fig, axes = new_figure(9.0, 4.4, ncols=max(len(panels), 1), squeeze=False)
    axes = axes[0]
    for ax, panel in zip(axes, panels, strict=False):
        for i, (t, y) in enumerate(panel["curves"].items()):
            color, marker = STYLES.get(t, (f"C{i % 10}", "d"))
            ax.plot(d["R"], y, color=color, lw=1.6, marker=marker, ms=3.5, label=f"tan α = {t:g}")
        ax.set_title(limit_state_title(panel["limit_state"]))
        ax.set_ylabel(f"mean {d.get('answer', 'critical')} PGA/(g tan α) [-]")
        r_axis(ax, d["R"])
        ax.set_ylim(bottom=0.0)
        ax.legend(loc="upper left", title=f"mean {d.get('answer', '')} per slenderness".strip(),
                  title_fontsize=7)
    suptitle_and_notes(
        fig, d, f"Mean spectra per slenderness, {d.get('title', 'ensemble')},\n"
        f"{MODE_STYLE[d['mode']]['label']} model{paper_tag(d, 'Fig 11')}")
    return fig


# ------------------------------------------------------ comparison with the paper


def compare(notes: Mapping) -> list[Comparison]:
    """This figure's statements of the paper set against the run's notes."""
    m = first_notes(notes, "fig11_slenderness").get("measured", {})
    rows = []
    for key, t in m.items():
        if not key.startswith(TAN_ALPHAS_NOTE):
            continue
        ls = key.removeprefix(TAN_ALPHAS_NOTE)
        spread = m.get(SPREAD_NOTE + ls)
        rows.append(judged(
            "fig11_slenderness", f"Slenderness has 'a very small influence' once the intensity "
            f"is normalized by g tan α, {limit_state_title(ls)} (§5.3)", "very small influence",
            f"largest spread among tan α = {', '.join(f'{v:g}' for v in t)}: "
            f"{fmt(100 * spread, 3) if finite(spread) else '—'} % of the mean",
            spread <= 0.15 if finite(spread) else None, "spread ≤ 15 % of the mean at every R",
            "slenderness changes the normalized spectra beyond the tolerance",
            f"only tan α = {', '.join(f'{v:g}' for v in t) or 'none'} computed"))
    return rows or [Comparison("fig11_slenderness", "Influence of slenderness (§5.3)",
                               "very small", "—", NOT_COMPUTED, "no mean spectra")]


# ---------------------------------------------------------------- the figure's entry

from rocking.plot.registry import FigureSpec  # noqa: E402


def _wanted(subject) -> bool:
    """Two or more tan α computed for the study's primary mode ("3d", else its first)."""
    plan = subject.plan
    if not plan.modes:
        return False
    mode = MODE_3D if MODE_3D in plan.modes else plan.modes[0]
    return sum(bool(plan.limit_states_of(mode, t)) for t in plan.tan_alpha) > 1


FIGURE = FigureSpec(
    name="fig11_slenderness", module=__name__, number=11, label="Fig 11",
    caption=(
        "Mean performance spectra (undamped 3D model) per slenderness tan α of the study, "
        "the intensity normalized by g tan α; the means are of each motion's critical "
        "intensity, I10 by default, as the legend says."
    ),
    paper=(
        "The paper's Fig 11: tan α = 0.1, 0.2 and 0.3; it reports that, once the intensity "
        "is normalized by g tan α, slenderness has a very small influence. Slendernesses "
        "this run did not compute are named in the figure."
    ),
    scope="study", wanted=_wanted,
    inputs={"means": "means", "motions": "motions"},
    params={"paper": "paper"},
    el_centro_only=True)
"""Fig 11, for a study with two or more tan α."""
