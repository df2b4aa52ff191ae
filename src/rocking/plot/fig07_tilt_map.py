"""Figure 7: contours of the peak normalized tilt θmax/α over (R, PGA/(g tan α)) of one record.

Reads the tilt map of the study (``results/<study>/tilt_map.zarr``, variable
``theta_max_over_alpha`` over (mode, R, intensity); older stores name the first dimension
``model``); one panel per model present (undamped left, damped right in the paper). The
contours are drawn on the grid the configuration gives, which the figure states and marks.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from rocking.plot import _axes, _load
from rocking.plot._style import footnote, new_figure, pga_g_axis, styled
from rocking.plot.comparisons import Comparison, finite, first_notes, fmt, judged, rank_correlation
from rocking.spectra.modes import MODE_3D, MODE_3D_DAMPED
from rocking.store.attrs import decode_attrs

if TYPE_CHECKING:
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure

VARIABLE = "theta_max_over_alpha"
MODEL_ORDER = (MODE_3D, MODE_3D_DAMPED)
LEVELS = (0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
"""Contour levels of θmax/α [-]; above 1 the cylinder has passed its static stability limit."""
TOP = 1.2
"""Upper edge of the top colour class (overturned; a class value, not a tilt) [-]."""
TOP_COLOR = "#e8e8e8"
"""The class "overturned": a pale grey, so the area it covers does not outshine the
classes below α, where the paper's contours are."""
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
    """Viridis for the ten classes of θmax/α below 1, then one class for a cylinder that
    passed θmax = α but stayed standing (orange, rare: the few cells where it shows must
    catch the eye) and one for overturning (pale grey, :data:`TOP_COLOR`: it covers most of
    the map and must not outshine the classes below α, where the paper's contours are)."""
    from matplotlib import colormaps
    from matplotlib.colors import ListedColormap

    below = colormaps["viridis"](np.linspace(0.0, 1.0, len(LEVELS) - 1))
    return ListedColormap([*below, "#f58518", TOP_COLOR])


def _class_values(z: np.ndarray, overturned_at: float) -> np.ndarray:
    """θmax/α [-] mapped on the colour classes: below 1 unchanged, above 1 still standing →
    the middle of [1, 1.1), overturned (stored as π/(2α)) → the middle of [1.1, 1.2]; NaN
    (not computed) stays NaN."""
    over = z >= overturned_at * (1.0 - 1e-9)
    return np.where(over, 0.5 * (_TOP_LEVELS[0] + TOP), np.where(
        z >= LEVELS[-1], 0.5 * (LEVELS[-1] + _TOP_LEVELS[0]), z))


_TOP_LEVELS = (1.1,)
"""Edge between the class "θmax > α, standing" and the class "overturned" [-] (class
values, not a tilt: both classes are as wide as the others on the colour bar)."""


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
    """Filled contours of θmax/α below 1; above it two classes of their own: still standing
    (θmax > α) and overturned."""
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import BoundaryNorm

    models = list(d["theta_over_alpha"])
    fig, axes = new_figure(4.2 * max(len(models), 1) + 0.8, 4.4, ncols=max(len(models), 1),
                           sharey=True, squeeze=False)
    axes = axes[0]
    tan_alpha = float(decode_attrs({"t": d["attrs"]["tan_alpha"]})["t"])  # the store's
    overturned_at = 0.5 * np.pi / np.arctan(tan_alpha)  # θ = π/2 over α, as the store keeps it
    levels = [*LEVELS, *_TOP_LEVELS, TOP]
    cmap, norm = class_colors(), BoundaryNorm(levels, len(levels) - 1)
    RR, II = np.meshgrid(d["R"], d["intensity"])
    counts = {"above": 0, "over": 0}
    for ax, model in zip(axes, models, strict=False):
        z = np.asarray(d["theta_over_alpha"][model], dtype=float).T
        counts["over"] += int(np.sum(z >= overturned_at * (1.0 - 1e-9)))
        counts["above"] += int(np.sum((z > LEVELS[-1]) & (z < overturned_at * (1.0 - 1e-9))))
        if min(z.shape) >= 2:
            _contours(ax, d["R"], d["intensity"], z, overturned_at, cmap)
        else:  # one size or one intensity: no contour exists, colour the points
            ax.scatter(RR.ravel(), II.ravel(), c=np.ma.masked_invalid(
                _class_values(z, overturned_at)).ravel(), marker="s", s=90, cmap=cmap,
                norm=norm)
        ax.plot(RR.ravel(), II.ravel(), ".", color="0.45", ms=1.2, alpha=0.6)  # the grid
        ax.grid(False)  # grid lines would read as contours
        ax.set_title(TITLES.get(model, f"{model} model"))
        ax.set_xlabel("R [m]")
    if not models:
        axes[0].text(0.5, 0.5, "no tilt map computed", ha="center", transform=axes[0].transAxes)
    axes[0].set_ylabel("PGA/(g tan α) [-]")
    if models:
        pga_g_axis(axes[-1], float(tan_alpha))
        # every class as wide as the others: the two top ones are classes, not tilt ranges
        centres = [0.5 * (LEVELS[-1] + _TOP_LEVELS[0]), 0.5 * (_TOP_LEVELS[0] + TOP)]
        cbar = fig.colorbar(ScalarMappable(norm=norm, cmap=cmap), ax=list(axes), pad=0.02,
                            spacing="uniform", ticks=[*LEVELS, *centres])
        cbar.ax.set_yticklabels([f"{v:g}" for v in LEVELS] + ["θmax > α, standing",
                                                               "overturned"], fontsize=7)
        cbar.set_label("θmax/α [-] below 1; above: standing or overturned")
    R, inten = d["R"], d["intensity"]
    footnote(fig, [
        f"Grid (dots): {R.size} sizes R = {R.min():g}–{R.max():g} m × {inten.size} intensities "
        f"PGA/(g tan α) = {inten.min():g}–{inten.max():g}; contours interpolate linearly "
        "between grid points.",
        "Classes: ten of 0.1 in θmax/α below α (viridis); orange (squares at the points): "
        f"θmax > α and the cylinder stayed standing ({_points(counts['above'])}); grey: "
        f"overturned, θ reached π/2 ({_points(counts['over'])}; counted over the panels).",
        f"Record on its principal axes: {d['axes']['text']}; PGA = max √(ügx² + ügy²) (vector).",
    ])
    fig.suptitle(f"Normalized peak tilt, tan α = {tan_alpha:g} (Fig 7); black line θmax = α\n"
                 f"scaled record: {record_label(d['attrs'])}")
    return fig


def _points(n: int) -> str:
    return f"{n} grid point" + ("" if n == 1 else "s")


def _contours(ax, R: np.ndarray, intensity: np.ndarray, z: np.ndarray, overturned_at: float,
              cmap: ListedColormap) -> None:
    """Filled classes of one map (z: intensity × R): θmax/α below 1 with everything above in
    the "standing" class, then the overturned area on top, then the line θmax = α.

    Values above 1 are clipped to the middle of the top classes (so the contours between a
    point below α and one above do not depend on how far above it is). The overturned area
    is the contour at 1 of that field with the points standing above α mirrored below 1: its
    edge is the line θmax = α where it meets points below α and falls half way to the
    points standing above α. (One field with a value per class would pass through the
    "standing" colour on every edge between a point below α and an overturned one.)
    """
    clipped = np.minimum(z, _TOP_LEVELS[0])
    ax.contourf(R, intensity, np.ma.masked_invalid(clipped), levels=[*LEVELS, TOP],
                colors=list(cmap.colors[:len(LEVELS)]), extend="neither")
    standing = (z > LEVELS[-1]) & (z < overturned_at * (1.0 - 1e-9))
    if np.any(z >= overturned_at * (1.0 - 1e-9)):
        edge = np.where(standing, 2.0 * LEVELS[-1] - clipped, clipped)
        ax.contourf(R, intensity, np.ma.masked_invalid(edge), levels=[LEVELS[-1], TOP],
                    colors=[TOP_COLOR])
    ax.contour(R, intensity, np.ma.masked_invalid(clipped), levels=[LEVELS[-1]],
               colors="black", linewidths=1.2)
    # a point standing just above α fills a sliver only: mark the point itself
    RR, II = np.meshgrid(R, intensity)
    ax.scatter(RR[standing], II[standing], marker="s", s=22, color=cmap.colors[len(LEVELS) - 1],
               edgecolors="black", linewidths=0.6, zorder=3)


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

from rocking.plot.registry import FigureSpec  # noqa: E402

FIGURE = FigureSpec(
    name="fig07_tilt_map", module=__name__, number=7, label="Fig 7",
    caption=(
        "Contours of the peak normalized tilt θmax/α over cylinder size R and normalized "
        "intensity PGA/(g tan α) for the study's scaled record (principal axes, "
        "high-passed), at the slenderness in the title, one panel per model; PGA is the "
        "vector peak max √(ügx² + ügy²); right axis PGA in g. Contours are drawn on the "
        "grid the configuration gives (dots); the black line is θmax = α. Classes: ten of "
        "0.1 in θmax/α below α; orange (squares at the grid points) θmax > α with the "
        "cylinder still standing; grey overturned (θ reached π/2)."
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
