"""rocking: seismic rocking of free-standing cylinders (3D, bounded) and blocks (2D).

Reproduces and extends Vassiliou, Burger, Egger, Bachmann, Broccardo & Stojadinović (2017),
"The three-dimensional behavior of inverted pendulum cylindrical structures during
earthquakes", Earthquake Engng Struct. Dyn. 46:2261–2280.
"""

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
]
