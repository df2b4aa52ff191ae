"""Analysis modes of the spectra and tilt maps: which model, under which excitation.

Kept free of heavy imports: the command line lists the modes in its help without loading
the dynamics engine.
"""

from __future__ import annotations

MODES: dict[str, tuple[str, str | None]] = {
    "3d": ("3d", None),
    "3d-damped": ("3d-damped", None),
    "2d-x": ("2d", "x"),
    "2d-y": ("2d", "y"),
}
"""Mode → (dynamics model, component exciting the 2D model or None for the pair)."""


def check_mode(mode: str) -> str:
    """Return ``mode`` if it is one of :data:`MODES`, else raise ValueError naming it."""
    if mode not in MODES:
        raise ValueError(f"mode must be one of {list(MODES)}, got {mode!r}")
    return mode
