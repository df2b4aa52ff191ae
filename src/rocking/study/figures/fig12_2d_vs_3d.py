"""Figure 12: mean spectra of the bidirectional 3D model versus unidirectional 2D models.

For each ensemble (El Centro, black; Loma Prieta or its stand-in, red) the 3D model under both
components is compared with the 2D model under the x and under the y component alone; the
intensity is the bidirectional PGA in all three (paper §5.4). tan α = 0.2.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from . import _load
from ._style import MODE_STYLE, limit_state_title, new_figure, styled

TAN_ALPHA = 0.2
MODES = ("3d", "2d-x", "2d-y")
REFERENCE_R = 10.0
"""Size of the paper's §5.4 statement (R = 10 m: ≈ 4 bidirectional, about twice 2D) [m]."""
ENSEMBLE_COLORS = ("black", "tab:red", "tab:blue", "tab:green")


def data(studies: Sequence[tuple[str, str | Path, str | Path | None]], *,
         tan_alpha: float = TAN_ALPHA, modes: tuple[str, ...] = MODES) -> dict:
    """Mean spectra per ensemble and mode.

    Parameters
    ----------
    studies : sequence of (name, mean_spectra path, store path or None)
        One entry per ensemble; the store's attributes give its label and stand-in flag.

    Returns
    -------
    dict
        ``ensembles``: [{``label``, ``stand_in``, ``R`` [m], ``panels``: {limit state:
        {mode: mean PGA/(g tan α) (R,)}}}], ``missing``: notes.
    """
    ensembles = []
    missing: list[str] = []
    for name, means, store in studies:
        agg = _load.open_means(means)
        attrs = dict(agg.attrs)
        if store is not None and Path(store).exists():
            attrs = {**attrs, **_load.open_store(store).attrs}
        label, stand_in = _load.ensemble_label(attrs, name)
        if not _load.has_value(agg, "tan_alpha", tan_alpha):
            missing.append(f"{label}: tan α = {tan_alpha:g} not computed")
            continue
        agg = _load.select_value(agg, "tan_alpha", tan_alpha)
        states = _load.labels(agg, "limit_state")
        panels: dict[str, dict[str, np.ndarray]] = {}
        for title, ls in (("overturning", _load.find_limit_state(states, "overturning")),
                          ("excessive tilt", _load.excessive_tilt(states))):
            if ls is None:
                missing.append(f"{label}: limit state {title} not computed")
                continue
            panels[title] = {}
            for mode in modes:
                y = _load.mean_curve(agg, mode, ls)
                if y is None:
                    missing.append(f"{label}: mode {mode} not computed")
                else:
                    panels[title][mode] = y
        ensembles.append({"name": name, "label": label, "stand_in": stand_in,
                          "R": agg["R"].values.astype(float), "panels": panels})
    names = " ".join(f"{e['name']} {e['label']}" for e in ensembles).lower()
    for wanted in ("El Centro", "Loma Prieta"):
        if wanted.split()[0].lower() not in names:
            missing.append(f"no {wanted} ensemble in this run")
    return {"ensembles": ensembles, "tan_alpha": tan_alpha, "missing": sorted(set(missing)),
            "measured": at_size(ensembles, REFERENCE_R)}


def at_size(ensembles: list[dict], R: float) -> dict:
    """Mean intensities at size ``R`` [m] (linear interpolation in R; NaN outside the grid)."""
    out = {"R": R}
    for ens in ensembles:
        for title, curves in ens["panels"].items():
            for mode, y in curves.items():
                ok = np.isfinite(y)
                inside = ok.any() and ens["R"][ok].min() <= R <= ens["R"][ok].max()
                value = float(np.interp(R, ens["R"][ok], y[ok])) if inside else float("nan")
                out[f"{ens['name']}|{title}|{mode}"] = value
    return out


@styled
def plot(d: dict) -> Figure:
    """Two panels (overturning, excessive tilt); colour = ensemble, line style = mode."""
    titles = ("overturning", "excessive tilt")
    fig, axes = new_figure(10.0, 5.2, ncols=2)
    handles, modes_seen = [], []
    for k, ens in enumerate(d["ensembles"]):
        color = ENSEMBLE_COLORS[k % len(ENSEMBLE_COLORS)]
        label = ens["label"]
        if ens["stand_in"] and "stand-in" not in label:
            label += " (stand-in)"
        handles.append(Line2D([], [], color=color, lw=1.6, label=label))
        for ax, title in zip(axes, titles, strict=True):
            for mode, y in ens["panels"].get(title, {}).items():
                ax.plot(ens["R"], y, color=color, ls=MODE_STYLE[mode]["linestyle"], lw=1.6,
                        marker="o", ms=3, label=f"{label}: {MODE_STYLE[mode]['label']}")
                if mode not in modes_seen:
                    modes_seen.append(mode)
    handles += [Line2D([], [], color="gray", lw=1.6, ls=MODE_STYLE[m]["linestyle"],
                       label=MODE_STYLE[m]["label"] + (" (both components)" if m == "3d"
                                                       else " only"))
                for m in modes_seen]
    for ax, title in zip(axes, titles, strict=True):
        ax.set_title(limit_state_title("overturning") if title == "overturning"
                     else "Excessive tilt θ > α/3")
        ax.set_xlabel("R [m]")
        ax.set_ylabel("mean PGA/(g tan α) [-] (bidirectional PGA)")
        ax.set_xlim(left=0.0)
        ax.set_ylim(bottom=0.0)
    if handles:
        # One legend for both panels, below them: colours are ensembles, styles are modes.
        fig.legend(handles=handles, loc="outside lower center", ncols=2)
    title = f"3D (bidirectional) versus 2D (one component), tan α = {d['tan_alpha']:g} (Fig 12)"
    if d["missing"]:
        title += "\nmissing: " + "; ".join(d["missing"])
    fig.suptitle(title)
    return fig
