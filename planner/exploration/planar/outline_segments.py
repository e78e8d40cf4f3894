"""Phases 2/3 on a posed outline: the exploring finger's contact runs along the outline.

:func:`.segments.explore_segment` moves the explorer's contact along the nominal circle
about the estimated centre. On a square that arc cuts through the faces (the tip pressed
into the face, then left it, and over the top corner it pushed the square back onto its
face). Here the contact runs along the :class:`~.shape_tracking.ShapeTracker`'s posed
outline (world polygon) by arclength, on a quintic (startup) profile, from the contact
nearest to the explorer to the outline point at the target's world polar angle about the
outline's centre; the flat pad's orientation follows the outline's normal (averaged over
the pad's width, so it turns smoothly over a corner), the round tip keeps its orientation.
Holding finger, force ramps and segment layout as in :func:`.segments.explore_segment`.
"""

from __future__ import annotations

import bisect
import math

import numpy as np

from planner.exploration.planar.heuristics import pad_angle
from planner.exploration.planar.outline_pose import nearest_on_polygon
from planner.exploration.planar.phase_segment import Segment
from planner.exploration.planar.sensing import round_contact_arclength
from planner.trajectory import ForceRamp, QuinticSpline


class PolylinePath:
    """Arclength parametrization of a closed polygon ``W`` (M, 2) [m]: point, unit tangent
    and outward normal (counter-clockwise ``W``) at arclength ``s`` (wrapped)."""

    def __init__(self, W: np.ndarray) -> None:
        W = np.asarray(W, float)
        area2 = float(np.sum(W[:, 0] * np.roll(W[:, 1], -1) - np.roll(W[:, 0], -1) * W[:, 1]))
        self.W = W if area2 > 0 else W[::-1].copy()
        d = np.diff(np.vstack([self.W, self.W[:1]]), axis=0)
        self.seg = np.hypot(d[:, 0], d[:, 1])
        self.cum = np.concatenate([[0.0], np.cumsum(self.seg)])
        self.length = float(self.cum[-1])
        self._cum = self.cum.tolist()
        self._pts = self.W.tolist()
        self._dir = (d / np.maximum(self.seg, 1e-12)[:, None]).tolist()

    def arclength_of(self, point) -> float:
        """Arclength [m] of the polygon point nearest to ``point``."""
        q, _ = nearest_on_polygon(self.W, point)
        A, B = self.W, np.roll(self.W, -1, axis=0)
        AB, AQ = B - A, q - A
        cross = np.abs(AB[:, 0] * AQ[:, 1] - AB[:, 1] * AQ[:, 0])
        d = cross + np.hypot(*(q - A).T) + np.hypot(*(q - B).T)
        k = int(np.argmin(d - self.seg))  # the segment q lies on
        return float(self.cum[k] + np.hypot(*(q - A[k])))

    def at(self, s: float):
        """``(point, tangent)`` at arclength ``s`` [m] (lists of floats)."""
        s = s % self.length
        k = min(max(bisect.bisect_right(self._cum, s) - 1, 0), len(self._pts) - 1)
        (x, y), (tx, ty) = self._pts[k], self._dir[k]
        w = s - self._cum[k]
        return [x + w * tx, y + w * ty], [tx, ty]

    def normal_angle(self, s: float, window: float) -> float:
        """World angle [rad] of the outward normal averaged over ``s +- window`` [m]."""
        nx = ny = 0.0
        for v in np.linspace(s - window, s + window, 8):  # even: symmetric about a corner
            _, (tx, ty) = self.at(float(v))
            nx, ny = nx + ty, ny - tx
        return math.atan2(ny, nx)

    def point_at_angle(self, centre, angle: float) -> float:
        """Arclength [m] of the vertex whose polar angle about ``centre`` is nearest to
        ``angle`` [rad]."""
        d = self.W - np.asarray(centre, float)
        diff = np.abs(np.remainder(np.arctan2(d[:, 1], d[:, 0]) - angle + np.pi, 2 * np.pi) - np.pi)
        return float(self.cum[int(np.argmin(diff))])


def outline_explore_segment(
    kind: int,
    est,
    q,
    tracker,
    target_beta: float,
    theta0: float,
    settings,
    hand,
    target_point=None,
    phi_end: float | None = None,
) -> Segment:
    """The phase-2 (``kind`` 2: the right tip explores) or phase-3 (the left pad) segment on
    the posed outline of ``tracker``: the explorer's contact from where it is to the outline
    point at world polar angle ``target_beta`` [rad] about the posed outline's centre, or to
    the outline point nearest ``target_point`` (2,) [m] when given; the round tip turns to
    ``phi_end`` [rad] on the way when given (else it keeps its orientation)."""
    s = settings
    k = 1 if kind == 2 else 0
    path = PolylinePath(tracker.outline.posed(tracker.pose))
    s0 = path.arclength_of(est.p[k])
    if target_point is not None:
        s1 = path.arclength_of(target_point)
    else:
        s1 = path.point_at_angle(tracker.pose[:2], target_beta)
    ds = math.remainder(s1 - s0, path.length)
    end = path.at(s0 + ds)[0]
    phi0 = float(q[3 * k : 3 * k + 3].sum())
    turn = 0.0 if phi_end is None or k == 0 else float(phi_end) - phi0
    r = hand.params.right.tip_radius
    T_move = max(abs(ds) / s.explore_speed, abs(turn) * r / s.explore_speed, 0.05)
    prof = QuinticSpline.between([0.0], [ds], T_move).scalar()
    T = s.startup_time + T_move
    w = hand.params.left.pad_half_width

    def explore(t: float):
        tm = min(max(t - s.startup_time, 0.0), T_move)
        a, v, _ = prof(tm)
        (px, py), (tx, ty) = path.at(s0 + a)
        if k == 1:
            phi = phi0 + turn * (a / ds if abs(ds) > 1e-9 else min(tm / T_move, 1.0))
        else:  # the pad flat on the outline's (smoothed) normal
            phi = pad_angle(path.normal_angle(s0 + a, w), phi0)
        return (px, py), (v * tx, v * ty), phi

    holder = 0 if kind == 2 else 1
    f_hold0 = float(max(est.normal_force[holder], 0.0))
    f_hold = s.left_hold_force if holder == 0 else s.hold_force
    hold = ForceRamp(f_hold0, f_hold, s.startup_time)
    fexp = ForceRamp(float(max(est.normal_force[k], 0.0)), s.explore_force, s.startup_time)
    phiR = float(q[3:6].sum())
    keep = (float(est.u), round_contact_arclength(est.beta[1], phiR, r),
            [float(q[0:3].sum()), phiR], [0.0, 0.0])  # fmt: skip
    return Segment(
        kind=kind,
        duration=T + 0.02,
        explore=explore,
        rolling=lambda t: keep,
        hold_force=lambda t: float(hold(t)),
        explore_force=lambda t: float(fexp(t)),
        theta0=theta0,
        target=math.atan2(end[1] - float(tracker.pose[1]), end[0] - float(tracker.pose[0])),
    )


__all__ = ["PolylinePath", "outline_explore_segment"]
