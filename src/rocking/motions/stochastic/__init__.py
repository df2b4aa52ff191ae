"""Rezaeian–Der Kiureghian stochastic ground-motion model: identification and simulation.

Modules: :mod:`.envelope` (gamma modulating function), :mod:`.filter` (time-varying filter,
optional low-frequency filter, normalized impulse-response band, unit-variance spectrum),
:mod:`.params` (the parameters of a component, with the extension of the spectrum-matched
fit), :mod:`.discretize` (time-domain and spectral discretizations), :mod:`.fit`
(identification from a record, both principal components; count-based or spectrum-matched),
:mod:`.spectrum_fit` (the spectrum-matched identification), :mod:`.quality` (how well an
ensemble's elastic spectrum matches its record's), :mod:`.pairs` (reproducible
bidirectional ensembles of synthetic pairs).
"""

from rocking.motions.stochastic.envelope import (
    GammaEnvelope,
    alphas_from_physical,
    physical_from_alphas,
)
from rocking.motions.stochastic.fit import RDKFit, fit_component, fit_rdk
from rocking.motions.stochastic.pairs import synthesize
from rocking.motions.stochastic.params import RDKParams
from rocking.motions.stochastic.quality import ensemble_quality
from rocking.motions.stochastic.spectrum_fit import fit_spectrum

__all__ = [
    "GammaEnvelope",
    "RDKFit",
    "RDKParams",
    "alphas_from_physical",
    "ensemble_quality",
    "fit_component",
    "fit_rdk",
    "fit_spectrum",
    "physical_from_alphas",
    "synthesize",
]
