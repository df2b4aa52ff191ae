"""Strong-motion record files: readers for PEER AT2 and plain text, and two-component pairs.

:func:`read_at2` reads PEER ``.AT2`` files: the NGA-West2 header (``NPTS=  5372, DT=
.0100 SEC,`` with a trailing comma), the older PEER 2000 header (``NPTS=  4000, DT= .01000
SEC``), the reversed ``4000  .0100  NPTS, DT`` line, and fixed-width layouts declared in the
header (e.g. the ``8F10.5`` "Peknold" El Centro). :func:`read_text` reads plain one-column
(acceleration, ``dt`` given) or two-column (time, acceleration) text. :func:`read_record`
picks the right reader and converts to m/s²; :func:`read_pair` puts two components on one
time axis.

Every malformed file (bad header, NPTS disagreeing with the data, a non-numeric token, NaN or
infinity, dt <= 0, a non-uniform time column, a number not written in the file's format such as
a last value cut before its exponent, a data line holding fewer values than the others) raises
:class:`RecordFormatError` naming the file and the line, so a record is never silently
truncated or padded. The named records of the study
are in :mod:`rocking.motions.catalogue`.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rocking._validate import positive_finite
from rocking.constants import G
from rocking.motions.motion import GroundMotion
from rocking.provenance import file_sha256

__all__ = [
    "Record",
    "RecordFormatError",
    "UNIT_FACTORS",
    "file_sha256",
    "header_azimuth",
    "pair_from_records",
    "read_at2",
    "read_pair",
    "read_record",
    "read_text",
    "with_vertical",
]

UNIT_FACTORS: dict[str, float] = {
    "g": G,
    "m/s2": 1.0,
    "m/s^2": 1.0,
    "cm/s2": 0.01,
    "cm/s^2": 0.01,
    "gal": 0.01,
}
"""Multipliers from the unit a file is written in to m/s²."""

# Header patterns. Regular expressions, not columns: the NGA-West2 line has variable spacing
# and a trailing comma that fixed-column readers trip over.
_NPTS_DT = re.compile(
    r"NPTS\s*=\s*(?P<npts>[^\s,]+)\s*,?\s*DT\s*=\s*(?P<dt>[^\s,]+)", re.IGNORECASE
)
_NPTS_DT_REVERSED = re.compile(
    r"^\s*(?P<npts>\S+)\s+(?P<dt>\S+)\s+NPTS\s*,\s*DT\b", re.IGNORECASE
)
_FORTRAN_FORMAT = re.compile(r"\b(\d+)\s*[FEG](\d+)\.(\d+)\b", re.IGNORECASE)
_UNITS = re.compile(r"UNITS\s+(?:OF|ARE|IN)\s*\(?\s*(?P<unit>CM/S(?:EC)?(?:/S(?:EC)?|2|\^2)|G)\b",
                    re.IGNORECASE)
_AZIMUTH = re.compile(
    r",\s*(?P<az>\d{1,3}|UP|DWN|DOWN|V)\s*(?:\([^)]*\))?\s*$", re.IGNORECASE
)
_HEADER_SCAN_LINES = 12


class RecordFormatError(ValueError):
    """A record file that cannot be read as it is; the message names the file and the line."""

    def __init__(self, path: str | Path, line: int | None, message: str) -> None:
        where = f"{path}" if line is None else f"{path}, line {line}"
        super().__init__(f"{where}: {message}")
        self.path = str(path)
        self.line = line


@dataclass(frozen=True, eq=False)
class Record:
    """One component read from a file.

    Parameters
    ----------
    acc : numpy.ndarray
        Acceleration [m/s²].
    dt : float
        Time step [s].
    meta : dict
        Provenance: ``file``, ``path``, ``sha256``, ``format``, ``units_file``, ``npts``,
        ``azimuth`` (degrees, ``"UP"`` or None), ``header`` lines, ``processing`` (list).
    """

    acc: np.ndarray
    dt: float
    meta: dict[str, Any] = field(default_factory=dict)

    def __iter__(self):
        # Lets ``acc, dt, meta = read_record(path)`` work as the contract describes.
        return iter((self.acc, self.dt, self.meta))


def _unit_factor(units: str) -> float:
    key = str(units).strip().lower()
    if key not in UNIT_FACTORS:
        raise ValueError(f"units must be one of {sorted(UNIT_FACTORS)}, got {units!r}")
    return UNIT_FACTORS[key]


def _read_lines(path: Path) -> list[str]:
    if path.is_dir():
        raise RecordFormatError(path, None, "is a directory, not a record file")
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise FileNotFoundError(f"record file not found: {path}") from None
    if not raw.strip():
        raise RecordFormatError(path, None, "the file is empty")
    # latin-1 never fails, so odd header bytes cannot hide the data behind a decode error.
    return raw.decode("latin-1").splitlines()


def _parse_float(token: str, path: Path, line: int) -> float:
    try:
        # Fortran writes double-precision exponents with D.
        value = float(token.replace("D", "E").replace("d", "e"))
    except ValueError:
        raise RecordFormatError(path, line, f"non-numeric value {token!r}") from None
    if not math.isfinite(value):
        raise RecordFormatError(path, line, f"non-finite value {token!r}")
    return value


_NUMBER_SHAPE = re.compile(r"[+-]?\d*\.(?P<frac>\d+)(?:[EeDd](?P<exp>[+-]?\d+))?")

_SHAPE_SAMPLE = 20
"""Values of a plain-text column that must share one number format for the column to be
read strictly (AT2 data always are)."""


def _shape(token: str) -> tuple[int, int] | None:
    """(digits after the point, exponent characters; -1 without exponent) of a number
    written with a decimal point, or None for other writings (integers)."""
    m = _NUMBER_SHAPE.fullmatch(token)
    if m is None:
        return None
    return len(m.group("frac")), -1 if m.group("exp") is None else len(m.group("exp"))


def _check_shapes(tokens: list[str], lines: list[int], path: Path, strict: bool) -> None:
    """Every number written like the first one: the same digits after the point and the same
    exponent (``.1773449E-03`` everywhere, never ``.1773449``). A file cut inside its last
    number (its exponent lost) would otherwise be read as a value 10^k times too large.

    ``strict`` (AT2 data, written by one Fortran format): any number not written like the
    first is an error. Otherwise (plain text, perhaps written with ``%g``) only a column whose
    first :data:`_SHAPE_SAMPLE` values share one format is held to it.
    """
    if not tokens:
        return
    first = _shape(tokens[0])
    if first is None:
        return
    if not strict and any(_shape(t) != first for t in tokens[:_SHAPE_SAMPLE]):
        return
    for tok, line in zip(tokens, lines, strict=True):
        if _shape(tok) != first:
            expo = "no exponent" if first[1] < 0 else f"an exponent of {first[1]} characters"
            raise RecordFormatError(
                path, line, f"value {tok!r} is not written like the file's numbers "
                f"({tokens[0]!r}: {first[0]} digits after the point, {expo}); the file is "
                f"cut or damaged")


def _split_fixed(text: str, width: int) -> list[str]:
    text = text.rstrip()
    return [text[i : i + width] for i in range(0, len(text), width) if text[i : i + width].strip()]


def _parse_values(
    lines: list[str], first: int, path: Path, width: int | None
) -> tuple[list[float], list[int]]:
    """Numbers of lines ``first:`` with, for each, the 1-based line it came from.

    Read strictly: every number written in the file's format (:func:`_check_shapes`), and
    every line but the last holding as many values as the first data line, the last no more.
    """
    values: list[float] = []
    origin: list[int] = []
    texts: list[str] = []
    per_line: list[tuple[int, int]] = []  # (line, values on it)
    for i in range(first, len(lines)):
        text = lines[i]
        if not text.strip():
            continue
        tokens = [t.strip() for t in (_split_fixed(text, width) if width else text.split())]
        for tok in tokens:
            values.append(_parse_float(tok, path, i + 1))
            origin.append(i + 1)
            texts.append(tok)
        per_line.append((i + 1, len(tokens)))
    _check_shapes(texts, origin, path, strict=True)
    if per_line:
        full = per_line[0][1]
        for k, (line, n) in enumerate(per_line):
            last = k == len(per_line) - 1
            if n > full or (n < full and not last):
                raise RecordFormatError(
                    path, line, f"{n} values on this line, the data lines hold {full} "
                    f"(line {per_line[0][0]}); the file is cut or damaged")
    return values, origin


def _azimuth(header: list[str]) -> float | str | None:
    # NGA-West2 / PEER 2000 put the component last on line 2: "..., El Centro Array #9, 180".
    if len(header) < 2:
        return None
    m = _AZIMUTH.search(header[1].strip())
    if not m:
        return None
    az = m.group("az").upper()
    return float(az) if az.isdigit() else "UP"


def read_at2(path: str | Path) -> tuple[np.ndarray, float, dict[str, Any]]:
    """Read a PEER ``.AT2`` acceleration file in its own units.

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    acc : numpy.ndarray
        Acceleration in the file's units (g for PEER files).
    dt : float
        Time step [s].
    meta : dict
        ``file``, ``path``, ``sha256``, ``format``, ``npts``, ``dt``, ``units_file`` (from the
        header; None if it does not say), ``azimuth``, ``title`` and ``header``.

    Raises
    ------
    RecordFormatError
        No NPTS/DT line, unreadable NPTS or DT, dt <= 0, a bad value, or a sample count that
        differs from NPTS; the message names the file and the line.
    """
    path = Path(path)
    lines = _read_lines(path)
    header_line = None
    for i, text in enumerate(lines[:_HEADER_SCAN_LINES]):
        m = _NPTS_DT.search(text) or _NPTS_DT_REVERSED.search(text)
        if m:
            header_line = i
            break
        if re.search(r"\bNPTS\b", text, re.IGNORECASE):
            raise RecordFormatError(path, i + 1, f"cannot read NPTS and DT from {text.strip()!r}")
    if header_line is None:
        last = min(len(lines), _HEADER_SCAN_LINES)
        raise RecordFormatError(
            path, None, f"no 'NPTS=..., DT=...' header line in lines 1-{last}"
        )
    lineno = header_line + 1
    npts_text, dt_text = m.group("npts"), m.group("dt")
    try:
        npts_f = float(npts_text)
    except ValueError:
        raise RecordFormatError(path, lineno, f"NPTS is not a number: {npts_text!r}") from None
    if not npts_f.is_integer() or npts_f < 2:
        raise RecordFormatError(path, lineno, f"NPTS must be an integer >= 2, got {npts_text!r}")
    try:
        dt = positive_finite("DT", dt_text)
    except ValueError as exc:
        raise RecordFormatError(path, lineno, str(exc)) from None
    npts = int(npts_f)

    header = lines[:lineno]
    width = None
    for text in header:
        fm = _FORTRAN_FORMAT.search(text)
        if fm:
            width = int(fm.group(2))
            break
    units_file = None
    for text in header:
        um = _UNITS.search(text)
        if um:
            unit = um.group("unit").upper()
            units_file = "g" if unit == "G" else "cm/s2"
            break

    values, origin = _parse_values(lines, lineno, path, width)
    if len(values) != npts:
        last = origin[-1] if origin else lineno
        if len(values) > npts:
            raise RecordFormatError(
                path, origin[npts],
                f"more samples than NPTS={npts} (line {lineno}); the data hold {len(values)}",
            )
        raise RecordFormatError(
            path, last,
            f"the data end after {len(values)} samples but NPTS={npts} (line {lineno})",
        )
    if header_line == 3 and header[0].upper().startswith("PEER NGA"):
        fmt = "peer-nga-west2"
    elif header_line == 3 and header[0].upper().startswith("PEER STRONG MOTION"):
        fmt = "peer-2000"
    elif width is not None:
        fmt = f"fixed-width-{width}"
    else:
        fmt = "peer-at2"
    meta = {
        "file": path.name,
        "path": str(path),
        "sha256": file_sha256(path),
        "format": fmt,
        "npts": npts,
        "dt": dt,
        "units_file": units_file,
        "azimuth": _azimuth(header),
        "title": header[1].strip() if len(header) > 1 else "",
        "header": [h.rstrip() for h in header],
    }
    return np.asarray(values, dtype=np.float64), dt, meta


def read_text(
    path: str | Path, dt: float | None = None
) -> tuple[np.ndarray, float, dict[str, Any]]:
    """Read plain text with one column (acceleration) or two (time, acceleration).

    Blank lines and lines starting with ``#`` are skipped; columns may be separated by
    blanks, commas or semicolons.

    Parameters
    ----------
    path : str or Path
        The file.
    dt : float, optional
        Time step [s]; required for one column; for two columns it must agree with the
        time column (relative 1e-6) when given.

    Returns
    -------
    acc : numpy.ndarray
        Acceleration in the file's units.
    dt : float
        Time step [s].
    meta : dict
        ``file``, ``path``, ``sha256``, ``format``, ``npts``, ``dt``, ``t0`` (first time [s]).

    Raises
    ------
    RecordFormatError
        A bad token, NaN, a change in the number of columns, a non-uniform or non-increasing
        time column, or dt <= 0, naming the file and the line.
    """
    path = Path(path)
    lines = _read_lines(path)
    rows: list[list[float]] = []
    texts: list[list[str]] = []
    origin: list[int] = []
    ncol = None
    for i, text in enumerate(lines):
        stripped = text.strip()
        if not stripped or stripped.startswith("#"):
            continue
        tokens = [t for t in re.split(r"[\s,;]+", stripped) if t]
        if ncol is None:
            ncol = len(tokens)
            if ncol not in (1, 2):
                raise RecordFormatError(
                    path, i + 1, f"expected 1 column (acc) or 2 (time, acc), found {ncol}"
                )
        elif len(tokens) != ncol:
            raise RecordFormatError(
                path, i + 1, f"expected {ncol} columns like the first data line, found "
                f"{len(tokens)}"
            )
        rows.append([_parse_float(t, path, i + 1) for t in tokens])
        texts.append(tokens)
        origin.append(i + 1)
    if len(rows) < 2:
        raise RecordFormatError(path, None, f"needs at least 2 samples, found {len(rows)}")
    for col in range(ncol):
        _check_shapes([t[col] for t in texts], origin, path, strict=False)
    data = np.asarray(rows, dtype=np.float64)
    t0 = 0.0
    if ncol == 1:
        if dt is None:
            raise ValueError(f"dt (the time step [s]) is required for the one-column file "
                             f"{path}")
        dt_val = positive_finite(f"{path}: dt", dt)
        acc = data[:, 0]
    else:
        t = data[:, 0]
        steps = np.diff(t)
        back = np.flatnonzero(steps <= 0.0)
        if back.size:
            k = int(back[0]) + 1
            raise RecordFormatError(
                path, origin[k], f"time does not increase: t = {float(t[k])!r} s after "
                f"t = {float(t[k - 1])!r} s (line {origin[k - 1]}); times must be increasing")
        step = float((t[-1] - t[0]) / (t.size - 1))
        bad = np.flatnonzero(np.abs(steps - step) > 1e-6 * step)
        if bad.size:
            k = int(bad[0]) + 1
            raise RecordFormatError(
                path, origin[k],
                f"time step {float(steps[k - 1])!r} s differs from the mean step {step!r} s: "
                "resample the record to a uniform dt first",
            )
        if dt is not None and abs(float(dt) - step) > 1e-6 * step:
            raise ValueError(f"dt={dt!r} disagrees with the time column of {path} ({step!r})")
        dt_val = float(step)
        t0 = float(t[0])
        acc = data[:, 1]
    meta = {
        "file": path.name,
        "path": str(path),
        "sha256": file_sha256(path),
        "format": f"text-{ncol}col",
        "npts": int(acc.size),
        "dt": dt_val,
        "t0": t0,
        "units_file": None,
        "azimuth": None,
    }
    return acc.copy(), dt_val, meta


def _looks_like_at2(path: Path) -> bool:
    if path.suffix.upper() == ".AT2" or not path.is_file():
        return True  # the AT2 reader names a missing file or a directory
    with path.open("rb") as fh:
        head = fh.read(4096).decode("latin-1")
    return bool(_NPTS_DT.search(head) or re.search(r"NPTS\s*,\s*DT", head, re.IGNORECASE))


def header_azimuth(path: str | Path) -> float | str | None:
    """Azimuth of the component in an AT2 file's header [deg], ``"UP"``, or None.

    None for files that are not AT2 or do not name an azimuth; a file that cannot be read
    also gives None (the reader reports it when the record itself is read).
    """
    p = Path(path)
    try:
        return _azimuth(_read_lines(p)[:2]) if _looks_like_at2(p) else None
    except OSError:
        return None


def read_record(
    path: str | Path, units: str = "g", dt: float | None = None
) -> Record:
    """Read one acceleration component and convert it to m/s².

    Parameters
    ----------
    path : str or Path
        A PEER ``.AT2`` file (any file whose header has ``NPTS=``/``DT=``) or plain text.
    units : str
        Unit the file is written in: ``"g"`` (PEER files; converted with
        :data:`rocking.constants.G`), ``"m/s2"``, ``"cm/s2"`` or ``"gal"``. When an AT2 header
        states its unit, it must agree.
    dt : float, optional
        Time step [s] for one-column text files; for an AT2 file or a two-column one it
        must agree with the file's (relative 1e-6) when given.

    Returns
    -------
    Record
        ``acc`` [m/s²], ``dt`` [s], ``meta``; unpacks as ``acc, dt, meta``.

    Raises
    ------
    RecordFormatError
        Malformed file (names the file and line).
    ValueError
        Unknown units, or units contradicting the header.
    """
    path = Path(path)
    factor = _unit_factor(units)
    if _looks_like_at2(path):
        acc, step, meta = read_at2(path)
        if dt is not None and abs(float(dt) - step) > 1e-6 * step:
            raise ValueError(f"dt={dt!r} disagrees with the header of {path} (DT= {step!r})")
        declared = meta["units_file"]
        if declared is not None and not math.isclose(UNIT_FACTORS[declared], factor):
            raise ValueError(
                f"units={units!r} contradicts the header of {path}, which says {declared!r}"
            )
    else:
        acc, step, meta = read_text(path, dt=dt)
    meta = {**meta, "units_file": units, "units": "m/s^2", "processing": []}
    return Record(acc * factor, step, meta)


def _component_meta(meta: dict[str, Any], npts_padded: int) -> dict[str, Any]:
    # the file's name and sha256 say which record it is; where it lay (a virtualenv's
    # site-packages, a user's folder) is not the motion's, and kept it would make the bytes of
    # a motions file, and so its digest, depend on the machine that wrote it
    keep = ("file", "sha256", "format", "npts", "azimuth", "title", "units_file")
    out = {k: meta.get(k) for k in keep}
    out["padded_to"] = npts_padded
    return out


def pair_from_records(rec_x: Record, rec_y: Record, name: str) -> GroundMotion:
    """Two components read by :func:`read_record` on one time axis, the shorter zero-padded.

    Raises
    ------
    ValueError
        Different time steps (names both files and both dt values).
    """
    if not math.isclose(rec_x.dt, rec_y.dt, rel_tol=1e-9):
        raise ValueError(
            f"the two components of {name!r} have different dt: {rec_x.dt!r} s "
            f"({rec_x.meta['file']}) and {rec_y.dt!r} s ({rec_y.meta['file']}); resample one"
        )
    n = max(rec_x.acc.size, rec_y.acc.size)
    # Zero padding at the end: the shorter component has ended, the ground is at rest.
    ax = np.zeros(n)
    ay = np.zeros(n)
    ax[: rec_x.acc.size] = rec_x.acc
    ay[: rec_y.acc.size] = rec_y.acc
    meta = {
        "source": "file",
        "files": [rec_x.meta["file"], rec_y.meta["file"]],
        "sha256": [rec_x.meta["sha256"], rec_y.meta["sha256"]],
        "azimuths": [rec_x.meta.get("azimuth"), rec_y.meta.get("azimuth")],
        "units": "m/s^2",
        "g": G,
        "components": {
            "x": _component_meta(rec_x.meta, n),
            "y": _component_meta(rec_y.meta, n),
        },
        "processing": [],
        "stand_in": False,
    }
    if rec_x.acc.size != rec_y.acc.size:
        meta["processing"].append(
            {"step": "zero-pad-end", "npts": [rec_x.acc.size, rec_y.acc.size], "to": n}
        )
    return GroundMotion(ax, ay, rec_x.dt, name, meta)


def read_pair(
    path_x: str | Path, path_y: str | Path, name: str, units: str = "g"
) -> GroundMotion:
    """Read two horizontal components onto one time axis.

    Parameters
    ----------
    path_x, path_y : str or Path
        Files of the x and y components (any format :func:`read_record` reads).
    name : str
        Name of the motion.
    units : str
        Unit of both files (see :func:`read_record`).

    Returns
    -------
    GroundMotion
        ax, ay [m/s²]; the shorter component padded with zeros at the end. Metadata: files,
        sha256, azimuths, units, processing.

    Raises
    ------
    ValueError
        Different time steps (names both files and both dt values), or a malformed file.
    """
    return pair_from_records(read_record(path_x, units), read_record(path_y, units), name)


VERTICAL_LENGTH_SLACK = 0.01
"""Largest relative difference of sample counts between a vertical file and the horizontal
pair it joins [-]: the components of one NGA station differ by a few samples (El Centro:
5378 against 5372), another record's file by far more."""


def _points_down(rec: Record) -> bool:
    """The component is positive downwards: ``DWN``/``DOWN`` ends the component label of an
    AT2 header's second line (Pacoima Dam's vertical file)."""
    header = rec.meta.get("header") or []
    if len(header) < 2:
        return False
    m = _AZIMUTH.search(str(header[1]).strip())
    return bool(m) and m.group("az").upper() in ("DWN", "DOWN")


def with_vertical(motion: GroundMotion, rec_z: Record) -> GroundMotion:
    """A horizontal pair with a vertical component read by :func:`read_record`.

    The vertical is put positive up: a file labelled ``DWN`` has its sign turned, and the
    processing line says so. The three components share one time axis, the shorter ones
    zero-padded at the end (as :func:`pair_from_records` pads the pair).

    Raises
    ------
    ValueError
        A vertical file with another dt than the pair, or whose length differs by more than
        :data:`VERTICAL_LENGTH_SLACK` (one line naming the file and both values).
    """
    name = rec_z.meta.get("file", "vertical file")
    if not math.isclose(rec_z.dt, motion.dt, rel_tol=1e-9):
        raise ValueError(f"vertical file {name}: dt {rec_z.dt!r} s differs from the "
                         f"horizontal pair's {motion.dt!r} s")
    n_h, n_z = motion.npts, rec_z.acc.size
    if abs(n_z - n_h) > VERTICAL_LENGTH_SLACK * max(n_h, n_z):
        raise ValueError(f"vertical file {name}: {n_z} samples against {n_h} of the "
                         "horizontal pair (another record?)")
    n = max(n_h, n_z)
    ax, ay, az = np.zeros(n), np.zeros(n), np.zeros(n)
    ax[:n_h], ay[:n_h] = motion.ax, motion.ay
    down = _points_down(rec_z)
    az[:n_z] = -rec_z.acc if down else rec_z.acc
    meta = dict(motion.metadata)
    meta["components"] = {**meta.get("components", {}), "z": _component_meta(rec_z.meta, n)}
    meta["vertical"] = {"file": name, "sha256": rec_z.meta.get("sha256"),
                        "sign": "turned (DWN file, now positive up)" if down else "up"}
    meta["processing"] = [*meta.get("processing", []),
                          {"step": "vertical", "file": name,
                           "sign": "DWN file: sign turned to up" if down else "UP file"}]
    return GroundMotion(ax, ay, motion.dt, motion.name, meta, az)
