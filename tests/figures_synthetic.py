"""Tiny synthetic study outputs with the layouts of docs/design.md, for figure/report tests.

Values follow a known formula so tests can check what the figures and tables receive:
pga_crit = (1 + r_ls) · (0.5 + 0.4 R) · f_motion · f_mode, with a few points not reached
(stored at the search bound UPPER, as the engine does). A partially computed store (modes
requested only at some slendernesses) leaves the other cells NaN and not flagged, as a study
with per-mode configuration does; limit states can be spelt either way ("tilt:0.3333" or the
canonical "tilt:1/3") and the tilt map's first dimension named "model" or "mode".
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr

from rocking.config.damping import Damping
from rocking.config.ensemble import EnsembleSpec
from rocking.config.plan import plan_study
from rocking.config.products import SpectraSpec, TiltMapSpec
from rocking.spectra.accuracy import PRESETS

MODES = ["3d", "3d-damped", "3d-x", "3d-y", "2d-x", "2d-y"]
LIMIT_STATES = ["tilt:0.1", "tilt:0.3333", "tilt:0.6", "overturning"]
MOTIONS = ["el-centro-1940", "synthetic-01", "synthetic-02", "synthetic-03"]
TAN_ALPHA = [0.1, 0.2, 0.3]
R = [1.0, 2.0, 4.0, 6.0, 10.0]
UPPER = 30.0
QUANTITY = {"name": "exceedance_quantile", "p": 0.1, "w": 0.02}
"""The quantity of the synthetic store (the default: I10)."""
MODE_FACTOR = {"3d": 1.0, "3d-damped": 1.05, "3d-x": 1.9, "3d-y": 1.6, "2d-x": 2.0,
               "2d-y": 1.8}
LS_FACTOR = {"tilt:0.1": 0.2, "tilt:0.3333": 0.5, "tilt:0.6": 0.8, "overturning": 3.0}


ENSEMBLE = EnsembleSpec("synth", "el-centro-1940", None, 3, 2017, None, "auto", "spectrum",
                        None)
"""The ensemble the synthetic stores record in their ``config`` (as the workflow would)."""


def spectra_spec(modes: list[str], limit_states: list[str]) -> SpectraSpec:
    """The study description a synthetic spectra store records (its ``config`` attribute)."""
    plan = plan_study([{"modes": modes, "tan_alpha": TAN_ALPHA, "limit_states": limit_states}])
    return SpectraSpec("synth", ENSEMBLE, tuple(R), plan, 1, None, PRESETS["default"],
                       QUANTITY, UPPER,
                       Damping.of_modes({"damped": {"omega_n": 2000.0, "zeta": 5.0}}, modes))


def pga_crit_formula() -> np.ndarray:
    """Array (mode, limit_state, motion, tan_alpha, R) of the synthetic critical intensities."""
    m = np.array([MODE_FACTOR[k] for k in MODES])[:, None, None, None, None]
    ls = (1.0 + np.array([LS_FACTOR[k] for k in LIMIT_STATES]))[None, :, None, None, None]
    mo = np.array([1.0, 0.8, 1.25, 1.1])[None, None, :, None, None]
    ta = np.array([1.02, 1.0, 0.97])[None, None, None, :, None]
    r = (0.5 + 0.4 * np.array(R))[None, None, None, None, :]
    return m * ls * mo * ta * r


def write_study(root: Path, *, ensemble: str = "El Centro 1940 ensemble",
                stand_in: bool = False, modes: list[str] | None = None,
                with_tilt_map: bool = True, requested: dict[str, list[float]] | None = None,
                limit_states: list[str] | None = None, tilt_dim: str = "model",
                with_motions: bool = True) -> dict[str, Path]:
    """Write spectra.zarr, mean_spectra.nc/.csv, tilt_map.zarr and motions.nc under ``root``.

    ``requested`` maps a mode to the slendernesses it was computed at (default: all); the other
    cells of that mode stay NaN and not flagged. ``limit_states`` respells :data:`LIMIT_STATES`
    (same order and ratios).
    """
    modes = MODES if modes is None else modes
    keep = [MODES.index(m) for m in modes]
    root.mkdir(parents=True, exist_ok=True)
    values = pga_crit_formula()[keep]
    not_reached = values > UPPER
    # two points the search bound cut off, as the engine would store them
    not_reached[0, -1, 1, 1, 0] = True
    not_reached[0, -1, 2, 1, 0] = True
    values = np.where(not_reached, UPPER, values)
    for i, mode in enumerate(modes):
        for j, t in enumerate(TAN_ALPHA):
            if requested is not None and mode in requested and t not in requested[mode]:
                values[i, :, :, j, :] = np.nan
                not_reached[i, :, :, j, :] = False
    dims = ("mode", "limit_state", "motion", "tan_alpha", "R")
    coords = {
        "mode": np.array(modes, dtype=object),
        "limit_state": np.array(limit_states or LIMIT_STATES, dtype=object),
        "motion": np.array(MOTIONS, dtype=object),
        "tan_alpha": np.array(TAN_ALPHA),
        "R": np.array(R),
    }
    ds = xr.Dataset(
        {
            "pga_crit": (dims, values),
            "i50": (dims, 1.3 * values),
            "first_exceedance": (dims, 0.98 * values),
            "plateau": (dims, np.zeros_like(not_reached)),
            "not_reached": (dims, not_reached),
            "non_monotonic": (dims, np.zeros_like(not_reached)),
            "n_analyses": (dims, np.full(values.shape, 12, np.int32)),
            "done": (("mode", "motion", "tan_alpha", "R"),
                     np.ones((len(modes), len(MOTIONS), len(TAN_ALPHA), len(R)), bool)),
        },
        coords=coords,
        attrs={
            "config": json.dumps(spectra_spec(modes, limit_states or LIMIT_STATES).to_attrs()),
            "tolerances": json.dumps({"intensity_rtol": 0.01}),
            "quantity": json.dumps(QUANTITY),
            "rocking_version": "0.1.0",
            "ensemble": json.dumps({"label": ensemble, "stand_in": stand_in, "name": "synth",
                                    "motions": [{"name": m, "label": m, "PGA": 2.7 / 9.80665}
                                                for m in MOTIONS]}),
            "search_options": json.dumps({"upper": UPPER, "omega_n": 2000.0, "zeta": 5.0}),
        },
    )
    paths = {"store": root / "spectra.zarr", "means": root / "mean_spectra.nc",
             "means_csv": root / "mean_spectra.csv"}
    ds.to_zarr(paths["store"], mode="w", zarr_format=3, consolidated=False)
    reached = ds["pga_crit"].where(~ds["not_reached"])
    means = xr.Dataset(
        {
            "mean": reached.mean("motion"),
            "std": reached.std("motion", ddof=1),
            "median": reached.median("motion"),
            "count": reached.notnull().sum("motion").astype(np.int32),
        },
        attrs=ds.attrs,
    ).transpose("mode", "limit_state", "tan_alpha", "R")
    means.to_netcdf(paths["means"])
    means.to_dataframe().reset_index().to_csv(paths["means_csv"], index=False)
    if with_tilt_map:
        paths["tilt_map"] = root / "tilt_map.zarr"
        write_tilt_map(paths["tilt_map"], dim=tilt_dim)
    if with_motions:
        paths["motions"] = root / "motions.nc"
        write_motions(paths["motions"])
    return paths


RECORD_AZIMUTHS = (340.46, 250.46)
"""Azimuths of x and y of the synthetic record [deg]: x N19.5°W, y S70.5°W."""


def write_motions(path: Path, n: int = 2, duration: float = 3.0):
    """A small ensemble file whose record (first motion) is on principal axes with azimuths."""
    from rocking import GroundMotion
    from rocking.motions.ensemble_io import save_ensemble

    dt = 0.01
    t = np.arange(0.0, duration, dt)
    env = np.sin(np.pi * t / duration) ** 2
    meta = {"axes": "principal (x = major)", "x_azimuth": RECORD_AZIMUTHS[0],
            "y_azimuth": RECORD_AZIMUTHS[1], "title": "synthetic record"}
    motions = [GroundMotion(4.0 * env * np.sin(2 * np.pi * (1.5 + 0.2 * i) * t),
                            3.0 * env * np.cos(2 * np.pi * 1.1 * t), dt, name,
                            meta if i == 0 else {"axes": "principal (x = major)"})
               for i, name in enumerate(["el-centro-1940", *[f"synthetic-{k:02d}"
                                                          for k in range(1, n)]])]
    save_ensemble(path, motions)
    return motions


def tilt_map_formula(R_: np.ndarray, intensity: np.ndarray, damped: bool) -> np.ndarray:
    """θmax/α (R, intensity): grows with intensity, falls with R, π/2/α once overturned."""
    x = (intensity[None, :] - 1.0) / (0.6 + 0.25 * R_[:, None]) * (0.8 if damped else 1.0)
    val = np.clip(x, 0.0, None) ** 1.5 * 0.4
    return np.where(val > 1.3, np.pi / 2 / np.arctan(0.2), val)


def write_tilt_map(path: Path, dim: str = "model") -> xr.Dataset:
    """A tilt map store with dims (``dim``, R, intensity), ``dim`` "model" or "mode"."""
    R_ = np.array([1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 10.0])
    intensity = np.linspace(1.0, 8.0, 15)
    z = np.stack([tilt_map_formula(R_, intensity, d) for d in (False, True)])
    ds = xr.Dataset(
        {"theta_max_over_alpha": ((dim, "R", "intensity"), z)},
        coords={dim: np.array(["3d", "3d-damped"], dtype=object), "R": R_,
                "intensity": intensity},
        attrs={"motion": "el-centro-1940", "tan_alpha": "0.2",
               "config": json.dumps(TiltMapSpec(
                   "synth", ENSEMBLE, ("3d", "3d-damped"), 0.2, tuple(R_.tolist()),
                   tuple(intensity.tolist()), 1, PRESETS["default"],
                   Damping(2000.0, 5.0)).to_attrs())},
    )
    ds.to_zarr(path, mode="w", zarr_format=3, consolidated=False)
    return ds
