"""An inventory's columns under their hazard: λ on the site plan, and the columns ranked.

Reads ``portfolio.csv`` (:func:`rocking.risk.portfolio.portfolio_table`). Two figures:

- :func:`plot_map`: each column at its lon/lat (a local plan in metres east and north of the
  columns' centre when they span less than 20 km, else degrees), coloured by its mean annual
  frequency λ of the limit state on a log colour scale, labelled with its id; one panel per
  limit state (overturning and θ > α/3 where present); the hazard sites used as crosses.
- :func:`plot_ranked`: the columns ranked by λ of the most severe limit state, one bar each
  with its 90 % bootstrap interval, and the other limit state beside it; return period on
  the right axis.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure

from rocking.plot._style import footnote, new_figure, styled
from rocking.risk.portfolio import error_words
from rocking.risk.risk_table import shown_limit_states
from rocking.spectra.limit_states import limit_state_title, severity

CAPTION_MAP = (
    "Each column of the inventory at its position, coloured by its mean annual frequency λ "
    "of the limit state (log scale), from the study's fragility surface interpolated at the "
    "column's R and tan α and integrated against the hazard curve of its site (crosses: the "
    "hazard sites used).")
CAPTION_RANKED = (
    "The columns ranked by λ of the most severe limit state, with the 90 % interval over "
    "bootstrap resamples of the motions (record-to-record sampling only; the interpolation "
    "error of the surface is stated beside it); right axis: return period 1/λ.")

PLAN_KM = 20.0
"""Columns spanning less than this [km] are drawn on a local plan in metres."""

EARTH_M_PER_DEG = 111_194.9
"""Metres per degree of latitude (sphere of 6371 km)."""


def data(portfolio: str | Path | pd.DataFrame, *, hazard: str = "", study: str = "") -> dict:
    """What the two figures draw.

    Returns
    -------
    dict
        ``limit_states`` (most severe first, at most two), ``columns``: a frame of one row
        per column (id, lon, lat, x, y [m or deg], and per limit state ``lambda``,
        ``lambda_p05``, ``lambda_p95`` as ``<field>|<limit state>``), ``plan`` (True: x, y in
        m), ``sites`` (lon, lat, x, y of the hazard sites used), ``errors`` {limit state:
        interp_error}, ``measured`` {"λ max <ls> [1/yr]", ...}, ``hazard``, ``study``,
        ``missing`` (columns without lon/lat, not on the map).
    """
    frame = portfolio if isinstance(portfolio, pd.DataFrame) else pd.read_csv(portfolio)
    frame = frame.copy()
    frame["maf"] = frame["lambda"]  # shown_limit_states reads limit_state only
    states = sorted(shown_limit_states(frame), key=severity, reverse=True)
    cols = frame.drop_duplicates("id")[["id", "lon", "lat"]].set_index("id")
    for ls in states:
        part = frame[frame["limit_state"] == ls].set_index("id")
        for k in ("lambda", "lambda_p05", "lambda_p95"):
            cols[f"{k}|{ls}"] = part[k]
    lon, lat = cols["lon"].to_numpy(float), cols["lat"].to_numpy(float)
    located = np.isfinite(lon) & np.isfinite(lat)
    sites = frame.drop_duplicates("hazard_site")[["hazard_site", "hazard_lon", "hazard_lat"]]
    plan = False
    if located.any():
        lon0, lat0 = float(np.mean(lon[located])), float(np.mean(lat[located]))
        kx = EARTH_M_PER_DEG * np.cos(np.radians(lat0))
        span = max(np.ptp(lon[located]) * kx, np.ptp(lat[located]) * EARTH_M_PER_DEG)
        plan = span < PLAN_KM * 1000.0
        if plan:
            cols["x"], cols["y"] = (lon - lon0) * kx, (lat - lat0) * EARTH_M_PER_DEG
            sites = sites.assign(x=(sites["hazard_lon"] - lon0) * kx,
                                 y=(sites["hazard_lat"] - lat0) * EARTH_M_PER_DEG)
        else:
            cols["x"], cols["y"] = lon, lat
            sites = sites.assign(x=sites["hazard_lon"], y=sites["hazard_lat"])
    else:
        cols["x"] = cols["y"] = np.nan
        sites = sites.assign(x=np.nan, y=np.nan)
    errors = {ls: float(frame.loc[frame["limit_state"] == ls, "interp_error"].iloc[0])
              for ls in states}
    measured = {}
    for ls in states:
        lam = cols[f"lambda|{ls}"].to_numpy(float)
        if np.isfinite(lam).any():
            measured[f"λ max {ls} [1/yr]"] = float(np.nanmax(lam))
            measured[f"λ min {ls} [1/yr]"] = float(np.nanmin(lam))
            measured[f"highest {ls}"] = str(cols.index[int(np.nanargmax(lam))])
    return {"limit_states": states, "columns": cols.reset_index(), "plan": plan,
            "sites": sites, "errors": errors, "measured": measured, "hazard": hazard,
            "study": study, "missing": [str(i) for i in cols.index[~located]]}


def _norm(d: dict) -> LogNorm:
    values = np.concatenate([d["columns"][f"lambda|{ls}"].to_numpy(float)
                             for ls in d["limit_states"]])
    values = values[np.isfinite(values) & (values > 0)]
    lo, hi = (values.min(), values.max()) if values.size else (1e-4, 1e-2)
    if hi <= lo * 1.01:
        lo, hi = lo / 1.5, hi * 1.5
    return LogNorm(vmin=lo, vmax=hi)


@styled
def plot_map(d: dict) -> Figure:
    """One panel per limit state: the columns at their positions coloured by λ (log)."""
    n = len(d["limit_states"]) or 1
    fig, axes = new_figure(5.2 * n + 0.8, 5.0, ncols=n, squeeze=False)
    norm = _norm(d)
    cols = d["columns"]
    for ax, ls in zip(axes[0], d["limit_states"], strict=False):
        lam = cols[f"lambda|{ls}"].to_numpy(float)
        sc = ax.scatter(cols["x"], cols["y"], c=lam, norm=norm, cmap="viridis", s=90,
                        edgecolors="black", linewidths=0.6, zorder=3)
        for r in cols.itertuples():
            ax.annotate(str(r.id), (r.x, r.y), xytext=(4, 4), textcoords="offset points",
                        fontsize=7)
        site = d["sites"]
        if np.isfinite(site["x"]).any():
            ax.plot(site["x"], site["y"], "k+", ms=12, mew=1.5, label="hazard site", zorder=2)
            ax.legend(fontsize=8, loc="best")
        ax.set_title(f"{limit_state_title(ls)}")
        ax.set_xlabel("east [m]" if d["plan"] else "longitude [deg]")
        ax.set_ylabel("north [m]" if d["plan"] else "latitude [deg]")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, alpha=0.3)
    fig.colorbar(sc, ax=axes[0].tolist(), label="mean annual frequency λ [1/yr]",
                 shrink=0.85)
    who = f"{d['study']}: " if d.get("study") else ""
    fig.suptitle(f"{who}λ of each column at its position"
                 + (f"\nhazard: {d['hazard']}" if d.get("hazard") else ""), fontsize=10)
    foot = []
    if d["plan"]:
        foot.append("Local plan: metres east and north of the columns' centre.")
    if d["missing"]:
        foot.append(f"Not on the map (no lon/lat): {', '.join(d['missing'])}.")
    footnote(fig, foot)
    return fig


@styled
def plot_ranked(d: dict) -> Figure:
    """The columns ranked by λ of the most severe limit state, bars with 90 % intervals."""
    states = d["limit_states"]
    cols = d["columns"].copy()
    first = states[0]
    cols = cols.sort_values(f"lambda|{first}", ascending=False, kind="stable")
    n = len(cols)
    fig, ax = new_figure(max(6.0, 0.55 * n + 2.5), 4.8)
    width = 0.8 / len(states)
    colors = ("#b2182b", "#2166ac")
    x = np.arange(n)
    for j, ls in enumerate(states):
        lam = cols[f"lambda|{ls}"].to_numpy(float)
        lo, hi = cols[f"lambda_p05|{ls}"].to_numpy(float), cols[f"lambda_p95|{ls}"].to_numpy(
            float)
        xs = x + (j - (len(states) - 1) / 2) * width
        ax.bar(xs, lam, width, color=colors[j % 2], alpha=0.8,
               label=f"{limit_state_title(ls)} (interpolation error of the median "
                     f"{error_words(d['errors'][ls])})")
        # the interval as drawn from its ends, not as ± about λ: with few motions λ may lie
        # outside its own bootstrap interval, and that is shown, not clipped
        shown = np.isfinite(lo) & np.isfinite(hi)
        ax.vlines(xs[shown], lo[shown], hi[shown], color="k", lw=1.0)
        for end in (lo, hi):
            ax.plot(xs[shown], end[shown], ls="none", marker="_", color="k", ms=6)
    ax.set_yscale("log")
    top = np.nanmax([cols[f"lambda_p95|{ls}"].max() for ls in states]
                    + [cols[f"lambda|{ls}"].max() for ls in states])
    if np.isfinite(top) and top > 0:
        ax.set_ylim(top=top * 2.5)  # room for the legend above the bars
    ax.set_xticks(x, cols["id"].astype(str), rotation=45, ha="right")
    ax.set_xlabel(f"column, ranked by λ of {limit_state_title(first).lower()} (highest first)")
    ax.set_ylabel("mean annual frequency λ [1/yr]")
    ax.grid(True, axis="y", which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="upper right")
    right = ax.secondary_yaxis("right", functions=(_inverse, _inverse))
    right.set_ylabel("return period [yr]")
    who = f"{d['study']}: " if d.get("study") else ""
    fig.suptitle(f"{who}columns ranked by mean annual frequency; bars: 90 % bootstrap "
                 "interval" + (f"\nhazard: {d['hazard']}" if d.get("hazard") else ""),
                 fontsize=10)
    return fig


def _inverse(x):
    x = np.asarray(x, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(x > 0, 1.0 / np.where(x > 0, x, 1.0), np.inf)


__all__ = ["CAPTION_MAP", "CAPTION_RANKED", "FIGURE", "data", "plot_map", "plot_ranked"]


def _arguments(inputs, params) -> dict:
    """``data()``'s keywords: the study named as its report names it."""
    return {"portfolio": inputs["portfolio"], "hazard": str(params["hazard_file"] or ""),
            "study": f"study {params['study']}"}


from rocking.plot.registry import FigureSpec  # noqa: E402

_ENTRY = dict(module=__name__, scope="study", wanted=lambda s: s.spec().inventory is not None,
              inputs={"portfolio": "portfolio"},
              params={"hazard_file": "hazard_file", "study": "study"}, arguments=_arguments,
              section="portfolio", category="Beyond the paper")
FIGURE = (
    FigureSpec(name="portfolio_map", number=16, label="portfolio map", caption=CAPTION_MAP,
               plot="plot_map", **_ENTRY),
    FigureSpec(name="portfolio_ranked", number=17, label="portfolio ranked",
               caption=CAPTION_RANKED, plot="plot_ranked", **_ENTRY),
)
"""The two figures of a study's inventory, drawn from one ``data``."""
