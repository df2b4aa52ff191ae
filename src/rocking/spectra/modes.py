"""Analysis modes of the spectra and tilt maps: which model, under which excitation.

A mode's name is its own constant (``MODE_*``), distinct from the name of the dynamics model
it runs (:mod:`rocking.dynamics.names`, ``MODEL_*``) even where the two spell the same
("3d-damped"). Kept free of heavy imports: the command line lists the modes in its help
without loading the dynamics engine.
"""

from __future__ import annotations

from rocking.dynamics.names import MODEL_2D, MODEL_3D, MODEL_3D_DAMPED

MODE_3D = "3d"
"""The undamped 3D rocking/wobbling cylinder under both components."""

MODE_3D_DAMPED = "3d-damped"
"""The 3D cylinder on a damped contact (spring ωn, damping ratio ζ) under both components."""

MODE_2D_X = "2d-x"
"""The 2D Housner block under the x (major principal axis) component alone."""

MODE_2D_Y = "2d-y"
"""The 2D Housner block under the y (minor principal axis) component alone."""

PLANAR_MODES: tuple[str, ...] = (MODE_2D_X, MODE_2D_Y)
"""The 2D modes, one per component."""

MODES: dict[str, tuple[str, str | None]] = {
    MODE_3D: (MODEL_3D, None),
    MODE_3D_DAMPED: (MODEL_3D_DAMPED, None),
    MODE_2D_X: (MODEL_2D, "x"),
    MODE_2D_Y: (MODEL_2D, "y"),
}
"""Mode → (dynamics model, component exciting the 2D model or None for the pair)."""


def is_damped(mode: str) -> bool:
    """Whether ``mode`` runs the damped contact model (which takes ωn and ζ)."""
    return MODES[check_mode(mode)][0] == MODEL_3D_DAMPED


def check_mode(mode: str) -> str:
    """Return ``mode`` if it is one of :data:`MODES`, else raise ValueError naming it."""
    if mode not in MODES:
        raise ValueError(f"mode must be one of {list(MODES)}, got {mode!r}")
    return mode
