"""Which stable two-finger grasps the hand can reach along a pivot (:mod:`.pivot_reach`).

The workspace question of a gait on a polygon (thesis §2.3.1: "finger workspaces were the
most serious limitation"): as the object pivots about its palm corner, which of its edges
and vertices can the flat left pad and the round right tip touch (joint limits with a
margin, links clear of the object), and does some reachable pair make a stable two-finger
grasp (Yoshikawa-Nagai: the contact line inside both friction cones, §2.2.3)? On the
square_gait hand the answer for the 11 cm square is: the left/right faces up to 30 deg, then
only the pad under the bottom-left corner with the tip on the top face, up to 55 deg.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.exploration.planar.pivot_reach import (
    FACE_END,
    JOINT_MARGIN,
    LINK_CLEARANCE,
    Face,
    HullClearance,
    finger_configurations,
    palm_corner,
    pivoted,
    rotation,
)


@dataclass(frozen=True)
class PivotGrasps:
    """What the fingers can touch at one rotation of a pivot (:func:`pivot_grasps`).

    Attributes:
        theta: the object's rotation from the phase start [rad].
        pad: indices of the polygon's edges (``W[i] -> W[i+1]``) and vertices (``M + i``)
            the left pad can touch within its joint limits, links clear.
        tip: the same for the round right tip.
        stable: whether some reachable pad contact and some reachable tip contact make a
            stable two-finger grasp (their line inside both friction cones, Yoshikawa-Nagai).
    """

    theta: float
    pad: tuple[int, ...]
    tip: tuple[int, ...]
    stable: bool


def _contact_samples(W: np.ndarray, spacing: float, cone_step: float):
    """Points (N, 2), outward normals (N, 2) and feature labels (N,) of the polygon ``W``:
    its edges every ``spacing`` [m] (away from the ends by :data:`FACE_END`) and its
    vertices with normals across their normal cones every ``cone_step`` [rad]."""
    M = len(W)
    inside = W.mean(axis=0)
    pts, nrm, lab = [], [], []
    for i in range(M):
        f = Face.between(W[i], W[(i + 1) % M], inside)
        n = max(2, int(f.length / spacing))
        for d in np.linspace(FACE_END, f.length - FACE_END, n):
            pts.append(f.start + d * f.tangent)
            nrm.append(f.normal)
            lab.append(i)
    for i in range(M):
        a = Face.between(W[i - 1], W[i], inside).normal
        b = Face.between(W[i], W[(i + 1) % M], inside).normal
        a0, a1 = math.atan2(a[1], a[0]), math.atan2(b[1], b[0])
        span = math.remainder(a1 - a0, 2 * math.pi)
        for t in np.linspace(0.0, 1.0, max(2, int(abs(span) / cone_step) + 1)):
            ang = a0 + t * span
            pts.append(W[i].copy())
            nrm.append(np.array([math.cos(ang), math.sin(ang)]))
            lab.append(M + i)
    return np.array(pts), np.array(nrm), np.array(lab)


def pivot_grasps(
    hand,
    W,
    thetas,
    mu: float,
    *,
    spacing: float = 0.005,
    cone_step: float = math.radians(10.0),
    phi_step: float = math.radians(3.0),
    margin: float = JOINT_MARGIN,
    clearance: float = LINK_CLEARANCE,
) -> list[PivotGrasps]:
    """For each rotation in ``thetas`` [rad] of the object (world polygon ``W`` (M, 2) at
    rotation 0, resting on the palm) about its palm corner: which edges and vertices each
    finger can touch and whether a reachable pair is a stable two-finger grasp with
    friction coefficient ``mu`` [-]. The pad lies flat on the contact's tangent; the round
    tip may touch with any point of its disc (its orientation is searched every
    ``phi_step``) as long as the links stay clear."""
    W = checks.points("W", W, dims=(2,), min_count=3)
    checks.positive("mu", mu, "-")
    r = float(hand.params.right.tip_radius)
    k = palm_corner(W)
    clear = HullClearance(W)
    P0, N0, lab = _contact_samples(W, spacing, cone_step)
    lim = hand.finger_limits("right")
    phis = np.arange(lim[:, 0].sum(), lim[:, 1].sum(), phi_step)
    cone = math.atan(mu)
    out = []
    for th in np.asarray(thetas, float):
        P = pivoted(P0, k, th)
        N = N0 @ rotation(th).T
        phi_pad = np.arctan2(N[:, 1], N[:, 0]) + 0.5 * math.pi
        _, _, pad_ok = finger_configurations(
            hand, "left", P, phi_pad, clear, k, th, margin, clearance
        )
        T = P + r * N
        tip_ok = np.zeros(len(P), bool)
        for i in np.flatnonzero(T[:, 1] >= r):
            Ti = np.broadcast_to(T[i], (len(phis), 2))
            ok = finger_configurations(hand, "right", Ti, phis, clear, k, th, margin, clearance)[2]
            tip_ok[i] = ok.any()
        stable = False
        if pad_ok.any() and tip_ok.any():
            a, b = P[pad_ok], P[tip_ok]
            line = b[None, :, :] - a[:, None, :]
            line /= np.maximum(np.linalg.norm(line, axis=-1, keepdims=True), 1e-12)
            # the pad pushes along its inward normal -n_a, the tip along -n_b
            ca = -(line * N[pad_ok][:, None, :]).sum(-1)
            cb = (line * N[tip_ok][None, :, :]).sum(-1)
            stable = bool(((ca >= math.cos(cone)) & (cb >= math.cos(cone))).any())
        out.append(PivotGrasps(float(th), tuple(sorted(set(lab[pad_ok].tolist()))),
                               tuple(sorted(set(lab[tip_ok].tolist()))), stable))  # fmt: skip
    return out


__all__ = ["PivotGrasps", "pivot_grasps"]
