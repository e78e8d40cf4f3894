"""Phase-1 trajectory planning: a CasADi NLP over the rolling-contact trajectory (§2.2.2).

The planner knows the object only through its *estimate*: a circle of radius ``R`` about a
centre ``c`` (the nominal shape, refitted to what the fingers sensed). Phase 1 rotates the
object clockwise with both fingers in pure rolling (eqs. 2.3-2.4, ``s = r theta``), as far as
the fingers' workspaces and the grasp's stability allow.

Decision variables at knots ``k = 0..N``: the object rotation ``theta_k`` [rad] (0 at the
start) and centre ``c_k`` (2,) [m], the joint angles ``q_k`` (6,) [rad], the world polar
angles ``beta_L,k``, ``beta_R,k`` of the two contacts about ``c_k`` [rad] and the contact
position ``u_k`` across the flat left pad [m] (a round left tip: its contact's arclength
from the tip's apex). Constraints, at every knot:

* finger kinematics (expressions walked from the Pinocchio model): the round right tip's
  centre at ``c + (R + r) n(beta_R)``; the flat left pad facing the object
  (``phi_L = beta_L + pi/2`` up to a whole turn) with its point ``u`` on ``c + R n(beta_L)``
  (a round left tip of radius ``r_L``: its centre at ``c + (R + r_L) n(beta_L)``);
* pure rolling, eq. (2.4) integrated: the contact travels equal arclengths on the object
  (``R (beta - theta)``) and on the fingertip (round: ``r (beta + pi - phi)``, the left
  one's ``u``; pad: ``-u``):
  ``R d(beta - theta) + d s_f = 0``;
* joint limits with a margin (a joint that starts inside the margin band may stay there but
  not move further toward its limit), the pad contact within the pad, the round contact
  within ``max_tip_angle`` of the tip's axis (with ``relax_start``, relaxed to the start
  the same way);
* stability (Yoshikawa-Nagai, eq. 2.9): the contact line within the friction cones with an
  angular margin, ``(-n_i) . u_i >= cos(atan(mu) - margin)``;
* the object above the palm (``c_y >= R``) and near its start, set down at the end (its
  final centre at most :data:`SET_DOWN` above the start: phases 2/3 hold it against the
  palm); monotone clockwise rotation with at most ``max_step`` per knot;
* with ``palm_points`` K > 0 (an object that is not the circle: the executor's posed
  outline), the palm constraint is the outline's instead: K points ``v_j`` of its hull
  (relative to the start centre, parameters) stay above the palm,
  ``c_y + (Rot(theta) v_j)_y >= min(0, start height)``, and the lowest of them ends at most
  :data:`SET_DOWN` above it (rotating an 11 cm square about its centre needs up to 23 mm of
  lift; the circle's ``c_y >= R`` put its corners 13 mm into the palm at 16 deg).

Objective: maximize the rotation ``-theta_N`` plus a small smoothness term. The NLP is built
once (:class:`RollingNLP`, parameters = the estimate and the start state) and solved with
IPOPT, warm-started from the previous solution.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.trajectory.nlp_rows import ConstraintRows, tip_frames

#: number of parameters: R, r, mu, margin, c0 (2), q0 (6), beta0 (2), u0, q_margin, home_x,
#: max_rotation
_NP = 18
#: weight of the final centre's distance from ``home_x`` [1/m^2] (objective units: rad)
HOME_WEIGHT = 500.0
#: the object's final centre at most this higher than at the start [m]
SET_DOWN = 1.0e-3


@dataclass(frozen=True)
class RollingPlan:
    """A phase-1 plan.

    Attributes:
        theta: (N+1,) object rotation at the knots [rad] (<= 0: clockwise).
        centre: (N+1, 2) object centre [m].
        q: (N+1, 6) joint angles [rad].
        beta: (N+1, 2) world polar angles of the left and right contacts [rad].
        u: (N+1,) contact position across the left pad [m] (a round left tip: its
            contact's arclength from the apex, :func:`round_contact_arclength`'s).
        rotation: total rotation ``theta[-1]`` [rad].
        success: the solver converged; solve_time_s: wall time of the solve [s].
        solve_cpu_s: its CPU time [s] (what load on a shared machine does not inflate).
        iterations: IPOPT iterations.
        stop: which constraint ends the rotation (the largest multiplier group).
    """

    theta: np.ndarray
    centre: np.ndarray
    q: np.ndarray
    beta: np.ndarray
    u: np.ndarray
    rotation: float
    success: bool
    solve_time_s: float
    stop: str
    solve_cpu_s: float = float("nan")
    iterations: int = 0


class RollingNLP:
    """The phase-1 NLP of one hand, built once, solved many times.

    Args:
        hand: ``robots.planar_hand.PlanarHand`` with a round right tip and a flat (the
            thesis' hand) or round left tip.
        knots: number of intervals N (>= 2).
        max_step: largest rotation per interval [rad].
        max_tip_angle: largest angle of the round contact from the tip axis [rad].
        travel: largest displacement of the object centre from its start [m].
        pad_use: fraction of the pad's half-width the contact may use [-].
        palm_points: number K of outline points kept above the palm (0: the circle's
            ``c_y`` constraint; see the module docstring).
        relax_start: the round contact's ``max_tip_angle`` relaxed to the start like the
            joint limits: a start farther round the tip may stay there but not roll further
            (the executor's last resort, ``GaitSettings.last_resort``).
    """

    def __init__(
        self,
        hand,
        knots: int = 8,
        max_step: float = 0.08,
        max_tip_angle: float = 1.2,
        travel: float = 0.01,
        pad_use: float = 0.6,
        tol: float = 1e-5,
        palm_points: int = 0,
        relax_start: bool = False,
    ) -> None:
        import casadi as cs

        t0 = time.perf_counter()
        self.hand = hand
        self.N = checks.integer("knots", knots, 2)
        self.max_step = checks.positive("max_step", max_step, "rad")
        self.max_tip_angle = checks.in_range("max_tip_angle", max_tip_angle, 0.0, math.pi, "rad")
        self.travel = checks.positive("travel", travel, "m")
        self.K = K = checks.integer("palm_points", palm_points, 0)
        self.relax_start = relax_start = bool(relax_start)
        pad = hand.params.left.pad_half_width
        N = self.N
        nk = 12  # theta, cx, cy, q(6), betaL, betaR, u
        X = cs.SX.sym("x", nk * (N + 1))
        P = cs.SX.sym("p", _NP + 2 * K)
        V = [P[_NP + 2 * j : _NP + 2 * j + 2] for j in range(K)]  # hull points - c0 [m]
        R, r, mu, margin = P[0], P[1], P[2], P[3]
        c0, q0, beta0, u0, qm, home = P[4:6], P[6:12], P[12:14], P[14], P[15], P[16]
        max_rot = P[17]
        fk = tip_frames(hand)
        rows = ConstraintRows()
        add, g = rows.add, rows.g

        # the left tip: the flat pad (None) or a round tip's radius [m]; with a round one
        # ``u`` is its contact's arclength from the apex [m], and the rolling term s_f = +u
        rL = hand.params.left.round_radius or None
        self.left_round = rL is not None
        sgn = 1.0 if rL is None else -1.0
        cos_max = math.cos(self.max_tip_angle)
        cos_tip0 = [None, None]

        def tip_angle(cos_tip, k, i):
            if k == 0:
                cos_tip0[i] = cos_tip
            if not relax_start:
                add(cos_tip, cos_max, 1.0)
            elif k > 0:
                add(cos_tip - cs.fmin(cos_max, cos_tip0[i]), 0, cs.inf)

        lim = hand.joint_limits
        cos_cone = cs.cos(cs.atan(mu) - margin)
        obj = 0
        phiL0 = None
        for k in range(N + 1):
            v = X[nk * k : nk * (k + 1)]
            th, c, q, bL, bR, u = v[0], v[1:3], v[3:9], v[9], v[10], v[11]
            pL, phL, pR, phR = fk(q)
            nL = cs.vertcat(cs.cos(bL), cs.sin(bL))
            nR = cs.vertcat(cs.cos(bR), cs.sin(bR))
            # kinematics: right tip centre, left pad point and orientation
            dR = pR - (c + (R + r) * nR)
            add(dR[0], 0, 0)
            add(dR[1], 0, 0)
            if rL is None:  # the flat pad's point u on the object
                dL = pL + u * cs.vertcat(cs.cos(phL), cs.sin(phL)) - (c + R * nL)
            else:  # a round left tip: its centre on the offset circle, u its arclength
                dL = pL - (c + (R + rL) * nL)
            add(dL[0], 0, 0)
            add(dL[1], 0, 0)
            if k == 0:
                phiL0, bL0, bR0, u_0 = phL, bL, bR, u
                for i in range(6):
                    add(q[i] - q0[i], 0, 0)
                add(th, 0, 0)
                # the sensed estimate is a prior: the start must be kinematically consistent
                obj += 1e3 * (cs.sumsqr(c - c0) + 1e-4 * cs.sumsqr(cs.vertcat(bL, bR) - beta0))
                obj += 1e3 * (u - u0) ** 2
            else:
                if rL is None:  # pad flat on the object: phi_L - beta_L constant
                    add((phL - bL) - (phiL0 - bL0), 0, 0)
                else:  # the round tip's arclength u follows its contact angle
                    add((u - u_0) - rL * ((bL - phL) - (bL0 - phiL0)), 0, 0)
                # pure rolling, eq. (2.4): R d(beta - theta) + d s_f = 0 (pad: s_f = -u)
                add(R * ((bL - th) - bL0) - sgn * (u - u_0), 0, 0)
                phR0 = q0[3] + q0[4] + q0[5]
                add(R * ((bR - th) - bR0) + r * ((bR - phR) - (bR0 - phR0)), 0, 0)
                vp = X[nk * (k - 1) : nk * k]
                add(vp[0] - th, 0, self.max_step)  # clockwise, bounded steps
                obj += 1e-2 * cs.sumsqr(q - vp[3:9]) + 1e2 * cs.sumsqr(c - vp[1:3])
            # joint limits with a margin, relaxed to the start: a joint that starts inside
            # the margin band (or beyond its limit: the previous phase ended on a workspace
            # event) may stay where it is but not move further toward its limit (the strict
            # margin at knot 1 made the NLP infeasible right at the start: "solver failed;
            # blocking: workspace (joint 5 0.0 deg from its limit)" on 20 of 31 objects: joint 5 =
            # the right finger's joint 3)
            for i in range(6 if k > 0 else 0):
                add(q[i] - cs.fmin(lim[i, 0] + qm, q0[i]), 0, cs.inf)
                add(q[i] - cs.fmax(lim[i, 1] - qm, q0[i]), -cs.inf, 0)
            if rL is None:
                add(u, -pad_use * pad, pad_use * pad)
            else:  # a round left contact near its tip's axis, relaxed to the start
                tip_angle(cs.cos(bL + math.pi / 2 - phL), k, 0)
            # round contact near the tip axis: angle of (-n_R) in the tip frame vs +y; with
            # relax_start a contact that starts farther round may stay there but not roll
            # further (the start is what it is)
            tip_angle(cs.cos((bR + math.pi - phR) - math.pi / 2), k, 1)
            # stability: contact line inside both cones with a margin
            cL = c + R * nL
            cR = c + (R + 0.0) * nR
            d = cR - cL
            ud = d / cs.sqrt(cs.sumsqr(d) + 1e-12)
            lo_st = 0 if k > 0 else -cs.inf  # the start is what it is
            add(cs.dot(-nL, ud) - cos_cone, lo_st, cs.inf)
            add(cs.dot(nR, ud) - cos_cone, lo_st, cs.inf)
            lows = [c[1] + cs.sin(th) * v[0] + cs.cos(th) * v[1] for v in V]
            if k > 0 and K:
                for v, low in zip(V, lows, strict=True):  # the outline above the palm
                    add(low - cs.fmin(0.0, X[2] + v[1]), 0, cs.inf)
            elif k > 0:
                # above the palm: not lower than the start or the circle resting on it (an
                # object that is not the model circle rests lower than R; c_y >= R made
                # the start itself infeasible for a 12 x 10 cm ellipse)
                add(c[1] - cs.fmin(R, X[2]), 0, cs.inf)
            add(cs.sumsqr(c - X[1:3]), 0, self.travel**2)
            if k == N:
                # set the object down where it started (on the palm): phases 2/3 hold it
                # against the palm, and an object left lifted fell back under the holding
                # finger there, rolling back (a 3 cm circle ended phase 1 11 mm up and rolled
                # back 14 of its 27 deg in phase 2: "no progress")
                if K:  # the outline's lowest point back on the palm
                    low = lows[0]
                    for e in lows[1:]:
                        low = cs.fmin(low, e)
                    add(low, -cs.inf, SET_DOWN)
                else:
                    add(c[1] - X[2], -cs.inf, SET_DOWN)
                add(th + max_rot, 0, cs.inf)  # at most max_rotation clockwise
        obj += X[nk * N]  # theta_N (negative): minimize = rotate as far as possible
        # bring the object back over the hand's middle: the explorers' friction rolls it along
        # the palm in phases 2/3 (up to 4 cm after a ridge caught the right tip) and an object
        # far off-centre leaves one finger no joint range to rotate it
        obj += HOME_WEIGHT * (X[nk * N + 1] - home) ** 2
        self._nk = nk
        self._ng = [int(e.shape[0]) for e in g]
        G = cs.vertcat(*g)
        self._lbg, self._ubg = rows.bounds()
        opts = {
            "ipopt.print_level": 0,
            "print_time": False,
            "ipopt.sb": "yes",
            "ipopt.max_iter": 200,
            "ipopt.tol": tol,
            "ipopt.mu_strategy": "adaptive",
            "ipopt.warm_start_init_point": "yes",
            "ipopt.mu_init": 1e-3,
            "ipopt.warm_start_bound_push": 1e-9,
            "ipopt.warm_start_bound_frac": 1e-9,
            "ipopt.warm_start_slack_bound_frac": 1e-9,
            "ipopt.warm_start_slack_bound_push": 1e-9,
            "ipopt.warm_start_mult_bound_push": 1e-9,
        }
        problem = {"x": X, "p": P, "f": obj, "g": G}
        self._solver = cs.nlpsol("rolling", "ipopt", problem, opts)
        self._last = None
        self.build_time_s = time.perf_counter() - t0

    def initial_guess(self, q0, centre, beta0, u0) -> np.ndarray:
        """A guess holding the start configuration at every knot."""
        v = np.concatenate([[0.0], centre, q0, beta0, [u0]])
        return np.tile(v, self.N + 1)

    def solve(
        self,
        q0,
        centre,
        radius: float,
        tip_radius: float,
        mu: float,
        beta0,
        u0: float,
        *,
        margin: float = 0.1,
        joint_margin: float = 0.05,
        warm: bool = True,
        home_x: float | None = None,
        max_rotation: float = math.inf,
        palm_points=None,
    ) -> RollingPlan:
        """Plan phase 1 from the current configuration.

        Args:
            q0: (6,) current joint angles [rad].
            centre: (2,) estimated object centre [m]; radius: estimated radius [m].
            tip_radius: radius of the round right tip [m].
            mu: friction coefficient [-]; margin: angular stability margin [rad].
            beta0: (2,) world polar angles of the left/right contacts [rad].
            u0: contact position across the left pad [m] (a round left tip: the contact's
                arclength from its apex [m]).
            joint_margin: distance kept from every joint limit [rad].
            warm: start from the previous solution (shifted to the new start).
            home_x: where the object centre should end, x [m] (default: where it starts).
            max_rotation: the largest rotation to plan [rad] (e.g. to stop before a sensed
                feature reaches the palm).
            palm_points: (K, 2) outline points relative to ``centre`` [m] (world axes at the
                start), required when built with ``palm_points`` K > 0.

        Returns:
            the :class:`RollingPlan`.

        A failed solve returns a plan with ``success`` False, no rotation and ``stop``
        "solver failed" (the executor turns that into an event).
        """
        q0 = checks.vector("q0", q0, 6, "rad")
        centre = checks.vector("centre", centre, 2, "m")
        beta0 = checks.vector("beta0", beta0, 2, "rad")
        p = np.concatenate(
            [
                [radius, tip_radius, mu, margin],
                centre,
                q0,
                beta0,
                [u0, joint_margin, centre[0] if home_x is None else float(home_x)],
                [min(float(max_rotation), 10.0)],
            ]
        )
        if self.K:
            if palm_points is None:
                raise checks.InvalidParameter(
                    f"palm_points: expected ({self.K}, 2) outline points [m], got None"
                )
            pts = checks.points("palm_points", palm_points, dims=(2,), n=self.K)
            p = np.concatenate([p, pts.ravel()])
        x0 = self.initial_guess(q0, centre, beta0, u0)
        args = {"x0": x0, "p": p, "lbg": self._lbg, "ubg": self._ubg}
        if warm and self._last is not None:
            prev = self._last.reshape(self.N + 1, self._nk).copy()
            shift = np.concatenate([[0.0], centre, q0, beta0, [u0]]) - prev[0]
            prev += shift  # same shape of the trajectory, moved to the new start
            args["x0"] = prev.ravel()
            args["lam_g0"] = self._lam_g
            args["lam_x0"] = self._lam_x
        t0, c0 = time.perf_counter(), time.process_time()
        sol = self._solver(**args)
        cpu = time.process_time() - c0
        ok = bool(self._solver.stats()["success"])
        self.iterations = int(self._solver.stats()["iter_count"])
        dt = time.perf_counter() - t0
        x = np.asarray(sol["x"]).ravel()
        if not ok:
            x = x0
        else:
            self._last = x.copy()
            self._lam_g = np.asarray(sol["lam_g"]).ravel()
            self._lam_x = np.asarray(sol["lam_x"]).ravel()
        V = x.reshape(self.N + 1, self._nk)
        stop = self._binding(np.asarray(sol["lam_g"]).ravel()) if ok else "solver failed"
        return RollingPlan(
            theta=V[:, 0].copy(),
            centre=V[:, 1:3].copy(),
            q=V[:, 3:9].copy(),
            beta=V[:, 9:11].copy(),
            u=V[:, 11].copy(),
            rotation=float(V[-1, 0]),
            success=ok,
            solve_time_s=dt,
            stop=stop,
            solve_cpu_s=cpu,
            iterations=self.iterations,
        )

    def _binding(self, lam: np.ndarray) -> str:
        """Name of the constraint group with the largest multiplier at the last knot."""
        names = (
            ["kinematics"] * 4
            + ["start"] * 0
            + ["left tip" if self.left_round else "flat pad", "rolling", "rolling", "step"]
            + ["joint limit"] * 12
            + ["tip angle" if self.left_round else "pad edge", "tip angle"]
            + ["stability", "stability"]
            + ["palm"] * max(self.K, 1)
            + ["travel", "set down", "rotation cap"]
        )
        last = lam[-len(names) :]
        k = int(np.argmax(np.abs(last)))
        return names[k] if abs(last[k]) > 1e-9 else "none"


__all__ = ["RollingNLP", "RollingPlan"]
