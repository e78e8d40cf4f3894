"""Compiled :func:`.pivot_reach.finger_configurations` (same maths, one call per batch).

Why compiled: the pivot planner's rolling-path search (:func:`.pivot_reach.tip_rolling_path`)
asks for the finger's configurations at ~90 candidate tip poses per rotation knot, and a
phase-2 regrasp search runs hundreds of such paths; the vectorized numpy version spent most
of its ~0.65 ms per batch in array-call overhead (12 of 20 s of a 3 s posed-triangle run).
The numpy version stays the reference (``tests/test_gait_shape_pivot.py`` compares the two).

Kinematics as :mod:`robots.planar_hand.kinematics`: link k points along
``d(s_k) = (-sin s_k, cos s_k)``, ``s_k = q_1 + ... + q_k``; the IK's two elbow branches
``q_2 = +-acos(c_2)``; angles shifted by multiples of 2 pi into the limits
(``kinematics.wrap_into``).
"""

from __future__ import annotations

import math

import numpy as np

from planner.jit import njit

TWO_PI = 2.0 * math.pi


@njit(cache=True, nogil=True)
def configurations(base, lengths, lim, T, phi, hull_n, hull_c, corner, theta, margin, clr,
                   q_out, m_out, ok_out):  # fmt: skip
    """For each tip pose ``T[i]`` (M, 2) [m], ``phi[i]`` (M,) [rad]: the elbow branch with
    the largest joint-limit margin among the feasible ones (the first branch when none is)
    into ``q_out`` (M, 3) [rad], its margin ``m_out`` (M,) [rad] and feasibility ``ok_out``
    (M,): reachable, inside the limits ``lim`` (3, 2) by ``margin`` [rad], its joints 1-3
    and link midpoints at least ``clr`` [m] outside the hull ``n . x + c <= 0``
    (``hull_n`` (H, 2), ``hull_c`` (H,)) turned by ``theta`` [rad] about ``corner`` (2,)."""
    l1, l2, l3 = lengths[0], lengths[1], lengths[2]
    ct, st = math.cos(-theta), math.sin(-theta)  # points back into the hull's frame
    q = np.empty(3)
    pts = np.empty((4, 2))
    probe = np.empty((6, 2))
    for i in range(T.shape[0]):
        wx = T[i, 0] - l3 * -math.sin(phi[i]) - base[0]
        wy = T[i, 1] - l3 * math.cos(phi[i]) - base[1]
        c2 = (wx * wx + wy * wy - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)
        reach = abs(c2) <= 1.0 + 1e-12
        q2a = math.acos(min(max(c2, -1.0), 1.0))
        best_m, chosen = -math.inf, False
        for b in range(2):
            q2 = q2a if b == 0 else -q2a
            q1 = math.atan2(wy, wx) - math.atan2(l1 + l2 * math.cos(q2), -l2 * math.sin(q2))
            q[0], q[1], q[2] = q1, q2, phi[i] - q1 - q2
            inside = True
            m = math.inf
            for j in range(3):
                lo = lim[j, 0]
                v = lo + (q[j] - lo) % TWO_PI
                q[j] = v
                if v > lim[j, 1] + 1e-12:
                    inside = False
                m = min(m, v - lo, lim[j, 1] - v)
            ok = reach and inside and m >= margin
            if ok:
                s = 0.0
                ax, ay = 0.0, 0.0  # numpy's order: the links' cumulative sum, then the base
                pts[0, 0], pts[0, 1] = base[0], base[1]
                for j in range(3):
                    s += q[j]
                    ax += -math.sin(s) * lengths[j]
                    ay += math.cos(s) * lengths[j]
                    pts[j + 1, 0], pts[j + 1, 1] = ax + base[0], ay + base[1]
                for j in range(3):
                    probe[j, 0], probe[j, 1] = pts[j, 0], pts[j, 1]
                    probe[3 + j, 0] = 0.5 * (pts[j, 0] + pts[j + 1, 0])
                    probe[3 + j, 1] = 0.5 * (pts[j, 1] + pts[j + 1, 1])
                for j in range(6):
                    dx, dy = probe[j, 0] - corner[0], probe[j, 1] - corner[1]
                    px = corner[0] + ct * dx - st * dy
                    py = corner[1] + st * dx + ct * dy
                    dist = -math.inf
                    for h in range(hull_n.shape[0]):
                        dist = max(dist, px * hull_n[h, 0] + py * hull_n[h, 1] + hull_c[h])
                    if dist < clr:
                        ok = False
                        break
            # numpy's argmax over where(ok, m, -inf): the first best feasible branch, else 0
            score = m if ok else -math.inf
            if not chosen or score > best_m:
                chosen = True
                best_m = score
                q_out[i, 0], q_out[i, 1], q_out[i, 2] = q[0], q[1], q[2]
                m_out[i] = m
                ok_out[i] = ok


__all__ = ["configurations"]
