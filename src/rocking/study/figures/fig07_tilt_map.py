"""Figure 7: contours of the peak normalized tilt θmax/α over (R, PGA/(g tan α)), El Centro.

Reads the tilt map of the study (``results/<study>/tilt_map.zarr``, variable
``theta_max_over_alpha`` with dims (model, R, intensity)); one panel per model present
(undamped left, damped right in the paper).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from . import _load
from ._style import MODE_STYLE, new_figure, styled

VARIABLE = "theta_max_over_alpha"
MODEL_ORDER = ("3d", "3d-damped")
LEVELS = (0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
"""Contour levels of θmax/α [-]; above 1 the cylinder has passed its static stability limit."""
TOP = 1.2
"""Upper edge of the top colour class (θmax > α) [-]."""


def data(path: str | Path) -> dict:
    """Load the map: ``R`` [m], ``intensity`` [-], ``theta_over_alpha[model]`` (R, intensity).

    Models are returned in the paper's order (undamped, damped, then any other).
    """
    ds = _load.open_store(path)
    if VARIABLE not in ds:
        raise ValueError(f"{str(path)!r} has no variable {VARIABLE!r}: {list(ds.data_vars)}")
    da = ds[VARIABLE].transpose("model", "R", "intensity")
    attrs = dict(ds.attrs)  # the store's: motion, tan_alpha, config, tolerances
    models = [str(m) for m in da["model"].values]
    ordered = [m for m in MODEL_ORDER if m in models] + [m for m in models if m not in MODEL_ORDER]
    R = da["R"].values.astype(float)
    intensity = da["intensity"].values.astype(float)
    maps = {m: da.sel(model=m).values.astype(float) for m in ordered}
    measured = {f"first_intensity_theta_above_alpha_{m}": first_above(z, intensity).tolist()
                for m, z in maps.items()}
    measured["R"] = R.tolist()
    return {"R": R, "intensity": intensity, "theta_over_alpha": maps, "attrs": attrs,
            "measured": measured}


def first_above(z: np.ndarray, intensity: np.ndarray, level: float = 1.0) -> np.ndarray:
    """Per R (rows of ``z``), the smallest intensity with θmax/α ≥ ``level``; NaN if none."""
    hit = np.asarray(z) >= level
    first = np.argmax(hit, axis=1)
    return np.where(hit.any(axis=1), intensity[first], np.nan)


@styled
def plot(d: dict) -> Figure:
    """Filled contours of θmax/α, values above 1 (incl. overturning) in one top class."""
    models = list(d["theta_over_alpha"])
    fig, axes = new_figure(4.2 * max(len(models), 1) + 0.8, 4.0, ncols=max(len(models), 1),
                           sharey=True, squeeze=False)
    axes = axes[0]
    # One class above θmax = α (incl. overturning at π/2/α): clip into it so the colour scale
    # stays finite and the detail below α, where the paper's contours are, stays readable.
    levels = [*LEVELS, TOP]
    mappable = None
    for ax, model in zip(axes, models, strict=False):
        z = np.minimum(d["theta_over_alpha"][model].T, 0.5 * (LEVELS[-1] + TOP))
        # NaN (not computed) stays blank; overturned values (θ = π/2) fall in the top class.
        mappable = ax.contourf(d["R"], d["intensity"], np.ma.masked_invalid(z), levels=levels,
                               cmap="viridis", extend="neither")
        ax.contour(d["R"], d["intensity"], np.ma.masked_invalid(z), levels=[1.0],
                   colors="white", linewidths=1.2)
        ax.grid(False)  # grid lines would read as contours
        ax.set_title(MODE_STYLE.get(model, {}).get("label", model) + " model")
        ax.set_xlabel("R [m]")
    if not models:
        axes[0].text(0.5, 0.5, "no tilt map computed", ha="center", transform=axes[0].transAxes)
    axes[0].set_ylabel("PGA/(g tan α) [-]")
    if mappable is not None:
        cbar = fig.colorbar(mappable, ax=list(axes), ticks=[*LEVELS, TOP])
        cbar.ax.set_yticklabels([f"{v:g}" for v in LEVELS] + ["> 1"])
        cbar.set_label("θmax/α [-] (top class: θmax > α, incl. overturning)")
    motion = d["attrs"].get("motion", "El Centro 1940")
    fig.suptitle(f"Normalized peak tilt, scaled record {motion} (Fig 7); white line θmax = α")
    return fig
