"""Identification of the Rezaeian–Der Kiureghian parameters from a record.

Per component:

1. Ia, D5-95 and t_mid from the Husid function; the gamma envelope (T0 = 0) matches them
   exactly.
2. f_mid and f′ from the cumulative zero-level up-crossings: a quadratic fitted through nine
   equally spaced samples of N₀⁺(t) between t_0.01 and t_0.99 has derivative f_f(t).
3. The spectral parameters, by one of two methods:

   - ``"spectrum"`` (default): the extended model whose ensemble's median 5 %-damped
     response spectrum matches the record's (:mod:`.spectrum_fit`); steps 1–2 give the
     envelope and the relative drift of the filter frequency.
   - ``"counts"`` (RDK 2010): ζ_f from the cumulative count of positive minima and negative
     maxima on [t_0.05, t_0.95]: the root of the signed area between the record's curve and
     the mean curve of unmodulated simulations (common random numbers for every ζ),
     bracketed on a grid and interpolated linearly (the SCEC BBP procedure), optionally
     refined by Brent's method. One narrow-band filter: it reproduces the record's crossing
     and extrema rates, not its response spectrum.

:func:`fit_rdk` does this for both principal components of a bidirectional motion.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

from rocking._json import to_plain
from rocking._validate import finite_array, positive_finite
from rocking.motions.counts import pmnm_cum, zero_upcrossings_cum
from rocking.motions.intensity import husid, times_from_husid
from rocking.motions.motion import GroundMotion
from rocking.motions.stochastic.discretize import DEFAULT_FC_HZ, time_domain
from rocking.motions.stochastic.filter import DEFAULT_FLOOR_HZ
from rocking.motions.stochastic.params import RDKParams
from rocking.motions.stochastic.spectrum_fit import fit_spectrum

#: Identification methods of :func:`fit_component` and :func:`fit_rdk`.
METHODS = ("spectrum", "counts")

#: ζ grid of the bracketing search (docs/equations.md, "Identification": 0.02, 0.05, 0.10, …, 0.90).
ZETA_GRID: tuple[float, ...] = (0.02, *[round(0.05 * i, 2) for i in range(1, 19)])

#: Husid fractions recorded in the diagnostics.
_FRACTIONS = (0.01, 0.05, 0.45, 0.95, 0.99)


@dataclass(frozen=True)
class ZetaSearch:
    """Outcome of the ζ_f search: the estimate and every (ζ, e(ζ)) evaluated."""

    zeta: float
    evaluated: dict[float, float]
    clipped: bool


def husid_times(a: ArrayLike, dt: float) -> dict[str, float]:
    """Ia [m/s] and t_0.01, t_0.05, t_0.45, t_0.95, t_0.99 [s] of a record."""
    h = husid(a, dt)
    ts = times_from_husid(h, dt, list(_FRACTIONS))
    out = {"Ia": float(h[-1])}
    out.update({f"t{round(100 * p):02d}": float(t) for p, t in zip(_FRACTIONS, ts, strict=True)})
    return out


def fit_frequency(
    a: ArrayLike, dt: float, t01: float, t99: float, t_mid: float, n_points: int = 9
) -> tuple[float, float, NDArray[np.float64]]:
    """f_mid [Hz] and f′ [Hz/s] from the cumulative zero up-crossings (docs/equations.md,
    "Identification").

    Parameters
    ----------
    a : array_like
        Acceleration [any unit], 1-D.
    dt : float
        Time step [s].
    t01, t99 : float
        Window of the fit [s] (t_0.01, t_0.99 of the record).
    t_mid : float
        Time at which f_mid is evaluated [s].
    n_points : int
        Number of equally spaced samples of N₀⁺(t) fitted by least squares (≥ 3).

    Returns
    -------
    (float, float, numpy.ndarray)
        f_mid, f′ and the coefficients (c₀, c₁, c₂) of N(t) ≈ c₀ + c₁t + c₂t².
    """
    x = finite_array("a", a)
    dt = positive_finite("dt", dt)
    if not 0.0 <= t01 < t99 <= (x.size - 1) * dt:
        raise ValueError(f"need 0 <= t01 < t99 <= record end, got t01={t01!r}, t99={t99!r}")
    if n_points < 3:
        raise ValueError(f"n_points must be >= 3 for a quadratic, got {n_points!r}")
    n_up = zero_upcrossings_cum(x)
    ts = np.linspace(t01, t99, n_points)
    counts = np.interp(ts, np.arange(x.size) * dt, n_up)
    c = np.polynomial.polynomial.polyfit(ts, counts, 2)
    # f_f(t) = dN/dt = c₁ + 2c₂t: the slope is 2c₂ (a public code uses c₂ by mistake).
    return float(c[1] + 2.0 * c[2] * t_mid), float(2.0 * c[2]), c


def _window(t05: float, t95: float, dt: float) -> tuple[int, int]:
    """Indices of the first and last samples inside [t05, t95]."""
    return int(math.ceil(t05 / dt - 1e-9)), int(math.floor(t95 / dt + 1e-9))


def fit_zeta(
    a: ArrayLike,
    dt: float,
    trial: RDKParams,
    t05: float,
    t95: float,
    *,
    zeta_grid: tuple[float, ...] = ZETA_GRID,
    n_sim: int = 50,
    seed: int = 0,
    refine: bool = False,
    floor_hz: float = DEFAULT_FLOOR_HZ,
) -> ZetaSearch:
    """ζ_f from the positive-minima + negative-maxima count on [t_0.05, t_0.95]
    (docs/equations.md, "Identification").

    Parameters
    ----------
    a : array_like
        Record acceleration, 1-D, on the step ``dt``.
    dt : float
        Time step [s]; the simulations use the same step (the count depends on it).
    trial : RDKParams
        Parameters with the fitted envelope and filter frequency (its ζ_f is ignored).
    t05, t95 : float
        Counting window [s].
    zeta_grid : tuple of float
        Increasing ζ values in (0, 1) bracketing the root.
    n_sim : int
        Number of unmodulated simulations averaged per ζ (the same noise for every ζ).
        20 is the usual minimum; the default 50 halves the seed scatter of ζ̂ (El Centro
        major component: sd 0.004 with 20, 0.002 with 100).
    seed : int
        Seed of that noise.
    refine : bool
        Refine the linear interpolation by Brent's method on e(ζ) inside the bracket.
    floor_hz : float
        Floor of the filter frequency [Hz].

    Returns
    -------
    ZetaSearch
        The estimate, the evaluated errors e(ζ) = Σ [N_rec − N̄_ζ] Δt [count·s], and whether
        it was clipped to a grid end (no sign change; a warning is issued).
    """
    x = finite_array("a", a)
    dt = positive_finite("dt", dt)
    grid = np.asarray(zeta_grid, dtype=np.float64)
    if grid.size < 2 or np.any(np.diff(grid) <= 0) or grid[0] <= 0 or grid[-1] >= 1:
        raise ValueError(f"zeta_grid must increase inside (0, 1), got {zeta_grid!r}")
    if int(n_sim) != n_sim or n_sim < 1:
        raise ValueError(f"n_sim must be a positive integer, got {n_sim!r}")
    i05, i95 = _window(t05, t95, dt)
    if not (0 <= i05 < i95 - 2 and i95 < x.size):
        raise ValueError(f"window [t05, t95] = [{t05!r}, {t95!r}] s holds fewer than 3 samples")
    n_rec = pmnm_cum(x[i05 : i95 + 1])
    # The unmodulated process of the model starts at t = 0 like the record; it is counted
    # on the same window so the start-up transient of the filter is excluded the same way.
    noise = np.random.default_rng(seed).standard_normal((i95 + 1, int(n_sim)))
    evaluated: dict[float, float] = {}

    def error(zeta: float) -> float:
        if zeta not in evaluated:
            p = RDKParams(trial.Ia, trial.D5_95, trial.t_mid, trial.f_mid, trial.f_slope, zeta)
            y = time_domain(p, dt, i95 + 1, noise, modulate=False, floor_hz=floor_hz)
            n_sim_mean = pmnm_cum(y[:, i05:]).mean(axis=0)
            evaluated[zeta] = float(np.sum(n_rec - n_sim_mean) * dt)
        return evaluated[zeta]

    lo, hi = 0, grid.size - 1
    e_lo, e_hi = error(float(grid[lo])), error(float(grid[hi]))
    # e decreases with ζ (a wider band has more extrema): no sign change means the record
    # lies outside what the grid can reproduce.
    if e_lo <= 0.0 or e_hi >= 0.0:
        end = float(grid[0] if e_lo <= 0.0 else grid[-1])
        warnings.warn(
            f"PM+NM count not bracketed by zeta_grid ({grid[0]}..{grid[-1]}): "
            f"zeta_f clipped to {end}",
            RuntimeWarning,
            stacklevel=2,
        )
        return ZetaSearch(end, dict(sorted(evaluated.items())), True)
    # Bisection over grid indices finds the bracketing pair with ~log2(len) evaluations.
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if error(float(grid[mid])) > 0.0:
            lo = mid
        else:
            hi = mid
    z0, z1 = float(grid[lo]), float(grid[hi])
    e0, e1 = error(z0), error(z1)
    zeta = z0 + (z1 - z0) * e0 / (e0 - e1)
    if refine:
        zeta = brentq(error, z0, z1, xtol=1e-3) if e0 * e1 < 0.0 else zeta
    return ZetaSearch(float(zeta), dict(sorted(evaluated.items())), False)


def fit_component(
    a: ArrayLike,
    dt: float,
    *,
    method: Literal["spectrum", "counts"] = "spectrum",
    post: Callable[[NDArray[np.float64]], NDArray[np.float64]] | None = None,
    zeta_grid: tuple[float, ...] = ZETA_GRID,
    n_sim: int = 50,
    psa_sims: int = 20,
    iterations: int = 2,
    seed: int = 0,
    refine: bool = False,
    floor_hz: float = DEFAULT_FLOOR_HZ,
) -> RDKParams:
    """Identify the RDK parameters of one acceleration component.

    Parameters
    ----------
    a : array_like
        Acceleration [m/s²], 1-D, starting at the record's first sample (T0 = 0).
    dt : float
        Time step [s], > 0 (the record's own step: simulations use it).
    method : {"spectrum", "counts"}
        Spectrum-matched extended model (default) or the RDK (2010) count-based filter.
    post : callable or None
        ``"spectrum"`` only: the high-pass the ensemble will get, applied to the record and
        the simulations of the fit alike ((m, n) → (m, n′)); None: none.
    zeta_grid, n_sim, refine
        ``"counts"`` only: settings of the ζ_f search, see :func:`fit_zeta`.
    psa_sims, iterations : int
        ``"spectrum"`` only: simulations per misfit evaluation and Gauss–Newton steps
        (:func:`.fit_spectrum`).
    seed : int
        Seed of the simulations of either search.
    floor_hz : float
        Floor of the filter frequency [Hz].

    Returns
    -------
    RDKParams
        With ``diagnostics``: the method, Husid times, up-crossing fit coefficients, the
        record's counts, the settings and the search record of the method.
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    x = finite_array("a", a)
    dt = positive_finite("dt", dt)
    if x.size < 10:
        raise ValueError(f"a needs at least 10 samples, got {x.size}")
    ht = husid_times(x, dt)
    if not ht["Ia"] > 0.0:
        raise ValueError("a is identically zero: no Arias intensity to fit")
    d5_95 = ht["t95"] - ht["t05"]
    f_mid, f_slope, coef = fit_frequency(x, dt, ht["t01"], ht["t99"], ht["t45"])
    if not f_mid > 0.0:
        raise ValueError(f"fitted f_mid = {f_mid!r} Hz is not positive: is a an acceleration?")
    i05, i95 = _window(ht["t05"], ht["t95"], dt)
    diagnostics: dict[str, Any] = {
        "method": method,
        **ht,
        "upcrossing_coef": coef.tolist(),
        "upcrossing_f_mid": f_mid,
        "upcrossing_f_slope": f_slope,
        "n_upcrossings": int(zero_upcrossings_cum(x)[-1]),
        "n_pmnm_5_95": int(pmnm_cum(x[i05 : i95 + 1])[-1]),
        "settings": {"seed": int(seed), "floor_hz": float(floor_hz), "dt": dt, "T0": 0.0},
    }
    # ζ does not enter steps 1-2; a mid-grid value stands in until it is identified.
    trial = RDKParams(ht["Ia"], d5_95, ht["t45"], f_mid, f_slope, 0.5, diagnostics=diagnostics)
    if method == "spectrum":
        diagnostics["settings"].update(psa_sims=int(psa_sims), iterations=int(iterations))
        return fit_spectrum(x, dt, trial, post if post is not None else _identity,
                            n_sim=psa_sims, seed=seed, iterations=iterations,
                            floor_hz=floor_hz)
    search = fit_zeta(
        x, dt, trial, ht["t05"], ht["t95"],
        zeta_grid=zeta_grid, n_sim=n_sim, seed=seed, refine=refine, floor_hz=floor_hz,
    )  # fmt: skip
    diagnostics["zeta_errors"] = {f"{z:.4f}": e for z, e in search.evaluated.items()}
    diagnostics["zeta_clipped"] = search.clipped
    diagnostics["settings"].update(n_sim=int(n_sim), refine=bool(refine),
                                   zeta_grid=[float(z) for z in zeta_grid])
    return RDKParams(ht["Ia"], d5_95, ht["t45"], f_mid, f_slope, search.zeta,
                     diagnostics=diagnostics)


def _identity(x: NDArray[np.float64]) -> NDArray[np.float64]:
    return x


def highpass_post(
    highpass: bool | str = True, fc_hz: float = DEFAULT_FC_HZ, order: int = 4, dt: float = 0.01
) -> Callable[[NDArray[np.float64]], NDArray[np.float64]]:
    """The post-processing high-pass of :func:`~rocking.motions.stochastic.synthesize`, a function.

    ``highpass`` True means the RDK (2010) oscillator, False none; the padding is kept.
    """
    if highpass is False:
        return _identity
    kind = "oscillator" if highpass is True else str(highpass)
    if kind not in ("oscillator", "butterworth"):
        raise ValueError(
            f"highpass must be True, False, 'oscillator' or 'butterworth', got {highpass!r}"
        )
    fc_hz = positive_finite("fc_hz", fc_hz)
    from rocking.motions.highpass import highpass_rows

    def post(x: NDArray[np.float64]) -> NDArray[np.float64]:
        return highpass_rows(x, dt, kind, fc_hz, order)[0]

    return post


@dataclass(frozen=True)
class RDKFit:
    """RDK parameters of both principal components of a bidirectional record.

    Attributes
    ----------
    angle : float
        Rotation applied to reach the principal axes [deg], from the record's x toward y
        (see :func:`rocking.motions.principal.to_principal_axes`).
    major, minor : RDKParams
        Parameters of the major (larger Arias intensity, x after rotation) and minor
        components.
    dt : float
        Time step of the record [s] (simulations use it).
    name : str
        Name of the record.
    diagnostics : dict
        Principal-axis metadata (computed angle, offset from the nearest recording axis,
        correlations) and the record's provenance.
    """

    angle: float
    major: RDKParams
    minor: RDKParams
    dt: float
    name: str = "record"
    diagnostics: dict[str, Any] = field(default_factory=dict, compare=False, repr=False)

    def to_dict(self) -> dict[str, Any]:
        """Plain-JSON dictionary of the fit."""
        return {
            "name": self.name,
            "dt": self.dt,
            "angle_deg": self.angle,
            "major": self.major.to_dict(),
            "minor": self.minor.to_dict(),
            "diagnostics": to_plain(self.diagnostics),
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> RDKFit:
        """Inverse of :meth:`to_dict`."""
        return cls(
            float(d["angle_deg"]),
            RDKParams.from_dict(d["major"]),
            RDKParams.from_dict(d["minor"]),
            float(d["dt"]),
            str(d.get("name", "record")),
            dict(d.get("diagnostics", {})),
        )


def fit_rdk(
    motion: GroundMotion,
    angle: float | str | None = None,
    *,
    method: Literal["spectrum", "counts"] = "spectrum",
    highpass: bool | str = True,
    fc_hz: float = DEFAULT_FC_HZ,
    order: int = 4,
    n_sim: int = 50,
    psa_sims: int = 20,
    seed: int = 0,
    refine: bool = False,
    zeta_grid: tuple[float, ...] = ZETA_GRID,
    floor_hz: float = DEFAULT_FLOOR_HZ,
) -> RDKFit:
    """Fit the RDK model to both principal components of a bidirectional record.

    Parameters
    ----------
    motion : GroundMotion
        The recorded pair [m/s²] on its own time step.
    angle : None, "auto" or float
        Principal-axis rotation: None/"auto" computes θ_p; a number [deg] forces the offset
        of the major axis from the nearest recording axis with the computed sense (e.g. the
        paper's 22.33° for El Centro), see :func:`rocking.motions.principal.to_principal_axes`.
    method : {"spectrum", "counts"}
        Identification of the spectral parameters (:func:`fit_component`).
    highpass, fc_hz, order
        ``"spectrum"`` only: the post-processing high-pass the ensemble will get (as in
        :func:`~rocking.motions.stochastic.synthesize`); the match is between high-passed spectra.
    n_sim, psa_sims, seed, refine, zeta_grid, floor_hz
        Settings of the searches (:func:`fit_component`); the minor component uses
        ``seed + 1`` so that its simulations are independent of the major one's.

    Returns
    -------
    RDKFit
    """
    from rocking.motions.principal import to_principal_axes

    if not isinstance(motion, GroundMotion):
        raise ValueError(f"motion must be a GroundMotion, got {type(motion).__name__}")
    if motion.is_unidirectional:
        raise ValueError(f"motion {motion.name!r} has a zero component: a pair is needed")
    rotated, applied = to_principal_axes(motion, angle)
    kw: dict[str, Any] = dict(method=method, n_sim=n_sim, psa_sims=psa_sims, refine=refine,
                              zeta_grid=zeta_grid, floor_hz=floor_hz)
    if method == "spectrum":
        kw["post"] = highpass_post(highpass, fc_hz, order, motion.dt)
    major = fit_component(rotated.ax, motion.dt, seed=seed, **kw)
    minor = fit_component(rotated.ay, motion.dt, seed=seed + 1, **kw)
    keys = (
        "principal_angle_deg", "principal_offset_deg", "principal_reference_axis",
        "forced_angle_deg", "correlation_before", "correlation_after", "x_azimuth", "y_azimuth",
    )  # fmt: skip
    meta = {k: rotated.metadata[k] for k in keys if k in rotated.metadata}
    provenance = ("source", "files", "sha256", "title")
    meta["record"] = {k: motion.metadata[k] for k in provenance if k in motion.metadata}
    meta["npts"] = motion.npts
    meta["method"] = method
    if method == "spectrum":
        meta["highpass"] = {"kind": highpass, "fc_hz": fc_hz, "order": order}
    return RDKFit(float(applied), major, minor, motion.dt, motion.name, meta)
