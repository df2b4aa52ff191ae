"""Ground motions: records, principal axes, high-pass filters, intensity measures, response
spectra, Rezaeian–Der Kiureghian stochastic ensembles (:mod:`.stochastic`) and ensemble files.
"""

from rocking._lazy import lazy_exports

_EXPORTS = {
    "GroundMotion": "motion",
    "load_record": "catalogue",
    "read_record": "readers",
    "read_pair": "readers",
    "loma_prieta_pair": "catalogue",
    "to_principal_axes": "principal",
    "principal_angle": "principal",
    "rotate": "principal",
    "highpass_motion": "highpass",
    "brune_corner": "highpass",
    "pseudo_acceleration": "response_spectrum",
    "spectral_displacement": "response_spectrum",
    "intensity_measure": "measures",
    "load_ensemble": "ensemble_io",
    "save_ensemble": "ensemble_io",
}

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
__all__ = list(_EXPORTS)
