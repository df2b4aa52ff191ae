"""Peak tilt over a grid of sizes and intensities for one motion (the paper's Fig 7)."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import xarray as xr

from rocking._progress import maybe as _progress
from rocking._validate import positive_finite
from rocking.dynamics.bodies import Cylinder
from rocking.dynamics.contact import Contact
from rocking.dynamics.result import Status
from rocking.motions.motion import GroundMotion
from rocking.spectra.accuracy import Accuracy
from rocking.spectra.critical import make_analysis, uplift_intensity
from rocking.spectra.modes import MODE_3D, MODES, check_mode
from rocking.spectra.search import RETRY_RTOL_FACTOR, checked
from rocking.units import attrs


def tilt_map(
    R_values: Sequence[float],
    tan_alpha: float,
    motion: GroundMotion,
    intensities: Sequence[float],
    mode: str = MODE_3D,
    *,
    accuracy: str | Accuracy | dict = "default",
    omega_n: float | None = None,
    zeta: float | None = None,
    progress=False,
) -> xr.Dataset:
    """Peak normalized tilt θ_max/α over a grid of sizes and intensities (paper Fig 7).

    Parameters
    ----------
    R_values : sequence of float
        Cylinder semi-diagonals [m].
    tan_alpha : float
        Slenderness [-].
    motion : GroundMotion
        Unscaled pair; intensities are normalized by its vector PGA.
    intensities : sequence of float
        Normalized intensities PGA/(g tan α) [-], > 0.
    mode : str
        As in :func:`critical_intensity`.
    accuracy : str, Accuracy or dict
        Only its ODE tolerance is used.
    omega_n, zeta : float, optional
        Damped-model parameters.
    progress : bool or rocking._progress.Progress
        True: report analyses done / total, rate and ETA on stderr.

    Returns
    -------
    xarray.Dataset
        ``theta_max_over_alpha`` (R, intensity) [-] (π/(2α) where overturned, 0 below uplift,
        NaN where the analysis failed twice), ``overturned`` and ``failed`` (bool); the
        coordinate ``pga_g`` gives each intensity as PGA [g]. Every variable and
        coordinate has CF ``units`` and ``long_name``.
    """
    check_mode(mode)
    acc = Accuracy.of(accuracy)
    contact = Contact.of(omega_n, zeta)
    R_arr = np.array([positive_finite("R", r) for r in R_values], dtype=float)
    I_arr = np.array([positive_finite("intensity", i) for i in intensities], dtype=float)
    lower = uplift_intensity(motion, mode)
    rtol = acc.rtol_for(MODES[mode][0])
    ratio = np.zeros((R_arr.size, I_arr.size))
    overturned = np.zeros(ratio.shape, dtype=bool)
    failed = np.zeros(ratio.shape, dtype=bool)
    bar = _progress(progress, ratio.size, f"tilt map {mode}", unit="analysis")
    for i, R in enumerate(R_arr):
        body = Cylinder(R, tan_alpha)
        analyze = make_analysis(body, motion, mode, contact=contact,
                                rest_tilt=acc.rest_tilt)
        for j, intensity in enumerate(I_arr):
            if intensity <= lower:
                if bar is not None:
                    bar.update()
                continue  # below uplift the body stays at rest
            out = checked(analyze(intensity, None, rtol))
            if out.status is Status.FAILED:
                out = checked(analyze(intensity, None, rtol * RETRY_RTOL_FACTOR))
            failed[i, j] = out.status is Status.FAILED
            overturned[i, j] = out.overturned
            theta = 0.5 * math.pi if out.overturned else out.theta_max
            ratio[i, j] = np.nan if failed[i, j] else theta / body.alpha
            if bar is not None:
                bar.update()
    if bar is not None and bar is not progress:
        bar.close()
    coords = {"R": ("R", R_arr, attrs("R")),
              "intensity": ("intensity", I_arr, attrs("intensity")),
              "pga_g": ("intensity", I_arr * float(tan_alpha), attrs("pga_g"))}
    return xr.Dataset(
        {
            "theta_max_over_alpha": (("R", "intensity"), ratio, attrs("theta_max_over_alpha")),
            "overturned": (("R", "intensity"), overturned, attrs("overturned")),
            "failed": (("R", "intensity"), failed, attrs("failed")),
        },
        coords=coords,
        attrs={"mode": mode, "tan_alpha": float(tan_alpha), "motion": motion.name,
               "rtol": rtol, "pga_g": motion.pga_g},
    )
