"""How far refinement moves a statistic of a study, read from its ``refinement_sample.csv``
(:mod:`rocking.study.refinement`): the report's findings and the legends of Figs 9, 10 and
12 quote it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ..spectra.modes import MODE_3D

SAMPLE_FILE = "refinement_sample.csv"
"""The sample's file name in a study's folder (beside ``mean_spectra.nc``)."""


def read_refinement(path) -> pd.DataFrame | None:
    """``refinement_sample.csv`` of :mod:`rocking.study.refinement` (None when absent)."""
    if path is None or not Path(path).exists():
        return None
    df = pd.read_csv(path)
    return df if len(df) else None


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
    return f"refinement moves it by {100 * delta:+.1f} % [{cells}]".replace("-", "−")


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
