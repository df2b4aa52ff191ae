"""An inventory's columns under their hazard: λ on the site plan, and the columns ranked.

Reads ``portfolio.csv`` (:func:`rocking.risk.portfolio.portfolio_table`). Two figures:

- :func:`plot_map`: each column at its lon/lat (a local plan in metres east and north of the
  columns' centre when they span less than 20 km, else degrees), coloured by its mean annual
  frequency λ of the limit state on a log colour scale, labelled with its id (labels placed
  where they overlap no other label or marker, with a leader line where they had to move);
  one panel per limit state (overturning and θ > α/3 where present); the hazard sites used
  as crosses, labelled, each column joined to its own by a thin line.
- :func:`plot_ranked`: the columns ranked by λ of the most severe limit state, a point each
  with its 90 % bootstrap interval as a bar, on a log axis (a point, not a bar from an
  arbitrary baseline), the other limit state beside it; return period on the right axis; the
  site's answer (expected number per year, bounds on "at least one") said under it.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rocking.motions.measures import DEFAULT_COMPONENT
from rocking.plot._style import footnote, new_figure, styled
from rocking.spectra.limit_states import limit_state_title, severity

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.colors import LogNorm
    from matplotlib.figure import Figure

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
        per column (id, lon, lat, x, y [m or deg], its hazard site's ``sx``, ``sy``, and per
        limit state ``lambda``, ``lambda_p05``, ``lambda_p95`` as ``<field>|<limit
        state>``), ``plan`` (True: x, y in m), ``sites`` (the hazard sites used: label, lon,
        lat, x, y), ``errors`` {limit state: interp_error}, ``site`` {limit state: the
        site's answer, :func:`rocking.risk.portfolio.site_answer`}, ``measured`` {"λ max
        <ls> [1/yr]", ...}, ``terms`` (measure and component), ``hazard``, ``study``,
        ``missing`` (columns without lon/lat, not on the map).
    """
    import pandas as pd

    from rocking.risk.portfolio import read_portfolio, site_answer
    from rocking.risk.risk_table import shown_limit_states

    frame = portfolio if isinstance(portfolio, pd.DataFrame) else read_portfolio(portfolio)
    # the site's answer with its interval, where portfolio_site.csv is beside the table
    site_csv = (Path(portfolio).with_name("portfolio_site.csv")
                if not isinstance(portfolio, pd.DataFrame) else None)
    saved = (pd.read_csv(site_csv) if site_csv is not None and site_csv.is_file()
             else pd.DataFrame(frame.attrs["site"]) if frame.attrs.get("site") else None)
    if saved is not None:
        saved = saved.set_index("limit_state")
    frame = frame.copy()
    frame["maf"] = frame["lambda"]  # shown_limit_states reads limit_state only
    states = sorted(shown_limit_states(frame), key=severity, reverse=True)
    cols = frame.drop_duplicates("id")[["id", "lon", "lat", "hazard_site", "hazard_lon",
                                       "hazard_lat"]].set_index("id")
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
            def to_xy(lo, la):
                return (lo - lon0) * kx, (la - lat0) * EARTH_M_PER_DEG
        else:
            def to_xy(lo, la):
                return lo, la
        cols["x"], cols["y"] = to_xy(lon, lat)
        cols["sx"], cols["sy"] = to_xy(cols["hazard_lon"].to_numpy(float),
                                       cols["hazard_lat"].to_numpy(float))
        sx, sy = to_xy(sites["hazard_lon"].to_numpy(float), sites["hazard_lat"].to_numpy(float))
        sites = sites.assign(x=sx, y=sy)
    else:
        cols["x"] = cols["y"] = cols["sx"] = cols["sy"] = np.nan
        sites = sites.assign(x=np.nan, y=np.nan)
    errors = {ls: float(frame.loc[frame["limit_state"] == ls, "interp_error"].iloc[0])
              for ls in states}
    measured, answer = {}, {}
    for ls in states:
        lam = cols[f"lambda|{ls}"].to_numpy(float)
        if np.isfinite(lam).any():
            measured[f"λ max {ls} [1/yr]"] = float(np.nanmax(lam))
            measured[f"λ min {ls} [1/yr]"] = float(np.nanmin(lam))
            measured[f"highest {ls}"] = str(cols.index[int(np.nanargmax(lam))])
        answer[ls] = (saved.loc[ls].to_dict() | {"limit_state": ls}
                      if saved is not None and ls in saved.index else site_answer(ls, lam, None))
        measured[f"expected {ls} per year"] = float(answer[ls]["expected_per_year"])
    first = frame.iloc[0]
    terms = f"{first.get('measure', 'pga')}, {first.get('component', DEFAULT_COMPONENT)} component"
    return {"limit_states": states, "columns": cols.reset_index(), "plan": plan,
            "sites": sites, "errors": errors, "site": answer, "measured": measured,
            "terms": terms, "hazard": hazard, "study": study,
            "missing": [str(i) for i in cols.index[~located]]}


def _norm(d: dict) -> LogNorm:
    from matplotlib.colors import LogNorm

    values = np.concatenate([d["columns"][f"lambda|{ls}"].to_numpy(float)
                             for ls in d["limit_states"]])
    values = values[np.isfinite(values) & (values > 0)]
    lo, hi = (values.min(), values.max()) if values.size else (1e-4, 1e-2)
    if hi <= lo * 1.01:
        lo, hi = lo / 1.5, hi * 1.5
    return LogNorm(vmin=lo, vmax=hi)


LABEL_OFFSETS = [(6, 3), (6, -9), (-6, 3), (-6, -9), (9, -3), (-9, -3), (0, 9), (0, -15),
                 (14, 12), (-14, 12), (14, -18), (-14, -18), (20, -3), (-20, -3), (0, 20),
                 (0, -26)]
"""Offsets [pt] tried in turn for a column's label, nearest first (left-aligned to the right
of the marker, right-aligned to its left)."""


def place_labels(ax, xs, ys, texts, fontsize: float = 7.0) -> list:
    """Each label at the first offset (:data:`LABEL_OFFSETS`) where its box overlaps no
    label placed before and no marker; a label that moved beyond the first ring gets a
    leader line. Returns the text artists."""
    fig = ax.figure
    renderer = fig.canvas.get_renderer()  # an Agg canvas: plot_map gives the figure one
    to_px = ax.transData.transform
    markers = [to_px((x, y)) for x, y in zip(xs, ys, strict=True)]
    marker_r = 6.0 * fig.dpi / 72.0  # half a marker of s=90 [px]
    placed, artists = [], []
    for i, ((x, y), text) in enumerate(zip(zip(xs, ys, strict=True), texts, strict=True)):
        others = markers[:i] + markers[i + 1:]  # its own marker is beside it by design
        best = None
        for k, (dx, dy) in enumerate(LABEL_OFFSETS):
            t = ax.annotate(str(text), (x, y), xytext=(dx, dy), textcoords="offset points",
                            fontsize=fontsize, ha="left" if dx >= 0 else "right",
                            va="bottom" if dy >= 0 else "top")
            box = t.get_window_extent(renderer).expanded(1.05, 1.1)
            clash = any(box.overlaps(b) for b in placed) or any(
                box.x0 - marker_r < mx < box.x1 + marker_r
                and box.y0 - marker_r < my < box.y1 + marker_r for mx, my in others)
            if not clash:
                best = (t, box, k)
                break
            t.remove()
        if best is None:  # nowhere free: the first place, said by its leader
            t = ax.annotate(str(text), (x, y), xytext=LABEL_OFFSETS[-1],
                            textcoords="offset points", fontsize=fontsize, ha="left")
            best = (t, t.get_window_extent(renderer), len(LABEL_OFFSETS))
        t, box, k = best
        t.set_in_layout(False)  # placed on the final layout: it must not move the axes
        if k >= 8:
            t.remove()
            dx, dy = LABEL_OFFSETS[min(k, len(LABEL_OFFSETS) - 1)]
            t = ax.annotate(str(text), (x, y), xytext=(dx, dy), textcoords="offset points",
                            fontsize=fontsize, ha="left" if dx >= 0 else "right",
                            va="bottom" if dy >= 0 else "top",
                            arrowprops={"arrowstyle": "-", "lw": 0.5, "color": "0.4"})
            t.set_in_layout(False)
        placed.append(box)
        artists.append(t)
    return artists


@styled
def plot_map(d: dict) -> Figure:
    """One panel per limit state: the columns at their positions coloured by λ (log), each
    joined to the hazard site it takes."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    n = len(d["limit_states"]) or 1
    fig, axes = new_figure(5.2 * n + 0.8, 5.2, ncols=n, squeeze=False)
    FigureCanvasAgg(fig)  # a renderer to measure the labels with
    norm = _norm(d)
    cols = d["columns"]
    site = d["sites"]
    shown = np.isfinite(site["x"]) & np.isfinite(site["y"])
    span = max(np.ptp(cols["x"].dropna()), np.ptp(cols["y"].dropna()), 1e-9) \
        if cols["x"].notna().any() else 0.0
    cx, cy = cols["x"].mean(), cols["y"].mean()
    # a site far beyond the columns would shrink them to a dot: joined only when near
    near = shown & (np.hypot(site["x"] - cx, site["y"] - cy) <= 3.0 * span + 1e-9)
    for ax, ls in zip(axes[0], d["limit_states"], strict=False):
        lam = cols[f"lambda|{ls}"].to_numpy(float)
        joined = np.isfinite(cols["sx"]) & np.isfinite(cols["x"]) & np.isin(
            cols["hazard_site"], site.loc[near, "hazard_site"])
        for r in cols[joined].itertuples():
            ax.plot([r.x, r.sx], [r.y, r.sy], "-", color="0.6", lw=0.6, zorder=1)
        sc = ax.scatter(cols["x"], cols["y"], c=lam, norm=norm, cmap="viridis", s=90,
                        edgecolors="black", linewidths=0.6, zorder=3)
        if near.any():
            ax.plot(site.loc[near, "x"], site.loc[near, "y"], "k+", ms=12, mew=1.5, zorder=2,
                    label="hazard site (thin lines: the site each column takes)")
            for r in site[near].itertuples():
                ax.annotate(f"site {r.hazard_site}", (r.x, r.y), xytext=(6, -12),
                            textcoords="offset points", fontsize=6.5, color="0.25")
            if ax is axes[0][0]:
                ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12),
                          frameon=False)
        ax.set_title(f"{limit_state_title(ls)}")
        ax.set_xlabel("east [m]" if d["plan"] else "longitude [deg]")
        ax.set_ylabel("north [m]" if d["plan"] else "latitude [deg]")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, alpha=0.3)
        ax.margins(0.15)
    fig.colorbar(sc, ax=axes[0].tolist(), label="mean annual frequency λ [1/yr]",
                 shrink=0.85)
    who = f"{d['study']}: " if d.get("study") else ""
    fig.suptitle(f"{who}λ of each column at its position ({d.get('terms', 'pga')})"
                 + (f"\nhazard: {d['hazard']}" if d.get("hazard") else ""), fontsize=10)
    foot = []
    if d["plan"]:
        foot.append("Local plan: metres east and north of the columns' centre.")
    far = site[shown & ~near]
    if len(far):
        foot.append("Hazard sites beyond the plan: " + "; ".join(
            f"{r.hazard_site}" for r in far.itertuples()) + " (hazard_site and "
            "hazard_distance_km of portfolio.csv name each column's).")
    if d["missing"]:
        foot.append(f"Not on the map (no lon/lat): {', '.join(d['missing'])}.")
    footnote(fig, foot)
    fig.canvas.draw()  # the final layout and limits before the labels are placed
    for ax in axes[0][:len(d["limit_states"])]:
        place_labels(ax, cols["x"].to_numpy(float), cols["y"].to_numpy(float), cols["id"])
    return fig


@styled
def plot_ranked(d: dict) -> Figure:
    """The columns ranked by λ of the most severe limit state: points with their 90 %
    intervals as bars, on a log axis."""
    import pandas as pd

    from rocking.risk.portfolio import error_words, site_lines

    states = d["limit_states"]
    cols = d["columns"].copy()
    first = states[0]
    cols = cols.sort_values(f"lambda|{first}", ascending=False, kind="stable")
    n = len(cols)
    fig, ax = new_figure(max(6.0, 0.55 * n + 2.5), 5.2)
    width = 0.36 if len(states) > 1 else 0.0
    colors = ("#b2182b", "#2166ac")
    markers = ("o", "s")
    x = np.arange(n)
    for j, ls in enumerate(states):
        lam = cols[f"lambda|{ls}"].to_numpy(float)
        lo, hi = cols[f"lambda_p05|{ls}"].to_numpy(float), cols[f"lambda_p95|{ls}"].to_numpy(
            float)
        xs = x + (j - (len(states) - 1) / 2) * width
        ax.plot(xs, lam, markers[j % 2], color=colors[j % 2], ms=5, zorder=3,
                label=f"{limit_state_title(ls)} (interpolation error of the median "
                      f"{error_words(d['errors'][ls])})")
        # the interval as drawn from its ends, not as ± about λ: with few motions λ may lie
        # outside its own bootstrap interval, and that is shown, not clipped
        shown = np.isfinite(lo) & np.isfinite(hi)
        ax.vlines(xs[shown], lo[shown], hi[shown], color=colors[j % 2], lw=1.2, zorder=2)
        for end in (lo, hi):
            ax.plot(xs[shown], end[shown], ls="none", marker="_", color=colors[j % 2], ms=7)
    ax.set_yscale("log")
    values = np.concatenate([cols[f"{k}|{ls}"].to_numpy(float) for ls in states
                             for k in ("lambda", "lambda_p05", "lambda_p95")])
    values = values[np.isfinite(values) & (values > 0)]
    if values.size:
        ax.set_ylim(values.min() / 1.6, values.max() * 2.2)  # room for the legend above
    ax.set_xticks(x, cols["id"].astype(str), rotation=45, ha="right")
    ax.set_xlim(-0.7, n - 0.3)
    ax.set_xlabel(f"column, ranked by λ of {limit_state_title(first).lower()} (highest first)")
    ax.set_ylabel("mean annual frequency λ [1/yr]")
    ax.grid(True, axis="y", which="both", alpha=0.3)
    ax.legend(fontsize=7.5, loc="upper right")
    right = ax.secondary_yaxis("right", functions=(_inverse, _inverse))
    right.set_ylabel("return period [yr]")
    who = f"{d['study']}: " if d.get("study") else ""
    fig.suptitle(f"{who}columns ranked by mean annual frequency ({d.get('terms', 'pga')})"
                 "\nbars: 90 % bootstrap interval over the motions"
                 + (f"; hazard: {d['hazard']}" if d.get("hazard") else ""), fontsize=10)
    answer = d.get("site", {})
    footnote(fig, [f"The site. {line}." for line in
                   site_lines(pd.DataFrame(list(answer.values())))] if answer else [])
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
