"""One fragility: the censored lognormal fit of a study's answers (:mod:`.lognormal`), the
bootstrap over motions (:mod:`.bootstrap`), the fragility table with what it was fitted in
(:mod:`.table`), the multiple-stripe fragility (:mod:`.stripes`) and the surface over R and
tan α (:mod:`.surface`)."""

from rocking._lazy import lazy_exports

_EXPORTS = {
    "fit_lognormal": "lognormal",
    "LognormalFit": "lognormal",
    "read_bootstrap": "bootstrap",
    "read_fragilities": "table",
    "FragilitySurface": "surface",
    "stripe_fragility": "stripes",
    "StripeFragility": "stripes",
    "fit_stripes": "stripes",
}

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
__all__ = list(_EXPORTS)
