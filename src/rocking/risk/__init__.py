"""From fragility to risk: hazard curves, mean annual frequencies, exports to risk tools.

:mod:`.hazard` (:class:`HazardCurve`: PGA or Sa(T) in a stated component, from OpenQuake
CSVs of one or many sites, tables or a power law; formats recognized before parsing, files
parsed once), :mod:`.reconcile` (the one place a fragility is brought into a hazard's
measure, component and unit, or refused), :mod:`.annual_frequency` (λ_LS of a lognormal
fragility under a hazard curve, and its interval over bootstrap resamples), :mod:`.risk_table`
(the risk table), :mod:`.nrml` (OpenQuake NRML 0.5 fragility model), :mod:`.pelicun`
(pelicun / FEMA P-58 damage model CSV), :mod:`.exports` (a study's risk outputs);
:mod:`.inventory` (a CSV of columns as people keep it, checked, with their hazard sites),
:mod:`.portfolio` (``portfolio.csv``: every column's fragility and λ, ranked, and the site's
answer) and :mod:`.exposure` (an inventory as OpenQuake's exposure model and pelicun's
assets). The fragilities come from :mod:`rocking.fragility`.
"""

from rocking._lazy import lazy_exports

_EXPORTS = {
    "HazardCurve": "hazard",
    "parse_hazard": "hazard",
    "read_hazard_file": "hazard",
    "reconcile": "reconcile",
    "mean_annual_frequency": "annual_frequency",
    "annual_frequency_parts": "annual_frequency",
    "annual_frequency_interval": "annual_frequency",
    "mean_annual_frequencies": "annual_frequency",
    "probability_in": "annual_frequency",
    "write_nrml": "nrml",
    "write_pelicun_csv": "pelicun",
    "risk_table": "risk_table",
    "risk_tables": "risk_table",
    "write_fragility_exports": "exports",
    "write_risk_outputs": "exports",
    "write_exposure": "exposure",
    "read_inventory": "inventory",
    "read_hazard_sites": "inventory",
    "portfolio_table": "portfolio",
    "site_portfolio": "portfolio",
}

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
__all__ = list(_EXPORTS)
