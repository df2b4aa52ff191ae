"""What the commands print for people: labelled lines and tables with units.

Every command prints, by default, a few ``label  value`` lines (the body, the motion and the
processing applied to it, the intensity) and a table whose columns carry their units; tilts
in rad and as a share of α, intensities as PGA in g and as PGA/(g tan α). ``--json`` prints
the machine form instead (:func:`add_json`). The processing is printed with every answer:
the command line takes a record as given unless asked (``--rotation``, ``--highpass``),
while the workflow's ensembles turn it to principal axes and high-pass it (docs/cli.md,
"Processing: the command line and the workflow").
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Iterable, Sequence
from typing import Any

WORKFLOW_PROCESSING = "--rotation auto --highpass oscillator, with --mw for --files"
"""The command-line spelling of the workflow's default processing of a record."""


def add_json(p: argparse.ArgumentParser, what: str) -> None:
    """``--json``: the machine-readable output on stdout instead of the labelled text."""
    p.add_argument("--json", action="store_true",
                   help=f"print {what} as strict JSON on stdout (for scripts) instead of "
                   "the labelled text")


def num(value: Any, digits: int = 4) -> str:
    """A number with ``digits`` significant digits; ``—`` for None or NaN."""
    if value is None:
        return "—"
    x = float(value)
    if not math.isfinite(x):
        return "—"
    return f"{x:.{digits}g}"


def interval(lo: Any, hi: Any) -> str:
    """``lo–hi``, or ``—`` when the interval is undefined."""
    text = f"{num(lo)}–{num(hi)}"
    return "—" if text == "—–—" else text


def block(rows: Iterable[tuple[str, str]]) -> str:
    """``label  value`` lines with the values aligned."""
    rows = list(rows)
    width = max((len(label) for label, _ in rows), default=0)
    return "\n".join(f"{label.ljust(width)}  {value}" for label, value in rows)


def table(header: Sequence[str], rows: Iterable[Sequence[str]],
          left: Sequence[int] = ()) -> str:
    """A plain-text table, the header (with units) on top: numbers right-aligned, the
    columns ``left`` (names, flags) left-aligned."""
    rows = [list(map(str, r)) for r in rows]
    widths = [max(len(h), *(len(r[i]) for r in rows)) if rows else len(h)
              for i, h in enumerate(header)]

    def line(cells):
        return "  ".join(c.ljust(w) if i in left else c.rjust(w)
                         for i, (c, w) in enumerate(zip(cells, widths, strict=True))).rstrip()

    return "\n".join([line(header), *(line(r) for r in rows)])


def _highpass_kind(motion) -> str:
    steps = [s for s in motion.metadata.get("processing", []) if isinstance(s, dict)
             and s.get("step") == "highpass"]
    if steps:
        return str(steps[-1].get("kind", "high-pass"))
    return str(motion.metadata.get("highpass", {}).get("kind", "high-pass"))


def processing(motion, stored: bool = False) -> str:
    """Rotation and high-pass of a motion in words, e.g. ``rotation: principal axes (turned
    −70.46°); high-pass: oscillator, corner fc = 0.09465 Hz``.

    An unprocessed record read from a name or files gets the options that give the
    workflow's processing; a motion ``stored`` in an ensemble file is used as it is, so it
    gets none (its processing is the ensemble's).
    """
    from rocking.motions.identity import identity

    who = identity(motion)
    rot, fc = who["rotation_deg"], who["highpass_fc_hz"]
    if who["kind"] == "synthetic":
        rotation = "— (a synthetic pair: its record's axes)"
    elif math.isfinite(rot):
        rotation = f"principal axes (turned {rot:.2f}°)"
    else:
        rotation = "none (recorded axes)"
    highpass = (f"{_highpass_kind(motion)}, corner fc = {fc:.4g} Hz" if math.isfinite(fc)
                else "none")
    text = f"rotation: {rotation}; high-pass: {highpass}"
    if stored:
        text += " (as stored in the ensemble file)"
    elif who["kind"] == "record" and not math.isfinite(rot) and not math.isfinite(fc):
        text += f" (as given; the workflow's ensembles use {WORKFLOW_PROCESSING})"
    return text


def processing_fields(motion) -> dict[str, Any]:
    """The processing as JSON fields: ``rotation_deg`` (None: recorded axes),
    ``highpass`` (kind or None) and ``highpass_fc_hz`` [Hz] (None: none)."""
    from rocking.motions.identity import identity

    who = identity(motion)
    fc = who["highpass_fc_hz"]
    rot = who["rotation_deg"]
    return {"rotation_deg": rot if math.isfinite(rot) else None,
            "highpass": _highpass_kind(motion) if math.isfinite(fc) else None,
            "highpass_fc_hz": fc if math.isfinite(fc) else None}


def slenderness(tan_alpha: float) -> str:
    """``tan α = 0.2 (α = 0.1974 rad = 11.31°)``."""
    alpha = math.atan(tan_alpha)
    return f"tan α = {num(tan_alpha)} (α = {alpha:.4g} rad = {math.degrees(alpha):.4g}°)"


def body_line(kind: str, R: float, tan_alpha: float) -> str:
    """``cylinder, R = 6 m, tan α = 0.2 (α = 0.1974 rad = 11.31°)``."""
    return f"{kind}, R = {num(R)} m, {slenderness(tan_alpha)}"


def intensity(pga_ratio: float, tan_alpha: float) -> str:
    """``PGA = 0.4 g = 2 g tan α``: an intensity in both units."""
    return f"PGA = {num(pga_ratio * tan_alpha)} g = {num(pga_ratio)} g tan α"


def tilt(theta: float, alpha: float) -> str:
    """``0.05603 rad = 0.2838 α``: a tilt in rad and as a share of α."""
    return f"{num(theta)} rad = {num(theta / alpha)} α"
