"""Seismic performance rocking spectra: limit states, the quantity answered (:mod:`.quantity`),
accuracy presets, the critical-intensity search (:mod:`.search`) bound to the dynamics
(:mod:`.critical`), the Fig 7 tilt map (:mod:`.tilt_map`).
"""

from rocking._lazy import lazy_exports

_EXPORTS = {
    "LimitState": "limit_states",
    "DEFAULT_LIMIT_STATES": "limit_states",
    "parse_limit_states": "limit_states",
    "Accuracy": "accuracy",
    "Quantity": "quantity",
    "local_exceedance": "quantity",
    "exceedance_quantile": "quantity",
    "CriticalResult": "search",
    "search_critical": "search",
    "critical_intensity": "critical",
    "critical_intensity_batch": "critical",
    "MODES": "critical",
    "tilt_map": "tilt_map",
}

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
__all__ = list(_EXPORTS)
