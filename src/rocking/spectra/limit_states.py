"""Performance limit states of a rocking body, as data.

A limit state is exceeded the first time the tilt passes a goal. Two kinds exist:

- ``"overturning"``: θ reaches π/2 (the analysis reports ``overturned``);
- ``"tilt:<r>"``: |θ| > r·α, with r > 0 given as a decimal (``"tilt:0.5"``) or a fraction
  (``"tilt:1/3"``). The paper's "excessive tilt" (θ > α/3, §5.2) is ``"tilt:1/3"``, also
  accepted as ``"excessive-tilt"``.

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


def _parse_ratio(text: str, original: str) -> tuple[float, str]:
    """Ratio r and its canonical spelling from the part after ``tilt:``."""
    body = text.strip()
    try:
        if "/" in body:
            num, den = body.split("/", 1)
            frac = Fraction(int(num.strip()), int(den.strip()))
            r = float(frac)
            canon = f"{frac.numerator}/{frac.denominator}" if frac.denominator != 1 else None
        else:
            r = float(body)
            canon = None
    except (ValueError, ZeroDivisionError):
        raise ValueError(
            f"limit_state must be 'overturning' or 'tilt:<r>' with a number r > 0, "
            f"got {original!r}"
        ) from None
    if not math.isfinite(r) or r <= 0.0:
        raise ValueError(f"limit_state tilt ratio must be a finite number > 0, got {original!r}")
    if canon is None:
        # 15 significant digits round-trip typed decimals: "0.5", "1", "0.3333".
        canon = f"{r:.15g}"
    return r, canon


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


def parse_limit_states(specs: str | LimitState | Iterable[str | LimitState] | None) -> tuple[
    LimitState, ...
]:
    """Parse a set of limit states, ordered by increasing tilt goal (overturning last).

    Parameters
    ----------
    specs : str, LimitState, iterable of them, or None
        A comma-separated string, one limit state, or a sequence; None or ``"default"``
        gives :data:`DEFAULT_LIMIT_STATES`.

    Returns
    -------
    tuple of LimitState
        Sorted by ratio, without duplicates.

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
    return tuple(parsed[r] for r in sorted(parsed))
