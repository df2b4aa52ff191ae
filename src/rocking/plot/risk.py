"""Risk (beyond the paper): mean annual frequency of overturning and excessive tilt against R.

Reads ``results/<study>/risk.csv`` (:func:`rocking.risk.risk_table.risk_table`): for each mode at
one slenderness, the mean annual frequency λ_LS [1/yr] of each size R under the study's
hazard curve, on a log scale, one panel per limit state, with the 90 % bootstrap band
(``lambda_p05``–``lambda_p95``) shaded. A size without a fit leaves a gap in its line (never
a line drawn across it); where the bracketing stripes bound λ there, a bracket
(``lambda_lo``–``lambda_hi``) marks it. The right axis gives the return period 1/λ_LS; the
notes give λ_LS at R = 2, 6, 10 m per mode and the ratio of 2D to 3D. Where the table also
holds the multiple-stripe fragility's rows (``fragility`` column ``stripes``), they are drawn
beside the critical-intensity ones (open squares, dotted), and the notes give their λ_LS and
the ratio stripes / critical intensity.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rocking.motions.measures import COMPONENTS, Measure
from rocking.plot._style import MODE_STYLE, footnote, styled, with_legend_row
from rocking.spectra.limit_states import limit_state_title
from rocking.spectra.modes import PLANAR_MODES

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure

CAPTION = (
    "Risk (beyond the paper): mean annual frequency of exceeding overturning and excessive "
    "tilt (θ > α/3) against the size R, per analysis mode, from the lognormal fragilities "
    "integrated against the study's hazard curve (λ_LS = ∫ P(LS | PGA) |dλ(PGA)|; hazard "
    "log-log interpolated, last slope extrapolated). Right axis: return period. PGA is the "
    "fragility's and the hazard's in one horizontal component (risk.csv's component column; "
    "docs/risk.md). Where the study has stripes, open squares: "
    "the same integral with the multiple-stripe fragility (the probability of exceeding at "
    "the intensity, the one the integral asks for); filled circles: the critical-intensity "
    "fragility (larger: it also counts motions that exceed at a lower intensity only). "
    "The 90 % interval of λ from resampling the motions (bootstrap): filled for 3D, a dashed "
    "outline for 3D damped, tinted for 2D, hatched for the stripes (error bars where the "
    "study has one size); a gap in a line "
    "is a size without a fit, a bracket there the range of λ the bracketing stripes imply."
)
"""Caption (the workflow makes the figure; the report's section: :mod:`rocking.report.risk`)."""

R_NOTES = (2.0, 6.0, 10.0)


def _curve(sel: pd.DataFrame) -> dict:
    """R, λ, its band and the bracket bounds of one mode's rows (NaN where absent)."""
    def col(name):
        return (sel[name].to_numpy(float) if name in sel.columns
                else np.full(len(sel), np.nan))

    return {"R": col("R"), "maf": col("maf"), "p05": col("lambda_p05"),
            "p95": col("lambda_p95"), "lo": col("lambda_lo"), "hi": col("lambda_hi"),
            "status": sel["status"].astype(str).to_numpy() if "status" in sel.columns
            else np.full(len(sel), "ok")}


def _stripe_curves(rows: pd.DataFrame, ls: str, measured: dict) -> dict:
    """λ_LS against R per mode from the stripe rows of one limit state; their notes and the
    ratio stripes / critical intensity at R = 2, 6, 10 m go into ``measured``."""
    curves = {}
    for mode in MODE_STYLE:
        sel = rows[rows["mode"] == mode].sort_values("R")
        if sel.empty:
            continue
        curves[mode] = _curve(sel)
        for R in R_NOTES:
            hit = sel[np.isclose(sel["R"], R)]
            if hit.empty or not np.isfinite(hit["maf"].iloc[0]):
                continue
            lam = float(hit["maf"].iloc[0])
            measured[f"stripes {mode} {ls} R={R:g} m [1/yr]"] = lam
            critical = measured.get(f"{mode} {ls} R={R:g} m [1/yr]")
            if critical:
                measured[f"ratio stripes/critical intensity {mode} {ls} R={R:g} m [-]"] = (
                    lam / critical)
    return curves


def data(risk: str | Path | pd.DataFrame, *, tan_alpha: float | None = None,
         hazard: str = "", study: str = "") -> dict:
    """λ_LS against R per mode for the study's limit states (overturning and excessive tilt
    in the paper; :func:`rocking.report.risk.shown_limit_states`) at ``tan_alpha`` (default
    the study's, :func:`rocking.report.risk.main_tan_alpha`).

    Returns
    -------
    dict
        ``panels``: [{``limit_state``, ``curves``: {mode: {``R``, ``maf``, ``p05``,
        ``p95``, ``lo``, ``hi``, ``status``}}, ``stripes``: the same from the stripe
        fragility (empty without it)}],
        ``measured``: {"<mode> <limit state> R=<R> m": λ [1/yr], "ratio 2d-x/3d ...": [-]},
        ``missing``, ``gaps`` (sizes without a fit, named), ``tan_alpha``, ``hazard``,
        ``study``, ``measure``.
    """
    # CRITICAL_INTENSITY and STRIPES: the values of risk.csv's fragility column
    from rocking.fragility.table import CRITICAL_INTENSITY, STRIPES
    from rocking.risk.risk_table import main_tan_alpha, read_risk_table, shown_limit_states

    frame = read_risk_table(risk)
    if tan_alpha is None:
        tan_alpha = main_tan_alpha(frame[frame["fragility"] == CRITICAL_INTENSITY])
    if tan_alpha is None:
        raise ValueError("the risk table has no rows")
    frame = frame[np.isclose(frame["tan_alpha"].astype(float), tan_alpha)]
    measure = str(frame["measure"].iloc[0]) if "measure" in frame.columns and len(frame) \
        else "pga"
    component = str(frame["component"].iloc[0]) if "component" in frame.columns and len(frame) \
        else ""
    stripes = frame[frame["fragility"] == STRIPES]
    frame = frame[frame["fragility"] == CRITICAL_INTENSITY]
    modes = [m for m in MODE_STYLE if m in set(frame["mode"])]
    missing: list[str] = []
    gaps: list[str] = []
    panels, measured = [], {}
    for ls in shown_limit_states(frame):
        rows = frame[frame["limit_state"] == ls]
        curves = {}
        for mode in modes:
            sel = rows[rows["mode"] == mode].sort_values("R")
            if sel.empty:
                missing.append(f"{mode} {ls} at tan α = {tan_alpha:g}")
                continue
            curves[mode] = _curve(sel)
            for R in R_NOTES:
                hit = sel[np.isclose(sel["R"], R)]
                if not hit.empty and np.isfinite(hit["maf"].iloc[0]):
                    measured[f"{mode} {ls} R={R:g} m [1/yr]"] = float(hit["maf"].iloc[0])
        for two in PLANAR_MODES:
            for R in R_NOTES:
                a = measured.get(f"{two} {ls} R={R:g} m [1/yr]")
                b = measured.get(f"3d {ls} R={R:g} m [1/yr]")
                if a is not None and b:
                    measured[f"ratio {two}/3d {ls} R={R:g} m [-]"] = a / b
        stripe = _stripe_curves(stripes[stripes["limit_state"] == ls], ls, measured)
        for kind, group in (("critical intensities", curves), ("stripes", stripe)):
            for mode, c in group.items():
                gaps += [f"{kind} {mode} {ls} R = {R:g} m ({st})"
                         for R, m, st in zip(c["R"], c["maf"], c["status"], strict=True)
                         if not np.isfinite(m)]
        panels.append({"limit_state": ls, "curves": curves, "stripes": stripe})
    return {"panels": panels, "measured": measured, "missing": missing, "gaps": gaps,
            "tan_alpha": tan_alpha, "hazard": hazard, "study": study, "measure": measure,
            "component": component}


_BANDS = {
    # how each kind of curve shows its 90 % interval, so that three grey ones differ:
    # filled (3D), outlined dashed (3D damped: it lies on the 3D band), hatched (stripes)
    "fill": {"alpha": 0.18, "linewidth": 0},
    "outline": {"facecolor": "none", "linewidth": 0.8, "linestyle": "--"},
    "hatch": {"facecolor": "none", "linewidth": 0, "hatch": "////"},
}


def _band_kind(mode: str, stripes: bool) -> str:
    """How the 90 % interval of a curve is drawn (:data:`_BANDS`)."""
    if stripes:
        return "hatch"
    return "outline" if mode == "3d-damped" else "fill"


def _draw(ax, c: dict, style: dict, *, marker: str, mfc, linestyle: str, label: str,
          band: str = "fill", shift: float = 0.0) -> None:
    """One mode's λ(R): the line (broken where a size has no fit), its 90 % interval (a band
    over two sizes or more, an error bar at a lone size: a band of one size draws nothing),
    brackets where stripes bound a gap; ``shift`` [m] moves it sideways (a study of one size,
    where the bars of the modes would lie on one another)."""
    c = {**c, "R": c["R"] + shift}
    maf = np.where(c["maf"] > 0, c["maf"], np.nan)  # NaN breaks the line: no line over a gap
    ax.semilogy(c["R"], maf, marker=marker, ms=4.0, mfc=mfc, color=style["color"],
                linestyle=linestyle, label=label)
    has = np.isfinite(c["p05"]) & np.isfinite(c["p95"]) & (c["p05"] > 0)
    spans = has[:-1] & has[1:]  # neighbouring sizes both with an interval: a band exists
    if spans.any():
        kw = dict(_BANDS[band])
        edge = {"edgecolor": style["color"]} if band != "fill" else {}
        ax.fill_between(c["R"], np.where(has, c["p05"], np.nan),
                        np.where(has, c["p95"], np.nan), color=style["color"], **edge, **kw,
                        label=f"{label}: 90 % interval")
    lone = has & ~np.r_[spans, False] & ~np.r_[False, spans]
    if lone.any():  # sizes whose interval no band shows: a bar at each
        mid = np.where(np.isfinite(maf[lone]), maf[lone], np.sqrt(c["p05"][lone] *
                                                                    c["p95"][lone]))
        ax.errorbar(c["R"][lone], mid, yerr=[mid - c["p05"][lone], c["p95"][lone] - mid],
                    fmt="none", ecolor=style["color"], capsize=3, lw=1.0,
                    label=None if spans.any() else f"{label}: 90 % interval")
    gap = ~np.isfinite(c["maf"])
    for R, lo, hi in zip(c["R"][gap], c["lo"][gap], c["hi"][gap], strict=True):
        if np.isfinite(hi) and hi > 0:
            bottom = lo if np.isfinite(lo) and lo > 0 else hi * 1e-2
            ax.annotate("", xy=(R, bottom), xytext=(R, hi),
                        arrowprops={"arrowstyle": "|-|" if lo > 0 else "-|>",
                                    "color": style["color"], "lw": 1.0})
        else:
            ax.plot([R], [np.nan])  # nothing known there: the gap alone says it


def _hazard_line(d: dict) -> str:
    """The title's hazard line: the file, EXAMPLE when it is the repository's example curve
    (config/hazard/README.md; :func:`rocking.report.risk.assumptions` says the same), and
    the component of its intensity measure."""
    hazard = d.get("hazard") or "the study's hazard curve"
    line = f"hazard: {hazard}"
    if "example_hazard_curve" in hazard:
        line = f"hazard: EXAMPLE curve, not a real site's: {hazard}"
    component = d.get("component") or ""
    if component:
        known = COMPONENTS.get(component)
        unit = Measure.of(d.get("measure", "pga")).label
        line += (f"\nintensity: {unit}, horizontal component {component}"
                 + (f" ({known.description})" if known else "")
                 + ", the fragility's and the hazard's")
    return line


@styled
def plot(d: dict) -> Figure:
    """One log-scale panel per limit state, one line per mode, its 90 % interval (filled,
    outlined or hatched, so that the grey ones differ), gaps where a size has no fit
    (brackets where stripes bound it); return period on the right; one legend below the
    panels, so that it covers no curve; the hazard named in the title, EXAMPLE if it is."""
    # a row below the panels holds the legend (inside, it hid the 2D curves)
    fig, axes, legend_row = with_legend_row(11.0, 6.0, ncols=len(d["panels"]) or 1,
                                            legend_share=0.2)
    for ax, panel in zip(axes, d["panels"], strict=False):
        curves = [(m, c, False) for m, c in panel["curves"].items()] + [
            (m, c, True) for m, c in panel.get("stripes", {}).items()]
        sizes = np.unique(np.concatenate([c["R"] for _, c, _ in curves])) if curves else []
        # one size: no line, no band; the modes' bars side by side around it
        step = 0.06 * float(sizes[0]) if len(sizes) == 1 else 0.0
        for k, (mode, c, stripe) in enumerate(curves):
            style = MODE_STYLE[mode]
            shift = step * (k - 0.5 * (len(curves) - 1))
            if stripe:
                _draw(ax, c, style, marker="s", mfc="none", linestyle=":",
                      label=f"{style['label']}, stripes", band=_band_kind(mode, True),
                      shift=shift)
            else:
                label = style["label"] + (", critical intensities" if panel.get("stripes")
                                          else "")
                _draw(ax, c, style, marker="o", mfc=None, linestyle=style["linestyle"],
                      label=label, band=_band_kind(mode, False), shift=shift)
        if step:
            ax.set_xticks(sizes)
            ax.set_xlim(sizes[0] - 4 * step * len(curves) / 2,
                        sizes[0] + 4 * step * len(curves) / 2)
        ax.set_title(limit_state_title(panel["limit_state"]))
        ax.set_xlabel("R [m]")
        unit = Measure.of(d.get("measure", "pga")).label
        ax.set_ylabel(f"mean annual frequency λ [1/yr] ({unit} hazard)")
        ax.grid(True, which="both", alpha=0.3)
        if panel["curves"]:
            right = ax.secondary_yaxis("right", functions=(_inverse, _inverse))
            right.set_ylabel("return period [yr]")
    # one legend for both panels (same modes, same styles), below them: none over a curve
    handles, labels = [], []
    for ax in axes:
        for h, lab in zip(*ax.get_legend_handles_labels(), strict=True):
            if lab not in labels:
                handles.append(h)
                labels.append(lab)
    if handles:
        handles, labels = _rows(handles, labels)
        legend_row.legend(handles, labels, loc="center", ncols=2, fontsize=8, frameon=False)
    who = f"{d['study']}: " if d.get("study") else ""
    title = f"{who}mean annual frequency of exceedance, tan α = {d['tan_alpha']:g}"
    title += "\n" + _hazard_line(d)
    fig.suptitle(title, fontsize=10)
    foot = []
    lone = {float(c["R"][0]) for p in d["panels"] for g in (p["curves"], p.get("stripes", {}))
            for c in g.values() if len(np.unique(c["R"])) == 1}
    if len(lone) == 1 and all(len(np.unique(c["R"])) == 1 for p in d["panels"]
                              for g in (p["curves"], p.get("stripes", {})) for c in g.values()):
        foot.append(f"One size, R = {lone.pop():g} m: the modes set side by side around it, "
                    "each with its 90 % interval as a bar.")
    if d["missing"]:
        foot.append("Not in this run: " + "; ".join(d["missing"]) + ".")
    if d.get("gaps"):
        foot.append("No fit (gap): " + "; ".join(d["gaps"][:6])
                    + (f"; and {len(d['gaps']) - 6} more" if len(d["gaps"]) > 6 else "") + ".")
    footnote(fig, foot)
    return fig


def _rows(handles: list, labels: list[str]) -> tuple[list, list[str]]:
    """Legend entries ordered for two columns filled column by column: each curve on the
    left, its 90 % interval beside it on the right (a blank where it has none)."""
    from matplotlib.lines import Line2D

    suffix = ": 90 % interval"
    curves = [(h, lab) for h, lab in zip(handles, labels, strict=True)
              if not lab.endswith(suffix)]
    bands = dict((lab[:-len(suffix)], (h, lab)) for h, lab in zip(handles, labels, strict=True)
                 if lab.endswith(suffix))
    blank = (Line2D([], [], alpha=0.0), " ")
    right = [bands.get(lab, blank) for _, lab in curves]
    pairs = curves + right
    return [h for h, _ in pairs], [lab for _, lab in pairs]


def _inverse(x):
    # return period ↔ annual frequency; guard the axis' own zero
    x = np.asarray(x, dtype=float)
    with np.errstate(divide="ignore"):
        return np.where(x > 0, 1.0 / np.where(x > 0, x, 1.0), np.inf)


def _arguments(inputs, params) -> dict:
    """``data()``'s keywords: the hazard named as the risk rule read it."""
    from rocking.risk.hazard import parse_hazard

    return {"risk": inputs["risk"], "hazard": parse_hazard(params["hazard"]).source,
            "study": f"study {params['study']} (ensemble {params['ensemble']})"}


from rocking.plot.registry import FigureSpec  # noqa: E402

FIGURE = FigureSpec(
    name="risk", rule="risk_figure", module=__name__, number=15, label="risk",
    caption=CAPTION, scope="study", wanted=lambda s: s.spec().hazard is not None,
    inputs={"risk": "risk"},
    params={"hazard": "hazard", "study": "study", "ensemble": "ensemble"},
    arguments=_arguments, section="risk", category="Beyond the paper")
"""The risk figure, in the report's risk section of every study with a hazard."""
