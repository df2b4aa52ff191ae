"""The risk table: every fitted fragility of a study under one hazard curve.

One row per (mode, tan α, R, limit state) with a fit: the median capacity and β, the mean
annual frequency λ_LS [1/yr] (:func:`rocking.risk.annual_frequency.mean_annual_frequency`),
the return period 1/λ_LS [yr], the probability of at least one exceedance in 50 years
(Poisson) and the share of λ_LS that rests on extrapolating the hazard curve's last slope
(:func:`rocking.risk.annual_frequency.annual_frequency_parts`, ``extrapolated``).

The first column, ``fragility``, says which fragility the row integrates
(``first_exceedance`` or ``stripes``, :data:`rocking.risk.fragilities.KINDS`); the last,
``status``, the fit's status (a stripe fit whose median lies outside the stripes is
``extrapolated``). :func:`risk_tables` stacks the tables of several fragilities of a study,
so that both answers stand side by side in one ``risk.csv``.
"""

from __future__ import annotations

import pandas as pd

from ..units import header
from .annual_frequency import annual_frequency_parts, probability_in
from .fragilities import Fragilities, read_fragilities
from .hazard import HazardCurve

YEARS = 50.0
"""Exposure time of the probability column [yr] (``p_50yr``)."""

COLUMNS = ("fragility", "mode", "tan_alpha", "R", "limit_state", "median_pga_g", "beta",
           "maf", "return_period", "p_50yr", "share_extrapolated", "status")
"""Columns of :func:`risk_table` (with units in their titles, :func:`rocking.units.header`)."""


def risk_table(fragility, hazard: HazardCurve) -> pd.DataFrame:
    """Mean annual frequency, return period and 50-year probability of each limit state.

    Parameters
    ----------
    fragility : Fragilities, path, DataFrame or Dataset
        The study's fitted fragilities, or anything
        :func:`rocking.risk.fragilities.read_fragilities` reads.
    hazard : HazardCurve
        The site's hazard curve (PGA [g]).

    Returns
    -------
    pandas.DataFrame
        :data:`COLUMNS`, titles with units (``maf [1/yr]``, ``return_period [yr]`` ...);
        ``attrs["skipped"]`` names the fragilities without a fit.
    """
    frag = fragility if isinstance(fragility, Fragilities) else read_fragilities(fragility)
    out = []
    for r in frag.rows.itertuples():
        parts = annual_frequency_parts(r.median_g, r.beta, hazard)
        maf = parts["total"]
        out.append({"fragility": frag.kind, "mode": r.mode, "tan_alpha": r.tan_alpha, "R": r.R,
                    "limit_state": r.limit_state, "median_pga_g": r.median_g, "beta": r.beta,
                    "maf": maf, "return_period": 1.0 / maf if maf > 0 else float("inf"),
                    "p_50yr": probability_in(maf, YEARS),
                    "share_extrapolated": parts["extrapolated"] / maf if maf > 0 else 0.0,
                    "status": r.status})
    table = pd.DataFrame(out, columns=list(COLUMNS)).rename(columns=header)
    table.attrs["skipped"] = frag.skipped_note()
    table.attrs["hazard"] = hazard.source
    table.attrs["fragility"] = frag.kind
    return table


def risk_tables(fragilities, hazard: HazardCurve) -> pd.DataFrame:
    """:func:`risk_table` of each fragility, stacked (the ``fragility`` column tells them apart).

    Parameters
    ----------
    fragilities : sequence of Fragilities, paths, DataFrames or Datasets
        E.g. a study's ``fragility.csv`` and ``stripe_fragility.csv``; two of one kind are
        refused (their rows could not be told apart).
    hazard : HazardCurve
        The site's hazard curve (PGA [g]).

    Returns
    -------
    pandas.DataFrame
        The rows of every table, in the order given; ``attrs["skipped"]`` joins their notes.
    """
    tables = [risk_table(f, hazard) for f in fragilities]
    kinds = [t.attrs["fragility"] for t in tables]
    if len(set(kinds)) != len(kinds):
        raise ValueError(f"fragilities: one table per kind, got kinds {kinds}")
    if not tables:
        raise ValueError("fragilities: give at least one fragility table")
    out = pd.concat(tables, ignore_index=True)
    out.attrs["skipped"] = " ".join(f"[{t.attrs['fragility']}] {t.attrs['skipped']}"
                                    for t in tables if t.attrs["skipped"])
    out.attrs["hazard"] = hazard.source
    return out


__all__ = ["COLUMNS", "YEARS", "risk_table", "risk_tables"]
