"""Named accuracy presets of the critical-intensity search.

The search (:mod:`rocking.spectra.search`) estimates I_p = inf{s : P(s) >= p}
(:mod:`rocking.spectra.quantity`) in two kinds of analyses, and these choices set together
how close its answer is to the converged I_p and what it costs:

- ``rtol``: relative tolerance of the ODE integration of each analysis of the undamped 3D
  and the 2D models, and ``rtol_damped`` that of the stiff damped 3D model (its cost grows
  faster with the accuracy asked, so it gets its own value);
- ``scan_step``: relative step h of the scan grid I_j = I_uplift·(1 + h)^(j + u), u random
  per cell, that finds a first exceedance of each limit state (the candidate around which
  P is sampled; under ``first_exceedance`` the answer itself);
- ``local_step``: width δ of the strata, in ln I, of the local sample around a candidate,
  one analysis at a random position in each: a window of P(s) (±w in ln s) holds about
  2w/δ analyses, and the noise of P̂ — hence of I_p — falls with their number;
- ``local_below`` and ``local_above``: how far below and above a candidate (in ln I) the
  local sample first reaches; it is extended down by ``local_below`` while P̂ at the lowest
  s it can judge is p/2 or more; ``confirm``: a crossing of p is confirmed on a sample twice
  as dense before it is taken.

``rest_tilt`` sets the analyses' micro-uplift rest criterion (None: the engine's default).

The presets were chosen on ``python -m benchmarks resolution`` (docs/performance.md,
"The trade"): the answers of each preset against I10 of a 0.02 % lattice, with analyses
and CPU seconds per point. ``default`` (2 % scan, 0.6 % strata) had 86 % of its answers
within 5 % of I10 (90 % with the seven goals of Fig 10), median error 0.3 %, at 0.84 times
the CPU of the first-exceedance ``default`` before it with two goals (1.2 times with seven);
``precise`` (1 % scan, 0.4 % strata) 93 %, median 0.2 %, at about twice the cost; ``fast``
(3 % scan) 83 %, median 0.4 %. Strata of at most 0.6 % keep more than 1/p analyses in a
confirmed window (w = 2 %, p = 0.1): a window of exceedance narrower than half a stratum
never makes an answer by itself.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

from rocking.dynamics.names import MODEL_3D_DAMPED


@dataclass(frozen=True)
class Accuracy:
    """Settings of one critical-intensity search.

    Parameters
    ----------
    name : str
        Label written to outputs.
    rtol : float
        ODE relative tolerance of the "3d" and "2d" analyses [-], in (0, 1e-2].
    scan_step : float
        Relative step of the scan grid [-], in (0, 1].
    local_step : float
        Width of a stratum of the local sample in ln I [-], in (0, 0.1].
    local_below, local_above : float
        Reach of the local sample below and above a candidate in ln I [-], in (0, 1];
        ``local_below`` >= ln(1 + ``scan_step``), so that the sample around the next
        candidate of the grid joins the one below it.
    confirm : bool
        Confirm a crossing of p on a sample twice as dense (a second analysis in every
        stratum its window touches) before taking it as I_p.
    rtol_damped : float, optional
        ODE relative tolerance of the "3d-damped" analyses [-]; default ``rtol``.
    rest_tilt : float, optional
        Rest tilt of every analysis [rad] (``rest_tilt`` of
        :func:`rocking.dynamics.analysis.ground_response`): None, the engine's default per
        model (micro-uplift below a 5 µm rim lift ends an undamped 3D episode); 0, the exact
        treatment that follows every micro-uplift to its end; at most 1e-4.
    configured : str or dict, optional
        What :meth:`of` built it from: a preset's name (a preset spells itself by its
        name) or a mapping of fields as it was given; None for settings built directly or
        changed by :meth:`with_`. A study's stores record and hash this
        spelling (:meth:`record`), not the settings, so that a store keeps its digest; it
        takes no part in equality.

    Build one with :meth:`of` where the settings enter (a configuration, a command line, a
    public function's argument, a store's attributes) and hand the object down: nothing
    below resolves it again.
    """

    name: str
    rtol: float
    scan_step: float
    local_step: float
    local_below: float = 0.04
    local_above: float = 0.02
    confirm: bool = True
    rtol_damped: float | None = None
    rest_tilt: float | None = None
    configured: str | dict[str, Any] | None = field(default=None, compare=False, repr=False,
                                                    kw_only=True)

    @classmethod
    def of(cls, accuracy: str | Accuracy | Mapping[str, Any]) -> Accuracy:
        """The settings of a preset name, a ready :class:`Accuracy` (itself), or a mapping
        of its fields: the one way to resolve them.

        A mapping may name a preset under ``"preset"`` and override some of its fields, e.g.
        ``{"preset": "default", "rtol": 1e-9}`` (the form a workflow configuration uses); one
        with a ``"name"`` and no ``"preset"`` is a record (:meth:`to_dict`, the settings a
        store keeps): the fields it leaves out are its named preset's. The value is kept as
        given in ``configured``.

        Raises
        ------
        ValueError
            For an unknown preset name or field.
        """
        if isinstance(accuracy, Accuracy):
            return accuracy
        if isinstance(accuracy, str):
            key = accuracy.strip().lower()
            if key not in PRESETS:
                raise ValueError(f"accuracy must be one of {sorted(PRESETS)}, got {accuracy!r}")
            # a preset spells itself by its name: "Default" and "default" are one setting
            return PRESETS[key]
        if isinstance(accuracy, Mapping):
            fields = dict(accuracy)
            unknown = sorted(set(fields) - set(FIELDS) - {"preset"})
            if unknown:
                raise ValueError(f"accuracy has unknown field(s) {unknown}; allowed "
                                 f"{sorted([*FIELDS, 'preset'])}")
            # a record that names a preset and leaves fields out takes them from that
            # preset, never from the default under the preset's name
            named = str(fields.get("name", "")).strip().lower()
            base = cls.of(fields.pop("preset", named if named in PRESETS else "default"))
            return replace(base.with_(**fields) if fields else base,
                           configured=dict(accuracy))
        raise ValueError(f"accuracy must be a preset name, an Accuracy or a mapping, got "
                         f"{accuracy!r}")

    def record(self) -> str | dict[str, Any]:
        """What a study's store records (and hashes) of these settings: the value they
        were configured as (:attr:`configured`), else their fields (:meth:`to_dict`)."""
        if self.configured is None:
            return self.to_dict()
        return dict(self.configured) if isinstance(self.configured, Mapping) \
            else self.configured

    @property
    def preset(self) -> str | None:
        """The preset's name as configured when the settings were given as one (what a
        report and the risk table name), None for tolerances given as a mapping."""
        return self.configured if isinstance(self.configured, str) else None

    def __post_init__(self) -> None:
        _check_range("rtol", self.rtol, 0.0, 1e-2)
        if self.rtol_damped is None:
            object.__setattr__(self, "rtol_damped", self.rtol)
        _check_range("rtol_damped", self.rtol_damped, 0.0, 1e-2)
        _check_range("scan_step", self.scan_step, 0.0, 1.0)
        _check_range("local_step", self.local_step, 0.0, 0.1)
        _check_range("local_below", self.local_below, 0.0, 1.0)
        _check_range("local_above", self.local_above, 0.0, 1.0)
        for name in ("rtol", "rtol_damped", "scan_step", "local_step", "local_below",
                     "local_above"):
            object.__setattr__(self, name, float(getattr(self, name)))
        if not isinstance(self.confirm, bool):
            raise ValueError(f"confirm must be true or false, got {self.confirm!r}")
        if self.local_below < math.log1p(self.scan_step) - 1e-12:
            raise ValueError(f"local_below must be >= ln(1 + scan_step) = "
                             f"{math.log1p(self.scan_step):.6g}, got {self.local_below!r}")
        if self.rest_tilt is not None:
            # ≤ 1e-4 rad stays below the engine's bound 0.01 α for every tan α > 0.0101, so a
            # valid study configuration never fails inside a worker
            _check_range("rest_tilt", self.rest_tilt, 0.0, 1e-4, lower_closed=True)
            object.__setattr__(self, "rest_tilt", float(self.rest_tilt))

    def check_window(self, w: float) -> None:
        """A local sample must be wider than the window of P (2w in ln s) to judge any s:
        a one-line error naming the settings otherwise."""
        if self.local_below + self.local_above <= 2.0 * w:
            raise ValueError(f"accuracy local_below + local_above = "
                             f"{self.local_below + self.local_above:g} must exceed the "
                             f"window 2 w = {2.0 * w:g} of quantity.w")

    def with_(self, **changes) -> Accuracy:
        """A copy with some fields changed (named ``"custom"`` unless a name is given; it
        keeps no ``configured`` spelling of the settings it was changed from)."""
        changes.setdefault("name", "custom")
        changes.setdefault("configured", None)
        return replace(self, **changes)

    def rtol_for(self, model: str) -> float:
        """ODE relative tolerance of a dynamics model ("3d", "3d-damped" or "2d") [-]."""
        return self.rtol_damped if model == MODEL_3D_DAMPED else self.rtol

    def to_dict(self) -> dict:
        """JSON-serialisable form (written into study attributes and CLI outputs)."""
        return {"name": self.name, "rtol": self.rtol, "rtol_damped": self.rtol_damped,
                "scan_step": self.scan_step, "local_step": self.local_step,
                "local_below": self.local_below, "local_above": self.local_above,
                "confirm": self.confirm, "rest_tilt": self.rest_tilt}


DEFAULT_UPPER = 20.0
"""Default highest normalized intensity searched, PGA/(g tan α) [-]: the one value of the
search bound (the library's ``upper=``, a configuration's ``search.upper``, the command
lines' ``--upper``; the default stripes reach it too). It lives here, beside the search's
other settings, because this module is light: the command line prints it in its help
without loading the search."""


FIELDS = ("name", "rtol", "rtol_damped", "scan_step", "local_step", "local_below",
          "local_above", "confirm", "rest_tilt")
"""The fields of :class:`Accuracy` a mapping may set."""


def _check_range(name: str, value, lo: float, hi: float, lower_closed: bool = False) -> None:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a number, got {value!r}") from None
    below = v < lo if lower_closed else v <= lo
    if isinstance(value, bool) or not math.isfinite(v) or below or v > hi:
        low = f">= {lo}" if lower_closed else f"> {lo}"
        raise ValueError(f"{name} must be {low} and <= {hi}, got {value!r}")


PRESETS: dict[str, Accuracy] = {
    "fast": Accuracy("fast", rtol=1e-6, rtol_damped=1e-5, scan_step=0.03, local_step=0.006,
                     configured="fast"),
    "default": Accuracy("default", rtol=1e-7, rtol_damped=1e-6, scan_step=0.02,
                        local_step=0.006, configured="default"),
    "precise": Accuracy("precise", rtol=1e-8, rtol_damped=1e-7, scan_step=0.01,
                        local_step=0.004, configured="precise"),
}
"""The named presets, from cheapest to most accurate (each spelled by its name)."""


STATED: dict[str, tuple[float, float]] = {"fast": (0.05, 0.83), "default": (0.05, 0.86),
                                          "precise": (0.05, 0.93)}
"""The accuracy a preset states for its answers, (e, q): a share q of its answers lie within
e (relative) of the converged I10 (docs/performance.md, "The trade";
``python -m benchmarks resolution`` measures it: the shares with two goals, the lower). The
one place the number lives: ``rocking verify``
(:func:`rocking.study.verify.answer_tolerance`), the verdicts' per-motion criterion
(:mod:`rocking.plot.criteria`) and the report read it from here. A preset without its own
entry is held to the ``default``'s."""
