"""Integration of Montana's contact equations for two parametric surfaces (App. A.2).

The state is the pair of contact coordinates ``(u1, u2)``, the contact angle ``ψ`` and, as
a check, the pose ``(R, p)`` of body 1 in body 2's reference frame (``x_2 = R x_1 + p``).
The rates come from :func:`planner.contact.montana.montana_rates`; the pose from the same
relative twist. After every step the contact condition is verified geometrically: the two
contact points must coincide and the normals be opposite (``vz = 0`` keeps contact).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.contact.montana import montana_rates
from planner.errors import ContactLost, CoordinatePatchExit

Motion = Callable[[float], tuple[np.ndarray, np.ndarray]]


@dataclass(frozen=True)
class ContactTrajectory:
    """Contact coordinates and relative pose over time.

    Attributes:
        t: (N,) times [s].
        u1: (N, 2) contact coordinates on body 1.
        u2: (N, 2) contact coordinates on body 2.
        psi: (N,) contact angle [rad].
        rotation: (N, 3, 3) ``R``, body-1 coordinates -> body-2 coordinates.
        position: (N, 3) ``p``, body 1's origin in body-2 coordinates [m].
        point1: (N, 3) contact point on body 1, body-1 coordinates [m].
        point2: (N, 3) contact point on body 2, body-2 coordinates [m].
        residual: (N,) contact residual ``|R f1(u1) + p - f2(u2)| + L (|R z1 + z2| +
            |R x1 - (cos ψ x2 - sin ψ y2)|)`` [m], ``L`` the length scale given to the
            integrator: the contact frames must agree in position, normal and angle ``ψ``.
        path_length1: total length of the contact path on body 1 [m].
        path_length2: total length of the contact path on body 2 [m].
    """

    t: np.ndarray
    u1: np.ndarray
    u2: np.ndarray
    psi: np.ndarray
    rotation: np.ndarray
    position: np.ndarray
    point1: np.ndarray
    point2: np.ndarray
    residual: np.ndarray

    @property
    def path_length1(self) -> float:
        return float(np.sum(np.linalg.norm(np.diff(self.point1, axis=0), axis=1)))

    @property
    def path_length2(self) -> float:
        return float(np.sum(np.linalg.norm(np.diff(self.point2, axis=0), axis=1)))


def _hat(w: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def initial_pose(surface1, surface2, u1, u2, psi: float) -> tuple[np.ndarray, np.ndarray]:
    """Pose ``(R, p)`` of body 1 in body 2's frame that puts the bodies in contact.

    The contact frames coincide in position, ``z1 = -z2`` and
    ``x1 = cos ψ x2 - sin ψ y2`` (the inverse of the relation of eq. A.13, ``R_ψ`` being an
    involution).

    Returns:
        ``R`` (3, 3) and ``p`` (3,) [m].
    """
    g1 = surface1.local_geometry(*u1)
    g2 = surface2.local_geometry(*u2)
    c, s = math.cos(psi), math.sin(psi)
    b = np.array([[c, -s, 0.0], [-s, -c, 0.0], [0.0, 0.0, -1.0]])
    rot = g2.gauss_frame @ b @ g1.gauss_frame.T
    return rot, g2.point - rot @ g1.point


def integrate_contact(
    surface1,
    surface2,
    u1,
    u2,
    psi: float,
    motion: Motion | tuple,
    duration: float,
    steps: int,
    *,
    tolerance: float = 1e-6,
    length_scale: float = 1.0,
) -> ContactTrajectory:
    """Advance ``(u1, u2, ψ)`` under a prescribed relative motion (RK4, eq. A.12).

    Args:
        surface1, surface2: the bodies' surfaces (objects with ``local_geometry(u, v)`` and
            ``contains(u, v)``, e.g. :class:`~planner.geometry.surfaces.ParametricSurface`).
        u1, u2: (2,) initial contact coordinates on each body.
        psi: initial contact angle [rad].
        motion: ``motion(t) -> (v, omega)``, the relative velocity of body 1 w.r.t. body 2 in
            ``C_l1`` (see :mod:`planner.contact.montana`), or a constant ``(v, omega)`` pair
            [m/s, rad/s].
        duration: time to integrate [s] (> 0).
        steps: number of RK4 steps (>= 1).
        tolerance: largest allowed contact residual [m] before :class:`ContactLost`.
        length_scale: ``L`` weighting the normal mismatch in the residual [m].

    Returns:
        The trajectory, ``steps + 1`` samples.

    Raises:
        ContactLost: the motion has ``vz != 0`` or the bodies drift apart.
        CoordinatePatchExit: a contact point leaves its chart's domain; the trajectory up to
            there is attached to the exception as ``.trajectory``.
        SingularConfiguration: the relative curvature ``K1 + K̃2`` is singular.
    """
    steps = checks.integer("steps", steps, 1)
    duration = checks.positive("duration", duration, "s")
    if callable(motion):
        motion_fn = motion
    else:
        const = (np.asarray(motion[0], dtype=float), np.asarray(motion[1], dtype=float))
        motion_fn = lambda t: const  # noqa: E731
    dt = duration / steps
    x = np.concatenate(
        [
            checks.vector("u1", u1, 2),
            checks.vector("u2", u2, 2),
            [checks.in_range("psi", psi, -math.inf, math.inf, "rad", closed=(False, False))],
        ]
    )
    rot, pos = initial_pose(surface1, surface2, x[0:2], x[2:4], x[4])
    rates = functools.partial(_rates, surface1, surface2, motion_fn)
    rows = [(0.0, x.copy(), rot.copy(), pos.copy())]
    residuals = [_residual(surface1, surface2, x, rot, pos, length_scale)]
    for i in range(steps):
        x, rot, pos = _rk4_step(rates, i * dt, dt, x, rot, pos)
        t = (i + 1) * dt
        _check_charts(t, x, surface1, surface2, rows, residuals)
        rows.append((t, x.copy(), rot.copy(), pos.copy()))
        residuals.append(_residual(surface1, surface2, x, rot, pos, length_scale))
        if residuals[-1] > tolerance:
            raise ContactLost(
                f"at t = {t:.6g} s the contact residual is {residuals[-1]:.3g} m "
                f"> tolerance {tolerance:g} m; reduce the step (dt = {dt:g} s)"
            )
    return _pack(rows, residuals, surface1, surface2)


def _rates(surface1, surface2, motion_fn, t, x, rot, pos):
    """Time derivatives of ``(u1, u2, psi)`` (eq. A.12), of ``rot`` and of ``pos``."""
    g1 = surface1.local_geometry(x[0], x[1])
    g2 = surface2.local_geometry(x[2], x[3])
    v, w = motion_fn(t)
    u1d, u2d, psid = montana_rates(
        g1.curvature_matrix,
        g1.torsion,
        g1.metric,
        g2.curvature_matrix,
        g2.torsion,
        g2.metric,
        x[4],
        v,
        w,
    )
    frame = rot @ g1.gauss_frame
    w2 = frame @ np.asarray(w, float)
    v2 = frame @ np.asarray(v, float)
    contact = rot @ g1.point + pos
    return (
        np.concatenate([u1d, u2d, [psid]]),
        _hat(w2) @ rot,
        v2 + np.cross(w2, pos - contact),
    )


def _rk4_step(rates, t, dt, x, rot, pos):
    """One RK4 step of ``(x, rot, pos)``; ``rot`` is re-orthonormalized (SVD)."""
    k1 = rates(t, x, rot, pos)
    k2 = rates(t + dt / 2, *_advance(x, rot, pos, k1, dt / 2))
    k3 = rates(t + dt / 2, *_advance(x, rot, pos, k2, dt / 2))
    k4 = rates(t + dt, *_advance(x, rot, pos, k3, dt))
    x = x + dt / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
    rot = rot + dt / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
    uq, _, vq = np.linalg.svd(rot)
    pos = pos + dt / 6 * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2])
    return x, uq @ vq, pos


def _check_charts(t, x, surface1, surface2, rows, residuals) -> None:
    """Raise :class:`CoordinatePatchExit` (with the trajectory so far) off a chart."""
    for body, surf, uv in ((1, surface1, x[0:2]), (2, surface2, x[2:4])):
        if not surf.contains(*uv):
            exc = CoordinatePatchExit(
                f"at t = {t:.6g} s the contact point on body {body} left its chart: "
                f"u{body} = {uv.tolist()} is outside U = {surf.domain.tolist()}; "
                f"shorten the motion or re-chart the surface"
            )
            exc.trajectory = _pack(rows, residuals, surface1, surface2)
            raise exc


def _advance(x, rot, pos, k, h):
    return x + h * k[0], rot + h * k[1], pos + h * k[2]


def _residual(surface1, surface2, x, rot, pos, scale) -> float:
    g1 = surface1.local_geometry(x[0], x[1])
    g2 = surface2.local_geometry(x[2], x[3])
    gap = np.linalg.norm(rot @ g1.point + pos - g2.point)
    f1, f2 = rot @ g1.gauss_frame, g2.gauss_frame
    c, s = math.cos(x[4]), math.sin(x[4])
    turn = np.linalg.norm(f1[:, 0] - (c * f2[:, 0] - s * f2[:, 1]))  # x1 = cψ x2 - sψ y2
    return float(gap + scale * (np.linalg.norm(f1[:, 2] + f2[:, 2]) + turn))


def _pack(rows, residuals, surface1, surface2) -> ContactTrajectory:
    t = np.array([r[0] for r in rows])
    xs = np.array([r[1] for r in rows])
    return ContactTrajectory(
        t=t,
        u1=xs[:, 0:2],
        u2=xs[:, 2:4],
        psi=xs[:, 4],
        rotation=np.array([r[2] for r in rows]),
        position=np.array([r[3] for r in rows]),
        point1=surface1.point(xs[:, 0], xs[:, 1]),
        point2=surface2.point(xs[:, 2], xs[:, 3]),
        residual=np.array(residuals),
    )


__all__ = ["ContactTrajectory", "initial_pose", "integrate_contact"]
