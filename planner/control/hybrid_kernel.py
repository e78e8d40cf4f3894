"""The compiled control step of the hybrid force/velocity law (numba; thesis §4.3, App. C).

One call does everything the 1 kHz interrupt of App. C.2.2 does: OWTS voltages -> contact
normal in the TCS (eqs. C.1-C.3), 3GM forward kinematics and Jacobian (eqs. C.4-C.9 with the
corrected C.8, see :mod:`robots.three_gm.closed_form`), the corrected TCS rotation and the
filtered normal (eqs. 4.1-4.2), the SCS (eq. 4.3 corrected, with the singularity switch), the
desired-velocity ramp and desired position (eq. 4.9), the PD force parallel to the surface
(eqs. 4.7, 4.8, 4.10, 4.11), the open-loop normal force (4.12-4.13), gravity compensation and
``τ = Jᵀ f`` within the torque limits (C.10). :mod:`planner.control.hybrid_reference` is the
same law in plain numpy; the tests compare the two.

Layout of the flat arrays (indices are module constants so the Python side never guesses):

* ``state`` (12,): filtered normal n_W (0:3), desired contact point x_des (3:6), ramped
  desired velocity v_cmd (6:9), previous tangential velocity (9:12).
* ``par`` (``NPAR``,): see ``P_*``.
* ``out`` (``NOUT``,): τ (0:3), contact point x (3:6), fingertip centre (6:9), ẋ (9:12),
  contact flag (12), saturation flag (13), OWTS intensity (14), alternative-SCS flag (15),
  γ1 (16), singular flag (17), normal-force command after saturation (18); the parts the
  variants of :mod:`planner.control.hybrid_variants` build on: the Jacobian ``J`` row-major
  (19:28), gravity torques τ_g of θ1, θ2 (28:30), the Cartesian force ``f`` before
  saturation (30:33), the SCS axes x_S (33:36) and y_S (36:39).

:func:`hybrid_step` presses with ``par[P_FN]`` (open loop, eq. 4.12);
:func:`hybrid_step_closed_loop` first runs a PI loop on the sensed normal force
(:func:`normal_force_pi`) and presses with its command.
"""

from __future__ import annotations

import math

import numpy as np

from planner.jit import njit

# parameter indices
P_L1, P_L2, P_L3, P_L4, P_L5, P_H1, P_H2, P_H3 = range(8)
P_KP, P_KV, P_FN, P_ALPHA, P_RATE, P_RAMP, P_RTIP = range(8, 15)
P_OWTS_HALF, P_OWTS_K, P_OWTS_XO, P_OWTS_YO, P_OWTS_THR = range(15, 20)
P_G1, P_G5, P_G2, P_G3, P_GT, P_GC11 = range(20, 26)  # m_i g [N] of links 1, 5, 2, 3, tip; M g
P_TAU1, P_TAU2, P_TAU3 = range(26, 29)
P_SWITCH, P_EMAX = 29, 30
#: centre of mass (x along the link, y in the plane) of the bodies on theta1, gamma1, theta2,
#: gamma2 in their joint frames [m]
P_C1X, P_C1Y, P_C5X, P_C5Y, P_C2X, P_C2Y, P_C3X, P_C3Y = range(31, 39)
NPAR = 39
NOUT = 39
O_J, O_TG, O_F, O_XS, O_YS = 19, 28, 30, 33, 36
#: closed-loop normal force: gains and state of :func:`normal_force_pi` (``fpar``, ``fstate``)
F_KP, F_KI, F_IMAX, F_FMAX = range(4)
NFPAR = 4
S_INT, S_MEAS = range(2)
NFSTATE = 2


@njit(cache=True, fastmath=False)
def hybrid_step(theta, thd, volts, state, target, par, out):
    """Advance the law one servo period and write the torques into ``out[0:3]``.

    Args:
        theta: (3,) joint angles [rad]; thd: (3,) joint rates [rad/s].
        volts: (4,) OWTS PSD voltages [V] (all zero: no contact).
        state: (12,) controller state (updated in place).
        target: (3,) desired contact-point velocity in the WCS [m/s] (before the ramp).
        par: (NPAR,) parameters.
        out: (NOUT,) outputs (written).
    """
    _law(theta, thd, volts, state, target, par, out, par[P_FN])


@njit(cache=True, fastmath=False)
def normal_force_pi(force, volts, state, fstate, fpar, par, saturated):
    """Normal-force command [N] of the closed-loop variant: PI on the sensed normal force.

    ``f_meas = f_tip · n_W`` (the force the tip applies on the surface along the filtered
    normal of the previous step), ``e = f_des - f_meas``,
    ``f_cmd = clip(f_des + k_P e + k_I ∫e dt, 0, f_max)``. The integral runs only in contact
    and while the previous step was not torque limited (conditional integration, no wind-up);
    it is bounded by ``F_IMAX`` [N s] and reset when the contact is lost.

    Args:
        force: (3,) sensed fingertip force on the surface in the WCS [N].
        volts: (4,) OWTS voltages (contact: total above the sensor's threshold) [V].
        state: (12,) law state (reads the filtered normal n_W, 0:3).
        fstate: (NFSTATE,) integral [N s] and last measured normal force [N] (updated).
        fpar: (NFPAR,) ``k_P`` [-], ``k_I`` [1/s], integral bound [N s], ``f_max`` [N].
        par: (NPAR,) law parameters (``P_FN``: f_des, ``P_RATE``: servo rate).
        saturated: whether the previous step was torque limited.
    """
    fd = par[P_FN]
    meas = force[0] * state[0] + force[1] * state[1] + force[2] * state[2]
    fstate[S_MEAS] = meas
    contact = volts[0] + volts[1] + volts[2] + volts[3] > par[P_OWTS_THR]
    if not contact:
        fstate[S_INT] = 0.0
        return fd
    e = fd - meas
    if not saturated:
        lim = fpar[F_IMAX]
        fstate[S_INT] = min(lim, max(-lim, fstate[S_INT] + e / par[P_RATE]))
    return min(fpar[F_FMAX], max(0.0, fd + fpar[F_KP] * e + fpar[F_KI] * fstate[S_INT]))


@njit(cache=True, fastmath=False)
def hybrid_step_closed_loop(theta, thd, volts, force, state, fstate, target, par, fpar, out):
    """:func:`hybrid_step` pressing with the PI command of :func:`normal_force_pi`.

    Args: as :func:`hybrid_step`, plus ``force`` (3,) the sensed tip force [N] and the PI's
    ``fstate`` and ``fpar``. ``out[18]`` is the command after saturation.
    """
    fn = normal_force_pi(force, volts, state, fstate, fpar, par, out[13] != 0.0)
    _law(theta, thd, volts, state, target, par, out, fn)


@njit(cache=True, fastmath=False, inline="always")
def _owts_normal(volts, par):
    """OWTS, eqs. C.1-C.3: ``(contact, S, nT)`` - the intensity sum [V] and the contact
    normal in the TCS (zeros without contact)."""
    S = volts[0] + volts[1] + volts[2] + volts[3]
    contact = S > par[P_OWTS_THR]
    nT0 = 0.0
    nT1 = 0.0
    nT2 = 0.0
    if contact:
        half = par[P_OWTS_HALF]
        xd = ((volts[0] - volts[1] + volts[2] - volts[3]) / S - par[P_OWTS_XO]) * half
        yd = ((-volts[0] + volts[1] + volts[2] - volts[3]) / S - par[P_OWTS_YO]) * half
        rho = math.hypot(xd, yd)
        th = par[P_OWTS_K] * rho
        k = par[P_OWTS_K] if rho < 1e-15 else math.sin(th) / rho
        nT0, nT1, nT2 = xd * k, yd * k, math.cos(th)
    return contact, S, nT0, nT1, nT2


@njit(cache=True, fastmath=False, inline="always")
def _five_bar(theta, par):
    """3GM closed form, eqs. C.4-C.9 (C.8 corrected): the fingertip centre ``xf`` [m], the
    Jacobian ``J`` (3, 3) [m/rad], the passive angles γ1, γ2 [rad], dγ1/dθ1, dγ1/dθ2 [-] and
    the singular flag."""
    l1, l2, l3, l4, l5 = par[P_L1], par[P_L2], par[P_L3], par[P_L4], par[P_L5]
    t1, t2, t3 = theta[0], theta[1], theta[2]
    c1, s1 = math.cos(t1), math.sin(t1)
    a1 = l1 * c1 - l2 * math.cos(t2)
    a2 = l1 * s1 - l2 * math.sin(t2) + par[P_H1]
    aa = a1 * a1 + a2 * a2
    na = math.sqrt(aa)
    b1 = (l3 * l3 - l4 * l4 - aa) / (2.0 * l4)
    b2 = (l3 * l3 - l4 * l4 + aa) / (2.0 * l3)
    arg1 = b1 / na
    arg2 = b2 / na
    singular = not (-1.0 <= arg1 <= 1.0 and -1.0 <= arg2 <= 1.0)
    arg1 = min(1.0, max(-1.0, arg1))
    arg2 = min(1.0, max(-1.0, arg2))
    c = math.atan2(a2, a1)
    g1 = c - math.acos(arg1)
    g2 = c - math.acos(arg2)
    sg1, cg1 = math.sin(g1), math.cos(g1)
    r = l1 * c1 + l5 * cg1
    c3, s3 = math.cos(t3), math.sin(t3)
    rh = r + par[P_H2]
    h3 = par[P_H3]
    xf0 = rh * c3 + h3 * s3
    xf1 = rh * s3 - h3 * c3
    xf2 = l1 * s1 + l5 * sg1
    den = math.sin(g2 - g1)
    if abs(den) < 1e-9:
        singular = True
        den = 1e-9
    dg1_1 = l1 * math.sin(t1 - g2) / (l4 * den)
    dg1_2 = l2 * math.sin(g2 - t2) / (l4 * den)
    dr1 = -l1 * s1 - l5 * dg1_1 * sg1
    dr2 = -l5 * dg1_2 * sg1
    J = np.empty((3, 3))
    J[0, 0] = dr1 * c3
    J[0, 1] = dr2 * c3
    J[0, 2] = -rh * s3 + h3 * c3
    J[1, 0] = dr1 * s3
    J[1, 1] = dr2 * s3
    J[1, 2] = rh * c3 + h3 * s3
    J[2, 0] = l1 * c1 + l5 * dg1_1 * cg1
    J[2, 1] = l5 * dg1_2 * cg1
    J[2, 2] = 0.0
    return xf0, xf1, xf2, J, g1, g2, dg1_1, dg1_2, singular


@njit(cache=True, fastmath=False, inline="always")
def _filtered_normal(g1, t3, contact, nT0, nT1, nT2, state, par):
    """TCS (eq. 4.1 corrected) and the low-pass filtered WCS normal (eq. 4.2), stored in
    ``state[0:3]`` and returned; the tip's axis when the OWTS sees no contact."""
    sg1, cg1 = math.sin(g1), math.cos(g1)
    c3, s3 = math.cos(t3), math.sin(t3)
    R = np.empty((3, 3))
    R[0, 0], R[0, 1], R[0, 2] = sg1 * c3, -s3, cg1 * c3
    R[1, 0], R[1, 1], R[1, 2] = sg1 * s3, c3, cg1 * s3
    R[2, 0], R[2, 1], R[2, 2] = -cg1, 0.0, sg1
    if contact and nT0 * nT0 + nT1 * nT1 + nT2 * nT2 > 1e-12:
        m0 = R[0, 0] * nT0 + R[0, 1] * nT1 + R[0, 2] * nT2
        m1 = R[1, 0] * nT0 + R[1, 1] * nT1 + R[1, 2] * nT2
        m2 = R[2, 0] * nT0 + R[2, 1] * nT1 + R[2, 2] * nT2
    else:
        m0, m1, m2 = R[0, 2], R[1, 2], R[2, 2]
    al = par[P_ALPHA]
    n0 = al * m0 + (1.0 - al) * state[0]
    n1 = al * m1 + (1.0 - al) * state[1]
    n2 = al * m2 + (1.0 - al) * state[2]
    nn = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
    if nn < 1e-9:
        n0, n1, n2, nn = m0, m1, m2, math.sqrt(m0 * m0 + m1 * m1 + m2 * m2)
    n0, n1, n2 = n0 / nn, n1 / nn, n2 / nn
    state[0], state[1], state[2] = n0, n1, n2
    return n0, n1, n2


@njit(cache=True, fastmath=False, inline="always")
def _surface_frame(n0, n1, n2, par):
    """SCS, eq. 4.3 corrected, switching near ``z_Sx = z_Sz = 0``: the axes x_S, y_S (z_S =
    -n) and the alternative-frame flag."""
    zx, zy, zz = -n0, -n1, -n2
    if zx * zx + zz * zz >= par[P_SWITCH]:
        h = math.hypot(zx, zz)
        x0, x1, x2 = zz / h, 0.0, -zx / h
        y0, y1, y2 = zy * x2 - zz * x1, zz * x0 - zx * x2, zx * x1 - zy * x0
        alt = 0.0
    else:
        h = math.hypot(zy, zz)
        y0, y1, y2 = 0.0, zz / h, -zy / h
        x0, x1, x2 = y1 * zz - y2 * zy, y2 * zx - y0 * zz, y0 * zy - y1 * zx
        alt = 1.0
    return x0, x1, x2, y0, y1, y2, alt


@njit(cache=True, fastmath=False, inline="always")
def _ramp(target, n0, n1, n2, state, par):
    """The ramped desired velocity, its tangential part and the desired position (eq. 4.9),
    all in ``state``; returns the tangential desired velocity [m/s]."""
    w = par[P_RATE]
    d0, d1, d2 = target[0] - state[6], target[1] - state[7], target[2] - state[8]
    dn = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    dmax = par[P_RAMP] / w
    if dn > dmax:
        d0, d1, d2 = d0 * dmax / dn, d1 * dmax / dn, d2 * dmax / dn
    state[6] += d0
    state[7] += d1
    state[8] += d2
    vn = state[6] * n0 + state[7] * n1 + state[8] * n2
    vt0, vt1, vt2 = state[6] - vn * n0, state[7] - vn * n1, state[8] - vn * n2
    state[9], state[10], state[11] = vt0, vt1, vt2
    state[3] += vt0 / w
    state[4] += vt1 / w
    state[5] += vt2 / w
    return vt0, vt1, vt2


@njit(cache=True, fastmath=False, inline="always")
def _gravity_torques(theta, g1, g2, dg1_1, dg1_2, par):
    """Gravity compensation τ_g of θ1, θ2 [N m]: the gradient of the bodies' potential
    energy through the closed chain (eq. C.11)."""
    l1, l2, l3, l5 = par[P_L1], par[P_L2], par[P_L3], par[P_L5]
    t1, t2 = theta[0], theta[1]
    sgm = math.sin(g1 - g2)
    if abs(sgm) < 1e-9:
        sgm = 1e-9
    dg2_1 = l1 * math.sin(g1 - t1) / (l3 * sgm)
    dg2_2 = -l2 * math.sin(g1 - t2) / (l3 * sgm)
    c1, s1 = math.cos(t1), math.sin(t1)
    c2, s2 = math.cos(t2), math.sin(t2)
    sg1, cg1 = math.sin(g1), math.cos(g1)
    cg2, sg2 = math.cos(g2), math.sin(g2)
    G1, G5, G2, G3, GT = par[P_G1], par[P_G5], par[P_G2], par[P_G3], par[P_GT]
    # dz/d(angle) of each body's centre of mass: cx cos a - cy sin a
    m1 = par[P_C1X] * c1 - par[P_C1Y] * s1
    m5 = par[P_C5X] * cg1 - par[P_C5Y] * sg1
    m2 = par[P_C2X] * c2 - par[P_C2Y] * s2
    m3 = par[P_C3X] * cg2 - par[P_C3Y] * sg2
    tg0 = (
        G1 * m1
        + G5 * (l1 * c1 + m5 * dg1_1)
        + G3 * m3 * dg2_1
        + GT * (l1 * c1 + l5 * cg1 * dg1_1)
        + par[P_GC11] * l5 * c1
    )
    tg1 = G5 * m5 * dg1_2 + G2 * m2 + G3 * (l2 * c2 + m3 * dg2_2) + GT * l5 * cg1 * dg1_2
    return tg0, tg1


@njit(cache=True, fastmath=False)
def _law(theta, thd, volts, state, target, par, out, fn):
    """The law of eqs. 4.1-4.13 pressing with the normal force ``fn`` [N]."""
    contact, S, nT0, nT1, nT2 = _owts_normal(volts, par)
    xf0, xf1, xf2, J, g1, g2, dg1_1, dg1_2, singular = _five_bar(theta, par)
    n0, n1, n2 = _filtered_normal(g1, theta[2], contact, nT0, nT1, nT2, state, par)
    x0, x1, x2, y0, y1, y2, alt = _surface_frame(n0, n1, n2, par)
    zx, zy, zz = -n0, -n1, -n2
    # ---- contact point (4.7), velocity (C.10), ramp and desired position (4.9) --------------
    rt = par[P_RTIP]
    p0, p1, p2 = xf0 + rt * n0, xf1 + rt * n1, xf2 + rt * n2
    v0 = J[0, 0] * thd[0] + J[0, 1] * thd[1] + J[0, 2] * thd[2]
    v1 = J[1, 0] * thd[0] + J[1, 1] * thd[1] + J[1, 2] * thd[2]
    v2 = J[2, 0] * thd[0] + J[2, 1] * thd[1] + J[2, 2] * thd[2]
    vt0, vt1, vt2 = _ramp(target, n0, n1, n2, state, par)
    # ---- PD in the SCS, eqs. 4.8, 4.10-4.11: K_W = R diag(k, k, 0) R^T ------------------------
    e0, e1, e2 = state[3] - p0, state[4] - p1, state[5] - p2
    ex = e0 * x0 + e1 * x1 + e2 * x2
    ey = e0 * y0 + e1 * y1 + e2 * y2
    emax = par[P_EMAX]
    et = math.hypot(ex, ey)
    if et > emax:  # bounded tracking error: re-anchor the desired point (wind-up guard)
        ex, ey = ex * emax / et, ey * emax / et
        ez = e0 * zx + e1 * zy + e2 * zz
        state[3] = p0 + ex * x0 + ey * y0 + ez * zx
        state[4] = p1 + ex * x1 + ey * y1 + ez * zy
        state[5] = p2 + ex * x2 + ey * y2 + ez * zz
    u0, u1, u2 = vt0 - v0, vt1 - v1, vt2 - v2
    ux = u0 * x0 + u1 * x1 + u2 * x2
    uy = u0 * y0 + u1 * y1 + u2 * y2
    kp, kv = par[P_KP], par[P_KV]
    fx = kp * ex + kv * ux
    fy = kp * ey + kv * uy
    f0 = fx * x0 + fy * y0 + fn * n0
    f1 = fx * x1 + fy * y1 + fn * n1
    f2 = fx * x2 + fy * y2 + fn * n2
    tg0, tg1 = _gravity_torques(theta, g1, g2, dg1_1, dg1_2, par)
    # ---- τ = Jᵀ f + τ_g within the limits (C.10) ----------------------------------------------
    j0 = J[0, 0] * f0 + J[1, 0] * f1 + J[2, 0] * f2
    j1 = J[0, 1] * f0 + J[1, 1] * f1 + J[2, 1] * f2
    j2 = J[0, 2] * f0 + J[1, 2] * f1 + J[2, 2] * f2
    scale = 1.0
    lim0, lim1, lim2 = par[P_TAU1], par[P_TAU2], par[P_TAU3]
    for jv, gv, lim in ((j0, tg0, lim0), (j1, tg1, lim1), (j2, 0.0, lim2)):
        room = lim - abs(gv)
        if room <= 0.0:
            scale = 0.0
        elif abs(jv) > room:
            scale = min(scale, room / abs(jv))
    out[0] = min(lim0, max(-lim0, tg0 + scale * j0))
    out[1] = min(lim1, max(-lim1, tg1 + scale * j1))
    out[2] = min(lim2, max(-lim2, scale * j2))
    out[3], out[4], out[5] = p0, p1, p2
    out[6], out[7], out[8] = xf0, xf1, xf2
    out[9], out[10], out[11] = v0, v1, v2
    out[12] = 1.0 if contact else 0.0
    out[13] = 1.0 if scale < 1.0 else 0.0
    out[14] = S / 5.0
    out[15] = alt
    out[16] = g1
    out[17] = 1.0 if singular else 0.0
    out[18] = fn * scale
    for i in range(3):
        for j in range(3):
            out[O_J + 3 * i + j] = J[i, j]
    out[O_TG], out[O_TG + 1] = tg0, tg1
    out[O_F], out[O_F + 1], out[O_F + 2] = f0, f1, f2
    out[O_XS], out[O_XS + 1], out[O_XS + 2] = x0, x1, x2
    out[O_YS], out[O_YS + 1], out[O_YS + 2] = y0, y1, y2
