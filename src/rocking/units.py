"""Units and descriptions of every quantity the project writes (stores, NetCDF, CSV, JSON).

One table, :data:`QUANTITIES`, gives each output name its CF ``units`` (UDUNITS-2 strings:
``"1"`` for dimensionless numbers, labels and flags; ``"gravity"`` for accelerations in
g = 9.80665 m/s²), the unit as written in CSV headers (``"-"``, ``"g"``, ``"m/s2"``) and a
``long_name``. :func:`attrs` gives the xarray attributes, :func:`header` a CSV column title
``name [unit]``. Intensity measures keep the field's names: ``PGA`` [g], ``SA(T)`` [g],
Arias intensity ``Ia`` [m/s].

The normalized intensity PGA/(g tan α) is dimensionless; in CSV headers its unit is written
``g tan(alpha)`` (PGA measured in units of g·tan α), so a table says what the number is.
"""

from __future__ import annotations

from collections.abc import Iterable

__all__ = ["CSV_FLOAT_FORMAT", "QUANTITIES", "attrs", "header", "headers", "read_table",
           "set_attrs", "strip_units"]

CSV_FLOAT_FORMAT = "%.10g"
"""Floats of every CSV the project writes: 10 significant digits. A double's 17th digit is
the arithmetic's noise (0.20812080200000002 for 0.208120802); the JSON, netCDF and zarr
outputs keep every bit."""

# name: (CF units, CSV unit, long_name)
QUANTITIES: dict[str, tuple[str, str, str]] = {
    # labels and grid coordinates
    "mode": ("1", "", "analysis mode: dynamics model and excitation (3d, 3d-damped, 3d-x, 3d-y, "
             "2d-x, 2d-y)"),
    "limit_state": ("1", "", "performance limit state (overturning, tilt:r: theta > r alpha, "
                    "sliding:mu: mu_required_max > mu)"),
    "motion": ("1", "", "ground-motion name"),
    "tan_alpha": ("1", "-", "slenderness tan(alpha) = b/h"),
    "R": ("m", "m", "semi-diagonal R = sqrt(b^2 + h^2)"),
    "intensity": ("1", "g tan(alpha)", "normalized intensity PGA/(g tan(alpha))"),
    "pga_g": ("gravity", "g", "vector peak ground acceleration PGA"),
    # spectra store and critical-intensity tables
    "pga_crit": ("1", "g tan(alpha)",
                 "critical intensity PGA/(g tan(alpha)): the quantity's answer (I_p = "
                 "inf{s: P(s) >= p} by default, or the first exceedance on the scan grid)"),
    "pga_crit_g": ("gravity", "g", "critical PGA: the quantity's answer in g"),
    "quantity": ("1", "", "what the critical intensity is: exceedance_quantile (I_p) or "
                 "first_exceedance (on the scan grid)"),
    "quantity_p": ("1", "-", "exceedance share p of I_p = inf{s: P(s) >= p}"),
    "quantity_w": ("1", "-", "half-width w of the window of P(s) in ln s"),
    "i50": ("1", "g tan(alpha)", "I_0.5 = inf{s: P(s) >= 0.5} from the same local samples"),
    "first_exceedance": ("1", "g tan(alpha)", "smallest exceeding intensity on the scan "
                         "grid (step scan_step)"),
    "scan_step": ("1", "-", "relative step of the search's scan grid"),
    "plateau": ("1", "", "P(s) rises near p without crossing it more than a window below "
                "the answer: I_p is ill-conditioned there"),
    "not_reached": ("1", "", "limit state not exceeded up to the search bound"),
    "non_monotonic": ("1", "", "exceeded at some intensity, not at a higher one"),
    "failed": ("1", "", "an analysis failed even after a retry"),
    "slides": ("1", "", "an analysis up to the answer that did not overturn needed more "
               "friction than mu while in contact (empty: no mu given)"),
    "lifts_off": ("1", "", "an analysis up to the answer had a normal force N <= 0 (empty: "
                  "not monitored, no mu and no sliding goal)"),
    "mu": ("1", "-", "support friction coefficient the slides flag compares with"),
    "n_analyses": ("1", "", "analyses run by the search (all limit states together)"),
    "done": ("1", "", "chunk computed and written"),
    "requested": ("1", "", "some run of the study asks for this cell (false: not computed)"),
    "bracket_lo": ("1", "g tan(alpha)", "highest stripe with no motion exceeding, below every "
                   "exceeding one (the stripe median lies above it)"),
    "bracket_hi": ("1", "g tan(alpha)", "lowest stripe with every motion exceeding, above every "
                   "non-exceeding one (the stripe median lies below it)"),
    "lower": ("1", "g tan(alpha)", "uplift intensity (start of the search)"),
    "upper": ("1", "g tan(alpha)", "highest intensity searched"),
    "censoring_bound": ("1", "g tan(alpha)", "search bound the motions not reached are "
                        "censored at in the fragility's fit"),
    "accuracy": ("1", "", "accuracy preset of the search"),
    # tilt map
    "theta_max_over_alpha": ("1", "-", "peak tilt theta_max/alpha (pi/(2 alpha) if overturned)"),
    "overturned": ("1", "", "the body overturned"),
    # ensemble statistics
    "mean": ("1", "g tan(alpha)", "mean over motions of the critical PGA/(g tan(alpha)) "
             "(of the per-motion I_p under the default quantity)"),
    "std": ("1", "g tan(alpha)", "sample std (ddof 1) over motions of PGA/(g tan(alpha))"),
    "median": ("1", "g tan(alpha)", "median of PGA/(g tan(alpha))"),
    "mean_pga_g": ("gravity", "g", "mean over motions of the critical PGA"),
    "count": ("1", "", "motions whose limit state was reached"),
    "n_not_reached": ("1", "", "motions left out: limit state not reached"),
    "n_plateau": ("1", "", "motions whose answer is flagged plateau (I_p ill-conditioned)"),
    "n_slides": ("1", "", "motions whose analyses up to the answer needed more friction "
                 "than mu"),
    "n_lifts_off": ("1", "", "motions whose analyses up to the answer had N < 0"),
    "median_all": ("1", "g tan(alpha)", "median over all motions, those not reached counted "
                   "above the search bound (Kaplan-Meier; NaN: above the bound)"),
    "censoring": ("1", "", "how the statistics treat motions not reached at the search bound"),
    # fragility and line fits
    "median_pga_g": ("gravity", "g", "median critical PGA of the lognormal fragility"),
    "beta": ("1", "-", "lognormal dispersion beta (std of ln PGA)"),
    "log_likelihood": ("1", "-", "maximized log-likelihood of the lognormal fit"),
    "n": ("1", "", "motions used"),
    "n_censored": ("1", "", "motions right-censored (not reached)"),
    "status": ("1", "", "fit status (ok, median-at-bound, too-few-observed, no-spread, "
                          "not-computed)"),
    "slope": ("m-1", "1/m", "slope of the mean PGA/(g tan(alpha)) against R"),
    "intercept": ("1", "g tan(alpha)", "intercept of the mean PGA/(g tan(alpha)) at R = 0"),
    "r_squared": ("1", "-", "coefficient of determination of the line fit"),
    # multiple-stripe fragility
    "n_exceeding": ("1", "", "motions exceeding the limit state at the stripe"),
    "n_motions": ("1", "", "motions analysed at the stripe"),
    "fraction": ("1", "-", "share of the analysed motions exceeding the limit state"),
    "median_lo": ("1", "g tan(alpha)", "lower end of the 95 % interval of the median"),
    "median_hi": ("1", "g tan(alpha)", "upper end of the 95 % interval of the median"),
    "beta_lo": ("1", "-", "lower end of the 95 % interval of beta"),
    "beta_hi": ("1", "-", "upper end of the 95 % interval of beta"),
    "reason": ("1", "", "why a fit has no finite maximum or is flagged"),
    # ground motions
    "ax": ("m s-2", "m/s2", "ground acceleration along x"),
    "ay": ("m s-2", "m/s2", "ground acceleration along y"),
    "az": ("m s-2", "m/s2", "vertical ground acceleration, positive up"),
    "has_az": ("1", "", "1 where the motion carries a vertical component (az), 0 where not"),
    "dt": ("s", "s", "time step"),
    "npts": ("1", "", "samples of the motion (the rest of the row is padding)"),
    "metadata": ("1", "", "provenance of the motion as JSON text"),
    "source_record": ("1", "", "recorded pair the motion comes from"),
    "kind": ("1", "", "record (processed) or synthetic (RDK pair fitted to a record)"),
    "processing": ("1", "", "processing of the motion, in order"),
    "rotation_deg": ("degree", "deg", "rotation applied to the recorded axes"),
    "highpass_fc_hz": ("Hz", "Hz", "high-pass corner frequency (NaN: none)"),
    "padding_s": ("s", "s", "zero padding added by the processing"),
    "duration_s": ("s", "s", "duration of the motion"),
    "PGA": ("gravity", "g", "vector peak ground acceleration PGA = max sqrt(ax^2 + ay^2)"),
    "Ia_x": ("m s-1", "m/s", "Arias intensity of the x component"),
    "Ia_y": ("m s-1", "m/s", "Arias intensity of the y component"),
    "SA": ("gravity", "g", "5 %-damped pseudo-spectral acceleration SA(T)"),
    # time histories of one analysis
    "t": ("s", "s", "time"),
    "theta": ("rad", "rad", "tilt theta"),
    "theta_dot": ("rad s-1", "rad/s", "tilt rate"),
    "phi": ("rad", "rad", "rolling angle of the contact point phi"),
    "phi_dot": ("rad s-1", "rad/s", "rolling rate of the contact point"),
    "w": ("m", "m", "contact-spring displacement"),
    "w_dot": ("m s-1", "m/s", "contact-spring velocity"),
    "contact_force": ("N kg-1", "N/kg", "normal contact force per unit mass of the body"),
    "normal_force": ("1", "mg", "normal force the support supplies, in weights (< 0: lift-off)"),
    "mu_required": ("1", "-", "friction coefficient the body needs |F|/N (inf: N <= 0)"),
    # risk (rocking.risk): a fragility under a site's hazard curve
    "maf": ("year-1", "1/yr", "mean annual frequency of exceeding the limit state"),
    "return_period": ("year", "yr", "return period 1/maf of exceeding the limit state"),
    "p_50yr": ("1", "-", "probability of exceeding the limit state in 50 years (Poisson)"),
    "share_extrapolated": ("1", "-",
                           "share of maf resting on the hazard curve's extrapolated tail"),
    "share_below_first": ("1", "-", "share of maf from below the hazard's first level (its "
                                    "first log-log slope extrapolated)"),
    "lambda_p05": ("year-1", "1/yr", "5th percentile of maf over bootstrap resamples of the "
                                     "motions"),
    "lambda_p95": ("year-1", "1/yr", "95th percentile of maf over bootstrap resamples of the "
                                     "motions"),
    "lambda_lo": ("year-1", "1/yr", "maf implied at least by the bracketing stripes (no fit)"),
    "lambda_hi": ("year-1", "1/yr", "maf implied at most by the bracketing stripes (no fit)"),
    "median_im": ("gravity", "g", "median capacity in the row's intensity measure"),
    # bootstrap of a fragility over the motions
    "median_p05": ("gravity", "g", "5th percentile of the median over bootstrap resamples"),
    "median_p95": ("gravity", "g", "95th percentile of the median over bootstrap resamples"),
    "bootstrap_fitted": ("1", "", "bootstrap resamples with a fit"),
}
"""Output name → (CF units, unit in CSV headers, long_name)."""


def attrs(name: str, **extra: str) -> dict[str, str]:
    """CF attributes ``{"units", "long_name"}`` of an output quantity (KeyError if unknown)."""
    units, _, long_name = QUANTITIES[name]
    return {"units": units, "long_name": long_name, **extra}


def header(name: str) -> str:
    """CSV column title: ``"R [m]"``; labels and flags keep their bare name."""
    unit = QUANTITIES[name][1] if name in QUANTITIES else ""
    return f"{name} [{unit}]" if unit else name


def headers(columns: Iterable[str]) -> dict[str, str]:
    """Column renaming ``{name: header(name)}`` for :meth:`pandas.DataFrame.rename`."""
    return {c: header(c) for c in columns}


def strip_units(column: str) -> str:
    """The bare name of a CSV column title (``"R [m]"`` → ``"R"``)."""
    return column.split(" [", 1)[0]


def set_attrs(ds):
    """Give every variable and coordinate of an xarray Dataset its CF attributes (in place).

    Names not in :data:`QUANTITIES` are left as they are. Returns ``ds``.
    """
    for name in ds.variables:
        if str(name) in QUANTITIES:
            ds[name].attrs.update(attrs(str(name)))
    return ds


def read_table(path):
    """A CSV written by the project as a pandas DataFrame with bare column names."""
    import pandas as pd

    return pd.read_csv(path).rename(columns=strip_units)
