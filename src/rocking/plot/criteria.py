"""Criteria of the verdicts that set an ensemble statistic against a number or a word of the
paper, each tolerance derived from the scatter of the ensemble and the stated error of the
answers (docs/models.md, "Verdicts and their criteria"). The answers are each motion's I10
(:class:`rocking.spectra.quantity.Quantity`); the paper's are first exceedances on a grid it
does not state, a quantity that falls as the grid is refined.

- A number of the paper quoted as "about v" (:func:`about_value`): the paper's own number is
  a statistic of its own ensemble of as many motions, so it scatters as much as ours (standard
  error s each, √2·s for the difference), and "about 4" is rounded to the nearest unit
  (± 0.5: standard deviation 0.5/√3). Reproduced when |ours − v| ≤ 2·√(2 s² + (0.5/√3)²),
  two standard deviations of the difference. Where the same cells' mean first exceedance on
  several grids is known (:func:`about_family`), the paper's number is held against the
  whole family, from the mean I10 to the coarsest grid's mean: reproduced when it lies within
  that band widened by the same two standard deviations.
- A ratio of the paper quoted as "about twice" (:func:`ratio_about`): in logarithms, the same
  with the ratio's standard error and "about twice" read to the nearest half (1.75–2.25).
- A ratio said to exceed 1 ("2D above 3D", :func:`ratio_above_one`): ln ratio more than two
  of its standard errors above 0.
- Ratios judged across the sizes R, not at one: ln r pooled over the sizes (their mean), its
  standard error the mean of the sizes' standard errors (the sizes share their motions, so
  their errors are correlated: averaging them does not shrink the error).
- A mean that leaves out motions not reached (censored) is biased low and never supports
  "reproduced" (:func:`censored_note`); ratios are read from the censoring-aware medians of
  the lognormal fit (``fragility.csv``) where the figure has them.
- The paper's per-motion claim (damped and undamped spectra "essentially identical") is judged
  per motion (:func:`share_within`): the share of (motion, R) pairs whose relative difference
  is within :data:`PER_MOTION_TOL`, against :data:`PER_MOTION_SHARE`, both from the stated
  error of the answers (``rocking.spectra.accuracy.STATED``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from rocking.spectra.accuracy import STATED

Z = 2.0
"""Standard deviations a difference may span and still be "reproduced" (about 95 %)."""
ROUNDING_UNIT = 0.5
"""Half-width of the rounding of a number the paper gives as "about 4" (nearest unit)."""
RATIO_ROUNDING = math.log(2.25 / 2.0)
"""Half-width in ln of "about twice" read to the nearest half (1.75–2.25) [-]."""
Z_P90 = 1.6449
"""The 95th percentile of the standard normal: a 5–95 % interval spans 2·Z_P90 SE."""
PER_MOTION_TOL = 2.0 * STATED["default"][0]
"""Relative difference of two answers of one motion that their stated error cannot resolve
[-]: a ``default`` answer lies within e of the converged I10 in a share q of the cells
(``rocking.spectra.accuracy.STATED``), so two answers of identical models differ by up to
2e there."""
PER_MOTION_SHARE = 2.0 * STATED["default"][1] - 1.0
"""Share of (motion, R) pairs within :data:`PER_MOTION_TOL` for "essentially identical per
motion" [-]: each of the two answers is beyond its stated error in a share 1 − q of the
cells, so identical models' answers differ by more than 2e in up to 2(1 − q) of the
pairs."""
MAX_CENSORED_SHARE = 0.5
"""Largest share of motions censored at the search bound for which a fitted median is read
[-]: with more, the median lies above every observed answer and is the fit's
extrapolation."""


def about_value(value: float, se: float, paper: float,
                rounding: float = ROUNDING_UNIT) -> tuple[bool, float]:
    """(reproduced, tolerance): ``|value − paper| ≤ Z·√(2 se² + (rounding/√3)²)``."""
    tol = Z * math.sqrt(2.0 * se ** 2 + (rounding / math.sqrt(3.0)) ** 2)
    return abs(value - paper) <= tol, tol


def about_family(values: Sequence[float], se: float, paper: float,
                 rounding: float = ROUNDING_UNIT) -> tuple[bool, float, float, float]:
    """(reproduced, low, high, tolerance): whether ``paper`` lies within [low − tol, high +
    tol], low and high the smallest and largest of ``values`` (the mean I10 and the same
    cells' mean first exceedance on each grid: every answer the cells give), tol =
    Z·√(2 se² + (rounding/√3)²) as :func:`about_value`'s."""
    v = np.asarray(values, float)
    v = v[np.isfinite(v)]
    tol = Z * math.sqrt(2.0 * se ** 2 + (rounding / math.sqrt(3.0)) ** 2)
    if not v.size:
        return False, math.nan, math.nan, tol
    low, high = float(v.min()), float(v.max())
    return low - tol <= paper <= high + tol, low, high, tol


def se_log_from_interval(p05: float, p95: float) -> float:
    """Standard error of ln(median) from its bootstrap 5–95 % interval (NaN without one)."""
    if not (np.isfinite(p05) and np.isfinite(p95)) or p05 <= 0.0 or p95 <= 0.0:
        return float("nan")
    return math.log(p95 / p05) / (2.0 * Z_P90)


def pooled_ratio(ratio: Sequence[float], se_log: Sequence[float]) -> tuple[float, float]:
    """(ratio, se of its ln) pooled over sizes: exp of the mean ln ratio, mean of the SEs."""
    r = np.asarray(ratio, float)
    s = np.asarray(se_log, float)
    ok = np.isfinite(r) & (r > 0) & np.isfinite(s)
    if not ok.any():
        return float("nan"), float("nan")
    return float(np.exp(np.mean(np.log(r[ok])))), float(np.mean(s[ok]))


def ratio_about(ratio: float, se_log: float, paper: float = 2.0) -> tuple[bool, float]:
    """(reproduced, tolerance in ln): |ln(ratio/paper)| ≤ Z·√(2 se² + (rounding/√3)²)."""
    tol = Z * math.sqrt(2.0 * se_log ** 2 + (RATIO_ROUNDING / math.sqrt(3.0)) ** 2)
    return abs(math.log(ratio / paper)) <= tol, tol


def ratio_above_one(ratio: float, se_log: float) -> bool:
    """Whether ln ratio lies more than Z standard errors above 0."""
    return math.log(ratio) > Z * se_log


def share_within(values, tol: float = PER_MOTION_TOL) -> tuple[int, int]:
    """(within, total): finite values with |v| ≤ tol, and all finite values."""
    v = np.asarray(values, float).ravel()
    v = v[np.isfinite(v)]
    return int(np.sum(np.abs(v) <= tol * (1 + 1e-12))), int(v.size)


def censored_note(n_left_out: int, n_motions: int | None) -> str:
    """Why a mean over fewer motions than the ensemble cannot be "reproduced"."""
    of = f" of {n_motions}" if n_motions else ""
    return (f"the mean leaves out {n_left_out}{of} motions not reached at the search bound: "
            "a censored mean is biased low and supports no verdict of agreement")
