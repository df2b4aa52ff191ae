"""Figure 12: mean spectra of the bidirectional 3D model versus unidirectional 2D models.

For each ensemble (El Centro, black; Loma Prieta or its stand-in, red) the 3D model under both
components is compared with the 2D model under the x (major principal axis) and under the y
(minor) component alone; the intensity is the bidirectional PGA in all three (paper §5.4).
tan α = 0.2. The legend names each ensemble by its record and the number of motions averaged;
the note under the axes gives each ensemble's axis azimuths, so the 2D curves can be matched
with the paper's (whose x is E–W and y N–S before its rotation).
"""

from __future__ import annotations

import textwrap
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from ..spec import decode_attrs
from . import _axes, _load
from ._style import (
    MODE_STYLE,
    footnote,
    limit_state_title,
    pga_g_axis,
    styled,
    with_legend_row,
)

TAN_ALPHA = 0.2
MODES = ("3d", "2d-x", "2d-y")
REFERENCE_R = 10.0
"""Size of the paper's §5.4 statement (R = 10 m: ≈ 4 bidirectional, about twice 2D) [m]."""
ENSEMBLE_COLORS = ("black", "tab:red", "tab:blue", "tab:green")
MODE_LABELS = {"3d": "3D, both components", "2d-x": "2D, x (major axis) component only",
               "2d-y": "2D, y (minor axis) component only"}


def data(studies: Sequence[tuple], *, tan_alpha: float = TAN_ALPHA,
         modes: tuple[str, ...] = MODES) -> dict:
    """Mean spectra per ensemble and mode.

    Parameters
    ----------
    studies : sequence of (name, mean_spectra path, store path or None[, ensemble file or None])
        One entry per study; the store's attributes give the ensemble's label, motions and
        stand-in flag, the ensemble file the azimuths of x and y.

    Returns
    -------
    dict
        ``ensembles``: [{``name``, ``label``, ``stand_in``, ``n_motions``, ``axes``, ``R`` [m],
        ``panels``: {"overturning"/"excessive tilt": {mode: mean PGA/(g tan α) (R,)}}},
        ``missing``: notes; ``measured``: the means at R = 10 m.
    """
    ensembles = []
    missing: list[str] = []
    for entry in studies:
        name, means, store = entry[:3]
        motions = entry[3] if len(entry) > 3 else None
        ens = _ensemble(name, means, store, motions, tan_alpha, modes, missing)
        if ens is not None:
            ensembles.append(ens)
    names = " ".join(f"{e['name']} {e['label']}" for e in ensembles).lower()
    for wanted in ("El Centro", "Loma Prieta"):
        if wanted.split()[0].lower() not in names:
            missing.append(f"no {wanted} ensemble in this run")
    return {"ensembles": ensembles, "tan_alpha": tan_alpha, "missing": sorted(set(missing)),
            "measured": at_size(ensembles, REFERENCE_R),
            "axes": {e["name"]: e["axes"] for e in ensembles}}


def _ensemble(name: str, means, store, motions, tan_alpha: float, modes, missing: list[str]):
    """One ensemble's curves, or None (with a note) when its tan α was not computed."""
    agg = _load.open_means(means)
    attrs = dict(agg.attrs)
    if store is not None and Path(store).exists():
        attrs = {**attrs, **_load.open_store(store).attrs}
    record, stand_in = _load.ensemble_label(attrs, name)
    n = len(_load.labels(agg, "motion")) or _count_motions(attrs)
    label = f"{record}: mean of {n} motions" if n else f"{record}: ensemble mean"
    if not _load.has_value(agg, "tan_alpha", tan_alpha):
        missing.append(f"{record}: tan α = {tan_alpha:g} not computed")
        return None
    agg = _load.select_value(agg, "tan_alpha", tan_alpha)
    states = _load.labels(agg, "limit_state")
    panels: dict[str, dict[str, np.ndarray]] = {}
    spread: dict[str, np.ndarray] = {}
    for title, ls in _load._paper_limit_states(states, missing, prefix=f"{record}: "):
        panels[title] = {}
        for mode in modes:
            y = _load.mean_curve(agg, mode, ls)
            if y is None:
                missing.append(f"{record}: mode {mode} not computed")
                continue
            panels[title][mode] = y
            for stat in ("std", "count", "n_not_reached", "censoring"):
                if stat in agg and np.issubdtype(agg[stat].dtype, np.number):
                    spread[f"{title}|{mode}|{stat}"] = agg[stat].sel(
                        mode=mode, limit_state=ls).values.astype(float)
    return {"name": name, "label": label, "record": record, "stand_in": stand_in,
            "n_motions": n, "upper": _load.search_bound(attrs),
            "axes": _axes.from_ensemble(motions),
            "R": agg["R"].values.astype(float), "panels": panels, "spread": spread}


def _count_motions(attrs: dict) -> int:
    """Number of motions listed in a store's ``ensemble`` attribute (0 if unknown)."""
    raw = decode_attrs({"ensemble": attrs.get("ensemble")})["ensemble"]
    return len(raw.get("motions", [])) if isinstance(raw, dict) else 0


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
                for stat in ("std", "count", "n_not_reached"):
                    s = ens.get("spread", {}).get(f"{title}|{mode}|{stat}")
                    if s is not None and inside:
                        out[f"{ens['name']}|{title}|{mode}|{stat}"] = float(
                            np.interp(R, ens["R"][ok], s[ok]))
        out[f"{ens['name']}|label"] = ens["label"]
        out[f"{ens['name']}|n_motions"] = ens["n_motions"]
        out[f"{ens['name']}|upper"] = ens.get("upper")
        out[f"{ens['name']}|stand_in"] = bool(ens["stand_in"])
    return out


def fewer_motions(ens: dict, title: str, mode: str) -> np.ndarray:
    """Sizes R where the mean of (``title``, ``mode``) covers fewer motions than the ensemble.

    Uses the aggregate's ``censoring`` column when there is one, else ``n_not_reached`` > 0,
    else ``count`` below the ensemble's number of motions.
    """
    spread = ens.get("spread", {})
    y = ens["panels"].get(title, {}).get(mode)
    shape = np.shape(y) if y is not None else np.shape(ens["R"])
    for key, test in (("censoring", lambda v: np.nan_to_num(v) > 0),
                      ("n_not_reached", lambda v: np.nan_to_num(v) > 0),
                      ("count", lambda v: np.isfinite(v) & (v < ens["n_motions"]))):
        v = spread.get(f"{title}|{mode}|{key}")
        if v is not None:
            return np.asarray(test(np.asarray(v, float)), bool)
    return np.zeros(shape, bool)


@styled
def plot(d: dict) -> Figure:
    """Two panels (overturning, excessive tilt); colour = ensemble, line style = mode."""
    titles = ("overturning", "excessive tilt")
    fig, axes, legend_row = with_legend_row(10.0, 6.4, ncols=2, legend_share=0.22)
    handles, modes_seen, notes = [], [], []
    partial = False  # any mean over fewer motions than the ensemble
    for k, ens in enumerate(d["ensembles"]):
        color = ENSEMBLE_COLORS[k % len(ENSEMBLE_COLORS)]
        label = ens["label"]
        if ens["stand_in"] and "stand-in" not in label:
            label += " (stand-in)"
        handles.append(Line2D([], [], color=color, lw=1.6,
                              label="\n".join(textwrap.wrap(label, 48))))
        notes.append(f"{ens['record']}: {ens['axes']['text']}.")
        for ax, title in zip(axes, titles, strict=True):
            for mode, y in ens["panels"].get(title, {}).items():
                ax.plot(ens["R"], y, color=color, ls=MODE_STYLE[mode]["linestyle"], lw=1.6,
                        marker="o", ms=3, label=f"{label}: {MODE_LABELS.get(mode, mode)}")
                few = fewer_motions(ens, title, mode)
                if few.any():  # the mean leaves out motions not reached at the search bound
                    partial = True
                    ax.plot(ens["R"][few], y[few], "o", ms=7, mfc="white", mec=color, mew=1.2)
                if mode not in modes_seen:
                    modes_seen.append(mode)
    handles += [Line2D([], [], color="gray", lw=1.6, ls=MODE_STYLE[m]["linestyle"],
                       label=MODE_LABELS.get(m, m)) for m in modes_seen]
    if partial:
        handles.append(Line2D([], [], ls="", marker="o", ms=7, mfc="white", mec="gray",
                              label="open marker: mean over fewer motions than the ensemble\n"
                                    "(the others not reached at the search bound)"))
    for ax, title in zip(axes, titles, strict=True):
        ax.set_title(limit_state_title("overturning" if title == "overturning" else "tilt:1/3"))
        ax.set_xlabel("R [m]")
        ax.set_ylabel("mean PGA/(g tan α) [-] (bidirectional PGA)")
        ax.set_xlim(left=0.0)
        ax.set_ylim(0.0, ax.get_ylim()[1])  # the data's own top: the legend sits below
        pga_g_axis(ax, d["tan_alpha"])
    if handles:
        # One legend for both panels, in a row below them: colours are ensembles, styles are modes.
        legend_row.legend(handles=handles, loc="center", ncols=3, fontsize=7)
    title = f"3D (bidirectional) versus 2D (one component), tan α = {d['tan_alpha']:g} (Fig 12)"
    if d["missing"]:
        title += "\nreduced run: not everything the paper shows was computed (note below)"
        notes.insert(0, "Not computed in this run: " + "; ".join(d["missing"]) + ".")
    notes.append(f"Axes: {_axes.PAPER_AXES}.")
    footnote(fig, notes)
    fig.suptitle(title)
    return fig
