"""Stripe against first-exceedance fragility (beyond the paper), one figure per mode.

One panel per (limit state, R): the share of the motions exceeding at each stripe (markers)
and its binomial maximum-likelihood lognormal (solid, :mod:`rocking.spectra.stripes`), beside
the lognormal fitted to the motions' first-exceedance intensities (dashed,
:func:`rocking.spectra.fragility.fragility_table`). The first answers "at which intensity do
half of the motions exceed", the second "at which intensity does a motion first exceed"; a
body that exceeds in a narrow window of intensity and survives above it pulls the second
down only.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr
from matplotlib.figure import Figure
from matplotlib.ticker import FixedLocator, NullFormatter, ScalarFormatter
from scipy import stats

from ._style import MODE_STYLE, footnote, limit_state_title, new_figure, pga_g_axis, styled


def data(stripes: str | Path, fragility: str | Path | None, *, mode: str = "3d") -> dict:
    """Stripe fractions and both fits for every (limit state, R) of ``mode``.

    Returns
    -------
    dict
        ``panels``: [{``limit_state``, ``R``, ``x`` (stripes), ``fraction``, ``stripe``:
        (median, beta, status), ``first``: (median, beta, status)}], ``measured`` (medians
        and their ratio per panel), ``missing``, ``mode``, ``tan_alpha``.
    """
    from ..stripes import stripe_fits, stripe_table

    ds = xr.open_zarr(stripes, consolidated=True)
    if mode not in [str(m) for m in ds["mode"].values]:
        raise ValueError(f"mode {mode!r} is not in the stripes store {str(stripes)!r}")
    first = None
    if fragility is not None:
        with xr.open_dataset(fragility) as f:
            first = f.load()
    table = stripe_table(ds, first)
    fits = stripe_fits(ds)
    panels, measured, missing = [], {}, []
    for row in table[table["mode"] == mode].itertuples():
        r = fits[(mode, float(row.R))]
        j = r.limit_states.index(row.limit_state)
        panels.append({"limit_state": row.limit_state, "R": float(row.R),
                       "x": r.intensities, "fraction": r.fraction[:, j],
                       "stripe": (row.median, row.beta, row.status),
                       "first": (row.first_median, row.first_beta, row.first_status)})
        key = f"{row.limit_state}, R = {row.R:g} m"
        measured[key] = {"stripe_median": row.median, "first_exceedance_median":
                         row.first_median, "ratio": row.ratio, "stripe_status": row.status,
                         "stripe_reason": row.reason}
        if row.status != "ok":
            missing.append(f"{key}: {row.status}")
    return {"panels": panels, "measured": measured, "missing": missing, "mode": mode,
            "tan_alpha": float(ds.attrs.get("tan_alpha", np.nan))}


def _curve(ax, x: np.ndarray, fit: tuple, style: str, label: str, color: str) -> None:
    median, beta, status = fit
    if np.isfinite(median) and np.isfinite(beta):
        ax.plot(x, stats.norm.cdf(np.log(x / median) / beta), style, color=color,
                label=f"{label}: θ̂ = {median:.3g}, β = {beta:.2f}"
                + ("" if status == "ok" else f" [{status}]"))
    else:
        ax.plot([], [], style, color=color, label=f"{label}: no fit ({status})")


@styled
def plot(d: dict) -> Figure:
    """Panels in rows of limit states and columns of sizes R."""
    panels = d["panels"]
    states = list(dict.fromkeys(p["limit_state"] for p in panels)) or ["-"]
    sizes = sorted({p["R"] for p in panels}) or [0.0]
    fig, axes = new_figure(3.4 * len(sizes) + 0.6, 3.0 * len(states) + 0.9,
                           nrows=len(states), ncols=len(sizes), squeeze=False)
    color = MODE_STYLE.get(d["mode"], {}).get("color", "black")
    for p in panels:
        ax = axes[states.index(p["limit_state"])][sizes.index(p["R"])]
        x = np.asarray(p["x"], dtype=float)
        grid = np.geomspace(x[0], x[-1], 200)
        ax.plot(x, p["fraction"], "o", ms=3.5, mfc="none", color=color,
                label="share of motions exceeding")
        _curve(ax, grid, p["stripe"], "-", "stripes", color)
        _curve(ax, grid, p["first"], "--", "first exceedance", "tab:red")
        ax.set_xscale("log")
        # plain numbers at 1, 2, 5, 10, 20: log-axis labels like 3×10⁰ collide
        ax.xaxis.set_major_locator(FixedLocator([v for v in (1, 2, 5, 10, 20, 50)
                                                 if x[0] / 1.5 <= v <= x[-1] * 1.5]))
        ax.xaxis.set_major_formatter(ScalarFormatter())
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_ylim(-0.02, 1.02)
        ax.set_title(f"{limit_state_title(p['limit_state'])}, R = {p['R']:g} m", fontsize=9)
        ax.set_xlabel("PGA/(g tan α) [-]")
        ax.set_ylabel("P(exceeded) [-]")
        if np.isfinite(d["tan_alpha"]):  # one body per panel: its PGA in g on top
            top = pga_g_axis(ax, d["tan_alpha"], which="x")
            g = x * d["tan_alpha"]
            top.xaxis.set_major_locator(FixedLocator(
                [v for v in (0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10) if g[0] / 1.5 <= v <= g[-1] * 1.5]))
            top.xaxis.set_major_formatter(ScalarFormatter())
            top.xaxis.set_minor_formatter(NullFormatter())
        ax.legend(loc="best", fontsize=6)
    label = MODE_STYLE.get(d["mode"], {}).get("label", d["mode"])
    fig.suptitle(f"Stripe against first-exceedance fragility, {label} model, "
                 f"tan α = {d['tan_alpha']:g}")
    footnote(fig, ["Markers: share of the motions exceeding at each stripe; solid: its "
                   "binomial maximum-likelihood lognormal; dashed: lognormal of the motions' "
                   "first-exceedance intensities. PGA = vector peak.",
                   *(["Undefined or flagged stripe fits: " + "; ".join(d["missing"]) + "."]
                     if d["missing"] else [])])
    return fig
