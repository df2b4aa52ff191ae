"""Seismic hazard curves: the mean annual rate λ(im) at which PGA exceeds im at a site.

A :class:`HazardCurve` is a table of intensity levels [g] and their annual rates of exceedance
[1/yr], from a power law (λ = k0·im^−k) or from an OpenQuake hazard-curve CSV. Between levels
the curve is interpolated log-log (a piecewise power law, the shape hazard curves have
locally); beyond either end the first or last segment's log-log slope is extrapolated
(see :mod:`rocking.risk.annual_frequency` for why and for how much that end contributes).
"""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

POWER_LAW_IML = np.geomspace(1e-3, 10.0, 41)
"""Levels [g] at which a power-law curve is tabulated (exact there and, log-log, between)."""

_TIME = re.compile(r"investigation_time\s*=\s*['\"]?([0-9.eE+-]+)")
_IMT = re.compile(r"imt\s*=\s*['\"]?([A-Za-z0-9().]+)")


@dataclass(frozen=True, eq=False)
class HazardCurve:
    """Annual rate of exceedance of PGA at a site, tabulated at increasing levels.

    Parameters
    ----------
    im_g : array_like
        Intensity levels, PGA [g], strictly increasing, > 0.
    annual_rate : array_like
        Mean annual rate of exceedance λ at each level [1/yr], > 0 and non-increasing.
    imt : str
        Intensity measure type (``"PGA"``; others are refused by the readers).
    source : str
        Where the curve came from (a file path, or the power law), for tables and reports.
    """

    im_g: np.ndarray
    annual_rate: np.ndarray
    imt: str = "PGA"
    source: str = ""

    def __post_init__(self) -> None:
        im = np.asarray(self.im_g, dtype=float).ravel()
        lam = np.asarray(self.annual_rate, dtype=float).ravel()
        if im.size != lam.size:
            raise ValueError(f"im_g and annual_rate must have the same length, got {im.size} "
                             f"and {lam.size}")
        if im.size < 2:
            raise ValueError(f"a hazard curve needs at least 2 levels, got {im.size}")
        if np.any(~np.isfinite(im) | (im <= 0.0)) or np.any(np.diff(im) <= 0.0):
            raise ValueError(f"im_g must be finite, > 0 and strictly increasing, got {im}")
        if np.any(~np.isfinite(lam) | (lam <= 0.0)):
            raise ValueError("annual_rate must be finite and > 0 (a zero rate has no log-log "
                             f"slope; drop those levels), got {lam}")
        if np.any(np.diff(lam) > 0.0):
            raise ValueError(f"annual_rate must not increase with im_g, got {lam}")
        if self.imt != "PGA":
            raise ValueError(f"imt must be 'PGA' (the study's intensity measure), got "
                             f"{self.imt!r}")
        object.__setattr__(self, "im_g", im)
        object.__setattr__(self, "annual_rate", lam)

    @classmethod
    def from_power_law(cls, k0: float, k: float, im_g=None) -> HazardCurve:
        """λ(im) = k0·im^−k, tabulated at ``im_g`` (default :data:`POWER_LAW_IML`).

        Parameters
        ----------
        k0 : float
            Annual rate of exceeding 1 g [1/yr], > 0.
        k : float
            Log-log slope of the hazard curve [-], > 0.
        im_g : array_like, optional
            Levels [g]. The log-log interpolation and extrapolation reproduce the power law
            exactly everywhere, so the levels only bound what "inside the table" means.
        """
        k0, k = _positive("k0", k0), _positive("k", k)
        im = POWER_LAW_IML if im_g is None else np.asarray(im_g, dtype=float)
        return cls(im, k0 * im ** (-k), source=f"power law k0={k0:g}/yr, k={k:g}")

    @classmethod
    def from_openquake_csv(cls, path: str | Path, site: int = 0) -> HazardCurve:
        """Read one site of an OpenQuake ``hazard_curve-*.csv``.

        The file has a comment line holding ``investigation_time`` T [yr] and ``imt``, then a
        header ``lon,lat[,depth],poe-<iml>,...`` and one row per site of probabilities of
        exceedance in T. They become annual rates by λ = −ln(1 − poe)/T (Poisson). Levels with
        poe = 0 are dropped (no rate to interpolate in log-log); poe = 1 is refused.

        Parameters
        ----------
        path : path
            The CSV file.
        site : int
            Row of the site (0 = first).
        """
        path = Path(path)
        with path.open(newline="") as fh:
            lines = fh.read().splitlines()
        comments = [ln for ln in lines if ln.startswith("#")]
        body = [ln for ln in lines if ln.strip() and not ln.startswith("#")]
        meta = " ".join(comments)
        time, imt = _TIME.search(meta), _IMT.search(meta)
        if time is None or imt is None:
            raise ValueError(f"{path}: no comment line with investigation_time and imt "
                             "(an OpenQuake hazard_curve CSV starts with one)")
        years = float(time.group(1))
        if not years > 0:
            raise ValueError(f"{path}: investigation_time must be > 0, got {years!r}")
        if imt.group(1) != "PGA":
            raise ValueError(f"{path}: imt must be 'PGA' (the study's intensity), got "
                             f"{imt.group(1)!r}")
        rows = list(csv.reader(body))
        if len(rows) < 2:
            raise ValueError(f"{path}: expected a header and at least one site row")
        header, sites = rows[0], rows[1:]
        cols = [i for i, name in enumerate(header) if name.startswith("poe-")]
        if not cols:
            raise ValueError(f"{path}: no poe-<iml> columns in the header {header}")
        if not 0 <= site < len(sites):
            raise ValueError(f"site must be in 0..{len(sites) - 1} for {path}, got {site!r}")
        iml = np.array([float(header[i][4:]) for i in cols])
        poe = np.array([float(sites[site][i]) for i in cols])
        if np.any((poe < 0.0) | (poe >= 1.0)):
            raise ValueError(f"{path}: poe must be in [0, 1) (poe = 1 is an infinite rate), "
                             f"got {poe}")
        keep = poe > 0.0
        rate = -np.log1p(-poe[keep]) / years
        return cls(iml[keep], rate, imt="PGA", source=f"{path} (site {site})")

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

        Converts a hazard computed for another definition of PGA to the study's: a curve
        of the geometric mean or RotD50 becomes one of the vector peak (RotD100) with the
        ratio RotD100/RotD50 as ``factor`` (docs/risk.md).
        """
        factor = _positive("factor", factor)
        note = f", levels x{factor:g}" if factor != 1.0 else ""
        return HazardCurve(self.im_g * factor, self.annual_rate, self.imt, self.source + note)


def parse_hazard(spec, *, base: str | Path | None = None) -> HazardCurve:
    """A hazard curve from the forms the configuration and the CLI accept.

    Parameters
    ----------
    spec : str, path or dict
        ``"k0,k"`` (a power law), a path to an OpenQuake hazard-curve CSV, or a mapping
        ``{k0, k}`` or ``{file, site}``; either mapping may add ``im_factor`` (see
        :meth:`HazardCurve.scaled`, default 1).
    base : path, optional
        Directory a relative file path is taken from.
    """
    factor = 1.0
    if isinstance(spec, dict):
        spec = dict(spec)
        factor = spec.pop("im_factor", 1.0)
        if set(spec) == {"k0", "k"}:
            curve = HazardCurve.from_power_law(spec["k0"], spec["k"])
        elif "file" in spec and set(spec) <= {"file", "site"}:
            curve = HazardCurve.from_openquake_csv(_resolve(spec["file"], base),
                                                   int(spec.get("site", 0)))
        else:
            raise ValueError("hazard must be {k0, k} or {file, site} (optionally im_factor), "
                             f"got keys {sorted(spec)}")
    elif isinstance(spec, str | Path):
        text = str(spec)
        path = _resolve(text, base)
        if path.exists():
            curve = HazardCurve.from_openquake_csv(path)
        else:
            parts = text.split(",")
            try:
                k0, k = (float(parts[0]), float(parts[1])) if len(parts) == 2 else (None, None)
            except ValueError:
                k0 = k = None
            if k0 is None:
                raise ValueError("hazard must be an existing OpenQuake hazard-curve CSV or a "
                                 f"power law 'k0,k', got {text!r}")
            curve = HazardCurve.from_power_law(k0, k)
    else:
        raise ValueError(f"hazard must be a file path, 'k0,k' or a mapping, got {spec!r}")
    return curve.scaled(float(factor)) if factor != 1.0 else curve


def _positive(name: str, value) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        x = math.nan
    if isinstance(value, bool) or not (math.isfinite(x) and x > 0):
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return x


def _resolve(path, base) -> Path:
    p = Path(path)
    return p if p.is_absolute() or base is None else Path(base) / p


__all__ = ["POWER_LAW_IML", "HazardCurve", "parse_hazard"]
