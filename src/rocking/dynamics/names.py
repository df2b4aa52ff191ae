"""The dynamics models' names and the damped contact's default parameters.

Kept free of heavy imports: the command line shows them in its help, and the analysis modes
(:mod:`rocking.spectra.modes`) name their model, without loading numpy or the engine. The
models themselves, with every other per-model default, are the entries of
:data:`rocking.dynamics.models.MODELS`.
"""

from __future__ import annotations

MODEL_3D = "3d"
"""The undamped 3D rocking/wobbling cylinder on a rigid contact."""

MODEL_3D_DAMPED = "3d-damped"
"""The 3D cylinder on a contact spring–dashpot (frequency ωn, damping ratio ζ)."""

MODEL_2D = "2d"
"""The 2D Housner block (rocking in one plane, impacts with restitution)."""

MODEL_NAMES: tuple[str, ...] = (MODEL_3D, MODEL_3D_DAMPED, MODEL_2D)
"""Every model name, in the order of :data:`rocking.dynamics.models.MODELS`."""

DAMPED_OMEGA_N = 2000.0
"""Default contact spring frequency ωn of :data:`MODEL_3D_DAMPED` [rad/s], with
:data:`DAMPED_ZETA` one pair of :data:`PAPER_CONTACT_GRID`; ``damped.omega_n`` of the
configuration schema holds the same (tests/test_spec.py)."""

DAMPED_ZETA = 5.0
"""Default contact damping ratio ζ of :data:`MODEL_3D_DAMPED` [-] (``damped.zeta`` of the
configuration schema holds the same)."""

PAPER_CONTACT_GRID: tuple[tuple[float, float], ...] = tuple(
    (wn, z) for wn in (200.0, 2000.0) for z in (0.05, 0.5, 5.0, 50.0))
"""The paper's eight contact parameters (ωn [rad/s], ζ [-]) of the damped model (§3; the
paper's values, not tied to the defaults above): Fig 4 overlays them,
``python -m benchmarks damped`` measures the tolerance on them."""
