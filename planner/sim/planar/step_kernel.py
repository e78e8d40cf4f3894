"""Compiled hot path of the planar step: hand dynamics, contact rows, the LCP, the update.

:func:`contact_step` does in ONE numba call what :func:`planner.sim.planar.stepper.step`
does in Python after the contact search (same equations, same order, same Lemke solver;
tested against it to ~1e-12 on random states): the hand's ``M(q)`` and bias
``h(q, qd) = C(q, qd) qd + g(q)``, the normal/tangent rows of every candidate, the joint-limit
rows, the Stewart-Trinkle LCP, Lemke with its verified retries
(:func:`planner.sim.lcp.lemke_verified`) and the semi-implicit update. The only
Python left around it is the contact search and the packing of its candidates.

**Hand dynamics in closed form** (:func:`hand_dynamics`): each finger is a planar serial
chain of revolute z joints with identity joint rotations (the Pinocchio model of
:mod:`robots.planar_hand.model`; :func:`hand_parameters` checks that). With the absolute
angles ``s_k = q_1 + ... + q_k``, joint origins ``o_k = o_{k-1} + R(s_{k-1}) t_k`` and
centres of mass ``c_k = o_k + R(s_k) l_k`` (``t_k`` joint placement, ``l_k`` lever), the
COM Jacobian columns are ``z x (c_k - o_j)`` (j <= k) and

.. math::

    M = \\sum_k m_k J_{v,k}^T J_{v,k} + I_k J_{\\omega,k}^T J_{\\omega,k}, \\qquad
    h = \\sum_k m_k J_{v,k}^T (a_k - g), \\quad
    a_k = -\\sum_{i<k} \\dot s_i^2 R(s_i) t_{i+1} - \\dot s_k^2 R(s_k) l_k

(``a_k``: the COM acceleration at ``qdd = 0``; in the plane the angular velocity-product
and gyroscopic terms vanish). This is the Lagrangian of the chain, equal to Pinocchio's
CRBA/RNEA to ~1e-15 (``tests/test_sim_hand.py``) and ~20x cheaper than two Pinocchio calls
from Python.
"""

from __future__ import annotations

import numpy as np

from planner.errors import InvalidParameter
from planner.jit import njit
from planner.sim.lcp import _residual, lemke_verified
from planner.sim.planar.geometry_kernel import contacts_into

__all__ = [
    "contact_step",
    "full_step",
    "project_positions",
    "hand_dynamics",
    "hand_kinematics",
    "hand_parameters",
]

FIXED, FREE, TIP = 0, 1, 2


def hand_parameters(model, tip_lengths) -> np.ndarray:
    """Pack a planar hand's Pinocchio model for the kernels.

    Args:
        model: the hand's ``pinocchio.Model`` (6 revolute-z joints, two chains of three).
        tip_lengths: (2,) distance of each fingertip point along +y of the distal link [m].

    Returns:
        (2, 4, 6) array: rows 0-2 per joint ``tx, ty, cx, cy, m, Izz`` (placement in the
        parent joint's frame [m], COM lever [m], mass [kg], inertia about the COM
        [kg m^2]); row 3 ``0, L, 0, 0, 0, 0`` (the fingertip point in the distal frame).
    """
    P = np.zeros((2, 4, 6))
    if model.nv != 6 or list(model.parents) != [0, 0, 1, 2, 0, 4, 5]:
        raise InvalidParameter("hand_parameters: expected two chains of three joints")
    for f in range(2):
        for k in range(3):
            j = 1 + 3 * f + k
            if model.joints[j].shortname() != "JointModelRZ":
                raise InvalidParameter(f"joint {j} is not a revolute z joint")
            pl, inertia = model.jointPlacements[j], model.inertias[j]
            if not np.allclose(pl.rotation, np.eye(3), atol=0.0) or abs(pl.translation[2]) > 0:
                raise InvalidParameter(f"joint {j}: placement is not a planar translation")
            lev = inertia.lever
            P[f, k] = (
                pl.translation[0],
                pl.translation[1],
                lev[0],
                lev[1],
                inertia.mass,
                inertia.inertia[2, 2],
            )
        P[f, 3, 1] = float(tip_lengths[f])
    return P


@njit(cache=True)
def hand_kinematics(q, P, joints, tips):
    """Joint origins ``joints`` (2, 3, 2) [m] and fingertip frames ``tips`` (2, 3) (x, y, phi)."""
    for f in range(2):
        ox, oy, s = 0.0, 0.0, 0.0
        for k in range(4):
            c, sn = np.cos(s), np.sin(s)
            ox, oy = ox + c * P[f, k, 0] - sn * P[f, k, 1], oy + sn * P[f, k, 0] + c * P[f, k, 1]
            if k < 3:
                joints[f, k, 0], joints[f, k, 1] = ox, oy
                s += q[3 * f + k]
        tips[f, 0], tips[f, 1], tips[f, 2] = ox, oy, s


@njit(cache=True)
def hand_dynamics(q, qd, gx, gy, P, M, hb):
    """Joint-space inertia ``M`` (6, 6) [kg m^2] and bias ``hb`` (6,) [N m] (see module)."""
    M[:, :] = 0.0
    hb[:] = 0.0
    o = np.zeros((3, 2))
    for f in range(2):
        ox, oy, s, sd = 0.0, 0.0, 0.0, 0.0
        ax, ay = 0.0, 0.0  # velocity-product acceleration of the current joint origin
        b = 3 * f
        for k in range(3):
            c, sn = np.cos(s), np.sin(s)
            tx, ty = c * P[f, k, 0] - sn * P[f, k, 1], sn * P[f, k, 0] + c * P[f, k, 1]
            ox, oy = ox + tx, oy + ty
            ax, ay = ax - sd * sd * tx, ay - sd * sd * ty
            o[k, 0], o[k, 1] = ox, oy
            s += q[b + k]
            sd += qd[b + k]
            c, sn = np.cos(s), np.sin(s)
            lx, ly = c * P[f, k, 2] - sn * P[f, k, 3], sn * P[f, k, 2] + c * P[f, k, 3]
            cx, cy = ox + lx, oy + ly
            m, izz = P[f, k, 4], P[f, k, 5]
            acx, acy = ax - sd * sd * lx - gx, ay - sd * sd * ly - gy
            for i in range(k + 1):
                jix, jiy = -(cy - o[i, 1]), cx - o[i, 0]
                hb[b + i] += m * (jix * acx + jiy * acy)
                for j in range(i, k + 1):
                    jjx, jjy = -(cy - o[j, 1]), cx - o[j, 0]
                    M[b + i, b + j] += m * (jix * jjx + jiy * jjy) + izz
        for i in range(3):
            for j in range(i + 1, 3):
                M[b + j, b + i] = M[b + i, b + j]


@njit(cache=True)
def _inv3_into(A, r0, out):
    """Inverse of the symmetric 3x3 block ``A[r0:r0+3, r0:r0+3]`` into the same block of out."""
    a, b_, c = A[r0, r0], A[r0, r0 + 1], A[r0, r0 + 2]
    d, e, f = A[r0 + 1, r0], A[r0 + 1, r0 + 1], A[r0 + 1, r0 + 2]
    g, h, i = A[r0 + 2, r0], A[r0 + 2, r0 + 1], A[r0 + 2, r0 + 2]
    co00, co01, co02 = e * i - f * h, -(d * i - f * g), d * h - e * g
    det = a * co00 + b_ * co01 + c * co02
    out[r0, r0] = co00 / det
    out[r0, r0 + 1] = -(b_ * i - c * h) / det
    out[r0, r0 + 2] = (b_ * f - c * e) / det
    out[r0 + 1, r0] = co01 / det
    out[r0 + 1, r0 + 1] = (a * i - c * g) / det
    out[r0 + 1, r0 + 2] = -(a * f - c * d) / det
    out[r0 + 2, r0] = co02 / det
    out[r0 + 2, r0 + 1] = -(a * h - b_ * g) / det
    out[r0 + 2, r0 + 2] = (a * e - b_ * d) / det


@njit(cache=True)
def _add_row(row, kind, idx, nfree, x, joints, px, py, dx, dy, sign):
    """Add ``sign * d . (velocity of the body's material point p)`` coefficients to row."""
    if kind == FREE:
        k = 3 * idx
        row[k] += sign * dx
        row[k + 1] += sign * dy
        row[k + 2] += sign * (-dx * (py - x[idx, 1]) + dy * (px - x[idx, 0]))
    elif kind == TIP:
        off = 3 * nfree + 3 * idx
        for k in range(3):
            jx, jy = joints[idx, k, 0], joints[idx, k, 1]
            row[off + k] += sign * (-dx * (py - jy) + dy * (px - jx))


@njit(cache=True, inline="always")
def _inverse_mass(mass, inertia, has_hand, q, qd, gx, gy, P, nfree):
    """The block-diagonal inverse mass ``Minv`` (nv, nv) of the free bodies and the hand,
    and the hand's bias ``hb`` (6,) at ``(q, qd)`` (zeros without a hand)."""
    nv = 3 * nfree + (6 if has_hand else 0)
    Minv = np.zeros((nv, nv))
    for b in range(nfree):
        k = 3 * b
        Minv[k, k] = 1.0 / mass[b]
        Minv[k + 1, k + 1] = 1.0 / mass[b]
        Minv[k + 2, k + 2] = 1.0 / inertia[b]
    hb = np.zeros(6)
    if has_hand:
        M = np.zeros((6, 6))
        hand_dynamics(q, qd, gx, gy, P, M, hb)
        Mi = np.zeros((6, 6))
        _inv3_into(M, 0, Mi)
        _inv3_into(M, 3, Mi)
        o = 3 * nfree
        for i in range(6):
            for j in range(6):
                Minv[o + i, o + j] = Mi[i, j]
    return Minv, hb


@njit(cache=True, inline="always")
def _limit_rows(q, qd, h, limits):
    """Joint-limit rows: the joints within ``max(0.01, 2 |qd| h)`` [rad] of a limit.

    Returns ``(n, joint, gap, side)``: the first n entries of the (12,) arrays are the
    joint, its gap to the limit [rad] and the row's sign (+1 lower, -1 upper)."""
    n = 0
    joint = np.zeros(12, np.int64)
    gap = np.zeros(12)
    side = np.zeros(12)
    for k in range(6):
        near = max(0.01, 2.0 * abs(qd[k]) * h)
        g0, g1 = q[k] - limits[k, 0], limits[k, 1] - q[k]
        if g0 < near:
            joint[n], gap[n], side[n] = k, g0, 1.0
            n += 1
        if g1 < near:
            joint[n], gap[n], side[n] = k, g1, -1.0
            n += 1
    return n, joint, gap, side


@njit(cache=True, inline="always")
def _contact_rows(cand, kind, index, mu_body, nfree, x, joints, nlim, lim_joint, lim_side, nv):
    """The LCP's velocity rows: ``R`` (nn + 2 nf, nv) = normal rows of the candidates, the
    joint-limit rows, then +/- the tangent rows of the nf frictional candidates ``fr``;
    ``T`` (nc, nv) the tangent rows; ``mu`` (nc,) each candidate's friction."""
    nc = cand.shape[0]
    mu = np.zeros(nc)
    nf = 0
    for r in range(nc):
        mu[r] = max(mu_body[int(cand[r, 0])], mu_body[int(cand[r, 1])])
        if mu[r] > 0.0:
            nf += 1
    nn = nc + nlim
    R = np.zeros((nn + 2 * nf, nv))
    T = np.zeros((nc, nv))
    fr = np.zeros(nf, np.int64)
    kf = 0
    for r in range(nc):
        i, j = int(cand[r, 0]), int(cand[r, 1])
        pax, pay, pbx, pby = cand[r, 3], cand[r, 4], cand[r, 5], cand[r, 6]
        nx, ny = cand[r, 7], cand[r, 8]
        ia, ib = index[i], index[j]
        _add_row(R[r], kind[i], ia, nfree, x, joints, pax, pay, nx, ny, 1.0)
        _add_row(R[r], kind[j], ib, nfree, x, joints, pbx, pby, nx, ny, -1.0)
        _add_row(T[r], kind[i], ia, nfree, x, joints, pax, pay, -ny, nx, 1.0)
        _add_row(T[r], kind[j], ib, nfree, x, joints, pbx, pby, -ny, nx, -1.0)
        if mu[r] > 0.0:
            fr[kf] = r
            kf += 1
    for m in range(nlim):
        R[nc + m, 3 * nfree + lim_joint[m]] = lim_side[m]
    for k in range(nf):
        for c in range(nv):
            R[nn + k, c] = T[fr[k], c]
            R[nn + nf + k, c] = -T[fr[k], c]
    return R, T, fr, mu


#: the kinetic energy the impulses of a step may add, in units of the energy that gives
#: each penetrating row's effective mass its gap-closing speed ``-phi / h`` (stepper's
#: "Energy"); above it the answer is a wedged one and the step closes gaps only
ENERGY_ALLOWANCE = 100.0


@njit(cache=True)
def gains_energy(G, Rv, z, phi, nr, nn, h):
    """Whether impulses ``z[:nr]`` on rows with Delassus matrix ``G`` (nr, nr) and free
    velocities ``Rv`` (nr,) add more kinetic energy than the gap terms of the first ``nn``
    rows (gaps ``phi`` [m or rad], step ``h`` [s]) can: the gain
    ``z.Rv + z.G.z / 2`` [J] (= ``(nu+ M nu+ - v M v) / 2`` with ``nu+ = v + M^-1 R^T z``)
    against :data:`ENERGY_ALLOWANCE` times ``sum (phi_r / h)^2 / (2 G_rr)`` over the
    penetrating rows, plus round-off (1e-9 of the terms' magnitudes)."""
    gain, scale = 0.0, 0.0
    for r in range(nr):
        gz = 0.0
        for c in range(nr):
            gz += G[r, c] * z[c]
        a, b = z[r] * Rv[r], 0.5 * z[r] * gz
        gain += a + b
        scale += abs(a) + abs(b)
    allow = 0.0
    for r in range(nn):
        if phi[r] < 0.0 and G[r, r] > 0.0:
            allow += 0.5 * (phi[r] / h) ** 2 / G[r, r]
    return gain > ENERGY_ALLOWANCE * allow + 1e-9 * scale


@njit(cache=True, inline="always")
def _impulse_lcp(R, Minv, v_free, phi, fr, mu, nn, h, covers):
    """Solve the Stewart-Trinkle LCP of the step (normal, limit and friction-edge rows of
    ``R``, the friction-cone slack rows): ``(status, z, MRt)``; a failed Lemke path on the
    stabilized ``b + phi/h``, or an answer that adds energy (:func:`gains_energy`), is
    retried closing gaps only (``b + max(phi, 0)/h``)."""
    nf = fr.shape[0]
    nr = R.shape[0]
    MRt = Minv @ R.T
    G = R @ MRt
    m_all = nn + 3 * nf
    A = np.zeros((m_all, m_all))
    A[:nr, :nr] = G
    for k in range(nf):
        e = nr + k
        A[nn + k, e] = 1.0
        A[nn + nf + k, e] = 1.0
        A[e, fr[k]] = mu[fr[k]]
        A[e, nn + k] = -1.0
        A[e, nn + nf + k] = -1.0
    b = np.zeros(m_all)
    Rv = R @ v_free
    for r in range(nr):
        b[r] = Rv[r]
    bq = b.copy()
    for r in range(nn):
        bq[r] += phi[r] / h
    it = 50 * m_all + 10
    z, status, _ = lemke_verified(A, bq, covers, it, 1e-9)
    if status == 0 and gains_energy(G, Rv, z, phi, nr, nn, h):
        status = 1  # a spurious (wedged) answer: close gaps only (stepper's "Energy")
    if status != 0:  # a jam with sub-tolerance penetration: close gaps only
        for r in range(nn):
            b[r] += max(phi[r], 0.0) / h
        z, status, _ = lemke_verified(A, b, covers, it, 1e-9)
    return status, z, MRt


@njit(cache=True)
def contact_step(
    h, gx, gy, cand, kind, index, mu_body, x, v, mass, inertia, has_hand, q, qd, tau, P,
    limits, covers,
):  # fmt: skip
    """One step after the contact search (see :func:`planner.sim.planar.stepper.step`).

    Args:
        h: step [s]; gx, gy: gravity [m/s^2].
        cand: (nc, 10) candidates ``i, j, gap, pax, pay, pbx, pby, nx, ny, curvature``.
        kind, index, mu_body: (nbodies,) body kind, state row / finger, friction.
        x, v: (nfree, 3) centre-of-mass poses / velocities (updated in place on success).
        mass, inertia: (nfree,) [kg], [kg m^2].
        has_hand: whether q, qd, tau (6,) are the hand's (updated in place on success).
        P: (2, 4, 6) :func:`hand_parameters`; limits: (6, 2) joint limits [rad].
        covers: Lemke's retry covering vectors.

    Returns:
        ``(status, pn, pt, slip, mu, lim_joint, lim_impulse)``; status 0 ok, otherwise the
        LCP had no verified answer and nothing was updated.
    """
    nc = cand.shape[0]
    nfree = x.shape[0]
    Minv, hb = _inverse_mass(mass, inertia, has_hand, q, qd, gx, gy, P, nfree)
    nv = Minv.shape[0]
    f = np.zeros(nv)
    nu = np.zeros(nv)
    for b in range(nfree):
        k = 3 * b
        f[k], f[k + 1] = mass[b] * gx, mass[b] * gy
        nu[k], nu[k + 1], nu[k + 2] = v[b, 0], v[b, 1], v[b, 2]
    joints = np.zeros((2, 3, 2))
    nlim, lim_joint, lim_phi, lim_side = 0, np.zeros(12, np.int64), np.zeros(12), np.zeros(12)
    if has_hand:
        o = 3 * nfree
        for i in range(6):
            f[o + i] = tau[i] - hb[i]
            nu[o + i] = qd[i]
        tips = np.zeros((2, 3))
        hand_kinematics(q, P, joints, tips)
        nlim, lim_joint, lim_phi, lim_side = _limit_rows(q, qd, h, limits)
    v_free = nu + h * (Minv @ f)
    R, T, fr, mu = _contact_rows(
        cand, kind, index, mu_body, nfree, x, joints, nlim, lim_joint, lim_side, nv
    )
    nf, nn = fr.shape[0], nc + nlim
    pn = np.zeros(nc)
    pt = np.zeros(nc)
    pl = np.zeros(nlim)
    if nn + 2 * nf > 0:
        phi = np.zeros(nn)
        for r in range(nc):
            phi[r] = cand[r, 2]
        for m in range(nlim):
            phi[nc + m] = lim_phi[m]
        status, z, MRt = _impulse_lcp(R, Minv, v_free, phi, fr, mu, nn, h, covers)
        if status != 0:
            return status, pn, pt, pt, mu, lim_joint[:nlim], pl
        for r in range(nc):
            pn[r] = z[r]
        for m in range(nlim):
            pl[m] = z[nc + m]
        for k in range(nf):
            pt[fr[k]] = z[nn + k] - z[nn + nf + k]
        nu_new = v_free + MRt @ z[: nn + 2 * nf]
    else:
        nu_new = v_free
    slip = T @ nu_new
    for b in range(nfree):
        for c in range(3):
            v[b, c] = nu_new[3 * b + c]
            x[b, c] += h * v[b, c]
    if has_hand:
        for i in range(6):
            qd[i] = nu_new[3 * nfree + i]
            q[i] += h * qd[i]
    return 0, pn, pt, slip, mu, lim_joint[:nlim], pl


@njit(cache=True)
def project_positions(
    cand, kind, index, x, mass, inertia, has_hand, q, P, limits, covers,
):  # fmt: skip
    """Post-stabilization of :func:`planner.sim.planar.stepper._project`, compiled: the
    minimum-kinetic-metric displacement ``dq = M^-1 N^T z`` with ``z`` the LCP
    ``(N M^-1 N^T, phi)`` over the candidates' normal rows and the joint-limit rows within
    0.01 rad (``phi`` their gaps); a failed Lemke path is retried on ``G + eps I``
    (eps = 1e-9 max(1, max diag G)) and accepted when its residual on ``G`` is <= 1e-6.
    ``x`` (nfree, 3) and ``q`` (6,) are moved in place. Returns False (nothing moved)
    when no verified answer exists (the Python step then raises)."""
    nc = cand.shape[0]
    nfree = x.shape[0]
    zero = np.zeros(6)
    Minv, _ = _inverse_mass(mass, inertia, has_hand, q, zero, 0.0, 0.0, P, nfree)
    nv = Minv.shape[0]
    joints = np.zeros((2, 3, 2))
    nlim, lim_rows, lim_phi, lim_side = 0, np.zeros(12, np.int64), np.zeros(12), np.zeros(12)
    if has_hand:
        tips = np.zeros((2, 3))
        hand_kinematics(q, P, joints, tips)
        nlim, lim_rows, lim_phi, lim_side = _limit_rows(q, zero, 0.0, limits)
    nn = nc + nlim
    N = np.zeros((nn, nv))
    phi = np.zeros(nn)
    for r in range(nc):
        i, j = int(cand[r, 0]), int(cand[r, 1])
        nx, ny = cand[r, 7], cand[r, 8]
        _add_row(N[r], kind[i], index[i], nfree, x, joints, cand[r, 3], cand[r, 4], nx, ny, 1.0)
        _add_row(N[r], kind[j], index[j], nfree, x, joints, cand[r, 5], cand[r, 6], nx, ny, -1.0)
        phi[r] = cand[r, 2]
    for m in range(nlim):
        N[nc + m, 3 * nfree + lim_rows[m]] = lim_side[m]
        phi[nc + m] = lim_phi[m]
    MNt = Minv @ N.T
    G = N @ MNt
    it = 50 * nn + 10
    z, status, _ = lemke_verified(G, phi, covers, it, 1e-9)
    if status != 0:
        big = 1.0
        for r in range(nn):
            big = max(big, abs(G[r, r]))
        Gr = G.copy()
        for r in range(nn):
            Gr[r, r] += 1e-9 * big
        z, status, _ = lemke_verified(Gr, phi, covers, it, 1e-9)
        if status != 0 or _residual(G, phi, z) > 1e-6:
            return False
    dq = MNt @ z
    for b in range(nfree):
        for c in range(3):
            x[b, c] += dq[3 * b + c]
    if has_hand:
        for i in range(6):
            q[i] += dq[3 * nfree + i]
    return True


@njit(cache=True)
def _search(h, margin, F, I, pairs, poses, kind, index, x, v, has_hand, q, qd, P, out, counts):  # noqa: E741
    """Kinematics and the contact search of :func:`full_step`: fills ``out`` and ``counts``
    and returns the candidate count (larger than ``out`` when it is too small)."""
    nb = kind.shape[0]
    joints = np.zeros((2, 3, 2))
    tips = np.zeros((2, 3))
    tip_speed = 0.0
    if has_hand:
        hand_kinematics(q, P, joints, tips)
        for i in range(6):
            tip_speed = max(tip_speed, abs(qd[i]))
        tip_speed *= 0.25  # links + tip radius < 0.25 m
    reach = np.zeros(nb)
    for b in range(nb):
        if kind[b] == FREE:
            k = index[b]
            poses[b, 0], poses[b, 1], poses[b, 2] = x[k, 0], x[k, 1], x[k, 2]
            sp = np.hypot(v[k, 0], v[k, 1]) + abs(v[k, 2]) * F[b]
            reach[b] = 2.0 * h * sp
        elif kind[b] == TIP:
            k = index[b]
            poses[b, 0], poses[b, 1], poses[b, 2] = tips[k, 0], tips[k, 1], tips[k, 2]
            reach[b] = 2.0 * h * tip_speed
    margins = np.empty(pairs.shape[0])
    for k in range(pairs.shape[0]):
        margins[k] = margin + reach[pairs[k, 0]] + reach[pairs[k, 1]]
    return contacts_into(F, I, poses, pairs, margins, out, counts)


@njit(cache=True)
def full_step(
    h, gx, gy, margin, proj_tol, F, I, pairs, poses, kind, index, mu_body, x, v, mass,
    inertia, has_hand, q, qd, tau, P, limits, covers, out, counts,
):  # noqa: E741  # fmt: skip
    """The whole step in one call: kinematics, contact search, :func:`contact_step`.

    The contact search is :func:`planner.sim.planar.geometry_kernel.contacts_into` over the
    packed outlines ``F, I`` and body ``pairs``; ``poses`` (nbodies, 3) holds the fixed
    bodies' poses (the others are written here), ``out`` (cap, 10) and ``counts`` (npairs,)
    are its buffers. The margin of a pair is ``margin`` plus twice the distance each of its
    bodies can move in the step (as :func:`planner.sim.planar.stepper.find_contacts`).

    Returns:
        ``(status, n, pn, pt, slip, mu, lim_joint, lim_impulse)``: status 0 ok (the n
        candidates are ``out[:n]``), 1/2 no verified LCP answer, 3 the position projection
        (:func:`project_positions`, done here when a gap is below ``-proj_tol``) had no
        verified answer, 4 ``out`` too small (n rows needed), 5 a pair needs the Python
        geometry; nothing is updated unless the status is 0.
    """
    e0, e1 = np.zeros(0), np.zeros(0, np.int64)
    # a projected step keeps the positions it started from: nothing is updated unless the
    # step succeeds
    x_bak, q_bak = np.empty((0, 3)), np.empty(0)
    projected = False
    st, n = 0, 0
    for attempt in range(2):
        n = _search(h, margin, F, I, pairs, poses, kind, index, x, v, has_hand, q, qd, P, out,
                    counts)  # fmt: skip
        if n > out.shape[0]:
            st = 4
            break
        for k in range(pairs.shape[0]):
            if counts[k] < 0:
                st = 5
        if st != 0:
            break
        deep = False
        for r in range(n):
            if out[r, 2] < -proj_tol:
                deep = True
        if not deep or attempt == 1:  # the Python step projects once too
            break
        x_bak, q_bak = x.copy(), q.copy()
        projected = True
        if not project_positions(out[:n], kind, index, x, mass, inertia, has_hand, q, P,
                                 limits, covers):  # fmt: skip
            st = 3
            break
    if st == 0:
        st, pn, pt, slip, mu, lj, lp = contact_step(
            h, gx, gy, out[:n], kind, index, mu_body, x, v, mass, inertia, has_hand, q, qd,
            tau, P, limits, covers,
        )  # fmt: skip
        if st == 0:
            return st, n, pn, pt, slip, mu, lj, lp
    if projected:
        x[:] = x_bak
        q[:] = q_bak
    return st, n, e0, e0, e0, e0, e1, e0
