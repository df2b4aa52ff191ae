"""Seismic hazard curves: the mean annual rate λ(im) at which an intensity im is exceeded at a site.

A :class:`HazardCurve` is a table of intensity levels [g] and their annual rates of exceedance
[1/yr], in one intensity measure: PGA or Sa(T) (OpenQuake's ``PGA``, ``SA(1.0)``; the study's
``pga``, ``sa:1.0``, :mod:`rocking.motions.measures`). It comes from a power law
(λ = k0·im^−k), an OpenQuake hazard-curve CSV, or a plain two-column table (intensity and
annual rate, or intensity and probability of exceedance in a stated investigation time).
Between levels the curve is interpolated log-log (a piecewise power law, the shape hazard
curves have locally); beyond either end the first or last segment's log-log slope is
extrapolated (see :mod:`rocking.risk.annual_frequency` for why and for how much that end
contributes).

Engines write probabilities of exceedance with six significant digits, so the lowest levels
of a 50-year curve read ``1.000000E+00``: an infinite rate. Those levels are dropped (said
once, in one line, and kept on the curve as :attr:`HazardCurve.n_dropped` and
:attr:`HazardCurve.dropped_up_to`); the part of λ_LS that rests on the intensities below the
first kept level is ``below_first`` of :func:`rocking.risk.annual_frequency.annual_frequency_parts`
(``share_below_first`` in the risk table, with a warning when it is large).

Regional runs write many sites to one file: :func:`select_site` picks one by ``custom_site_id``,
by the nearest lon/lat within :data:`MAX_DISTANCE_KM` (great-circle) or by row, and refuses a
file of several sites when none is named. The file's ``kind`` (``mean``, ``quantile-0.85``,
``rlz-000``) is read from its comment line; anything but the mean is used only when the
configuration names it. Levels are read in the file's unit (a header ``pga [cm/s2]``, the
configuration's ``unit``, else g: the unit OpenQuake writes PGA and SA in) and converted to g;
levels implausible in g are refused in one line (:func:`check_plausible`). A UTF-8 byte-order
mark is stripped.
"""

from __future__ import annotations

import csv
import dataclasses
import logging
import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rocking._validate import positive_finite
from rocking.motions.measures import SA_NAME, parse_measure

log = logging.getLogger(__name__)

POWER_LAW_IML = np.geomspace(1e-3, 10.0, 41)
"""Levels [g] at which a power-law curve is tabulated (exact there and, log-log, between)."""

_TIME = re.compile(r"investigation_time\s*=\s*['\"]?([0-9.eE+-]+)")
_IMT = re.compile(r"\bimt\s*=\s*['\"]?([A-Za-z0-9().:]+)")
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


def imt_measure(imt: str) -> str:
    """The study's name of an intensity measure type: ``"PGA"`` → ``"pga"``,
    ``"SA(1.0)"`` → ``"sa:1"``; the study's own names (``"pga"``, ``"sa:1.0"``) are accepted
    too. Raises ValueError for any other (PGV and the rest: the study's PGV is in m/s, an
    engine's in cm/s, so it is refused rather than guessed)."""
    text = str(imt).strip()
    hit = SA_NAME.match(text)
    if hit:
        text = f"sa:{hit.group(1)}"
    try:
        kind, period = parse_measure(text)
    except ValueError:
        kind, period = "", None
    if kind == "pga":
        return "pga"
    if kind == "sa":
        return f"sa:{period:g}"
    raise ValueError(f"intensity measure type {imt!r} is not supported: use PGA or SA(T) "
                     "(e.g. SA(1.0)), in g")


def measure_imt(measure: str) -> str:
    """OpenQuake's name of a study measure: ``"pga"`` → ``"PGA"``, ``"sa:1"`` → ``"SA(1.0)"``."""
    kind, period = parse_measure(imt_measure(measure))
    if kind == "pga":
        return "PGA"
    return f"SA({period:.1f})" if period == round(period, 1) else f"SA({period:g})"


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
        The horizontal component the hazard declares (the entry's ``component``, else a
        ``component=`` comment of its file, read with the levels), None where unsaid.
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
        object.__setattr__(self, "imt", measure_imt(self.imt))
        object.__setattr__(self, "im_g", im)
        object.__setattr__(self, "annual_rate", lam)

    @property
    def measure(self) -> str:
        """The study's name of the curve's intensity measure (``"pga"``, ``"sa:1"``)."""
        return imt_measure(self.imt)

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
        return cls(im, k0 * im ** (-k), imt=imt,
                   source=f"power law k0={k0:g}/yr, k={k:g} ({measure_imt(imt)})")

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
        path = Path(path)
        return _openquake(path, *_read_csv(path), site, kind, unit)

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
        path = Path(path)
        return _table(path, *_read_csv(path), investigation_time, kind, unit)

    @classmethod
    def from_file(cls, path: str | Path, site=None, investigation_time: float | None = None,
                  *, kind: str | None = None, unit: str | None = None) -> HazardCurve:
        """A hazard file of any format of :data:`HAZARD_FORMATS`, read once and handed to the
        first format that recognizes it (arguments as :meth:`from_openquake_csv` and
        :meth:`from_table`)."""
        path = Path(path)
        comments, rows = _read_csv(path)
        fmt = next(f for f in HAZARD_FORMATS if f.recognizes(rows))
        curve = fmt.read(path, comments, rows, site, investigation_time, kind, unit)
        component = _file_component(comments, path)
        return curve if component is None else dataclasses.replace(curve, component=component)

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

        Converts a hazard computed for another definition of the measure to the study's: a
        curve of the geometric mean or RotD50 becomes one of the vector peak (RotD100) with
        the ratio RotD100/RotD50 as ``factor`` (docs/risk.md).
        """
        factor = positive_finite("factor", factor)
        note = f", levels x{factor:g}" if factor != 1.0 else ""
        # replace() carries every metadata field (site, kind, unit, ...) unchanged
        return dataclasses.replace(self, im_g=self.im_g * factor, source=self.source + note,
                                   dropped_up_to=self.dropped_up_to * factor)


@dataclass(frozen=True)
class Site:
    """One site (row) of an OpenQuake hazard-curve file."""

    row: int
    id: str  # custom_site_id ('' when the file has none)
    lon: float  # [deg]
    lat: float  # [deg]

    @property
    def label(self) -> str:
        """``"b (lon 10.1, lat 45)"`` or ``"row 1 (lon 10.1, lat 45)"``."""
        name = f"id {self.id}" if self.id else f"row {self.row}"
        return f"{name} (lon {self.lon:g}, lat {self.lat:g})"


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
        if not (-180.0 <= lon <= 360.0 and -90.0 <= lat <= 90.0):
            raise ValueError(f"{where}: site lon {lon:g}, lat {lat:g} is not a point on Earth "
                             "(lon in [-180, 360], lat in [-90, 90] degrees)")
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
           "--hazard-unit) or a header such as 'pga [cm/s2]'")
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


def file_sites(path: str | Path) -> list[Site]:
    """The sites (row, ``custom_site_id``, lon, lat) of an OpenQuake hazard-curve file; []
    for a two-column table (a curve of no stated site). Read each site's curve with
    :meth:`HazardCurve.from_file` and ``site=<row>``."""
    path = Path(path)
    _, rows = _read_csv(path)
    if not rows or not any(c.strip().startswith("poe-") for c in rows[0]):
        return []
    return _sites(rows[0], rows[1:], str(path))


def _sites(header: list[str], body: list[list[str]], where: str) -> list[Site]:
    names = [c.strip().lower() for c in header]
    col = {n: names.index(n) for n in ("custom_site_id", "lon", "lat") if n in names}
    sites = []
    for row, values in enumerate(body):
        def get(name, values=values, row=row):
            if name not in col:
                return math.nan
            try:
                return float(values[col[name]])
            except (ValueError, IndexError):
                raise ValueError(f"{where}: site row {row}: unreadable {name} "
                                 f"{values[col[name]] if col[name] < len(values) else ''!r}"
                                 ) from None

        sid = values[col["custom_site_id"]].strip() if "custom_site_id" in col and \
            col["custom_site_id"] < len(values) else ""
        sites.append(Site(row, sid, get("lon"), get("lat")))
    return sites


def _openquake(path: Path, comments: list[str], rows: list[list[str]], site, kind,
               unit) -> HazardCurve:
    """One site of an OpenQuake hazard-curve file already read (:meth:`from_openquake_csv`)."""
    meta = " ".join(comments)
    time, imt = _TIME.search(meta), _IMT.search(meta)
    if time is None or imt is None:
        missing = " and ".join(n for n, m in (("investigation_time", time), ("imt", imt))
                               if m is None)
        raise ValueError(f"{path}: no {missing} in a comment line (an OpenQuake "
                         "hazard_curve CSV starts with one)")
    years = positive_finite(f"{path}: investigation_time", time.group(1))
    measure = _file_measure(path, imt.group(1))
    used_kind = check_kind(file_kind(comments), kind, str(path))
    name, factor = unit_factor(unit, str(path)) if unit is not None else ("g", 1.0)
    if len(rows) < 2:
        raise ValueError(f"{path}: expected a header and at least one site row")
    header, body = rows[0], rows[1:]
    cols = [i for i, c in enumerate(header) if c.strip().startswith("poe-")]
    if not cols:
        raise ValueError(f"{path}: no poe-<iml> columns in the header {header}")
    chosen, label = select_site(_sites(header, body, str(path)), site, str(path))
    try:
        iml = np.array([float(header[i].strip()[4:]) for i in cols]) * factor
        poe = np.array([float(body[chosen.row][i]) for i in cols])
    except (ValueError, IndexError) as exc:
        raise ValueError(f"{path}: site {chosen.label}: unreadable level or probability "
                         f"({exc})") from None
    curve = _from_poe(iml, poe, years, measure, f"{path}, site {chosen.label}")
    curve = dataclasses.replace(curve, site=label, kind=used_kind, unit=name,
                                source=curve.source + _said(used_kind, name))
    return check_plausible(curve, unit is not None, "OpenQuake writes PGA and SA in g")


def _table(path: Path, comments: list[str], rows: list[list[str]], investigation_time, kind,
           unit) -> HazardCurve:
    """A two-column hazard table already read (:meth:`from_table`)."""
    if len(rows) < 2 or len(rows[0]) != 2:
        raise ValueError(f"{path}: a hazard table has a header of two columns "
                         "(intensity measure, annual_rate or poe) and one row per level")
    first, second = (c.split("[", 1)[0].strip() for c in rows[0])
    measure = _file_measure(path, first)
    hit = _HEADER_UNIT.match(rows[0][0])
    stated = hit.group(2) if hit else None
    if stated is not None and unit is not None and \
            unit_factor(stated, str(path))[0] != unit_factor(unit, str(path))[0]:
        raise ValueError(f"{path}: the header gives the levels in {stated!r}, the hazard "
                         f"entry in {unit!r}")
    given = stated if stated is not None else unit
    name, factor = unit_factor(given, str(path)) if given is not None else ("g", 1.0)
    used_kind = check_kind(file_kind(comments), kind, str(path))
    try:
        data = np.array([[float(v) for v in r] for r in rows[1:]], dtype=float)
    except ValueError as exc:
        raise ValueError(f"{path}: unreadable number ({exc})") from None
    if data.ndim != 2 or data.shape[1] != 2:
        raise ValueError(f"{path}: every row must have two numbers")
    im, value = data[:, 0] * factor, data[:, 1]
    if second.lower() in RATE_COLUMNS:
        if investigation_time is not None:
            raise ValueError(f"{path}: investigation_time is given but the table holds "
                             f"annual rates (column {second!r}); it applies to a poe column "
                             "only")
        curve = HazardCurve(im, value, imt=measure, source=str(path))
    elif second.lower() != "poe":
        raise ValueError(f"{path}: the second column must be annual_rate (or rate, lambda) "
                         f"or poe, got {second!r}")
    else:
        if investigation_time is None:
            hit = _TIME.search(" ".join(comments))
            if hit is None:
                raise ValueError(f"{path}: a poe column needs its investigation time: "
                                 "hazard {file, investigation_time} or a comment line "
                                 "'# investigation_time=50'")
            investigation_time = hit.group(1)
        years = positive_finite(f"{path}: investigation_time", investigation_time)
        curve = _from_poe(im, value, years, measure, str(path))
    curve = dataclasses.replace(curve, kind=used_kind, unit=name,
                                source=curve.source + _said(used_kind, name))
    return check_plausible(curve, given is not None, "no unit in the header")


def _said(kind: str, unit: str) -> str:
    """What a curve's source adds for a kind other than the mean and levels not in g."""
    return ((f", {kind}" if kind not in ("", "mean") else "")
            + (f", levels in {unit} converted to g" if unit != "g" else ""))


def _read_openquake(path: Path, comments: list[str], rows: list[list[str]], site,
                    investigation_time, kind, unit) -> HazardCurve:
    """:data:`HAZARD_FORMATS` reader of an OpenQuake CSV (it states its own time)."""
    if investigation_time is not None:
        raise ValueError(f"{path}: an OpenQuake hazard curve states its own "
                         "investigation_time; leave it out of the hazard entry")
    return _openquake(path, comments, rows, site, kind, unit)


def _read_table(path: Path, comments: list[str], rows: list[list[str]], site,
                investigation_time, kind, unit) -> HazardCurve:
    """:data:`HAZARD_FORMATS` reader of a two-column table (one curve: no site)."""
    if site is not None:
        raise ValueError(f"{path}: site applies to an OpenQuake hazard-curve CSV of "
                         f"sites, this is a two-column table (got site {site!r})")
    return _table(path, comments, rows, investigation_time, kind, unit)


@dataclass(frozen=True)
class HazardFormat:
    """One hazard file format: how it is recognized and read.

    Attributes
    ----------
    name : str
        Its name (docs, messages).
    recognizes : callable
        ``recognizes(rows) -> bool`` on the file's non-comment CSV rows (header first).
    read : callable
        ``read(path, comments, rows, site, investigation_time, kind, unit) -> HazardCurve``
        (levels in g, rates in 1/yr; a stated argument the format cannot use is refused in
        one line naming the file).
    """

    name: str
    recognizes: Callable[[list[list[str]]], bool]
    read: Callable[..., HazardCurve]


HAZARD_FORMATS = (
    HazardFormat("openquake", lambda rows: bool(rows) and any(
        c.strip().startswith("poe-") for c in rows[0]), _read_openquake),
    HazardFormat("table", lambda rows: True, _read_table),
)
"""The hazard file formats, tried in order (:meth:`HazardCurve.from_file`): an OpenQuake
hazard-curve CSV (a header with ``poe-<iml>`` columns), else a two-column table (the last
recognizes every file and refuses a malformed one itself)."""


HAZARD_KEYS = {"file", "site", "investigation_time", "kind", "unit", "im_factor",
               "component"}
"""Keys of a hazard mapping that names a file."""

POWER_LAW_KEYS = {"k0", "k", "measure", "im_factor", "component"}
"""Keys of a hazard mapping that gives a power law."""

_COMPONENT = re.compile(r"\bcomponent\s*=\s*['\"]?([A-Za-z_0-9]+)")


def _file_component(comments: list[str], path: Path) -> str | None:
    """A ``component='rotd50'`` in a file's comment lines, None without one."""
    from rocking.motions.measures import parse_component

    hit = _COMPONENT.search(" ".join(comments))
    return None if hit is None else parse_component(hit.group(1), f"{path}: component")


def _declared_component(spec: dict) -> str | None:
    """The hazard mapping's ``component`` key, checked (None without one)."""
    from rocking.motions.measures import parse_component

    if "component" not in spec:
        return None
    if float(spec.get("im_factor", 1.0)) != 1.0:
        raise ValueError("hazard: give component (risk converts the fragility) or "
                         "im_factor (you convert the hazard), not both")
    return parse_component(spec["component"], "hazard.component")


def hazard_component(spec, *, base: str | Path | None = None) -> str | None:
    """The horizontal component of a hazard's intensity measure, or None where unsaid.

    The hazard entry's ``component`` key (:data:`rocking.motions.measures.COMPONENTS`), else
    a ``component='rotd50'`` in a comment line of its file (OpenQuake does not write one; a
    file prepared by hand may). A ``component`` together with ``im_factor`` is refused: the
    first asks risk to compute the fragility in the hazard's component, the second to
    rescale the hazard by hand, and the two would convert twice. Where the curve is parsed
    anyway, read :attr:`HazardCurve.component` of :func:`parse_hazard` instead (the file
    read once).

    Parameters
    ----------
    spec : str, path or dict
        The hazard entry as :func:`parse_hazard` takes it.
    base : path, optional
        Directory a relative file path is taken from.
    """
    if isinstance(spec, dict):
        declared = _declared_component(spec)
        if declared is not None:
            return declared
        name = spec.get("file")
    else:
        name = spec
    if name is None:
        return None
    path = _resolve(str(name), base)
    if not path.is_file():
        return None
    comments, _ = _read_csv(path)
    return _file_component(comments, path)


def parse_hazard(spec, *, base: str | Path | None = None,
                 measure: str | None = None) -> HazardCurve:
    """A hazard curve from the forms the configuration and the CLI accept.

    Parameters
    ----------
    spec : str, path or dict
        ``"k0,k"`` (a power law), a path to an OpenQuake hazard-curve CSV or a two-column
        table (:meth:`HazardCurve.from_file`), or a mapping ``{k0, k[, measure]}`` or
        ``{file[, site][, kind][, unit][, investigation_time]}`` (``site``: a row,
        ``{id}`` or ``{lon, lat[, max_distance_km]}``, :func:`select_site`; ``kind``: the
        statistic to use when the file's is not the mean; ``unit``: of the levels, default
        g); either mapping may add ``im_factor`` (see :meth:`HazardCurve.scaled`, default 1).
    base : path, optional
        Directory a relative file path is taken from.
    measure : str, optional
        The intensity measure of a power law given as ``"k0,k"`` (default ``pga``); a file's
        own measure is read from it.
    """
    factor, declared = 1.0, None
    if isinstance(spec, dict):
        declared = _declared_component(spec)
        spec = dict(spec)
        factor = spec.pop("im_factor", 1.0)
        spec.pop("component", None)
        if {"k0", "k"} <= set(spec) and set(spec) <= POWER_LAW_KEYS:
            curve = HazardCurve.from_power_law(spec["k0"], spec["k"],
                                               imt=spec.get("measure", measure or "pga"))
        elif "file" in spec and set(spec) <= HAZARD_KEYS:
            curve = HazardCurve.from_file(_resolve(spec["file"], base), spec.get("site"),
                                          spec.get("investigation_time"),
                                          kind=spec.get("kind"), unit=spec.get("unit"))
        else:
            raise ValueError("hazard must be {k0, k[, measure]} or {file[, site][, kind]"
                             "[, unit][, investigation_time]} (optionally im_factor), got "
                             f"keys {sorted(spec)}")
    elif isinstance(spec, str | Path):
        text = str(spec)
        path = _resolve(text, base)
        if path.exists():
            curve = HazardCurve.from_file(path)
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
    if declared is not None:  # the entry's key wins over the file's comment
        curve = dataclasses.replace(curve, component=declared)
    return curve.scaled(float(factor)) if factor != 1.0 else curve


def _read_csv(path: Path) -> tuple[list[str], list[list[str]]]:
    """Comment lines (``#``) and the other non-empty rows of a CSV file."""
    try:
        # utf-8-sig strips a byte-order mark (spreadsheets write one) from the header
        with path.open(newline="", encoding="utf-8-sig") as fh:
            lines = fh.read().splitlines()
    except OSError as exc:
        raise ValueError(f"{path}: cannot read the hazard file ({exc.strerror})") from None
    except UnicodeDecodeError as exc:
        raise ValueError(f"{path}: not a UTF-8 text file (byte {exc.start}: "
                         f"{exc.reason})") from None
    comments = [ln for ln in lines if ln.lstrip().startswith("#")]
    body = [ln for ln in lines if ln.strip() and not ln.lstrip().startswith("#")]
    return comments, list(csv.reader(body))


def _file_measure(path: Path, imt: str) -> str:
    try:
        return imt_measure(imt)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None


def _from_poe(iml: np.ndarray, poe: np.ndarray, years: float, measure: str,
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
    return HazardCurve(iml[keep], rate, imt=measure, source=source, n_dropped=int(one.sum()),
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
           "POWER_LAW_IML", "POWER_LAW_KEYS", "UNITS", "HazardCurve", "HazardFormat", "Site",
           "check_kind", "check_plausible", "file_kind", "file_sites", "great_circle_km",
           "hazard_component", "imt_measure", "measure_imt", "parse_hazard",
           "select_site", "unit_factor"]
