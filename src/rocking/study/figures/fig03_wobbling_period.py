"""Figure 3: period of pure wobbling versus tilt, compared with Housner's 2D rocking period.

The 3D curve is the closed form of the corrected Eq (24): one turn of the contact point at
constant tilt θ takes T = 2π/|φ̇|, φ̇² = 2 (g/R) sin(α − θ)/μ'(θ). Normalized as T·p it does
not depend on R (p² = g/(κo R)). Housner's linearized 2D period of free rocking with amplitude
θ0 is T = (4/p) arccosh(1/(1 − θ0/α)).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.figure import Figure

from ...dynamics.bodies import Cylinder
from ._style import new_figure, styled

TAN_ALPHAS = (0.1, 0.2, 1.0, 1000.0)
"""Slendernesses of the paper's Fig 3 (1000 is the Euler's-disk limit)."""


def housner_period_times_p(theta_over_alpha) -> np.ndarray:
    """Housner's linearized free-rocking period times p, 4 arccosh(1/(1 − θ0/α)) [-]."""
    r = np.asarray(theta_over_alpha, dtype=float)
    if np.any((r <= 0.0) | (r >= 1.0)):
        raise ValueError(f"theta_over_alpha must lie in (0, 1), got {theta_over_alpha!r}")
    return 4.0 * np.arccosh(1.0 / (1.0 - r))


def data(tan_alphas: Sequence[float] = TAN_ALPHAS, n: int = 199, R: float = 1.0) -> dict:
    """Normalized wobbling periods T·p on a grid of θ/α.

    Parameters
    ----------
    tan_alphas : sequence of float
        Slendernesses [-].
    n : int
        Number of θ/α points, spread uniformly in the open interval (0, 1).
    R : float
        Semi-diagonal [m]; T·p is independent of it (kept to show that in tests).

    Returns
    -------
    dict
        ``theta_over_alpha`` (n,), ``wobbling`` {tan α: T·p (n,)}, ``housner`` (n,).
    """
    if n < 2:
        raise ValueError(f"n must be >= 2, got {n!r}")
    # Open interval: T·p → 0 at θ = 0 and → ∞ at θ = α for both curves.
    r = np.linspace(0.0, 1.0, n + 2)[1:-1]
    wobbling = {}
    for tan_alpha in tan_alphas:
        body = Cylinder(R, tan_alpha)
        wobbling[float(tan_alpha)] = body.wobbling_period(r * body.alpha) * body.p
    measured = {"Tp_at_half_alpha_housner": float(housner_period_times_p(0.5))}
    for tan_alpha in tan_alphas:
        body = Cylinder(R, tan_alpha)
        measured[f"Tp_at_half_alpha_tan{tan_alpha:g}"] = float(
            body.wobbling_period(0.5 * body.alpha) * body.p
        )
    return {"theta_over_alpha": r, "wobbling": wobbling, "housner": housner_period_times_p(r),
            "measured": measured}


@styled
def plot(d: dict) -> Figure:
    """Figure 3: T·p against θ/α, one line per slenderness plus Housner's 2D curve."""
    fig, ax = new_figure(5.0, 3.8)
    r = d["theta_over_alpha"]
    for tan_alpha, tp in d["wobbling"].items():
        ax.plot(r, tp, label=f"3D wobbling, tan α = {tan_alpha:g}")
    ax.plot(r, d["housner"], "k--", lw=1.5, label="2D rocking (Housner, linearized)")
    ax.set_xlim(0.0, 1.0)
    ax.set_ylim(0.0, 12.0)
    ax.set_xlabel("Normalized tilt θ/α [-]")
    ax.set_ylabel("Normalized period T·p [-]")
    ax.set_title("Wobbling period versus tilt (Fig 3)")
    ax.legend(loc="upper left")
    return fig
