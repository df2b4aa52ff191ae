"""Analysis modes of the spectra and tilt maps: which model, under which excitation.

A mode's name is its own constant (``MODE_*``), distinct from the name of the dynamics model
it runs (:mod:`rocking.dynamics.names`, ``MODEL_*``) even where the two spell the same
("3d-damped"). Kept free of heavy imports: the command line lists the modes in its help
without loading the dynamics engine.

Under one component (§5.4, "unidirectional excitation") the paper runs "the same undamped 3D
cylinder model" as under both; Housner's 2D block is a further comparator here. Planar motion
of the 3D model is unstable (§2.4) and exactly planar motion reaches θ = 0, where the model is
undefined, so the 3D modes under one component start every uplift with a small spin
:data:`UNIDIRECTIONAL_SPIN` (docs/models.md, "The 3D model under one component").
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

from rocking.dynamics.names import MODEL_2D, MODEL_3D, MODEL_3D_DAMPED

if TYPE_CHECKING:
    from rocking.motions.motion import GroundMotion

MODE_3D = "3d"
"""The undamped 3D rocking/wobbling cylinder under both components."""

MODE_3D_DAMPED = "3d-damped"
"""The 3D cylinder on a damped contact (spring ωn, damping ratio ζ) under both components."""

MODE_3D_X = "3d-x"
"""The undamped 3D cylinder under the x (major principal axis) component alone (the paper's
unidirectional excitation, §5.4)."""

MODE_3D_Y = "3d-y"
"""The undamped 3D cylinder under the y (minor principal axis) component alone."""

MODE_2D_X = "2d-x"
"""The 2D Housner block under the x (major principal axis) component alone."""

MODE_2D_Y = "2d-y"
"""The 2D Housner block under the y (minor principal axis) component alone."""

PLANAR_MODES: tuple[str, ...] = (MODE_2D_X, MODE_2D_Y)
"""The 2D modes, one per component."""

UNIDIRECTIONAL_MODES: tuple[str, ...] = (MODE_3D_X, MODE_3D_Y)
"""The undamped 3D model under one component, one mode per component: the paper's own
comparator of Fig 12."""

ONE_COMPONENT_MODES: tuple[str, ...] = UNIDIRECTIONAL_MODES + PLANAR_MODES
"""Every mode excited by one component of the pair."""

UNIDIRECTIONAL_SPIN = 1e-4
"""Spin φ̇ given to the 3D model at each uplift under one component [rad/s].

Inside the range where the answers do not depend on it (``python -m benchmarks
unidirectional``, docs/models.md "The 3D model under one component"): from 1e-8 to 1e-2 rad/s
no spin moves the critical intensities systematically, and single answers move as often as
on the mirrored motion. Smaller spins let the first quasi-impact dive below 1e-16 rad, shorter
than the driver's smallest step: of 96 analyses on El Centro and Corralitos 51 fail at 1e-10
rad/s, 5 at 1e-8, none from 1e-6; the damped model dives deeper (6 fail at 1e-6, none at
1e-4). Larger ones, above :data:`rocking.dynamics.analysis.MAX_UPLIFT_SPIN` of the wobbling
rate at uplift (about 1.6 rad/s at R = 6 m), are refused: they start the body wobbling."""


class Mode(NamedTuple):
    """A mode: the dynamics model and how the ground excites it.

    Attributes
    ----------
    model : str
        The dynamics model (``MODEL_*``).
    component : str or None
        ``"x"`` or ``"y"``: the one component exciting the model (placed on x,
        ``GroundMotion.component``); None: the pair.
    spin : float
        Spin φ̇ at each uplift [rad/s] (0: none; the 3D model under one component).
    """

    model: str
    component: str | None
    spin: float = 0.0


MODES: dict[str, Mode] = {
    MODE_3D: Mode(MODEL_3D, None),
    MODE_3D_DAMPED: Mode(MODEL_3D_DAMPED, None),
    MODE_3D_X: Mode(MODEL_3D, "x", UNIDIRECTIONAL_SPIN),
    MODE_3D_Y: Mode(MODEL_3D, "y", UNIDIRECTIONAL_SPIN),
    MODE_2D_X: Mode(MODEL_2D, "x"),
    MODE_2D_Y: Mode(MODEL_2D, "y"),
}
"""Mode → (dynamics model, component exciting it or None for the pair, spin at uplift)."""


def is_damped(mode: str) -> bool:
    """Whether ``mode`` runs the damped contact model (which takes ωn and ζ)."""
    return MODES[check_mode(mode)].model == MODEL_3D_DAMPED


def check_mode(mode: str) -> str:
    """Return ``mode`` if it is one of :data:`MODES`, else raise ValueError naming it."""
    if mode not in MODES:
        raise ValueError(f"mode must be one of {list(MODES)}, got {mode!r}")
    return mode


def excitation(mode: str, motion: GroundMotion,
               spin: float | None = None) -> tuple[GroundMotion, dict[str, float]]:
    """The motion ``mode``'s model is run on, and the keyword arguments of
    :func:`rocking.dynamics.analysis.ground_response` that complete its excitation.

    ``spin`` [rad/s] overrides the mode's :attr:`Mode.spin` (3D modes under one component
    only; checked by ``ground_response``). A 3D mode under one component needs the pair (its
    intensity is the pair's vector PGA, §5.4) with a live component: one line naming the
    record and the mode otherwise, before any analysis.
    """
    entry = MODES[check_mode(mode)]
    if spin is not None and not entry.spin:
        raise ValueError(f"phi_dot0 (the spin at uplift) applies to the modes "
                         f"{list(UNIDIRECTIONAL_MODES)}, not to mode {mode!r}, got {spin!r}")
    if entry.component is None:
        return motion, {}
    one = motion.component(entry.component)
    if entry.model == MODEL_2D:
        return one, {}
    for which in (entry.component, "y" if entry.component == "x" else "x"):
        if not (motion.ax if which == "x" else motion.ay).any():
            raise ValueError(
                f"motion {motion.name!r} has no {which} component (all zero), mode {mode!r} "
                f"needs both: the {entry.component} component excites it and the pair's "
                "vector PGA is its intensity (§5.4); give the record's two components")
    return one, {"phi_dot0": entry.spin if spin is None else spin}
