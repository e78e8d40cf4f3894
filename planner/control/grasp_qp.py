"""The per-step grasp QP of the planar hand as one CasADi Function (thesis §2.2.2-2.2.3).

Decision variables: the forces ``f = (f_L, f_R)`` (4,) [N] the two fingertips apply on the
object at their sensed contacts (WCS). Cost (all terms quadratic)::

    w_W |S_rho (G f - W)|^2  +  sum_i (f_i - d_i)^T S_i (f_i - d_i)  +  w_reg |f|^2

(``S_rho = diag(1, 1, 1/rho)``: the torque error divided by the mean object radius ``rho``
so that it weighs like a force at the contacts).

* phase 1 (``grasp = 1``): ``W`` is the object-impedance wrench of eq. (2.7) about the
  estimated object centre, ``G`` the grasp matrix of eq. (2.6); ``S_i = w_int u_i u_i^T`` and
  ``d_i = f_int u_i`` put the commanded internal force along the contact line (``u_L`` from
  the left contact to the right one, ``u_R = -u_L``);
* phases 2/3 (``grasp = 0``): the holding finger tracks ``d = f_int u_hold`` (towards the
  palm contact) plus a tangential impedance about its anchor ``p_hold`` (so the held object
  cannot be dragged along), the exploring finger the fingertip-impedance force (0.3 N normal
  force, §2.3.2), both with ``S = w_track I``.

Constraints: friction cones ``|t_i . f_i| <= mu n_i . f_i`` of the holding/grasping fingers
(eq. 2.1, planar; the exploring finger may slide), ``n_i . f_i >= f_min`` and the joint
torque limits ``|J_h^T f + tau_0| <= tau_max`` (eq. 2.5). The feed-forward ``tau_0`` holds the
fingers' gravity ``g(q)``, their mass times the desired joint acceleration (the "finger mass
feed-forward" of eq. 2.7), and the moments on the distal links (rolling PD, eq. 2.8, for
grasping/holding fingers; orientation impedance for the explorer).

Outputs (column-major CasADi): ``H`` (4, 4), ``c`` (4,), ``A^T`` (4, 12) (so its memory is
``A`` row-major, as DAQP wants), ``b_upper`` (12,), ``b_lower`` (12,), ``tau_0`` (6,),
``J_h^T`` (6, 4) and the diagnostics (17,) of :mod:`planner.control.grasp_layout`. The torques
are ``tau = tau_0 + J_h^T f*``.
"""

from __future__ import annotations

from planner.control.fingertip_impedance import fingertip_force, holding_force, orientation_moment
from planner.control.grasp_kinematics import finger_terms_sx
from planner.control.grasp_layout import (
    DAMPING,
    DAQP_INF,
    N_CON,
    N_DIAG,
    N_PAR,
    N_REF,
    PAR,
    REF,
)
from planner.control.object_impedance import (
    contact_accelerations,
    object_twist_two_contacts,
    object_wrench,
)

SIDES = ("left", "right")


def _unit(cs, vx, vy):
    d = cs.sqrt(vx * vx + vy * vy) + 1e-12
    return vx / d, vy / d


def _finger_qdd(cs, term, sl, acc, alpha, qd):
    """Joint accelerations of one finger for a contact acceleration and tip angular one."""
    J = cs.vertcat(term["J"][:, sl], cs.DM.ones(1, 3))
    rhs = cs.vertcat(acc[0] - term["Jdqd"][0], acc[1] - term["Jdqd"][1], alpha)
    return J.T @ cs.solve(J @ J.T + DAMPING * cs.DM.eye(3), rhs)


def _contacts(cs, terms, geo, qd):
    """Sensed contact points, WCS normals (the tip-frame normals ``geo[4:8]`` rotated by the
    tip angle) and contact-point velocities ``J qd`` of the left and right fingers."""
    pts, nrm, vel = [], [], []
    for k, side in enumerate(SIDES):
        t = terms[side]
        phi = t["phi"]
        ntx, nty = geo[4 + 2 * k], geo[5 + 2 * k]
        nrm.append((cs.cos(phi) * ntx - cs.sin(phi) * nty, cs.sin(phi) * ntx + cs.cos(phi) * nty))
        pts.append((t["p"][0], t["p"][1]))
        v = t["J"] @ qd
        vel.append((v[0], v[1]))
    return pts, nrm, vel


def _object_estimate(cs, r, p, pts, nrm, vel, explore):
    """The object's estimated centre (mean of ``contact + rho * normal`` over the holding and
    grasping contacts), pose, twist, the eq. (2.7) impedance wrench ``W`` (3,) and the grasp
    matrix ``G`` (3, 4) of eq. (2.6) about that centre."""
    wsum, cx, cy = 0, 0, 0
    for k in range(2):
        a = 1 - explore[k]
        cx += a * (pts[k][0] + r["rho"][k] * nrm[k][0])
        cy += a * (pts[k][1] + r["rho"][k] * nrm[k][1])
        wsum += a
    c = (cx / wsum, cy / wsum)
    x_est = (c[0], c[1], r["theta_est"][0])
    xd_est = object_twist_two_contacts(pts[0], pts[1], vel[0], vel[1], c)
    W = object_wrench(
        x_est,
        xd_est,
        r["x_des"],
        r["xd_des"],
        r["xdd_des"],
        p["mass"][0],
        p["inertia"][0],
        p["gravity"],
        p["kp"],
        p["kv"],
    )
    W = cs.vertcat(*W)
    G = cs.SX.zeros(3, 4)
    for k in range(2):
        G[0, 2 * k], G[1, 2 * k + 1] = 1, 1
        G[2, 2 * k] = -(pts[k][1] - c[1])
        G[2, 2 * k + 1] = pts[k][0] - c[0]
    return c, x_est, xd_est, W, G


def _force_targets(cs, r, p, pts, nrm, vel, grasp, explore):
    """Per-finger tracking weights ``S`` (4, 4) and targets ``d`` (4,): the internal force
    along the contact line when grasping; else the holding force towards the palm or the
    exploring fingertip's impedance force (§2.2.3, §2.3.2)."""
    u = _unit(cs, pts[1][0] - pts[0][0], pts[1][1] - pts[0][1])
    f_int = r["f_int"][0]
    S = cs.SX.zeros(4, 4)
    d = cs.SX.zeros(4, 1)
    for k in range(2):
        sl = slice(2 * k, 2 * k + 2)
        uk = cs.vertcat(u[0], u[1]) * (1 - 2 * k)
        hold = _unit(cs, r["palm"][0] - pts[k][0], r["palm"][1] - pts[k][1])
        ftip = fingertip_force(
            pts[k],
            vel[k],
            r["p_des"],
            r["v_des"],
            nrm[k],
            p["f_n_tip"][0],
            p["kp_tip"][0],
            p["kv_tip"][0],
        )
        S[sl, sl] = grasp * p["w_int"][0] * (uk @ uk.T) + (1 - grasp) * p["w_track"][0] * cs.DM.eye(
            2
        )
        fhold = holding_force(
            pts[k], vel[k], r["p_hold"], hold, f_int, p["kp_hold"][0], p["kv_hold"][0],
            p["mu"][0], sqrt=cs.sqrt,
        )  # fmt: skip
        target_other = explore[k] * cs.vertcat(*ftip) + (1 - explore[k]) * cs.vertcat(*fhold)
        d[sl] = grasp * f_int * uk + (1 - grasp) * target_other
    return S, d


def _feed_forward(cs, terms, r, p, qd, c, xd_est, pts, grasp, explore):
    """Feed-forward torques ``tau0`` (6,) [N m] (gravity, finger mass x desired joint
    acceleration, distal moments: rolling PD eq. 2.8 or the explorer's orientation
    impedance) and the hand Jacobian transpose ``J_h^T`` (6, 4) of eq. (2.5)."""
    tau0 = cs.SX.zeros(6, 1)
    acc = contact_accelerations(c, r["xdd_des"], xd_est[2], pts)
    JT = cs.SX.zeros(6, 4)
    for k, side in enumerate(SIDES):
        t = terms[side]
        sl = slice(3 * k, 3 * k + 3)
        a_k = [grasp * acc[k][0], grasp * acc[k][1]]
        qdd = _finger_qdd(cs, t, sl, a_k, grasp * r["xdd_des"][2], qd)
        phid = qd[3 * k] + qd[3 * k + 1] + qd[3 * k + 2]
        m_orient = orientation_moment(t["phi"], phid, r["phi_des"][k], p["k_phi"][0], p["d_phi"][0])
        moment = (1 - explore[k]) * r["m_roll"][k] + explore[k] * m_orient
        tau0[sl] = t["g"][sl] + t["M"][sl, sl] @ qdd + moment
        JT[sl, 2 * k : 2 * k + 2] = t["J"][:, sl].T
    return tau0, JT


def _constraints(cs, p, nrm, explore, tau0, JT):
    """Rows ``bl <= A f <= bu``: friction cones of the holding/grasping fingers (4; eq. 2.1,
    free for the explorer), minimum normal forces (2), joint torque limits (6)."""
    A = cs.SX.zeros(N_CON, 4)
    bu = cs.SX.zeros(N_CON, 1)
    bl = cs.SX.zeros(N_CON, 1)
    mu = p["mu"][0]
    for k in range(2):
        n = nrm[k]
        tvec = (-n[1], n[0])
        on = 1 - explore[k]
        for j, sgn in enumerate((1, -1)):
            row = 2 * k + j
            A[row, 2 * k] = on * (sgn * tvec[0] - mu * n[0])
            A[row, 2 * k + 1] = on * (sgn * tvec[1] - mu * n[1])
            bu[row] = explore[k] * DAQP_INF
            bl[row] = -DAQP_INF
        A[4 + k, 2 * k], A[4 + k, 2 * k + 1] = n[0], n[1]
        bu[4 + k] = DAQP_INF
        bl[4 + k] = p["f_min"][0]
    A[6:12, :] = JT
    bu[6:12] = p["tau_max"][0] - tau0
    bl[6:12] = -p["tau_max"][0] - tau0
    return A, bu, bl


def grasp_qp_function(model, name: str = "hapex_grasp_qp"):
    """Build the CasADi Function of the per-step QP data (see the module docstring).

    Args:
        model: the planar hand's ``pin.Model``.
        name: the Function's name (also the C symbol after code generation).

    Returns:
        ``casadi.Function`` ``(q, qd, geo, ref, par) -> (H, c, AT, bu, bl, tau0, JT, diag)``.
    """
    import casadi as cs

    q, qd = cs.SX.sym("q", 6), cs.SX.sym("qd", 6)
    geo = cs.SX.sym("geo", 8)
    ref, par = cs.SX.sym("ref", N_REF), cs.SX.sym("par", N_PAR)
    r = {k: ref[s] for k, s in REF.items()}
    p = {k: par[s] for k, s in PAR.items()}
    terms = finger_terms_sx(model, q, qd, geo[0:4], p["gravity"])
    grasp, explore = r["flags"][0], (r["flags"][1], r["flags"][2])
    pts, nrm, vel = _contacts(cs, terms, geo, qd)
    c, x_est, xd_est, W, G = _object_estimate(cs, r, p, pts, nrm, vel, explore)
    S, d = _force_targets(cs, r, p, pts, nrm, vel, grasp, explore)
    wW = grasp * p["w_wrench"][0]
    # torque row in force units: divided by the object's radius (errors compare as forces)
    rho = 0.5 * (r["rho"][0] + r["rho"][1])
    Gs = cs.vertcat(G[0:2, :], G[2, :] / rho)
    Ws = cs.vertcat(W[0:2], W[2] / rho)
    Hh = S + wW * (Gs.T @ Gs) + p["w_reg"][0] * cs.DM.eye(4)
    H = 2 * Hh
    cvec = -2 * (S @ d + wW * (Gs.T @ Ws))
    tau0, JT = _feed_forward(cs, terms, r, p, qd, c, xd_est, pts, grasp, explore)
    A, bu, bl = _constraints(cs, p, nrm, explore, tau0, JT)
    diag = cs.vertcat(
        pts[0][0],
        pts[0][1],
        pts[1][0],
        pts[1][1],
        nrm[0][0],
        nrm[0][1],
        nrm[1][0],
        nrm[1][1],
        *x_est,
        *xd_est,
        W,
    )
    assert diag.shape[0] == N_DIAG
    return cs.Function(
        name,
        [q, qd, geo, ref, par],
        [H, cvec, A.T, bu, bl, tau0, JT, diag],
        ["q", "qd", "geo", "ref", "par"],
        ["H", "c", "AT", "bu", "bl", "tau0", "JT", "diag"],
    )


__all__ = ["grasp_qp_function"]
