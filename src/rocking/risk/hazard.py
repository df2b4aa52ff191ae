"""Seismic hazard curves: the mean annual rate λ(im) at which an intensity im is exceeded at a site.

A :class:`HazardCurve` is a table of intensity levels [g] and their annual rates of exceedance
[1/yr], in one intensity measure: PGA or Sa(T) (OpenQuake's ``PGA``, ``SA(1.0)``; the study's
``pga``, ``sa:1.0``, :class:`rocking.motions.measures.Measure`), in one horizontal component
(:attr:`HazardCurve.component`). It comes from a power law (λ = k0·im^−k), an OpenQuake
hazard-curve CSV, or a plain two-column table (intensity and annual rate, or intensity and
probability of exceedance in a stated investigation time). Between levels the curve is
interpolated log-log (a piecewise power law, the shape hazard curves have locally); beyond
either end the first or last segment's log-log slope is extrapolated (see
:mod:`rocking.risk.annual_frequency` for why and for how much that end contributes).

A file is recognized from its first lines before it is parsed (:data:`HAZARD_FORMATS`,
:func:`hazard_format`) and parsed once, every site of it (:func:`read_hazard_file`, a
:class:`HazardFile`): a regional file of 10,000 sites is read in about a second, and each
site's curve is made from it when asked for. Two sites at the same coordinates, or one
``custom_site_id`` given twice, are refused naming both lines. The measure is the file's
``imt=`` (its comment line), else its file name (OpenQuake's ``hazard_curve-mean-SA(1.0)_3.csv``);
both given and different is refused.

Engines write probabilities of exceedance with six significant digits, so the lowest levels
of a 50-year curve read ``1.000000E+00``: an infinite rate. Those levels are dropped (said
once, in one line, and kept on the curve as :attr:`HazardCurve.n_dropped` and
:attr:`HazardCurve.dropped_up_to`); the part of λ_LS that rests on the intensities below the
first kept level is ``below_first`` of :func:`rocking.risk.annual_frequency.annual_frequency_parts`
(``share_below_first`` in the risk table, with a warning when it is large).

:func:`select_site` picks one site of a file by ``custom_site_id``, by the nearest lon/lat
within :data:`MAX_DISTANCE_KM` (great-circle) or by row, and refuses a file of several sites
when none is named. The file's ``kind`` (``mean``, ``quantile-0.85``, ``rlz-000``) is read
from its comment line; anything but the mean is used only when the configuration names it.
Levels are read in the file's unit (a header ``pga [cm/s2]``, the configuration's ``unit``,
else g: the unit OpenQuake writes PGA and SA in) and converted to g; levels implausible in g
are refused in one line (:func:`check_plausible`). A UTF-8 byte-order mark is stripped.

**The component.** A hazard's component is declared (the entry's ``component``, ``rocking
risk --component``), else read from a ``component='rotd50'`` in its file's comment lines (any
case: ``RotD50``), else, for an OpenQuake hazard-curve file, which never states it,
:data:`OPENQUAKE_COMPONENT` (``rotd50``), said in every output that uses it
(:attr:`HazardCurve.component_note`): the component of the NGA-West2 models that most
current OpenQuake models of active regions use, and the safe guess: if the file is in any
larger component (RotD100, the vector peak, the larger of two), the fragility is taken
smaller than it is and λ comes out high, never low. A table or a power law that says nothing
has no component (None): it is taken in the fragility's, said likewise.
"""

from __future__ import annotations

import csv
import dataclasses
import logging
import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from rocking._validate import positive_finite
from rocking.motions.measures import Measure, parse_component

log = logging.getLogger(__name__)

POWER_LAW_IML = np.geomspace(1e-3, 10.0, 41)
"""Levels [g] at which a power-law curve is tabulated (exact there and, log-log, between)."""

_TIME = re.compile(r"investigation_time\s*=\s*['\"]?([0-9.eE+-]+)")
_IMT = re.compile(r"\bimt\s*=\s*['\"]?([A-Za-z0-9().:]+)")
_NAME_IMT = re.compile(r"(?:^|[-_])(PGA|PGV|SA\([0-9.]+\))(?=[-_.]|$)", re.IGNORECASE)
_KIND = re.compile(r"\bkind\s*=\s*['\"]?([A-Za-z0-9_.-]+)")
_KIND_NAME = re.compile(r"^(mean|quantile-(0?\.[0-9]+)|rlz-[0-9]+)$")
_HEADER_UNIT = re.compile(r"^(.*?)\s*\[([^\]]*)\]\s*$")

STANDARD_GRAVITY = 9.80665
"""g [m/s²] (the conventional value, ISO 80000-3)."""

UNITS = {"g": 1.0, "m/s2": 1.0 / STANDARD_GRAVITY, "cm/s2": 0.01 / STANDARD_GRAVITY,
         "gal": 0.01 / STANDARD_GRAVITY}
"""Units a hazard's acceleration levels may be given in → factor to g."""

MAX_PLAUSIBLE_G = 10.0
"""No PGA or Sa above this [g] is exceeded more often than :data:`MIN_RATE_ABOVE_MAX`: the
largest recorded PGAs are 3–4 g. Levels beyond it at a higher rate are refused (levels in
cm/s² or m/s² read as g)."""

MIN_RATE_ABOVE_MAX = 1e-6
"""Annual rate [1/yr] above which a level beyond :data:`MAX_PLAUSIBLE_G` is implausible."""

MIN_PLAUSIBLE_TOP_G = 0.01
"""A hazard curve whose highest level is below this [g] is refused (levels in g declared
as cm/s²): it says nothing at intensities that move a rocking body."""

MAX_DISTANCE_KM = 5.0
"""Default greatest distance [km] from a requested lon/lat to the site taken (great-circle)."""

EARTH_RADIUS_KM = 6371.0
"""Mean Earth radius [km] of the great-circle distance (haversine)."""

SITES_LISTED = 5
"""Sites named in the one line that refuses a file of several sites without ``site``."""

RATE_COLUMNS = ("annual_rate", "rate", "lambda", "maf")
"""Names the second column of a two-column table may have when it holds annual rates."""


OPENQUAKE_COMPONENT = "rotd50"
"""Component of an OpenQuake hazard-curve file that states none (module docstring: RotD50,
the NGA-West2 models' component, and the safe guess)."""

HEAD_LINES = 8
"""Lines of a file :func:`hazard_format` reads to recognize its format."""


def hazard_measure(imt, where: str = "") -> Measure:
    """The intensity measure of a hazard: PGA or Sa(T) in g (any spelling of
    :meth:`rocking.motions.measures.Measure.of`). PGV and anything else are refused in one
    line (the study's PGV is in m/s, an engine's in cm/s: refused rather than guessed)."""
    try:
        measure = Measure.of(str(imt))
    except ValueError:
        measure = None
    if measure is None or measure.unit != "g":
        pre = f"{where}: " if where else ""
        raise ValueError(f"{pre}intensity measure type {imt!r} is not supported for a hazard: "
                         "use PGA or SA(T) (e.g. SA(1.0)), in g")
    return measure


@dataclass(frozen=True, eq=False)
class HazardCurve:
    """Annual rate of exceedance of an intensity measure at a site, at increasing levels.

    Parameters
    ----------
    im_g : array_like
        Intensity levels [g] (PGA or Sa(T)), strictly increasing, > 0.
    annual_rate : array_like
        Mean annual rate of exceedance λ at each level [1/yr], > 0 and non-increasing.
    imt : str
        Intensity measure type: ``"PGA"`` or ``"SA(<T>)"`` (or the study's ``"pga"``,
        ``"sa:<T>"``); :attr:`measure` is the study's name of it.
    source : str
        Where the curve came from (a file path, or the power law), for tables and reports.
    n_dropped : int
        Levels of the file left out because their probability of exceedance was 1 (an
        infinite rate), all below the first level kept.
    dropped_up_to : float
        The highest such level [g] (NaN when none was dropped).
    site : str
        The site of a file of sites, in words (its ``custom_site_id`` or row, its lon/lat, and
        how far it is from a requested point); '' for a table or a power law.
    kind : str
        The curve's statistic as the file states it or the configuration names it
        (``mean``, ``quantile-0.85``, ``rlz-000``); '' when neither says.
    unit : str
        The unit the file gave its levels in (:data:`UNITS`); :attr:`im_g` is in g always.
    component : str or None
        The horizontal component (:data:`rocking.motions.measures.COMPONENTS`): declared,
        read from its file, or :data:`OPENQUAKE_COMPONENT` for an OpenQuake file that says
        nothing; None for a table or power law that says nothing.
    component_source : str
        Where :attr:`component` comes from: ``"declared"``, ``"file"``, ``"default"`` (an
        OpenQuake file's, :data:`OPENQUAKE_COMPONENT`), ``"im_factor"`` (levels converted
        to the fragility's component by the user, :meth:`scaled`) or ``""`` (none).
    """

    im_g: np.ndarray
    annual_rate: np.ndarray
    imt: str = "PGA"
    source: str = ""
    n_dropped: int = 0
    dropped_up_to: float = math.nan
    site: str = ""
    kind: str = ""
    unit: str = "g"
    component: str | None = None
    component_source: str = ""

    def __post_init__(self) -> None:
        im = np.asarray(self.im_g, dtype=float).ravel()
        lam = np.asarray(self.annual_rate, dtype=float).ravel()
        where = f"{self.source}: " if self.source else ""
        if im.size != lam.size:
            raise ValueError(f"{where}im_g and annual_rate must have the same length, got "
                             f"{im.size} and {lam.size}")
        if im.size < 2:
            raise ValueError(f"{where}a hazard curve needs at least 2 levels with a finite "
                             f"rate, got {im.size}")
        if np.any(~np.isfinite(im) | (im <= 0.0)) or np.any(np.diff(im) <= 0.0):
            raise ValueError(f"{where}intensity levels must be finite, > 0 and strictly "
                             f"increasing, got {_short(im)}")
        if np.any(~np.isfinite(lam) | (lam <= 0.0)):
            raise ValueError(f"{where}annual rates must be finite and > 0 (a zero rate has no "
                             f"log-log slope; drop those levels), got {_short(lam)}")
        if np.any(np.diff(lam) > 0.0):
            i = int(np.flatnonzero(np.diff(lam) > 0.0)[0])
            raise ValueError(f"{where}annual rates must not increase with the intensity, got "
                             f"{lam[i]:.6g} at {im[i]:g} g and {lam[i + 1]:.6g} at "
                             f"{im[i + 1]:g} g")
        object.__setattr__(self, "imt", hazard_measure(self.imt, self.source).imt)
        if self.component is not None:
            object.__setattr__(self, "component", parse_component(self.component))
        object.__setattr__(self, "im_g", im)
        object.__setattr__(self, "annual_rate", lam)

    @property
    def measure(self) -> str:
        """The study's name of the curve's intensity measure (``"pga"``, ``"sa:1.0"``)."""
        return Measure.of(self.imt).name

    @property
    def component_note(self) -> str:
        """One line on where the component comes from when it was not declared ('' when it
        was, or was read from the file)."""
        if self.component_source == "default":
            return (f"{self.source}: an OpenQuake hazard curve does not state its horizontal "
                    f"component: taken as {OPENQUAKE_COMPONENT} (the NGA-West2 models'; on "
                    "the safe side if the file is in a larger one): declare it "
                    "(hazard.component, --component) if it is another")
        if self.component_source == "im_factor":
            return (f"{self.source}: levels converted by im_factor, so taken in the "
                    "fragility's horizontal component")
        if self.component is None:
            return (f"{self.source}: the hazard does not state its horizontal component: "
                    "taken in the fragility's; declare it (hazard.component, --component)")
        return ""

    @property
    def note(self) -> str:
        """One line on the levels dropped for a probability of exceedance of 1 ('' if none)."""
        if not self.n_dropped:
            return ""
        return (f"{self.source}: {self.n_dropped} level(s) with probability of exceedance 1 "
                f"(an infinite rate) dropped, up to {self.dropped_up_to:g} g; the part of "
                "each λ from below the first level kept is reported as share_below_first")

    @classmethod
    def from_power_law(cls, k0: float, k: float, im_g=None, imt: str = "PGA") -> HazardCurve:
        """λ(im) = k0·im^−k, tabulated at ``im_g`` (default :data:`POWER_LAW_IML`).

        Parameters
        ----------
        k0 : float
            Annual rate of exceeding 1 g [1/yr], > 0.
        k : float
            Log-log slope of the hazard curve [-], > 0 (a flat or rising curve is no hazard
            curve).
        im_g : array_like, optional
            Levels [g]. The log-log interpolation and extrapolation reproduce the power law
            exactly everywhere, so the levels only bound what "inside the table" means.
        imt : str
            The intensity measure (``"PGA"``, ``"SA(1.0)"``, ``"sa:1.0"``).
        """
        k0, k = positive_finite("k0", k0), positive_finite("k", k)
        im = POWER_LAW_IML if im_g is None else np.asarray(im_g, dtype=float)
        imt = hazard_measure(imt, "power law").imt
        return cls(im, k0 * im ** (-k), imt=imt, source=f"power law k0={k0:g}/yr, k={k:g} ({imt})")

    @classmethod
    def from_openquake_csv(cls, path: str | Path, site=None, *, kind: str | None = None,
                           unit: str | None = None) -> HazardCurve:
        """Read one site of an OpenQuake ``hazard_curve-*.csv``.

        The file has a comment line holding ``investigation_time`` T [yr], ``imt`` (``PGA``
        or ``SA(T)``) and ``kind`` (``mean``, ``quantile-0.85``, ``rlz-000``), then a header
        ``[custom_site_id,]lon,lat[,depth],poe-<iml>,...`` and one row per site of
        probabilities of exceedance in T. They become annual rates by λ = −ln(1 − poe)/T
        (Poisson). Levels with poe = 0 are dropped (no rate to interpolate in log-log);
        levels with poe = 1 (the lowest levels of a long investigation time written with six
        significant digits) are dropped too, said once in one line (logged, and
        :attr:`note`). Probabilities that increase with the level, fewer than two levels
        left, a missing ``investigation_time``/``imt``, a site not in the file, a file of
        several sites without ``site``, a kind other than the mean not named by ``kind``,
        or levels implausible in their unit are refused with one line naming the file.

        Parameters
        ----------
        path : path
            The CSV file.
        site : int, dict or None
            Which site (:func:`select_site`): a row (0 = first), ``{"id": ...}``
            (``custom_site_id``) or ``{"lon", "lat"[, "max_distance_km"]}`` [deg, km]; None
            only for a file of one site.
        kind : str, optional
            The statistic to use: needed for any file kind but ``mean``, and must match it.
        unit : str, optional
            The unit of the levels (:data:`UNITS`; default g, the engine's unit of PGA and SA).
        """
        hazard = read_hazard_file(path)
        if hazard.format != "openquake":
            raise ValueError(f"{path} is not an OpenQuake hazard-curve CSV (no poe-<iml> "
                             "columns in its header)")
        return hazard.curve(site, kind=kind, unit=unit)

    @classmethod
    def from_table(cls, path: str | Path, investigation_time: float | None = None, *,
                   kind: str | None = None, unit: str | None = None) -> HazardCurve:
        """Read a plain two-column hazard table.

        A header names the columns: the intensity measure first (``pga``, ``PGA``,
        ``sa:1.0``, ``SA(1.0)``, with or without a unit ``[g]``, ``[m/s2]``, ``[cm/s2]``,
        ``[gal]``; without one the levels are in g), then ``annual_rate`` (or ``rate``,
        ``lambda``: λ [1/yr]) or ``poe`` (probability of exceedance in the investigation
        time, given here or in a comment line ``# investigation_time=50``). Lines starting
        with ``#`` are comments (one may say ``kind=quantile-0.85``).

        Parameters
        ----------
        path : path
            The CSV file.
        investigation_time : float, optional
            T [yr] of a ``poe`` column (overrides a comment line).
        kind : str, optional
            The curve's statistic (must match a ``kind=`` comment where there is one).
        unit : str, optional
            The unit of the levels when the header gives none (it must agree where it does).
        """
        hazard = read_hazard_file(path)
        if hazard.format != "table":
            raise ValueError(f"{path} is not a two-column hazard table")
        return hazard.curve(investigation_time=investigation_time, kind=kind, unit=unit)

    @classmethod
    def from_file(cls, path: str | Path, site=None, investigation_time: float | None = None,
                  *, kind: str | None = None, unit: str | None = None) -> HazardCurve:
        """A hazard file of any format of :data:`HAZARD_FORMATS` (:func:`read_hazard_file`),
        one curve of it (arguments as :meth:`from_openquake_csv` and :meth:`from_table`)."""
        return read_hazard_file(path).curve(site, investigation_time, kind=kind, unit=unit)

    def rate(self, im_g) -> np.ndarray:
        """λ(im) [1/yr]: log-log interpolation, end slopes extrapolated."""
        x = np.log(np.asarray(im_g, dtype=float))
        lx, ly = np.log(self.im_g), np.log(self.annual_rate)
        slopes = np.diff(ly) / np.diff(lx)
        seg = np.clip(np.searchsorted(lx, x, side="right") - 1, 0, lx.size - 2)
        return np.exp(ly[seg] + slopes[seg] * (x - lx[seg]))

    def slope(self, im_g) -> np.ndarray:
        """−d ln λ / d ln im at ``im_g`` (the local power-law exponent k) [-]."""
        x = np.log(np.asarray(im_g, dtype=float))
        lx, ly = np.log(self.im_g), np.log(self.annual_rate)
        slopes = -np.diff(ly) / np.diff(lx)
        seg = np.clip(np.searchsorted(lx, x, side="right") - 1, 0, lx.size - 2)
        return slopes[seg]

    def scaled(self, factor: float) -> HazardCurve:
        """The curve of the intensity ``factor``·im (levels multiplied, rates unchanged).

        Converts a hazard computed for another definition of the measure to the
        fragility's (``im_factor``): a curve of RotD50 becomes one of the vector peak with
        the ratio RotD100/RotD50 as ``factor`` (docs/risk.md). The result is in the
        fragility's component by the user's word: its own component is dropped
        (``component_source`` ``"im_factor"``), so no refit converts it a second time.
        """
        factor = positive_finite("factor", factor)
        if factor == 1.0:
            return self
        # replace() carries every other metadata field (site, kind, unit, ...) unchanged
        return dataclasses.replace(self, im_g=self.im_g * factor,
                                   source=self.source + f", levels x{factor:g}",
                                   dropped_up_to=self.dropped_up_to * factor,
                                   component=None, component_source="im_factor")


@dataclass(frozen=True)
class Site:
    """One site (row) of an OpenQuake hazard-curve file."""

    row: int
    id: str  # custom_site_id ('' when the file has none)
    lon: float  # [deg]
    lat: float  # [deg]
    line: int = 0  # the line of the file it was read from (1 = the first), 0 when none

    @property
    def label(self) -> str:
        """``"b (lon 10.1, lat 45)"`` or ``"row 1 (lon 10.1, lat 45)"``."""
        name = f"id {self.id}" if self.id else f"row {self.row}"
        return f"{name} (lon {self.lon:g}, lat {self.lat:g})"


LON_RANGE = (-180.0, 180.0)
"""Longitudes a position may have [deg], everywhere (hazard sites, inventories, the
OpenQuake exposure): the engine's range."""

LAT_RANGE = (-90.0, 90.0)
"""Latitudes [deg]."""


def lon_lat_problem(lon: float, lat: float) -> str:
    """Why (lon, lat) is no position ('' when it is one), aimed at the likely mistake."""
    if LON_RANGE[0] <= lon <= LON_RANGE[1] and LAT_RANGE[0] <= lat <= LAT_RANGE[1]:
        return ""
    if LAT_RANGE[0] <= lon <= LAT_RANGE[1] and LON_RANGE[0] <= lat <= LON_RANGE[1]:
        return (f"lon {lon:g}, lat {lat:g} is not a point on Earth: lon and lat swapped? "
                "(lat must be in [-90, 90])")
    if LON_RANGE[1] < lon <= 360.0 and LAT_RANGE[0] <= lat <= LAT_RANGE[1]:
        return (f"lon {lon:g} is beyond 180: give it as {lon - 360.0:g} (lon in [-180, 180], "
                "as OpenQuake takes it)")
    return (f"lon {lon:g}, lat {lat:g} is not a point on Earth (lon in [-180, 180], lat in "
            "[-90, 90] degrees)")


def great_circle_km(lon1, lat1, lon2, lat2) -> np.ndarray:
    """Great-circle distance [km] between points given in degrees (haversine, sphere of
    :data:`EARTH_RADIUS_KM`)."""
    p1, p2 = np.radians(lat1), np.radians(lat2)
    dp, dl = p2 - p1, np.radians(np.asarray(lon2, dtype=float) - lon1)
    h = np.sin(dp / 2) ** 2 + np.cos(p1) * np.cos(p2) * np.sin(dl / 2) ** 2
    return 2.0 * EARTH_RADIUS_KM * np.arcsin(np.sqrt(np.clip(h, 0.0, 1.0)))


SITE_FORMS = ("a row (0 = first), {id: <custom_site_id>} or {lon, lat[, max_distance_km]}")


def select_site(sites: list[Site], site, where: str) -> tuple[Site, str]:
    """The site asked for, and its description (:attr:`HazardCurve.site`).

    Parameters
    ----------
    sites : list of Site
        The file's sites.
    site : int, dict or None
        A row, ``{"id": ...}``, or ``{"lon", "lat"[, "max_distance_km"]}`` [deg, km] (the
        nearest site, great-circle, within :data:`MAX_DISTANCE_KM` unless given); None
        only for a file of one site.
    where : str
        The file, for the one-line errors.
    """
    if site is None:
        if len(sites) == 1:
            return sites[0], sites[0].label
        shown = ", ".join(s.label for s in sites[:SITES_LISTED])
        more = f", ... ({len(sites) - SITES_LISTED} more)" if len(sites) > SITES_LISTED else ""
        raise ValueError(f"{where} has {len(sites)} sites: choose one with site: {{id: ...}} "
                         f"or site: {{lon: ..., lat: ...}} (rocking risk --site-id or "
                         f"--site-lon/--site-lat): {shown}{more}")
    if isinstance(site, bool) or not isinstance(site, int | dict):
        raise ValueError(f"{where}: site must be {SITE_FORMS}, got {site!r}")
    if isinstance(site, int):
        if not 0 <= site < len(sites):
            raise ValueError(f"{where}: site row {site} is not in the file: it has "
                             f"{len(sites)} site(s), rows 0..{len(sites) - 1}")
        return sites[site], sites[site].label
    keys = set(site)
    if keys == {"id"}:
        want = str(site["id"]).strip()
        if not any(s.id for s in sites):
            raise ValueError(f"{where}: site id {want!r} asked for but the file has no "
                             "custom_site_id column; give the site's lon and lat")
        hit = [s for s in sites if s.id == want]
        if not hit:
            ids = ", ".join(s.id for s in sites[:SITES_LISTED])
            more = f", ... ({len(sites)} in all)" if len(sites) > SITES_LISTED else ""
            raise ValueError(f"{where}: site id {want!r} is not in the file (its ids: "
                             f"{ids}{more})")
        return hit[0], hit[0].label
    if {"lon", "lat"} <= keys <= {"lon", "lat", "max_distance_km"}:
        lon, lat = _number("site.lon", site["lon"]), _number("site.lat", site["lat"])
        problem = lon_lat_problem(lon, lat)
        if problem:
            raise ValueError(f"{where}: site {problem}")
        limit = positive_finite(f"{where}: site.max_distance_km",
                          site.get("max_distance_km", MAX_DISTANCE_KM))
        located = [s for s in sites if math.isfinite(s.lon) and math.isfinite(s.lat)]
        if not located:
            raise ValueError(f"{where}: the file has no lon and lat columns; choose the site "
                             "by row or id")
        dist = great_circle_km(lon, lat, [s.lon for s in located], [s.lat for s in located])
        i = int(np.argmin(dist))
        best, d = located[i], float(dist[i])
        if d > limit:
            raise ValueError(f"{where}: no site within {limit:g} km of lon {lon:g}, lat "
                             f"{lat:g}: the nearest is {best.label}, {d:.3g} km away (to take it, "
                             f"set site.max_distance_km to {math.ceil(d * 10) / 10:g})")
        return best, f"{best.label}, {d:.3g} km from lon {lon:g}, lat {lat:g}"
    raise ValueError(f"{where}: site must be {SITE_FORMS}, got keys {sorted(keys)}")


def file_kind(comments: list[str]) -> str:
    """The ``kind='...'`` a hazard file's comment lines state ('' when none)."""
    hit = _KIND.search(" ".join(comments))
    return hit.group(1) if hit else ""


def check_kind(stated: str, asked: str | None, where: str) -> str:
    """The kind used: the file's ``mean`` (or none stated) without ``asked``; any other
    only when ``asked`` names it. Refused in one line otherwise."""
    if asked is None:
        if stated in ("", "mean"):
            return stated
        raise ValueError(f"{where} holds the {stated!r} hazard curve, not the mean: to use it, "
                         f"name it (hazard.kind: {stated}, or rocking risk --kind {stated})")
    name = str(asked).strip()
    if not _KIND_NAME.match(name) or (name.startswith("quantile-")
                                       and not 0.0 < float(name[9:]) < 1.0):
        raise ValueError(f"{where}: kind must be mean, quantile-<q> (0 < q < 1) or rlz-<n>, "
                         f"got {asked!r}")
    if stated and _kind_key(stated) != _kind_key(name):
        raise ValueError(f"{where} holds the {stated!r} hazard curve, the hazard entry names "
                         f"kind {name!r}")
    return stated or name


def _kind_key(kind: str):
    return ("quantile", float(kind[9:])) if kind.startswith("quantile-") else kind


def unit_factor(unit: str, where: str = "") -> tuple[str, float]:
    """The canonical name of an acceleration unit and its factor to g (:data:`UNITS`):
    ``"cm/s²"``, ``"cm/s^2"``, ``"Gal"`` ... Refused in one line for any other."""
    text = str(unit).strip().lower().replace(" ", "").replace("²", "2").replace("^2", "2")
    text = {"m/s/s": "m/s2", "ms-2": "m/s2", "cm/s/s": "cm/s2", "cms-2": "cm/s2"}.get(text,
                                                                                    text)
    if text not in UNITS:
        pre = f"{where}: " if where else ""
        raise ValueError(f"{pre}unit {unit!r} is not an acceleration unit of a hazard curve: "
                         f"use one of {', '.join(UNITS)}")
    return text, UNITS[text]


def check_plausible(curve: HazardCurve, declared: bool, what: str = "") -> HazardCurve:
    """``curve`` unchanged, or one line refusing levels implausible in g.

    Refused: a level above :data:`MAX_PLAUSIBLE_G` exceeded more often than
    :data:`MIN_RATE_ABOVE_MAX` per year (levels in cm/s² or m/s² read as g), or a highest
    level below :data:`MIN_PLAUSIBLE_TOP_G` (levels in g declared in cm/s²).

    Parameters
    ----------
    curve : HazardCurve
        Levels converted to g.
    declared : bool
        Whether the unit was stated (a header or the configuration) rather than assumed.
    what : str
        Where g was assumed from (e.g. "OpenQuake writes PGA and SA in g").
    """
    im, lam = curve.im_g, curve.annual_rate
    high = (im > MAX_PLAUSIBLE_G) & (lam > MIN_RATE_ABOVE_MAX)
    given = f"the levels were given in {curve.unit}" if declared else (
        f"the levels were taken as g{' (' + what + ')' if what else ''}")
    fix = ("; check the unit declared" if declared else
           "; if they are in cm/s2 or m/s2, say so: hazard.unit: cm/s2 (rocking risk "
           "or rocking portfolio --hazard-unit) or a header such as 'pga [cm/s2]'")
    if high.any():
        i = int(np.flatnonzero(high)[0])
        raise ValueError(f"{curve.source}: {im[i]:.4g} g exceeded {lam[i]:.3g} times a year "
                         f"is implausible (levels {im[0]:.4g}–{im[-1]:.4g} g; nothing above "
                         f"{MAX_PLAUSIBLE_G:g} g is exceeded more often than once in "
                         f"{1 / MIN_RATE_ABOVE_MAX:.0e} years): {given}{fix}")
    if im[-1] < MIN_PLAUSIBLE_TOP_G:
        raise ValueError(f"{curve.source}: the highest level is {im[-1]:.3g} g, implausibly "
                         f"small for a hazard curve (below {MIN_PLAUSIBLE_TOP_G:g} g): "
                         f"{given}{fix}")
    return curve



# ------------------------------------------------------------------------------------------
# Hazard files: recognized from their first lines, parsed once
# ------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class HazardFile:
    """A hazard file parsed once: every site's levels and values, and what the file states.

    Attributes
    ----------
    path : Path
    format : str
        The :class:`HazardFormat` that read it (``"openquake"``, ``"table"``).
    measure : Measure
        The file's intensity measure (PGA or Sa(T)).
    measure_from : str
        Where it was read (``"imt= of its comment line"``, ``"its file name"``, ``"its
        header"``).
    comments : tuple of str
        Its comment lines.
    kind : str
        The statistic its comment line states ('' when none).
    component : str or None
        A ``component=`` of its comment lines, checked (None without one).
    investigation_time : float or None
        [yr], as its comment line states it.
    levels : numpy.ndarray
        The intensity levels as written (the file's unit).
    values : numpy.ndarray
        (sites, levels): probabilities of exceedance (``value_kind`` ``"poe"``) or annual
        rates (``"rate"``).
    value_kind : str
    sites : list of Site
        The sites ([] for a table: one curve of no stated site).
    header_unit : str or None
        A unit given in a table's header (``pga [cm/s2]``).
    """

    path: Path
    format: str
    measure: Measure
    measure_from: str
    comments: tuple[str, ...]
    kind: str
    component: str | None
    investigation_time: float | None
    levels: np.ndarray
    values: np.ndarray
    value_kind: str
    sites: list[Site] = field(default_factory=list)
    header_unit: str | None = None

    def curve(self, site=None, investigation_time: float | None = None, *,
              kind: str | None = None, unit: str | None = None) -> HazardCurve:
        """One curve of the file: ``site`` chosen by :func:`select_site` (a row, ``{"id"}``
        or ``{"lon", "lat"[, "max_distance_km"]}``; None for a file of one site or a
        table), levels converted to g (``unit``; default the header's, else g), rates from
        probabilities of exceedance by λ = −ln(1 − poe)/T."""
        where = str(self.path)
        if self.format == "table":
            if site is not None:
                raise ValueError(f"{where}: site applies to an OpenQuake hazard-curve CSV of "
                                 f"sites, this is a two-column table (got site {site!r})")
            return self._curve(0, "", investigation_time, kind, unit)
        if investigation_time is not None:
            raise ValueError(f"{where}: an OpenQuake hazard curve states its own "
                             "investigation_time; leave it out of the hazard entry")
        chosen, label = select_site(self.sites, site, where)
        return self._curve(chosen.row, label, None, kind, unit)

    def curve_at(self, row: int, *, kind: str | None = None,
                 unit: str | None = None) -> HazardCurve:
        """The curve of the site of ``row`` (0 = the first site; a table's one curve)."""
        label = self.sites[row].label if self.sites else ""
        return self._curve(row, label, None, kind, unit)

    def _curve(self, row: int, label: str, investigation_time, kind, unit) -> HazardCurve:
        where = str(self.path)
        used_kind = check_kind(self.kind, kind, where)
        stated = self.header_unit
        if stated is not None and unit is not None and \
                unit_factor(stated, where)[0] != unit_factor(unit, where)[0]:
            raise ValueError(f"{where}: the header gives the levels in {stated!r}, the hazard "
                             f"entry in {unit!r}")
        given = stated if stated is not None else unit
        name, factor = unit_factor(given, where) if given is not None else ("g", 1.0)
        source = where if not label else f"{where}, site {label}"
        im, value = self.levels * factor, self.values[row]
        if self.value_kind == "rate":
            if investigation_time is not None:
                raise ValueError(f"{where}: investigation_time is given but the table holds "
                                 "annual rates; it applies to a poe column only")
            curve = HazardCurve(im, value, imt=self.measure.imt, source=source)
        else:
            years = investigation_time if investigation_time is not None else \
                self.investigation_time
            if years is None:
                raise ValueError(f"{where}: a poe column needs its investigation time: "
                                 "hazard {file, investigation_time} or a comment line "
                                 "'# investigation_time=50'")
            years = positive_finite(f"{where}: investigation_time", years)
            curve = _from_poe(im, value, years, self.measure.imt, source)
        component, said = self.component, "file" if self.component is not None else ""
        if component is None and self.format == "openquake":
            component, said = OPENQUAKE_COMPONENT, "default"
        curve = dataclasses.replace(curve, site=label, kind=used_kind, unit=name,
                                    source=curve.source + _said(used_kind, name),
                                    component=component, component_source=said)
        what = ("OpenQuake writes PGA and SA in g" if self.format == "openquake"
                else "no unit in the header")
        return check_plausible(curve, given is not None, what)


@dataclass(frozen=True)
class HazardFormat:
    """One hazard file format: how it is recognized and read.

    Attributes
    ----------
    name : str
        Its name (docs, messages).
    recognizes : callable
        ``recognizes(path, head) -> bool``: on the file's path and its first
        :data:`HEAD_LINES` lines, before the file is parsed.
    read : callable
        ``read(path) -> HazardFile``: the whole file parsed once (one-line errors naming the
        file and the line).
    """

    name: str
    recognizes: Callable[[Path, list[str]], bool]
    read: Callable[[Path], HazardFile]


def _text(path: Path) -> str:
    try:
        # utf-8-sig strips a byte-order mark (spreadsheets write one) from the header
        return path.read_text(encoding="utf-8-sig")
    except OSError as exc:
        raise ValueError(f"{path}: cannot read the hazard file ({exc.strerror})") from None
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path}: not a UTF-8 text file (byte {exc.start}: "
                         f"{exc.reason})") from None


def _head(path: Path, n: int = HEAD_LINES) -> list[str]:
    """The first ``n`` non-empty lines of a text file (a byte-order mark stripped)."""
    try:
        with path.open(encoding="utf-8-sig", errors="replace") as fh:
            out = []
            for line in fh:
                if line.strip():
                    out.append(line.rstrip("\r\n"))
                if len(out) >= n:
                    break
            return out
    except OSError as exc:
        raise ValueError(f"{path}: cannot read the hazard file ({exc.strerror})") from None


def _split(text: str) -> tuple[list[str], list[tuple[int, str]]]:
    """Comment lines (``#``) and the other non-empty lines with their line numbers (1 =
    the file's first line)."""
    comments, body = [], []
    for n, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped:
            continue
        (comments if stripped.startswith("#") else body).append(
            line if stripped.startswith("#") else (n, line))
    return comments, body


def _header(head: list[str]) -> list[str]:
    first = next((ln for ln in head if not ln.lstrip().startswith("#")), "")
    return [c.strip() for c in next(csv.reader([first]), [])]


def _openquake_measure(path: Path, comments) -> tuple[Measure, str]:
    """The measure of an OpenQuake file: its comment line's ``imt=``, else its file name;
    both and different refused."""
    hit = _IMT.search(" ".join(comments))
    named = _NAME_IMT.search(path.stem)
    stated = None if hit is None else hazard_measure(hit.group(1), str(path))
    by_name = None if named is None else hazard_measure(named.group(1), str(path))
    if stated is not None and by_name is not None and stated != by_name:
        raise ValueError(f"{path}: its comment line says imt={hit.group(1)!r}, its file name "
                         f"{named.group(1)!r}: which is it? (rename the file or fix the line)")
    if stated is not None:
        return stated, "imt= of its comment line"
    if by_name is not None:
        return by_name, "its file name"
    raise ValueError(f"{path}: no imt in a comment line and none in the file name (an "
                     "OpenQuake hazard_curve CSV starts with a line holding imt='PGA'; its "
                     "name says it, hazard_curve-mean-PGA_1.csv)")


def _read_openquake(path: Path) -> HazardFile:
    """:data:`HAZARD_FORMATS` reader of an OpenQuake hazard-curve CSV: every site at once."""
    comments, body = _split(_text(path))
    meta = " ".join(comments)
    time = _TIME.search(meta)
    if time is None:
        raise ValueError(f"{path}: no investigation_time in a comment line (an OpenQuake "
                         "hazard_curve CSV starts with one)")
    years = positive_finite(f"{path}: investigation_time", time.group(1))
    measure, measure_from = _openquake_measure(path, comments)
    if len(body) < 2:
        raise ValueError(f"{path}: expected a header and at least one site row")
    lines = [n for n, _ in body]
    rows = list(csv.reader(text for _, text in body))
    header = [c.strip() for c in rows[0]]
    cols = [i for i, c in enumerate(header) if c.startswith("poe-")]
    try:
        levels = np.array([float(header[i][4:]) for i in cols])
    except ValueError:
        raise ValueError(f"{path}: line {lines[0]}: unreadable level in the header "
                         f"{[header[i] for i in cols]}") from None
    values = np.full((len(rows) - 1, len(cols)), np.nan)
    for k, values_row in enumerate(rows[1:]):
        try:
            values[k] = [float(values_row[i]) for i in cols]
        except (ValueError, IndexError):
            raise ValueError(f"{path}: line {lines[k + 1]}: unreadable probability of "
                             f"exceedance (the row has {len(values_row)} of "
                             f"{len(header)} columns)") from None
    sites = _sites(header, rows[1:], lines[1:], str(path))
    return HazardFile(path, "openquake", measure, measure_from, tuple(comments),
                      file_kind(comments), _file_component(comments, path), years, levels,
                      values, "poe", sites)


def _read_table(path: Path) -> HazardFile:
    """:data:`HAZARD_FORMATS` reader of a two-column table (one curve: no site)."""
    comments, body = _split(_text(path))
    rows = list(csv.reader(text for _, text in body))
    if len(rows) < 2 or len(rows[0]) != 2:
        raise ValueError(f"{path}: a hazard table has a header of two columns "
                         "(intensity measure, annual_rate or poe) and one row per level")
    first, second = (c.split("[", 1)[0].strip() for c in rows[0])
    try:
        measure, measure_from = hazard_measure(first, str(path)), "its header"
    except ValueError:
        named = _NAME_IMT.search(path.stem)
        if named is None:
            raise
        measure, measure_from = hazard_measure(named.group(1), str(path)), "its file name"
    hit = _HEADER_UNIT.match(rows[0][0].strip())
    try:
        data = np.array([[float(v) for v in r] for r in rows[1:]], dtype=float)
    except ValueError as exc:
        raise ValueError(f"{path}: unreadable number ({exc})") from None
    if data.ndim != 2 or data.shape[1] != 2:
        raise ValueError(f"{path}: every row must have two numbers")
    if second.lower() in RATE_COLUMNS:
        value_kind = "rate"
    elif second.lower() == "poe":
        value_kind = "poe"
    else:
        raise ValueError(f"{path}: the second column must be annual_rate (or rate, lambda) "
                         f"or poe, got {second!r}")
    time = _TIME.search(" ".join(comments))
    return HazardFile(path, "table", measure, measure_from, tuple(comments),
                      file_kind(comments), _file_component(comments, path),
                      None if time is None else positive_finite(f"{path}: investigation_time",
                                                          time.group(1)),
                      data[:, 0], data[:, 1][None, :], value_kind, [],
                      hit.group(2) if hit else None)


HAZARD_FORMATS = (
    HazardFormat("openquake", lambda path, head: any(
        c.startswith("poe-") for c in _header(head)), _read_openquake),
    HazardFormat("table", lambda path, head: len(_header(head)) == 2, _read_table),
)
"""The hazard file formats, tried in order on a file's first lines (:func:`hazard_format`):
an OpenQuake hazard-curve CSV (a header with ``poe-<iml>`` columns), a two-column table."""


def hazard_format(path: str | Path) -> HazardFormat:
    """The format of a hazard file, from its first :data:`HEAD_LINES` lines (the file is not
    parsed); one line naming the file and the formats when none recognizes it."""
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such hazard file")
    head = _head(path)
    for fmt in HAZARD_FORMATS:
        if fmt.recognizes(path, head):
            return fmt
    raise ValueError(f"{path}: not a hazard file this reads: an OpenQuake hazard_curve CSV "
                     "(a comment line with imt= and investigation_time=, then "
                     "[custom_site_id,]lon,lat,...,poe-<iml>,...) or a two-column table "
                     f"(intensity, annual_rate or poe); its first line is "
                     f"{(head[0] if head else '')[:80]!r}")


def read_hazard_file(path: str | Path) -> HazardFile:
    """A hazard file of :data:`HAZARD_FORMATS`, recognized from its first lines, then parsed
    once (every site)."""
    path = Path(path)
    return hazard_format(path).read(path)


def file_sites(path: str | Path) -> list[Site]:
    """The sites (row, ``custom_site_id``, lon, lat, line) of an OpenQuake hazard-curve
    file; [] for a two-column table (a curve of no stated site)."""
    return read_hazard_file(path).sites


def _sites(header: list[str], body: list[list[str]], lines: list[int], where: str) -> list[Site]:
    """The sites of an OpenQuake file; a ``custom_site_id`` or a lon/lat given twice is
    refused naming both lines."""
    names = [c.lower() for c in header]
    col = {n: names.index(n) for n in ("custom_site_id", "lon", "lat") if n in names}

    def number(name, values, line):
        if name not in col:
            return math.nan
        text = values[col[name]] if col[name] < len(values) else ""
        try:
            return float(text)
        except ValueError:
            raise ValueError(f"{where}: line {line}: unreadable {name} {text!r}") from None

    sites, seen_id, seen_at = [], {}, {}
    for row, (values, line) in enumerate(zip(body, lines, strict=True)):
        sid = values[col["custom_site_id"]].strip() if "custom_site_id" in col and \
            col["custom_site_id"] < len(values) else ""
        site = Site(row, sid, number("lon", values, line), number("lat", values, line), line)
        if sid:
            if sid in seen_id:
                raise ValueError(f"{where}: custom_site_id {sid!r} is given twice, lines "
                                 f"{seen_id[sid]} and {line}: which curve is the site's? "
                                 "(give each site one id)")
            seen_id[sid] = line
        if math.isfinite(site.lon) and math.isfinite(site.lat):
            at = (site.lon, site.lat)
            if at in seen_at:
                raise ValueError(f"{where}: lines {seen_at[at]} and {line} are two sites at "
                                 f"the same lon {site.lon:g}, lat {site.lat:g}: which curve is "
                                 "the site's? (keep one, or move it)")
            seen_at[at] = line
        sites.append(site)
    return sites


def _said(kind: str, unit: str) -> str:
    """What a curve's source adds for a kind other than the mean and levels not in g."""
    return ((f", {kind}" if kind not in ("", "mean") else "")
            + (f", levels in {unit} converted to g" if unit != "g" else ""))


HAZARD_KEYS = {"file", "site", "investigation_time", "kind", "unit", "im_factor",
               "component"}
"""Keys of a hazard mapping that names a file."""

POWER_LAW_KEYS = {"k0", "k", "measure", "im_factor", "component"}
"""Keys of a hazard mapping that gives a power law."""

_COMPONENT = re.compile(r"\bcomponent\s*=\s*['\"]?([A-Za-z_0-9]+)")


def _file_component(comments, path: Path) -> str | None:
    """A ``component='rotd50'`` (any case) in a file's comment lines, None without one."""
    hit = _COMPONENT.search(" ".join(comments))
    return None if hit is None else parse_component(hit.group(1), f"{path}: component")


def _declared_component(spec: dict) -> str | None:
    """The hazard mapping's ``component`` key, checked (None without one)."""
    if spec.get("component") is None:
        return None
    if float(spec.get("im_factor", 1.0)) != 1.0:
        raise ValueError("hazard: give component (risk converts the fragility) or "
                         "im_factor (you convert the hazard), not both")
    return parse_component(spec["component"], "hazard.component")


def parse_hazard(spec, *, base: str | Path | None = None,
                 measure: str | None = None, component: str | None = None) -> HazardCurve:
    """A hazard curve from the forms the configuration and the CLI accept.

    Parameters
    ----------
    spec : str, path or dict
        ``"k0,k"`` (a power law), a path to an OpenQuake hazard-curve CSV or a two-column
        table (:func:`read_hazard_file`), or a mapping ``{k0, k[, measure]}`` or
        ``{file[, site][, kind][, unit][, investigation_time]}`` (``site``: a row,
        ``{id}`` or ``{lon, lat[, max_distance_km]}``, :func:`select_site`; ``kind``: the
        statistic to use when the file's is not the mean; ``unit``: of the levels, default
        g); either mapping may add ``component`` (the hazard's horizontal component, any
        case) or ``im_factor`` (see :meth:`HazardCurve.scaled`, default 1), not both.
    base : path, optional
        Directory a relative file path is taken from.
    measure : str, optional
        The intensity measure of a power law given as ``"k0,k"`` (default ``pga``); a file's
        own measure is read from it.
    component : str, optional
        The hazard's component declared outside the entry (``--component``): wins over the
        entry's and the file's.
    """
    entry = dict(spec) if isinstance(spec, dict) else {}
    _declared_component(entry)  # a bad or doubled component refused before the file is read
    if isinstance(spec, dict):
        spec = {k: v for k, v in spec.items() if k not in ("component", "im_factor")}
        if {"k0", "k"} <= set(spec) and set(spec) <= POWER_LAW_KEYS:
            curve = HazardCurve.from_power_law(spec["k0"], spec["k"],
                                               imt=spec.get("measure", measure or "pga"))
        elif "file" in spec and set(spec) <= HAZARD_KEYS:
            curve = read_hazard_file(_resolve(spec["file"], base)).curve(
                spec.get("site"), spec.get("investigation_time"), kind=spec.get("kind"),
                unit=spec.get("unit"))
        else:
            raise ValueError("hazard must be {k0, k[, measure]} or {file[, site][, kind]"
                             "[, unit][, investigation_time]} (optionally component or "
                             f"im_factor), got keys {sorted(spec)}")
    elif isinstance(spec, str | Path):
        text = str(spec)
        path = _resolve(text, base)
        if path.exists():
            curve = read_hazard_file(path).curve()
        else:
            parts = text.split(",")
            try:
                k0, k = (float(parts[0]), float(parts[1])) if len(parts) == 2 else (None, None)
            except ValueError:
                k0 = k = None
            if k0 is None:
                raise ValueError("hazard must be an existing hazard-curve file or a power "
                                 f"law 'k0,k', got {text!r}")
            curve = HazardCurve.from_power_law(k0, k, imt=measure or "pga")
    else:
        raise ValueError(f"hazard must be a file path, 'k0,k' or a mapping, got {spec!r}")
    if curve.note:
        log.warning(curve.note)
    return as_declared(curve, entry, component)


def as_declared(curve: HazardCurve, entry: dict, component: str | None = None) -> HazardCurve:
    """A curve read from a file with what its hazard entry declares: the entry's
    ``component`` (or ``component``, the command line's: it wins) over the file's and the
    default, or the entry's ``im_factor`` (the levels converted by the user,
    :meth:`HazardCurve.scaled`); the two together are refused."""
    declared = _declared_component(entry)
    if component is not None:
        declared = parse_component(component, "--component")
    if declared is not None:  # declared wins over the file's comment and the default
        curve = dataclasses.replace(curve, component=declared, component_source="declared")
    factor = float(entry.get("im_factor", 1.0))
    return curve.scaled(factor) if factor != 1.0 else curve


def _from_poe(iml: np.ndarray, poe: np.ndarray, years: float, imt: str,
              source: str) -> HazardCurve:
    """Annual rates of probabilities of exceedance in ``years``; poe = 0 and poe = 1 levels
    dropped (the latter counted and noted)."""
    if iml.size == 0:
        raise ValueError(f"{source}: the hazard curve is empty (no level)")
    bad = ~np.isfinite(poe) | (poe < 0.0) | (poe > 1.0)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise ValueError(f"{source}: probabilities of exceedance must be in [0, 1], got "
                         f"{poe[i]!r} at {iml[i]:g} g")
    if np.any(np.diff(iml) <= 0.0):
        raise ValueError(f"{source}: intensity levels must be strictly increasing, got "
                         f"{_short(iml)}")
    rise = np.flatnonzero(np.diff(poe) > 0.0)
    if rise.size:
        i = int(rise[0])
        raise ValueError(f"{source}: probabilities of exceedance must not increase with the "
                         f"level, got {poe[i]:.6g} at {iml[i]:g} g and {poe[i + 1]:.6g} at "
                         f"{iml[i + 1]:g} g")
    one = poe >= 1.0
    keep = (poe > 0.0) & ~one
    if keep.sum() < 2:
        raise ValueError(f"{source}: a hazard curve needs at least 2 levels with a "
                         f"probability of exceedance between 0 and 1, got {int(keep.sum())} "
                         f"of {iml.size}")
    rate = -np.log1p(-poe[keep]) / years
    dropped_up_to = float(iml[one].max()) if one.any() else math.nan
    return HazardCurve(iml[keep], rate, imt=imt, source=source, n_dropped=int(one.sum()),
                       dropped_up_to=dropped_up_to)


def _number(name: str, value) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        x = math.nan
    if isinstance(value, bool) or not math.isfinite(x):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    return x


def _short(a: np.ndarray) -> str:
    """An array in one short line (first and last values when long)."""
    a = np.asarray(a, dtype=float)
    if a.size <= 6:
        return "[" + ", ".join(f"{v:.6g}" for v in a) + "]"
    return ("[" + ", ".join(f"{v:.6g}" for v in a[:3]) + ", ..., "
            + ", ".join(f"{v:.6g}" for v in a[-2:]) + f"] ({a.size} values)")


def _resolve(path, base) -> Path:
    p = Path(path)
    return p if p.is_absolute() or base is None else Path(base) / p


__all__ = ["HAZARD_FORMATS", "HAZARD_KEYS", "MAX_DISTANCE_KM", "MAX_PLAUSIBLE_G",
           "OPENQUAKE_COMPONENT", "POWER_LAW_IML", "POWER_LAW_KEYS", "UNITS", "HazardCurve",
           "HazardFile", "HazardFormat", "Site", "as_declared", "check_kind", "check_plausible",
           "file_kind", "file_sites", "great_circle_km", "hazard_format", "hazard_measure",
           "lon_lat_problem", "parse_hazard", "read_hazard_file", "select_site", "unit_factor"]
