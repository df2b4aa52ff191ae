"""Performance limit states of a rocking body, as data.

A limit state is exceeded the first time the tilt passes a goal. Two kinds exist:

- ``"overturning"``: θ reaches π/2 (the analysis reports ``overturned``);
- ``"tilt:<r>"``: |θ| > r·α, with r > 0 given as a decimal (``"tilt:0.5"``) or a fraction
  (``"tilt:1/3"``). The paper's "excessive tilt" (θ > α/3, §5.2) is ``"tilt:1/3"``, also
  accepted as ``"excessive-tilt"``.

Each limit state has one canonical name, used in every output: ratios with a short exact
decimal are written as decimals (``"tilt:1/2"`` → ``"tilt:0.5"``), others as reduced
fractions (``"tilt:2/6"`` → ``"tilt:1/3"``). :func:`match_limit_state` finds a limit state
among labels in any spelling, including rounded decimals (``"tilt:0.3333"``).

Limit states are compared through their tilt threshold in radians, which depends on the
body's slenderness α; overturning has the largest threshold, π/2.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass
from fractions import Fraction

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
                f"limit state {self.name!r}: r·α = {tau!r} rad is not below π/2 for "
                f"alpha={alpha!r}; use 'overturning'"
            )
        return tau

    def exceeded(self, theta_max: float, overturned: bool, alpha: float) -> bool:
        """Whether an analysis that reached ``theta_max`` [rad] exceeded this limit state."""
        if overturned:
            return True
        if self.is_overturning:
            return False
        return bool(theta_max > self.threshold(alpha))

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
        parsed.setdefault(ls.ratio, ls)
    if not parsed:
        raise ValueError(f"limit_states must name at least one limit state, got {specs!r}")
    if not sort:
        return tuple(parsed.values())
    return tuple(parsed[r] for r in sorted(parsed))


MATCH_TOLERANCE = 1e-3
"""Largest difference of tilt ratios r [-] at which two labels denote one limit state when
their canonical names differ: a rounded decimal ("tilt:0.3333") selects "tilt:1/3"."""


def match_limit_state(wanted: str | LimitState, available: Iterable[str]) -> str:
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

    Returns
    -------
    str
        The label as it appears in ``available``.

    Raises
    ------
    KeyError
        Naming ``wanted`` and the labels, when none (or more than one) matches.
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
    if len(hits) != 1:
        why = "matches several" if hits else "is not one"
        raise KeyError(f"limit_state {str(wanted)!r} {why} of {labels}")
    return hits[0]
