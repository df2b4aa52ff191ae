"""Fragility curves (beyond the paper): the distribution over the motions of their critical
intensity PGA/(g tan α), per size R.

Lines are the lognormal maximum-likelihood fits of :mod:`rocking.fragility.lognormal` (stored in
``results/<study>/fragility.nc``) to each motion's critical intensity (the study's quantity:
I₁₀ by default, the intensity where the motion's local exceedance probability first reaches
0.1); markers are the ensemble's empirical fractions of motions whose critical intensity is
at most the abscissa (not-reached motions never count). This is P(critical intensity ≤ x),
not the probability that a motion scaled to x exceeds the limit state: that is the ensemble's
exceedance probability F(s) of the jittered stripes (:mod:`rocking.plot.stripe_fragility`).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rocking.plot import _axes, _load
from rocking.plot._style import MODE_STYLE, pga_g_axis, styled, suptitle_and_notes, with_legend_row
from rocking.plot.comparisons import NOT_IN_PAPER, Comparison
from rocking.spectra.limit_states import limit_state_title
from rocking.spectra.modes import MODE_3D

if TYPE_CHECKING:
    from matplotlib.figure import Figure

MEDIAN_SYMBOL = "IM₅₀"
"""Symbol of the fitted median intensity (θ is the tilt everywhere else)."""



def data(fragility: str | Path, store: str | Path, *, tan_alpha: float | None = None,
         mode: str | None = None, n: int = 200, motions: str | Path | None = None) -> dict:
    """Fitted curves and empirical points of the study's limit states (overturning and
    excessive tilt in the paper; :func:`._load.panel_limit_states`).

    ``mode`` and ``tan_alpha`` default to the study's (:func:`._load.primary_mode`,
    :func:`._load.main_tan_alpha`).

    Returns
    -------
    dict
        ``panels``: [{``limit_state``, ``curves``: {R: {``median``, ``beta``, ``im``,
        ``p``, ``x_obs`` (sorted reached critical intensities), ``p_obs``}}}], ``missing``.
    """
    import xarray as xr
    from scipy import stats

    with xr.open_dataset(fragility) as f:
        frag = _load.canonical(f.load())
    axes = _axes.from_ensemble(motions)
    ds = _load.open_store(store)
    mode = mode or _load.primary_mode(ds) or MODE_3D
    if tan_alpha is None:
        tan_alpha = _load.main_tan_alpha(ds, [mode]) or float(ds["tan_alpha"].values[0])
    record, stand_in = _load.ensemble_label(dict(ds.attrs), Path(str(store)).parent.name)
    upper = _load.search_bound(ds.attrs)
    missing: list[str] = []
    if mode not in _load.labels(frag, "mode") or not _load.has_value(frag, "tan_alpha",
                                                                       tan_alpha):
        return {"panels": [], "mode": mode, "tan_alpha": tan_alpha, "axes": axes,
                "record": record, "stand_in": stand_in, "upper": upper,
                "missing": [f"mode {mode} at tan α = {tan_alpha:g} not computed"]}
    frag = _load.select_value(frag, "tan_alpha", tan_alpha).sel(mode=mode)
    ds = _load.select_value(ds, "tan_alpha", tan_alpha).sel(mode=mode)
    cells = _load.requested_cells(ds)  # the limit states the study asked for here
    states = [ls for ls in _load.labels(frag, "limit_state")
              if ls not in _load.labels(cells, "limit_state") or bool(cells.sel(limit_state=ls))]
    panels = []
    for ls in _load.panel_limit_states(states):
        title = limit_state_title(ls)
        curves = {}
        for R in frag["R"].values.astype(float):
            par = _load.select_value(frag.sel(limit_state=ls), "R", R)
            median, beta = float(par["median"]), float(par["beta"])
            pts = _load.select_value(ds.sel(limit_state=ls), "R", R)
            x = pts["pga_crit"].values.astype(float)
            reached = ~pts["not_reached"].values.astype(bool)
            x_obs = np.sort(x[reached])
            if not np.isfinite(median):
                missing.append(f"{title}, R = {R:g} m: no fit ({str(par['status'].values)})")
                continue
            curves[R] = {
                "median": median,
                "beta": beta,
                "x_obs": x_obs,
                # Fraction of all motions (censored included) at or below each value.
                "p_obs": np.arange(1, x_obs.size + 1) / x.size,
            }
        # One intensity axis per panel, wide enough for the ensemble's values and the medians
        # (a median fitted far beyond every observation is cut at 3x the largest one).
        x_all = np.concatenate([c["x_obs"] for c in curves.values()] or [np.array([1.0])])
        top = float(np.max(x_all, initial=1.0))
        medians = [c["median"] for c in curves.values()]
        im_max = 1.25 * max(top, min(max(medians, default=top), 3.0 * top))
        if upper is not None:  # nothing is known beyond the search bound
            im_max = min(im_max, upper)
        im = np.linspace(im_max / n, im_max, n)
        for c in curves.values():
            c["im"] = im
            c["p"] = stats.norm.cdf(np.log(im / c["median"]) / c["beta"])
        panels.append({"limit_state": ls, "curves": curves})
    return {"panels": panels, "mode": mode, "tan_alpha": tan_alpha, "missing": missing,
            "axes": axes, "record": record, "stand_in": stand_in, "upper": upper,
            "title": _load.ensemble_title(dict(ds.attrs), Path(str(store)).parent.name)}


def _highlighted(sizes: list[float], k: int = 5) -> list[float]:
    """About ``k`` sizes spread evenly over the range (the nearest of ``sizes`` to even steps
    from the smallest to the largest): the ones drawn thick, with their points, and named."""
    if len(sizes) <= k:
        return list(sizes)
    targets = np.linspace(min(sizes), max(sizes), k)
    return sorted({min(sizes, key=lambda R, t=t: abs(R - t)) for t in targets})


def _name_curve(ax, c: dict, R: float, height: float, color) -> None:
    """Write "R = … m" on the fitted curve at P = ``height`` (staggered per size, so that
    names of curves that lie close together do not overlap)."""
    from scipy import stats

    x = c["median"] * np.exp(c["beta"] * stats.norm.ppf(height))
    if not (np.isfinite(x) and x <= c["im"][-1]):  # that height lies past the drawn range
        x = 0.9 * float(c["im"][-1])
        height = float(stats.norm.cdf(np.log(x / c["median"]) / c["beta"]))
    ax.annotate(f"R = {R:g} m", (x, height), xytext=(5, 0), textcoords="offset points",
                fontsize=6.5, va="center", ha="left",
                bbox={"boxstyle": "round,pad=0.15", "facecolor": "white", "alpha": 0.85,
                      "edgecolor": color, "lw": 0.8})


@styled
def plot(d: dict) -> Figure:
    """Two panels; a few sizes R drawn thick with their points and named on the curve, the
    others thin and faint for context; colour = R on a colour bar that marks the named ones."""
    from matplotlib import colormaps
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize
    from matplotlib.lines import Line2D

    panels = d["panels"]
    # a row below the panels holds the legend (inside, it hid the largest size's curve)
    fig, axes, legend_row = with_legend_row(11.0, 5.1, ncols=max(len(panels), 1),
                                            legend_share=0.07)
    sizes = sorted({R for p in panels for R in p["curves"]}) or [0.0, 1.0]
    named = _highlighted(sizes)
    norm = Normalize(min(sizes), max(sizes) if max(sizes) > min(sizes) else min(sizes) + 1.0)
    cmap = colormaps["viridis"]
    for ax, panel in zip(axes, panels, strict=False):
        shown = [R for R in named if R in panel["curves"]]
        for R, c in panel["curves"].items():
            color = cmap(norm(R))
            if R not in shown:  # context: where the other sizes lie, not read one by one
                ax.plot(c["im"], c["p"], color=color, lw=0.7, alpha=0.4, zorder=1)
                continue
            ax.plot(c["im"], c["p"], color=color, lw=1.9, zorder=3)
            ax.plot(c["x_obs"], c["p_obs"], "o", color=color, ms=3.5, mfc="none", zorder=3)
        for j, R in enumerate(shown):  # the smallest named highest: its curve is the steepest
            height = 0.88 - 0.76 * j / max(len(shown) - 1, 1)
            _name_curve(ax, panel["curves"][R], R, height, cmap(norm(R)))
        ax.set_title(limit_state_title(panel["limit_state"]))
        ax.set_xlabel("PGA/(g tan α) [-]")
        ax.set_ylabel("share of motions whose critical intensity ≤ PGA/(g tan α) [-]")
        ax.set_ylim(-0.02, 1.02)
        # to the drawn intensities, which stop at the search bound: nothing is known beyond
        ax.set_xlim(0.0, max((float(c["im"][-1]) for c in panel["curves"].values()),
                             default=d.get("upper") or 1.0))
        pga_g_axis(ax, d["tan_alpha"], which="x")
    if panels:
        cbar = fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=list(axes))
        cbar.set_label("cylinder size R [m]")
        cbar.set_ticks(named)  # the named sizes, marked where their colour is
        cbar.set_ticklabels([f"{R:g}" for R in named])
    else:
        axes[0].text(0.5, 0.5, "; ".join(d["missing"]), ha="center", transform=axes[0].transAxes)
    record = d.get("record", "")
    who = d.get("title") or (
        f"{record}{' (stand-in)' if d.get('stand_in') and 'stand-in' not in record else ''}")
    bound = f"; search bound {d['upper']:g}" if d.get("upper") else ""
    title = (f"Fragility curves, {who}\n"
             f"{MODE_STYLE.get(d['mode'], {}).get('label', d['mode'])} model, "
             f"tan α = {d['tan_alpha']:g}{bound}; medians {MEDIAN_SYMBOL} and dispersions β "
             "in the report's table")
    suptitle_and_notes(fig, d, title, reduced="not every point was computed (note below)")
    others = max((len(p["curves"]) - len([R for R in named if R in p["curves"]])
                  for p in panels), default=0)
    if panels:
        legend_row.legend(handles=[Line2D([], [], color="0.3", lw=1.9,
                                   label="lognormal MLE fit, sizes named on the curve"),
                            Line2D([], [], ls="", marker="o", mfc="none", mec="0.3",
                                   label="ensemble: share of motions whose critical "
                                         "intensity is ≤ x (named sizes)"),
                            *([Line2D([], [], color="0.3", lw=0.7, alpha=0.4,
                                      label=f"the other {others} sizes: fit only (thin)")]
                              if others else [])],
                   loc="center", ncols=3, fontsize=7, frameon=False)
    return fig


# ------------------------------------------------------ comparison with the paper


def compare(notes: Mapping) -> list[Comparison]:
    """This figure's statements of the paper set against the run's notes."""
    return [Comparison("fragility_curves", "Lognormal fragility curves per size R", "—",
                       "see the fragility table", NOT_IN_PAPER,
                       "an addition for performance-based design")]


# ---------------------------------------------------------------- the figure's entry

from rocking.plot.registry import FigureSpec  # noqa: E402

FIGURE = FigureSpec(
    name="fragility_curves", module=__name__, number=13, label="fragility",
    caption=(
        "Fragility curves: lognormal maximum-likelihood fits of the distribution over the "
        "motions of their critical intensity PGA/(g tan α) per size R, the share of motions "
        "whose critical intensity is at most x (not the probability that a motion scaled to "
        "x exceeds the limit state: the stripes give that); motions that never reached the "
        "limit state are right-censored at the search bound; colour gives R on the colour "
        "bar; five sizes spread over the range are drawn thick, named on their curves and "
        "ticked on the colour bar, with their empirical fractions as markers, the others "
        "thin; the x "
        "axis runs a quarter beyond the largest intensity observed (or the largest median, "
        "at most three times that), never beyond the search bound. Medians IM₅₀ and "
        "dispersions β are tabulated in the report."
    ),
    scope="study", wanted=lambda s: bool(s.plan.modes),
    inputs={"fragility": "fragility_nc", "complete": "spectra", "motions": "motions"},
    params={"store": "spectra_store"},
    category="Beyond the paper")
"""The fragility curves (beyond the paper), for every study."""
