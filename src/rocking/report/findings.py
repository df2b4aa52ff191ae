"""The report's findings: its headline answers, each a line with its number and a link to
the figure or table it comes from. A reproduction of the paper gets the paper's (Fig 12's
both components against one, Fig 9's damping, Fig 10's linearity, Fig 6's peak tilts:
:func:`paper_findings`); every study the answers of its tables (most dangerous record, median
capacities, λ, stripe against critical-intensity medians: :func:`study_findings`).
"""

from __future__ import annotations

import html
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from rocking.dynamics.names import MODEL_3D, MODEL_3D_DAMPED
from rocking.fragility.table import CRITICAL_INTENSITY
from rocking.plot.comparisons import Comparison, finite
from rocking.report.entries import FigureEntry
from rocking.report.tables import MODE_LABEL, as_recorded_word
from rocking.spectra.limit_states import limit_state_title, severity
from rocking.spectra.modes import MODE_3D
from rocking.units import read_table


def _as_recorded_finding(row) -> str:
    """What the analysis of the record at scale 1 says, and whether the scale factor agrees
    (rocking is not monotonic in the intensity: docs/records.md)."""
    word = as_recorded_word(row.get("exceeds_as_recorded"))
    if word == "analysis failed":
        return "its analysis as recorded failed"
    said = "as recorded (scale 1) it exceeds" if word == "yes" else \
        "as recorded (scale 1) it does not"
    if str(row.get("as_recorded_disagrees", "")).lower() in ("true", "1"):
        said += " although the scale factor says otherwise: the response is not monotonic"
    return said


def headline_text(who: str, R: float, mean: float, std: float | None, n: float | None,
                  answer: str, grids: Mapping | None = None, paper: bool = False) -> str:
    """The headline (3D overturning at R = 10 m): the mean of the study's answer with its
    standard error, and beside it the mean first exceedance of the same cells on each scan
    grid (``grids``: :func:`rocking.study.headline.summary`, where its cells are these), so
    that a reader sees why the paper's "about 4" and a coarse grid's higher mean can both be
    found."""
    se = f" ± {std / math.sqrt(n):.2f} (standard error, {n:g} motions)" if finite(
        std, n) and n > 0 else ""
    text = (f"{who}, R = {R:g} m: the 3D model overturns at a mean {answer} of {mean:.2f}{se}"
            f" ({answer}: the lowest PGA/(g tan α) near which {answer[1:]} % of the "
            "intensities exceed)" if answer.startswith("I") else
            f"{who}, R = {R:g} m: the 3D model overturns at a mean {answer} of {mean:.2f}{se}")
    if grids and grids.get("grids") and math.isclose(float(grids.get("R", R)), R):
        by = ", ".join(f"{v:.2f} ({100 * s:g} %)" for s, v in grids["grids"].items())
        over = (f", over {grids['n']} of {grids['of']} motions"
                if grids["n"] != grids["of"] else "")
        text += (f"; the same cells' mean first exceedance, by scan grid: {by}{over}: the "
                 "classic answer falls as its grid is refined")
    return text + (" (paper: about 4)" if paper else "")


def _median_text(x, med: str, r: str) -> str:
    """A median of ``fragility.csv`` with its β."""
    return f"{x[med]:.2f} (β {x['beta [-]']:.2f}) at R = {x[r]:g} m"


@dataclass(frozen=True)
class Finding:
    """One line of the report's findings summary: its text (with its number) and the
    anchor in the page of the figure or table it comes from."""

    text: str
    anchor: str


def _stem(entries: Sequence[FigureEntry], name: str) -> str | None:
    """Anchor (file stem) of the first figure of kind ``name`` in ``entries``."""
    return next((e.stem for e in entries if e.name == name), None)


def _notes(entries: Sequence[FigureEntry], name: str) -> Mapping:
    return next((e.notes for e in entries if e.name == name), {}).get("measured", {}) or {}


def _ensemble_title(m: Mapping, ens: str) -> str:
    """``"El Centro (elcentro)"``: an ensemble of Fig 12's notes by its record's label."""
    return re.sub(r": mean of \d+ motions?$", "", str(m.get(f"{ens}|label", ens)))


def _one_component_ratios(m12: Mapping, ens: str, modes: Sequence[str],
                          R: float) -> list[str]:
    """``"overturning x 2.10× (…), y 1.90×; excessive tilt …"``: the means under one
    component of ``modes`` over the 3D model's under both, from Fig 12's notes (the
    censoring-aware medians across R where the notes have them, else the means at ``R``)."""
    from rocking.plot.fig12_2d_vs_3d import ratio_evidence

    out = []
    for ls in ("overturning", "tilt:1/3"):
        key = "excessive tilt" if ls != "overturning" else ls
        parts = []
        for c in modes:
            ev = ratio_evidence(m12, ens, key, c)
            base, v1 = m12.get(f"{ens}|{key}|3d"), m12.get(f"{ens}|{key}|{c}")
            if ev is not None:
                text = (f"{c[-1]} {ev['pooled']:.2f}× (censoring-aware medians, geometric mean "
                        f"over {len(ev['R'])} sizes: {min(ev['ratio']):.2f}–"
                        f"{max(ev['ratio']):.2f}×)")
            elif finite(base, v1):  # notes without the fitted medians
                text = f"{c[-1]} {v1 / base:.2f}× (means at R = {R:g} m only)"
            else:
                continue
            parts.append(text)
        if parts:
            out.append(f"{key} " + ", ".join(parts))
    return out


def paper_findings(entries: Sequence[FigureEntry],
                   verdicts: Mapping[str, Sequence[Comparison]], study: str = "",
                   headlines: Mapping[str, Mapping] | None = None) -> list[Finding]:
    """Headline answers of a reproduction of the paper, read from the figures' notes:
    one component against both and the 3D mean at R = 10 m (Fig 12: every study it draws,
    ``study``'s first), damped against undamped (Fig 9), linearity in R (Fig 10), the El
    Centro peak tilts (Fig 6).

    ``headlines``: per study, :func:`rocking.study.headline.summary` of its
    ``headline.csv``: the 3D mean at R = 10 m is then said with the mean first exceedance
    of the same cells on each scan grid beside it (:func:`headline_text`)."""
    out = []
    m12, a12 = _notes(entries, "fig12_2d_vs_3d"), _stem(entries, "fig12_2d_vs_3d")
    if a12 is not None:
        R = m12.get("R", 10.0)
        names = sorted({k.split("|")[0] for k in m12 if k.count("|") >= 2})
        names = sorted(names, key=lambda n: n != study)  # the study's own curves first
        from rocking.plot.fig12_2d_vs_3d import (
            HOUSNER_COMPARATORS,
            HOUSNER_NOTE,
            PAPER_COMPARATORS,
        )

        for ens in names:
            v3 = m12.get(f"{ens}|overturning|3d")
            if not finite(v3):
                continue
            std, n = m12.get(f"{ens}|overturning|3d|std"), m12.get(f"{ens}|overturning|3d|count")
            paper_ratios = _one_component_ratios(m12, ens, PAPER_COMPARATORS, R)
            housner_ratios = _one_component_ratios(m12, ens, HOUSNER_COMPARATORS, R)
            who = _ensemble_title(m12, ens)
            # the paper gives the 3D number (and "about twice") for El Centro only
            centro = "centro" in (ens + who).lower()
            text = headline_text(who, R, v3, std, n, str(m12.get("answer", "I10")),
                                 (headlines or {}).get(ens), centro)
            if paper_ratios:
                twice = "; paper: about twice" if centro else ""
                text += ("; under one component the same 3D model needs (the paper's "
                         f"comparison, §5.4{twice}): {'; '.join(paper_ratios)}")
            if housner_ratios:
                text += ("; Housner's 2D block under one component, a further comparator, "
                         f"needs: {'; '.join(housner_ratios)} ({HOUSNER_NOTE})")
            if paper_ratios or housner_ratios:
                text += " (x = major, y = minor axis; ratios to the 3D model under both)"
            out.append(Finding(text, a12))
    m9, a9 = _notes(entries, "fig09_spectra"), _stem(entries, "fig09_spectra")
    for key, eff in m9.items():
        if not key.startswith("damping|") or not isinstance(eff, Mapping):
            continue
        worst, k, R = eff.get("max_abs_rel_diff_means"), eff.get("R_index_of_max"), m9.get("R")
        row = next((c for c in verdicts.get("fig09_spectra", [])
                    if limit_state_title(key.removeprefix("damping|")) in c.statement), None)
        if finite(worst):
            from rocking.plot.criteria import PER_MOTION_TOL, share_within

            within, total = share_within([v for rel in (eff.get("per_motion") or {}).values()
                                          for v in rel if v is not None])
            per = (f"; per motion {within} of {total} (motion, R) pairs within "
                   f"±{100 * PER_MOTION_TOL:g} %") if total else ""
            at = f" (at R = {R[k]:g} m)" if R and k is not None else ""
            at += per
            out.append(Finding(
                f"Damped against undamped, {limit_state_title(key.removeprefix('damping|'))}: "
                f"the ensemble means differ by at most {100 * worst:.1f} %{at}"
                + (f" — {row.verdict}" if row else "")
                + " (paper: essentially identical)", a9))
    from rocking.plot.fig10_goals import LINEAR_STATEMENT, LINEARITY_TOLERANCE

    rows10 = [c for c in verdicts.get("fig10_goals", [])
              if c.statement.startswith(LINEAR_STATEMENT)]
    rows10 = [c for c in rows10 if c.verdict in ("reproduced", "differs")]
    if rows10:
        ok = sum(c.verdict == "reproduced" for c in rows10)
        r2 = [float(x) for c in rows10 for x in re.findall(r"R² = ([0-9.]+)", c.ours)]
        span = f"; R² {min(r2):.3f}–{max(r2):.3f}" if r2 else ""
        out.append(Finding(
            f"Linearity in R (paper: 'almost straight lines'): {ok} of {len(rows10)} mean "
            f"spectra pass the one criterion of every study ({LINEARITY_TOLERANCE}"
            f"){span}" + ("" if ok == len(rows10) else "; those that fail bend: flat near the "
                          "uplift intensity at small R, then rising"),
            _stem(entries, "fig10_goals") or ""))
    m6 = _notes(entries, "fig06_el_centro")
    u, d = m6.get(f"theta_max_{MODEL_3D}"), m6.get(f"theta_max_{MODEL_3D_DAMPED}")
    if finite(u, d):
        out.append(Finding(
            f"El Centro, R = 6 m, tan α = 0.2 (Fig 6): peak tilt θmax {u:.4f} rad undamped and "
            f"{d:.4f} rad damped (paper: 0.0838 and 0.0668 rad); the companion figure shows "
            "θmax scattering by a factor of two within ±5 % of the scale", _stem(
                entries, "fig06_el_centro") or ""))
    return out




def _main(df: pd.DataFrame, col: str, prefer: Sequence) -> object | None:
    """The first of ``prefer`` present in column ``col``, else its most frequent value."""
    values = list(dict.fromkeys(df[col]))
    hit = next((p for p in prefer if p in values), None)
    return hit if hit is not None else (df[col].mode().iloc[0] if len(df) else None)


def study_findings(*, entries: Sequence[FigureEntry] = (), fragility=None, records=None,
                   risk=None, stripes=None) -> list[Finding]:
    """Headline answers of any study: the most dangerous record (``records.csv``), the
    median capacities (``fragility.csv``), λ with its interval (``risk.csv``; 5–95 % when
    the table has ``lambda_p05``/``lambda_p95``) and the stripe against critical-intensity
    medians. Each at the study's main mode (3D where run), slenderness and largest R."""
    out = []
    if records is not None and Path(records).exists():
        df = pd.read_csv(records)
        if len(df):
            mode = _main(df, "mode", [MODE_3D])
            df = df[df["mode"] == mode]
            ta = next(c for c in df.columns if c.startswith("tan_alpha"))
            ls = _main(df, "limit_state", ["overturning"])
            t = _main(df, ta, [0.2])
            r = next(c for c in df.columns if c.startswith("R"))
            sub = df[(df["limit_state"] == ls) & (df[ta] == t)]
            n_records = sub["motion"].nunique()
            sub = sub[sub[r] == sub[r].max()]
            sf = next(c for c in sub.columns if c.startswith("scale_factor"))
            sub = sub[np.isfinite(pd.to_numeric(sub[sf], errors="coerce"))]
            if len(sub):
                worst = sub.loc[sub[sf].idxmin()]
                g = next(c for c in sub.columns if c.startswith("pga_crit_g"))
                who = (f"The most dangerous of the {n_records} records is {worst['motion']}: it"
                       if n_records > 1 else f"The record {worst['motion']}")
                out.append(Finding(
                    f"{who} exceeds {limit_state_title(ls).lower()} of the R = {worst[r]:g} m, "
                    f"tan α = {t:g} cylinder ({MODE_LABEL.get(mode, mode)}) when scaled by "
                    f"{worst[sf]:.2f} (critical PGA {worst[g]:.3f} g); "
                    + _as_recorded_finding(worst), "records"))
    if fragility is not None and Path(fragility).exists():
        df = pd.read_csv(fragility)
        med = next(c for c in df.columns if c.startswith("median ["))
        df = df[np.isfinite(pd.to_numeric(df[med], errors="coerce"))]
        if len(df):
            ta = next(c for c in df.columns if c.startswith("tan_alpha"))
            r = next(c for c in df.columns if c.startswith("R"))
            mode = _main(df, "mode", [MODE_3D])
            t = _main(df[df["mode"] == mode], ta, [0.2])
            sub = df[(df["mode"] == mode) & (df[ta] == t)]
            present = list(dict.fromkeys(sub["limit_state"]))
            shown = [ls for ls in ("overturning", "tilt:1/3") if ls in present] or sorted(
                present, key=severity, reverse=True)[:2]
            texts = []
            for ls in shown:
                rows = sub[sub["limit_state"] == ls].sort_values(r)
                ends = rows.iloc[[0, -1]] if len(rows) > 1 else rows
                texts.append(f"{limit_state_title(ls).lower()} " + " to ".join(
                    _median_text(x, med, r) for _, x in ends.iterrows()))
            out.append(Finding(
                f"Median capacities IM₅₀ in PGA/(g tan α), {MODE_LABEL.get(mode, mode)}, "
                f"tan α = {t:g}: " + "; ".join(texts), "fragility"))
    if risk is not None and Path(risk).exists():
        from rocking.report.risk import main_tan_alpha, read_risk_table
        frame = read_risk_table(risk)
        df = frame[(frame["fragility"] == CRITICAL_INTENSITY) & np.isfinite(frame["maf"])]
        if len(df):
            mode = _main(df, "mode", [MODE_3D])
            t = main_tan_alpha(df[df["mode"] == mode])
            ls = _main(df, "limit_state", ["overturning"])
            stripes_df = frame[(frame["fragility"] != CRITICAL_INTENSITY)
                               & np.isfinite(frame["maf"])] if "fragility" in frame else \
                frame.iloc[:0]
            sub = df[(df["mode"] == mode) & (df["tan_alpha"] == t)
                     & (df["limit_state"] == ls)].sort_values("R")
            stripe = stripes_df[(stripes_df["mode"] == mode) & (stripes_df["tan_alpha"] == t)
                                & (stripes_df["limit_state"] == ls)].sort_values("R")
            if len(sub):
                def lam(x) -> str:
                    text = f"{x['maf']:.2g} /yr at R = {x['R']:g} m"
                    if finite(x.get("lambda_p05"), x.get("lambda_p95")):
                        text += f" (5–95 %: {x['lambda_p05']:.2g}–{x['lambda_p95']:.2g})"
                    return text
                ends = sub.iloc[[0, -1]] if len(sub) > 1 else sub
                text = (f"Annual frequency λ of {limit_state_title(ls).lower()}, "
                        f"{MODE_LABEL.get(mode, mode)}, tan α = {t:g}, fragility of the "
                        "per-motion answers under the study's hazard curve: "
                        + " to ".join(lam(x) for _, x in ends.iterrows()))
                if len(stripe):  # the λ the risk section recommends
                    text += "; with the multiple-stripe fragility " + ", ".join(
                        lam(x) for _, x in stripe.iterrows())
                out.append(Finding(text, "risk"))
    if stripes is not None and Path(stripes).exists():
        df = read_table(stripes)
        ratio = df["ratio"].to_numpy(dtype=float)
        ratio = ratio[np.isfinite(ratio)]
        if ratio.size:
            out.append(Finding(
                f"Multiple-stripe median against the median of the per-motion answers: "
                f"{ratio.min():.2f}–{ratio.max():.2f}× over {ratio.size} cells (a per-motion "
                "answer marks where exceedance begins near it, the stripe median where half "
                "the motions exceed)", "stripes"))
    return out


TABLE_ANCHORS = ("records", "fragility", "stripes")
"""Anchors of the report's tables (the other findings link a figure)."""


def findings_html(findings: Sequence[Finding]) -> str:
    """The findings summary: a list, each line linking to where its number comes from."""
    if not findings:
        return "<p>No headline answer could be read from this run's outputs.</p>"
    def link(anchor: str) -> str:
        what = "table" if anchor in TABLE_ANCHORS else "figure"
        return f" <a href='#{html.escape(anchor)}'>({what})</a>" if anchor else ""

    items = "".join(f"<li>{html.escape(f.text)}.{link(f.anchor)}</li>" for f in findings)
    return f"<ul class='findings'>{items}</ul>"
