"""Figure 11: mean performance spectra for tan α = 0.1, 0.2 and 0.3 (undamped 3D model).

Normalized by g tan α the spectra nearly coincide: slenderness acts mostly through
PGA/(g tan α) (paper §5.3). Slendernesses absent from a reduced run are listed as missing.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from . import _load
from ._style import MODE_STYLE, limit_state_title, new_figure, styled

TAN_ALPHAS = (0.1, 0.2, 0.3)
MODE = "3d"
COLORS = ("tab:blue", "black", "tab:red")


def data(means: str | Path, *, tan_alphas: tuple[float, ...] = TAN_ALPHAS,
         mode: str = MODE) -> dict:
    """``panels``: [{``limit_state``, ``curves`` {tan α: mean (R,)}}], ``R`` [m], ``missing``."""
    agg = _load.open_means(means)
    states = _load.labels(agg, "limit_state")
    missing = []
    if mode not in _load.labels(agg, "mode"):
        missing.append(f"mode {mode} not computed")
    present = [t for t in tan_alphas if _load.has_value(agg, "tan_alpha", t)]
    missing += [f"tan α = {t:g} not computed" for t in tan_alphas if t not in present]
    panels = []
    for title, ls in (("overturning", _load.find_limit_state(states, "overturning")),
                      ("excessive tilt", _load.excessive_tilt(states))):
        if ls is None:
            missing.append(f"limit state {title} not computed")
            continue
        curves: dict[float, np.ndarray] = {}
        for t in present:
            y = _load.mean_curve(_load.select_value(agg, "tan_alpha", t), mode, ls)
            if y is not None:
                curves[float(t)] = y
        panels.append({"limit_state": ls, "curves": curves})
    measured = {}
    for panel in panels:
        if len(panel["curves"]) >= 2:
            # Spread across slendernesses relative to their mean: the paper's "very small".
            y = np.vstack(list(panel["curves"].values()))
            spread = (np.nanmax(y, axis=0) - np.nanmin(y, axis=0)) / np.nanmean(y, axis=0)
            measured[f"max_rel_spread_{panel['limit_state']}"] = float(np.nanmax(spread))
    return {"R": agg["R"].values.astype(float), "panels": panels, "mode": mode,
            "missing": missing, "measured": measured}


@styled
def plot(d: dict) -> Figure:
    """Two panels (overturning, excessive tilt), one line per slenderness."""
    panels = d["panels"]
    fig, axes = new_figure(9.0, 4.0, ncols=max(len(panels), 1), squeeze=False)
    axes = axes[0]
    for ax, panel in zip(axes, panels, strict=False):
        for i, (t, y) in enumerate(panel["curves"].items()):
            ax.plot(d["R"], y, color=COLORS[i % len(COLORS)], lw=1.6, marker="o", ms=3,
                    label=f"tan α = {t:g}")
        ax.set_title(limit_state_title(panel["limit_state"]))
        ax.set_xlabel("R [m]")
        ax.set_ylabel("mean PGA/(g tan α) [-]")
        ax.set_xlim(left=0.0)
        ax.set_ylim(bottom=0.0)
        ax.legend(loc="upper left")
    title = f"Mean spectra for three slendernesses, {MODE_STYLE[d['mode']]['label']} model (Fig 11)"
    if d["missing"]:
        title += "\nmissing: " + "; ".join(d["missing"])
    fig.suptitle(title)
    return fig
