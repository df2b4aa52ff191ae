"""Every column of an inventory under its site's hazard: ``portfolio.csv``.

From a :class:`rocking.fragility.surface.FragilitySurface` (the study's fragility over R and tan α),
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
                               only and said to be unused: the surface is the study's)
mode                   –       the surface's analysis mode (``3d``)
limit_state            –       ``overturning``, ``tilt:1/3`` ... (the study's names)
fragility              –       ``critical_intensity`` (the study's fragility.csv)
measure                –       the hazard's measure (``pga``, ``sa:1.0``): the surface's
component              –       the hazard's horizontal component, the surface's too
                               (refitted there, :func:`rocking.risk.reconcile.
                               reconcile_surface`)
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
row                    –       the column's row in the inventory as a spreadsheet numbers
                               it (the header is row 1)
rank                   –       1 = the largest λ of that limit state in the inventory
=====================  ======  ==========================================================

The inventory's further columns follow, untouched. ``portfolio_site.csv`` gives the site's
answer per limit state (:func:`site_answer`): the expected number of columns reaching it per
year, Σλ, with its interval, and the bounds on the rate of "at least one" (max λ to Σλ).

The λ of each column is the exact integral of its lognormal against its site's hazard curve
as the project interpolates it (:func:`rocking.risk.annual_frequency.mean_annual_frequencies`);
its interval integrates each bootstrap resample of the interpolated fragility, through a
bicubic table of ln λ over (ln θ, β) per site and limit state (:class:`RateTable`; its error
against the exact λ is at most 6e-4 relative over θ 0.05–3 g, β 0.005–0.6 on the example
hazard, largest at the smallest β, where λ(θ) shows the hazard's kinks; the tests hold it
below 1e-3: far inside any interval), which is what makes 10,000 columns × 1000 resamples
affordable (docs/risk.md, the benchmark).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.interpolate import RectBivariateSpline

from rocking.fragility.surface import interval
from rocking.fragility.table import CRITICAL_INTENSITY
from rocking.risk.annual_frequency import mean_annual_frequencies
from rocking.risk.hazard import HazardCurve
from rocking.risk.inventory import HazardSites, Inventory
from rocking.risk.risk_table import YEARS

COLUMNS = ("id", "lon", "lat", "site", "height", "diameter", "R", "tan_alpha", "mu", "mode",
           "limit_state", "fragility", "measure", "component",
           "median", "median_p05", "median_p95", "beta",
           "beta_p05", "beta_p95", "interp_error", "extrapolated", "lambda", "lambda_p05",
           "lambda_p95", "return_period", "p_50yr", "hazard_site", "hazard_lon", "hazard_lat",
           "hazard_distance_km", "row", "rank")
"""Columns of ``portfolio.csv``, in order (module docstring: units and meaning)."""

CHUNK = 2000
"""Columns interpolated at once (bounds the (columns × resamples) work arrays)."""

LN_STEP, BETA_STEP = 0.05, 0.02
"""Node spacing of :class:`RateTable` in ln θ [-] and β [-]."""


@dataclass(frozen=True)
class RateTable:
    """ln λ of a site over a grid of (ln θ, β), interpolated bicubically.

    Built from :func:`mean_annual_frequencies` at the nodes over the range asked for; used
    for the many resamples of many columns, whose λ one at a time would cost too much.
    """

    spline: RectBivariateSpline
    ln_median: tuple[float, float]
    beta: tuple[float, float]
    hazard: HazardCurve

    @classmethod
    def over(cls, hazard: HazardCurve, median_range: tuple[float, float],
             beta_range: tuple[float, float]) -> RateTable:
        """The table over θ in ``median_range`` [g] and β in ``beta_range`` [-] (padded)."""
        l0, l1 = math.log(median_range[0]) - 0.1, math.log(median_range[1]) + 0.1
        b0, b1 = max(beta_range[0] - 0.05, 1e-3), beta_range[1] + 0.05
        x = np.linspace(l0, l1, max(8, math.ceil((l1 - l0) / LN_STEP) + 1))
        y = np.linspace(b0, b1, max(8, math.ceil((b1 - b0) / BETA_STEP) + 1))
        lam = mean_annual_frequencies(np.exp(x)[:, None] + 0 * y, 0 * x[:, None] + y, hazard)
        return cls(RectBivariateSpline(x, y, np.log(lam), kx=3, ky=3), (l0, l1), (b0, b1),
                   hazard)

    def __call__(self, median, beta) -> np.ndarray:
        """λ [1/yr] at (θ, β) (NaN where either is NaN or ≤ 0)."""
        m, b = np.asarray(median, float), np.asarray(beta, float)
        ok = np.isfinite(m) & np.isfinite(b) & (m > 0) & (b > 0)
        out = np.full(m.shape, np.nan)
        lm = np.log(np.where(ok, m, 1.0))
        inside = ok & (lm >= self.ln_median[0]) & (lm <= self.ln_median[1]) \
            & (b >= self.beta[0]) & (b <= self.beta[1])
        out[inside] = np.exp(self.spline.ev(lm[inside], b[inside]))
        beyond = ok & ~inside  # extrapolated columns only: their exact λ
        if beyond.any():
            out[beyond] = mean_annual_frequencies(m[beyond], b[beyond], self.hazard)
        return out


def portfolio_table(surface, inventory: Inventory, hazard: HazardSites, *, mode: str = "3d",
                    limit_states=None, progress=None) -> pd.DataFrame:
    """Per column and limit state: fragility, λ with its interval, rank (module docstring).

    Parameters
    ----------
    surface : rocking.fragility.surface.FragilitySurface
        In the hazard's measure and component (:func:`rocking.risk.reconcile.
        reconcile_surface`): its ``measure`` and ``component`` are written in every row.
    inventory : Inventory
        Checked columns with their hazard site (:func:`rocking.risk.inventory.read_inventory`
        with this ``hazard``).
    hazard : HazardSites
    mode : str
        The surface's mode.
    limit_states : sequence of str, optional
        Default: every limit state of the surface in ``mode``.
    progress : rocking._progress.Progress, optional
        Advanced by one per column and limit state.

    Returns
    -------
    pandas.DataFrame
        :data:`COLUMNS` and the inventory's own further columns, one row per column and
        limit state, by limit state then rank; ``attrs["site"]`` the site's answer per
        limit state (:func:`site_answer`, one record each).
    """
    from rocking.spectra.limit_states import parse_limit_state

    cols = inventory.columns
    if (cols["hazard_index"] < 0).any():
        raise ValueError("the inventory was read without this hazard: read_inventory(..., "
                         "hazard=...) gives each column its site")
    if surface.measure != hazard.measure:
        raise ValueError(f"the surface is in {surface.measure}, the hazard "
                         f"({hazard.source}) in {hazard.measure}: reconcile them first")
    states = (surface.limit_states(mode) if limit_states is None
              else [parse_limit_state(s).name for s in limit_states])
    errors = surface.interpolation_error()
    R, ta = cols["R"].to_numpy(float), cols["tan_alpha"].to_numpy(float)
    site = cols["hazard_index"].to_numpy(int)
    parts, answers = [], []
    used = np.unique(site)
    for ls in states:
        n = len(cols)
        tables = {}
        if surface.n_resamples:
            m0, m1, b0, b1 = surface.resample_range(mode, ls)
            tables = {k: RateTable.over(hazard.curve(k), (m0, m1), (b0, b1)) for k in used}
        res = {k: np.full(n, np.nan) for k in ("median", "median_p05", "median_p95", "beta",
                                               "beta_p05", "beta_p95", "lambda",
                                               "lambda_p05", "lambda_p95")}
        # Σλ of every resample: the resamples draw the same motions at every column, so
        # their sum is a resample of the site's expected number per year
        total = np.zeros(surface.n_resamples)
        for start in range(0, n, CHUNK):
            sl = slice(start, min(start + CHUNK, n))
            ev = surface.evaluate(R[sl], ta[sl], mode, ls, extrapolate=True)
            for k in ("median", "beta", "median_p05", "median_p95", "beta_p05", "beta_p95"):
                if k in ev:
                    res[k][sl] = ev[k]
            for k in np.unique(site[sl]):
                here = np.flatnonzero(site[sl] == k)
                curve = hazard.curve(k)
                res["lambda"][sl][here] = mean_annual_frequencies(
                    ev["median"][here], ev["beta"][here], curve)
                if "median_resamples" in ev:
                    med, bet = ev["median_resamples"][here], ev["beta_resamples"][here]
                    lam = tables[k](med, bet)
                    lo, hi = interval(lam)
                    res["lambda_p05"][sl][here], res["lambda_p95"][sl][here] = lo, hi
                    total += np.nansum(lam, axis=0)
            if progress is not None:
                progress.update(sl.stop - sl.start)
        lam = res["lambda"]
        answers.append(site_answer(ls, lam, total if surface.n_resamples else None))
        part = pd.DataFrame({
            "id": cols["id"], "lon": cols["lon"], "lat": cols["lat"], "site": cols["site"],
            "height": cols["height"], "diameter": cols["diameter"], "R": R, "tan_alpha": ta,
            "mu": cols["mu"], "mode": mode, "limit_state": ls, "fragility": CRITICAL_INTENSITY,
            "measure": surface.measure, "component": surface.component,
            **{k: res[k] for k in ("median", "median_p05", "median_p95",
                                   "beta", "beta_p05", "beta_p95")},
            "interp_error": errors.get((mode, ls), math.nan),
            "extrapolated": cols["extrapolated"].astype(bool),
            "lambda": lam, "lambda_p05": res["lambda_p05"], "lambda_p95": res["lambda_p95"],
            "return_period": np.where(lam > 0, 1.0 / np.where(lam > 0, lam, 1.0), np.inf),
            "p_50yr": -np.expm1(-lam * YEARS),
            "hazard_site": [_site_label(hazard, k) for k in site],
            "hazard_lon": [hazard.sites[k].lon for k in site],
            "hazard_lat": [hazard.sites[k].lat for k in site],
            "hazard_distance_km": cols["hazard_distance_km"],
            "row": cols["row"],
        })
        part["rank"] = part["lambda"].rank(ascending=False, method="min").astype("Int64")
        extra = inventory.extra
        part = pd.concat([part, extra.reset_index(drop=True)], axis=1) if extra is not None \
            and not extra.empty else part
        parts.append(part.sort_values("rank", kind="stable"))
    out = pd.concat(parts, ignore_index=True)
    out = out[[*COLUMNS, *[c for c in out.columns if c not in COLUMNS]]]
    out.attrs["skipped"] = inventory.skipped_note()
    out.attrs["site"] = answers  # records, not a frame: pandas compares attrs when it merges
    return out


SITE_COLUMNS = ("limit_state", "columns", "expected_per_year", "expected_p05",
                "expected_p95", "any_lo", "any_hi", "p_any_50yr_lo", "p_any_50yr_hi")
"""Columns of ``portfolio_site.csv`` (:func:`site_answer`)."""


def site_answer(limit_state: str, lam: np.ndarray, resampled_sum: np.ndarray | None) -> dict:
    """The site's answer for one limit state.

    - ``expected_per_year``: the expected number of columns reaching it per year, Σλ_i
      (exact whatever the correlation between columns: an expectation is additive), with
      its 90 % interval over the bootstrap resamples of the motions (``expected_p05``,
      ``expected_p95``; each resample's λ summed over the columns: the resamples draw the
      same motions at every column);
    - ``any_lo``, ``any_hi``: bounds on the annual rate of "at least one column reaches
      it", max λ_i (the columns fully dependent) to Σλ_i (never two at once); without a
      model of the correlation between columns nothing narrower holds;
    - ``p_any_50yr_lo``, ``p_any_50yr_hi``: the same as probabilities in 50 years
      (Poisson).
    """
    finite = lam[np.isfinite(lam)]
    total = float(finite.sum()) if finite.size else math.nan
    top = float(finite.max()) if finite.size else math.nan
    lo = hi = math.nan
    if resampled_sum is not None and resampled_sum.size:
        lo, hi = (float(v) for v in interval(resampled_sum))
    return {"limit_state": limit_state, "columns": int(finite.size),
            "expected_per_year": total, "expected_p05": lo, "expected_p95": hi,
            "any_lo": top, "any_hi": total,
            "p_any_50yr_lo": float(-np.expm1(-top * YEARS)),
            "p_any_50yr_hi": float(-np.expm1(-total * YEARS))}


def site_lines(site: pd.DataFrame) -> list[str]:
    """The site's answer in words, one line per limit state."""
    from rocking.spectra.limit_states import limit_state_title

    out = []
    for r in site.itertuples():
        band = (f" (90 % {r.expected_p05:.3g}–{r.expected_p95:.3g})"
                if np.isfinite([r.expected_p05, r.expected_p95]).all() else "")
        out.append(f"{limit_state_title(r.limit_state)}: {r.expected_per_year:.3g} columns "
                   f"per year expected{band}, one every {1 / r.expected_per_year:.3g} years; "
                   f"the rate of at least one lies between {r.any_lo:.3g} and "
                   f"{r.any_hi:.3g} per year (P(50 yr) {r.p_any_50yr_lo:.2g}–"
                   f"{r.p_any_50yr_hi:.2g}; the columns' dependence decides where)")
    return out


def _site_label(hazard: HazardSites, k: int) -> str:
    s = hazard.sites[k]
    if s.id or math.isfinite(s.lon):
        return s.label
    return hazard.curve(k).site or hazard.curve(k).source


def error_words(interp_error: float) -> str:
    """How the interpolation error of a median is quoted: ``"±5.1 % (leave-one-out)"``, or
    why there is none (a grid of two values per direction has no node to leave out)."""
    if not math.isfinite(interp_error):
        return "not measured (no interior grid node to leave out)"
    return f"±{100 * interp_error:.1f} % (leave-one-out)"


@dataclass
class SitePortfolio:
    """What :func:`site_portfolio` computed: the table and what it rests on."""

    table: pd.DataFrame
    inventory: Inventory
    surface: object
    hazard: HazardSites
    notes: list[str]

    @property
    def site(self) -> pd.DataFrame:
        """The site's answer per limit state (:func:`site_answer`)."""
        return pd.DataFrame(self.table.attrs["site"], columns=list(SITE_COLUMNS))


def site_portfolio(study: str | Path, inventory: str | Path, hazard, *, site=None,
                   kind: str | None = None, unit: str | None = None,
                   component: str | None = None, mode: str = "3d", limit_states=None,
                   resamples: int | None = None, extrapolate: bool = False,
                   skip_invalid: bool = False, max_distance_km: float | None = None,
                   progress_from: int = 2000,
                   study_component: str | None = None) -> SitePortfolio:
    """Every column of ``inventory`` under ``hazard``, from the surface of a study's folder:
    the one composition behind ``rocking portfolio`` and the workflow's ``portfolio`` rule.

    Everything is checked before any λ is computed: the hazard (file, sites, kind,
    measure and component), the surface in the hazard's measure and component
    (:func:`rocking.risk.reconcile.reconcile_surface`: refitted from the study's motions
    where the hazard's component is not the vector peak) and every row of the inventory.

    Parameters
    ----------
    study : path
        The study's results folder (``critical.csv``, ``fragility.csv``,
        ``motion_measures.csv``).
    inventory : path
        The inventory CSV (:func:`rocking.risk.inventory.read_inventory`).
    hazard : str, path or dict
        A hazard file (one or many sites) or power law; a mapping as a study's ``hazard:``
        (its ``file``, ``kind``, ``unit``, ``component``, ``im_factor``; its ``site`` is the
        study's, not the columns': each column takes its own, by its lon/lat or site id).
    site : int or dict, optional
        One site for every column (``{"id"}`` or ``{"lon", "lat"[, "max_distance_km"]}``).
    kind, unit, component : str, optional
        As the hazard entry's keys (given here, they win over the entry's).
    mode, limit_states, resamples, extrapolate, skip_invalid, max_distance_km
        As :meth:`FragilitySurface.from_study` and :func:`read_inventory` take them.
    progress_from : int
        Inventories of this many columns or more show a progress bar on the terminal.
    study_component : str, optional
        The study's component (the workflow's ``studies.<name>.component``): taken where
        the hazard states none; default the fragility's.
    """
    from rocking._progress import Progress
    from rocking.risk.hazard import MAX_DISTANCE_KM
    from rocking.risk.inventory import read_hazard_sites, read_inventory
    from rocking.risk.reconcile import reconcile_surface

    if resamples is not None and int(resamples) < 0:
        raise ValueError(f"resamples must be >= 0, got {resamples}")
    sites = read_hazard_sites(hazard, site=site, kind=kind, unit=unit, component=component)
    surface = reconcile_surface(
        study, sites.measure, sites.component, hazard=f"the hazard ({sites.source})",
        hazard_note=sites.component_note if sites.component is not None else "",
        mode=mode, limit_states=limit_states, n_resamples=resamples,
        assumed=None if study_component is None else (study_component,
                                                      "the study's component"))
    columns = read_inventory(inventory, surface=surface, hazard=sites,
                             extrapolate=extrapolate, skip_invalid=skip_invalid,
                             max_distance_km=(MAX_DISTANCE_KM if max_distance_km is None
                                              else max_distance_km))
    notes = [x for x in (surface.note, columns.skipped_note(), columns.unused_note()) if x]
    n_states = len(limit_states or surface.limit_states(mode))
    bar = (Progress(len(columns.columns) * n_states, "portfolio", unit="column")
           if len(columns.columns) >= progress_from else None)
    try:
        table = portfolio_table(surface, columns, sites, mode=mode, limit_states=limit_states,
                                progress=bar)
    finally:
        if bar is not None:
            bar.close()
    return SitePortfolio(table, columns, surface, sites, notes)


POSITIONS = ("lon", "lat", "hazard_lon", "hazard_lat")
"""Columns of ``portfolio.csv`` written with every digit (shortest exact form)."""


def _exact(value) -> str:
    value = float(value)
    return "" if not math.isfinite(value) else repr(value)


def read_portfolio(path: str | Path) -> pd.DataFrame:
    """``portfolio.csv`` as written: ids, sites and the inventory's further columns as text
    (``007`` stays ``007``), numbers as numbers."""
    head = pd.read_csv(path, nrows=0).columns
    text = {c: str for c in head if c not in NUMBERS}
    return pd.read_csv(path, dtype=text, keep_default_na=False, na_values={
        c: ["", "nan", "NaN"] for c in head if c in NUMBERS})


NUMBERS = ("lon", "lat", "height", "diameter", "R", "tan_alpha", "mu", "median", "median_p05",
           "median_p95", "beta", "beta_p05", "beta_p95", "interp_error", "lambda",
           "lambda_p05", "lambda_p95", "return_period", "p_50yr", "hazard_lon", "hazard_lat",
           "hazard_distance_km", "row", "rank")
"""Numeric columns of ``portfolio.csv`` (:func:`read_portfolio`; the rest is text)."""


def write_portfolio(table: pd.DataFrame, out_dir: str | Path,
                    skipped: pd.DataFrame | None = None) -> Path:
    """``<out_dir>/portfolio.csv``, ``portfolio_site.csv`` (the site's answer per limit
    state, :func:`site_answer`, where the table has it) and ``portfolio_skipped.csv``
    (the rows left out, when any), written under temporary names and renamed; returns the
    table's path."""
    from rocking.provenance import write_atomic

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "portfolio.csv"
    # positions with every digit they were given (%.6g would cut 23.538123 to 23.5381)
    exact = table.assign(**{c: [_exact(v) for v in table[c]]
                            for c in POSITIONS if c in table.columns})
    write_atomic(path, lambda tmp: exact.to_csv(tmp, index=False, float_format="%.6g"))
    if table.attrs.get("site"):
        site = pd.DataFrame(table.attrs["site"], columns=list(SITE_COLUMNS))
        write_atomic(out_dir / "portfolio_site.csv",
                     lambda tmp: site.to_csv(tmp, index=False, float_format="%.6g"))
    if skipped is not None and not skipped.empty:
        write_atomic(out_dir / "portfolio_skipped.csv",
                     lambda tmp: skipped.to_csv(tmp, index=False))
    return path


__all__ = ["COLUMNS", "SITE_COLUMNS", "RateTable", "SitePortfolio", "error_words",
           "portfolio_table", "read_portfolio", "site_answer", "site_lines", "site_portfolio",
           "write_portfolio"]
