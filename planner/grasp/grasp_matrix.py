"""The grasp matrix ``G`` (eq. 2.6) and its composition with the hand Jacobian (eq. 2.5).

Conventions: contact forces ``f`` (applied by the fingers *on the object*, in WCS) map to the
net object wrench about a reference point ``c`` by ``w = G f``; dually, an object twist
``xdot_obj`` (velocity of ``c``, angular velocity) gives the contact-point velocities
``xdot_c = G^T xdot_obj``. Eq. 2.6 of the thesis writes the velocity map with the transpose on
the other side (its "grasp Jacobian" is our ``G^T``); the matrices are the same up to that
transpose. With the hand Jacobian ``J_h`` of eq. 2.5 (``xdot_c = J_h qdot``), the joint
torques that realize contact forces ``f`` are ``tau = J_h^T f``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from planner import checks
from planner.contact.cones import unit_directions
from planner.errors import InvalidParameter


def grasp_matrix(
    points, torque_reference=None, *, normals=None, soft_finger: bool = False
) -> np.ndarray:
    """The grasp matrix mapping contact forces to the object wrench (eq. 2.6, transposed).

    Args:
        points: (k, 2) or (k, 3) contact points in WCS [m].
        torque_reference: (2,) or (3,) point about which torques are taken [m]
            (default: the centroid of the contacts).
        normals: (k, 3) inward unit normals; needed only for ``soft_finger``.
        soft_finger: spatial only: add, per contact, a moment about the normal (Fig. 2.5 c).

    Returns:
        Planar: (3, 2k), rows ``(f_x, f_y, tau_z)``, columns ``(f_1x, f_1y, f_2x, ...)``.
        Spatial: (6, 3k) rows ``(f, tau)``; with ``soft_finger`` (6, 4k), the 4th column of
        each contact being its moment about the normal [N m per N m].
    """
    p = checks.points("points", points)
    k, d = p.shape
    c = (
        p.mean(axis=0)
        if torque_reference is None
        else checks.vector("torque_reference", torque_reference, d, "m")
    )
    r = p - c
    if d == 2:
        G = np.zeros((3, 2 * k))
        G[0, 0::2] = 1.0
        G[1, 1::2] = 1.0
        G[2, 0::2] = -r[:, 1]
        G[2, 1::2] = r[:, 0]
        return G
    per = 4 if soft_finger else 3
    G = np.zeros((6, per * k))
    for i in range(k):
        j = per * i
        G[:3, j : j + 3] = np.eye(3)
        rx, ry, rz = r[i]
        G[3:, j : j + 3] = [[0.0, -rz, ry], [rz, 0.0, -rx], [-ry, rx, 0.0]]
    if soft_finger:
        if normals is None:
            raise InvalidParameter("normals: expected (k, 3) inward normals with soft_finger=True")
        n = unit_directions("normals", normals, 3)
        if n.shape[0] != k:
            raise InvalidParameter(f"normals: expected {k} rows like points, got {n.shape[0]}")
        G[3:, 3::4] = n.T
    return G


def hand_jacobian(jacobians: Sequence[np.ndarray]) -> np.ndarray:
    """Stack per-finger contact Jacobians into the block-diagonal hand Jacobian ``J_h`` (eq. 2.5).

    Args:
        jacobians: per contact, a (d, n_i) Jacobian of its contact point w.r.t. that finger's
            joints (e.g. ``PlanarHand.jacobian(q, finger)``, (2, 3)) [m/rad].

    Returns:
        (d k, sum n_i) block-diagonal ``J_h`` with ``xdot_c = J_h qdot``.
    """
    blocks = [np.atleast_2d(np.asarray(j, dtype=float)) for j in jacobians]
    if not blocks or len({b.shape[0] for b in blocks}) != 1:
        raise InvalidParameter(
            "jacobians: expected a non-empty list of (d, n_i) arrays with the same row count d"
        )
    d = blocks[0].shape[0]
    out = np.zeros((d * len(blocks), sum(b.shape[1] for b in blocks)))
    col = 0
    for i, b in enumerate(blocks):
        out[d * i : d * (i + 1), col : col + b.shape[1]] = b
        col += b.shape[1]
    return out


def joint_torques(jacobians: Sequence[np.ndarray], forces) -> np.ndarray:
    """Joint torques ``tau = J_h^T f`` that apply contact forces ``f`` (statics of eq. 2.5).

    Args:
        jacobians: per-contact Jacobians as in :func:`hand_jacobian`.
        forces: (k, d) contact forces [N].

    Returns:
        (sum n_i,) joint torques [N m].
    """
    J = hand_jacobian(jacobians)
    f = checks.vector("forces", np.ravel(forces), J.shape[0], "N")
    return J.T @ f


__all__ = ["grasp_matrix", "hand_jacobian", "joint_torques"]
