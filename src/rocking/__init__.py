"""rocking: seismic rocking of free-standing cylinders (3D, bounded) and blocks (2D).

Reproduces and extends Vassiliou, Burger, Egger, Bachmann, Broccardo & Stojadinović (2017),
"The three-dimensional behavior of inverted pendulum cylindrical structures during
earthquakes", Earthquake Engng Struct. Dyn. 46:2261–2280.
"""

from .analysis import free_vibration, ground_response
from .bodies import Block, Cylinder
from .constants import G
from .motion import GroundMotion
from .result import QuasiImpacts, Response, Status

__version__ = "0.1.0"

__all__ = [
    "G",
    "Block",
    "Cylinder",
    "GroundMotion",
    "QuasiImpacts",
    "Response",
    "Status",
    "__version__",
    "free_vibration", "ground_response",
]

# Stochastic ground motions (Rezaeian–Der Kiureghian): identification and simulation.
from .stochastic import RDKFit, RDKParams, fit_rdk, synthesize  # noqa: E402

__all__ += ["RDKFit", "RDKParams", "fit_rdk", "synthesize"]

# Seismic performance rocking spectra: limit states, accuracy presets, critical intensities.
from .accuracy import PRESETS as ACCURACY_PRESETS  # noqa: E402
from .accuracy import Accuracy, get_accuracy  # noqa: E402
from .limit_states import DEFAULT_LIMIT_STATES, LimitState, parse_limit_states  # noqa: E402
from .performance import (  # noqa: E402
    CriticalResult,
    critical_intensity,
    critical_intensity_batch,
    tilt_map,
)

__all__ += [
    "ACCURACY_PRESETS",
    "Accuracy",
    "CriticalResult",
    "DEFAULT_LIMIT_STATES",
    "LimitState",
    "critical_intensity",
    "critical_intensity_batch",
    "get_accuracy",
    "parse_limit_states",
    "tilt_map",
]

# Ground motions: records, principal axes, high-pass filters, response spectra, ensemble files.
from .ensemble_io import load_ensemble, save_ensemble  # noqa: E402
from .highpass import brune_corner, highpass_motion  # noqa: E402
from .principal import principal_angle, rotate, to_principal_axes  # noqa: E402
from .records import load_record, loma_prieta_pair, read_pair, read_record  # noqa: E402
from .response_spectrum import pseudo_acceleration, spectral_displacement  # noqa: E402

__all__ += [
    "brune_corner",
    "highpass_motion",
    "load_ensemble",
    "load_record",
    "loma_prieta_pair",
    "principal_angle",
    "pseudo_acceleration",
    "read_pair",
    "read_record",
    "rotate",
    "save_ensemble",
    "spectral_displacement",
    "to_principal_axes",
]
