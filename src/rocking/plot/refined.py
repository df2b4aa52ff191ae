"""How far refinement moves a statistic of a study, read from its ``refinement_sample.csv``
(:mod:`rocking.study.refinement`): the report's findings and the legends of Figs 9, 10 and
12 quote it.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np
import pandas as pd

from rocking.spectra.modes import MODE_3D
from rocking.study.refinement import REFINED_STEP

SAMPLE_FILE = "refinement_sample.csv"
"""The sample's file name in a study's folder (beside ``mean_spectra.nc``)."""


def read_refinement(path) -> pd.DataFrame | None:
    """``refinement_sample.csv`` of :mod:`rocking.study.refinement` (None when absent)."""
    if path is None or not Path(path).exists():
        return None
    df = pd.read_csv(path)
    return df if len(df) else None


def read_refinements(paths, study: str = "") -> dict[str, pd.DataFrame]:
    """The samples of the studies a report quotes, by study: the first of ``paths`` is
    ``study``'s own, each other one is named by its folder (``<root>/<study>/``); absent or
    empty tables are left out. ``paths`` may be one path (the study's own) or None."""
    if paths is None:
        return {}
    paths = [paths] if isinstance(paths, str | Path) else list(paths)
    out = {}
    for i, p in enumerate(paths):
        df = read_refinement(p)
        if df is not None:
            out.setdefault(study if i == 0 else Path(p).parent.name, df)
    return out


def lambda_shift(df: pd.DataFrame | None, mode: str, limit_state: str, R: float,
                 tan_alpha: float, what: str = "maf") -> tuple[float, int, int] | None:
    """How far refinement moves λ (``what`` "maf") or the fragility median ("median") of
    one point, from ``refinement_risk.csv``
    (:func:`rocking.study.refinement.write_refinement_risk`): (refined/unrefined − 1, cells
    refined, cells behind the fit), or None where no cell of the point was refined."""
    if df is None or df.empty:
        return None
    at = df[(df["mode"] == mode) & (df["limit_state"] == limit_state)
            & np.isclose(df["R"].astype(float), R)
            & np.isclose(df["tan_alpha"].astype(float), tan_alpha)]
    delta = at[f"{what}_refined"].astype(float) / at[what].astype(float) - 1.0
    at = at[np.isfinite(delta) & (at["n_refined"] > 0)]
    if at.empty:
        return None
    row = at.iloc[0]
    return float(delta[at.index[0]]), int(row["n_refined"]), int(row["n"])


def lambda_text(found: tuple[float, int, int] | None) -> str:
    """``"refinement moves it by +20.8 % [all 11 cells refined, fragility refitted]"``, or
    ``"[1 of its 11 cells refined, ...]"`` (empty without a refined cell)."""
    if found is None:
        return ""
    delta, k, n = found
    cells = f"all {n} cells" if k == n else f"{k} of its {n} cells"
    return f"refinement moves it by {_percent(delta)} [{cells} refined, fragility refitted]"


def _refined(df: pd.DataFrame) -> pd.DataFrame:
    return df[~df["truncated"].astype(bool) & np.isfinite(df["shift"].astype(float))]


def cell_shift(df: pd.DataFrame | None, mode: str, limit_state: str, R: float | None = None,
               n_cells: int | None = None, tan_alpha: float = 0.2
               ) -> tuple[float, int, bool] | None:
    """How far refinement moves a statistic of (mode, limit state) [relative, ≤ 0]: (shift,
    cells it rests on, exact).

    Exact where every one of the ``n_cells`` answers behind the mean at size ``R`` was
    refined (the mean of the refined answers against the mean of the answers); else the mean
    relative shift of the sample's cells of this (mode, limit state) — every size and
    slenderness — applied to the statistic, as a lognormal median or a mean moves when every
    answer moves by the same share. None without refined cells of it.
    """
    if df is None:
        return None
    sub = _refined(df[(df["mode"] == mode) & (df["limit_state"] == limit_state)])
    if sub.empty:
        return None
    if R is not None and n_cells:
        at = sub[np.isclose(sub["R"], R) & np.isclose(sub["tan_alpha"], tan_alpha)]
        if len(at) >= n_cells:
            return float(at["refined"].mean() / at["answer"].mean() - 1.0), len(at), True
    return float(sub["shift"].mean()), len(sub), False


def shift_text(found: tuple[float, int, bool] | None) -> str:
    """``"refinement moves it by −2.1 % [sample of 3 cells]"`` (empty without a sample)."""
    if found is None:
        return ""
    delta, n, exact = found
    cells = f"all {n} cells refined" if exact else f"sample of {n} cell{'s' * (n != 1)}"
    return f"refinement moves it by {_percent(delta)} [{cells}]"


def _percent(delta: float) -> str:
    """``"−2.1 %"``, ``"+20.8 %"``; ``"0.0 %"`` where it rounds to nothing (no sign)."""
    text = f"{100 * delta:+.1f} %"
    return "0.0 %" if text in ("+0.0 %", "-0.0 %") else text.replace("-", "−")


def ratio_shift(df: pd.DataFrame | None, mode: str, limit_state: str,
                base: str = MODE_3D) -> tuple[float, int, bool] | None:
    """How far refinement moves a ratio ``mode``/``base`` of one limit state: (1 + δ)/(1 + δ₀)
    − 1 of the two modes' sample shifts (:func:`cell_shift`)."""
    a, b = cell_shift(df, mode, limit_state), cell_shift(df, base, limit_state)
    if a is None or b is None:
        return None
    return (1.0 + a[0]) / (1.0 + b[0]) - 1.0, a[1] + b[1], False


def beside(path) -> pd.DataFrame | None:
    """The refinement sample in the folder of ``path`` (a study's ``mean_spectra.nc``)."""
    return read_refinement(Path(path).parent / SAMPLE_FILE) if path is not None else None


def legend_phrase(df: pd.DataFrame | None, mode: str, limit_state: str | None = None,
                  R: float | None = None, n_cells: int | None = None) -> str:
    """One short legend phrase: ``"refinement (0.05 % scan): −2.1 % [sample of 3 cells]"``
    for one (mode, limit state), or over every limit state of ``mode`` (empty without a
    sample)."""
    if df is None:
        return ""
    if limit_state is None:
        sub = _refined(df[df["mode"] == mode])
        if sub.empty:
            return ""
        found = (float(sub["shift"].mean()), len(sub), False)
    else:
        found = cell_shift(df, mode, limit_state, R, n_cells)
    text = shift_text(found)
    return text.replace("refinement moves it by", "refinement (0.05 % scan) moves answers by"
                        ) if text else ""


def refinement_note(table: pd.DataFrame | None,
                    others: Mapping[str, pd.DataFrame] | None = None, study: str = "") -> str:
    """What the findings' "refinement moves it by" rests on: the sample, how it was drawn
    (k per mode and limit state, its seed, the headline cells) and the scan; and the samples
    of the other studies the findings quote."""
    if table is None:
        text = ("No refinement sample in this run (refinement_sample.csv): the headline "
                "numbers carry no measured movement under refinement.")
    else:
        text = ("Refinement: " + sample_words(table, "this study's")
                + " were searched again with a fixed "
                f"{100 * REFINED_STEP:g} % scan from uplift to the answer at the study's "
                "own tolerances; " + moved_words(table) + ". A number marked \"all n cells "
                "refined\" is recomputed from the refined answers (a median and λ by fitting "
                "the fragility again and integrating it with the hazard curve; \"k of its n "
                "cells\": only k refined); one marked \"sample of n cells\" takes the "
                "sample's mean shift of its mode and limit state. Refinement only lowers "
                "answers: a finer scan finds windows of exceedance the coarse one stepped "
                "over.")
    for name, other in (others or {}).items():
        if name != study:
            text += (f" The numbers of the study {name} rest on its own sample: "
                     + sample_words(other, "its") + "; " + moved_words(other) + ".")
    return text


def sample_words(table: pd.DataFrame, whose: str) -> str:
    """``"24 of this study's cells (11 of the headline mean, 13 drawn: k = 1 per mode and
    limit state, seed 0)"``; k and seed where the table records them."""
    head = int((table["why"] == "headline").sum())
    how = ""
    if {"k", "seed"} <= set(table.columns) and len(table):
        how = f": k = {int(table['k'].iloc[0])} per mode and limit state, seed " \
              f"{int(table['seed'].iloc[0])}"
    else:
        how = " per mode and limit state with a fixed seed"
    return (f"{len(table)} of {whose} cells ({head} of the headline mean, "
            f"{len(table) - head} drawn{how})")


def moved_words(table: pd.DataFrame) -> str:
    """``"23 of 24 moved down (median −3.8 %, largest −29.1 %)"`` and the truncated ones."""
    refined = table[~table["truncated"].astype(bool)]
    shift = refined["shift"].astype(float)
    moved = int((shift < -1e-12).sum())
    cut = int(table["truncated"].astype(bool).sum())
    return (f"{moved} of {len(refined)} moved down (median {100 * shift.median():+.1f} %, "
            f"largest {100 * shift.min():+.1f} %)".replace("-", "−")
            + (f"; {cut} needed more analyses than allowed and are left out" if cut else ""))


NOT_MEASURED = "refinement_not_measured"
"""Key of a figure's notes that says why its legend quotes no move under refinement."""


def not_measured(df: pd.DataFrame | None, mode: str, limit_state: str | None = None) -> str:
    """Why no move under refinement can be quoted for (mode, limit state), for a figure's
    sidecar (empty when :func:`legend_phrase` has one): no sample in the study's folder, or
    a sample without a refined cell of it."""
    if legend_phrase(df, mode, limit_state):
        return ""
    if df is None:
        return (f"not measured: no {SAMPLE_FILE} (or an empty one) in the study's folder, so "
                "no figure number carries its move under refinement")
    what = f"{mode} {limit_state}" if limit_state else mode
    return f"not measured: {SAMPLE_FILE} holds no refined cell of {what}"
