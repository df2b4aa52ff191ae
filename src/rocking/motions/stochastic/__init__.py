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

from rocking._lazy import lazy_exports

# Imported when first used (rocking._lazy): the workflow's check of a configuration reads one
# light module of this package (.recorded) while Snakemake plans, without numba and scipy.
_EXPORTS = {
    **dict.fromkeys(("GammaEnvelope", "alphas_from_physical", "physical_from_alphas"),
                    "envelope"),
    **dict.fromkeys(("RDKFit", "fit_component", "fit_rdk"), "fit"),
    "synthesize": "pairs",
    "RDKParams": "params",
    "ensemble_quality": "quality",
    "fit_spectrum": "spectrum_fit",
}

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
__all__ = sorted(_EXPORTS)
