"""Figure 10: mean performance spectra for every performance goal (θ > r·α and overturning).

Undamped 3D model, tan α = 0.2, mean over the ensemble (the study's ``mean_spectra.nc``).
The paper shows seven goals; a reduced run shows the goals it computed and names the others.
Every curve gets a least-squares line in R (the paper: "almost straight lines").
"""

from __future__ import annotations

from pathlib import Path

import matplotlib as mpl
import numpy as np
from matplotlib.figure import Figure

from ...spectra.fragility import fit_line
from ...spectra.limit_states import DEFAULT_LIMIT_STATES
from . import _axes, _load
from ._style import (
    MODE_STYLE,
    _missing_and_axes_note,
    limit_state_sort_key,
    limit_state_title,
    new_figure,
    styled,
)

TAN_ALPHA = 0.2
MODE = "3d"
PAPER_GOALS = DEFAULT_LIMIT_STATES
"""The seven performance goals of the paper's Fig 10."""


def data(means: str | Path, *, tan_alpha: float = TAN_ALPHA, mode: str = MODE,
         motions: str | Path | None = None) -> dict:
    """Mean spectra per limit state: ``R`` [m], ``curves`` {limit state: PGA/(g tan α) (R,)},
    ``missing`` (goals, mode or slenderness not computed), ``measured`` line fits per goal."""
    agg = _load.open_means(means)
    missing = []
    curves: dict[str, np.ndarray] = {}
    R = agg["R"].values.astype(float)
    if not _load.has_value(agg, "tan_alpha", tan_alpha):
        missing.append(f"tan α = {tan_alpha:g} not computed")
    elif mode not in _load.labels(agg, "mode"):
        missing.append(f"mode {mode} not computed")
    else:
        agg = _load.select_value(agg, "tan_alpha", tan_alpha)
        for ls in sorted(_load.labels(agg, "limit_state"), key=limit_state_sort_key):
            y = _load.mean_curve(agg, mode, ls)
            if y is not None:
                curves[ls] = y
    absent = [g for g in PAPER_GOALS if _load.find_limit_state(list(curves), g) is None]
    if absent and not missing:
        missing.append(f"{len(absent)} of the paper's {len(PAPER_GOALS)} goals not computed: "
                       + ", ".join(limit_state_title(g) for g in absent))
    measured = {"n_goals": len(curves), "n_paper_goals": len(PAPER_GOALS),
                "absent_goals": absent}
    for ls, y in curves.items():
        fit = fit_line(R, y)
        measured[f"line|{ls}"] = {"slope": fit.slope, "intercept": fit.intercept,
                                  "r_squared": fit.r_squared, "n": fit.n}
    return {"R": R, "curves": curves, "tan_alpha": tan_alpha, "mode": mode,
            "missing": missing, "measured": measured, "axes": _axes.from_ensemble(motions)}


@styled
def plot(d: dict) -> Figure:
    """One panel, one line per goal, coloured from mild tilt (light) to overturning (dark)."""
    fig, ax = new_figure(6.0, 5.0)
    n = len(d["curves"])
    cmap = mpl.colormaps["viridis_r"]
    for i, (ls, y) in enumerate(d["curves"].items()):
        r2 = d["measured"].get(f"line|{ls}", {}).get("r_squared", np.nan)
        ax.plot(d["R"], y, color=cmap(0.15 + 0.85 * i / max(n - 1, 1)), lw=1.6, marker="o",
                ms=3, label=f"{limit_state_title(ls)} (line fit R² = {r2:.3f})")
    if not n:
        ax.text(0.5, 0.5, "; ".join(d["missing"]) or "no data", ha="center",
                transform=ax.transAxes)
    ax.set_xlabel("R [m]")
    ax.set_ylabel("mean PGA/(g tan α) [-]")
    ax.set_xlim(left=0.0)
    ax.set_ylim(bottom=0.0)
    ax.legend(loc="upper left", title="performance goal", fontsize=7)
    title = (f"Mean spectra per performance goal, {MODE_STYLE[d['mode']]['label']} model, "
             f"tan α = {d['tan_alpha']:g} (Fig 10)")
    m = d["measured"]
    if d["missing"]:
        title += f"\nreduced run: {m['n_goals']} of the paper's {m['n_paper_goals']} goals"
    ax.set_title(title, fontsize=8)
    _missing_and_axes_note(fig, d)
    return fig
