"""rocking: seismic rocking of free-standing cylinders (3D, bounded) and blocks (2D).

Reproduces and extends Vassiliou, Burger, Egger, Bachmann, Broccardo & Stojadinović (2017),
"The three-dimensional behavior of inverted pendulum cylindrical structures during
earthquakes", Earthquake Engng Struct. Dyn. 46:2261–2280.

Subpackages, from the bottom up: :mod:`rocking.motions` (records, principal axes, filters,
stochastic ensembles), :mod:`rocking.dynamics` (bodies, models, analyses; it takes a
:class:`GroundMotion`),
:mod:`rocking.spectra` (limit states, critical-intensity search, fragility),
:mod:`rocking.risk` (hazard curves, mean annual frequency, NRML and pelicun exports),
:mod:`rocking.study` (zarr store, Dask cluster, aggregates) and :mod:`rocking.plot` (the
figures and the report, which read the study's outputs). The names below are the public API;
each is imported on first use.
"""

from rocking._lazy import lazy_exports
from rocking.constants import G

__version__ = "0.1.0"

_EXPORTS = {
    # dynamics
    "Cylinder": "dynamics.bodies",
    "Block": "dynamics.bodies",
    "Response": "dynamics.result",
    "Status": "dynamics.result",
    "QuasiImpacts": "dynamics.result",
    "free_vibration": "dynamics.analysis",
    "ground_response": "dynamics.analysis",
    # ground motions
    "GroundMotion": "motions.motion",
    "load_motion": "motions.source",
    "process_motion": "motions.source",
    "load_record": "motions.catalogue",
    "read_record": "motions.readers",
    "read_pair": "motions.readers",
    "loma_prieta_pair": "motions.catalogue",
    "to_principal_axes": "motions.principal",
    "principal_angle": "motions.principal",
    "rotate": "motions.principal",
    "highpass_motion": "motions.highpass",
    "brune_corner": "motions.highpass",
    "pseudo_acceleration": "motions.response_spectrum",
    "spectral_displacement": "motions.response_spectrum",
    "load_ensemble": "motions.ensemble_io",
    "intensity_measure": "motions.measures",
    "save_ensemble": "motions.ensemble_io",
    "RDKFit": "motions.stochastic",
    "RDKParams": "motions.stochastic",
    "fit_rdk": "motions.stochastic",
    "synthesize": "motions.stochastic",
    # performance spectra
    "LimitState": "spectra.limit_states",
    "DEFAULT_LIMIT_STATES": "spectra.limit_states",
    "parse_limit_states": "spectra.limit_states",
    "Accuracy": "spectra.accuracy",
    "CriticalResult": "spectra.search",
    "critical_intensity": "spectra.critical",
    "critical_intensity_batch": "spectra.critical",
    "tilt_map": "spectra.tilt_map",
    "match_limit_state": "spectra.limit_states",
    "stripe_fragility": "fragility.stripes",
    "fit_lognormal": "fragility.lognormal",
    "LognormalFit": "fragility.lognormal",
    "StripeFragility": "fragility.stripes",
    # study outputs
    "select": "store.select",
    # risk: hazard curves and mean annual frequencies
    "HazardCurve": "risk.hazard",
    "mean_annual_frequency": "risk.annual_frequency",
}

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
__all__ = ["G", "__version__", *_EXPORTS]
