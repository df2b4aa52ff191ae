"""Stripe against critical-intensity fragility (beyond the paper), one figure per mode.

One panel per (limit state, R): the share of the motions exceeding at each stripe (markers,
refined stripes filled, with its 90 % bootstrap interval over the motions as a bar; with the
stripes jittered it is F(s), the mean over the motions of their local exceedance
probability) and its binomial maximum-likelihood lognormal (solid,
:mod:`rocking.fragility.stripes`) with the bootstrap's 90 % interval of its median IM₅₀, beside
the lognormal fitted to the motions' critical intensities (dashed, the study's quantity, I10
by default: :func:`rocking.fragility.lognormal.fragility_table`; PGA stripes only). The first
answers "at which intensity do half of the motions exceed", the second "from which intensity
does a motion start to exceed"; a body that exceeds in a narrow window of intensity and
survives above it pulls the second down only. A row without a fit is drawn as the span of
intensities that brackets its median, never as a curve.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rocking.motions.measures import Measure
from rocking.plot._style import MODE_STYLE, footnote, new_figure, styled
from rocking.spectra.limit_states import limit_state_title
from rocking.spectra.modes import MODE_3D

if TYPE_CHECKING:
    from matplotlib.figure import Figure

CAPTION = ("Markers: share of the motions exceeding at each stripe, each analysis jittered "
           "within ±w of it in ln PGA, so F(s), the mean over the motions of their local "
           "exceedance probability, with its 90 % bootstrap interval over the motions as a bar "
           "(filled: stripes added where the fit separated); solid: its binomial "
           "maximum-likelihood lognormal, "
           "IM₅₀ its median, the bar at P = 0.5 the 90 % bootstrap interval of IM₅₀ over "
           "resamples of the motions; dashed: lognormal of the motions' critical "
           "intensities (the study's quantity; PGA stripes only); shaded: where no "
           "lognormal fits, the intensities between the last stripe with no motion "
           "exceeding and the first with all exceeding, which bracket the median. "
           "Intensities are vector peaks of the pair.")
"""What the figure shows (the footnote; workflow/report/stripe_fragility.rst says the same)."""


def data(stripes: str | Path, fragility: str | Path | None, *, mode: str = MODE_3D,
         table: str | Path | None = None, refined: str | Path | None = None) -> dict:
    """Stripe fractions, fits, brackets and intervals for every (limit state, R) of ``mode``.

    Parameters
    ----------
    stripes : path
        The stripes store.
    fragility : path, optional
        The study's critical-intensity ``fragility.nc``.
    mode : str
    table : path, optional
        ``stripe_fragility.csv`` (refined, bootstrapped): its rows are drawn, and its
        refined stripes replayed from the store's refinement file; None: the stripes as
        asked, fitted here.
    refined : path, optional
        The refined analyses to replay (``stripe_fragility_refined.jsonl``, written with the
        table); default the store's refinement file.

    Returns
    -------
    dict
        ``panels``: [{``limit_state``, ``R``, ``x`` (stripes [measure unit]), ``refined``,
        ``fraction``, ``stripe``: (IM₅₀, beta, status), ``bracket``, ``interval``,
        ``critical``: (median, beta, status) [measure unit]}], ``measured``, ``missing``,
        ``mode``, ``tan_alpha``, ``measure``, ``study``, ``ensemble``, ``n_motions``.
    """
    import xarray as xr

    from rocking.execution import stripes as st
    from rocking.fragility.stripe_table import (
        store_jitter,
        store_measure,
        stripe_fits,
        stripe_table,
    )
    from rocking.fragility.stripes import exceedance_table
    from rocking.fragility.table import renamed
    from rocking.store.attrs import decode_attrs
    from rocking.units import read_table

    ds = xr.open_zarr(stripes, consolidated=True)
    if mode not in [str(m) for m in ds["mode"].values]:
        raise ValueError(f"mode {mode!r} is not in the stripes store {str(stripes)!r}")
    if table is not None:
        tab = renamed(read_table(table))
        budget = int(tab["n_refined"].max()) if len(tab) else 0
        rows = st.stripe_rows(ds, refine=budget,
                              cache=refined or st.refine_cache_path(stripes))
    else:
        critical = None
        if fragility is not None:
            with xr.open_dataset(fragility) as f:
                critical = f.load()
        rows = st.stripe_rows(ds)
        tab = stripe_table(ds, critical, rows=rows)
    base = {k: set(r.intensities.tolist()) for k, r in stripe_fits(ds).items()}
    sizes = [float(v) for v in ds["R"].values]
    panels, measured, missing = [], {}, []
    for row in tab[tab["mode"] == mode].itertuples():
        R = store_size(row.R, sizes)  # the table's R is the store's to 10 digits
        r = rows[(mode, row.limit_state, R)]
        scale = r.scale
        x = r.intensities * scale
        refined = np.array([v not in base[(mode, R)] for v in r.intensities])
        critical_g = row.critical_median * scale if r.measure == "pga" else np.nan
        shares = exceedance_table(r)
        panels.append({"limit_state": row.limit_state, "R": R, "x": x,
                       "refined": refined, "fraction": r.fraction[:, 0],
                       "share_interval": (shares["share_p05"].to_numpy(),
                                          shares["share_p95"].to_numpy()),
                       "stripe": (row.median_im, row.beta, row.status),
                       "bracket": (row.bracket_lo, row.bracket_hi),
                       "interval": (row.median_p05, row.median_p95),
                       "critical": (critical_g, row.critical_beta, row.critical_status)})
        key = f"{row.limit_state}, R = {row.R:g} m"
        measured[key] = {"stripe_median": row.median, "stripe_median_im": row.median_im,
                         "median_p05": row.median_p05, "median_p95": row.median_p95,
                         "critical_intensity_median": row.critical_median, "ratio": row.ratio,
                         "stripe_status": row.status, "stripe_reason": row.reason,
                         "bracket_lo": row.bracket_lo, "bracket_hi": row.bracket_hi,
                         "n_refined": int(row.n_refined)}
        if row.status != "ok":
            missing.append(f"{key}: {row.status}")
    attrs = decode_attrs(ds.attrs)
    ens = attrs.get("ensemble", {})
    measure = store_measure(attrs)
    return {"panels": panels, "measured": measured, "missing": missing, "mode": mode,
            "jitter": store_jitter(attrs),
            "tan_alpha": float(ds.attrs.get("tan_alpha", np.nan)), "measure": measure,
            "measure_label": Measure.of(measure).label,
            "unit": Measure.of(measure).unit,
            "study": str(attrs.get("config", {}).get("study", "")),
            "ensemble": str(ens.get("name", "")), "n_motions": int(ds.sizes["motion"])}


SIZE_RTOL = 1e-8
"""Relative difference at which a size R read back from a table (written to 10 significant
digits, :data:`rocking.units.CSV_FLOAT_FORMAT`) is the store's R [-]."""


def store_size(R: float, sizes: list[float]) -> float:
    """The size of the store ``R`` denotes: the nearest within :data:`SIZE_RTOL` (a body
    given by height and diameter has R = √(b² + h²) with all its digits, the table keeps
    10), else a ValueError naming both."""
    near = min(sizes, key=lambda v: abs(v - float(R)))
    if abs(near - float(R)) > SIZE_RTOL * abs(near):
        raise ValueError(f"R = {float(R)!r} m of the stripe table is not a size of the stripes "
                         f"store {sizes}")
    return near


def _curve(ax, x: np.ndarray, fit: tuple, style: str, label: str, color: str, unit: str,
           name: str = "IM₅₀") -> bool:
    """The lognormal where it exists (True), else only a legend entry (False)."""
    from scipy import stats

    median, beta, status = fit
    if np.isfinite(median) and np.isfinite(beta) and beta > 0:
        ax.plot(x, stats.norm.cdf(np.log(x / median) / beta), style, color=color,
                label=f"{label}: {name} = {median:.3g} {unit}, β = {beta:.2f}"
                + ("" if status == "ok" else f" [{status}]"))
        return True
    return False


def _ticks(axis, lo: float, hi: float) -> None:
    from matplotlib.ticker import FixedLocator, NullFormatter, ScalarFormatter

    # plain numbers: log-axis labels like 3×10⁻¹ collide
    steps = [m * 10.0**e for e in range(-3, 3) for m in (1, 2, 5)]
    axis.set_major_locator(FixedLocator([v for v in steps if lo / 1.5 <= v <= hi * 1.5]))
    axis.set_major_formatter(ScalarFormatter())
    axis.set_minor_formatter(NullFormatter())


@styled
def plot(d: dict) -> Figure:
    """Panels in rows of limit states and columns of sizes R."""
    panels = d["panels"]
    states = list(dict.fromkeys(p["limit_state"] for p in panels)) or ["-"]
    sizes = sorted({p["R"] for p in panels}) or [0.0]
    fig, axes = new_figure(3.6 * len(sizes) + 0.6, 3.9 * len(states) + 1.2,
                           nrows=len(states), ncols=len(sizes), squeeze=False)
    color = MODE_STYLE.get(d["mode"], {}).get("color", "black")
    unit, im = d.get("unit", "g"), d.get("measure_label", "PGA")
    for p in panels:
        ax = axes[states.index(p["limit_state"])][sizes.index(p["R"])]
        x = np.asarray(p["x"], dtype=float)
        grid = np.geomspace(x[0], x[-1], 200)
        ref = np.asarray(p.get("refined", np.zeros(x.size, bool)), dtype=bool)
        lo, hi = p.get("share_interval", (None, None))
        if lo is not None:  # F(s)'s spread over other sets of as many motions
            ax.vlines(x, lo, hi, color=color, lw=0.8, alpha=0.5)
        jitter = d.get("jitter", 0.0)
        ax.plot(x[~ref], p["fraction"][~ref], "o", ms=3.5, mfc="none", color=color,
                label=("F(s): share of motions exceeding, jittered ±"
                       f"{jitter:g} in ln s" if jitter else "share of motions exceeding"))
        if ref.any():
            ax.plot(x[ref], p["fraction"][ref], "o", ms=3.5, color=color,
                    label=f"… at {int(ref.sum())} stripe(s) added")
        if _curve(ax, grid, p["stripe"], "-", "stripes", color, unit):
            lo, hi = p.get("interval", (np.nan, np.nan))
            if np.isfinite(lo) and np.isfinite(hi):
                ax.plot([lo, hi], [0.5, 0.5], "-", lw=3, alpha=0.4, color=color,
                        solid_capstyle="butt",
                        label=f"90 % bootstrap IM₅₀: {lo:.3g}–{hi:.3g} {unit}")
        else:
            lo, hi = p.get("bracket", (np.nan, np.nan))
            status = p["stripe"][2]
            if np.isfinite(lo) and lo > 0 and np.isfinite(hi):
                ax.axvspan(lo, hi, color=color, alpha=0.2, lw=0,
                           label=f"no fit ({status}): IM₅₀ in {lo:.3g}–{hi:.3g} {unit}")
            else:
                ax.plot([], [], " ", label=f"no fit ({status}): IM₅₀ "
                        + (f"> {lo:.3g} {unit}" if np.isfinite(lo) and lo > 0
                           else f"< {hi:.3g} {unit}" if np.isfinite(hi) else "unknown"))
        _curve(ax, grid, p["critical"], "--", "critical intensities", "tab:red", unit, "median")
        ax.set_xscale("log")
        _ticks(ax.xaxis, x[0], x[-1])
        ax.set_ylim(-0.02, 1.02)
        ax.set_title(f"{limit_state_title(p['limit_state'])}, R = {p['R']:g} m", fontsize=9)
        ax.set_xlabel(f"{im} [{unit}]")
        ax.set_ylabel("P(exceeded) [-]")
        # below the panel, not in it: where "best" finds room depends on the data, and at
        # the larger sizes the markers spread over every corner
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), fontsize=6, frameon=False)
    label = MODE_STYLE.get(d["mode"], {}).get("label", d["mode"])
    who = ", ".join(v for v in (f"study {d['study']}" if d.get("study") else "",
                                f"ensemble {d['ensemble']} ({d['n_motions']} motions)"
                                if d.get("ensemble") else "") if v)
    fig.suptitle(f"Multiple-stripe fragility in {im}, {who + ', ' if who else ''}{label} "
                 f"model, tan α = {d['tan_alpha']:g}")
    footnote(fig, [CAPTION,
                   *(["Undefined or flagged stripe fits: " + "; ".join(d["missing"]) + "."]
                     if d["missing"] else [])])
    return fig


REPORT_CAPTION = (
    "Multiple-stripe against critical-intensity fragility (beyond the paper), one panel "
    "per limit state and size R of the study's stripes: markers the share of the "
    "motions exceeding the limit state at each stripe intensity, the solid line its "
    "binomial maximum-likelihood lognormal, the dashed line the lognormal of the "
    "motions' critical intensities; medians IM₅₀ and dispersions β in the legend and in "
    "the table below."
)
"""The caption under each stripe figure in the report and the gallery (the figure's own
footnote is :data:`CAPTION`)."""


from rocking.plot.registry import FigureSpec  # noqa: E402

FIGURE = FigureSpec(
    name="stripe_fragility", rule="stripe_fragility_figure", module=__name__, number=14,
    label="stripe fragility", caption=REPORT_CAPTION, scope="study",
    wanted=lambda s: s.spec().stripes is not None,
    per="mode", per_values=lambda s: s.spec().stripes.modes,
    inputs={"fragility": "fragility_nc", "table": "stripe_table", "refined": "stripe_refined"},
    params={"stripes": "stripes_store"}, section="stripes", category="Beyond the paper")
"""One figure per mode of a study's stripes, in the report's stripes section."""
