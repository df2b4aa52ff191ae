"""Figure 7: contours of the peak normalized tilt θmax/α over (R, PGA/(g tan α)) of one record.

Reads the tilt map of the study (``results/<study>/tilt_map.zarr``, variable
``theta_max_over_alpha`` over (mode, R, intensity); older stores name the first dimension
``model``); one panel per model present (undamped left, damped right in the paper). The
contours are drawn on the grid the configuration gives, which the figure states and marks.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np
from matplotlib import colormaps
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.figure import Figure

from ..spectra.modes import MODE_3D, MODE_3D_DAMPED
from ..study.store_attrs import decode_attrs
from . import _axes, _load
from ._style import footnote, new_figure, pga_g_axis, styled
from .comparisons import Comparison, finite, first_notes, fmt, judged, rank_correlation

VARIABLE = "theta_max_over_alpha"
MODEL_ORDER = (MODE_3D, MODE_3D_DAMPED)
LEVELS = (0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
"""Contour levels of θmax/α [-]; above 1 the cylinder has passed its static stability limit."""
TOP = 1.2
"""Upper edge of the top colour class (θmax > α) [-]."""
TOP_COLOR = "#e8e8e8"
"""The class θmax > α (incl. overturning): a pale grey, so the area it covers does
not outshine the classes below α, where the paper's contours are."""
TITLES = {MODE_3D: "Undamped 3D model", MODE_3D_DAMPED: "Damped 3D model"}


def record_label(attrs: dict) -> str:
    """Who the tilt map scales: the label of the store's ``motion`` in its ``ensemble``
    attribute (a record's name, e.g. "1940 Imperial Valley, El Centro Array #9 (NGA-West2
    RSN 6)"), else the motion's name."""
    attrs = decode_attrs(attrs)
    motions = attrs.get("ensemble", {}).get("motions", []) if isinstance(
        attrs.get("ensemble"), dict) else []
    found = [m.get("label", m["name"]) for m in motions if m.get("name") == attrs["motion"]]
    return found[0] if found else str(attrs["motion"])


def class_colors() -> ListedColormap:
    """Viridis for the classes of θmax/α below 1, pale grey for the top class (> 1)."""
    below = colormaps["viridis"](np.linspace(0.0, 1.0, len(LEVELS) - 1))
    return ListedColormap([*below, TOP_COLOR])


def data(path: str | Path, motions: str | Path | None = None) -> dict:
    """Load the map: ``R`` [m], ``intensity`` [-], ``theta_over_alpha[mode]`` (R, intensity).

    Parameters
    ----------
    path : path
        The tilt-map store.
    motions : path, optional
        The ensemble file, for the physical directions of the record's x and y.

    Models are returned in the paper's order (undamped, damped, then any other).
    """
    ds = _load.open_store(path)
    if VARIABLE not in ds:
        raise ValueError(f"{str(path)!r} has no variable {VARIABLE!r}: {list(ds.data_vars)}")
    da = ds[VARIABLE].transpose("mode", "R", "intensity")
    attrs = dict(ds.attrs)  # the store's: motion, tan_alpha, config, tolerances
    models = _load.labels(da, "mode")
    ordered = [m for m in MODEL_ORDER if m in models] + [m for m in models if m not in MODEL_ORDER]
    R = da["R"].values.astype(float)
    intensity = da["intensity"].values.astype(float)
    maps = {m: da.sel(mode=m).values.astype(float) for m in ordered}
    return {"R": R, "intensity": intensity, "theta_over_alpha": maps, "attrs": attrs,
            "axes": _axes.from_ensemble(motions),
            "grid": {"R": R.tolist(), "intensity": intensity.tolist()},
            "measured": measurements(R, intensity, maps)}


def first_above(z: np.ndarray, intensity: np.ndarray, level: float = 1.0) -> np.ndarray:
    """Per R (rows of ``z``), the smallest intensity with θmax/α ≥ ``level``; NaN if none."""
    hit = np.asarray(z) >= level
    first = np.argmax(hit, axis=1)
    return np.where(hit.any(axis=1), intensity[first], np.nan)


def measurements(R: np.ndarray, intensity: np.ndarray, maps: dict) -> dict:
    """Per model the lowest intensity with θmax ≥ α per R and whether it grows with R; between
    models the relative gap of those intensities and the mean |Δ(θmax/α)| below α."""
    out: dict = {"R": R.tolist()}
    firsts = {}
    for m, z in maps.items():
        firsts[m] = first_above(z, intensity)
        out[f"first_intensity_theta_above_alpha_{m}"] = firsts[m].tolist()
        steps = np.diff(firsts[m][np.isfinite(firsts[m])])
        out[f"fraction_rising_{m}"] = float(np.mean(steps >= 0)) if steps.size else None
    if MODE_3D in maps and MODE_3D_DAMPED in maps:
        a, b = firsts[MODE_3D], firsts[MODE_3D_DAMPED]
        both = np.isfinite(a) & np.isfinite(b)
        out["max_rel_gap_first_intensity"] = (float(np.max(np.abs(b[both] - a[both]) / a[both]))
                                              if both.any() else None)
        za, zb = maps[MODE_3D], maps[MODE_3D_DAMPED]
        below = (za < 1.0) & (zb < 1.0) & np.isfinite(za) & np.isfinite(zb)
        out["mean_abs_gap_below_alpha"] = (float(np.mean(np.abs(za - zb)[below]))
                                           if below.any() else None)
    return out


@styled
def plot(d: dict) -> Figure:
    """Filled contours of θmax/α, values above 1 (incl. overturning) in one top class."""
    models = list(d["theta_over_alpha"])
    fig, axes = new_figure(4.2 * max(len(models), 1) + 0.8, 4.4, ncols=max(len(models), 1),
                           sharey=True, squeeze=False)
    axes = axes[0]
    # One class above θmax = α (incl. overturning at π/2/α): clip into it so the colour scale
    # stays finite and the detail below α, where the paper's contours are, stays readable.
    levels = [*LEVELS, TOP]
    mappable = None
    RR, II = np.meshgrid(d["R"], d["intensity"])
    for ax, model in zip(axes, models, strict=False):
        z = np.minimum(d["theta_over_alpha"][model].T, 0.5 * (LEVELS[-1] + TOP))
        # NaN (not computed) stays blank; overturned values (θ = π/2) fall in the top class.
        zm = np.ma.masked_invalid(z)
        if min(z.shape) >= 2:
            mappable = ax.contourf(d["R"], d["intensity"], zm, levels=levels,
                                   cmap=class_colors(), extend="neither")
            ax.contour(d["R"], d["intensity"], zm, levels=[1.0], colors="black",
                       linewidths=1.2)
        else:  # one size or one intensity: no contour exists, colour the points
            norm = BoundaryNorm(levels, len(levels) - 1)
            mappable = ax.scatter(RR.ravel(), II.ravel(), c=zm.ravel(), marker="s", s=90,
                                  cmap=class_colors(), norm=norm)
        ax.plot(RR.ravel(), II.ravel(), ".", color="0.45", ms=1.2, alpha=0.6)  # the grid
        ax.grid(False)  # grid lines would read as contours
        ax.set_title(TITLES.get(model, f"{model} model"))
        ax.set_xlabel("R [m]")
    if not models:
        axes[0].text(0.5, 0.5, "no tilt map computed", ha="center", transform=axes[0].transAxes)
    axes[0].set_ylabel("PGA/(g tan α) [-]")
    tan_alpha = float(decode_attrs({"t": d["attrs"]["tan_alpha"]})["t"])  # the store's
    if models:
        pga_g_axis(axes[-1], float(tan_alpha))
    if mappable is not None:
        cbar = fig.colorbar(mappable, ax=list(axes), ticks=[*LEVELS, TOP], pad=0.08)
        cbar.ax.set_yticklabels([f"{v:g}" for v in LEVELS] + ["> 1"])
        cbar.set_label("θmax/α [-] (grey top class: θmax > α, incl. overturning)")
    R, inten = d["R"], d["intensity"]
    footnote(fig, [
        f"Grid (dots): {R.size} sizes R = {R.min():g}–{R.max():g} m × {inten.size} intensities "
        f"PGA/(g tan α) = {inten.min():g}–{inten.max():g}; contours interpolate linearly "
        "between grid points.",
        f"Record on its principal axes: {d['axes']['text']}; PGA = max √(ügx² + ügy²) (vector).",
    ])
    fig.suptitle(f"Normalized peak tilt, tan α = {tan_alpha:g} (Fig 7); black line θmax = α\n"
                 f"scaled record: {record_label(d['attrs'])}")
    return fig


# ------------------------------------------------------ comparison with the paper


def compare(notes: Mapping) -> list[Comparison]:
    """This figure's statements of the paper set against the run's notes."""
    m = first_notes(notes, "fig07_tilt_map").get("measured", {})
    name = "fig07_tilt_map"
    firsts = {k.rsplit("_", 1)[1]: v for k, v in m.items()
              if k.startswith("first_intensity_theta_above_alpha_")}
    ours = "; ".join(f"{mod}: " + ", ".join(f"{fmt(v, 3)}" for v in vals)
                     for mod, vals in firsts.items())
    trend = {mod: rank_correlation(m.get("R"), vals) for mod, vals in firsts.items()}
    ok = all(finite(r) and r >= 0.7 for r in trend.values()) if trend else None
    gap = m.get("mean_abs_gap_below_alpha")
    corr = "; ".join(f"{mod} {fmt(r, 2)}" for mod, r in trend.items())
    return [
        judged(name, "Larger cylinders are harder to overturn (§5, Fig 7)",
               "intensity to reach θmax = α grows with R",
               f"lowest PGA/(g tan α) with θmax ≥ α at R = {m.get('R')} m: {ours}; rank "
               f"correlation with R: {corr}", ok,
               "Spearman rank correlation with R ≥ 0.7 (it rises overall; narrow windows of "
               "exceedance make single steps fall)",
               "the intensity to reach θmax = α does not rise with R on this grid",
               "no tilt map computed"),
        judged(name, "'The damped and undamped models give almost identical overturning "
               "spectra' (§5, Fig 7)", "almost identical maps",
               f"mean |Δ(θmax/α)| below α = {fmt(gap, 3)}; largest relative gap of the "
               f"intensity reaching θmax = α: {fmt(m.get('max_rel_gap_first_intensity'), 2)}",
               gap <= 0.05 if finite(gap) else None, "mean |Δ(θmax/α)| ≤ 0.05",
               "the damped model's map departs from the undamped one",
               "both models are needed"),
    ]


# ---------------------------------------------------------------- the figure's entry

from .registry import FigureSpec  # noqa: E402

FIGURE = FigureSpec(
    name="fig07_tilt_map", module=__name__, number=7, label="Fig 7",
    caption=(
        "Contours of the peak normalized tilt θmax/α over cylinder size R and normalized "
        "intensity PGA/(g tan α) for the study's scaled record (principal axes, "
        "high-passed), at the slenderness in the title, one panel per model; PGA is the "
        "vector peak max √(ügx² + ügy²); right axis PGA in g. Contours are drawn on the "
        "grid the configuration gives (dots); the black line is θmax = α and the pale grey "
        "top class θmax > α, which includes overturning."
    ),
    paper=(
        "The paper's Fig 7: the El Centro record at tan α = 0.2, undamped (left) and damped "
        "(right); it reports that larger cylinders are harder to overturn and that both "
        "models give almost identical maps."
    ),
    scope="study", wanted=lambda s: s.spec().tilt_map is not None,
    inputs={"complete": "tilt_map", "motions": "motions"},
    params={"path": "tilt_map_store"},
    el_centro_only=True)
"""Fig 7, for every study with a tilt map."""
