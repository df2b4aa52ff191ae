"""From fragility to risk: hazard curves, mean annual frequencies, exports to risk tools.

:mod:`.hazard` (:class:`HazardCurve`: PGA or Sa(T), from OpenQuake CSVs, tables or a power
law), :mod:`.annual_frequency` (λ_LS of a lognormal fragility under a hazard curve, and its
interval over bootstrap resamples), :mod:`.risk_table` (the risk table of a study: λ, return
period, 50-year probability per requested fragility), :mod:`.nrml` (OpenQuake NRML 0.5
fragility model), :mod:`.pelicun` (pelicun / FEMA P-58 damage model CSV), :mod:`.exports`
(the files of the workflow's risk rules); :mod:`.inventory` (a CSV of columns, checked, with
their hazard sites), :mod:`.portfolio` (``portfolio.csv``: every column's fragility and λ,
ranked) and :mod:`.exposure` (an inventory as OpenQuake's exposure model and pelicun's
assets). The fragilities themselves are :mod:`rocking.fragility`'s, the report's risk section
:mod:`rocking.report.risk`'s.
"""

from rocking._lazy import lazy_exports

_EXPORTS = {
    "HazardCurve": "hazard",
    "parse_hazard": "hazard",
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
}

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
__all__ = list(_EXPORTS)
