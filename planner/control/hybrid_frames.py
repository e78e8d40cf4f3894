"""Coordinate systems of the hybrid force/velocity law (thesis §4.3.2, eqs. 4.1-4.6).

Frames: WCS (world, the 3GM base), TCS (tactile, at the fingertip centre, z along the OWTS
pole), SCS (surface, at the contact, z along the outward surface normal). ``R_AB`` maps B
coordinates into A: ``R_WT`` maps TCS into WCS (the thesis calls it ``R_TW``).

Corrections to the OCR'd text, derived here and checked numerically in the tests:

* **Eq. 4.1** as printed is ``Rz(π/2 + γ1) Rx(π/2 - θ3)``
  (:func:`robots.three_gm.rotation_tcs_to_wcs`). In the C.6 frame (base rotation θ3 about
  the vertical z axis) its z column is ``(cos γ1 cos θ3, sin γ1 cos θ3, sin θ3)``: at the
  workspace centre that is ``(0.115, -0.99, 0.084)``, horizontal, whereas the sensor pole sits
  at the end of the distal link, which points along ``(cos γ1 cos θ3, cos γ1 sin θ3, sin γ1)``
  ``= (0.115, 0.010, -0.993)``, down at the plate. The printed matrix rotates about the axes of
  a frame whose base axis is horizontal; in the C.6 frame the rotation is
  ``R_WT = Rz(θ3) Ry(π/2 - γ1)`` (:func:`tcs_rotation`): z_T along the distal link (the x axis
  of the Pinocchio ``endpoint`` frame), y_T normal to the five-bar plane.
* **Eq. 4.3** prints ``x_S = (z_Sz, z_Sx, 0)``, which is not orthogonal to ``z_S``. The text
  asks for ``x_S`` in the world x-z plane (zero y component); the unique such direction is
  ``x_S = (z_Sz, 0, -z_Sx)`` (normalized), singular exactly where the text says
  (``z_Sx = z_Sz = 0``). Near it (``z_Sx² + z_Sz² < sin² 30°``) the alternative of the text is
  used: ``y_S`` in the world y-z plane, ``y_S = (0, z_Sz, -z_Sy)`` (normalized), singular only
  at ``z_S = ±x_W``, far from the switch.
* **Eq. 4.4** labels the SCS matrix ``R_TW``; it is ``R_WS = [x_S y_S z_S]`` (SCS into WCS).
* **Eq. 4.11** prints ``K_W = R_SW^T K_S R_SW``; with ``R_SW`` mapping SCS into WCS (eq. 4.4)
  the similarity transform is ``K_W = R K_S R^T``. Either way, with ``K_S = diag(k, k, 0)`` the
  result is ``k (I - z_S z_S^T)``: independent of the choice of x_S, y_S, so the law is
  continuous across the frame switch even though the frame is not (tested).
"""

from __future__ import annotations

import math

import numpy as np

from planner import checks

#: sin² of the angle between z_S and the world y axis below which the alternative SCS is used.
SWITCH_SIN2 = 0.25

__all__ = [
    "SWITCH_SIN2",
    "filter_normal",
    "gain_matrix",
    "surface_frame",
    "tcs_rotation",
]


def tcs_rotation(gamma1: float, theta3: float) -> np.ndarray:
    """``R_WT`` (the thesis' R_TW, eq. 4.1 corrected): TCS coordinates into the WCS.

    Args:
        gamma1: passive angle γ1 of eq. C.5 [rad] (direction of the distal link in the plane).
        theta3: base rotation θ3 [rad].

    Returns:
        (3, 3) rotation ``Rz(θ3) Ry(π/2 - γ1)``; its z column is the OWTS pole direction.
    """
    cg, sg = math.cos(gamma1), math.sin(gamma1)
    c3, s3 = math.cos(theta3), math.sin(theta3)
    return np.array(
        [
            [sg * c3, -s3, cg * c3],
            [sg * s3, c3, cg * s3],
            [-cg, 0.0, sg],
        ]
    )


def filter_normal(
    n_prev: np.ndarray, n_tcs: np.ndarray, r_wt: np.ndarray, alpha: float = 0.05
) -> np.ndarray:
    """Low-pass filtered contact normal in the WCS (eq. 4.2, with its no-contact rule).

    ``n_W,k = α R_WT n_T + (1 - α) n_W,k-1``, renormalized (the thesis' filter output is not a
    unit vector; the normal must be, eqs. 4.7 and 4.12). A zero ``n_T`` (no contact) is
    replaced by the TCS z axis (the pole) as the text prescribes.

    Args:
        n_prev: (3,) previous filtered normal in the WCS (unit) [-].
        n_tcs: (3,) OWTS normal in the TCS (outward on the fingertip; zero = no contact) [-].
        r_wt: (3, 3) TCS-to-WCS rotation (:func:`tcs_rotation`).
        alpha: filter weight of the new sample, in (0, 1] (0.05 in the thesis).

    Returns:
        (3,) unit normal in the WCS, pointing from the fingertip centre into the surface.
    """
    checks.in_range("alpha", alpha, 0.0, 1.0, closed=(False, True))
    n = np.asarray(n_tcs, float)
    meas = r_wt[:, 2] if float(n @ n) < 1e-12 else r_wt @ n
    out = alpha * meas + (1.0 - alpha) * np.asarray(n_prev, float)
    norm = float(np.linalg.norm(out))
    return meas / float(np.linalg.norm(meas)) if norm < 1e-9 else out / norm


def surface_frame(z_s: np.ndarray) -> tuple[np.ndarray, bool]:
    """The SCS axes in the WCS (eq. 4.3 corrected, with the singularity switch).

    Args:
        z_s: (3,) outward surface normal ``z_S = -n_W`` (normalized here) [-].

    Returns:
        ``(R_WS, alternative)``: the (3, 3) rotation ``[x_S y_S z_S]`` (SCS into WCS, eq. 4.4)
        and whether the alternative frame (``y_S`` in the world y-z plane) was used.
    """
    z = np.asarray(z_s, float)
    z = z / np.linalg.norm(z)
    zx, zy, zz = z
    if zx * zx + zz * zz >= SWITCH_SIN2:
        x = np.array([zz, 0.0, -zx]) / math.hypot(zx, zz)
        y = np.cross(z, x)
        alt = False
    else:
        y = np.array([0.0, zz, -zy]) / math.hypot(zy, zz)
        x = np.cross(y, z)
        alt = True
    return np.column_stack([x, y, z]), alt


def gain_matrix(r_ws: np.ndarray, gain: float) -> np.ndarray:
    """Cartesian gain in the WCS, ``R K_S R^T`` with ``K_S = diag(k, k, 0)`` (eqs. 4.10-4.11).

    Args:
        r_ws: (3, 3) SCS-to-WCS rotation from :func:`surface_frame`.
        gain: scalar gain ``k_p`` [N/m] or ``k_v`` [N s/m].

    Returns:
        (3, 3) gain matrix; it equals ``k (I - z_S z_S^T)`` for any x_S, y_S.
    """
    return r_ws @ np.diag([gain, gain, 0.0]) @ r_ws.T
