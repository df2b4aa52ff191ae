"""Performance limit states of a rocking body: the one place that knows what a goal means.

An analysis reports its response as named peak quantities (:data:`QUANTITIES`: the largest
tilt ``theta_max``, ``overturned``, and room for the peaks other models add). A limit state
owns the quantity it watches, its threshold for a body, whether an analysis exceeded it
(:meth:`LimitState.exceeded`), when an analysis may stop once it is decided
(:meth:`LimitState.stop_at`), its severity order (:attr:`LimitState.severity`) and its title
(:attr:`LimitState.title`); it parses (:func:`parse_limit_state`) and prints (``str``)
itself. The search, the stripes, the study plan, the figures, the risk tables and the
configuration checks ask only these. Two kinds exist:

- ``"overturning"``: θ reaches π/2 (the analysis reports ``overturned``);
- ``"tilt:<r>"``: |θ| > r·α, with r > 0 given as a decimal (``"tilt:0.5"``) or a fraction
  (``"tilt:1/3"``). The paper's "excessive tilt" (θ > α/3, §5.2) is ``"tilt:1/3"``, also
  accepted as ``"excessive-tilt"``.

Each limit state has one canonical name, used in every output: ratios with a short exact
decimal are written as decimals (``"tilt:1/2"`` → ``"tilt:0.5"``), others as reduced
fractions (``"tilt:2/6"`` → ``"tilt:1/3"``). :func:`match_limit_state` finds a limit state
among labels in any spelling, including rounded decimals (``"tilt:0.3333"``).

Limit states are ordered by severity: increasing tilt goal, overturning last. An analysis
that overturned exceeds every limit state.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Protocol

import numpy as np

THETA_MAX = "theta_max"
"""Largest |θ| reached by an analysis [rad]."""

OVERTURNED = "overturned"
"""Whether θ reached π/2 (1.0 or True if it did)."""

QUANTITIES: dict[str, str] = {
    THETA_MAX: "largest |θ| reached [rad]",
    OVERTURNED: "θ reached π/2 [bool]",
    "mu_required_max": "largest friction coefficient the contact needed [-]",
    "normal_force_min": "smallest normal contact force, over the weight [-]",
}
"""The named peak quantities an analysis may report (:attr:`HasPeaks.peaks`); the last two
are reserved for the contact models that will report them."""


class HasPeaks(Protocol):
    """What a limit state reads of an analysis: its named peak quantities."""

    @property
    def peaks(self) -> Mapping[str, float]:
        """Peak quantities by name (keys of :data:`QUANTITIES`)."""
        ...


def check_peaks(peaks: Mapping[str, float]) -> Mapping[str, float]:
    """Return ``peaks`` if every name is one of :data:`QUANTITIES`, else raise ValueError."""
    unknown = sorted(set(peaks) - set(QUANTITIES))
    if unknown:
        raise ValueError(f"peaks: unknown quantity name(s) {unknown}; known {list(QUANTITIES)}")
    return peaks

OVERTURNING = "overturning"
"""Name of the overturning limit state."""

EXCESSIVE_TILT = "tilt:1/3"
"""The paper's excessive-tilt limit state, θ > α/3 (§5.2)."""

DEFAULT_LIMIT_STATES: tuple[str, ...] = (
    "tilt:0.1",
    "tilt:0.2",
    EXCESSIVE_TILT,
    "tilt:0.5",
    "tilt:0.75",
    "tilt:1",
    OVERTURNING,
)
"""The seven performance goals of the paper's Fig 10: r ∈ {0.1, 0.2, 1/3, 0.5, 0.75, 1} and
overturning."""

_ALIASES = {"excessive-tilt": EXCESSIVE_TILT, "excessive_tilt": EXCESSIVE_TILT}


@dataclass(frozen=True)
class LimitState:
    """One performance limit state.

    Attributes
    ----------
    name : str
        Canonical name, ``"overturning"`` or ``"tilt:<r>"``.
    ratio : float
        r of ``"tilt:<r>"`` [-]; ``inf`` for overturning.
    """

    name: str
    ratio: float

    @property
    def is_overturning(self) -> bool:
        """True for the overturning limit state."""
        return math.isinf(self.ratio)

    @property
    def quantity(self) -> str:
        """Name of the peak quantity this limit state watches (:data:`QUANTITIES`)."""
        return OVERTURNED if self.is_overturning else THETA_MAX

    @property
    def severity(self) -> float:
        """Sort key, mildest first: the tilt goal r, infinity for overturning."""
        return self.ratio

    @property
    def title(self) -> str:
        """Human title: ``"Overturning"``, ``"Tilt θ > α/3 (excessive tilt)"``.

        Ratios within 1e-3 of a fraction with a denominator up to 12 are written as one.
        """
        if self.is_overturning:
            return "Overturning"
        frac = Fraction(self.ratio).limit_denominator(12)
        if frac == 1 and abs(self.ratio - 1.0) <= 1e-3:
            return "Tilt θ > α"
        if frac.denominator == 1 or abs(float(frac) - self.ratio) > 1e-3:
            return f"Tilt θ > {self.ratio:.3g}·α"
        if frac.numerator == 1:
            return f"Tilt θ > α/{frac.denominator}" + (
                " (excessive tilt)" if frac == Fraction(1, 3) else "")
        return f"Tilt θ > {frac.numerator}α/{frac.denominator}"

    def threshold(self, alpha: float) -> float:
        """Tilt whose first exceedance defines the limit state [rad].

        Parameters
        ----------
        alpha : float
            Slenderness angle of the body [rad].

        Returns
        -------
        float
            r·α for a tilt goal, π/2 for overturning.

        Raises
        ------
        ValueError
            If r·α ≥ π/2: such a tilt can only be passed by overturning, so the goal is
            meaningless (use ``"overturning"``).
        """
        if self.is_overturning:
            return 0.5 * math.pi
        tau = self.ratio * alpha
        if tau >= 0.5 * math.pi:
            raise ValueError(
                f"limit state {self.name!r}: r·α = {tau:.4g} rad is not below π/2 for "
                f"alpha={alpha!r} (a body tilted that far has overturned); use 'overturning' "
                f"or r < {0.5 * math.pi / alpha:.4g}"
            )
        return tau

    def exceeded(self, outcome: HasPeaks | Mapping[str, float], alpha: float) -> bool:
        """Whether an analysis exceeded this limit state.

        Parameters
        ----------
        outcome : HasPeaks or mapping
            The analysis (anything with ``peaks``) or its peaks by name.
        alpha : float
            Slenderness angle of the body [rad].
        """
        peaks = outcome if isinstance(outcome, Mapping) else outcome.peaks
        if peaks[OVERTURNED]:
            return True  # an overturned body has passed every goal
        if self.is_overturning:
            return False
        return bool(peaks[self.quantity] > self.threshold(alpha))

    def scan_goal(self, alpha: float) -> float:
        """Tilt the search measures the response's closeness to this limit state against
        [rad]: the threshold, but never above α: no tilt beyond α (and no overturning) is
        reached without first passing α, where the restoring moment of the weight vanishes."""
        return min(self.threshold(alpha), alpha)

    def passed_at_tilt(self, tilt: float, alpha: float) -> bool:
        """Whether an analysis that went past ``tilt`` [rad] has certainly exceeded this
        limit state (how a run stopped on purpose decides the goals below its stop)."""
        return self.threshold(alpha) <= tilt

    def stop_at(self, alpha: float) -> float | None:
        """Tilt past which an analysis may end with this limit state decided [rad]; None
        when the analysis must run to its end (overturning may come at any time)."""
        return None if self.is_overturning else float(self.threshold(alpha))

    def __str__(self) -> str:
        return self.name


def _canonical_ratio(frac: Fraction) -> str:
    """One spelling per ratio: a short exact decimal ("0.5", "1") when the ratio has one,
    else the fraction ("1/3")."""
    den = frac.denominator
    while den % 2 == 0:
        den //= 2
    while den % 5 == 0:
        den //= 5
    if den == 1:
        return f"{float(frac):.15g}"
    return f"{frac.numerator}/{frac.denominator}"


def _parse_ratio(text: str, original: str) -> tuple[float, str]:
    """Ratio r and its canonical spelling from the part after ``tilt:``."""
    body = text.strip()
    try:
        if "/" in body:
            num, den = body.split("/", 1)
            frac = Fraction(int(num.strip()), int(den.strip()))
            r = float(frac)
        else:
            r = float(body)
            frac = None
    except (ValueError, ZeroDivisionError):
        raise ValueError(
            f"limit_state must be 'overturning' or 'tilt:<r>' with a number r > 0, "
            f"got {original!r}"
        ) from None
    if not math.isfinite(r) or r <= 0.0:
        raise ValueError(f"limit_state tilt ratio must be a finite number > 0, got {original!r}")
    if frac is None:
        # A decimal that is a simple fraction to rounding ("0.333333333333333") is that
        # fraction; other decimals keep the digits typed ("0.3333" is not 1/3).
        near = Fraction(r).limit_denominator(1000)
        frac = near if abs(float(near) - r) <= 1e-12 * r else None
    if frac is None:
        # 15 significant digits round-trip typed decimals: "0.3333", "0.125".
        return r, f"{r:.15g}"
    return r, _canonical_ratio(frac)


def parse_limit_state(spec: str | LimitState) -> LimitState:
    """Parse one limit state.

    Parameters
    ----------
    spec : str or LimitState
        ``"overturning"``, ``"tilt:<r>"`` (decimal or fraction), ``"excessive-tilt"``;
        case and surrounding blanks are ignored.

    Returns
    -------
    LimitState

    Raises
    ------
    ValueError
        Naming the offending text, for anything else.
    """
    if isinstance(spec, LimitState):
        return spec
    if not isinstance(spec, str):
        raise ValueError(f"limit_state must be a string, got {spec!r}")
    text = spec.strip().lower()
    text = _ALIASES.get(text, text)
    if text == OVERTURNING:
        return LimitState(OVERTURNING, math.inf)
    kind, sep, rest = text.partition(":")
    if kind != "tilt" or not sep:
        raise ValueError(f"limit_state must be 'overturning' or 'tilt:<r>', got {spec!r}")
    r, canon = _parse_ratio(rest, spec)
    return LimitState(f"tilt:{canon}", r)


def parse_limit_states(specs: str | LimitState | Iterable[str | LimitState] | None, *,
                       sort: bool = True) -> tuple[LimitState, ...]:
    """Parse a set of limit states.

    Parameters
    ----------
    specs : str, LimitState, iterable of them, or None
        A comma-separated string, one limit state, or a sequence; None or ``"default"``
        gives :data:`DEFAULT_LIMIT_STATES`.
    sort : bool
        Order by increasing tilt goal, overturning last (the search's order); False keeps
        the order given.

    Returns
    -------
    tuple of LimitState
        Without duplicates (two spellings of one limit state count once).

    Raises
    ------
    ValueError
        For an unknown limit state or an empty set.
    """
    if specs is None or (isinstance(specs, str) and specs.strip().lower() == "default"):
        specs = DEFAULT_LIMIT_STATES
    if isinstance(specs, LimitState):
        specs = [specs]
    elif isinstance(specs, str):
        specs = [s for s in specs.split(",") if s.strip()]
    parsed = {}
    for s in specs:
        ls = parse_limit_state(s)
        parsed.setdefault(ls.name, ls)
    if not parsed:
        raise ValueError(f"limit_states must name at least one limit state, got {specs!r}")
    if not sort:
        return tuple(parsed.values())
    return tuple(sorted(parsed.values(), key=severity))


def severity(limit_state: str | LimitState) -> float:
    """:attr:`LimitState.severity` of any spelling: the sort key from mildest to overturning."""
    return parse_limit_state(limit_state).severity


def limit_state_title(limit_state: str | LimitState) -> str:
    """:attr:`LimitState.title` of any spelling (``"tilt:1/3"``, ``"tilt:0.3333"``)."""
    return parse_limit_state(limit_state).title


def sort_limit_states(names: Iterable[str | LimitState]) -> list[str]:
    """Canonical names, once each, in increasing severity."""
    return sorted({parse_limit_state(n).name for n in names}, key=severity)


def stop_for(states: Sequence[LimitState], alpha: float) -> float | None:
    """Tilt past which one analysis has decided every one of ``states`` [rad]: the largest
    :meth:`LimitState.stop_at`, None when any must run to the end."""
    stops = [ls.stop_at(alpha) for ls in states]
    return None if any(s is None for s in stops) else max(stops)


def classify(outcome: HasPeaks | Mapping[str, float], states: Sequence[LimitState],
             alpha: float, stop_at: float | None, *,
             stopped: bool) -> tuple[np.ndarray, np.ndarray]:
    """What one successful analysis decides: (known, exceeded) per limit state.

    Parameters
    ----------
    outcome : HasPeaks or mapping
        The analysis or its peaks.
    states : sequence of LimitState
    alpha : float
        Slenderness angle of the body [rad].
    stop_at : float or None
        Tilt the analysis was allowed to stop at [rad] (None: run to the end).
    stopped : bool
        The analysis ended on purpose past ``stop_at``: the goals up to ``stop_at`` are
        passed even if the reported peak sits exactly on it; those above are unknown.

    Returns
    -------
    known, exceeded : ndarray of bool
    """
    exceeded = np.array([ls.exceeded(outcome, alpha) for ls in states])
    if not stopped:
        return np.ones(len(states), dtype=bool), exceeded
    limit = math.inf if stop_at is None else stop_at
    known = np.array([ls.passed_at_tilt(limit, alpha) for ls in states], dtype=bool)
    return known, (exceeded | known) & known


MATCH_TOLERANCE = 1e-3
"""Largest difference of tilt ratios r [-] at which two labels denote one limit state when
their canonical names differ: a rounded decimal ("tilt:0.3333") selects "tilt:1/3"."""


def match_limit_state(wanted: str | LimitState, available: Iterable[str], *,
                      missing_ok: bool = False) -> str | None:
    """The label among ``available`` that denotes the limit state ``wanted``.

    Every spelling is accepted on both sides: ``"tilt:1/3"``, ``"tilt:2/6"``,
    ``"excessive-tilt"`` and ``"tilt:0.3333"`` select the same entry. The canonical name
    wins; otherwise the tilt goal whose ratio r lies within :data:`MATCH_TOLERANCE`.

    Parameters
    ----------
    wanted : str or LimitState
        Any accepted spelling.
    available : iterable of str
        Labels, e.g. the ``limit_state`` coordinate of a store.
    missing_ok : bool
        Return None, instead of raising, when no label matches.

    Returns
    -------
    str or None
        The label as it appears in ``available``.

    Raises
    ------
    KeyError
        Naming ``wanted`` and the labels, when none (unless ``missing_ok``) or more than one
        matches.
    """
    labels = [str(a) for a in available]
    want = parse_limit_state(wanted)
    parsed = []
    for label in labels:
        try:
            parsed.append(parse_limit_state(label))
        except ValueError:
            parsed.append(None)
    exact = [lab for lab, p in zip(labels, parsed, strict=True) if p is not None
             and p.name == want.name]
    close = [lab for lab, p in zip(labels, parsed, strict=True) if p is not None
             and not want.is_overturning and not p.is_overturning
             and abs(p.ratio - want.ratio) <= MATCH_TOLERANCE]
    hits = exact or close
    if not hits and missing_ok:
        return None
    if len(hits) != 1:
        why = "matches several" if hits else "is not one"
        raise KeyError(f"limit_state {str(wanted)!r} {why} of {labels}")
    return hits[0]
