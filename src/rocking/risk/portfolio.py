"""Every column of an inventory under its site's hazard: ``portfolio.csv``.

From a :class:`rocking.risk.surface.FragilitySurface` (the study's fragility over R and tan α),
an inventory (:mod:`rocking.risk.inventory`) and a hazard file of one or many sites,
:func:`portfolio_table` gives, per column and limit state, the interpolated lognormal
fragility with its bootstrap interval and its interpolation error, the mean annual frequency
λ with its 90 % interval, the return period, the probability in 50 years, the hazard site
used and its distance, and the rank of the column among the inventory.

``portfolio.csv`` (long format: one row per column and limit state; the names are stable,
other tools read them, e.g. :mod:`rocking.risk.exposure`):

=====================  ======  ==========================================================
column                 unit    meaning
=====================  ======  ==========================================================
id                     –       the inventory's id of the column
lon, lat               deg     the column's position as the inventory gives it (NaN: none)
site                   –       the inventory's ``site`` (a hazard ``custom_site_id``; '')
height, diameter       m       as the inventory gives them (NaN where it gave R, tan α)
R                      m       semi-diagonal √(b² + h²)
tan_alpha              –       slenderness b/h
mu                     –       the inventory's support friction (NaN: not given; carried
                               only, the surface is the study's, no sliding check)
mode                   –       the surface's analysis mode (``3d``)
limit_state            –       ``overturning``, ``tilt:1/3`` ... (the study's names)
fragility              –       ``first_exceedance`` (the study's fragility.csv)
measure                –       ``pga`` (vector peak PGA, as the study's)
median                 g       median PGA capacity θ of the interpolated lognormal
median_p05, median_p95 g       its 90 % interval over the bootstrap resamples of the motions
beta                   –       dispersion β (std of ln capacity)
beta_p05, beta_p95     –       its 90 % interval over the resamples
interp_error           –       interpolation error of ln θ: the largest leave-one-out error
                               of the surface's mode and limit state (a factor e^±this)
extrapolated           –       True only when the user allowed columns beyond the grid
lambda                 1/yr    mean annual frequency λ of the limit state
lambda_p05, lambda_p95 1/yr    its 90 % interval over the resamples
return_period          yr      1/λ
p_50yr                 –       probability of at least one exceedance in 50 years (Poisson)
hazard_site            –       the hazard file's site used (id or row)
hazard_lon, hazard_lat deg     its position (NaN for a table or a power law)
hazard_distance_km     km      great-circle distance from the column to it (NaN: no lon/lat)
rank                   –       1 = the largest λ of that limit state in the inventory
=====================  ======  ==========================================================
"""
