"""One fragility: the censored lognormal fit of a study's answers (:mod:`.lognormal`), the
bootstrap over motions (:mod:`.bootstrap`), the one table type with what it was fitted in and
its one reader and writer (:mod:`.table`), the refit in any measure and component from each
motion's answers (:mod:`.refit`), the multiple-stripe fragility and the ensemble's exceedance
probability F(s) (:mod:`.stripes`) and the surface over R and tan α (:mod:`.surface`)."""

from rocking._lazy import lazy_exports

_EXPORTS = {
    "fit_lognormal": "lognormal",
    "LognormalFit": "lognormal",
    "read_bootstrap": "bootstrap",
    "read_fragilities": "table",
    "write_fragilities": "table",
    "Fragilities": "table",
    "refit_study": "refit",
    "fit_cells": "refit",
    "exceedance_table": "stripes",
    "jittered": "stripes",
    "FragilitySurface": "surface",
    "stripe_fragility": "stripes",
    "StripeFragility": "stripes",
    "fit_stripes": "stripes",
}

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
__all__ = list(_EXPORTS)
