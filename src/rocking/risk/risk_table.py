"""The risk table: every requested fragility of a study under one hazard curve.

One row per requested (mode, tan α, R, limit state) of each fragility, with or without a fit:
the median capacity and β, the mean annual frequency λ_LS [1/yr]
(:func:`rocking.risk.annual_frequency.mean_annual_frequency`) with its 90 % bootstrap interval
over the motions (``lambda_p05``, ``lambda_p95``: each resample of the motions refitted and
integrated, :mod:`rocking.fragility.bootstrap`), the return period 1/λ_LS [yr], the probability of
at least one exceedance in 50 years (Poisson), the share of λ_LS that rests on extrapolating
the hazard curve's last slope (``share_extrapolated``) and on its first slope extrapolated
below its first level (``share_below_first``: the hazard table says nothing there, levels
with probability of exceedance 1 dropped included; warned about above
:data:`rocking.report.risk.BELOW_FIRST_WARN`), and the hazard's site and kind
(``hazard_site``, ``hazard_kind``: :class:`rocking.risk.hazard.HazardCurve`).

A row without a fit (median NaN: too few motions exceeded, or a separated stripe fit) is
present with its ``status`` and λ NaN; for stripes the bracketing stripes bound it: λ lies
between the hazard's rates at the two stripes that bracket the step from no motion exceeding
to all exceeding (``lambda_lo`` = λ(bracket_hi), ``lambda_hi`` = λ(bracket_lo); NaN where a
side is open).

The first column, ``fragility``, says which fragility the row integrates
(``critical_intensity`` or ``stripes``, :data:`rocking.fragility.table.KINDS`), ``measure`` in
which intensity measure, ``component`` in which horizontal component (that of the
fragility and of the hazard: they are never mixed); the last, ``status``, the fit's
status. :func:`risk_tables` stacks the tables of several fragilities of a study, so that
both answers stand side by side in one ``risk.csv``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pandas as pd

from rocking.fragility.table import CRITICAL_INTENSITY, Fragilities, renamed, sort_rows
from rocking.motions.measures import same_measure
from rocking.risk.annual_frequency import (
    annual_frequency_interval,
    annual_frequency_parts,
    probability_in,
)
from rocking.risk.hazard import HazardCurve
from rocking.spectra.limit_states import (
    EXCESSIVE_TILT,
    OVERTURNING,
    parse_limit_state,
    severity,
)
from rocking.units import header, strip_units

YEARS = 50.0
"""Exposure time of the probability column [yr] (``p_50yr``)."""

CI = 0.90
"""Central probability of the bootstrap interval of λ (5th to 95th percentile)."""

COLUMNS = ("fragility", "measure", "component", "component_source", "mode", "tan_alpha", "R",
           "limit_state",
           "median_im", "median_pga_g", "beta", "n", "maf", "lambda_p05", "lambda_p95",
           "lambda_lo", "lambda_hi", "return_period", "p_50yr", "share_extrapolated",
           "share_below_first", "hazard_site", "hazard_kind", "preset", "status")
"""Columns of :func:`risk_table` (with units in their titles, :func:`rocking.units.header`)."""


def risk_table(fragility, hazard: HazardCurve, *, preset: str = "",
               assumed: tuple[str, str] | None = None) -> pd.DataFrame:
    """Mean annual frequency, its interval, return period and 50-year probability of each
    limit state.

    Parameters
    ----------
    fragility : Fragilities, path, DataFrame or Dataset
        The study's fragilities, or anything
        :func:`rocking.fragility.table.read_fragilities` reads: brought into the hazard's
        measure, component and unit by :func:`rocking.risk.reconcile.reconcile` (refitted
        from the study's motions where its table is in another component), or refused.
    hazard : HazardCurve
        The site's hazard curve.
    preset : str
        The accuracy preset of the analyses behind the fragility ('' unknown), carried in
        the ``preset`` column (the report warns about ``fast``).
    assumed : (str, str), optional
        The component taken where the hazard states none, and whose it is (the workflow:
        the study's); default the fragility's.

    Returns
    -------
    pandas.DataFrame
        :data:`COLUMNS`, titles with units (``maf [1/yr]``, ``return_period [yr]`` ...);
        ``attrs["skipped"]`` names the rows without a fit, ``attrs["note"]`` what was
        assumed or refitted to meet the hazard's terms.
    """
    from rocking.risk.reconcile import reconcile

    frag = reconcile(fragility, hazard, assumed=assumed)
    source = _component_source(hazard, frag)
    out = [_fitted_row(r, frag, hazard) for r in frag.rows.itertuples()]
    out += [_unfitted_row(r, frag, hazard) for r in frag.skipped.itertuples()]
    table = pd.DataFrame(out, columns=list(COLUMNS))
    table["preset"] = preset
    table["component_source"] = source
    table = sort_rows(table).rename(columns=header)
    table.attrs["skipped"] = frag.skipped_note()
    table.attrs["hazard"] = hazard.source
    table.attrs["fragility"] = frag.kind
    table.attrs["note"] = frag.note
    return table


def _component_source(hazard: HazardCurve, frag: Fragilities) -> str:
    """Where the component of a risk row comes from: ``declared``, ``file``,
    ``openquake-default`` (:data:`rocking.risk.hazard.OPENQUAKE_COMPONENT`) or ``assumed``
    (the hazard states none); ``+refit`` where the fragility was refitted in it."""
    said = {"declared": "declared", "file": "file", "default": "openquake-default"}.get(
        hazard.component_source, "assumed")
    return said + ("+refit" if frag.refitted else "")


def _base(r, frag: Fragilities) -> dict:
    pga = same_measure(frag.measure, "pga")
    return {"fragility": frag.kind, "measure": frag.measure, "component": frag.component,
            "mode": r.mode,
            "tan_alpha": r.tan_alpha, "R": r.R, "limit_state": r.limit_state,
            "median_im": r.median_g, "median_pga_g": r.median_g if pga else math.nan,
            "beta": r.beta, "n": r.n, "status": r.status}


def _hazard_columns(hazard: HazardCurve) -> dict:
    return {"hazard_site": hazard.site, "hazard_kind": hazard.kind}


def _fitted_row(r, frag: Fragilities, hazard: HazardCurve) -> dict:
    parts = annual_frequency_parts(r.median_g, r.beta, hazard)
    maf = parts["total"]
    lo = hi = math.nan
    resamples = frag.resamples(int(r.row))
    if resamples is not None:
        lo, hi, _ = annual_frequency_interval(*resamples, hazard, ci=CI)
    return {**_base(r, frag), **_hazard_columns(hazard), "maf": maf, "lambda_p05": lo,
            "lambda_p95": hi,
            "lambda_lo": math.nan, "lambda_hi": math.nan,
            "return_period": 1.0 / maf if maf > 0 else math.inf,
            "p_50yr": probability_in(maf, YEARS),
            "share_extrapolated": parts["extrapolated"] / maf if maf > 0 else 0.0,
            "share_below_first": parts["below_first"] / maf if maf > 0 else 0.0}


def _unfitted_row(r, frag: Fragilities, hazard: HazardCurve) -> dict:
    """A row without a fit: λ NaN; the bracketing stripes' bounds where the table has them."""
    lo_im, hi_im = float(r.bracket_lo), float(r.bracket_hi)
    lam_lo = float(hazard.rate(hi_im)) if math.isfinite(hi_im) and hi_im > 0 else math.nan
    lam_hi = float(hazard.rate(lo_im)) if math.isfinite(lo_im) and lo_im > 0 else math.nan
    if math.isfinite(lam_hi) and not math.isfinite(hi_im):
        lam_lo = 0.0  # nothing exceeded up to the highest stripe: only an upper bound
    return {**_base(r, frag), **_hazard_columns(hazard), "maf": math.nan,
            "lambda_p05": math.nan,
            "lambda_p95": math.nan, "lambda_lo": lam_lo, "lambda_hi": lam_hi,
            "return_period": math.nan, "p_50yr": math.nan, "share_extrapolated": math.nan,
            "share_below_first": math.nan}


def risk_tables(fragilities, hazard: HazardCurve, *, preset: str = "",
                assumed: tuple[str, str] | None = None) -> pd.DataFrame:
    """:func:`risk_table` of each fragility, stacked (the ``fragility`` column tells them apart).

    Parameters
    ----------
    fragilities : sequence of Fragilities, paths, DataFrames or Datasets
        E.g. a study's ``fragility.csv`` and ``stripe_fragility.csv``; two of one kind are
        refused (their rows could not be told apart).
    hazard : HazardCurve
        The site's hazard curve.
    preset, assumed
        As for :func:`risk_table`.

    Returns
    -------
    pandas.DataFrame
        The rows of every table, in the order given; ``attrs["skipped"]`` joins their notes.
    """
    tables = [risk_table(f, hazard, preset=preset, assumed=assumed) for f in fragilities]
    kinds = [t.attrs["fragility"] for t in tables]
    if len(set(kinds)) != len(kinds):
        raise ValueError(f"fragilities: one table per kind, got kinds {kinds}")
    if not tables:
        raise ValueError("fragilities: give at least one fragility table")
    out = pd.concat(tables, ignore_index=True)
    out.attrs["skipped"] = " ".join(f"[{t.attrs['fragility']}] {t.attrs['skipped']}"
                                    for t in tables if t.attrs["skipped"])
    out.attrs["hazard"] = hazard.source
    out.attrs["note"] = "; ".join(dict.fromkeys(t.attrs["note"] for t in tables
                                                if t.attrs["note"]))
    return out


def lambda_line(row) -> str:
    """One line for people: λ with its 90 % interval, or the bounds of a row without a fit."""
    get = row.get if hasattr(row, "get") else (lambda k, d=None: getattr(row, k, d))
    maf = float(get("maf", math.nan))
    if math.isfinite(maf):
        lo, hi = float(get("lambda_p05", math.nan)), float(get("lambda_p95", math.nan))
        band = (f" (90 % interval {lo:.3g}–{hi:.3g})" if np.isfinite([lo, hi]).all()
                else " (no interval: no bootstrap samples)")
        return f"λ = {maf:.3g} per year{band}"
    lo, hi = float(get("lambda_lo", math.nan)), float(get("lambda_hi", math.nan))
    if math.isfinite(lo) or math.isfinite(hi):
        lo_txt = f"{lo:.3g}" if math.isfinite(lo) else "?"
        hi_txt = f"{hi:.3g}" if math.isfinite(hi) else "?"
        return (f"no fit ({get('status', '')}): λ between {lo_txt} and {hi_txt} per year "
                "(the rates at the bracketing stripes)")
    return f"no fit ({get('status', '')}): no λ"


__all__ = ["BELOW_FIRST_WARN", "CI", "COLUMNS", "FAST_BIAS", "MIN_RECORDS", "PAPER_LIMIT_STATES",
           "PRESET_ERRORS", "YEARS", "below_first_warning", "lambda_line",
           "main_tan_alpha", "preset_note", "preset_warning", "read_risk_table", "risk_table",
           "risk_tables", "shown_limit_states"]


PAPER_LIMIT_STATES = (OVERTURNING, EXCESSIVE_TILT)
"""The limit states shown when a study has them (the paper's overturning and θ > α/3)."""



def read_risk_table(risk: str | Path | pd.DataFrame) -> pd.DataFrame:
    """``risk.csv`` (or its frame) with unit-free column names, canonical limit-state names,
    and a ``fragility`` column in today's names (a table written before the stripe rows: the
    critical-intensity fragility; an earlier version's name read as today's,
    :func:`rocking.fragility.table.renamed`)."""
    frame = risk if isinstance(risk, pd.DataFrame) else pd.read_csv(risk)
    frame = renamed(frame.rename(columns={c: strip_units(str(c)) for c in frame.columns}))
    frame["limit_state"] = [parse_limit_state(s).name for s in frame["limit_state"]]
    if "fragility" not in frame.columns:  # a risk.csv written before the stripe rows
        frame["fragility"] = CRITICAL_INTENSITY
    return frame



PRESET_ERRORS = {
    "fast": (7.7, 35.0),
    "default": (1.6, 15.0),
    "precise": (0.93, 10.0),
}
"""Preset → error of its critical intensities against a converged reference [%]: median and
90th percentile (docs/performance.md, "Accuracy of the presets against the converged
reference", two goals). Always on the high side: the search steps over narrow windows of
exceedance, so capacities come out too high and λ too low."""



FAST_BIAS = ("on the four shipped records (tan α 0.11, R 3–3.02 m, docs/risk.md) the fast "
             "preset's median capacity ran 9–11 % above the default preset's (one record's "
             "30–46 %) and λ of overturning 27–38 % lower; on issue 29's four records 20–37 % "
             "and about 40 %")
"""The measured cost of the fast preset in risk (docs/risk.md, and the issue's case)."""



MIN_RECORDS = 10
"""Fewer motions behind a fragility than this get a warning on the width of its interval."""



def preset_note(preset: str) -> str:
    """The measured error of the preset that was run, with its sign ('' for an unknown one)."""
    if preset not in PRESET_ERRORS:
        return ""
    median, p90 = PRESET_ERRORS[preset]
    return (f"Search preset '{preset}': its critical intensities are {median:g} % off on "
            f"median and {p90:g} % at the 90th percentile against a converged reference, "
            "always too high (first exceedances step over narrow windows of exceedance), so "
            "capacities are overestimated and λ is too low (docs/performance.md).")



def preset_warning(preset: str) -> str:
    """One line for a risk computed from ``fast`` answers ('' otherwise)."""
    if preset != "fast":
        return ""
    median, p90 = PRESET_ERRORS["fast"]
    return (f"WARNING: λ computed from fast-preset answers, unconservative: capacities "
            f"{median:g} % (median) to {p90:g} % (90th percentile) too high, {FAST_BIAS}; "
            "rerun with accuracy: default before using λ.")



BELOW_FIRST_WARN = 0.01
"""Share of λ above which its part from below the hazard's first level is warned about: the
hazard table says nothing there (its first log-log slope is extrapolated), so more than 1 %
of λ resting on it is a number the hazard does not support."""



def below_first_warning(risk) -> str:
    """One line when some λ rest for more than :data:`BELOW_FIRST_WARN` on the hazard below
    its first level ('' otherwise, and for a table written before ``share_below_first``)."""
    frame = read_risk_table(risk)
    if "share_below_first" not in frame.columns:
        return ""
    share = frame["share_below_first"].astype(float)
    big = frame[share > BELOW_FIRST_WARN]
    if big.empty:
        return ""
    worst = big.loc[big["share_below_first"].astype(float).idxmax()]
    return (f"WARNING: {len(big)} of {int(np.isfinite(share).sum())} λ rest for more than "
            f"{100 * BELOW_FIRST_WARN:g} % on the hazard below its first level, where the hazard "
            f"table says nothing and its first log-log slope is extrapolated (up to "
            f"{100 * float(worst['share_below_first']):.0f} % at {worst['mode']}, R = "
            f"{float(worst['R']):g} m, {worst['limit_state']}, median "
            f"{float(worst['median_im']):.3g} g): use a hazard curve whose levels start well "
            "below the fragility medians (share_below_first in risk.csv).")



def main_tan_alpha(frame: pd.DataFrame) -> float | None:
    """The slenderness with the most risk rows (the paper's 0.2, where every mode ran);
    among equals the middle one; None for an empty table."""
    counts = frame.groupby("tan_alpha").size()
    best = [float(t) for t, n in counts.items() if n == counts.max()]
    return best[len(best) // 2] if best else None



def shown_limit_states(frame: pd.DataFrame) -> list[str]:
    """The paper's overturning and θ > α/3 where the table has them, else the study's own
    limit states, most severe first (at most two)."""
    present = list(dict.fromkeys(frame["limit_state"]))
    paper = [ls for ls in PAPER_LIMIT_STATES if ls in present]
    own = sorted(present, key=severity, reverse=True)
    return paper if len(paper) == len(PAPER_LIMIT_STATES) else (paper + [
        ls for ls in own if ls not in paper])[:2]
