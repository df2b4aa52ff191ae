"""Figure 9: seismic performance rocking spectra per ground motion, with their mean.

Left overturning, right excessive tilt (θ > α/3), tan α = 0.2. Each motion has one colour;
undamped solid, damped dashed; the thick black line is the mean over the motions (from the
study's aggregate ``mean_spectra.nc``). Points where the limit state was not reached within
the search range are not drawn.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from . import _load
from ._style import limit_state_title, new_figure, styled

TAN_ALPHA = 0.2
MODES = ("3d", "3d-damped")
LINESTYLES = {"3d": "-", "3d-damped": "--"}


def data(store: str | Path, means: str | Path, *, tan_alpha: float = TAN_ALPHA,
         modes: tuple[str, ...] = MODES) -> dict:
    """Arrays of Fig 9 from the store and the aggregate.

    Returns
    -------
    dict
        ``R`` [m]; ``motions``; ``panels``: list of {``limit_state``, ``curves``:
        {mode: {motion: pga_crit (R,)}}, ``means``: {mode: mean (R,)}}; ``missing``: notes.
        Intensities are PGA/(g tan α) [-], NaN where not reached or not computed.
    """
    ds = _load.open_store(store)
    agg = _load.open_means(means)
    missing: list[str] = []
    if not _load.has_value(ds, "tan_alpha", tan_alpha):
        raise ValueError(f"tan_alpha={tan_alpha!r} is not in the store {str(store)!r}")
    ds = _load.select_value(ds, "tan_alpha", tan_alpha)
    agg = _load.select_value(agg, "tan_alpha", tan_alpha)
    states = _load.labels(ds, "limit_state")
    wanted = [("overturning", _load.find_limit_state(states, "overturning")),
              ("excessive tilt", _load.excessive_tilt(states))]
    store_modes = _load.labels(ds, "mode")
    motions = _load.labels(ds, "motion")
    panels = []
    for title, ls in wanted:
        if ls is None:
            missing.append(f"limit state {title} not computed")
            continue
        curves: dict[str, dict[str, np.ndarray]] = {}
        mean: dict[str, np.ndarray] = {}
        for mode in modes:
            if mode not in store_modes:
                missing.append(f"mode {mode} not computed")
                continue
            sel = ds.sel(mode=mode, limit_state=ls)
            vals = sel["pga_crit"].transpose("motion", "R").values.astype(float)
            reached = ~sel["not_reached"].transpose("motion", "R").values.astype(bool)
            curves[mode] = {m: np.where(reached[i], vals[i], np.nan)
                            for i, m in enumerate(motions)}
            m = _load.mean_curve(agg, mode, ls)
            if m is None:
                missing.append(f"mean of mode {mode} not aggregated")
            else:
                mean[mode] = m
        panels.append({"limit_state": ls, "curves": curves, "means": mean})
    measured = {}
    for panel in panels:
        m = panel["means"]
        if "3d" in m and "3d-damped" in m:
            # The paper's claim "undamped and damped spectra are essentially identical".
            rel = np.abs(m["3d-damped"] - m["3d"]) / m["3d"]
            measured[f"max_rel_diff_damped_{panel['limit_state']}"] = float(np.nanmax(rel))
    return {
        "measured": measured,
        "R": ds["R"].values.astype(float),
        "R_mean": agg["R"].values.astype(float),
        "motions": motions,
        "panels": panels,
        "tan_alpha": tan_alpha,
        "missing": sorted(set(missing)),
    }


@styled
def plot(d: dict) -> Figure:
    """Two panels (overturning, excessive tilt); individual spectra thin, mean thick."""
    panels = d["panels"]
    fig, axes = new_figure(10.0, 4.6, ncols=max(len(panels), 1), squeeze=False)
    axes = axes[0]
    colors = {m: f"C{i % 10}" for i, m in enumerate(d["motions"])}
    for ax, panel in zip(axes, panels, strict=False):
        for mode, curves in panel["curves"].items():
            for motion, y in curves.items():
                ax.plot(d["R"], y, color=colors[motion], ls=LINESTYLES.get(mode, "-"), lw=0.8,
                        marker=".", ms=3)
        for mode, y in panel["means"].items():
            ax.plot(d["R_mean"], y, color="black", lw=2.6, ls=LINESTYLES.get(mode, "-"),
                    label=f"mean, {'damped' if mode == '3d-damped' else 'undamped'}")
        ax.set_title(limit_state_title(panel["limit_state"]))
        ax.set_xlabel("R [m]")
        ax.set_ylabel("PGA/(g tan α) [-]")
        ax.set_xlim(left=0.0)
        ax.set_ylim(bottom=0.0)
        handles = [Line2D([], [], color=colors[m], lw=0.8, label=m) for m in d["motions"]]
        ax.legend(handles=ax.get_legend_handles_labels()[0] + handles, loc="upper left",
                  ncols=2 if len(handles) > 6 else 1)
    for ax in axes[len(panels):]:
        ax.text(0.5, 0.5, "no limit state computed", ha="center", transform=ax.transAxes)
    title = (f"Performance spectra, tan α = {d['tan_alpha']:g} (Fig 9); "
             "solid undamped, dashed damped")
    if d["missing"]:
        title += "\nmissing: " + "; ".join(d["missing"])
    fig.suptitle(title)
    return fig
