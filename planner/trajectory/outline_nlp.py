"""Phase-1 planning on a polygonal outline: the rolling NLP with the contacts' modes fixed.

:class:`~.rolling_nlp.RollingNLP` plans rolling on a circle. A sharp square pivots: its
corner sits on the pad while the pad turns, the round tip rolls along a face, the square
turns about the corner it stands on. Here the object is the executor's posed outline (a
polygon, object frame) and the contacts keep the modes they have at the phase start:

* the flat left pad touches the outline at the object point ``P`` (a corner, or the middle
  of a face lying on the pad): ``P`` on the pad's line, at a fixed place ``u`` on the pad
  (no slip: rolling a corner on a line is pivoting), every hull point behind the pad's line
  (the pad supports the outline); on a face the pad turns with the object;
* the round right tip touches the face ``m . x = h`` (object frame, ``m`` its outward unit
  normal): its centre at ``r`` from the face's line, the contact within the face, pure
  rolling, eq. (2.4) on a line: ``d a + r d(theta - phi_R) = 0`` with ``a`` the contact's
  place along the face (counter-clockwise);
* the outline's hull points above the palm (it may pivot on a corner), the lowest back on
  it at the end; the stability, joint-limit, step and travel constraints of the circle NLP.

Decision variables at knots ``k = 0..N``: the outline's pose ``(x, y, theta)`` [m, m, rad]
and the joint angles ``q`` (6,) [rad]. The plan is returned as a
:class:`~.rolling_nlp.RollingPlan` in the executor's per-step conventions (centre: the pad
contact plus ``R`` inward along the pad normal; rotation reference: eq. (2.4) integrated on
the pad, ``d phi_L - d u / R``), so that the controller tracks what it senses.
"""

from __future__ import annotations

import math
import time

import numpy as np

from planner import checks
from planner.trajectory.nlp_rows import ConstraintRows, tip_frames
from planner.trajectory.rolling_nlp import HOME_WEIGHT, SET_DOWN, RollingPlan

#: hull points may lie this far beyond the pad's line (the pose estimate's error) [m]
SUPPORT_TOL = 1e-3
#: parameters: r, mu, margin, q0 (6), pose0 (3), qm, home_x, max_rot, face flag, P (2),
#: m (2), h, a_lo, a_hi
_NP = 24


class OutlineNLP:
    """The phase-1 NLP on a polygonal outline (module docstring), built once.

    Args:
        hand: ``robots.planar_hand.PlanarHand`` (flat left pad, round right tip).
        hull_points: number K of the outline's hull points (parameters of every solve).
        knots: intervals N; max_step: largest rotation per interval [rad];
        max_tip_angle: largest angle of the round contact from the tip's axis [rad];
        travel: largest displacement of the pose from its start [m];
        pad_use: fraction of the pad's half-width the contact may use [-].
    """

    def __init__(
        self,
        hand,
        hull_points: int,
        knots: int = 8,
        max_step: float = 0.08,
        max_tip_angle: float = 1.2,
        travel: float = 0.03,
        pad_use: float = 0.9,
        tol: float = 1e-5,
    ) -> None:
        import casadi as cs

        t0 = time.perf_counter()
        self.hand = hand
        self.N = N = checks.integer("knots", knots, 2)
        self.K = K = checks.integer("hull_points", hull_points, 3)
        max_step = checks.positive("max_step", max_step, "rad")
        cos_tip = math.cos(checks.in_range("max_tip_angle", max_tip_angle, 0.0, math.pi, "rad"))
        travel = checks.positive("travel", travel, "m")
        pad = pad_use * hand.params.left.pad_half_width
        nk = 9
        X = cs.SX.sym("x", nk * (N + 1))
        P = cs.SX.sym("p", _NP + 2 * K)
        r, mu, margin, q0, pose0 = P[0], P[1], P[2], P[3:9], P[9:12]
        qm, home, max_rot, face = P[12], P[13], P[14], P[15]
        Po, mo, h, a_lo, a_hi = P[16:18], P[18:20], P[20], P[21], P[22]
        V = [P[_NP + 2 * j : _NP + 2 * j + 2] for j in range(K)]
        fk = tip_frames(hand)
        rows = ConstraintRows()
        add, g = rows.add, rows.g

        def rot(a, v):
            return cs.vertcat(cs.cos(a) * v[0] - cs.sin(a) * v[1],
                              cs.sin(a) * v[0] + cs.cos(a) * v[1])  # fmt: skip

        lim = hand.joint_limits
        cos_cone = cs.cos(cs.atan(mu) - margin)
        eo = cs.vertcat(-mo[1], mo[0])  # counter-clockwise along the tip's face
        obj = 0
        first = None
        lows0 = [pose0[1] + rot(pose0[2], v)[1] for v in V]
        for k in range(N + 1):
            v = X[nk * k : nk * (k + 1)]
            c, th, q = v[0:2], v[2], v[3:9]
            pL, phL, tR, phR = fk(q)
            nL = cs.vertcat(cs.sin(phL), -cs.cos(phL))
            tL = cs.vertcat(cs.cos(phL), cs.sin(phL))
            w = c + rot(th, Po)
            u = cs.dot(tL, w - pL)
            m, e = rot(th, mo), rot(th, eo)
            a = cs.dot(e, tR - c)
            add(cs.dot(nL, w - pL), 0, 0)  # the pad's contact point on its line
            add(cs.dot(m, tR - c) - h - r, 0, 0)  # the tip on the face's line
            bR = cs.atan2(m[1], m[0])
            tip_cos = cs.cos((bR + math.pi - phR) - math.pi / 2)
            behind = [cs.dot(nL, c + rot(th, vj) - pL) for vj in V]
            if k == 0:
                first = (u, a, th, phR, phL)
                tip_cos0, behind0 = tip_cos, behind
                for i in range(6):
                    add(q[i] - q0[i], 0, 0)
                obj += 1e4 * cs.sumsqr(c - pose0[0:2]) + 10.0 * (th - pose0[2]) ** 2
            else:
                u0, a0, th0, phR0, phL0 = first
                add(u - u0, 0, 0)  # no slip on the pad
                add(face * ((phL - th) - (phL0 - th0)), 0, 0)  # a face turns the pad
                add((a - a0) + r * ((th - th0) - (phR - phR0)), 0, 0)  # rolling, eq. (2.4)
                vp = X[nk * (k - 1) : nk * k]
                add(vp[2] - th, 0, max_step)
                obj += 1e-2 * cs.sumsqr(q - vp[3:9]) + 1e2 * cs.sumsqr(c - vp[0:2])
                for i in range(6):
                    add(q[i] - cs.fmin(lim[i, 0] + qm, q0[i]), 0, cs.inf)
                    add(q[i] - cs.fmax(lim[i, 1] - qm, q0[i]), -cs.inf, 0)
                add(u, -pad, pad)
                add(a - a_lo, 0, cs.inf)  # the contact within the face
                add(a - a_hi, -cs.inf, 0)
                for b, b0 in zip(behind, behind0, strict=True):  # the pad supports the outline
                    add(b - cs.fmax(SUPPORT_TOL, b0), -cs.inf, 0)
                lows = [c[1] + rot(th, vj)[1] for vj in V]
                for low, low0 in zip(lows, lows0, strict=True):
                    add(low - cs.fmin(0.0, low0), 0, cs.inf)
                add(cs.sumsqr(c - X[0:2]), 0, travel**2)
                # the round contact near the tip's axis (angle of -m in the tip frame vs +y;
                # a contact that starts beyond it may not move further out: the round tip
                # met the square's face 76 deg from its axis)
                add(tip_cos - cs.fmin(cos_tip, tip_cos0), 0, cs.inf)
            d = (tR - r * m) - w
            ud = d / cs.sqrt(cs.sumsqr(d) + 1e-12)
            lo_st = 0 if k > 0 else -cs.inf
            add(cs.dot(-nL, ud) - cos_cone, lo_st, cs.inf)
            add(cs.dot(m, ud) - cos_cone, lo_st, cs.inf)
            if k == N:
                low = lows[0]
                for e_ in lows[1:]:
                    low = cs.fmin(low, e_)
                add(low, -cs.inf, SET_DOWN)
                add((th - X[2]) + max_rot, 0, cs.inf)
        obj += X[nk * N + 2] + HOME_WEIGHT * (X[nk * N] - home) ** 2
        self._nk = nk
        self._lbg, self._ubg = rows.bounds()
        opts = {
            "ipopt.print_level": 0,
            "print_time": False,
            "ipopt.sb": "yes",
            "ipopt.max_iter": 300,
            "ipopt.tol": tol,
            "ipopt.mu_strategy": "adaptive",
        }
        problem = {"x": X, "p": P, "f": obj, "g": cs.vertcat(*g)}
        self.constraints = cs.Function("g", [X, P], [problem["g"]])  # for tests, diagnosis
        self._solver = cs.nlpsol("outline_rolling", "ipopt", problem, opts)
        self._fk = fk
        self.build_time_s = time.perf_counter() - t0
        self.iterations = 0

    def solve(self, q0, pose0, contact: dict, hull, tip_radius: float, mu: float, *,
              margin: float = 0.1, joint_margin: float = 0.05, home_x: float | None = None,
              max_rotation: float = math.inf, radius: float = 0.05,
              u_sensed: float | None = None) -> RollingPlan:  # fmt: skip
        """Plan phase 1 from joint angles ``q0`` [rad] and the outline's pose ``pose0``.

        Args:
            contact: the modes, object frame: ``pad_point`` (2,) [m] and ``pad_face``
                (bool), ``tip_normal`` (2,) unit, ``tip_offset`` [m], ``tip_range``
                (lo, hi) [m] (the face's extent along its counter-clockwise tangent).
            hull: (K, 2) hull points of the outline, object frame [m].
            radius: the executor's per-step estimate radius [m] (for the returned plan's
                conventions only).
            u_sensed: the pad contact the tactile array senses [m]: the plan's pad contact
                and centre are shifted along the pad by its difference from the plan's
                start (the array's centroid stops at its outermost taxel).

        Returns:
            the :class:`RollingPlan` (``rotation``: the outline's planned rotation).
        """
        q0 = checks.vector("q0", q0, 6, "rad")
        pose0 = checks.vector("pose0", pose0, 3)
        hull = checks.points("hull", hull, dims=(2,), n=self.K)
        p = np.concatenate([
            [tip_radius, mu, margin], q0, pose0,
            [joint_margin, pose0[0] if home_x is None else float(home_x),
             min(float(max_rotation), 10.0), 1.0 if contact["pad_face"] else 0.0],
            contact["pad_point"], contact["tip_normal"], [contact["tip_offset"]],
            contact["tip_range"], [0.0], hull.ravel(),
        ])  # fmt: skip
        x0 = np.tile(np.concatenate([pose0, q0]), self.N + 1)
        self.last_args = (x0, p)
        t0, c0 = time.perf_counter(), time.process_time()
        sol = self._solver(x0=x0, p=p, lbg=self._lbg, ubg=self._ubg)

        cpu = time.process_time() - c0
        ok = bool(self._solver.stats()["success"])
        self.iterations = int(self._solver.stats()["iter_count"])
        x = np.asarray(sol["x"]).ravel() if ok else x0
        self.last_solution = (x.reshape(self.N + 1, self._nk).copy(), p)  # pose, q per knot
        return self._plan(x.reshape(self.N + 1, self._nk), contact, ok, time.perf_counter() - t0,
                          cpu, float(radius), u_sensed)  # fmt: skip

    def _plan(self, Vx, contact, ok, wall, cpu, R, u_sensed) -> RollingPlan:
        """The solution in the executor's conventions (module docstring)."""
        n = len(Vx)
        cen, beta, u, theta = np.zeros((n, 2)), np.zeros((n, 2)), np.zeros(n), np.zeros(n)
        mo = np.asarray(contact["tip_normal"], float)
        Po = np.asarray(contact["pad_point"], float)
        for k, (x, y, th, *q) in enumerate(Vx):
            pL, phL, _, _ = (np.asarray(z, float).ravel() for z in self._fk(q))
            phL = float(phL[0])
            cs_, sn = math.cos(th), math.sin(th)
            w = np.array([x + cs_ * Po[0] - sn * Po[1], y + sn * Po[0] + cs_ * Po[1]])
            nL = np.array([math.sin(phL), -math.cos(phL)])
            u[k] = float((w - pL) @ np.array([math.cos(phL), math.sin(phL)]))
            cen[k] = w - R * nL
            if u_sensed is not None:
                shift = float(u_sensed) - (u[0] if k else u[k])
                tL = np.array([math.cos(phL), math.sin(phL)])
                cen[k] += shift * tL
                u[k] += shift
            beta[k] = (phL - 0.5 * math.pi, th + math.atan2(mo[1], mo[0]))
            theta[k] = (phL - 0.5 * math.pi) - beta[0, 0] - (u[k] - u[0]) / R
        return RollingPlan(
            theta=theta, centre=cen, q=Vx[:, 3:9].copy(), beta=beta, u=u,
            rotation=float(Vx[-1, 2] - Vx[0, 2]), success=ok, solve_time_s=wall,
            stop="none" if ok else "solver failed", solve_cpu_s=cpu, iterations=self.iterations,
        )  # fmt: skip


__all__ = ["OutlineNLP"]
