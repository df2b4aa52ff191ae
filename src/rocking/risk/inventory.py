"""An inventory of columns: a CSV read, checked and given its hazard sites before any work.

One row per column (free-standing monolithic column, pier, statue ...):

=========================  ====  =============================================================
column                     unit  meaning
=========================  ====  =============================================================
id                         –     unique name of the column (required), kept as text (``007``
                                 stays ``007``)
height, diameter           m     its height 2h and diameter 2b (both, or R and tan_alpha)
R, tan_alpha               m, –  semi-diagonal and slenderness instead (both); beside height
                                 and diameter they must agree with them
mu                         –     support friction coefficient (optional, ≥ 0): carried into
                                 portfolio.csv, not used (:meth:`Inventory.unused_note`)
lon, lat                   deg   position (optional; both or neither; lon in [−180, 180], lat
                                 in [−90, 90]): the hazard site is the nearest within
                                 ``max_distance_km`` (5 km by default)
site                       –     a hazard file's ``custom_site_id`` instead (optional)
anything else              –     carried through to portfolio.csv untouched
=========================  ====  =============================================================

Inventories are read as people keep them: column names in any case, with a unit suffix
(``height_m``, ``height [m]``, ``height (cm)``, ``diameter_mm``: converted to m; ``lon
[deg]``), ``longitude``/``latitude`` for ``lon``/``lat``; a semicolon- or tab-separated
export, with decimal commas, is read as such and said so (:attr:`Inventory.notes`); a
UTF-8 byte-order mark is stripped, a Windows-1252 file read as such. Rows are numbered as a
spreadsheet shows them: the file's lines, the header (or the first comment line) row 1.

Height and diameter become R and tan α as everywhere in the project
(:func:`rocking.dynamics.dimensions.body_size`). Every row is checked before any fragility
or λ is computed, and each bad row is named in one line with its row, id, column and value:
an empty or duplicate id, no dimensions, a dimension that is not a length > 0 (or R and
tan α that contradict them), a column beyond the surface's grid (unless extrapolation is
asked for), lon without lat or off the Earth, a ``site`` not in the hazard file, no site
within the distance, no lon/lat and no site with a hazard file of several sites. Each hint
aims at the likely mistake: height and diameter swapped, sizes in mm or cm, lon and lat
swapped. By default the first bad row refuses the inventory (the line says how many rows
are bad); with ``skip_invalid`` the bad rows are left out, each listed with its reason
(:attr:`Inventory.skipped`), and counted — never dropped silently.
"""

from __future__ import annotations

import csv
import math
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from rocking._validate import positive_finite
from rocking.dynamics.dimensions import body_size
from rocking.risk.hazard import (
    MAX_DISTANCE_KM,
    HazardCurve,
    Site,
    as_declared,
    great_circle_km,
    lon_lat_problem,
    parse_hazard,
    read_hazard_file,
)

COLUMNS = ("id", "height", "diameter", "R", "tan_alpha", "mu", "lon", "lat", "site")
"""Columns an inventory reads (``id`` and one pair of dimensions required); any other is
carried through."""

NUMERIC = ("height", "diameter", "R", "tan_alpha", "mu", "lon", "lat")


@dataclass(frozen=True, eq=False)
class HazardSites:
    """The hazard curves an inventory may use: every site of a file, or one curve.

    The file is parsed once (:func:`rocking.risk.hazard.read_hazard_file`); a site's curve
    is made when a column first asks for it (:meth:`curve`), so a regional file of 10,000
    sites costs one parse and the curves of the sites the columns use.

    Attributes
    ----------
    sites : list of Site
        Their row, ``custom_site_id``, lon and lat (NaN where the hazard states none: a
        two-column table or a power law).
    source : str
        The hazard given, for the one-line errors.
    measure : str
        The hazard's intensity measure (``"pga"``, ``"sa:1.0"``).
    component : str or None
        Its horizontal component (:attr:`rocking.risk.hazard.HazardCurve.component`).
    component_note : str
        What the output says of where the component comes from ('' when declared or read).
    """

    sites: list[Site]
    source: str
    make: Callable[[int], HazardCurve] = field(repr=False)
    measure: str = "pga"
    component: str | None = None
    component_note: str = ""
    _made: dict = field(default_factory=dict, repr=False)

    @property
    def several(self) -> bool:
        return len(self.sites) > 1

    def curve(self, k: int) -> HazardCurve:
        """The hazard curve of site ``k`` (made once)."""
        if k not in self._made:
            self._made[k] = self.make(k)
        return self._made[k]


def read_hazard_sites(spec, *, site=None, kind: str | None = None, unit: str | None = None,
                      component: str | None = None) -> HazardSites:
    """Every site of a hazard file (or the one ``site`` names), or one curve.

    Parameters
    ----------
    spec : str, path or dict
        An OpenQuake hazard-curve CSV, a two-column table, a power law ``"k0,k"``, or a
        study's ``hazard:`` mapping (:func:`rocking.risk.hazard.parse_hazard`; its ``site``
        is the study's, not the columns': left out; its ``component``, ``kind``, ``unit``
        and ``im_factor`` apply to every site).
    site : int or dict, optional
        Use only this site of the file for every column (a row, ``{"id"}`` or ``{"lon",
        "lat"[, "max_distance_km"]}``, :func:`rocking.risk.hazard.select_site`).
    kind, unit, component : str, optional
        As the hazard entry's keys (given here, they win over the entry's).
    """
    entry = ({k: v for k, v in spec.items() if k != "site"} if isinstance(spec, dict)
             else {"file": str(spec)})
    for key, value in (("kind", kind), ("unit", unit), ("component", component)):
        if value is not None:
            entry[key] = value
    name = str(entry.get("file", spec))
    path = Path(name)
    if "file" not in entry or not path.is_file():
        curve = parse_hazard(entry if "file" not in entry else name)
        return _one(curve, str(spec))
    hazard = read_hazard_file(path)
    if not hazard.sites or site is not None:
        curve = parse_hazard({**entry, **({"site": site} if site is not None else {})})
        row = next((s for s in hazard.sites if curve.site.startswith(s.label)), None)
        return _one(curve, str(path), row)
    def make(k: int) -> HazardCurve:
        return as_declared(hazard.curve_at(k, kind=entry.get("kind"), unit=entry.get("unit")),
                           entry)

    probe = make(0)  # kind, unit, component: checked once, on the file already parsed

    return HazardSites(hazard.sites, str(path), make, probe.measure, probe.component,
                       probe.component_note)


def _one(curve: HazardCurve, source: str, site: Site | None = None) -> HazardSites:
    """One curve for every column."""
    return HazardSites([site or Site(0, "", math.nan, math.nan)], source, lambda k: curve,
                       curve.measure, curve.component, curve.component_note)


@dataclass(frozen=True)
class Inventory:
    """The valid columns of an inventory, with their hazard site, and the rows left out.

    Attributes
    ----------
    columns : pandas.DataFrame
        One row per valid column: ``id`` (text), ``lon``, ``lat``, ``site`` (as given),
        ``height``, ``diameter`` [m] (NaN where R and tan α were given), ``R`` [m],
        ``tan_alpha`` [-], ``mu`` [-], ``row`` (the row as a spreadsheet numbers it),
        ``hazard_index`` (into :attr:`HazardSites.sites`), ``hazard_distance_km`` [km] (NaN
        without lon/lat or a located site).
    skipped : pandas.DataFrame
        ``row``, ``id``, ``column``, ``reason`` of each row left out (``skip_invalid``).
    source : str
        The file read.
    extra : pandas.DataFrame or None
        The inventory's further columns of the valid rows, as text, in its order.
    notes : list of str
        How the file was read, where that is worth saying (its separator and decimal mark,
        its encoding, columns converted from mm or cm).
    """

    columns: pd.DataFrame
    skipped: pd.DataFrame
    source: str = ""
    extra: pd.DataFrame | None = None
    notes: list[str] = field(default_factory=list)

    def skipped_note(self) -> str:
        """One line counting and listing the rows left out ('' when none)."""
        if self.skipped.empty:
            return ""
        items = "; ".join(f"row {r.row} (id {r.id}) {r.column}: {r.reason}"
                          for r in self.skipped.itertuples())
        return f"{len(self.skipped)} row(s) of {self.source} skipped: {items}"

    def unused_note(self) -> str:
        """One line when the inventory gives ``mu`` ('' otherwise): it is carried, not used
        (the surface is the study's fragility of tilt and overturning; no column is checked
        for sliding at its own μ)."""
        given = int(np.isfinite(self.columns["mu"].to_numpy(float)).sum())
        if not given:
            return ""
        return (f"{self.source}: mu of {given} column(s) carried into portfolio.csv and not "
                "used: the fragilities are the study's (tilt and overturning, its own "
                "contact); a column that may slide needs a study with its mu "
                "(studies.<name>.mu) or a sliding:<mu> limit state")


class _Bad(Exception):
    def __init__(self, column: str, reason: str):
        super().__init__(reason)
        self.column, self.reason = column, reason


NAMES = {"id": "id", "height": "height", "diameter": "diameter", "r": "R",
         "tan_alpha": "tan_alpha", "mu": "mu", "lon": "lon", "longitude": "lon",
         "lat": "lat", "latitude": "lat", "site": "site"}
"""Column names read (any case) → the inventory's name."""

LENGTH_UNITS = {"m": 1.0, "cm": 0.01, "mm": 0.001}
"""Units a length column may name in its title → factor to m."""

ANGLE_UNITS = ("deg", "degree", "degrees", "°")

_TITLE = re.compile(r"^\s*(.*?)\s*(?:\[\s*([^\]]*?)\s*\]|\(\s*([^)]*?)\s*\))?\s*$")
_DECIMAL_COMMA = re.compile(r"^\s*[-+]?\d+,\d+\s*$")

MAX_PLAUSIBLE_LENGTH_M = 100.0
"""A height or diameter above this [m], in a column without a unit, is taken for a
length in mm or cm (the hint says so)."""


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
        One line naming the file, the row (as a spreadsheet numbers it), the id and the
        column of the first bad row, and how many rows are bad.
    """
    path = Path(path)
    frame, lines, factors, untitled, extra_names, notes = _read(path)
    n = len(frame)
    ids = frame["id"].fillna("").astype(str).str.strip() if "id" in frame else \
        pd.Series([""] * n)
    bad: dict[int, tuple[str, str]] = {}
    out = pd.DataFrame({"id": ids, "row": lines})
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
                                   first_of, lines, factors, untitled)
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
            for i in np.flatnonzero(outside):
                bad[int(i)] = _outside(out.loc[i], surface)
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
        raise ValueError(f"{path}: row {lines[i]} (id {ids.iloc[i] or '?'}), column {column}: "
                         f"{reason}{more}")
    skipped = pd.DataFrame([{"row": lines[i], "id": ids.iloc[i], "column": c, "reason": r}
                            for i, (c, r) in sorted(bad.items())],
                           columns=["row", "id", "column", "reason"])
    keep = [i for i in range(n) if i not in bad]
    if not keep:
        raise ValueError(f"{path}: no valid column ({n} row(s), all bad: row "
                         f"{skipped['row'].iloc[0] if n else 0}: "
                         f"{skipped['reason'].iloc[0] if n else 'the file has no rows'})")
    extra = frame[extra_names].iloc[keep].reset_index(drop=True) if extra_names else None
    return Inventory(out.iloc[keep].reset_index(drop=True), skipped, str(path), extra, notes)


def _outside(row, surface) -> tuple[str, str]:
    """Why a column beyond the grid is refused, aimed at the likely mistake."""
    r0, r1, t0, t1 = surface.bounds()
    R, ta = float(row["R"]), float(row["tan_alpha"])
    col = "R" if not r0 * (1 - 1e-9) <= R <= r1 * (1 + 1e-9) else "tan_alpha"
    grid = (f"outside the surface's grid (R {R:.4g} m, tan α {ta:.4g}; the grid spans "
            f"R {r0:g}–{r1:g} m, tan α {t0:g}–{t1:g})")
    h, d = float(row["height"]), float(row["diameter"])
    if math.isfinite(h) and math.isfinite(d) and d > h and not surface.outside(R, h / d):
        return "height", (f"{grid}: height {h:g} m is below diameter {d:g} m: swapped? "
                          f"(swapped, tan α {d / h:.4g} → {h / d:.4g}, inside the grid)")
    if R > 50 * r1:
        return col, f"{grid}: sizes in mm or cm? (give metres, or name the column height_mm)"
    return col, f"{grid}; allow extrapolation to have it answered and marked"


def _encoded(path: Path) -> tuple[str, str]:
    """The file's text and, for a file that is not UTF-8, a note naming the encoding."""
    raw = path.read_bytes()
    try:
        return raw.decode("utf-8-sig"), ""
    except UnicodeDecodeError:
        return raw.decode("cp1252", errors="replace"), (
            f"{path}: not UTF-8, read as Windows-1252 (a spreadsheet's export)")


def _title(name: str, path: Path) -> tuple[str | None, str | None]:
    """A column title → (the inventory's name or None for an extra column, its unit)."""
    hit = _TITLE.match(str(name))
    base, unit = hit.group(1), hit.group(2) or hit.group(3)
    key = base.strip().lower().replace(" ", "_")
    if key in NAMES:
        return NAMES[key], unit
    stem, _, suffix = key.rpartition("_")
    if stem in NAMES and unit is None and (suffix in LENGTH_UNITS or suffix in ANGLE_UNITS):
        return NAMES[stem], suffix
    return None, None


def _read(path: Path):
    """The inventory's cells as text, each row's line number, the unit factors of its
    length columns, the length columns without a unit, its further columns and the notes."""
    if not path.is_file():
        raise ValueError(f"--inventory: no such file: {str(path)!r}")
    text, enc_note = _encoded(path)
    lines = text.splitlines()
    body = [(n, ln) for n, ln in enumerate(lines, start=1)
            if ln.strip() and not ln.lstrip().startswith("#")]
    if not body:
        raise ValueError(f"{path}: no header and no rows (an inventory has id and height, "
                         "diameter or R, tan_alpha)")
    head = body[0][1]
    sep = max((",", ";", "\t"), key=head.count)
    notes = [enc_note] if enc_note else []
    rows = list(csv.reader([ln for _, ln in body], delimiter=sep, skipinitialspace=True))
    width = len(rows[0])
    for (n, _), r in zip(body[1:], rows[1:], strict=True):
        if len(r) != width:
            hint = (": a decimal comma in a comma-separated file? (export with ';' as the "
                    "separator, or with decimal points)" if sep == "," and len(r) > width
                    else "")
            raise ValueError(f"{path}: row {n} has {len(r)} fields, the header {width}"
                             f"{hint}")
    decimal = sep != "," and any(_DECIMAL_COMMA.match(c) for r in rows[1:] for c in r)
    if sep != ",":
        notes.append(f"{path}: read as {'semicolon' if sep == ';' else 'tab'}-separated"
                     + (" with decimal commas" if decimal else ""))
    titles = [c.strip() for c in rows[0]]
    names, units, extra = [], {}, []
    for t in titles:
        name, unit = _title(t, path)
        if name is None:
            names.append(t)
            extra.append(t)
            continue
        if name in names:
            raise ValueError(f"{path}: two columns are {name} ({t!r} and another): keep one")
        names.append(name)
        units[name] = unit
    if "id" not in names:
        raise ValueError(f"{path}: no id column (an inventory has id; height and diameter "
                         f"or R and tan_alpha; optional mu, lon, lat, site); its columns: "
                         f"{', '.join(titles)}")
    dims = {"height", "diameter"} <= set(names) or {"R", "tan_alpha"} <= set(names)
    if not dims:
        guess = [t for t in extra if t.lower()[:1] in "hdr"]
        raise ValueError(f"{path}: no dimensions: give the columns height and diameter [m], "
                         "or R [m] and tan_alpha [-]"
                         + (f" (read as further columns: {', '.join(guess)}: misspelled?)"
                            if guess else ""))
    factors, untitled = {}, set()
    for name, unit in units.items():
        if name in ("height", "diameter", "R"):
            if unit is None:
                untitled.add(name)
                continue
            if unit.lower() not in LENGTH_UNITS:
                raise ValueError(f"{path}: column {name} in {unit!r}: give m, cm or mm")
            factors[name] = LENGTH_UNITS[unit.lower()]
            if factors[name] != 1.0:
                notes.append(f"{path}: {name} read in {unit}, converted to m")
        elif unit is not None and name in ("lon", "lat") and unit.lower() not in ANGLE_UNITS:
            raise ValueError(f"{path}: column {name} in {unit!r}: give degrees")
        elif unit is not None and name not in ("lon", "lat") and unit not in ("-", ""):
            raise ValueError(f"{path}: column {name} in {unit!r}: it has no unit")
    cells = [r for r in rows[1:]]
    if decimal:
        cells = [[c.replace(",", ".") if _DECIMAL_COMMA.match(c) else c for c in r]
                 for r in cells]
    frame = pd.DataFrame(cells, columns=names, dtype=str)
    return frame, [n for n, _ in body[1:]], factors, untitled, extra, notes


def _number(text, name: str) -> float | None:
    if text is None or (isinstance(text, float) and math.isnan(text)) or str(text).strip() == "":
        return None
    try:
        value = float(text)
    except ValueError:
        hint = " (a decimal comma? export with decimal points, or ';' as the separator)" \
            if _DECIMAL_COMMA.match(str(text)) else ""
        raise _Bad(name, f"not a number: {text!r}{hint}") from None
    if not math.isfinite(value):
        raise _Bad(name, f"must be finite, got {text!r}")
    return value


def _check_row(texts: dict, ident: str, i: int, first_of: dict, lines: list[int],
               factors: dict, untitled: set) -> list[float]:
    if not ident:
        raise _Bad("id", "empty id")
    if ident in first_of:
        raise _Bad("id", f"id {ident!r} duplicates row {lines[first_of[ident]]}")
    first_of[ident] = i
    v = {name: _number(texts[name], name) for name in NUMERIC}
    for name, factor in factors.items():
        if v[name] is not None:
            v[name] *= factor
    for name in ("height", "diameter", "R", "tan_alpha"):
        if v[name] is not None:
            try:
                positive_finite(name, v[name])
            except ValueError as exc:  # the row and column prefix the one check's line
                raise _Bad(name, str(exc)) from None
    for name in ("height", "diameter", "R"):
        if name in untitled and v[name] is not None and v[name] > MAX_PLAUSIBLE_LENGTH_M:
            raise _Bad(name, f"{v[name]:g} m is no column's size: in mm or cm? (give metres, "
                       f"or name the column {name}_mm or '{name} [cm]')")
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
    if v["lon"] is not None:
        problem = lon_lat_problem(v["lon"], v["lat"])
        if problem:
            raise _Bad("lon", problem)
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
    index = np.full(len(out), -1)
    distance = np.full(len(out), np.nan)
    nearest, dist = _nearest(lon, lat, located, slon, slat)
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
            d = (float(great_circle_km(lon[i], lat[i], slon[k], slat[k]))
                 if located[i] and math.isfinite(slon[k]) else math.nan)
        elif not hazard.several:
            k = 0
            d = (float(great_circle_km(lon[i], lat[i], slon[0], slat[0]))
                 if located[i] and math.isfinite(slon[0]) else math.nan)
        elif not located[i]:
            bad[i] = ("lon", f"no lon/lat and no site, and the hazard {hazard.source} has "
                      f"{len(hazard.sites)} sites: give the column's lon and lat, or site")
            continue
        elif not math.isfinite(dist[i]):
            bad[i] = ("lon", f"the hazard {hazard.source} has no lon/lat to locate the column")
            continue
        else:
            k, d = int(nearest[i]), float(dist[i])
        if math.isfinite(d) and d > limit:
            bad[i] = ("lon", _too_far(hazard, k, d, limit, lon[i], lat[i], slon, slat))
            continue
        index[i], distance[i] = k, d
    out["hazard_index"], out["hazard_distance_km"] = index, distance


def _nearest(lon, lat, located, slon, slat) -> tuple[np.ndarray, np.ndarray]:
    """The nearest site of every located column and its distance [km] (−1, NaN else),
    in chunks of columns: a file of 10,000 sites never builds a (columns × sites) matrix
    larger than a few million distances."""
    nearest = np.full(lon.size, -1)
    dist = np.full(lon.size, np.nan)
    have = np.isfinite(slon) & np.isfinite(slat)
    if not have.any():
        return nearest, dist
    which = np.flatnonzero(have)
    rows = np.flatnonzero(located)
    step = max(1, 2_000_000 // which.size)
    for start in range(0, rows.size, step):
        r = rows[start:start + step]
        d = great_circle_km(lon[r, None], lat[r, None], slon[None, which], slat[None, which])
        j = np.argmin(d, axis=1)
        nearest[r], dist[r] = which[j], d[np.arange(r.size), j]
    return nearest, dist


def _too_far(hazard: HazardSites, k: int, d: float, limit: float, lon: float, lat: float,
             slon, slat) -> str:
    """Why the nearest site is refused, aimed at the likely mistake: lon and lat swapped
    (swapped, the column lies within the distance of a site)."""
    line = (f"the nearest hazard site, {hazard.sites[k].label}, is {d:.3g} km away, beyond "
            f"{limit:g} km")
    if -90.0 <= lon <= 90.0 and math.isfinite(lat):
        have = np.isfinite(slon) & np.isfinite(slat)
        if have.any():
            swapped = great_circle_km(lat, lon, slon[have], slat[have])
            j = int(np.argmin(swapped))
            if swapped[j] <= limit:
                site = hazard.sites[int(np.flatnonzero(have)[j])]
                return (f"{line}: lon and lat swapped? (lon {lat:g}, lat {lon:g} is "
                        f"{float(swapped[j]):.3g} km from {site.label})")
    return f"{line} (raise --max-distance-km to take it)"


__all__ = ["COLUMNS", "HazardSites", "Inventory", "read_hazard_sites", "read_inventory"]
