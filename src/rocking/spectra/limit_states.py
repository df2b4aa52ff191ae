"""Performance limit states of a rocking body: the one place that knows what a goal means.

An analysis reports its response as named peak quantities (:data:`QUANTITIES`: the largest
tilt ``theta_max``, ``overturned``, the largest friction the contact needed
``mu_required_max`` and the smallest normal force ``normal_force_min``). A limit state
(:class:`LimitState`, the protocol every kind implements) owns the quantity it watches, its
threshold for a body, whether an analysis exceeded it (:meth:`LimitState.exceeded`), when
an analysis may stop once it is decided
(:meth:`LimitState.stop_at`, :meth:`LimitState.decided_when_stopped`), whether a body at
rest can exceed it (:attr:`LimitState.at_rest`) and whether it needs the whole record
monitored (:attr:`LimitState.whole_record`), its severity order
(:attr:`LimitState.severity`) and its title (:attr:`LimitState.title`); it parses
(:func:`parse_limit_state`) and prints (``str``) itself. The search, the stripes, the study
plan, the figures, the risk tables and the configuration checks ask only these. Three kinds
exist:

- ``"overturning"`` (:class:`Overturning`): θ reaches π/2 (the analysis reports
  ``overturned``);
- ``"tilt:<r>"`` (:class:`TiltGoal`): |θ| > r·α, with r > 0 given as a decimal
  (``"tilt:0.5"``) or a fraction (``"tilt:1/3"``). The paper's "excessive tilt" (θ > α/3,
  §5.2) is ``"tilt:1/3"``, also accepted as ``"excessive-tilt"``;
- ``"sliding:<μ>"`` (:class:`Sliding`): the body slides while in contact: it needs more
  friction than the support's coefficient μ > 0 somewhere in an analysis that did not
  overturn, ``mu_required_max`` > μ (over N > 0). Leaving the support (N ≤ 0,
  :func:`lifts_off`) is not sliding, and neither is the fall of an overturning body: there
  N → 0⁺ while the contact still carries a horizontal force, so μ_req grows without bound
  (62 to 246 in the falls of the column of docs/risk.md under El Centro) whatever μ; an
  overturned analysis therefore says nothing about sliding (:meth:`LimitState.decides`).
  A body at rest needs |a_h|/(g + a_z), so a sliding goal may be exceeded below uplift (μ
  below about tan α).

Lift-off has no goal of its own: without vertical ground motion N ≤ 0 comes only in the fall
of an overturning body, and it marks the model leaving its range (a rigid body on a rigid
support), not a damage state; every answer says whether an analysis up to it lifted off
(the ``lifts_off`` flag, :func:`lifts_off`).

Each limit state has one canonical name, used in every output: ratios with a short exact
decimal are written as decimals (``"tilt:1/2"`` → ``"tilt:0.5"``), others as reduced
fractions (``"tilt:2/6"`` → ``"tilt:1/3"``); μ as a decimal (``"sliding:0.60"`` →
``"sliding:0.6"``). :func:`match_limit_state` finds a limit state among labels in any
spelling, including rounded decimals (``"tilt:0.3333"``).

Limit states are ordered by severity, a pair (axis, level): the tilt axis first (increasing
tilt goal, overturning last), then the sliding axis (increasing μ: a smaller μ is exceeded
first). The two axes are not nested: an analysis that overturned exceeds every tilt goal,
but a sliding goal only by its own monitors (where the sliding answer lies above the
overturning one, overturning governs).
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import ClassVar, Protocol

import numpy as np

from rocking.dynamics.result import contact_slides, leaves_support

THETA_MAX = "theta_max"
"""Largest |θ| reached by an analysis [rad]."""

OVERTURNED = "overturned"
"""Whether θ reached π/2 (1.0 or True if it did)."""

MU_REQUIRED_MAX = "mu_required_max"
"""Largest friction coefficient the contact needed, |F_h|/N over N > 0 [-]."""

NORMAL_FORCE_MIN = "normal_force_min"
"""Smallest normal contact force, over the weight [-] (< 0: the body would lift off)."""

QUANTITIES: dict[str, str] = {
    THETA_MAX: "largest |θ| reached [rad]",
    OVERTURNED: "θ reached π/2 [bool]",
    MU_REQUIRED_MAX: "largest friction coefficient the contact needed [-]",
    NORMAL_FORCE_MIN: "smallest normal contact force, over the weight [-]",
}
"""The named peak quantities an analysis may report (:attr:`HasPeaks.peaks`)."""


class HasPeaks(Protocol):
    """What a limit state reads of an analysis: its named peak quantities."""

    @property
    def peaks(self) -> Mapping[str, float]:
        """Peak quantities by name (keys of :data:`QUANTITIES`)."""
        ...


def lifts_off(peaks: Mapping[str, float]) -> bool:
    """The body left its support somewhere in the analysis: ``normal_force_min`` ≤ 0
    (:func:`rocking.dynamics.result.leaves_support`; False where not reported)."""
    return leaves_support(float(peaks.get(NORMAL_FORCE_MIN, math.nan)))


def slides_in_contact(peaks: Mapping[str, float], mu: float | None) -> bool | None:
    """The body slid while in contact: an analysis that did not overturn needed more
    friction than ``mu`` (:func:`rocking.dynamics.result.contact_slides`); None without
    ``mu``, where the analysis overturned or did not report ``mu_required_max``."""
    if MU_REQUIRED_MAX not in peaks:
        return None
    return contact_slides(float(peaks[MU_REQUIRED_MAX]), bool(peaks.get(OVERTURNED)), mu)


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

TILT_AXIS, SLIDING_AXIS = 0, 1
"""First entry of :attr:`LimitState.severity`: the tilt axis (tilt goals, overturning last)
and the sliding axis. Limit states of different axes are not nested."""

_KINDS_TEXT = "'overturning', 'tilt:<r>' or 'sliding:<mu>'"


def _peaks_of(outcome: HasPeaks | Mapping[str, float]) -> Mapping[str, float]:
    return outcome if isinstance(outcome, Mapping) else outcome.peaks


def _peak(peaks: Mapping[str, float], name: str, who: str) -> float:
    """``peaks[name]``, or a ValueError naming the limit state that needs it."""
    if name not in peaks:
        raise ValueError(f"limit state {who!r} reads the peak {name!r}, which the analysis "
                         f"did not report (it reported {sorted(peaks)})")
    return peaks[name]


class LimitState(ABC):
    """The protocol of a performance limit state (one subclass per kind).

    Attributes
    ----------
    name : str
        Canonical name (``str(limit_state)``).
    at_rest : bool
        A body at rest (below uplift) can exceed it: the search looks below the uplift
        intensity for it.
    whole_record : bool
        Its quantity can grow after the tilt is decided: an analysis deciding it may not end
        early once its peak tilt is decided (``stop_when_decided``), and it never stops at a
        tilt.
    """

    name: str
    at_rest: ClassVar[bool] = False
    whole_record: ClassVar[bool] = False

    @property
    @abstractmethod
    def quantity(self) -> str:
        """Name of the peak quantity this limit state watches (:data:`QUANTITIES`)."""

    @property
    @abstractmethod
    def severity(self) -> tuple[int, float]:
        """Sort key, mildest first: (axis, level), :data:`TILT_AXIS` or
        :data:`SLIDING_AXIS` and the level along it."""

    @property
    @abstractmethod
    def title(self) -> str:
        """Human title, e.g. ``"Tilt θ > α/3 (excessive tilt)"``."""

    @abstractmethod
    def threshold(self, alpha: float) -> float:
        """Value of :attr:`quantity` whose first exceedance defines the limit state, for a
        body of slenderness angle ``alpha`` [rad] (tilts in [rad], μ in [-]); a ValueError
        where the goal is meaningless for that body."""

    @abstractmethod
    def exceeded(self, outcome: HasPeaks | Mapping[str, float], alpha: float) -> bool:
        """Whether an analysis (anything with ``peaks``, or its peaks by name) exceeded this
        limit state, for a body of slenderness angle ``alpha`` [rad]."""

    def decides(self, outcome: HasPeaks | Mapping[str, float]) -> bool:
        """Whether a finished analysis says anything about this limit state (default: yes;
        :class:`Sliding`: not where it overturned)."""
        return True

    @abstractmethod
    def decided_when_stopped(self, outcome: HasPeaks | Mapping[str, float], tilt: float,
                             alpha: float) -> bool:
        """Whether an analysis that ended on purpose past ``tilt`` [rad] has certainly
        exceeded this limit state (how such a run decides it)."""

    def stop_at(self, alpha: float) -> float | None:
        """Tilt past which an analysis may end with this limit state decided [rad]; None
        (the default) when the analysis must run to its end."""
        return None

    def near(self, other: LimitState) -> bool:
        """``other`` is of the same axis with a level within :data:`MATCH_TOLERANCE` (a
        rounded spelling of this limit state)."""
        (a, x), (b, y) = self.severity, other.severity
        return a == b and math.isfinite(x) and math.isfinite(y) \
            and abs(x - y) <= MATCH_TOLERANCE

    def __str__(self) -> str:
        return self.name


@dataclass(frozen=True)
class Overturning(LimitState):
    """θ reaches π/2. An analysis must run to its end to decide it (it may come at any
    time)."""

    name: str = field(default=OVERTURNING, init=False)

    quantity = property(lambda self: OVERTURNED,
                        doc="``overturned``.")
    severity = property(lambda self: (TILT_AXIS, math.inf),
                        doc="Last on the tilt axis.")
    title = property(lambda self: "Overturning", doc="``\"Overturning\"``.")

    def threshold(self, alpha: float) -> float:
        """π/2 [rad]."""
        return 0.5 * math.pi

    def exceeded(self, outcome: HasPeaks | Mapping[str, float], alpha: float) -> bool:
        return bool(_peaks_of(outcome)[OVERTURNED])

    def decided_when_stopped(self, outcome: HasPeaks | Mapping[str, float], tilt: float,
                             alpha: float) -> bool:
        return self.threshold(alpha) <= tilt


@dataclass(frozen=True)
class TiltGoal(LimitState):
    """|θ| > r·α.

    Attributes
    ----------
    name : str
        Canonical name ``"tilt:<r>"``.
    ratio : float
        r [-], > 0.
    """

    name: str
    ratio: float

    quantity = property(lambda self: THETA_MAX, doc="``theta_max``.")
    severity = property(lambda self: (TILT_AXIS, self.ratio), doc="(tilt axis, r).")

    @property
    def title(self) -> str:
        """``"Tilt θ > α/3 (excessive tilt)"``: ratios within 1e-3 of a fraction with a
        denominator up to 12 are written as one."""
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
        """r·α [rad]; a ValueError if r·α ≥ π/2: such a tilt can only be passed by
        overturning, so the goal is meaningless (use ``"overturning"``)."""
        tau = self.ratio * alpha
        if tau >= 0.5 * math.pi:
            raise ValueError(
                f"limit state {self.name!r}: r·α = {tau:.4g} rad is not below π/2 for "
                f"alpha={alpha!r} (a body tilted that far has overturned); use 'overturning' "
                f"or r < {0.5 * math.pi / alpha:.4g}"
            )
        return tau

    def exceeded(self, outcome: HasPeaks | Mapping[str, float], alpha: float) -> bool:
        peaks = _peaks_of(outcome)
        if peaks[OVERTURNED]:
            return True  # an overturned body has passed every tilt goal
        return bool(peaks[THETA_MAX] > self.threshold(alpha))

    def decided_when_stopped(self, outcome: HasPeaks | Mapping[str, float], tilt: float,
                             alpha: float) -> bool:
        """Goals up to the stop are passed even if the reported peak sits exactly on it."""
        return self.threshold(alpha) <= tilt

    def stop_at(self, alpha: float) -> float:
        """The threshold: past it the goal is decided [rad]."""
        return float(self.threshold(alpha))

    @staticmethod
    def parse(text: str, original: str) -> TiltGoal:
        """From the part after ``tilt:``."""
        r, canon = _parse_ratio(text, original)
        return TiltGoal(f"tilt:{canon}", r)


@dataclass(frozen=True)
class Sliding(LimitState):
    """The body slides while in contact: an analysis that did not overturn needed more
    friction than μ (``mu_required_max`` > μ, over N > 0; :func:`slides_in_contact`).

    Leaving the support (N ≤ 0) is not sliding. An overturned analysis decides nothing
    (:meth:`decides`): its fall needs unbounded friction as N → 0⁺ whatever μ. Its quantity
    is monitored along the whole analysis and can grow after the tilt is decided (and at
    rest: |a_h|/(g + a_z)), so an analysis deciding it runs to its end and the search looks
    for it below uplift too. Its exceedance need not grow with the intensity (as a tilt
    goal's); the search answers it like any goal (:mod:`rocking.spectra.quantity`). Where
    the answer lies above the overturning answer of the same motion, the body overturns
    before it slides.

    Attributes
    ----------
    name : str
        Canonical name ``"sliding:<μ>"``.
    mu : float
        Support friction coefficient μ [-], > 0.
    """

    name: str
    mu: float
    at_rest: ClassVar[bool] = True
    whole_record: ClassVar[bool] = True

    quantity = property(lambda self: MU_REQUIRED_MAX, doc="``mu_required_max``.")
    severity = property(lambda self: (SLIDING_AXIS, self.mu), doc="(sliding axis, μ).")
    title = property(lambda self: f"Sliding at μ = {self.mu:.3g}",
                     doc="``\"Sliding at μ = 0.6\"``.")

    def threshold(self, alpha: float) -> float:
        """μ [-], whatever the body."""
        return self.mu

    def exceeded(self, outcome: HasPeaks | Mapping[str, float], alpha: float) -> bool:
        """:func:`slides_in_contact` (False where it says nothing: an overturned analysis)."""
        peaks = _peaks_of(outcome)
        _peak(peaks, MU_REQUIRED_MAX, self.name)
        return bool(slides_in_contact(peaks, self.mu))

    def decides(self, outcome: HasPeaks | Mapping[str, float]) -> bool:
        """Not where the analysis overturned."""
        return not _peaks_of(outcome)[OVERTURNED]

    def decided_when_stopped(self, outcome: HasPeaks | Mapping[str, float], tilt: float,
                             alpha: float) -> bool:
        """Only if already exceeded: a peak over μ stays over, a run cut short says
        nothing of what it would have needed later."""
        return self.exceeded(outcome, alpha)

    @staticmethod
    def parse(text: str, original: str) -> Sliding:
        """From the part after ``sliding:``."""
        try:
            mu = float(text.strip())
        except ValueError:
            raise ValueError(f"limit_state must be 'sliding:<mu>' with a number mu > 0, "
                             f"got {original!r}") from None
        if not math.isfinite(mu) or mu <= 0.0:
            raise ValueError(f"limit_state sliding friction coefficient mu must be a finite "
                             f"number > 0, got {original!r}")
        return Sliding(f"sliding:{mu:.15g}", mu)


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
            f"limit_state must be 'tilt:<r>' with a number r > 0, "
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


_KINDS: dict[str, Callable[[str, str], LimitState]] = {
    "tilt": TiltGoal.parse,
    "sliding": Sliding.parse,
}
"""The kinds written ``<kind>:<value>``, each parsing its value (the text after the colon
and the whole text, for the message)."""


def parse_limit_state(spec: str | LimitState) -> LimitState:
    """Parse one limit state.

    Parameters
    ----------
    spec : str or LimitState
        ``"overturning"``, ``"tilt:<r>"`` (decimal or fraction), ``"excessive-tilt"``,
        ``"sliding:<mu>"``; case and surrounding blanks are ignored.

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
        return Overturning()
    kind, sep, rest = text.partition(":")
    if kind not in _KINDS or not sep:
        raise ValueError(f"limit_state must be {_KINDS_TEXT}, got {spec!r}")
    return _KINDS[kind](rest, spec)


def parse_limit_states(specs: str | LimitState | Iterable[str | LimitState] | None, *,
                       sort: bool = True) -> tuple[LimitState, ...]:
    """Parse a set of limit states.

    Parameters
    ----------
    specs : str, LimitState, iterable of them, or None
        A comma-separated string, one limit state, or a sequence; None or ``"default"``
        gives :data:`DEFAULT_LIMIT_STATES`.
    sort : bool
        Order by increasing severity (:attr:`LimitState.severity`); False keeps
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


def severity(limit_state: str | LimitState) -> tuple[int, float]:
    """:attr:`LimitState.severity` of any spelling: the sort key (axis, level), mildest
    first, the tilt axis before the sliding axis."""
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


def whole_record(states: Iterable[LimitState]) -> bool:
    """Whether analyses deciding ``states`` must be monitored to the end of the record
    (:attr:`LimitState.whole_record` of any)."""
    return any(ls.whole_record for ls in states)


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
        The analysis ended on purpose past ``stop_at``: each limit state decides what that
        says (:meth:`LimitState.decided_when_stopped`: the tilt goals up to ``stop_at`` are
        passed even if the reported peak sits exactly on it, those above unknown). A limit
        state the analysis says nothing about (:meth:`LimitState.decides`) is unknown.

    Returns
    -------
    known, exceeded : ndarray of bool
    """
    exceeded = np.array([ls.exceeded(outcome, alpha) for ls in states], dtype=bool)
    decides = np.array([ls.decides(outcome) for ls in states], dtype=bool)
    if not stopped:
        return decides, exceeded & decides
    limit = math.inf if stop_at is None else stop_at
    known = np.array([ls.decided_when_stopped(outcome, limit, alpha) for ls in states],
                     dtype=bool) & decides
    return known, (exceeded | known) & known


MATCH_TOLERANCE = 1e-3
"""Largest difference of levels (tilt ratio r, friction μ) [-] at which two labels of one
axis denote one limit state when their canonical names differ: a rounded decimal
("tilt:0.3333") selects "tilt:1/3"."""


def match_limit_state(wanted: str | LimitState, available: Iterable[str], *,
                      missing_ok: bool = False) -> str | None:
    """The label among ``available`` that denotes the limit state ``wanted``.

    Every spelling is accepted on both sides: ``"tilt:1/3"``, ``"tilt:2/6"``,
    ``"excessive-tilt"`` and ``"tilt:0.3333"`` select the same entry. The canonical name
    wins; otherwise the limit state of the same axis within :data:`MATCH_TOLERANCE`
    (:meth:`LimitState.near`).

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
             and want.near(p)]
    hits = exact or close
    if not hits and missing_ok:
        return None
    if len(hits) != 1:
        why = "matches several" if hits else "is not one"
        raise KeyError(f"limit_state {str(wanted)!r} {why} of {labels}")
    return hits[0]
