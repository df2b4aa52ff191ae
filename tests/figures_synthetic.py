"""Tiny synthetic study outputs with the layouts of docs/design.md, for figure/report tests.

Values follow a known formula so tests can check what the figures and tables receive:
pga_crit = (1 + r_ls) · (0.5 + 0.4 R) · f_motion · f_mode, with a few points not reached
(stored at the search bound UPPER, as the engine does).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import xarray as xr

MODES = ["3d", "3d-damped", "2d-x", "2d-y"]
LIMIT_STATES = ["tilt:0.1", "tilt:0.3333", "tilt:0.6", "overturning"]
MOTIONS = ["el-centro-1940", "synthetic-01", "synthetic-02", "synthetic-03"]
TAN_ALPHA = [0.1, 0.2, 0.3]
R = [1.0, 2.0, 4.0, 6.0, 10.0]
UPPER = 30.0
MODE_FACTOR = {"3d": 1.0, "3d-damped": 1.05, "2d-x": 2.0, "2d-y": 1.8}
LS_FACTOR = {"tilt:0.1": 0.2, "tilt:0.3333": 0.5, "tilt:0.6": 0.8, "overturning": 3.0}


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
                with_tilt_map: bool = True) -> dict[str, Path]:
    """Write spectra.zarr, mean_spectra.nc/.csv and tilt_map.zarr under ``root``."""
    modes = MODES if modes is None else modes
    keep = [MODES.index(m) for m in modes]
    root.mkdir(parents=True, exist_ok=True)
    values = pga_crit_formula()[keep]
    not_reached = values > UPPER
    # two points the search bound cut off, as the engine would store them
    not_reached[0, -1, 1, 1, 0] = True
    not_reached[0, -1, 2, 1, 0] = True
    values = np.where(not_reached, UPPER, values)
    dims = ("mode", "limit_state", "motion", "tan_alpha", "R")
    coords = {
        "mode": np.array(modes, dtype=object),
        "limit_state": np.array(LIMIT_STATES, dtype=object),
        "motion": np.array(MOTIONS, dtype=object),
        "tan_alpha": np.array(TAN_ALPHA),
        "R": np.array(R),
    }
    ds = xr.Dataset(
        {
            "pga_crit": (dims, values),
            "not_reached": (dims, not_reached),
            "non_monotonic": (dims, np.zeros_like(not_reached)),
            "n_analyses": (dims, np.full(values.shape, 12, np.int32)),
            "done": (("mode", "motion", "tan_alpha", "R"),
                     np.ones((len(modes), len(MOTIONS), len(TAN_ALPHA), len(R)), bool)),
        },
        coords=coords,
        attrs={
            "config": json.dumps({"spectra": {"upper": UPPER}}),
            "tolerances": json.dumps({"intensity_rtol": 0.01}),
            "rocking_version": "0.1.0",
            "ensemble": json.dumps({"label": ensemble, "stand_in": stand_in}),
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
            "count": (~ds["not_reached"]).sum("motion").astype(np.int32),
        },
        attrs=ds.attrs,
    ).transpose("mode", "limit_state", "tan_alpha", "R")
    means.to_netcdf(paths["means"])
    means.to_dataframe().reset_index().to_csv(paths["means_csv"], index=False)
    if with_tilt_map:
        paths["tilt_map"] = root / "tilt_map.zarr"
        write_tilt_map(paths["tilt_map"])
    return paths


def tilt_map_formula(R_: np.ndarray, intensity: np.ndarray, damped: bool) -> np.ndarray:
    """θmax/α (R, intensity): grows with intensity, falls with R, π/2/α once overturned."""
    x = (intensity[None, :] - 1.0) / (0.6 + 0.25 * R_[:, None]) * (0.8 if damped else 1.0)
    val = np.clip(x, 0.0, None) ** 1.5 * 0.4
    return np.where(val > 1.3, np.pi / 2 / np.arctan(0.2), val)


def write_tilt_map(path: Path) -> xr.Dataset:
    """A tilt map store with dims (model, R, intensity)."""
    R_ = np.array([1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 10.0])
    intensity = np.linspace(1.0, 8.0, 15)
    z = np.stack([tilt_map_formula(R_, intensity, d) for d in (False, True)])
    ds = xr.Dataset(
        {"theta_max_over_alpha": (("model", "R", "intensity"), z)},
        coords={"model": np.array(["3d", "3d-damped"], dtype=object), "R": R_,
                "intensity": intensity},
        attrs={"motion": "el-centro-1940", "tan_alpha": "0.2"},
    )
    ds.to_zarr(path, mode="w", zarr_format=3, consolidated=False)
    return ds
