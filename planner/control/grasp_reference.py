"""Plain reference implementation of the planar grasp control step (numpy + Pinocchio +
qpsolvers): the same step as :class:`planner.control.grasp_step.GraspStep`, written the
obvious way. It is the cross-check of the generated code (tests) and the "naive" column of
``benchmarks/bench_control.py``.
"""

from __future__ import annotations

import numpy as np

from planner.control.fingertip_impedance import fingertip_force, holding_force, orientation_moment
from planner.control.grasp_kinematics import numeric_finger_terms
from planner.control.grasp_layout import DAMPING, N_CON, PAR, REF
from planner.control.object_impedance import (
    contact_accelerations,
    object_twist_two_contacts,
    object_wrench,
)


def _unit(v: np.ndarray) -> np.ndarray:
    return v / (np.linalg.norm(v) + 1e-12)


def reference_step(model, data, q, qd, geo, ref, par, solver: str = "daqp") -> dict:
    """One control step computed with numpy/Pinocchio and ``qpsolvers.solve_qp``.

    Args:
        model, data: the hand's ``pin.Model`` and ``pin.Data``.
        q, qd, geo, ref, par: the step inputs (layout of :mod:`planner.control.grasp_layout`).
        solver: the qpsolvers backend.

    Returns:
        dict with ``tau`` (6,) [N m], ``forces`` (4,) [N], ``H``, ``c``, ``A``, ``bu``, ``bl``.
    """
    import qpsolvers

    r = {k: ref[s] for k, s in REF.items()}
    p = {k: par[s] for k, s in PAR.items()}
    T = numeric_finger_terms(model, data, q, qd, geo[:4], p["gravity"])
    grasp, explore = r["flags"][0], r["flags"][1:3]
    pts, nrm, vel = _contacts(T, geo, qd)
    centre, xd_est, W, G = _object_terms(r, p, pts, nrm, vel, explore)
    S, d = _targets(r, p, pts, nrm, vel, grasp, explore)
    wW = grasp * p["w_wrench"][0]
    scale = np.array([1.0, 1.0, 2.0 / (r["rho"][0] + r["rho"][1])])
    Gs, Ws = G * scale[:, None], W * scale
    H = 2 * (S + wW * Gs.T @ Gs + p["w_reg"][0] * np.eye(4))
    c = -2 * (S @ d + wW * Gs.T @ Ws)
    tau0, JT = _feed_forward(T, r, p, qd, centre, xd_est, pts, grasp, explore)
    Gin, hin = _inequalities(p, nrm, explore, tau0, JT)
    f = qpsolvers.solve_qp(H, c, Gin, hin, solver=solver)
    ok = f is not None
    f = f if ok else np.zeros(4)
    assert Gin.shape[0] <= 2 * N_CON
    return {"tau": tau0 + JT @ f, "forces": f, "H": H, "c": c, "ok": ok, "wrench": W}


def _contacts(T, geo, qd):
    """Contact points, WCS normals and contact velocities of the left and right fingers."""
    pts, nrm, vel = [], [], []
    for k, side in enumerate(("left", "right")):
        phi = T[side]["phi"]
        c, s = np.cos(phi), np.sin(phi)
        nt = geo[4 + 2 * k : 6 + 2 * k]
        nrm.append(np.array([c * nt[0] - s * nt[1], s * nt[0] + c * nt[1]]))
        pts.append(T[side]["p"])
        vel.append(T[side]["J"] @ qd)
    return pts, nrm, vel


def _object_terms(r, p, pts, nrm, vel, explore):
    """Estimated object centre [m] and twist, the eq. (2.7) wrench and the grasp matrix."""
    a = 1.0 - explore
    centre = sum(a[k] * (pts[k] + r["rho"][k] * nrm[k]) for k in range(2)) / a.sum()
    x_est = np.array([centre[0], centre[1], r["theta_est"][0]])
    xd_est = np.array(object_twist_two_contacts(pts[0], pts[1], vel[0], vel[1], centre))
    W = np.array(
        object_wrench(
            x_est, xd_est, r["x_des"], r["xd_des"], r["xdd_des"], p["mass"][0],
            p["inertia"][0], p["gravity"], p["kp"], p["kv"],
        )
    )  # fmt: skip
    rel = [pt - centre for pt in pts]
    G = np.array([[1, 0, 1, 0], [0, 1, 0, 1], [-rel[0][1], rel[0][0], -rel[1][1], rel[1][0]]])
    return centre, xd_est, W, G


def _targets(r, p, pts, nrm, vel, grasp, explore):
    """Tracking weights ``S`` (4, 4) and force targets ``d`` (4,) [N] of the two fingers."""
    u = _unit(pts[1] - pts[0])
    S, d = np.zeros((4, 4)), np.zeros(4)
    f_int = r["f_int"][0]
    for k in range(2):
        sl = slice(2 * k, 2 * k + 2)
        uk = u * (1 - 2 * k)
        if grasp:
            S[sl, sl] = p["w_int"][0] * np.outer(uk, uk)
            d[sl] = f_int * uk
        else:
            S[sl, sl] = p["w_track"][0] * np.eye(2)
            if explore[k]:
                d[sl] = fingertip_force(
                    pts[k], vel[k], r["p_des"], r["v_des"], nrm[k], p["f_n_tip"][0],
                    p["kp_tip"][0], p["kv_tip"][0],
                )  # fmt: skip
            else:
                d[sl] = holding_force(
                    pts[k], vel[k], r["p_hold"], _unit(r["palm"] - pts[k]), f_int,
                    p["kp_hold"][0], p["kv_hold"][0], p["mu"][0],
                )  # fmt: skip
    return S, d


def _feed_forward(T, r, p, qd, centre, xd_est, pts, grasp, explore):
    """Feed-forward torques ``tau0`` (6,) [N m] and the hand Jacobian transpose (6, 4)."""
    acc = contact_accelerations(centre, r["xdd_des"], xd_est[2], pts)
    M, gq = T["hand"]["M"], T["hand"]["g"]
    tau0, JT = np.zeros(6), np.zeros((6, 4))
    for k, side in enumerate(("left", "right")):
        sl = slice(3 * k, 3 * k + 3)
        J = T[side]["J"][:, sl]
        Ja = np.vstack([J, np.ones((1, 3))])
        rhs = np.array(
            [grasp * acc[k][0] - T[side]["Jdqd"][0], grasp * acc[k][1] - T[side]["Jdqd"][1],
             grasp * r["xdd_des"][2]]
        )  # fmt: skip
        qdd = Ja.T @ np.linalg.solve(Ja @ Ja.T + DAMPING * np.eye(3), rhs)
        phid = qd[sl].sum()
        m_or = orientation_moment(
            T[side]["phi"], phid, r["phi_des"][k], p["k_phi"][0], p["d_phi"][0]
        )
        moment = r["m_roll"][k] if not explore[k] else m_or
        tau0[sl] = gq[sl] + M[sl, sl] @ qdd + moment
        JT[sl, 2 * k : 2 * k + 2] = J.T
    return tau0, JT


def _inequalities(p, nrm, explore, tau0, JT):
    """``Gin f <= hin``: friction cones of the non-exploring fingers, minimum normal
    forces, joint torque limits."""
    rows, ub = [], []
    mu = p["mu"][0]
    for k in range(2):
        if explore[k]:
            continue
        n, t = nrm[k], np.array([-nrm[k][1], nrm[k][0]])
        for sgn in (1, -1):
            row = np.zeros(4)
            row[2 * k : 2 * k + 2] = sgn * t - mu * n
            rows.append(row)
            ub.append(0.0)
    for k in range(2):
        row = np.zeros(4)
        row[2 * k : 2 * k + 2] = -nrm[k]
        rows.append(row)
        ub.append(-p["f_min"][0])
    tmax = p["tau_max"][0]
    Gin = np.vstack([np.array(rows), JT, -JT])
    hin = np.concatenate([ub, tmax - tau0, tmax + tau0])
    return Gin, hin


__all__ = ["reference_step"]
