"""Figure 8: the ensemble's acceleration traces and 5 %-damped pseudo-acceleration spectra.

Top row the record on its principal axes (first member of the ensemble file), then the
synthetic pairs; left the x (major) and y components, right the spectra of all motions, the
record's drawn thick. The synthetic pairs match the record only through linear-oscillator
statistics, which is why their rocking spectra scatter (paper §5.1–5.2).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.figure import Figure

from ...constants import G
from ...motions.motion import GroundMotion
from ...motions.response_spectrum import pseudo_acceleration
from ._style import styled

DAMPING = 0.05
PERIODS = np.geomspace(0.02, 5.0, 120)
"""Oscillator periods [s], log-spaced as the spectra are drawn."""


def data(motions: Sequence[GroundMotion], *, periods=PERIODS, damping: float = DAMPING) -> dict:
    """Traces [g] and PSA spectra [g] of every motion, in ensemble order.

    Returns
    -------
    dict
        ``motions``: [{``name``, ``t`` [s], ``ax``, ``ay`` [g], ``psa_x``, ``psa_y`` [g],
        ``stand_in``}], ``periods`` [s], ``damping`` [-].
    """
    if not motions:
        raise ValueError("motions must hold at least one GroundMotion, got an empty list")
    periods = np.asarray(periods, dtype=float)
    out = []
    for m in motions:
        psa = pseudo_acceleration(np.vstack([m.ax, m.ay]), m.dt, periods, damping) / G
        out.append({
            "name": m.name,
            "t": m.time,
            "ax": np.asarray(m.ax) / G,
            "ay": np.asarray(m.ay) / G,
            "psa_x": psa[0],
            "psa_y": psa[1],
            "stand_in": bool(m.metadata.get("stand_in", False)),
        })
    first = motions[0].metadata
    measured = {
        "record": motions[0].name,
        "record_pga_g": motions[0].pga_g,
        "principal_offset_deg": first.get("principal_offset_deg"),
        "rotation_deg": first.get("rotation_deg"),
        "n_motions": len(motions),
    }
    missing = [f"{m['name']} is a stand-in" for m in out if m["stand_in"]]
    return {"motions": out, "periods": periods, "damping": damping, "measured": measured,
            "missing": missing}


@styled
def plot(d: dict) -> Figure:
    """Traces in stacked rows (x left, y middle), spectra in one panel on the right."""
    motions = d["motions"]
    n = len(motions)
    fig = Figure(figsize=(11.0, max(0.75 * n + 1.6, 4.5)), layout="constrained")
    grid = fig.add_gridspec(n, 3, width_ratios=(1.0, 1.0, 1.1))
    peak = max(float(np.max(np.abs(np.r_[m["ax"], m["ay"]]))) for m in motions)
    t_end = max(float(m["t"][-1]) for m in motions)
    first_x = None
    for i, m in enumerate(motions):
        color = "black" if i == 0 else f"C{(i - 1) % 10}"
        ax_x = fig.add_subplot(grid[i, 0], sharex=first_x, sharey=first_x)
        ax_y = fig.add_subplot(grid[i, 1], sharex=first_x, sharey=first_x)
        first_x = first_x or ax_x
        ax_x.plot(m["t"], m["ax"], color=color, lw=0.5)
        ax_y.plot(m["t"], m["ay"], color=color, lw=0.5)
        label = m["name"] + (" (stand-in)" if m["stand_in"] else "")
        ax_x.set_ylabel(label, rotation=0, ha="right", va="center", fontsize=7)
        for ax in (ax_x, ax_y):
            ax.set_ylim(-1.1 * peak, 1.1 * peak)
            ax.set_xlim(0.0, t_end)
            ax.tick_params(labelsize=6)
            if i < n - 1:
                ax.tick_params(labelbottom=False)
        if i == 0:
            ax_x.set_title("x (major principal) component [g]")
            ax_y.set_title("y component [g]")
    for ax in (ax_x, ax_y):  # the bottom row carries the time axis
        ax.set_xlabel("t [s]")
    ax_s = fig.add_subplot(grid[:, 2])
    for i, m in enumerate(motions):
        color = "black" if i == 0 else f"C{(i - 1) % 10}"
        lw = 2.0 if i == 0 else 0.8
        ax_s.plot(d["periods"], m["psa_x"], color=color, lw=lw, label=f"{m['name']} x")
        ax_s.plot(d["periods"], m["psa_y"], color=color, lw=lw, ls="--")
    ax_s.set_xscale("log")
    ax_s.set_xlim(float(d["periods"][0]), float(d["periods"][-1]))
    ax_s.set_xlabel("T [s]")
    ax_s.set_ylabel(f"PSA, ζ = {100 * d['damping']:g} % [g]")
    ax_s.set_title("Pseudo-acceleration spectra\n(solid x, dashed y)")
    ax_s.legend(loc="upper left", fontsize=6)
    fig.suptitle("Ground motions of the ensemble (Fig 8)")
    return fig
