"""The report's tables read from the study's CSV files: the per-record answers and the
fragility over a suite (:func:`records_section`), multiple-stripe against critical-intensity
medians (:func:`stripes_section`), the fragility table by size (:func:`fragility_pivot`) and
the linear fits of the mean spectra (:func:`linear_fit_rows`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from rocking.fragility.stripes import BOOTSTRAP_LEVEL, CONFIDENCE
from rocking.fragility.table import renamed
from rocking.plot._style import MODE_STYLE
from rocking.risk.portfolio import error_words
from rocking.spectra.limit_states import limit_state_title, severity
from rocking.units import read_table

MODE_LABEL = {m: s["label"] for m, s in MODE_STYLE.items()}
"""Reader's name of each analysis mode ("3D", "2D, x component")."""


def as_recorded_word(value) -> str:
    """records.csv's ``exceeds_as_recorded`` (one analysis at scale 1) in a table cell."""
    if pd.isna(value):
        return "analysis failed"
    return "yes" if str(value).lower() in ("true", "1") else "no"


def table_html(df: pd.DataFrame) -> str:
    """``df`` as an HTML table: no index, text escaped, missing values as a dash."""
    return df.to_html(index=False, escape=True, border=0, na_rep="—",
                      float_format=lambda v: f"{v:.4g}")


def records_section(records: str | Path, suite_fragility: str | Path | None = None
                    ) -> list[str]:
    """HTML of the per-record answers (``records.csv``) at the study's main mode and
    slenderness, largest and smallest R, and of the fragility over the suite in each
    intensity measure (``suite_fragility.csv``; fits only)."""
    df = pd.read_csv(records)
    parts = ["<h2 id='records'>The recorded motions one by one</h2>"]
    if df.empty:
        return parts + ["<p>No recorded motion in this study.</p>"]
    ta = next(c for c in df.columns if c.startswith("tan_alpha"))
    r = next(c for c in df.columns if c.startswith("R"))
    sf = next(c for c in df.columns if c.startswith("scale_factor"))
    crit = next(c for c in df.columns if c.startswith("pga_crit_g"))
    rec = next(c for c in df.columns if c.startswith("pga_g"))
    sizes = sorted(set(df[r]))
    keep = df[df[r].isin({sizes[0], sizes[len(sizes) // 2], sizes[-1]})]
    table = pd.DataFrame({
        "record": keep["motion"], "mode": keep["mode"].map(lambda m: MODE_LABEL.get(m, m)),
        "tan α": keep[ta], "limit state": keep["limit_state"].map(limit_state_title),
        "R [m]": keep[r], "PGA processed [g]": keep[rec], "critical PGA [g]": keep[crit],
        "scale factor to exceed": keep[sf],
        "exceeds as recorded": keep["exceeds_as_recorded"].map(as_recorded_word),
    })
    parts.append(f"<p>Per record: the factor its processed version must be scaled by to "
                 f"exceed each limit state, at R = {sizes[0]:g}, {sizes[len(sizes) // 2]:g} "
                 f"and {sizes[-1]:g} m (every size, Sa(T) and PGV: records.csv).</p>")
    parts.append(table_html(table))
    if suite_fragility is not None and Path(suite_fragility).exists():
        fr = pd.read_csv(suite_fragility)
        fr = fr[np.isfinite(pd.to_numeric(fr["median"], errors="coerce"))]
        if fr.empty:
            parts.append("<p>Fragility over the suite: no fit (too few records reached the "
                         "limit states).</p>")
        else:
            out = pd.DataFrame({
                "motions": fr["motions"], "mode": fr["mode"].map(lambda m: MODE_LABEL.get(m, m)),
                "tan α": fr["tan_alpha"], "limit state": fr["limit_state"].map(
                    limit_state_title), "R [m]": fr["R"],
                "measure": fr["measure"] + " [" + fr["unit"].astype(str) + "]",
                "median IM₅₀": fr["median"], "β": fr["beta"], "n": fr["n"],
                "censored": fr["n_censored"]})
            parts.append("<p id='suite-fragility'>Lognormal fragility over the suite in each "
                         "intensity measure (median IM₅₀ in the measure's unit; recorded "
                         "motions and synthetic pairs fitted separately).</p>")
            parts.append(table_html(out))
    return parts


def stripes_section(path: str | Path) -> list[str]:
    """HTML of the report's stripe-fragility section: what each answer means, then one row
    per (mode, limit state, tan α, R) with both medians and their ratio."""
    df = renamed(read_table(path))
    ok = df[np.isfinite(df["ratio"].to_numpy(dtype=float))]
    parts = ["<h2 id='stripes'>Two answers to \"how strong must the earthquake be\": "
             "critical intensities and multiple-stripe fragility</h2>",
             "<p>The answer of the spectra and of the fragility curves above is each "
             "motion's <em>critical intensity</em> (the study's quantity, I10 by default: the "
             "smallest PGA/(g tan α) at which at least 10 % of the intensities near it exceed "
             "the limit state; the paper's is the first exceedance), then the lognormal fit "
             "over motions: the critical-intensity fragility. Rocking near a limit state is "
             "chaotic in the intensity: a motion exceeds it in narrow windows and the body "
             "survives stronger scalings of the same motion, so a motion's critical intensity "
             "is where exceedance <em>starts</em>, not where it becomes likely. The "
             "<em>multiple-stripe</em> "
             "fragility analyses every motion once at each of a fixed set of intensities and "
             "fits the share exceeding by binomial maximum likelihood: its median is the "
             "intensity at which half the motions exceed. It "
             "converges as stripes are added (docs/performance.md). In brackets: beside the "
             "median "
             f"in PGA/(g tan α) its {100 * CONFIDENCE:g} % Wald interval (the binomial fit's "
             f"curvature), beside the median in g its {100 * BOOTSTRAP_LEVEL:g} % bootstrap "
             "interval over the motions.</p>"]
    measure = str(df["measure"].iloc[0]) if "measure" in df and len(df) else "pga"
    name = "PGA" if measure == "pga" else measure
    if ok.empty:
        parts.append("<p>No (mode, limit state, R) has both fits in this run"
                     + ("" if measure == "pga" else f" (the stripes are in {name}, the critical "
                        "intensities in PGA)") + ".</p>")
        if measure == "pga" or df.empty:
            return parts
    else:
        ratio = ok["ratio"].to_numpy(dtype=float)
        parts.append(f"<p>Over the {len(ok)} cells with both fits, the stripe median is "
                     f"{np.min(ratio):.2f}–{np.max(ratio):.2f} times the critical-intensity "
                     f"median (median ratio {np.median(ratio):.2f}): a column designed with "
                     "the critical intensities is designed for the onset of exceedance, with "
                     "the stripe median as its 50 % point.</p>")
    nan = pd.Series(np.nan, index=df.index)
    rows = pd.DataFrame({
        "mode": df["mode"], "limit state": df["limit_state"].map(limit_state_title),
        "tan α": df["tan_alpha"], "R [m]": df["R"],
        f"stripe median [{name}/(g tan α)] ({100 * CONFIDENCE:g} % Wald)": [
            f"{m:.3g} ({lo:.3g}–{hi:.3g})" if np.isfinite(m) else f"— ({st})"
            for m, lo, hi, st in zip(df["median"], df["median_lo"], df["median_hi"],
                                     df["status"], strict=True)],
        # in the measure's unit: the bootstrap's interval, or where no lognormal fits
        # the stripes that bracket the median (never a number for a missing fit)
        f"stripe median [{name}, g], {100 * BOOTSTRAP_LEVEL:g} % over motions": [
            f"{m:.3g} ({a:.3g}–{b:.3g})" if np.isfinite(m) and np.isfinite(a)
            else f"{m:.3g}" if np.isfinite(m)
            else f"between {lo:.3g} and {hi:.3g}" if np.isfinite(lo) else "—"
            for m, a, b, lo, hi in zip(df.get("median_im", nan), df.get("median_p05", nan),
                                       df.get("median_p95", nan), df.get("bracket_lo", nan),
                                       df.get("bracket_hi", nan), strict=True)],
        "stripe β": df["beta"].map(lambda b: f"{b:.2f}" if np.isfinite(b) else "—"),
        "critical-intensity median": df["critical_median"].map(
            lambda m: f"{m:.3g}" if np.isfinite(m) else "—"),
        "ratio": df["ratio"].map(lambda r: f"{r:.2f}" if np.isfinite(r) else "—"),
        "motions × stripes": [f"{n} × {k}" + (f" + {int(a)} added" if a > 0 else "")
                              for n, k, a in zip(df["n_motions"], df["stripes"],
                                                 df.get("n_refined", nan).fillna(0),
                                                 strict=True)],
    })
    parts.append(table_html(rows))
    return parts


def fragility_pivot(path: str | Path) -> pd.DataFrame:
    """The fragility table as one row per (mode, limit state, tan α) and one column per R.

    Each cell is ``"median (β)"`` with the median in PGA/(g tan α) (× tan α for g) and, when
    motions were right-censored at the search bound, ``"+k>"`` for the k of them. Points not
    computed (no fit) are left out: a reader wants the fits, not the empty grid.
    """
    df = pd.read_csv(path)
    med = next(c for c in df.columns if c.startswith("median [") or c == "median")
    ta = next(c for c in df.columns if c.startswith("tan_alpha"))
    r = next(c for c in df.columns if c.startswith("R"))
    df = df[np.isfinite(pd.to_numeric(df[med], errors="coerce"))]
    if df.empty:
        return pd.DataFrame()
    beta = next(c for c in df.columns if c.startswith("beta"))
    cens = "n_censored" if "n_censored" in df.columns else None

    def cell(row) -> str:
        text = f"{row[med]:.3g} ({row[beta]:.2f})"
        if cens and row[cens] > 0:
            text += f" {int(row[cens])}>"
        return text

    df = df.assign(cell=df.apply(cell, axis=1))
    out = df.pivot_table(index=["mode", "limit_state", ta], columns=r, values="cell",
                         aggfunc="first", sort=False)
    out.columns = [f"R = {c:g}" for c in out.columns]
    out = out.reset_index().rename(columns={"limit_state": "limit state", ta: "tan α"})
    return out.assign(**{"limit state": out["limit state"].map(limit_state_title)})


def linear_fit_rows(path: str | Path) -> pd.DataFrame:
    """Linear fits of the mean spectra over enough sizes to mean something (at least
    :data:`.fig10_goals.MIN_FIT_SIZES`; rows without a fit dropped), limit states
    in words."""
    from rocking.plot.fig10_goals import MIN_FIT_SIZES

    df = pd.read_csv(path)
    n = next((c for c in df.columns if c == "n"), None)
    df = df[df[n] >= MIN_FIT_SIZES] if n is not None else df
    if "limit_state" in df:
        df = df.assign(limit_state=df["limit_state"].map(limit_state_title))
    return df


SHOWN_IN_REPORT = 10
"""Columns of the ranked table in the report (the highest λ of the most severe state)."""



def section_html(portfolio: str | Path | pd.DataFrame) -> list[str]:
    """The report's section on the inventory: what was computed, the ranked columns of the
    most severe limit state with their intervals, and the two figures (captions from their
    sidecars, beside ``figures/`` of the study)."""
    import html

    from rocking.report.tables import table_html
    from rocking.risk.portfolio import read_portfolio, site_lines

    frame = portfolio if isinstance(portfolio, pd.DataFrame) else read_portfolio(portfolio)
    states = sorted(frame["limit_state"].unique(), key=severity, reverse=True)
    top = frame[frame["limit_state"] == states[0]].sort_values("rank", kind="stable")
    site_csv = (Path(portfolio).with_name("portfolio_site.csv")
                if not isinstance(portfolio, pd.DataFrame) else None)
    site = (pd.read_csv(site_csv) if site_csv is not None and site_csv.is_file()
            else pd.DataFrame(frame.attrs["site"]) if frame.attrs.get("site") else None)
    error = float(top["interp_error"].iloc[0])
    sites = sorted(set(frame["hazard_site"].astype(str)))
    extrapolated = int(frame.drop_duplicates("id")["extrapolated"].astype(bool).sum())
    text = (f"{frame['id'].nunique()} columns of the inventory, each with the study's "
            f"fragility interpolated at its R and tan α (mode {frame['mode'].iloc[0]}, "
            f"{frame['measure'].iloc[0]} in the hazard's {frame['component'].iloc[0]} "
            "component; interpolation error of the "
            f"median for {limit_state_title(states[0])}: {error_words(error)}) and "
            "integrated against the hazard curve of its "
            f"site ({len(sites)} site(s) used: {', '.join(sites[:5])}"
            f"{' …' if len(sites) > 5 else ''}). Intervals are 90 % over bootstrap "
            "resamples of the motions. "
            + (f"{extrapolated} column(s) lie beyond the study's grid (extrapolated, "
               "marked in portfolio.csv). " if extrapolated else "")
            + "Every column and limit state: portfolio.csv.")
    shown = top.head(SHOWN_IN_REPORT)
    table = pd.DataFrame({
        "rank": shown["rank"], "id": shown["id"], "R [m]": shown["R"],
        "tan α [-]": shown["tan_alpha"], "median [g]": shown["median"],
        "β [-]": shown["beta"], "λ [1/yr]": shown["lambda"],
        "λ 5 % [1/yr]": shown["lambda_p05"], "λ 95 % [1/yr]": shown["lambda_p95"],
        "return period [yr]": shown["return_period"], "P(50 yr) [-]": shown["p_50yr"],
        "hazard site": shown["hazard_site"], "distance [km]": shown["hazard_distance_km"]})
    more = (f" (the {SHOWN_IN_REPORT} highest of {len(top)})"
            if len(top) > SHOWN_IN_REPORT else "")
    answer = ([f"<p>The site: {html.escape(line)}.</p>" for line in site_lines(site)]
              if site is not None and len(site) else [])
    return ["<h2 id='portfolio'>Every column of the site (beyond the paper)</h2>",
            f"<p>{html.escape(text)}</p>", *answer,
            f"<p>{html.escape(limit_state_title(states[0]))}, ranked by λ{more}:</p>",
            table_html(table)]
