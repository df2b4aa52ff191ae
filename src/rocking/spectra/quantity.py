"""What "the critical intensity" of a cell means: the quantity a search estimates.

Rocking response to one motion is practically unpredictable at the scale of its windows of
exceedance: below the first robust rise the body exceeds a goal in many windows 0.01–0.04 %
of the intensity wide, whose number nearly doubles with each halving of a scan's step and
which move with perturbations far below any real uncertainty (R changed by 1 mm on 10 m).
The smallest exceeding intensity therefore does not settle as the scan is refined. What
does converge is the *local exceedance probability*

    P(s) = share of the intensities x with |ln(x/s)| <= w whose analysis exceeds the goal,

a window average of the exceedance over ±w in ln s (w = 2 % by default), and its low
quantile

    I_p = inf{s : P(s) >= p}            (p = 0.1 by default: ``I10``),

the lowest intensity around which at least a share p of the intensities exceed. I_p of a
response that steps cleanly from "never" to "always" at s* is s*·exp(−w(1 − 2p)) (the
window centred there holds a share p above s*), 0.984 s* for the defaults; an isolated
window of exceedance narrower than 2pw does not move it.

:class:`Quantity` names the choice (``quantity:`` in a configuration, ``--quantity`` on the
command line): ``exceedance_quantile`` (I_p, the default) or ``first_exceedance`` (the
classic smallest exceeding intensity on the search's scan grid, always labelled with that
grid's step). :func:`local_exceedance` and :func:`exceedance_quantile` estimate P and I_p
from any analysed sample of intensities (a search's, a fine lattice's).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

from rocking._validate import positive_finite_array

if TYPE_CHECKING:
    import numpy as np

EXCEEDANCE_QUANTILE = "exceedance_quantile"
"""I_p = inf{s : P(s) >= p}, the converging answer (the default)."""

FIRST_EXCEEDANCE = "first_exceedance"
"""The smallest exceeding intensity on the search's scan grid (labelled with its step)."""

QUANTITIES = (EXCEEDANCE_QUANTILE, FIRST_EXCEEDANCE)
"""The names a :class:`Quantity` may take."""

COLUMNS = ("quantity", "quantity_p", "quantity_w")
"""Columns naming the quantity in every table of answers (:meth:`Quantity.columns`): named
like its configuration keys (``quantity``, ``quantity.p``, ``quantity.w``); a bare ``w`` is
the contact-spring displacement of a time history."""

PLATEAU_SHARE = 0.5
"""A local maximum of P̂ of at least this share of p, more than one window below I_p (or
anywhere when P̂ never reaches p), marks the answer ``plateau`` [-]: there P rises near p
without crossing it, and a small change of the response could move I_p down to it."""


@dataclass(frozen=True)
class Quantity:
    """What the critical intensity of a (motion, body, limit state, mode) cell means.

    Parameters
    ----------
    name : {"exceedance_quantile", "first_exceedance"}
        I_p (default) or the first exceedance on the scan grid.
    p : float
        Exceedance share of I_p = inf{s : P(s) >= p} [-], in (0, 1).
    w : float
        Half-width of the window of P(s) in ln s [-], in (0, 0.5).

    Checked once here; a bad value is one line naming its configuration key
    (``quantity``, ``quantity.p``, ``quantity.w``) and the value.
    """

    name: str = EXCEEDANCE_QUANTILE
    p: float = 0.1
    w: float = 0.02

    def __post_init__(self) -> None:
        if self.name not in QUANTITIES:
            raise ValueError(f"quantity must be one of {list(QUANTITIES)}, got {self.name!r}")
        object.__setattr__(self, "p", _open_interval("quantity.p", self.p, 0.0, 1.0))
        object.__setattr__(self, "w", _open_interval("quantity.w", self.w, 0.0, 0.5))

    @property
    def is_quantile(self) -> bool:
        """Whether the answer is I_p (else the first exceedance)."""
        return self.name == EXCEEDANCE_QUANTILE

    @property
    def label(self) -> str:
        """Short name of the answer: ``"I10"`` for p = 0.1, ``"first exceedance"``."""
        if not self.is_quantile:
            return "first exceedance"
        return f"I{100.0 * self.p:.4g}"

    def describe(self, scan_step: float | None = None) -> str:
        """One phrase for tables and reports: ``"I10 (P >= 0.1 within ±2 % in ln s)"`` or
        ``"first exceedance on the 3 % scan grid"`` (the grid step, relative, when known)."""
        if self.is_quantile:
            return f"{self.label} (P >= {self.p:g} within ±{100.0 * self.w:g} % in ln s)"
        if scan_step is None:
            return "first exceedance on the scan grid"
        return f"first exceedance on the {100.0 * scan_step:g} % scan grid"

    def to_dict(self) -> dict:
        """JSON-serialisable form (store attributes, tables, CLI outputs): name, p and w,
        always all three (a store's digest tells every choice apart)."""
        return {"name": self.name, "p": self.p, "w": self.w}

    def columns(self) -> dict:
        """The quantity as table columns (:data:`COLUMNS`)."""
        return dict(zip(COLUMNS, (self.name, self.p, self.w), strict=True))

    @classmethod
    def from_value(cls, value: str | Mapping | Quantity | None) -> Quantity:
        """A :class:`Quantity` from None (the default), a name, a mapping with ``name``,
        ``p`` and ``w`` (any may be left out), or a :class:`Quantity` itself."""
        if value is None:
            return cls()
        if isinstance(value, Quantity):
            return value
        if isinstance(value, str):
            return cls(name=value.strip())
        if isinstance(value, Mapping):
            unknown = sorted(set(value) - {"name", "p", "w"})
            if unknown:
                raise ValueError(f"quantity has unknown key(s) {unknown}; allowed "
                                 "['name', 'p', 'w']")
            return cls(**dict(value))
        raise ValueError(f"quantity must be one of {list(QUANTITIES)} or a mapping with "
                         f"name, p and w, got {value!r}")


def _open_interval(key: str, value, lo: float, hi: float) -> float:
    """``value`` as a float in the open interval (lo, hi), else one line naming ``key``."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{key} must be a number in ({lo:g}, {hi:g}), got {value!r}") from None
    if isinstance(value, bool) or not (lo < v < hi):
        raise ValueError(f"{key} must be a number in ({lo:g}, {hi:g}), got {value!r}")
    return v


# --------------------------------------------------------------------------- estimators
def _sample(intensities, exceeded, weights=None) -> tuple[np.ndarray, np.ndarray,
                                                         np.ndarray]:
    """(ln x, exceeded, weight) sorted by intensity, the positive finite intensities only."""
    import numpy as np  # on use: the command line's help loads no numpy

    x = np.asarray(intensities, dtype=float).ravel()
    e = np.asarray(exceeded, dtype=bool).ravel()
    wt = np.ones(x.shape) if weights is None else np.asarray(weights, dtype=float).ravel()
    if x.shape != e.shape or x.shape != wt.shape:
        raise ValueError(f"intensities, exceeded and weights must have one shape, got "
                         f"{x.shape}, {e.shape} and {wt.shape}")
    if np.isnan(x).any():
        raise ValueError("intensities must not contain NaN")
    positive_finite_array("weights", wt)
    keep = (x > 0.0) & np.isfinite(x)
    order = np.argsort(x[keep], kind="stable")
    return np.log(x[keep][order]), e[keep][order], wt[keep][order]


def local_exceedance(intensities, exceeded, s, w: float, weights=None) -> np.ndarray:
    """P̂(s): the share of the analysed intensities within |ln(x/s)| <= w that exceed.

    Parameters
    ----------
    intensities : array_like
        Analysed intensities x [-] (any order; each analysis once).
    exceeded : array_like of bool
        Whether the analysis at each x exceeded the goal.
    s : float or array_like
        Intensities at which to estimate P [-].
    w : float
        Half-width of the window in ln s [-], > 0.
    weights : array_like, optional
        Weight of each analysis (> 0; default 1): the share is weighted, so a sample denser
        in one part of a window (the search's, where it confirms an answer) counts each part
        by its width, not by its number of analyses.

    Returns
    -------
    ndarray
        P̂ at each s (shape of ``s``); NaN where the window holds no analysed intensity.
    """
    import numpy as np  # on use: the command line's help loads no numpy

    w = _open_interval("w", w, 0.0, math.inf)
    lx, e, wt = _sample(intensities, exceeded, weights)
    ls = np.log(np.asarray(s, dtype=float))
    cum_e = np.concatenate([[0.0], np.cumsum(wt * e)])
    cum_w = np.concatenate([[0.0], np.cumsum(wt)])
    # the window is closed: x e^{-w}..x e^{+w}; a tiny slack keeps a sample lying exactly on
    # an edge (a lattice point s·e^{±w}) inside despite the rounding of the logarithms
    eps = 1e-12
    lo = np.searchsorted(lx, ls - w - eps, side="left")
    hi = np.searchsorted(lx, ls + w + eps, side="right")
    total = cum_w[hi] - cum_w[lo]
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(hi > lo, (cum_e[hi] - cum_e[lo]) / np.where(hi > lo, total, 1.0),
                       np.nan)
    return np.asarray(out, dtype=float)


def breakpoints(intensities, w: float) -> np.ndarray:
    """The s [-] at which P̂ of a sample may change, increasing: where an analysed
    intensity x enters the window (s = x e^{-w}, closed) or has just left it (s just past
    x e^{w}). P̂ is constant from each to the next, so its infimum crossing of any level
    is one of them."""
    import numpy as np  # on use: the command line's help loads no numpy

    lx = np.log(np.asarray(intensities, dtype=float).ravel())
    return np.exp(np.unique(np.concatenate([lx - w, lx + w + 2e-12])))


def exceedance_quantile(intensities, exceeded, p: float, w: float,
                        weights=None) -> tuple[float, bool]:
    """I_p = inf{s : P̂(s) >= p} of an analysed sample, and whether it is on a plateau.

    Parameters
    ----------
    intensities, exceeded : array_like
        As in :func:`local_exceedance`.
    p : float
        Exceedance share [-], in (0, 1).
    w : float
        Half-width of the window in ln s [-], > 0.
    weights : array_like, optional
        As in :func:`local_exceedance`.

    Returns
    -------
    (I_p, plateau) : (float, bool)
        I_p [-] (NaN where P̂ never reaches p: not reached); ``plateau`` where P̂ has a local
        maximum of at least :data:`PLATEAU_SHARE`·p more than one window (2w in ln s) below
        I_p, or anywhere when P̂ never reaches p: P rises near p without crossing it there,
        so I_p is ill-conditioned.
    """
    import numpy as np  # on use: the command line's help loads no numpy

    p = _open_interval("p", p, 0.0, 1.0)
    w = _open_interval("w", w, 0.0, math.inf)
    lx, e, wt = _sample(intensities, exceeded, weights)
    if not e.any():
        return math.nan, False
    s = breakpoints(np.exp(lx), w)
    P = local_exceedance(np.exp(lx), e, s, w, wt)
    reach = np.flatnonzero(P >= p - 1e-12)
    if reach.size == 0:
        return math.nan, bool(np.nanmax(P) >= PLATEAU_SHARE * p)
    ip = float(s[reach[0]])
    below = P[s < ip * math.exp(-2.0 * w)]
    plateau = bool(below.size and np.nanmax(below, initial=0.0) >= PLATEAU_SHARE * p)
    return ip, plateau
