"""The 3GM's well-conditioned workspace (thesis App. C.2.1): the trapezoid and its check."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import SingularConfiguration
from robots.errors import UnreachableTarget
from robots.three_gm.gm import ThreeGM
from robots.three_gm.params import WORKSPACE_HALF_ANGLE, WORKSPACE_RADII, WORKSPACE_Z


def trapezoid_grid(n: int) -> np.ndarray:
    """(n**3, 3) grid of points filling the trapezoid of App. C.2.1 in the WCS [m].

    Radius, base angle and height each take ``n`` evenly spaced values (n >= 2).
    """
    n = checks.integer("n", n, 2)
    rho = np.linspace(*WORKSPACE_RADII, int(n))
    ang = np.linspace(-WORKSPACE_HALF_ANGLE, WORKSPACE_HALF_ANGLE, int(n))
    z = np.linspace(*WORKSPACE_Z, int(n))
    R, A, Z = np.meshgrid(rho, ang, z, indexing="ij")
    return np.column_stack([(R * np.cos(A)).ravel(), (R * np.sin(A)).ravel(), Z.ravel()])


def trapezoid_volume() -> float:
    """Volume of the trapezoid [m³]: height x (front + back width)/2 x length (~112 in³)."""
    r0, r1 = WORKSPACE_RADII
    front, back = 2 * WORKSPACE_HALF_ANGLE * r0, 2 * WORKSPACE_HALF_ANGLE * r1
    return (WORKSPACE_Z[1] - WORKSPACE_Z[0]) * 0.5 * (front + back) * (r1 - r0)


@dataclass(frozen=True)
class ConditionedWorkspace:
    """Result of :func:`check_conditioned_workspace`.

    Attributes:
        points: (N, 3) tested points in the WCS [m].
        theta: (N, 3) IK solutions [rad] (NaN rows where IK failed; see ``reachable``).
        reachable: (N,) IK succeeded inside the joint limits.
        condition: (N,) condition number of the 2-D five-bar Jacobian (rows x-y radial and z,
            columns θ1, θ2) [-]; inf where unreachable.
        force_capacity: (N,) force available in every direction [N]; 0 where unreachable.
    """

    points: np.ndarray
    theta: np.ndarray
    reachable: np.ndarray
    condition: np.ndarray
    force_capacity: np.ndarray


def check_conditioned_workspace(gm: ThreeGM, points: np.ndarray) -> ConditionedWorkspace:
    """Solve IK at every point (continuation from the previous solution) and condition it.

    Args:
        gm: the finger.
        points: (N, 3) points in the WCS [m].
    """
    pts = checks.points("points", points, dims=(3,), min_count=0)
    n = len(pts)
    theta = np.full((n, 3), np.nan)
    cond = np.full(n, np.inf)
    cap = np.zeros(n)
    guess = gm.center_theta
    for i, x in enumerate(pts):
        try:
            th = gm.inverse_kinematics(x, guess)
        except UnreachableTarget:
            try:
                th = gm.inverse_kinematics(x)
            except UnreachableTarget:
                continue
        try:
            J = gm.jacobian(th)
        except SingularConfiguration:
            continue
        theta[i] = th
        guess = th
        rad = np.array([np.cos(th[2]), np.sin(th[2]), 0.0])
        J2 = np.vstack([rad @ J[:, :2], J[2, :2]])
        s = np.linalg.svd(J2, compute_uv=False)
        cond[i] = s[0] / s[1] if s[1] > 0 else np.inf
        cap[i] = gm.force_capacity(th)
    return ConditionedWorkspace(pts, theta, np.isfinite(cond), cond, cap)
