"""Cumulative counts of zero-level up-crossings and local extrema of a sampled signal.

These counts identify the filter of the Rezaeian–Der Kiureghian model: the rate of zero
up-crossings gives the predominant frequency ω_f(t), the count of positive minima and
negative maxima (PM+NM) gives the bandwidth ζ_f.

Conventions (all arrays have the time on the last axis; stacks of signals are allowed):

- up-crossing between samples k and k+1 when a_k < 0 ≤ a_{k+1}; it is counted at k+1;
- positive minimum at k when a_k > 0, a_{k−1} > a_k and a_{k+1} > a_k;
- negative maximum at k when a_k < 0, a_{k−1} < a_k and a_{k+1} < a_k;
- local maximum at k when a_{k−1} < a_k and a_{k+1} < a_k (any sign).

Each cumulative count N[k] is the number of events at samples ≤ k, so N[0] = 0. Because a
signal's maxima are its positive excursions' peaks plus its negative maxima, and each positive
excursion has one more maximum than minima, N_pmnm ≈ N_max − N₀⁺ up to end effects.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray


def _signal(a: ArrayLike) -> NDArray[np.float64]:
    x = np.asarray(a, dtype=np.float64)
    if x.ndim == 0 or x.shape[-1] < 3:
        raise ValueError(f"a needs at least 3 samples along its last axis, got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        bad = np.argwhere(~np.isfinite(x))[0]
        raise ValueError(f"a has a non-finite value {x[tuple(bad)]!r} at index {tuple(bad)}")
    return x


def _cumulate_at(events: NDArray[np.bool_], first: int, n: int) -> NDArray[np.int64]:
    """Cumulative count of ``events`` placed at samples first, first+1, … on length ``n``."""
    out = np.zeros(events.shape[:-1] + (n,), dtype=np.int64)
    np.cumsum(events, axis=-1, out=out[..., first : first + events.shape[-1]])
    # Samples after the last possible event keep the final count.
    last = first + events.shape[-1]
    if last < n:
        out[..., last:] = out[..., last - 1 : last]
    return out


def zero_upcrossings_cum(a: ArrayLike) -> NDArray[np.int64]:
    """Cumulative number of zero-level up-crossings N₀⁺[k] (events at samples ≤ k).

    Parameters
    ----------
    a : array_like
        Signal [any unit], time on the last axis, ≥ 3 samples.

    Returns
    -------
    numpy.ndarray of int64
        Same shape as ``a``.
    """
    x = _signal(a)
    up = (x[..., :-1] < 0.0) & (x[..., 1:] >= 0.0)
    return _cumulate_at(up, 1, x.shape[-1])


def _interior_cum(
    a: ArrayLike,
    event: Callable[[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
                    NDArray[np.bool_]],
) -> NDArray[np.int64]:
    """Cumulative count of ``event(prev, mid, nxt)``, judged at each interior sample of ``a``."""
    x = _signal(a)
    return _cumulate_at(event(x[..., :-2], x[..., 1:-1], x[..., 2:]), 1, x.shape[-1])


def pmnm_cum(a: ArrayLike) -> NDArray[np.int64]:
    """Cumulative number of positive minima plus negative maxima N_pmnm[k].

    Parameters
    ----------
    a : array_like
        Signal [any unit], time on the last axis, ≥ 3 samples.

    Returns
    -------
    numpy.ndarray of int64
        Same shape as ``a``.
    """

    def pm_or_nm(prev, mid, nxt):
        pos_min = (mid > 0.0) & (prev > mid) & (nxt > mid)
        neg_max = (mid < 0.0) & (prev < mid) & (nxt < mid)
        return pos_min | neg_max

    return _interior_cum(a, pm_or_nm)


def maxima_cum(a: ArrayLike) -> NDArray[np.int64]:
    """Cumulative number of strict local maxima N_max[k] (any sign).

    Parameters
    ----------
    a : array_like
        Signal [any unit], time on the last axis, ≥ 3 samples.

    Returns
    -------
    numpy.ndarray of int64
        Same shape as ``a``.
    """
    return _interior_cum(a, lambda prev, mid, nxt: (prev < mid) & (nxt < mid))
