"""Closed-form kinematics of one planar 3R finger (vectorized numpy).

A finger with base ``b``, link lengths ``l1, l2, l3`` and joint angles ``q`` has absolute link
angles ``s_k = q_1 + ... + q_k`` measured counter-clockwise from +y; link k points along
``d(s_k) = (-sin s_k, cos s_k)``. The fingertip point is

.. math:: p = b + l_1 d(s_1) + l_2 d(s_2) + l_3 d(s_3),

its orientation is ``phi = s_3`` and column k of the fingertip Jacobian (the finger's block of
the hand Jacobian J_h, thesis eq. 2.5) is ``sum_{i>=k} l_i d'(s_i)`` with
``d'(s) = (-cos s, -sin s)``.
"""

from __future__ import annotations

import math

import numpy as np

TWO_PI = 2.0 * np.pi


def direction(angle: np.ndarray) -> np.ndarray:
    """Unit vector(s) ``d(angle) = (-sin, cos)`` [-]: shape ``angle.shape + (2,)``."""
    angle = np.asarray(angle, dtype=float)
    return np.stack([-np.sin(angle), np.cos(angle)], axis=-1)


def finger_points(base: np.ndarray, lengths: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Joint and fingertip points of a finger.

    Args:
        base: (2,) joint-1 position [m].
        lengths: (3,) link lengths [m].
        q: (..., 3) joint angles [rad].

    Returns:
        (..., 4, 2) positions of joint 1, joint 2, joint 3 and the fingertip point [m].
    """
    s = np.cumsum(q, axis=-1)
    steps = direction(s) * np.asarray(lengths)[:, None]
    pts = np.cumsum(steps, axis=-2) + base
    start = np.broadcast_to(base, pts.shape[:-2] + (1, 2))
    return np.concatenate([start, pts], axis=-2)


def fingertip(
    base: np.ndarray, lengths: np.ndarray, q: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Fingertip position (..., 2) [m] and orientation phi = q1+q2+q3 (...,) [rad]."""
    return finger_points(base, lengths, q)[..., 3, :], np.sum(q, axis=-1)


def fingertip_jacobian(
    lengths: np.ndarray, q: np.ndarray, offset: np.ndarray | None = None
) -> np.ndarray:
    """Jacobian d p / d q of a point fixed on the distal link.

    Args:
        lengths: (3,) link lengths [m].
        q: (..., 3) joint angles [rad].
        offset: (2,) the point in the fingertip frame (x across, y along the distal link,
            origin at the fingertip point) [m]; default the fingertip point itself.

    Returns:
        (..., 2, 3) Jacobian [m/rad].
    """
    s = np.cumsum(q, axis=-1)
    dd = np.stack([-np.cos(s), -np.sin(s)], axis=-1) * np.asarray(lengths)[:, None]
    if offset is not None:
        ox, oy = float(offset[0]), float(offset[1])
        s3 = s[..., 2]
        # tip-frame point (ox, oy) -> R(s3) (ox, oy); derivative w.r.t. s3:
        extra = np.stack(
            [-np.sin(s3) * ox - np.cos(s3) * oy, np.cos(s3) * ox - np.sin(s3) * oy], axis=-1
        )
        dd = dd.copy()
        dd[..., 2, :] += extra
    cols = np.cumsum(dd[..., ::-1, :], axis=-2)[..., ::-1, :]  # column k = sum_{i>=k}
    return np.swapaxes(cols, -1, -2)


def tip_and_jacobian(base, lengths, q) -> tuple[float, float, float, np.ndarray]:
    """Scalar fast path for one configuration (``math`` instead of numpy ufuncs).

    Args:
        base: (2,) joint-1 position [m]; lengths: (3,) [m]; q: (3,) joint angles [rad].

    Returns:
        fingertip x [m], y [m], orientation phi [rad] and the (2, 3) Jacobian [m/rad].
    """
    l1, l2, l3 = lengths
    s1 = q[0]
    s2 = s1 + q[1]
    s3 = s2 + q[2]
    c1, n1, c2, n2, c3, n3 = (
        math.cos(s1),
        math.sin(s1),
        math.cos(s2),
        math.sin(s2),
        math.cos(s3),
        math.sin(s3),
    )
    x = base[0] - l1 * n1 - l2 * n2 - l3 * n3
    y = base[1] + l1 * c1 + l2 * c2 + l3 * c3
    j3x, j3y = -l3 * c3, -l3 * n3
    j2x, j2y = j3x - l2 * c2, j3y - l2 * n2
    j1x, j1y = j2x - l1 * c1, j2y - l1 * n1
    return x, y, s3, np.array([[j1x, j2x, j3x], [j1y, j2y, j3y]])


def wrap_into(q: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Shift angles by multiples of 2*pi into ``[lower, upper]`` where possible.

    Returns:
        (shifted angles, boolean mask "inside the limits") with the shapes of ``q``.
    """
    shifted = lower + np.mod(q - lower, TWO_PI)
    ok = shifted <= upper + 1e-12
    return shifted, ok


def ik_branches(
    base: np.ndarray, lengths: np.ndarray, position: np.ndarray, phi: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Closed-form IK for given fingertip positions and orientations, both elbow branches.

    Args:
        base: (2,) joint-1 position [m].
        lengths: (3,) link lengths [m].
        position: (..., 2) fingertip targets [m].
        phi: (...) fingertip orientations [rad] (broadcast against ``position[..., 0]``).

    Returns:
        q: (..., 2, 3) joint angles for the two elbow branches [rad] (unwrapped),
        ok: (..., 2) whether the wrist point is within reach for that branch.
    """
    l1, l2, l3 = (float(v) for v in lengths)
    phi = np.asarray(phi, dtype=float)
    wrist = np.asarray(position, dtype=float) - l3 * direction(phi)
    v = wrist - base
    c2 = (np.sum(v * v, axis=-1) - l1**2 - l2**2) / (2.0 * l1 * l2)
    ok = np.abs(c2) <= 1.0 + 1e-12
    q2a = np.arccos(np.clip(c2, -1.0, 1.0))
    q2 = np.stack([q2a, -q2a], axis=-1)  # (..., 2)
    w0x = -l2 * np.sin(q2)
    w0y = l1 + l2 * np.cos(q2)
    q1 = np.arctan2(v[..., 1], v[..., 0])[..., None] - np.arctan2(w0y, w0x)
    q3 = phi[..., None] - q1 - q2
    q = np.stack([q1, q2, q3], axis=-1)
    return q, np.broadcast_to(ok[..., None], q2.shape)
