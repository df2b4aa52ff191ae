"""What a ground motion is: the source record and the processing applied, as flat fields.

:func:`identity` reads a motion's processing metadata (written by the loaders, the high-pass,
the rotation, the cut and the RDK simulation); the ensemble files
(:mod:`rocking.motions.ensemble_io`), the stores and the CSV outputs carry its fields.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rocking.motions.motion import GroundMotion

__all__ = ["describe_processing", "identity"]


def _steps(motion: GroundMotion) -> list[dict[str, Any]]:
    return [s for s in motion.metadata.get("processing", []) if isinstance(s, dict)]


def _unprocessed_npts(motion: GroundMotion) -> int:
    """Samples of the motion before any filter padding (record or simulation length)."""
    for step in _steps(motion):
        if step.get("step") == "rdk-simulation":
            return int(step["npts"])
        if step.get("step") == "zero-pad-end":
            return int(step["to"])
    comps = motion.metadata.get("components", {})
    counts = [int(c["npts"]) for c in comps.values() if isinstance(c, dict) and "npts" in c]
    return max(counts) if counts else motion.npts


def identity(motion: GroundMotion) -> dict[str, Any]:
    """Where a motion comes from and what was applied, as flat fields.

    Returns
    -------
    dict
        ``source_record`` (the recorded pair it comes from), ``kind`` (``"record"`` or
        ``"synthetic"``), ``rotation_deg`` [deg] (NaN: recorded axes), ``highpass_fc_hz``
        [Hz] (NaN: none), ``padding_s`` [s] (zeros the high-pass padding left in the
        motion), ``duration_s`` [s], ``PGA`` [g], ``Ia_x``,
        ``Ia_y`` [m/s] and ``processing``, one line saying it all.
    """
    meta = motion.metadata
    synthetic = "generator" in meta
    source = str(meta.get("record") if synthetic else motion.name)
    rotation = math.nan
    fc = math.nan
    n_data = _unprocessed_npts(motion)
    front = 0
    words = []
    for step in _steps(motion):
        kind = step.get("step")
        if kind == "rotation" and not synthetic:
            rotation = float(step["angle_deg"])
            words.append(f"rotated {rotation:.2f} deg to principal axes")
        elif kind == "highpass":
            fc = float(step["fc_hz"])
            front += int(step.get("pad_front", 0))
            words.append(f"high-passed ({step['kind']}, fc {fc:.4g} Hz)")
        elif kind == "truncate":
            words.append(f"cut to {float(step['max_duration']):g} s")
        elif kind == "vertical":
            words.append(f"with its vertical component ({step['sign']})")
    if synthetic:
        head = (f"RDK synthetic pair {meta.get('realization')} of {source} "
                f"(seed {meta.get('seed')})")
    else:
        # a motion read from the user's files has its name as title: say it once
        title = meta.get("title")
        head = f"{source} ({'recorded' if title in (None, source) else title})"
    # zeros the filters added that are still in the motion (a cut may have removed them)
    padding = (motion.npts - min(n_data, max(motion.npts - front, 0))) * motion.dt
    if padding:
        words.append(f"zero-padded to {motion.duration:.2f} s ({padding:.2f} s of zeros)")
    text = head + (": " + ", ".join(words) if words else ": as recorded")
    return {
        "source_record": source,
        "kind": "synthetic" if synthetic else "record",
        "rotation_deg": rotation,
        "highpass_fc_hz": fc,
        "padding_s": padding,
        "duration_s": motion.duration,
        "PGA": motion.pga_g,
        **_arias(motion),
        "processing": text,
    }


def _arias(motion: GroundMotion) -> dict[str, float]:
    from rocking.motions.intensity import arias  # scipy: loaded only when a motion is described

    with np.errstate(over="ignore"):  # an absurd test signal may overflow to inf: say so
        return {"Ia_x": float(arias(motion.ax, motion.dt)),
                "Ia_y": float(arias(motion.ay, motion.dt))}


def describe_processing(motion: GroundMotion) -> str:
    """One line: the source record and the processing steps of ``motion``."""
    return identity(motion)["processing"]
