"""An inventory of columns: a CSV read, checked and given its hazard sites before any work.

One row per column (free-standing monolithic column, pier, statue ...):

=========================  ====  =============================================================
column                     unit  meaning
=========================  ====  =============================================================
id                         –     unique name of the column (required)
height, diameter           m     its height 2h and diameter 2b (both, or R and tan_alpha)
R, tan_alpha               m, –  semi-diagonal and slenderness instead (both); beside height
                                 and diameter they must agree with them
mu                         –     support friction coefficient (optional, ≥ 0; carried into
                                 portfolio.csv)
lon, lat                   deg   position (optional; both or neither): the hazard site is the
                                 nearest within ``max_distance_km`` (5 km by default)
site                       –     a hazard file's ``custom_site_id`` instead (optional)
=========================  ====  =============================================================

Height and diameter become R and tan α as everywhere in the project
(:func:`rocking.dynamics.dimensions.body_size`). Every row is checked before any fragility
or λ is computed, and each bad row is named in one line with its column: an unknown column,
an empty or duplicate id, no dimensions, a dimension that is not a length > 0 (or R and
tan α that contradict them), a column beyond the surface's grid (unless extrapolation is
asked for), lon without lat, a ``site`` not in the hazard file, no site within the distance,
no lon/lat and no site with a hazard file of several sites. By default the first bad row
refuses the inventory (the line says how many rows are bad); with ``skip_invalid`` the bad
rows are left out, each listed with its reason (:attr:`Inventory.skipped`), and counted —
never dropped silently.
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from rocking.dynamics.dimensions import body_size
from rocking.risk.hazard import (
    MAX_DISTANCE_KM,
    HazardCurve,
    Site,
    file_sites,
    great_circle_km,
    parse_hazard,
)

COLUMNS = ("id", "height", "diameter", "R", "tan_alpha", "mu", "lon", "lat", "site")
"""Columns an inventory may have (``id`` and one pair of dimensions required)."""

NUMERIC = ("height", "diameter", "R", "tan_alpha", "mu", "lon", "lat")


@dataclass(frozen=True)
class HazardSites:
    """The hazard curves an inventory may use: every site of a file, or one curve.

    Attributes
    ----------
    curves : list of HazardCurve
        One per site.
    sites : list of Site
        Their row, ``custom_site_id``, lon and lat (NaN where the hazard states none: a
        two-column table or a power law).
    source : str
        The hazard given, for the one-line errors.
    """

    curves: list[HazardCurve]
    sites: list[Site]
    source: str

    @property
    def several(self) -> bool:
        return len(self.curves) > 1


def read_hazard_sites(spec, *, site=None, kind: str | None = None,
                      unit: str | None = None) -> HazardSites:
    """Every site of a hazard file (or the one ``site`` names), or one curve.

    Parameters
    ----------
    spec : str or path
        An OpenQuake hazard-curve CSV, a two-column table or a power law ``"k0,k"``
        (:func:`rocking.risk.hazard.parse_hazard`).
    site : int or dict, optional
        Use only this site of the file for every column (a row, ``{"id"}`` or ``{"lon",
        "lat"[, "max_distance_km"]}``, :func:`rocking.risk.hazard.select_site`).
    kind, unit : str, optional
        As for :meth:`rocking.risk.hazard.HazardCurve.from_file`.
    """
    path = Path(str(spec))
    sites = file_sites(path) if path.is_file() else []
    if not sites:
        extra = {k: v for k, v in (("kind", kind), ("unit", unit)) if v is not None}
        curve = parse_hazard({"file": str(path), **extra} if path.is_file() and extra else spec)
        return HazardSites([curve], [Site(0, "", math.nan, math.nan)], str(spec))
    if site is not None:
        curve = HazardCurve.from_file(path, site, kind=kind, unit=unit)
        row = _site_row(sites, curve)
        return HazardSites([curve], [sites[row]], str(spec))
    curves = [HazardCurve.from_file(path, s.row, kind=kind, unit=unit) for s in sites]
    return HazardSites(curves, sites, str(spec))


def _site_row(sites: list[Site], curve: HazardCurve) -> int:
    """The row of the site a curve was read from (its label starts the curve's site)."""
    for s in sites:
        if curve.site.startswith(s.label):
            return s.row
    return 0


@dataclass(frozen=True)
class Inventory:
    """The valid columns of an inventory, with their hazard site, and the rows left out.

    Attributes
    ----------
    columns : pandas.DataFrame
        One row per valid column: ``id``, ``lon``, ``lat``, ``site`` (as given), ``height``,
        ``diameter`` [m] (NaN where R and tan α were given), ``R`` [m], ``tan_alpha`` [-],
        ``mu`` [-], ``row`` (1-based data row of the file), ``hazard_index`` (into
        :attr:`HazardSites.curves`), ``hazard_distance_km`` [km] (NaN without lon/lat or
        a located site).
    skipped : pandas.DataFrame
        ``row``, ``id``, ``column``, ``reason`` of each row left out (``skip_invalid``).
    source : str
        The file read.
    """

    columns: pd.DataFrame
    skipped: pd.DataFrame
    source: str = ""

    def skipped_note(self) -> str:
        """One line counting and listing the rows left out ('' when none)."""
        if self.skipped.empty:
            return ""
        items = "; ".join(f"row {r.row} (id {r.id}) {r.column}: {r.reason}"
                          for r in self.skipped.itertuples())
        return f"{len(self.skipped)} row(s) of {self.source} skipped: {items}"


class _Bad(Exception):
    def __init__(self, column: str, reason: str):
        super().__init__(reason)
        self.column, self.reason = column, reason


def read_inventory(path: str | Path, *, surface=None, hazard: HazardSites | None = None,
                   extrapolate: bool = False, skip_invalid: bool = False,
                   max_distance_km: float = MAX_DISTANCE_KM) -> Inventory:
    """Read and check an inventory CSV (module docstring: its columns and what is refused).

    Parameters
    ----------
    path : path
        The CSV file (``#`` lines are comments).
    surface : rocking.fragility.surface.FragilitySurface, optional
        Columns beyond its grid are refused (or, with ``extrapolate``, kept).
    hazard : HazardSites, optional
        Each column is given its site (``hazard_index``, ``hazard_distance_km``).
    extrapolate : bool
        Keep columns beyond the surface's grid (portfolio.csv marks them).
    skip_invalid : bool
        Leave bad rows out (listed in :attr:`Inventory.skipped`) instead of refusing.
    max_distance_km : float
        Farthest a hazard site may be from a column's lon/lat [km].

    Raises
    ------
    ValueError
        One line naming the file, the row (1 = the first data row, comment lines not
        counted), the id and the column of the first bad row, and how many rows are bad.
    """
    path = Path(path)
    frame = _read(path)
    n = len(frame)
    ids = frame["id"].fillna("").astype(str).str.strip() if "id" in frame else \
        pd.Series([""] * n)
    bad: dict[int, tuple[str, str]] = {}
    out = pd.DataFrame({"id": ids, "row": np.arange(1, n + 1)})
    for name in NUMERIC:
        out[name] = np.nan
    out["site"] = (frame["site"].fillna("").astype(str).str.strip() if "site" in frame
                   else "")
    first_of: dict[str, int] = {}
    texts = {name: frame[name].tolist() if name in frame.columns else [None] * n
             for name in NUMERIC}
    values = np.full((n, len(NUMERIC)), np.nan)
    id_list = ids.tolist()
    for i in range(n):
        try:
            values[i] = _check_row({k: t[i] for k, t in texts.items()}, id_list[i], i,
                                   first_of)
        except _Bad as exc:
            bad[i] = (exc.column, exc.reason)
    for j, name in enumerate(NUMERIC):
        out[name] = values[:, j]
    ok = np.array([i not in bad for i in range(n)])
    if surface is not None and ok.any():
        outside = np.zeros(n, bool)
        outside[ok] = surface.outside(out.loc[ok, "R"].to_numpy(float),
                                      out.loc[ok, "tan_alpha"].to_numpy(float))
        if not extrapolate:
            r0, r1, t0, t1 = surface.bounds()
            for i in np.flatnonzero(outside):
                R, ta = out.loc[i, "R"], out.loc[i, "tan_alpha"]
                col = "R" if not r0 * (1 - 1e-9) <= R <= r1 * (1 + 1e-9) else "tan_alpha"
                bad[int(i)] = (col, f"outside the surface's grid (R {R:.4g} m, tan α {ta:.4g}; "
                               f"the grid spans R {r0:g}–{r1:g} m, tan α {t0:g}–{t1:g}; "
                               "allow extrapolation to have it answered and marked)")
        out["extrapolated"] = outside
    else:
        out["extrapolated"] = False
    out["hazard_index"], out["hazard_distance_km"] = -1, np.nan
    if hazard is not None:
        _assign_sites(out, hazard, bad, max_distance_km)
    if bad and not skip_invalid:
        i = min(bad)
        column, reason = bad[i]
        more = f" ({len(bad)} bad rows in all; skip them with --skip-invalid)" \
            if len(bad) > 1 else ""
        raise ValueError(f"{path}: row {i + 1} (id {ids.iloc[i] or '?'}), column {column}: "
                         f"{reason}{more}")
    skipped = pd.DataFrame([{"row": i + 1, "id": ids.iloc[i], "column": c, "reason": r}
                            for i, (c, r) in sorted(bad.items())],
                           columns=["row", "id", "column", "reason"])
    keep = [i for i in range(n) if i not in bad]
    if not keep:
        raise ValueError(f"{path}: no valid column ({n} row(s), all bad: row "
                         f"{skipped['row'].iloc[0] if n else 0}: "
                         f"{skipped['reason'].iloc[0] if n else 'the file has no rows'})")
    return Inventory(out.iloc[keep].reset_index(drop=True), skipped, str(path))


def _read(path: Path) -> pd.DataFrame:
    if not path.is_file():
        raise ValueError(f"--inventory: no such file: {str(path)!r}")
    try:
        # whole lines starting with # are comments (pandas' comment= would also cut an id
        # such as "T#1" short)
        text = "".join(line for line in path.read_text(encoding="utf-8-sig").splitlines(True)
                       if not line.lstrip().startswith("#"))
        frame = pd.read_csv(io.StringIO(text), dtype=str, skipinitialspace=True)
    except (pd.errors.ParserError, UnicodeDecodeError, pd.errors.EmptyDataError) as exc:
        raise ValueError(f"{path}: not a readable CSV inventory "
                         f"({str(exc).splitlines()[0][:120]})") from None
    frame.columns = [str(c).strip() for c in frame.columns]
    unknown = [c for c in frame.columns if c not in COLUMNS]
    if unknown:
        raise ValueError(f"{path}: unknown column {unknown[0]!r} (an inventory has "
                         f"{', '.join(COLUMNS)})")
    if "id" not in frame.columns:
        raise ValueError(f"{path}: no id column (an inventory has {', '.join(COLUMNS)})")
    dims = ({"height", "diameter"} <= set(frame.columns)
            or {"R", "tan_alpha"} <= set(frame.columns))
    if not dims:
        raise ValueError(f"{path}: no dimensions: give the columns height and diameter [m], "
                         "or R [m] and tan_alpha [-]")
    return frame


def _number(text, name: str) -> float | None:
    if text is None or (isinstance(text, float) and math.isnan(text)) or str(text).strip() == "":
        return None
    try:
        value = float(text)
    except ValueError:
        raise _Bad(name, f"not a number: {text!r}") from None
    if not math.isfinite(value):
        raise _Bad(name, f"must be finite, got {text!r}")
    return value


def _check_row(texts: dict, ident: str, i: int, first_of: dict) -> list[float]:
    if not ident:
        raise _Bad("id", "empty id")
    if ident in first_of:
        raise _Bad("id", f"id {ident!r} duplicates row {first_of[ident] + 1}")
    first_of[ident] = i
    v = {name: _number(texts[name], name) for name in NUMERIC}
    for name in ("height", "diameter", "R", "tan_alpha"):
        if v[name] is not None and v[name] <= 0:
            raise _Bad(name, f"must be > 0, got {v[name]:g}")
    if v["height"] is not None or v["diameter"] is not None:
        try:
            R, ta = body_size(v["height"], v["diameter"], R=None if v["R"] is None else [v["R"]],
                              tan_alpha=v["tan_alpha"])
        except ValueError as exc:
            msg = str(exc)
            col = msg.split()[0] if msg.split()[0] in NUMERIC else "height"
            if "go together" in msg:
                col = "diameter" if v["diameter"] is None else "height"
            raise _Bad(col, msg) from None
    elif v["R"] is not None and v["tan_alpha"] is not None:
        R, ta = v["R"], v["tan_alpha"]
    else:
        missing = "tan_alpha" if v["R"] is not None else "R" if v["tan_alpha"] is not None \
            else "height"
        raise _Bad(missing, "no dimensions: give height and diameter [m], or R [m] and "
                   "tan_alpha [-]")
    if v["mu"] is not None and v["mu"] < 0:
        raise _Bad("mu", f"must be ≥ 0, got {v['mu']:g}")
    if (v["lon"] is None) != (v["lat"] is None):
        raise _Bad("lat" if v["lat"] is None else "lon", "lon and lat go together")
    if v["lon"] is not None and not (-180 <= v["lon"] <= 360 and -90 <= v["lat"] <= 90):
        raise _Bad("lon", f"lon {v['lon']:g}, lat {v['lat']:g} is not a point on Earth")
    nan = math.nan
    return [nan if v["height"] is None else v["height"],
            nan if v["diameter"] is None else v["diameter"], R, ta,
            nan if v["mu"] is None else v["mu"], nan if v["lon"] is None else v["lon"],
            nan if v["lat"] is None else v["lat"]]


def _assign_sites(out: pd.DataFrame, hazard: HazardSites, bad: dict, limit: float) -> None:
    """Each good row's hazard site (in place): its ``site`` id, else the nearest to its
    lon/lat within ``limit`` km; one curve serves all (distance checked where known)."""
    slon = np.array([s.lon for s in hazard.sites], float)
    slat = np.array([s.lat for s in hazard.sites], float)
    ids = {s.id: k for k, s in enumerate(hazard.sites) if s.id}
    lon, lat = out["lon"].to_numpy(float), out["lat"].to_numpy(float)
    located = np.isfinite(lon) & np.isfinite(lat)
    dist = np.full((len(out), len(hazard.sites)), np.nan)
    if located.any() and np.isfinite(slon).any():
        dist[located] = great_circle_km(lon[located, None], lat[located, None],
                                        slon[None, :], slat[None, :])
    nearest = np.where(located & np.isfinite(dist).any(axis=1),
                       np.argmin(np.where(np.isfinite(dist), dist, np.inf), axis=1), -1)
    index = np.full(len(out), -1)
    distance = np.full(len(out), np.nan)
    site_ids = out["site"].tolist()
    for i in range(len(out)):
        if i in bad:
            continue
        sid = site_ids[i]
        if sid:
            if sid not in ids:
                shown = ", ".join(list(ids)[:5]) or "none: the hazard has no custom_site_id"
                bad[i] = ("site", f"site {sid!r} is not in the hazard {hazard.source} (its "
                          f"ids: {shown})")
                continue
            k = ids[sid]
        elif not hazard.several:
            k = 0
        elif not located[i]:
            bad[i] = ("lon", f"no lon/lat and no site, and the hazard {hazard.source} has "
                      f"{len(hazard.sites)} sites: give the column's lon and lat, or site")
            continue
        elif not np.isfinite(dist[i]).any():
            bad[i] = ("lon", f"the hazard {hazard.source} has no lon/lat to locate the column")
            continue
        else:
            k = int(nearest[i])
        d = float(dist[i, k])
        if math.isfinite(d) and d > limit:
            bad[i] = ("lon", f"the nearest hazard site, {hazard.sites[k].label}, is {d:.3g} km "
                      f"away, beyond {limit:g} km (raise --max-distance-km to take it)")
            continue
        index[i], distance[i] = k, d
    out["hazard_index"], out["hazard_distance_km"] = index, distance


__all__ = ["COLUMNS", "HazardSites", "Inventory", "read_hazard_sites", "read_inventory"]
