"""Figure 10: mean performance spectra for every performance goal (θ > r·α and overturning).

Undamped 3D model, tan α = 0.2, mean over the ensemble (the study's ``mean_spectra.nc``).
The paper shows seven goals; a reduced run shows the limit states it computed.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib as mpl
import numpy as np
from matplotlib.figure import Figure

from . import _load
from ._style import MODE_STYLE, limit_state_sort_key, limit_state_title, new_figure, styled

TAN_ALPHA = 0.2
MODE = "3d"


def data(means: str | Path, *, tan_alpha: float = TAN_ALPHA, mode: str = MODE) -> dict:
    """Mean spectra per limit state: ``R`` [m], ``curves`` {limit state: PGA/(g tan α) (R,)}."""
    agg = _load.open_means(means)
    agg = _load.select_value(agg, "tan_alpha", tan_alpha)
    missing = []
    curves: dict[str, np.ndarray] = {}
    if mode not in _load.labels(agg, "mode"):
        missing.append(f"mode {mode} not computed")
    else:
        for ls in sorted(_load.labels(agg, "limit_state"), key=limit_state_sort_key):
            curves[ls] = _load.mean_curve(agg, mode, ls)
    return {"R": agg["R"].values.astype(float), "curves": curves, "tan_alpha": tan_alpha,
            "mode": mode, "missing": missing}


@styled
def plot(d: dict) -> Figure:
    """One panel, one line per goal, coloured from mild tilt (light) to overturning (dark)."""
    fig, ax = new_figure(5.5, 4.2)
    n = len(d["curves"])
    cmap = mpl.colormaps["viridis_r"]
    for i, (ls, y) in enumerate(d["curves"].items()):
        ax.plot(d["R"], y, color=cmap(0.15 + 0.85 * i / max(n - 1, 1)), lw=1.6, marker="o",
                ms=3, label=limit_state_title(ls))
    if not n:
        ax.text(0.5, 0.5, "; ".join(d["missing"]) or "no data", ha="center",
                transform=ax.transAxes)
    ax.set_xlabel("R [m]")
    ax.set_ylabel("mean PGA/(g tan α) [-]")
    ax.set_xlim(left=0.0)
    ax.set_ylim(bottom=0.0)
    ax.legend(loc="upper left", title="performance goal")
    ax.set_title(f"Mean spectra per performance goal, {MODE_STYLE[d['mode']]['label']} model, "
                 f"tan α = {d['tan_alpha']:g} (Fig 10)")
    return fig
