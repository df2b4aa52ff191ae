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

import importlib

# Each public name and the module that defines it, imported when first asked for: the
# workflow's check of a configuration reads one light module of this package
# (.recorded, a file of recorded parameters) while Snakemake plans a run, and the package
# must not load numba and scipy with it.
_WHERE = {
    **dict.fromkeys(("GammaEnvelope", "alphas_from_physical", "physical_from_alphas"),
                    "envelope"),
    **dict.fromkeys(("RDKFit", "fit_component", "fit_rdk"), "fit"),
    "synthesize": "pairs",
    "RDKParams": "params",
    "ensemble_quality": "quality",
    "fit_spectrum": "spectrum_fit",
}


def __getattr__(name: str):
    if name in _WHERE:
        value = getattr(importlib.import_module(f"{__name__}.{_WHERE[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


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
