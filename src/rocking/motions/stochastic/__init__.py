"""Rezaeian–Der Kiureghian stochastic ground-motion model: identification and simulation.

Modules: :mod:`.envelope` (gamma modulating function), :mod:`.filter` (time-varying filter,
normalized impulse-response band), :mod:`.params` (the six parameters of a component),
:mod:`.simulate` (time-domain and spectral discretizations), :mod:`.fit` (identification from
a record, both principal components), :mod:`.ensemble` (reproducible bidirectional ensembles).
"""

from .ensemble import synthesize
from .envelope import GammaEnvelope, alphas_from_physical, physical_from_alphas
from .fit import RDKFit, fit_component, fit_rdk
from .params import RDKParams

__all__ = [
    "GammaEnvelope",
    "RDKFit",
    "RDKParams",
    "alphas_from_physical",
    "fit_component",
    "fit_rdk",
    "physical_from_alphas",
    "synthesize",
]
