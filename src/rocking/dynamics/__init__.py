"""Dynamics of rocking bodies: bodies, the compiled models and the public analyses.

:mod:`.bodies` (cylinder, block), :mod:`.result` (what an analysis returns), the models
:mod:`.cylinder3d` (undamped 3D), :mod:`.cylinder3d_damped` (3D on a contact spring–dashpot),
:mod:`.housner2d` (2D Housner), their integrators (:mod:`._rk`, :mod:`._rosenbrock`) and
:mod:`.analysis` (:func:`free_vibration`, :func:`ground_response`).
"""

from rocking._lazy import lazy_exports

_EXPORTS = {
    "Cylinder": "bodies",
    "Block": "bodies",
    "Response": "result",
    "Status": "result",
    "QuasiImpacts": "result",
    "free_vibration": "analysis",
    "ground_response": "analysis",
}

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
__all__ = list(_EXPORTS)
