"""Figure 10: mean performance spectra for every performance goal (θ > r·α and overturning).

The study's primary mode (undamped 3D in the paper) at its slenderness (tan α = 0.2 in the
paper; :func:`._load.main_tan_alpha`), mean over the ensemble (the study's
``mean_spectra.nc``), one line per goal the study computed, however many. The paper shows
seven goals; a reduced reproduction names the others. Every curve gets a least-squares line
in R (the paper: "almost straight lines"). The means are of the per-motion answers of the
study's quantity (I10 by default), as the legend says; means over answers flagged plateau
are counted per goal.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rocking.plot import _axes, _load
from rocking.plot._style import (
    MODE_STYLE,
    footnote,
    goal_color,
    new_figure,
    paper_tag,
    pga_g_axis,
    plateau_suffix,
    r_axis,
    styled,
)
from rocking.plot.comparisons import (
    EQUATIONS,
    NOT_COMPUTED,
    NOT_IN_PAPER,
    Comparison,
    finite,
    first_notes,
    fmt,
    judged,
)
from rocking.spectra.limit_states import (
    DEFAULT_LIMIT_STATES,
    limit_state_title,
    match_limit_state,
    severity,
)
from rocking.spectra.modes import MODE_3D
from rocking.store.attrs import decode_attrs

if TYPE_CHECKING:
    from matplotlib.figure import Figure

PAPER_GOALS = DEFAULT_LIMIT_STATES
"""The seven performance goals of the paper's Fig 10."""
LINEAR_R2 = 0.95
"""Least R² of a straight line in R for "almost straight lines" (§5.2, §6) [-]."""
LINEAR_STATEMENT = "Mean spectrum almost linear in R"
"""Start of the linearity verdict's statement (the report keeps it in every study)."""
LINE_NOTE = "line|"
"""Prefix of the measured key of one goal's least-squares line."""
COINCIDE_NOTE = "coincide"
"""Measured key of the goals whose statistics coincide."""
LINEAR_RTOL = 0.10
"""Largest departure of the least-squares line from the mean spectrum at any R, relative to
the spectrum's average level over R, for "almost straight lines" (§5.2, §6) [-]: about the
standard error of a mean over the paper's 11 motions (scatter among motions 30 %:
0.3/√11 ≈ 9 %), so a line within it describes the spectrum as well as the mean is known.
R² alone does not say it: a mean that bends can have R² above 0.95 (a wide range of values),
a flat one R² far below (little to explain)."""
LINEARITY_TOLERANCE = (f"the least-squares line within {100 * LINEAR_RTOL:g} % of the mean "
                       "spectrum's average level, at every R")
"""The one linearity criterion of every study, in words."""
MIN_FIT_SIZES = 5
"""Fewest sizes R a least-squares line is fitted and judged over [-]."""
FLAT_TOL = 0.10
"""A mean spectrum is "flat" while it stays within this share of its smallest-R value [-]."""
MIN_FLAT_SIZES = 3
"""Fewest sizes R a flat stretch must span to be called one (a single point is none) [-]."""


def data(means: str | Path, *, tan_alpha: float | None = None, mode: str | None = None,
         motions: str | Path | None = None, paper: bool = True) -> dict:
    """Mean spectra per limit state: ``R`` [m], ``curves`` {limit state: PGA/(g tan α) (R,)},
    ``plateau`` {limit state: bool (R,)} where some motion's answer is flagged plateau,
    ``answer`` (the quantity's label) and ``answer_definition``, ``missing`` (goals, mode or
    slenderness not computed), ``measured`` line fits per goal.

    ``mode`` and ``tan_alpha`` default to the study's (:func:`._load.primary_mode`,
    :func:`._load.main_tan_alpha`); ``paper`` (a reproduction of the paper) names the paper's
    goals the run did not compute.
    """
    from rocking.fragility.lognormal import fit_line

    agg = _load.open_means(means)
    mode = mode or _load.primary_mode(agg) or MODE_3D
    if tan_alpha is None:
        tan_alpha = _load.main_tan_alpha(agg, [mode]) or float(agg["tan_alpha"].values[0])
    missing = []
    plateau: dict[str, np.ndarray] = {}
    curves: dict[str, np.ndarray] = {}
    R = agg["R"].values.astype(float)
    if not _load.has_value(agg, "tan_alpha", tan_alpha):
        missing.append(f"tan α = {tan_alpha:g} not computed")
    elif mode not in _load.labels(agg, "mode"):
        missing.append(f"mode {mode} not computed")
    else:
        agg = _load.select_value(agg, "tan_alpha", tan_alpha)
        for ls in sorted(_load.labels(agg, "limit_state"), key=severity):
            y = _load.mean_curve(agg, mode, ls)
            if y is not None:
                curves[ls] = y
                flag = _load.plateau_means(agg, mode, ls)
                if flag is not None:
                    plateau[ls] = flag
    # the paper draws Fig 10 for its El Centro study only: another record's is beyond it
    in_paper = paper and _paper_record(dict(agg.attrs))
    absent = [g for g in PAPER_GOALS
              if match_limit_state(g, list(curves), missing_ok=True) is None]
    if absent and not missing and in_paper:
        missing.append(f"{len(absent)} of the paper's {len(PAPER_GOALS)} goals not computed: "
                       + ", ".join(limit_state_title(g) for g in absent))
    measured = {"n_goals": len(curves), "n_paper_goals": len(PAPER_GOALS),
                "absent_goals": absent, "answer": _load.answer_label(agg.attrs)}
    for ls, y in curves.items():
        if np.isfinite(y).sum() < MIN_FIT_SIZES:  # a line through 3 points says nothing
            continue
        fit = fit_line(R, y)
        measured[LINE_NOTE + ls] = {"slope": fit.slope, "intercept": fit.intercept,
                                  "r_squared": fit.r_squared, "n": fit.n,
                                  **shape(R, y, fit.slope, fit.intercept)}
    same = coinciding(agg, mode, list(curves)) if curves else []
    if same:
        measured[COINCIDE_NOTE] = same
    return {"R": R, "curves": curves, "plateau": plateau, "tan_alpha": tan_alpha,
            "answer": _load.answer_label(agg.attrs),
            "answer_definition": _load.answer_definition(agg.attrs),
            "mode": mode, "missing": missing, "reproduction": paper, "in_paper": in_paper,
            "measured": measured,
            "axes": _axes.from_ensemble(motions), "title": _load.ensemble_title(
                dict(agg.attrs), Path(str(means)).parent.name)}


def _paper_record(attrs: dict) -> bool:
    """Whether the aggregate's ensemble is built on the paper's record (El Centro 1940, the
    only one the paper draws Fig 10 for; :data:`.report.EL_CENTRO_FIGURES`); True when the
    attributes do not say (an older aggregate: as before)."""
    raw = decode_attrs({"e": attrs.get("ensemble")})["e"]
    motions = raw.get("motions") if isinstance(raw, dict) else None
    if not motions:
        return True
    # each motion's source record; without them, the first motion (an ensemble's record)
    sources = {m["source_record"] for m in motions if m.get("source_record")} or {
        motions[0].get("name")}
    return sources == {"el-centro-1940"}


def shape(R: np.ndarray, y: np.ndarray, slope: float, intercept: float) -> dict:
    """How a mean spectrum departs from its line: flat stretch, end value, residual signs.

    Returns
    -------
    dict
        ``flat_to_R`` [m]: the largest R up to which y stays within :data:`FLAT_TOL` of its
        value at the smallest R, and ``flat_sizes`` the sizes up to it; ``flat_level`` [-]:
        that value at ``start_R`` [m]; ``end_R`` [m] and ``end_value`` [-]: the last finite
        point; ``residual_signs``: "+"/"−" of y − line per R (the pattern ``++−−−++`` is a
        bend, not scatter); ``max_rel_deviation`` [-]: the largest |y − line| over the mean
        of y across R (the linearity criterion, :func:`linearity_ok`), at ``worst_R`` [m];
        ``curvature`` [1/m²]: the second-degree coefficient of a parabola fitted to y
        (> 0: the spectrum bends upward).
    """
    ok = np.isfinite(y)
    if ok.sum() < 2:
        return {}
    r, v = R[ok], y[ok]
    within = np.abs(v / v[0] - 1.0) <= FLAT_TOL
    last = int(np.argmin(within)) - 1 if not within.all() else v.size - 1
    res = v - (slope * r + intercept)
    worst = int(np.argmax(np.abs(res)))
    curvature = float(np.polyfit(r, v, 2)[0]) if v.size >= 3 else 0.0
    return {"flat_to_R": float(r[max(last, 0)]), "flat_sizes": max(last, 0) + 1,
            "flat_level": float(v[0]), "start_R": float(r[0]),
            "max_rel_deviation": float(np.max(np.abs(res)) / np.mean(np.abs(v))),
            "worst_R": float(r[worst]), "curvature": curvature,
            "end_R": float(r[-1]), "end_value": float(v[-1]),
            "residual_signs": "".join("+" if e >= 0 else "−" for e in res)}


def shape_text(fit: Mapping) -> str:
    """The shape of a mean spectrum in words, from its numbers (:func:`shape`): flat where
    it is flat over :data:`MIN_FLAT_SIZES` sizes or more, else rising and bending up or
    down, with where its line misses it most."""
    if fit["flat_to_R"] >= fit["end_R"]:
        return (f"nearly flat, within {100 * FLAT_TOL:g} % of {fit['flat_level']:.2f} at every "
                f"R (up to {fit['end_value']:.2f} at R = {fit['end_R']:g} m)")
    if "flat_sizes" not in fit:  # notes written before the shape was measured
        return (f"flat, then rising: within {100 * FLAT_TOL:g} % of {fit['flat_level']:.2f} up "
                f"to R = {fit['flat_to_R']:g} m, then up to {fit['end_value']:.2f} at "
                f"R = {fit['end_R']:g} m")
    if fit["flat_sizes"] >= MIN_FLAT_SIZES:
        return (f"flat, then rising: within {100 * FLAT_TOL:g} % of {fit['flat_level']:.2f} up "
                f"to R = {fit['flat_to_R']:g} m ({fit['flat_sizes']} sizes), then up to "
                f"{fit['end_value']:.2f} at R = {fit['end_R']:g} m")
    bend = "upward" if fit["curvature"] > 0 else "downward"
    return (f"rising from {fit['flat_level']:.2f} at R = {fit['start_R']:g} m to "
            f"{fit['end_value']:.2f} at R = {fit['end_R']:g} m, bending {bend}; its line "
            f"misses it most at R = {fit['worst_R']:g} m")


def coinciding(agg, mode: str, states: list[str]) -> list[dict]:
    """Pairs of goals whose ensemble statistics are identical at every R.

    θ > α and overturning coincide when every motion that tilts past α at the smallest such
    intensity also overturns there: then mean, median, std and count agree at every R.

    Returns
    -------
    list of dict
        {``goals``: [a, b], ``n_R``: sizes compared, ``n_motions``: motions per size (the
        largest count)}.
    """
    stats = [s for s in ("mean", "median", "std", "count") if s in agg]
    out = []
    ordered = sorted(states, key=severity)
    for a, b in zip(ordered, ordered[1:], strict=False):
        va = [_load.mean_curve(agg, mode, a, s) for s in stats]
        vb = [_load.mean_curve(agg, mode, b, s) for s in stats]
        if any(x is None for x in va + vb):
            continue
        if all(np.array_equal(x, y, equal_nan=True) for x, y in zip(va, vb, strict=True)):
            count = (_load.mean_curve(agg, mode, a, "count") if "count" in agg else None)
            out.append({"goals": [a, b], "n_R": int(np.isfinite(va[0]).sum()),
                        "n_motions": int(np.nanmax(count)) if count is not None else None})
    return out


def coincide_text(c: dict) -> str:
    """``"Tilt θ > α and Overturning coincide at all 20 R (11 motions each)"``."""
    a, b = (limit_state_title(g) for g in c["goals"])
    each = f" ({c['n_motions']} motions each)" if c.get("n_motions") else ""
    return (f"{a} and {b.lower()} coincide: identical mean, median and spread at all "
            f"{c['n_R']} sizes{each}")


@styled
def plot(d: dict) -> Figure:
    """One panel, one line per goal, coloured from mild tilt (light) to overturning (dark)."""
    n = len(d["curves"])
    fig, ax = new_figure(6.4, 4.6 + 0.16 * (n + 2))  # the legend, a line per goal, below
    same = d["measured"].get(COINCIDE_NOTE, [])
    hidden = {c["goals"][0]: c["goals"][1] for c in same}  # drawn under its twin
    fitted = False
    for ls, y in d["curves"].items():
        fit = d["measured"].get(LINE_NOTE + ls, {})
        color = goal_color(ls)  # one colour per goal in every figure and study
        label = limit_state_title(ls)
        if ls in hidden:
            label += f" = {limit_state_title(hidden[ls]).lower()}"
        if finite(fit.get("r_squared")):
            dev = fit.get("max_rel_deviation")
            label += f" (R² {fit['r_squared']:.3f}" + (
                f", line off by ≤ {100 * dev:.0f} %" if finite(dev) else "") + ")"
        flag = d.get("plateau", {}).get(ls)
        if flag is not None:  # means over answers some of which are ill-conditioned
            label += plateau_suffix(int(np.sum(flag)), int(np.isfinite(y).sum()), "means")
        ax.plot(d["R"], y, color=color, lw=1.6, marker="o", ms=3, label=label,
                ls="-" if ls not in hidden else (0, (1, 1)), zorder=3 if ls in hidden else 2)
        if np.isfinite(fit.get("slope", np.nan)):
            # the least-squares line whose R² the legend quotes
            fitted = True
            ax.plot(d["R"], fit["slope"] * d["R"] + fit["intercept"], color=color, lw=0.8,
                    ls="--", alpha=0.8)
    if fitted:
        ax.plot([], [], color="0.4", lw=0.8, ls="--", label="least-squares line of each goal")
    if not n:
        ax.text(0.5, 0.5, "; ".join(d["missing"]) or "no data", ha="center",
                transform=ax.transAxes)
    ax.set_ylabel(f"mean {d.get('answer', 'critical')} PGA/(g tan α) [-]")
    r_axis(ax, d["R"])
    ax.set_ylim(bottom=0.0)
    pga_g_axis(ax, d["tan_alpha"])
    on_plateau = any(np.any(f) for f in d.get("plateau", {}).values())
    # under the axes, where it covers no curve whatever their number and shape
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncols=1, fontsize=7,
              title_fontsize=7, frameon=False,
              title=f"mean {d.get('answer', 'critical intensity')} per performance goal"
              + (" (line fit)" if fitted else "")
              + ("; some means over answers on a plateau" if on_plateau else ""))
    notes = [coincide_text(c) for c in same]
    top = list(d["curves"])[-1] if d["curves"] else None
    fit = d["measured"].get(LINE_NOTE + top, {}) if top else {}
    if "flat_to_R" in fit and linearity_ok(fit) is False:
        # the shape that fails the criterion, for the most severe goal, in the data's numbers
        notes.append(f"{limit_state_title(top)}: {shape_text(fit)} (residuals from the line "
                     f"by R: {fit['residual_signs']}).")
    in_paper = d.get("in_paper", d.get("reproduction", True))
    beyond = d.get("reproduction", True) and not in_paper  # a reproduction, but no Fig 10
    m = d["measured"]
    # one line each: what is drawn, from what, and how it stands to the paper
    lines = [f"Mean spectra per performance goal, {MODE_STYLE[d['mode']]['label']} model, "
             f"tan α = {d['tan_alpha']:g}{paper_tag({'paper': in_paper}, 'Fig 10')}",
             d.get("title", "ensemble")]
    if beyond:
        lines.append("beyond the paper: its Fig 10 is of El Centro only")
    elif d["missing"] and in_paper:
        lines.append(f"reduced run: {m['n_goals']} of the paper's {m['n_paper_goals']} goals")
    ax.set_title("\n".join(lines), fontsize=8)
    footnote(fig, [*notes, "Not computed in this run: " + "; ".join(d["missing"]) + "."
                   if d["missing"] else "",
                   f"Motions on their principal axes: {d['axes']['text']}; PGA = vector peak."])
    return fig


# ------------------------------------------------------ comparison with the paper


OVERTURNING_PHYSICS = (
    "At the smallest intensity that takes θ past α, no motion left the cylinder standing. "
    "Why: at θ = α the centre of mass is straight above the pivot (the contact point); beyond "
    "it, gravity's moment about the pivot turns from restoring to overturning and grows as "
    "θ grows, so only a reversal of the ground acceleration strong and long enough could "
    "bring the body back; at the threshold intensity, which just pushes θ past α, the "
    "motion has no such reserve. In numbers: gravity's moment about the pivot is "
    "m g ρ sin(α − θ), ρ the distance from the pivot to the centre of mass "
    "(geometry: {eq}#geometry-and-inertia); it changes sign at θ = α")


def compare(notes: Mapping) -> list[Comparison]:
    """This figure's statements of the paper set against the run's notes."""
    m = first_notes(notes, "fig10_goals").get("measured", {})
    name = "fig10_goals"
    rows = []
    absent = m.get("absent_goals", [])
    if absent:
        rows.append(Comparison(name, "Seven performance goals (Fig 10)", "7",
                               f"{m.get('n_goals', 0)}", NOT_COMPUTED,
                               "goals " + ", ".join(limit_state_title(g) for g in absent)))
    twins = {c["goals"][0]: c for c in m.get(COINCIDE_NOTE, [])}
    for c in m.get(COINCIDE_NOTE, []):
        a, b = (limit_state_title(g) for g in c["goals"])
        rows.append(Comparison(
            name, f"{a} and {b.lower()}: the same goal in this run", "seven distinct curves",
            f"identical mean, median and spread at all {c['n_R']} sizes "
            f"({c.get('n_motions')} motions each)", NOT_IN_PAPER,
            OVERTURNING_PHYSICS.format(eq=EQUATIONS)))
    for key, fit in m.items():
        if not key.startswith(LINE_NOTE):
            continue
        ls = key.removeprefix(LINE_NOTE)
        if ls in twins:  # said once, under the goal it coincides with
            continue
        r2 = fit.get("r_squared")
        rows.append(judged(
            name, f"{LINEAR_STATEMENT}, {limit_state_title(ls)} (§5.2, §6: "
            "'increases almost linearly with cylinder size R')", "almost straight lines",
            f"slope {fmt(fit.get('slope'))} 1/m, intercept {fmt(fit.get('intercept'))}, "
            f"R² = {fmt(r2, 4)} (n = {fit.get('n')}); the line departs from the mean by up to "
            f"{_pct(fit.get('max_rel_deviation'))}", linearity_ok(fit),
            LINEARITY_TOLERANCE, _bend_reason(fit),
            f"fewer than {MIN_FIT_SIZES} sizes R, or notes written before the criterion "
            "(regenerate the figure)"))
    return rows


def _pct(v) -> str:
    return f"{100 * v:.1f} %" if finite(v) else "not measured"


def linearity_ok(fit: Mapping) -> bool | None:
    """The linearity criterion of every study (:data:`LINEARITY_TOLERANCE`): the
    least-squares line stays within :data:`LINEAR_RTOL` of the mean spectrum at every R;
    None without a fit (or notes written before the criterion)."""
    dev = fit.get("max_rel_deviation")
    return bool(dev <= LINEAR_RTOL) if finite(dev) else None


def _bend_reason(fit: Mapping) -> str:
    """Why a mean spectrum is not a straight line, in numbers (:func:`shape_text`): flat
    throughout (a low R² of a small variation), flat, then rising, or rising with a bend."""
    if "flat_to_R" not in fit:
        return "the mean spectrum bends in R (R² below the tolerance)"
    signs = fit.get("residual_signs", "")
    runs = 1 + sum(a != b for a, b in zip(signs, signs[1:], strict=False)) if signs else 0
    pattern = (f"residuals from the line by R: {signs} "
               + ("(a bend: few long runs of one sign, not scatter)" if runs <= 3
                  else f"({runs} runs of one sign)"))
    if fit["flat_to_R"] >= fit["end_R"]:
        return (f"the mean spectrum is {shape_text(fit)}: the line explains little of so small "
                f"a variation; {pattern}")
    return f"the mean spectrum is not straight but {shape_text(fit)}; {pattern}"


# ---------------------------------------------------------------- the figure's entry

from rocking.plot.registry import FigureSpec  # noqa: E402

FIGURE = FigureSpec(
    name="fig10_goals", module=__name__, number=10, label="Fig 10",
    caption=(
        "Mean performance spectra of the study's performance goals θ > r·α and overturning "
        "(the mode and slenderness in the title), each goal in its own colour in every "
        "figure; dashed lines are the least-squares lines (fitted over five sizes R or "
        "more) whose R² and largest departure from the mean the legend gives. Goals whose "
        "statistics coincide at every R (a cylinder tilted past α at the threshold "
        "intensity overturned) are drawn dotted over each other and said so in the figure. "
        "The means are of each motion's critical intensity, I10 by default (the lowest "
        "PGA/(g tan α) near which 10 % of the intensities exceed), as the legend says; means "
        "over answers flagged plateau (I10 ill-conditioned) are counted per goal in the "
        "legend. Right axis PGA in g."
    ),
    paper=(
        "The paper's Fig 10: the undamped 3D model at tan α = 0.2 and seven goals, r ∈ "
        "{0.1, 0.2, 1/3, 0.5, 0.75, 1} and overturning, all almost linear in R (θ > α and "
        "overturning coincide in the paper run); goals a reduced run did not compute are "
        "named in the figure."
    ),
    scope="study", wanted=lambda s: bool(s.plan.modes),
    inputs={"means": "means", "motions": "motions"},
    params={"paper": "paper"},
    el_centro_only=True, general=lambda statement: statement.startswith(LINEAR_STATEMENT))
"""Fig 10, for every study; its linearity in R is stated of rocking spectra in general
(§6), judged in every study."""
