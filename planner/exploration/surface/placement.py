"""Placing the plate in the 3GM's workspace, and the bad-input checks of the explorer.

The plate frame ``(u, v, w)`` is mapped into the WCS by ``T_WS``: the region's centre lies
straight below the workspace centre of App. C.2.1 (the fingertip touches it there), the plate
tilted by ``tilt`` about the WCS ``y`` axis (downhill towards ``+x``, as a wire on a 45° plate
in §3.4.2). Every corner of the region (and the bug-2 goal) must be reachable by the fingertip
centre, and the normal force must be within the motors' capacity: else
:class:`~planner.errors.InvalidParameter` (bad input, exit 2 in a scenario).
"""

from __future__ import annotations

import math

import numpy as np

from planner import checks
from planner.errors import InvalidParameter

__all__ = ["check_reachable", "plate_pose", "region_box", "to_world"]


def region_box(region) -> np.ndarray:
    """((u0, u1), (v0, v1)) [m] as a validated (2, 2) array."""
    try:
        reg = np.array(region, float)
    except (TypeError, ValueError):
        raise InvalidParameter(
            f"region: expected ((u0, u1), (v0, v1)) [m], got {region!r}"
        ) from None
    if reg.shape != (2, 2) or not np.all(np.isfinite(reg)) or np.any(reg[:, 0] >= reg[:, 1]):
        raise InvalidParameter(
            f"region: expected ((u0, u1), (v0, v1)) with u0 < u1, v0 < v1 [m], got {region!r}"
        )
    return reg


def plate_pose(finger, region: np.ndarray, tilt: float, height: float, clearance: float):
    """``T_WS`` (4, 4): the region centre under the workspace centre, tilted by ``tilt``.

    Args:
        finger: the :class:`robots.three_gm.ThreeGM`.
        region: (2, 2) region box [m].
        tilt: rotation of the plate about the WCS y axis [rad].
        height: plate height (``base`` + features) under the region centre [m].
        clearance: distance of the fingertip centre above the plate there [m] (r_f + gap).
    """
    a = checks.in_range("tilt", tilt, -math.pi / 3, math.pi / 3, "rad")
    c, s = math.cos(a), math.sin(a)
    R = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    centre_uv = region.mean(axis=1)
    x0 = finger.workspace_center
    local = np.array([centre_uv[0], centre_uv[1], height + clearance])
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = x0 - R @ local
    return T


def to_world(T: np.ndarray, uvw) -> np.ndarray:
    """Plate-frame point(s) (..., 3) into the WCS [m]."""
    return np.asarray(uvw, float) @ T[:3, :3].T + T[:3, 3]


def check_reachable(finger, T, points_uv, heights, tip_radius: float, what: str) -> None:
    """Raise :class:`InvalidParameter` if the fingertip cannot rest on the plate at any of the
    ``points_uv`` (N, 2) [m] (heights (N,) of the plate there)."""
    from robots.errors import UnreachableTarget

    for (u, v), h in zip(np.asarray(points_uv, float), np.asarray(heights, float), strict=True):
        x = to_world(T, [u, v, h + tip_radius])
        try:
            finger.inverse_kinematics(x)
        except (UnreachableTarget, InvalidParameter):
            raise InvalidParameter(
                f"{what}: the point ({u * 1e3:.1f}, {v * 1e3:.1f}) mm of the plate (WCS "
                f"{np.round(x * 1e3, 1).tolist()} mm) is outside the 3GM's reach; move or "
                "shrink it"
            ) from None
