"""One step of the 3GM on one plate as ONE numba call: the hot path of the spatial world.

:func:`finger_step` does, in compiled code and without a Python allocation, everything
:func:`planner.sim.spatial.stepping.step_body` does for the finger alone over one
:class:`~planner.sim.spatial.Plate` / :class:`~planner.sim.spatial.Plane` (the general
path stays the reference; the tests compare both on random states):

1. the reduced dynamics (the generated C function of
   :mod:`planner.sim.spatial.finger_codegen`, called through its address by
   :func:`call_compiled`): ``c, J, J_ω, M_r⁻¹`` and ``θ̇_free``;
2. torque clipping at the App. C limits, the foot point on the plate (Newton of
   :func:`planner.sim.spatial.kernel.plate_foot`, warm-started; from the nearest grid sample
   on a cold start or when it does not converge);
3. the contact problem: the exact circular cone of
   :mod:`planner.sim.spatial.friction_cone` (separate / stick / slide by Newton on
   ``g(φ)``), coupled with the joint limits (unilateral rows ``±e_i``,
   ``0 <= λ_i ⊥ (θ_i - θ_lim)/h ± θ̇_i⁺ >= 0``) by block Gauss-Seidel when a limit is
   within reach (alone, the contact is solved in one exact 3x3 solve);
4. ``θ⁺ = θ + h θ̇⁺``, the kinematics at ``θ⁺`` (second generated function), the
   mass-weighted projection onto the offset surface (joints held at an active limit do
   not move);
5. the contact record and the OWTS rows of every 5 kHz sample time in the step.

The state lives in one float vector (layout: the ``TH``... constants below) that
:class:`planner.sim.spatial.bodies.FingerBody` exposes as attributes. Return codes: a
bitmask (bits 0-2: joint ``i`` held at a limit, bit 3: the contact carried force), or
``FALLBACK`` (the sliding Newton found no valid root, or the tip touches the plate at more than
one point, :func:`.kernel.plate_other_feet`: nothing was changed, the caller runs the general
path), ``SINGULAR_START`` (the loop cannot close at ``θ``; nothing changed) or
``SINGULAR_END`` (at ``θ⁺``; the angles were advanced, as in the general path).
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from planner.jit import njit
from planner.sim.spatial.closest import FOOT_SLACK
from planner.sim.spatial.cone_kernel import cone_impulse
from planner.sim.spatial.kernel import (
    MAX_OTHER_FEET,
    plate_eval,
    plate_foot,
    plate_other_feet,
    plate_seed,
)

__all__ = ["FALLBACK", "SINGULAR_END", "SINGULAR_START", "STATE_SIZE", "finger_step"]

# state vector layout (float64)
TH, THD, C, J, JW, MINV, G1, HINT, HINT_OK = 0, 3, 6, 9, 18, 27, 36, 37, 39
ACT, FN, PT, NRM, FT, SLIP, GAP, LIM, SIN = 40, 41, 42, 45, 48, 51, 54, 55, 58
STATE_SIZE = 60
# parameter vector layout
P_H, P_MU, P_R, P_BASE, P_ROT, P_T, P_LIM, P_TAU = 0, 1, 2, 3, 4, 13, 16, 22
P_RATE, P_FULL, P_SIN, P_ALL = 25, 26, 27, 28
PARAM_SIZE = 29
#: |sin(γ2 - γ1)| below which the 3GM is singular (links l3, l4 aligned) [-]; ``prm[P_SIN]``
SINGULAR_SIN = 1e-6
# buffers of the generated functions (inputs, then outputs; matrices column-major)
D_C, D_J, D_JW, D_MINV, D_THDF, D_G1, D_SIN = 10, 13, 22, 31, 40, 43, 56
K_C, K_J, K_JW, K_G1, K_SIN = 3, 6, 15, 24, 25

FALLBACK, SINGULAR_START, SINGULAR_END = -1, -2, -3
_PROJ_TOL = 1e-12  # [m]
_MARGIN = 1e-5  # [m] candidate margin of the contact
_LIM_MARGIN = 1e-9  # [rad] candidate margin of a joint limit
_SWEEPS = 200


@intrinsic
def call_compiled(typingctx, fn, arg, res, iw, w):
    """Call a CasADi-generated C function ``int f(const double** arg, double** res,
    long long* iw, double* w, int mem)`` from its address ``fn`` (int64) and the int64
    addresses of its buffers (see :attr:`~.finger_codegen.CompiledFunction.pointers`)."""
    sig = types.int32(types.int64, types.int64, types.int64, types.int64, types.int64)

    def codegen(context, builder, signature, args):
        i8p = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.IntType(32), [i8p, i8p, i8p, i8p, ir.IntType(32)])
        f = builder.inttoptr(args[0], fnty.as_pointer())
        ptrs = [builder.inttoptr(a, i8p) for a in args[1:]]
        return builder.call(f, [*ptrs, ir.Constant(ir.IntType(32), 0)])

    return sig, codegen


@njit(cache=True)
def _foot(F, P, base, prm, x, cx, cy, cz, out):
    """Foot of the WCS point ``c``: ``out`` = point (3), normal (3); returns the distance.
    Warm start and update of the hint in ``x``."""
    R = prm[P_ROT : P_ROT + 9]
    t = prm[P_T : P_T + 3]
    d0, d1, d2 = cx - t[0], cy - t[1], cz - t[2]
    px = R[0] * d0 + R[3] * d1 + R[6] * d2
    py = R[1] * d0 + R[4] * d1 + R[7] * d2
    pz = R[2] * d0 + R[5] * d1 + R[8] * d2
    if x[HINT_OK] == 0.0:  # cold start: the nearest sample under the sphere
        x[HINT], x[HINT + 1] = plate_seed(F, P, base, px, py, pz)
        x[HINT_OK] = 1.0
    fx, fy, fz, nx, ny, nz, dist, done = plate_foot(F, P, base, px, py, pz, x[HINT], x[HINT + 1])
    if done:  # a local foot farther than the surface straight below is not the nearest
        e2 = (px - fx) ** 2 + (py - fy) ** 2 + (pz - fz) ** 2
        below = pz - plate_eval(F, P, base, px, py)[0]
        done = below >= 0.0 and e2 <= (below + FOOT_SLACK) ** 2
    if not done:  # a sharp crest crossed, or a foot left behind: the nearest sample
        sx, sy = plate_seed(F, P, base, px, py, pz)
        fx, fy, fz, nx, ny, nz, dist, done = plate_foot(F, P, base, px, py, pz, sx, sy)
    x[HINT], x[HINT + 1] = fx, fy
    for i in range(3):
        out[i] = R[3 * i] * fx + R[3 * i + 1] * fy + R[3 * i + 2] * fz + t[i]
        out[3 + i] = R[3 * i] * nx + R[3 * i + 1] * ny + R[3 * i + 2] * nz
    return dist


@njit(cache=True)
def _other_feet(F, P, base, prm, x, reach) -> int:
    """How many other feet of the tip's centre :func:`.kernel.plate_other_feet` finds within
    ``reach`` [m] besides the one :func:`_foot` left in the hint (a sphere wider than a
    groove touches both rims: the general path solves those contacts together)."""
    R = prm[P_ROT : P_ROT + 9]
    t = prm[P_T : P_T + 3]
    d0, d1, d2 = x[C] - t[0], x[C + 1] - t[1], x[C + 2] - t[2]
    px = R[0] * d0 + R[3] * d1 + R[6] * d2
    py = R[1] * d0 + R[4] * d1 + R[7] * d2
    pz = R[2] * d0 + R[5] * d1 + R[8] * d2
    out = np.empty((MAX_OTHER_FEET, 7))
    return plate_other_feet(F, P, base, px, py, pz, prm[P_R], reach, x[HINT], x[HINT + 1], out)


@njit(cache=True)
def _kinematics(x, kin, kp):
    """Centre, ``J``, ``J_ω``, γ1 at ``x[TH]`` (generated kinematics); False: singular."""
    kin[0], kin[1], kin[2] = x[TH], x[TH + 1], x[TH + 2]
    call_compiled(kp[0], kp[1], kp[2], kp[3], kp[4])
    for i in range(3):
        x[C + i] = kin[K_C + i]
        for j in range(3):
            x[J + 3 * i + j] = kin[K_J + 3 * j + i]
            x[JW + 3 * i + j] = kin[K_JW + 3 * j + i]
    x[G1] = kin[K_G1]
    x[SIN] = kin[K_SIN]
    return math.isfinite(kin[K_C])


@njit(cache=True)
def _limit_rows(x, prm, thd_f, reach, idx, sgn, rate):
    """Joint-limit rows within reach: joint ``idx``, sign (+1 lower, -1 upper), ``gap/h``
    (a round-off violation above ``-_LIM_MARGIN`` is corrected; a joint further beyond is held,
    not pushed back: 0); returns their number."""
    h = prm[P_H]
    m = 0
    for i in range(3):
        lo, hi = prm[P_LIM + 2 * i], prm[P_LIM + 2 * i + 1]
        th = x[TH + i]
        gl, gu = th - lo, hi - th
        if gl <= reach:
            idx[m], sgn[m], rate[m] = i, 1.0, (gl if gl >= -_LIM_MARGIN else 0.0) / h
            m += 1
        elif gu <= reach:
            idx[m], sgn[m], rate[m] = i, -1.0, (gu if gu >= -_LIM_MARGIN else 0.0) / h
            m += 1
    return m


@njit(cache=True)
def _solve(W, MJt, Jc, Minv, thd_f, has_c, gap_rate, mu, m, idx, sgn, rate, lam, lim, v):
    """Contact and limit impulses (block Gauss-Seidel over the exact cone and the scalar
    limit rows; one exact solve without limits). ``v`` (3,): ``θ̇⁺``. Returns the contact
    status (0: no candidate, 1-3 as :func:`.cone_kernel.cone_impulse`, -1 fall back to the
    Python step: a cone solve it cannot do, or sweeps that did not converge)."""
    for i in range(3):
        v[i] = thd_f[i]
        lam[i] = 0.0
        lim[i] = 0.0
    status = 0
    new = np.zeros(3)
    for _ in range(_SWEEPS):
        change, size = 0.0, 0.0
        if has_c:
            ub = np.zeros(3)
            for i in range(3):
                ub[i] = Jc[i, 0] * v[0] + Jc[i, 1] * v[1] + Jc[i, 2] * v[2]
                ub[i] -= W[i, 0] * lam[0] + W[i, 1] * lam[1] + W[i, 2] * lam[2]
            status = cone_impulse(W, ub[0] + gap_rate, ub[1], ub[2], mu, new)
            if status < 0:
                return -1
            d0, d1, d2 = new[0] - lam[0], new[1] - lam[1], new[2] - lam[2]
            for i in range(3):
                v[i] = v[i] + MJt[i, 0] * d0 + MJt[i, 1] * d1 + MJt[i, 2] * d2
                lam[i] = new[i]
                size = max(size, abs(new[i]))
            change = max(abs(d0), abs(d1), abs(d2))
        if m == 0:
            return status
        for j in range(m):
            i, s = idx[j], sgn[j]
            old = lim[i] * s
            nl = max(0.0, old - (s * v[i] + rate[j]) / Minv[i, i])
            d = nl - old
            for k in range(3):
                v[k] += Minv[k, i] * s * d
            lim[i] = s * nl
            change = max(change, abs(d))
            size = max(size, nl)
        if change <= 1e-13 * (1.0 + size):
            return status
    return -1  # the sweeps cycle: the Python step solves it (relaxed restarts)


@njit(cache=True)
def _project(F, P, base, prm, x, Minv, lim, foot):
    """Mass-weighted Gauss-Newton of the centre onto the offset surface (joints with a
    limit impulse held); returns the final gap [m]; ``foot`` = point, normal."""
    Pm = Minv.copy()
    for i in range(3):  # condition on the held joints: P = Z (Zᵀ M Z)⁻¹ Zᵀ
        if lim[i] != 0.0 and Pm[i, i] > 0.0:
            col = Pm[:, i].copy()
            piv = col[i]
            for a in range(3):
                for b in range(3):
                    Pm[a, b] -= col[a] * col[b] / piv
    r = prm[P_R]
    gap = 0.0
    for _ in range(20):
        d = _foot(F, P, base, prm, x, x[C], x[C + 1], x[C + 2], foot)
        gap = d - r
        if abs(gap) <= _PROJ_TOL:
            break
        jn = np.zeros(3)
        for k in range(3):
            jn[k] = foot[3] * x[J + k] + foot[4] * x[J + 3 + k] + foot[5] * x[J + 6 + k]
        mj = Pm @ jn
        den = jn[0] * mj[0] + jn[1] * mj[1] + jn[2] * mj[2]
        if not den > 0.0:
            break
        dq = -gap * mj / den
        for i in range(3):
            x[TH + i] += dq[i]
        for i in range(3):
            x[C + i] += x[J + 3 * i] * dq[0] + x[J + 3 * i + 1] * dq[1] + x[J + 3 * i + 2] * dq[2]
    return gap


@njit(cache=True)
def _owts_rows(x, prm, t_end, rows, times, ost):
    """The OWTS row of the step (normal of the tip in the TCS, intensity, friction in the
    TCS) at every 5 kHz sample time ``<= t_end`` (as :meth:`.sensing.OWTSRecorder.advance`)."""
    row = np.zeros(7)
    if x[ACT] > 0.0:
        c3, s3 = math.cos(x[TH + 2]), math.sin(x[TH + 2])
        cg, sg = math.cos(x[G1]), math.sin(x[G1])
        R = np.array([[c3 * sg, -s3, c3 * cg], [s3 * sg, c3, s3 * cg], [-cg, 0.0, sg]])
        n0, n1, n2 = x[NRM], x[NRM + 1], x[NRM + 2]
        f0, f1, f2 = x[FT], x[FT + 1], x[FT + 2]
        for j in range(3):
            row[j] = -(R[0, j] * n0 + R[1, j] * n1 + R[2, j] * n2)
            row[4 + j] = R[0, j] * f0 + R[1, j] * f1 + R[2, j] * f2
        row[3] = min(x[FN] / prm[P_FULL], 1.0)
    rate = prm[P_RATE]
    while ost[0] / rate <= t_end + 1e-12 and ost[1] < rows.shape[0]:
        k = int(ost[1])
        rows[k, :] = row
        times[k] = ost[0] / rate
        ost[0] += 1.0
        ost[1] += 1.0


@njit(cache=True)
def finger_step(x, tau_in, t_end, prm, F, P, dyn, dp, kin, kp, rows, times, ost):
    """One step (module docstring). ``x``: state; ``tau_in`` (3,) [N m] (clipped here);
    ``t_end`` [s]: time after the step; ``prm``: parameters; ``F, P``: packed plate;
    ``dyn, dp`` / ``kin, kp``: buffer and addresses of the generated dynamics / kinematics;
    ``rows, times, ost``: OWTS sample buffer, times and ``(next index, count)``."""
    h, mu, r = prm[P_H], prm[P_MU], prm[P_R]
    for i in range(3):
        dyn[i], dyn[3 + i] = x[TH + i], x[THD + i]
        lim_t = prm[P_TAU + i]
        dyn[6 + i] = min(max(tau_in[i], -lim_t), lim_t)
    dyn[9] = h
    call_compiled(dp[0], dp[1], dp[2], dp[3], dp[4])
    thd_f = dyn[D_THDF : D_THDF + 3].copy()
    ok = math.isfinite(dyn[D_C]) and abs(dyn[D_SIN]) >= prm[P_SIN]
    for i in range(3):
        ok = ok and math.isfinite(thd_f[i])
    if not ok:
        return SINGULAR_START
    Minv = np.empty((3, 3))
    for i in range(3):
        x[C + i] = dyn[D_C + i]
        for j in range(3):
            x[J + 3 * i + j] = dyn[D_J + 3 * j + i]
            x[JW + 3 * i + j] = dyn[D_JW + 3 * j + i]
            Minv[i, j] = dyn[D_MINV + 3 * j + i]
            x[MINV + 3 * i + j] = Minv[i, j]
    x[G1], x[SIN] = dyn[D_G1], dyn[D_SIN]
    vmax = max(abs(thd_f[0]), abs(thd_f[1]), abs(thd_f[2]))
    foot = np.empty(6)
    dist = _foot(F, P, prm[P_BASE], prm, x, x[C], x[C + 1], x[C + 2], foot)
    gap = dist - r
    reach = 2.0 * h * vmax * 0.2 + _MARGIN
    has_c = gap <= reach
    if prm[P_ALL] != 0.0 and _other_feet(F, P, prm[P_BASE], prm, x, reach) > 0:
        return FALLBACK  # several contacts: the general path (nothing changed but the hint)
    Jc = np.zeros((3, 3))
    MJt = np.zeros((3, 3))
    W = np.zeros((3, 3))
    Cf = np.zeros((3, 3))
    if has_c:
        _contact_operator(x, foot, r, Minv, Cf, Jc, MJt, W)
    idx = np.zeros(3, np.int64)
    sgn, rate = np.zeros(3), np.zeros(3)
    m = _limit_rows(x, prm, thd_f, 2.0 * h * vmax + _LIM_MARGIN, idx, sgn, rate)
    lam, lim, v = np.zeros(3), np.zeros(3), np.zeros(3)
    status = _solve(W, MJt, Jc, Minv, thd_f, has_c, gap / h, mu, m, idx, sgn, rate, lam, lim, v)
    if status < 0:
        return FALLBACK
    for i in range(3):
        x[THD + i] = v[i]
        x[TH + i] = x[TH + i] + h * v[i]
        x[LIM + i] = lim[i]
    sin0 = x[SIN]
    # singular also when nearer alignment than the step moved it (bodies.aligning)
    if not _kinematics(x, kin, kp) or abs(x[SIN]) < max(prm[P_SIN], abs(x[SIN] - sin0)):
        return SINGULAR_END
    active = status >= 2 and lam[0] > 0.0
    x[ACT] = 0.0
    if active:
        g = _project(F, P, prm[P_BASE], prm, x, Minv, lim, foot)
        u = Jc @ v
        x[ACT], x[FN], x[GAP] = 1.0, lam[0] / h, g
        for i in range(3):
            x[PT + i], x[NRM + i] = foot[i], foot[3 + i]
            x[FT + i] = (lam[1] * Cf[1, i] + lam[2] * Cf[2, i]) / h
            x[SLIP + i] = u[1] * Cf[1, i] + u[2] * Cf[2, i]
    elif status == 1:  # a candidate that separated must not end up penetrating
        d = _foot(F, P, prm[P_BASE], prm, x, x[C], x[C + 1], x[C + 2], foot)
        if d - r < -_PROJ_TOL:
            _project(F, P, prm[P_BASE], prm, x, Minv, lim, foot)
    _owts_rows(x, prm, t_end, rows, times, ost)
    code = 8 if active else 0
    for i in range(3):
        if lim[i] != 0.0:
            code |= 1 << i
    return code


@njit(cache=True)
def _contact_operator(x, foot, r, Minv, Cf, Jc, MJt, W):
    """Contact frame ``Cf`` (rows n, t1, t2), ``J_c = Cf (J + r [n]× J_ω)``,
    ``M⁻¹ J_cᵀ`` and the Delassus operator ``W`` (symmetrized)."""
    n0, n1, n2 = foot[3], foot[4], foot[5]
    if abs(n0) < 0.9:
        a, b, c = 1.0 - n0 * n0, -n0 * n1, -n0 * n2
    else:
        a, b, c = -n1 * n0, 1.0 - n1 * n1, -n1 * n2
    k = 1.0 / math.sqrt(a * a + b * b + c * c)
    a, b, c = a * k, b * k, c * k
    Cf[0, 0], Cf[0, 1], Cf[0, 2] = n0, n1, n2
    Cf[1, 0], Cf[1, 1], Cf[1, 2] = a, b, c
    Cf[2, 0], Cf[2, 1], Cf[2, 2] = n1 * c - n2 * b, n2 * a - n0 * c, n0 * b - n1 * a
    Jp = np.empty((3, 3))
    for j in range(3):
        w0, w1, w2 = x[JW + j], x[JW + 3 + j], x[JW + 6 + j]
        Jp[0, j] = x[J + j] + r * (n1 * w2 - n2 * w1)
        Jp[1, j] = x[J + 3 + j] + r * (n2 * w0 - n0 * w2)
        Jp[2, j] = x[J + 6 + j] + r * (n0 * w1 - n1 * w0)
    Jc[:, :] = Cf @ Jp
    MJt[:, :] = Minv @ Jc.T
    Wt = Jc @ MJt
    W[:, :] = 0.5 * (Wt + Wt.T)
