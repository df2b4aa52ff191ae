"""Principal horizontal axes of a two-component ground motion (Penzien & Watabe 1975).

The 2×2 matrix σ_ij = Σ_k a_i(t_k) a_j(t_k) (proportional to the Arias-intensity tensor
(π/2g)∫a_i a_j dt) transforms like a plane stress. The principal angle

    θ_p = ½ atan2(2σ₁₂, σ₁₁ − σ₂₂)

(measured from axis x toward axis y) diagonalizes it; with ``atan2`` the first rotated
component is always the major one (larger Arias intensity). Rotation by θ:

    a₁′ =  cos θ · a_x + sin θ · a_y
    a₂′ = −sin θ · a_x + cos θ · a_y

The correlation that the rotation removes is the *uncentred* one, σ₁₂/√(σ₁₁σ₂₂), because the
Arias tensor is built from raw products; for processed records the means are negligible.

Azimuths: with the :mod:`.records` convention (y azimuth = x azimuth − 90°), the new x
axis points to azimuth az_x − θ.
"""

from __future__ import annotations

import math

import numpy as np

from rocking._validate import finite, positive_finite
from rocking.constants import G
from rocking.motions.motion import GroundMotion

__all__ = [
    "arias_tensor",
    "correlation",
    "principal_angle",
    "rotate",
    "rotate_components",
    "to_principal_axes",
]


def _pair(a1, a2) -> tuple[np.ndarray, np.ndarray]:
    x = np.asarray(a1, dtype=np.float64)
    y = np.asarray(a2, dtype=np.float64)
    if x.ndim != 1 or y.ndim != 1 or x.size != y.size:
        raise ValueError(
            f"a1 and a2 must be 1-D arrays of equal length, got shapes {x.shape} and {y.shape}"
        )
    for label, arr in (("a1", x), ("a2", y)):
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            raise ValueError(f"{label} has a non-finite value {arr[bad[0]]!r} at sample {bad[0]}")
    return x, y


def _dot(a: np.ndarray, b: np.ndarray) -> float:
    """Σ a_k b_k correctly rounded (:func:`math.fsum` of the exact-rounded products).

    Not ``a @ b``: BLAS sums in an order that depends on the CPU's kernel and on the length,
    so the horizontals of a record padded to its vertical file (a few trailing zeros) got
    another last bit of the principal angle on AVX2 machines, and with it other samples.
    The exactly rounded sum is the same for any length of trailing zeros, kernel or order."""
    return math.fsum((a * b).tolist())


def arias_tensor(a1, a2, dt: float) -> np.ndarray:
    """Arias-intensity tensor I_ij = (π/2g) Σ a_i a_j Δt [m/s].

    Parameters
    ----------
    a1, a2 : array_like
        The two components [m/s²].
    dt : float
        Time step [s].

    Returns
    -------
    numpy.ndarray
        Symmetric 2×2 matrix; its trace is the total (rotation-invariant) Arias intensity.
    """
    x, y = _pair(a1, a2)
    step = positive_finite("dt", dt)
    xy = _dot(x, y)
    s = np.array([[_dot(x, x), xy], [xy, _dot(y, y)]])
    return s * (math.pi / (2.0 * G) * step)


def correlation(a1, a2) -> float:
    """Uncentred correlation Σa₁a₂ / √(Σa₁² Σa₂²) [-] (the quantity principal axes zero)."""
    x, y = _pair(a1, a2)
    den = math.sqrt(_dot(x, x) * _dot(y, y))
    if den == 0.0:
        raise ValueError("correlation is undefined: a component is identically zero")
    return _dot(x, y) / den


def principal_angle(a1, a2) -> float:
    """Angle from axis 1 toward axis 2 of the major principal axis [deg], in (−90, 90].

    Parameters
    ----------
    a1, a2 : array_like
        The two components on one time axis (any unit).

    Returns
    -------
    float
        θ_p = ½ atan2(2σ₁₂, σ₁₁ − σ₂₂) in degrees; rotating by it (:func:`rotate_components`)
        makes the components uncorrelated with the larger-intensity one first.

    Raises
    ------
    ValueError
        Unequal lengths, non-finite samples, or both components identically zero.
    """
    x, y = _pair(a1, a2)
    s11, s22, s12 = _dot(x, x), _dot(y, y), _dot(x, y)
    if s11 == 0.0 and s22 == 0.0:
        raise ValueError("principal angle is undefined: both components are identically zero")
    return math.degrees(0.5 * math.atan2(2.0 * s12, s11 - s22))


def rotate_components(a1, a2, angle_deg: float) -> tuple[np.ndarray, np.ndarray]:
    """Components along axes turned by ``angle_deg`` from axis 1 toward axis 2.

    Parameters
    ----------
    a1, a2 : array_like
        The two components.
    angle_deg : float
        Rotation angle [deg].

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        ``cos θ a1 + sin θ a2`` and ``−sin θ a1 + cos θ a2``; a1² + a2² is preserved sample
        by sample.
    """
    x, y = _pair(a1, a2)
    th = math.radians(finite("angle_deg", angle_deg))
    c, s = math.cos(th), math.sin(th)
    return c * x + s * y, -s * x + c * y


def _azimuth_after(meta: dict, angle_deg: float) -> dict:
    """New component azimuths when the metadata carries the old ones."""
    az_x, az_y = meta.get("x_azimuth"), meta.get("y_azimuth")
    if not isinstance(az_x, (int, float)) or not isinstance(az_y, (int, float)):
        return {}
    # Turning from x toward y moves the azimuth in the direction of y's offset from x.
    sense = 1.0 if math.isclose((az_y - az_x) % 360.0, 90.0) else -1.0
    new_x = (az_x + sense * angle_deg) % 360.0
    return {"x_azimuth": new_x, "y_azimuth": (new_x + sense * 90.0) % 360.0}


def rotate(motion: GroundMotion, angle_deg: float) -> GroundMotion:
    """The motion seen in axes turned by ``angle_deg`` from x toward y.

    Parameters
    ----------
    motion : GroundMotion
        Input pair.
    angle_deg : float
        Rotation angle [deg].

    Returns
    -------
    GroundMotion
        Rotated pair with the same name and dt; metadata gets a ``rotation`` processing step
        and updated ``x_azimuth``/``y_azimuth`` when they were known.
    """
    bx, by = rotate_components(motion.ax, motion.ay, angle_deg)
    meta = dict(motion.metadata)
    meta["processing"] = [
        *meta.get("processing", []),
        {"step": "rotation", "angle_deg": float(angle_deg)},
    ]
    meta.update(_azimuth_after(motion.metadata, angle_deg))
    return GroundMotion(bx, by, motion.dt, motion.name, meta, motion.az)  # z: about it


def to_principal_axes(
    motion: GroundMotion, angle: float | str | None = None
) -> tuple[GroundMotion, float]:
    """Rotate a pair to its principal axes, x = major (larger Arias intensity).

    Parameters
    ----------
    motion : GroundMotion
        Input pair.
    angle : None, "auto" or float
        None/"auto": the computed principal angle θ_p. A number [deg] in [−45, 45] forces the
        offset of the major axis from the recording axis nearest to it (x if |θ_p| <= 45°,
        else y): its magnitude is used with the sense of the computed offset, because the
        paper gives 22.33° without a sense and the wrong sense makes the components *more*
        correlated. If the forced rotation leaves the larger intensity on y, the axes are
        turned a further 90° so that x stays the major one.

    Returns
    -------
    (GroundMotion, float)
        The rotated motion and the rotation applied [deg]. Metadata: ``principal_angle_deg``
        (computed θ_p), ``principal_offset_deg`` (θ_p from the nearest recording axis, named
        by ``principal_reference_axis``; the number to compare with published angles),
        ``rotation_deg`` (applied), ``forced_angle_deg`` (or None), and the correlation
        before and after.

    Raises
    ------
    ValueError
        A non-numeric angle, or a motion with both components zero.
    """
    computed = principal_angle(motion.ax, motion.ay)
    reference = 0.0 if abs(computed) <= 45.0 else math.copysign(90.0, computed)
    offset = computed - reference
    if angle is None or (isinstance(angle, str) and angle.strip().lower() == "auto"):
        applied = computed
        forced = None
    else:
        forced = finite("angle", angle)
        if abs(forced) > 45.0:
            raise ValueError(
                f"angle is the offset of the major axis from the nearest recording axis and "
                f"must lie in [-45, 45] deg, got {angle!r}"
            )
        # Published angles (the paper's 22.33°) are the offset of the major axis from the
        # nearer recording axis, without a sense: keep the computed axis and sense.
        applied = reference + math.copysign(abs(forced), offset)
    bx, by = rotate_components(motion.ax, motion.ay, applied)
    if _dot(by, by) > _dot(bx, bx):
        applied += 90.0 if applied <= 0.0 else -90.0
        bx, by = rotate_components(motion.ax, motion.ay, applied)
    out = rotate(motion, applied)
    meta = dict(out.metadata)
    nonzero = np.any(motion.ax) and np.any(motion.ay)
    meta.update(
        principal_angle_deg=computed,
        principal_offset_deg=offset,
        principal_reference_axis="x" if reference == 0.0 else "y",
        rotation_deg=applied,
        forced_angle_deg=forced,
        correlation_before=correlation(motion.ax, motion.ay) if nonzero else 0.0,
        correlation_after=correlation(out.ax, out.ay) if np.any(out.ay) else 0.0,
        axes="principal (x = major)",
    )
    meta["processing"][-1] = {
        "step": "rotation",
        "angle_deg": applied,
        "principal_angle_deg": computed,
        "forced_angle_deg": forced,
    }
    return GroundMotion(out.ax, out.ay, out.dt, out.name, meta, out.az), applied
