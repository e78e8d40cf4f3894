"""The executor's estimate of a non-round object: the nominal outline, posed (§2.2.3).

When the planner's model (``nominal`` of :func:`~.machine.explore_object`) is not round,
the phase machine keeps a :class:`ShapeTracker`: the nominal outline posed by
:func:`.outline_pose.fit_pose` at every phase start from the pad's line and tactile
centroid, the round tip and the palm, with the rolling-integrated rotation as the prior;
with both fingers touching, also by a global search over the outline's symmetry period
without the prior (:func:`.outline_pose.fit_pose_global`), taken when it fits the readings
better (a square tipped over its corner 30 deg further than the rolling estimate said).
It replaces the per-step circle (:mod:`.sensing`) where that one was false on a square:

* the hold check of phases 2/3 (the held object must not move): the holding fingertip's
  encoder position, not the circle centre (``pad contact + R n``: with the pad flat on a
  face its tactile centroid sits at the pad's edge and the centre jumped 16 mm while the
  square stood still);
* the transition-4 decision: the right-palm grasp from the posed outline's contacts;
* the phase-1 start: the local circle tangent to the pad at its sensed contact and touching
  the tip (the controller's radius is set to it, so that its per-step estimate and the plan
  agree), and the posed outline's hull points for the NLP's palm clearance.
"""

from __future__ import annotations

import math

import numpy as np

from planner.exploration.planar.outline_pose import (
    FLAT_TOL,
    TIE_COST,
    Outline,
    Readings,
    contacts,
    fit_pose,
    fit_pose_global,
    nearest_on_polygon,
    pad_window,
    residuals,
    symmetry_order,
)

#: a nominal outline whose ``roundness`` is below this is a circle (no tracker) [-]
ROUND_TOL = 0.03
#: strain-gauge normal force [N] above which the right tip touches
TIP_TOUCH = 0.05
#: weight of the rotation prior [m/rad] (a rotation 0.1 rad off the prior costs 1 mm)
THETA_WEIGHT = 0.01
#: a fingertip sensing no force touches the posed outline when this near it
#: (``readings(geometric=True)``) [m]
GEOM_TOUCH = 5e-4
#: a fit whose residual norm exceeds this is not used [m]
FIT_TOL = 3e-3
#: offsets of the rotation starts of a fit from the prior [rad]
THETA_STARTS = (0.0, -0.15, 0.15, -0.3, 0.3)
#: a straight face shorter than this is not one for the outline NLP [m]
MIN_FACE = 0.01
#: the round contact keeps this far from a face's ends [m]
FACE_MARGIN = 0.002
#: hull points of the outline the phase-1 NLP keeps above the palm
PALM_POINTS = 16


def is_round(profile) -> bool:
    """Whether the executor models the closed ``profile`` as a circle (its roundness below
    :data:`ROUND_TOL`): a round nominal is used through its mean radius, any other one is
    posed (:meth:`ShapeTracker.of`)."""
    return _round(Outline.from_profile(profile))


def _round(outline: Outline) -> bool:
    return outline.roundness() < ROUND_TOL


class ShapeTracker:
    """The posed nominal outline (module docstring).

    Args:
        outline: the nominal :class:`~.outline_pose.Outline` (object frame) [m].
        pose: (3,) its start pose ``(x, y, theta)`` [m, m, rad].
        hand: the ``PlanarHand`` (pad half-width, tip radius).
        pad_u_max: the largest tactile centroid, the outermost taxel centre [m] (default:
            the pad's half-width).
    """

    def __init__(self, outline: Outline, pose, hand, pad_u_max: float | None = None) -> None:
        self.outline = outline
        self.pose = np.asarray(pose, float).copy()
        self.pad_w = float(hand.params.left.pad_half_width)
        self.r = float(hand.params.right.tip_radius)
        self.u_max = self.pad_w if pad_u_max is None else float(pad_u_max)
        self.hull = outline.hull(PALM_POINTS)
        self._theta = 0.0  # the rotation estimate at the last fit [rad]
        self._centre = None  # the circle estimate's centre at the last fit [m]
        self.cost = 0.0
        self.fits = 0
        self.rejected = 0
        self.global_fits = 0  # fits taken from the global search
        self.order = symmetry_order(outline)  # rotational symmetry of the nominal outline

    @classmethod
    def of(cls, nominal, hand, pad_u_max: float | None = None):
        """A tracker for ``nominal`` (a closed Profile), or None when it is round."""
        if nominal is None:
            return None
        from planner.exploration.planar.objects import rest_height

        outline = Outline.from_profile(nominal)
        if _round(outline):
            return None
        return cls(outline, (0.0, rest_height(nominal), 0.0), hand, pad_u_max)

    def readings(self, est, palm: bool, geometric: bool = False) -> Readings:
        """The sensed constraints of the estimate ``est`` (a ``GraspEstimate``); with
        ``geometric``, a fingertip that senses no force but lies within
        :data:`GEOM_TOUCH` of the posed outline touches it too (the start grasp, placed on
        the object at rest before any squeeze), the pad's centroid then the middle of the
        outline's support set on it."""
        touch = est.pad_touch
        tip = float(est.normal_force[1]) > TIP_TOUCH
        u = float(est.u) if touch else float("nan")
        if geometric and not (touch and tip):
            W = self.outline.posed(self.pose)
            if not tip:
                tip = abs(nearest_on_polygon(W, est.tips[1])[1] - self.r) < GEOM_TOUCH
            if not touch:
                touch, u = self._pad_by_geometry(W, est)
        return Readings(
            pad_point=est.tips[0].copy() if touch else None,
            pad_angle=float(est.phi[0]),
            pad_u=u,
            pad_half_width=self.pad_w,
            pad_u_max=self.u_max,
            tip_centre=est.tips[1].copy() if tip else None,
            tip_radius=self.r,
            palm=palm,
        )

    def _pad_by_geometry(self, W: np.ndarray, est) -> tuple[bool, float]:
        """Whether the flat pad (its centre ``est.tips[0]``, angle ``est.phi[0]``) lies
        on the posed outline ``W`` within :data:`GEOM_TOUCH`, and the middle of the
        outline's support set on it from the pad centre [m] (clipped to the taxels)."""
        c, s = math.cos(float(est.phi[0])), math.sin(float(est.phi[0]))
        n, t = np.array([s, -c]), np.array([c, s])
        p = np.asarray(est.tips[0], float)
        Wp = pad_window(W, p, t, self.pad_w)
        if len(Wp) == 0:
            return False, float("nan")
        h = Wp @ n
        if abs(float(h.max()) - float(n @ p)) >= GEOM_TOUCH:
            return False, float("nan")
        along = (Wp[h >= h.max() - FLAT_TOL] - p) @ t
        return True, float(np.clip(0.5 * (along.min() + along.max()), -self.u_max, self.u_max))

    def update(self, est, theta: float, palm: bool = True) -> bool:
        """Refit the pose to ``est``; ``theta`` [rad] is the executor's rotation estimate
        (its change since the last fit is the prior's). Returns whether the fit was used."""
        prior = float(self.pose[2] + (theta - self._theta))
        guess = self.pose.copy()
        if self._centre is not None:
            guess[:2] += est.centre - self._centre
        guess[2] = prior
        rd = self.readings(est, palm)
        # several starts: the rolling-integrated rotation of a square was 13 deg off after
        # one phase 1 (it integrates eq. 2.4 on the circle) and one start found a local
        # minimum 3-9 mm off
        fits = [fit_pose(self.outline, rd, (guess[0], guess[1], prior + d), prior, THETA_WEIGHT,
                         max_step=0.05 + abs(d)) for d in THETA_STARTS]  # fmt: skip
        fit = min(fits, key=lambda f: f.cost if f.success else math.inf)
        if rd.pad_point is not None and rd.tip_centre is not None:
            fit = self._global(rd, fit, prior)
        self.cost = fit.cost
        self._theta, self._centre = theta, est.centre.copy()
        if not fit.success or fit.cost > FIT_TOL:
            self.rejected += 1
            self.pose = guess
            return False
        self.fits += 1
        self.pose = fit.pose
        return True

    def _global(self, rd: Readings, local, prior: float):
        """The better of the ``local`` fit (started at the rolling prior) and
        :func:`.outline_pose.fit_pose_global` (starts over the symmetry period, no prior),
        by the sensed residuals alone: the global one is taken when the local one failed or
        fits the readings :data:`.outline_pose.TIE_COST` worse (the 6 cm square tipped 42
        deg where the rolling estimate said 12: the local fit stayed 30 mm off)."""
        glob = fit_pose_global(self.outline, rd, self.pose, prior, self.order)
        if not glob.success:
            return local
        sensed = float(np.linalg.norm(residuals(self.outline, local.pose, rd)))
        if not local.success or glob.cost < sensed - TIE_COST:
            self.global_fits += 1
            return glob
        return local

    def right_palm_epsilon(self, est, mu: float) -> float:
        """Grasp quality of the right tip and the palm holding the posed outline [-]."""
        from planner.grasp import epsilon_two_planar

        c = contacts(self.outline, self.pose, self.readings(est, True))
        if "tip" not in c:
            return 0.0
        return float(epsilon_two_planar(c["tip"], -c["tip_normal"], c["palm"],
                                        np.array([0.0, 1.0]), mu))  # fmt: skip

    def local_circle(self, est, r: float, R0: float, span=(0.3, 4.0), geometric=False):
        """The circle the phase-1 NLP plans on (the documented reduction of rolling on the
        outline: the local curvature between the two contacts): tangent to the pad at its
        sensed contact and touching the round tip (``|T - p + R n| = R + r``), its radius
        clamped to ``span`` times ``R0`` [m]. Returns ``(centre (2,), R, beta (2,), u)`` or
        None (no pad or tip contact on the posed outline; ``geometric``: as in
        :meth:`readings`)."""
        rd = self.readings(est, True, geometric)
        if rd.pad_point is None or rd.tip_centre is None:
            return None
        c, s = math.cos(rd.pad_angle), math.sin(rd.pad_angle)
        n, t = np.array([s, -c]), np.array([c, s])
        # the pad contact where the tactile array senses it (the controller's per-step
        # estimate uses it too: a plan from the posed outline's contact, 1-2 mm beside it,
        # started with a jump of the rolling references)
        p = rd.pad_point + rd.pad_u * t
        d = rd.tip_centre - p
        den = 2.0 * (float(d @ n) - r)
        if abs(den) < 1e-9:
            return None
        R = float(np.clip((r * r - float(d @ d)) / den, span[0] * R0, span[1] * R0))
        centre = p - R * n
        bl = math.atan2(n[1], n[0])
        tip = rd.tip_centre - centre
        br = math.atan2(tip[1], tip[0])
        return centre, R, np.array([bl, br]), float((p - rd.pad_point) @ t)

    def hull_points(self) -> np.ndarray:
        """(PALM_POINTS, 2) hull points of the outline, object frame [m] (the last one
        repeated when the hull has fewer)."""
        H = self.hull
        return np.vstack([H, np.repeat(H[-1:], PALM_POINTS - len(H), axis=0)])

    def contact_modes(self, est) -> dict | None:
        """The contacts' modes for :class:`planner.trajectory.OutlineNLP` (object frame), or
        None when the round tip is not on a straight face at least :data:`MIN_FACE` long
        (then the outline is planned on its local circle).

        Returns:
            ``{"pad_point", "pad_face", "tip_normal", "tip_offset", "tip_range"}``.
        """
        rd = self.readings(est, True)
        if rd.pad_point is None or rd.tip_centre is None:
            return None
        x, y, a = self.pose
        c, s = math.cos(a), math.sin(a)
        Rt = np.array([[c, s], [-s, c]])  # world -> object frame

        def to_obj(w):
            return Rt @ (np.asarray(w, float) - (x, y))

        con = contacts(self.outline, self.pose, rd)
        pad = to_obj(con["pad"])
        W = self.outline.posed(self.pose)
        cp, sp = math.cos(rd.pad_angle), math.sin(rd.pad_angle)
        h = W @ np.array([sp, -cp])
        sup = (W[h >= h.max() - FLAT_TOL] - rd.pad_point) @ np.array([cp, sp])
        face = self.face_at(to_obj(con["tip"]))
        if face is None:
            return None
        A, B = face
        e = (B - A) / np.linalg.norm(B - A)
        m = np.array([e[1], -e[0]])
        if m @ (A - self.outline.points.mean(axis=0)) < 0:  # outward
            m, e = -m, -e
        eo = np.array([-m[1], m[0]])
        lo, hi = sorted((float(A @ eo), float(B @ eo)))
        return {
            "pad_point": pad,
            "pad_face": bool(sup.max() - sup.min() > 2e-3),
            "tip_normal": m,
            "tip_offset": float(m @ A),
            "tip_range": (lo + FACE_MARGIN, hi - FACE_MARGIN),
        }

    def face_at(self, point):
        """The straight face of the outline (object frame) through ``point`` (2,) [m]: its
        two ends ``(A, B)`` [m], or None when shorter than :data:`MIN_FACE`."""
        P = self.outline.points
        n = len(P)
        k = int(np.argmin(np.linalg.norm(P - point, axis=1)))
        d = np.diff(np.vstack([P, P[:1]]), axis=0)
        ang = np.arctan2(d[:, 1], d[:, 0])

        def same(i, j):
            return abs(math.remainder(ang[i % n] - ang[j % n], 2 * math.pi)) < 1e-3

        # the segment through the point: k-1 -> k or k -> k+1, whichever is nearer
        seg = k if np.linalg.norm(P[(k + 1) % n] - point) < np.linalg.norm(P[k - 1] - point) \
            else k - 1  # fmt: skip
        i, j = seg, seg
        while same(i - 1, seg) and (seg - i) < n:
            i -= 1
        while same(j + 1, seg) and (j - seg) < n:
            j += 1
        A, B = P[i % n], P[(j + 1) % n]
        if np.linalg.norm(B - A) < MIN_FACE:
            return None
        return A, B

    def palm_points(self, centre) -> np.ndarray:
        """(PALM_POINTS, 2) hull points of the posed outline relative to ``centre`` [m]
        (world axes: the NLP's object frame at the phase start)."""
        x, y, a = self.pose
        cs, sn = math.cos(a), math.sin(a)
        H = self.hull
        W = np.column_stack([x + cs * H[:, 0] - sn * H[:, 1], y + sn * H[:, 0] + cs * H[:, 1]])
        P = W - np.asarray(centre, float)
        if len(P) < PALM_POINTS:  # repeat the last point (the NLP has a fixed size)
            P = np.vstack([P, np.repeat(P[-1:], PALM_POINTS - len(P), axis=0)])
        return P


__all__ = ["PALM_POINTS", "ROUND_TOL", "ShapeTracker", "is_round"]
