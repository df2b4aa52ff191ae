"""Figure 3: period of pure wobbling versus tilt, compared with Housner's 2D rocking period.

The 3D curve is the closed form of the corrected Eq (24): one turn of the contact point at
constant tilt θ takes T = 2π/|φ̇|, φ̇² = 2 (g/R) sin(α − θ)/μ'(θ). Normalized as T·p it does
not depend on R (p² = g/(κo R)). Housner's linearized 2D period of free rocking with amplitude
θ0 is T = (4/p) arccosh(1/(1 − θ0/α)).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from rocking.plot._style import new_figure, styled
from rocking.plot.comparisons import REPRODUCED, Comparison, finite, first_notes, judged

if TYPE_CHECKING:
    from matplotlib.figure import Figure

TAN_ALPHAS = (0.1, 0.2, 1.0, 1000.0)
"""Slendernesses of the paper's Fig 3 (1000 is the Euler's-disk limit)."""


def housner_period_times_p(theta_over_alpha) -> np.ndarray:
    """Housner's linearized free-rocking period times p, 4 arccosh(1/(1 − θ0/α)) [-]."""
    r = np.asarray(theta_over_alpha, dtype=float)
    if np.any((r <= 0.0) | (r >= 1.0)):
        raise ValueError(f"theta_over_alpha must lie in (0, 1), got {theta_over_alpha!r}")
    return 4.0 * np.arccosh(1.0 / (1.0 - r))


STYLES = {
    0.1: {"color": "tab:blue", "ls": "--", "lw": 1.4, "marker": "o", "markevery": (0.05, 0.1),
          "ms": 3.5, "mfc": "none"},
    0.2: {"color": "tab:orange", "ls": "-", "lw": 2.4, "alpha": 0.8},
    1.0: {"color": "tab:green", "ls": "-.", "lw": 1.4},
    1000.0: {"color": "tab:red", "ls": ":", "lw": 1.8},
}
"""Line style per slenderness: the nearly coincident tan α = 0.1 (dashed, open markers) and
0.2 (wide, translucent) curves stay distinguishable where they overlap."""

ZOOM = (0.48, 0.52)
"""θ/α window of the inset that separates the tan α = 0.1 and 0.2 curves [-]."""


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
        ``theta_over_alpha`` (n,), ``wobbling`` {tan α: T·p (n,)}, ``housner`` (n,),
        ``measured``: T·p at θ/α = 0.5, the range of T_wobbling/T_Housner over
        0.1 ≤ θ/α ≤ 0.9 per slenderness, and the largest relative gap between the two most
        slender curves.
    """
    from rocking.dynamics.bodies import Cylinder

    if n < 2:
        raise ValueError(f"n must be >= 2, got {n!r}")
    # Open interval: T·p → 0 at θ = 0 and → ∞ at θ = α for both curves.
    r = np.linspace(0.0, 1.0, n + 2)[1:-1]
    wobbling = {}
    for tan_alpha in tan_alphas:
        body = Cylinder(R, tan_alpha)
        wobbling[float(tan_alpha)] = body.wobbling_period(r * body.alpha) * body.p
    housner = housner_period_times_p(r)
    return {"theta_over_alpha": r, "wobbling": wobbling, "housner": housner,
            "measured": measurements(r, wobbling, housner, R)}


def measurements(r: np.ndarray, wobbling: dict, housner: np.ndarray, R: float) -> dict:
    """What Fig 3 shows in numbers: T·p at θ/α = 0.5, the wobbling/rocking period ratio, the
    growth of every curve with tilt and the gap between the two most slender curves."""
    from rocking.dynamics.bodies import Cylinder

    measured: dict = {"Tp_at_half_alpha_housner": float(housner_period_times_p(0.5))}
    inner = (r >= 0.1) & (r <= 0.9)
    for tan_alpha, tp in wobbling.items():
        body = Cylinder(R, tan_alpha)
        measured[f"Tp_at_half_alpha_tan{tan_alpha:g}"] = float(
            body.wobbling_period(0.5 * body.alpha) * body.p)
        ratio = tp[inner] / housner[inner]
        measured[f"ratio_to_housner_tan{tan_alpha:g}"] = [float(ratio.min()), float(ratio.max())]
        measured[f"increasing_tan{tan_alpha:g}"] = bool(np.all(np.diff(tp) > 0))
    slender = sorted(wobbling)[:2]
    if len(slender) == 2:
        a, b = (wobbling[t] for t in slender)
        measured["slender_pair"] = slender
        measured["max_rel_gap_slender_pair"] = float(np.max(np.abs(a / b - 1.0)))
    return measured


@styled
def plot(d: dict) -> Figure:
    """Figure 3: T·p against θ/α, one line per slenderness plus Housner's 2D curve, with an
    inset that separates the two most slender curves."""
    fig, ax = new_figure(5.6, 4.4)
    r = d["theta_over_alpha"]
    for tan_alpha, tp in d["wobbling"].items():
        ax.plot(r, tp, label=f"3D wobbling, tan α = {tan_alpha:g}",
                **STYLES.get(tan_alpha, {}))
    ax.plot(r, d["housner"], "k--", lw=1.5, label="2D rocking (Housner, linearized)")
    ax.set_xlim(0.0, 1.0)
    ax.set_ylim(0.0, 12.0)
    ax.set_xlabel("Normalized tilt θ/α [-]")
    ax.set_ylabel("Normalized period T·p [-]")
    ax.set_title("Wobbling period versus tilt (Fig 3)")
    ax.legend(loc="upper left")
    _zoom(ax, d)
    return fig


def _zoom(ax, d: dict) -> None:
    # The two most slender curves differ by < 1 %: an inset magnifies a window where both
    # are seen as separate lines, and the gap is written out.
    m = d.get("measured", {})
    if "slender_pair" not in m:
        return
    r = d["theta_over_alpha"]
    window = (r >= ZOOM[0]) & (r <= ZOOM[1])
    if window.sum() < 2:
        return
    inset = ax.inset_axes((0.62, 0.07, 0.35, 0.35))
    ys = []
    for tan_alpha in m["slender_pair"]:
        style = {k: v for k, v in STYLES.get(tan_alpha, {}).items() if k != "markevery"}
        inset.plot(r[window], d["wobbling"][tan_alpha][window], **style)
        ys.append(d["wobbling"][tan_alpha][window])
    inset.set_xlim(*ZOOM)
    lo, hi = float(np.min(ys)), float(np.max(ys))
    inset.set_ylim(lo - 0.02 * (hi - lo), hi + 0.02 * (hi - lo))
    inset.tick_params(labelsize=6)
    a, b = m["slender_pair"]
    inset.set_title(f"tan α = {a:g} vs {b:g}: ≤ {100 * m['max_rel_gap_slender_pair']:.2f} % apart",
                    fontsize=6.5)
    ax.indicate_inset_zoom(inset, edgecolor="0.4")


# ------------------------------------------------------ comparison with the paper


def compare(notes: Mapping) -> list[Comparison]:
    """This figure's statements of the paper set against the run's notes."""
    m = first_notes(notes, "fig03_wobbling_period").get("measured", {})
    ratios = {k.split("tan", 1)[1]: v for k, v in m.items() if k.startswith("ratio_to_housner")}
    rising = [v for k, v in m.items() if k.startswith("increasing_tan")]
    ok = (all(rising) and all(0.5 <= lo and hi <= 2.0 for lo, hi in ratios.values())
          if ratios else None)
    ours = "; ".join(f"tan α = {t}: {lo:.2f}–{hi:.2f}" for t, (lo, hi) in ratios.items())
    gap = m.get("max_rel_gap_slender_pair")
    rows = [judged(
        "fig03_wobbling_period", "Wobbling period versus tilt: 'the analogy between 2D rocking "
        "and 3D bounded wobbling is evident' (§2.2, Fig 3)",
        "both periods grow from 0 without bound as θ → α (qualitative)",
        f"every curve rises with θ/α: {all(rising)}; T_wobbling/T_Housner for 0.1 ≤ θ/α ≤ 0.9: "
        + ours, ok, "every curve rising and within a factor 2 of Housner's period",
        "a wobbling period departs from Housner's by more than a factor 2")]
    if finite(gap):
        rows.append(Comparison(
            "fig03_wobbling_period", "Curves of tan α = 0.1 and 0.2 (Fig 3)",
            "drawn as nearly one curve", f"at most {100 * gap:.2f} % apart (inset)", REPRODUCED,
            "the slender limit: T·p depends on α only through small terms"))
    return rows


# ---------------------------------------------------------------- the figure's entry

from rocking.plot.registry import FigureSpec  # noqa: E402

FIGURE = FigureSpec(
    name="fig03_wobbling_period", module=__name__, number=3, label="Fig 3",
    caption=(
        "Fig 3. Period of pure wobbling T, normalized by the frequency parameter p, against "
        "the normalized tilt θ/α for tan α = 0.1, 0.2, 1 and 1000 (Euler's disk), with "
        "Housner's linearized 2D rocking period. Closed form of Eq (24) as corrected in "
        "docs/equations.md#eq-24-the-wobbling-period (the printed equation has a sign error "
        "under the root); no ground motion, so no x/y direction. The curves of tan α = 0.1 "
        "and 0.2 lie within 1 % of each other; the inset magnifies them and gives their "
        "largest gap."
    ),
    scope="global", wanted=lambda s: s.reproduces, paper_only=True, el_centro_only=True)
"""Fig 3: closed forms only, drawn once for a reproduction of the paper."""
