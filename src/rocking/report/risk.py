"""The risk section of a study's HTML report: assumptions, then λ of the main limit states.

:func:`risk_section_html` returns the section as an HTML fragment (``<h2>`` … tables) for
:func:`rocking.report.html.build` to append; :func:`assumptions` its statements as text.
"""

from __future__ import annotations

import base64
import html
import math
from pathlib import Path

import numpy as np
import pandas as pd

from rocking.fragility.table import CRITICAL_INTENSITY, STRIPES
from rocking.risk.risk_table import (
    MIN_RECORDS,
    below_first_warning,
    main_tan_alpha,
    preset_note,
    preset_warning,
    read_risk_table,
    shown_limit_states,
)
from rocking.spectra.modes import MODES


def assumptions(hazard: str = "") -> list[str]:
    """The statements a reader needs to use the numbers (one paragraph each)."""
    source = "Hazard: " + (hazard or "the study's hazard curve") + "."
    if "example_hazard_curve" in hazard:
        source += (" This curve is an EXAMPLE shipped with the repository, not a site's "
                   "hazard: PGA 0.25 g at 475 years and 0.50 g at 2475 years, plausible for "
                   "rock or stiff soil in a moderate-to-high seismicity region "
                   "(config/hazard/README.md).")
    return [
        source,
        "Intensity measure: the spectra's PGA in g is the vector peak of the horizontal "
        "pair, max √(ax² + ay²), the largest peak over all horizontal directions (RotD100 "
        "sampled finely) in every mode, 2D included. Hazard models give RotD50 or the "
        "geometric mean of the two components, smaller by about 1.2–1.3 for PGA. The "
        "fragility and the hazard are in one measure and one component (risk.csv's measure, "
        "component and component_source): the hazard's as declared (hazard: {file, "
        "component}), read from its file, or for an OpenQuake file that states none RotD50, "
        "the safe side; where it is not the fragility table's, the fragility is refitted in "
        "it from each motion's critical PGA and its own ratio of the two components. A "
        "manual factor on the hazard's levels (hazard.im_factor = f) is the alternative.",
        "Integration: λ_LS = ∫ P(LS | PGA) |dλ(PGA)| with the lognormal fragility (median, β) "
        "of the study's motions; the hazard is interpolated log-log between its levels and "
        "its first and last log-log slopes are extrapolated beyond them (share_extrapolated "
        "and share_below_first in risk.csv: the parts of λ that rest on the last and the "
        "first slope). Exceedances are Poisson: "
        "P(50 years) = 1 − exp(−50 λ).",
        "Fragility: record-to-record variability of the study's motions only (its records, "
        "and their synthetic pairs where it has them), with the 90 % bootstrap interval "
        "saying how far another set of as many motions could move λ; no modelling or hazard "
        "uncertainty.",
    ]


WHICH_TO_USE = (
    "Which λ risk uses: the lognormal of the motions' critical intensities (I₁₀), the "
    "critical-intensity rows, in the portfolio and the exports too. It exists at every body "
    "of the study's grid and in every measure and component (refitted per motion), which "
    "the stripes cannot be, and it errs on the safe side: I₁₀ is where a motion's local "
    "exceedance probability first reaches 0.1, below where it exceeds as often as not, so "
    "its λ lies above that of F(s). The stripe rows, each analysis jittered within ±w in "
    "ln s, estimate F(s) = the mean over the motions of their local exceedance probability: "
    "P(LS | PGA) itself, which converges as motions are added; their λ is the best "
    "estimate, and the ratio of the two says how conservative the headline is (on the El "
    "Centro study 0.39–0.93, docs/risk.md).")
"""The report's sentence on which of the two mean annual frequencies risk uses, and why."""


INTERVAL_MEANING = (
    "The 90 % interval of λ (lambda_p05 to lambda_p95 in risk.csv) is the spread of λ over "
    "1000 resamples of the study's motions drawn with replacement, each refitted and "
    "integrated again: the range within which λ would fall 9 times in 10 with another set of "
    "motions like these. It measures the record-to-record sampling uncertainty only, not the "
    "hazard's, the model's or the search preset's error.")
"""What the interval on λ means, in words (the report and docs/risk.md)."""


def hazard_sentence(risk) -> str:
    """The hazard's site and kind as risk.csv records them ('' for a table without them,
    as from a power law)."""
    frame = read_risk_table(risk)

    def said(column):
        if column not in frame.columns:
            return []
        return sorted({str(v) for v in frame[column].dropna() if str(v) not in ("", "nan")})

    sites, kinds = said("hazard_site"), said("hazard_kind")
    if not sites and not kinds:
        return ""
    text = "Hazard curve used: " + (f"site {'; '.join(sites)}, " if sites else "")
    return text + (f"kind {', '.join(kinds)}." if kinds else
                   "kind not stated by the file (taken as the mean).")


SOURCES = {"declared": "declared by the hazard entry", "file": "stated by the hazard file",
           "openquake-default": "not stated by the OpenQuake file: taken as RotD50, the "
                                "NGA-West2 models' component and the safe side",
           "assumed": "not stated by the hazard: taken as the study's"}
"""Where risk.csv's component comes from (``component_source``), in words."""


def terms_sentence(risk) -> str:
    """The measure and component λ was integrated in, where it comes from and whether the
    fragility was refitted in it ('' for a table written before these columns)."""
    frame = read_risk_table(risk)
    if "component_source" not in frame.columns or frame.empty:
        return ""
    first = frame.iloc[0]
    source = str(first["component_source"])
    base = source.split("+")[0]
    text = (f"Measure {first['measure']}, component {first['component']} "
            f"({SOURCES.get(base, base)})")
    if source.endswith("+refit"):
        text += ("; the critical-intensity fragility refitted in it from each motion's "
                 "critical PGA and its ratio of the two (motion_measures.csv)")
    return text + "."


def small_suite_warnings(risk) -> list[str]:
    """One sentence per fragility whose rows rest on fewer than :data:`MIN_RECORDS` motions:
    the interval's width at n and what 1/√n says more motions would give."""
    frame = read_risk_table(risk)
    if "n" not in frame.columns:
        return []
    out = []
    ok = frame[np.isfinite(frame["n"].astype(float)) & (frame["n"] < MIN_RECORDS)]
    for kind, rows in ok.groupby("fragility", sort=False):
        n = int(rows["n"].min())
        with np.errstate(all="ignore"):
            ratio = (rows["lambda_p95"] / rows["lambda_p05"]).astype(float)
        ratio = ratio[np.isfinite(ratio) & (ratio > 0)]
        text = (f"The {kind.replace('_', '-')} fragility rests on {n} motion(s) in some rows "
                f"(fewer than {MIN_RECORDS}): ")
        if ratio.empty:
            text += "no bootstrap interval could be formed there."
        else:
            width = float(np.median(ratio))
            at_ten = width ** math.sqrt(n / MIN_RECORDS)
            text += (f"the 90 % interval of λ spans a factor {width:.3g} (median over those "
                     f"rows, p95/p05); its log-width shrinks as 1/√n, so {MIN_RECORDS} motions "
                     f"would give about a factor {at_ten:.3g} and {4 * n} motions half the "
                     "log-width. Add records before relying on λ.")
        out.append(text)
    return out


def interval_table(risk, *, tan_alpha: float | None = None) -> pd.DataFrame:
    """λ with its 90 % interval (or the bracket bounds of a row without a fit) for the shown
    limit states at ``tan_alpha``, every fragility and mode; empty without rows."""
    frame = read_risk_table(risk)
    tan_alpha = main_tan_alpha(frame) if tan_alpha is None else tan_alpha
    if tan_alpha is None or "lambda_p05" not in frame.columns:
        return pd.DataFrame()
    frame = frame[(frame["tan_alpha"] - tan_alpha).abs() < 1e-9]
    frame = frame[frame["limit_state"].isin(shown_limit_states(frame))]
    return pd.DataFrame({
        "fragility": frame["fragility"], "mode": frame["mode"], "R [m]": frame["R"],
        "limit state": frame["limit_state"], "n": frame["n"],
        "λ [1/yr]": frame["maf"], "λ 5 % [1/yr]": frame["lambda_p05"],
        "λ 95 % [1/yr]": frame["lambda_p95"],
        "no fit: λ from [1/yr]": frame["lambda_lo"], "no fit: λ to [1/yr]": frame["lambda_hi"],
        "fit": frame["status"]}).reset_index(drop=True)


def comparison_table(risk) -> pd.DataFrame:
    """λ [1/yr] of the critical-intensity and of the stripe fragility side by side.

    One row per (mode, tan α, R, limit state) that has both, in the table's order, with
    their ratio (stripes / critical intensity) and the stripe fit's status; empty when the
    table has no stripe rows.
    """
    frame = read_risk_table(risk)
    keys = ["mode", "tan_alpha", "R", "limit_state"]
    critical = frame[frame["fragility"] == CRITICAL_INTENSITY]
    stripes = frame[frame["fragility"] == STRIPES]
    if stripes.empty:
        return pd.DataFrame()
    both = stripes[[*keys, "maf", "status"]].merge(critical[[*keys, "maf"]], on=keys,
                                                    suffixes=("_stripes", "_critical"))
    # rows without a fit on either side have no ratio: they are named in the gaps sentence
    both = both[np.isfinite(both["maf_stripes"]) & np.isfinite(both["maf_critical"])]
    if both.empty:
        return pd.DataFrame()
    return pd.DataFrame({
        "mode": both["mode"], "tan α [-]": both["tan_alpha"], "R [m]": both["R"],
        "limit state": both["limit_state"],
        "λ critical intensity [1/yr]": both["maf_critical"],
        "λ stripes [1/yr]": both["maf_stripes"],
        "stripes / critical intensity [-]": both["maf_stripes"] / both["maf_critical"],
        "stripe fit": both["status"],
    })


def summary_table(risk, *, tan_alpha: float | None = None) -> pd.DataFrame:
    """λ [1/yr] of the shown limit states (:func:`shown_limit_states`) per R (rows) and mode
    (columns) at ``tan_alpha`` (default :func:`main_tan_alpha`)."""
    frame = read_risk_table(risk)
    frame = frame[frame["fragility"] == CRITICAL_INTENSITY]  # the stripe rows: comparison_table
    tan_alpha = main_tan_alpha(frame) if tan_alpha is None else tan_alpha
    if tan_alpha is None:
        return pd.DataFrame()
    frame = frame[(frame["tan_alpha"] - tan_alpha).abs() < 1e-9]
    states = shown_limit_states(frame) if not frame.empty else []
    frame = frame[frame["limit_state"].isin(states)]
    if frame.empty:
        return pd.DataFrame()
    label = {ls: ("tilt θ > α/3" if ls == "tilt:1/3" else
                  "overturning" if ls == "overturning" else ls) for ls in states}
    frame = frame.assign(column=[f"{label[ls]}, {m} [1/yr]"
                                 for ls, m in zip(frame["limit_state"], frame["mode"],
                                                  strict=True)])
    table = frame.pivot_table(index="R", columns="column", values="maf", sort=False)
    order = [f"{label[ls]}, {m} [1/yr]" for ls in states for m in MODES]
    table = table[[c for c in order if c in table.columns]]
    table = table.reset_index().rename(columns={"R": "R [m]"})
    table.columns.name = None
    return table


def risk_section_html(risk, *, hazard: str = "", figure: str | Path | None = None) -> str:
    """The report's risk section as an HTML fragment.

    Parameters
    ----------
    risk : path or DataFrame
        ``results/<study>/risk.csv``.
    hazard : str
        Where the hazard curve came from (shown in the assumptions).
    figure : path, optional
        ``results/<study>/figures/risk.png``, embedded when given.
    """
    parts = ["<h2 id='risk'>From fragility to risk: mean annual frequency of exceedance</h2>"]
    parts += [f"<p>{html.escape(s)}</p>" for s in assumptions(hazard)]
    said = hazard_sentence(risk)
    if said:
        parts.append(f"<p>{html.escape(said)}</p>")
    terms = terms_sentence(risk)
    if terms:
        parts.append(f"<p>{html.escape(terms)}</p>")
    warning = below_first_warning(risk)
    if warning:
        parts.append(f"<p><strong>{html.escape(warning)}</strong></p>")
    if figure is not None and Path(figure).exists():
        data = base64.b64encode(Path(figure).read_bytes()).decode()
        # the same markup as the report's other figures, so a gallery links it instead
        parts.append(f"<figure id='risk'><img alt='risk' src='data:image/png;base64,{data}'>"
                     "</figure>")
    tan_alpha = main_tan_alpha(read_risk_table(risk))
    table = summary_table(risk, tan_alpha=tan_alpha)
    if table.empty:
        parts.append("<p>No fragility with a mean annual frequency in this run.</p>")
    else:
        parts.append(f"<p>Mean annual frequency λ [1/yr] at tan α = {tan_alpha:g} (return "
                     "period 1/λ; every mode, slenderness and limit state in risk.csv).</p>")
        parts.append(table.to_html(index=False, escape=True, border=0, na_rep="—",
                                   float_format=lambda v: f"{v:.3g}"))
    parts += _comparison_html(risk)
    parts += _uncertainty_html(risk, tan_alpha)
    return "\n".join(parts)


def _uncertainty_html(risk, tan_alpha) -> list[str]:
    """The interval in words, the preset's error and warning, small suites, rows without a
    fit."""
    frame = read_risk_table(risk)
    parts = ["<h3>How sure: the interval of λ, the preset, the rows without a fit</h3>",
             f"<p>{html.escape(INTERVAL_MEANING)}</p>"]
    presets = sorted({str(p) for p in frame.get("preset", pd.Series(dtype=str)).dropna()
                      if str(p) and str(p) != "nan"})
    for preset in presets:
        warning = preset_warning(preset)
        if warning:
            parts.append(f"<p><strong>{html.escape(warning)}</strong></p>")
        note = preset_note(preset)
        if note:
            parts.append(f"<p>{html.escape(note)}</p>")
    parts += [f"<p>{html.escape(w)}</p>" for w in small_suite_warnings(frame)]
    gaps = frame[~np.isfinite(frame["maf"].astype(float))]
    if not gaps.empty:
        parts.append(f"<p>{html.escape(_gap_sentence(gaps))}</p>")
    table = interval_table(frame, tan_alpha=tan_alpha)
    if not table.empty:
        parts.append(table.to_html(index=False, escape=True, border=0, na_rep="—",
                                   float_format=lambda v: f"{v:.3g}"))
    return parts


def _gap_sentence(gaps: pd.DataFrame) -> str:
    """What to use where a fit is missing."""
    bounded = gaps[np.isfinite(gaps["lambda_hi"].astype(float))] \
        if "lambda_hi" in gaps.columns else gaps.iloc[0:0]
    text = (f"{len(gaps)} row(s) of risk.csv have no fit (status: "
            f"{', '.join(sorted(set(map(str, gaps['status']))))}) and no λ. ")
    if not bounded.empty:
        text += (f"For {len(bounded)} of them the stripes bracket the step from no motion "
                 "exceeding to all exceeding: λ lies between lambda_lo and lambda_hi, the "
                 "hazard's rates at those two stripes; use lambda_hi as the conservative "
                 "value, or refine the stripes there. ")
    text += ("Elsewhere use the other fragility's λ of the same row, or add motions "
             "(critical-intensity fragility: fewer than two motions exceeded).")
    return text


def _comparison_html(risk) -> list[str]:
    """The two λ side by side with a sentence of numbers and which to use (none without
    stripe rows)."""
    both = comparison_table(risk)
    if both.empty:
        return []
    ratio = both["stripes / critical intensity [-]"]
    worst = both.loc[ratio.idxmin()]
    text = (f"The same integral with the multiple-stripe fragility, beside the "
            f"critical-intensity one ({len(both)} cells with both): the stripe λ is "
            f"{ratio.min():.2g}–{ratio.max():.2g} times the critical-intensity λ (smallest at "
            f"{worst['mode']}, R = {worst['R [m]']:g} m, {worst['limit state']}: "
            f"{worst['λ stripes [1/yr]']:.3g} against "
            f"{worst['λ critical intensity [1/yr]']:.3g} per year). ")
    odd = both[both["stripe fit"] != "ok"]
    if not odd.empty:
        text += (f"{len(odd)} stripe fit(s) are not 'ok' (e.g. 'extrapolated': the median lies "
                 "outside the stripes); their λ rests on the fitted lognormal's tail. ")
    return [f"<p>{html.escape(text + WHICH_TO_USE)}</p>",
            both.to_html(index=False, escape=True, border=0, na_rep="—",
                         float_format=lambda v: f"{v:.3g}")]


__all__ = ["INTERVAL_MEANING", "SOURCES", "WHICH_TO_USE", "assumptions", "comparison_table",
           "hazard_sentence", "terms_sentence", "interval_table", "risk_section_html",
           "small_suite_warnings", "summary_table"]
