"""The compiled body of one gait-controller call (numba): everything after the phase's
reference values, the compiled grasp step (:class:`planner.control.grasp_step.GraspStep`,
called through its C entry point) included.

:func:`gait_kernel` does, on flat arrays and without allocating: the sensing of
:mod:`.sensing` (:func:`~.sensing.sense_kernel`), the rolling integration of the object
rotation (eq. 2.4), the sensed internal force and its PI servo
(:mod:`planner.control.internal_force`), the rolling PD of eq. 2.8 and the fingertip
orientation moments (:mod:`planner.control.rolling_pd`), the step's inputs ``q, qd, geo,
ref`` (layout :mod:`planner.control.grasp_layout`), the step and the check of its command,
the trace row
(:data:`~.controller.TRACE_NAMES`) and the event checks that end a phase. The laws are the
library's Python functions, transcribed with the same operation order (the replay test
compares the torques, the trace and the events with the recorded Python controller).

Arrays (indices are the constants below):

* ``sv`` (:data:`N_SV`,): the phase references at this call, from the segment's callables;
* ``ks`` (:data:`N_KS`,): constants of the controller and the phase, and its state;
* ``row`` (29,): the trace row written by the call.

The return value is the event code (:data:`EVENTS`; 0: none).
"""

from __future__ import annotations

import math

from llvmlite import ir
from numba import types
from numba.extending import intrinsic

from planner.control.grasp_stability import epsilon_two_scalar
from planner.exploration.planar.sensing import sense_kernel
from planner.jit import njit

# --- sv: reference values of the phase at this call
V_FDES, V_HAS_POSE, V_X, V_XD = 0, 1, 2, 5  # hold force [N]; pose (3) and twist (3)
V_HAS_ROLL, V_UDES, V_SRDES, V_PHI, V_PHID = 8, 9, 10, 11, 13  # rolling references
V_HAS_EXP, V_PDES, V_VDES, V_PHIDES = 15, 16, 18, 20  # exploring finger references
V_HAS_FNT, V_FNT, V_T, V_TL = 21, 22, 23, 24  # exploring force [N]; time, phase time [s]
N_SV = 25

# --- ks: constants of the controller (set once)
K_R, K_RTIP, K_DT = 0, 1, 2  # estimate radius [m], right tip radius [m], period [s]
K_PI_KP, K_PI_KI, K_PI_MAX = 3, 4, 5  # internal-force PI gains
K_ROLL_KP, K_ROLL_KV, K_ROLL_MAX = 6, 7, 8  # rolling PD gains (eq. 2.8)
K_HOLD_KP, K_HOLD_KV = 9, 10  # fingertip orientation gains
K_STARTUP, K_LOST_F, K_LOST_T, K_MU, K_MIN_EPS, K_MARGIN = 11, 12, 13, 14, 15, 16
K_LIM_LO, K_LIM_HI = 17, 23  # joint limits (6 each) [rad]
K_F_NT = 29  # index of f_n_tip in the step's input block
# --- ks: constants of the phase (set by start)
K_KIND, K_SOURCE, K_HOLDER, K_EX0, K_EX1, K_GRASP, K_THETA0, K_DURATION = range(30, 38)
# --- ks: state
S_THETA, S_U0, S_BETA0, S_INT, S_WEAK, S_HOLD = 38, 39, 40, 41, 42, 43  # S_HOLD: 2
S_TRIG, S_LO, S_HI, S_DONE, S_EPS, S_HIT = 45, 46, 52, 58, 59, 60  # S_LO, S_HI: 6 each
S_FLAG = 61  # DAQP exit flag of the step
K_STEP_FN, K_STEP_ARG, K_TAU_BOUND = 62, 63, 64  # the compiled step (0: run by Python)
# --- ks: the exploring pad's contact servo (phase constants and state; K_USERVO 0: off)
K_USERVO, K_UTARGET, S_UINT = 65, 66, 67
#: 1 once phase 1 took its rolling reference (``S_U0``, ``S_BETA0``) from its own first
#: touching reading (0: not yet)
S_REF = 68
#: radius of a round left tip [m] (0: the flat pad): its contact coordinate ``u`` is then an
#: arclength on the tip (``s_L = u``; the pad's is ``s_L = -u``), it rolls with the
#: effective radius ``r_L R / (r_L + R)`` and, exploring, is steered by its contact
K_RTIP_L = 69
N_KS = 70
#: contact servo of the exploring pad: proportional gain [-], integral gain [1/s] and the
#: largest orientation correction [rad] (:func:`_contact_servo`)
USERVO_KP, USERVO_KI, USERVO_MAX = 0.5, 10.0, 0.2
#: largest lead of the servoed pad's centre reference over the pad along it [m]
USERVO_PUSH = 2.5e-3
#: bit of the kernel's return value: the step ran and its command is rejected (fallback)
REJECTED = 8

#: event codes returned by :func:`gait_kernel`
EVENTS = {1: "workspace limit", 2: "contact lost", 3: "grasp stability lost", 4: "path finished"}


@intrinsic
def _call_step(typingctx, address, argument):  # pragma: no cover
    """``int f(void*)`` called through its address (both as integers): the compiled grasp
    step ``hx_run`` of :mod:`planner.control.grasp_step` on its bound arrays."""
    sig = types.int32(types.intp, types.intp)

    def codegen(context, builder, signature, args):
        i8p = ir.IntType(8).as_pointer()
        fnty = ir.FunctionType(ir.IntType(32), [i8p])
        fptr = builder.inttoptr(args[0], fnty.as_pointer())
        return builder.call(fptr, [builder.inttoptr(args[1], i8p)])

    return sig, codegen


@njit(cache=True, nogil=True, inline="always")
def _max(a, b):  # pragma: no cover
    """Python's ``max(a, b)`` (``b`` only if it is greater)."""
    return b if b > a else a


@njit(cache=True, nogil=True, inline="always")
def _min(a, b):  # pragma: no cover
    """Python's ``min(a, b)``."""
    return b if b < a else a


@njit(cache=True, nogil=True)
def _internal_force(p1x, p1y, p2x, p2y, f1x, f1y, f2x, f2y):  # pragma: no cover
    """:func:`planner.control.internal_force.sensed_internal_force` on scalars [N]."""
    dx, dy = p2x - p1x, p2y - p1y
    d = math.hypot(dx, dy)
    if d == 0.0:
        return 0.0
    ux, uy = dx / d, dy / d
    return _min(f1x * ux + f1y * uy, -(f2x * ux + f2y * uy))


@njit(cache=True, nogil=True)
def _rolling_moment(s, sd, s_des, sd_des, kp, kv, limit):  # pragma: no cover
    """:func:`planner.control.rolling_pd.rolling_moment` on scalars [N m]."""
    m = -(kp * (s_des - s) + kv * (sd_des - sd))
    return _max(-limit, _min(limit, m))


@njit(cache=True, nogil=True)
def _arclength(beta, phi, tip_radius):  # pragma: no cover
    """:func:`planner.exploration.planar.sensing.round_contact_arclength` [m]."""
    alpha = (beta + math.pi) - phi
    a = math.atan2(math.sin(alpha), math.cos(alpha))
    return tip_radius * (a - 0.5 * math.pi)


@njit(cache=True, nogil=True)
def gait_kernel(  # pragma: no cover
    q, qd, forces, image, has_image, geo, taxel_u, b, sv, ks, inputs, row, tau
):
    """One controller call (see the module docstring).

    Args:
        q, qd: (6,) encoder angles [rad] and rates [rad/s]; forces: (2, 2) strain gauges [N].
        image, has_image: the left tactile image [Pa] and whether there is one.
        geo, taxel_u, b: the sensing's geometry, taxel centres and estimate buffer.
        sv, ks: the references and the constants/state (layouts above).
        inputs: the step's input block (``q, qd, geo, ref, par``), written here.
        row: (29,) the trace row, written here.
        tau: (6,) the step's torque array [N m].

    With ``ks[K_STEP_FN]`` set, the kernel also runs the compiled step on ``inputs`` and
    checks its command (finite, within ``ks[K_TAU_BOUND]``).

    Returns:
        the event code (0: none; :data:`EVENTS`), plus :data:`REJECTED` when the step ran
        and its command must be replaced by the fallback.
    """
    kind = int(ks[K_KIND])
    sense_kernel(q, forces, image, has_image, int(ks[K_SOURCE]), geo, taxel_u, b)
    R, r = ks[K_R], ks[K_RTIP]
    u, cx = b[0], b[10]
    if kind == 1 and b[1] != 0.0:  # rolling integration (eq. 2.4)
        if ks[S_REF] == 0.0:  # from the phase's own first reading (see GaitController.start)
            ks[S_U0], ks[S_BETA0], ks[S_REF] = u, b[12], 1.0
        # eq. (2.4): theta = dbeta_L + ds_L / R, with s_L = -u on the pad, +u on a round tip
        sgn = 1.0 if ks[K_RTIP_L] > 0.0 else -1.0
        ks[S_THETA] = ks[K_THETA0] + (b[12] - ks[S_BETA0]) + sgn * (u - ks[S_U0]) / R
    theta = ks[S_THETA]
    f_des = sv[V_FDES]
    h = 2 * int(ks[K_HOLDER])
    if kind == 1:
        sensed = _internal_force(b[2], b[3], b[4], b[5], b[14], b[15], b[16], b[17])
    else:
        fx, fy = b[14 + h], b[15 + h]
        sensed = _internal_force(b[2 + h], b[3 + h], cx, 0.0, fx, fy, -fx, -fy)
    # internal-force PI with anti-windup (InternalForcePI.command)
    err = f_des - sensed
    lim = ks[K_PI_MAX]
    ks[S_INT] = _max(-lim, _min(lim, ks[S_INT] + ks[K_PI_KI] * err * ks[K_DT]))
    corr = _max(-lim, _min(lim, ks[K_PI_KP] * err + ks[S_INT]))
    f_cmd = _max(0.0, f_des + corr)
    m0, m1 = 0.0, 0.0
    u_des, sR, sR_des = math.nan, math.nan, math.nan
    if sv[V_HAS_ROLL] != 0.0:
        u_des, sR_des = sv[V_UDES], sv[V_SRDES]
        sR = _arclength(b[13], b[33], r)
        kp = 0.0
        if kind == 1:
            w_des = sv[V_XD + 2] if sv[V_HAS_POSE] != 0.0 else 0.0
            # contact rates from pure rolling (eq. 2.4): ds = -d(phi - theta) / (k_f + k_o)
            rL = ks[K_RTIP_L]
            sgn, kL = (1.0, rL * R / (rL + R)) if rL > 0.0 else (-1.0, R)
            sdL = -kL * (qd[0] + qd[1] + qd[2] - w_des)
            sdR = -(r * R / (r + R)) * (qd[3] + qd[4] + qd[5] - w_des)
            g = (ks[K_ROLL_KP], ks[K_ROLL_KV], ks[K_ROLL_MAX])
            m0 = _rolling_moment(sgn * u, sdL, sgn * u_des, 0.0, g[0], g[1], g[2])
            m1 = _rolling_moment(sR, sdR, sR_des, 0.0, g[0], g[1], g[2])
            kp = ks[K_HOLD_KP]
        # orientation of each grasping/holding fingertip along its planned path (phases
        # 2/3: damping only; a distal moment on the holder rolled the object along the palm)
        kv = ks[K_HOLD_KV]
        phid = qd[0] + qd[1] + qd[2]
        m0 += kp * (sv[V_PHI] - b[32]) - kv * (phid - sv[V_PHID])
        phid = qd[3] + qd[4] + qd[5]
        m1 += kp * (sv[V_PHI + 1] - b[33]) - kv * (phid - sv[V_PHID + 1])
    _write_inputs(q, qd, b, sv, ks, inputs, kind, h, theta, f_cmd, m0, m1)
    rejected = 0
    if ks[K_STEP_FN] != 0.0:
        ks[S_FLAG] = _call_step(int(ks[K_STEP_FN]), int(ks[K_STEP_ARG]))
        bound = ks[K_TAU_BOUND]
        for i in range(6):
            if not abs(tau[i]) <= bound:  # NaN and inf fail too
                rejected = REJECTED
    has_exp = sv[V_HAS_EXP] != 0.0
    row[0], row[1] = sv[V_T], kind
    for i in range(12):
        row[2 + i] = b[i]
    row[14], row[15], row[16], row[17], row[18] = theta, b[18], b[19], f_cmd, sensed
    row[19] = sv[V_PDES] if has_exp else 0.0
    row[20] = sv[V_PDES + 1] if has_exp else 0.0
    row[21], row[22], row[23], row[24] = u_des, sR, sR_des, f_des
    for i in range(4):
        row[25 + i] = b[14 + i]
    if ks[S_DONE] != 0.0:
        return rejected
    return rejected + _events(q, b, ks, kind, sv[V_TL])


@njit(cache=True, nogil=True)
def _write_inputs(q, qd, b, sv, ks, inputs, kind, h, theta, f_cmd, m0, m1):  # pragma: no cover
    """The grasp step's inputs ``q, qd, geo, ref`` (and ``f_n_tip`` of ``par``)."""
    for i in range(6):
        inputs[i], inputs[6 + i] = q[i], qd[i]
    for i in range(8):
        inputs[12 + i] = b[20 + i]
    if kind == 3 and ks[K_RTIP_L] == 0.0:  # the exploring pad is steered by its centre
        inputs[12], inputs[13] = 0.0, 0.0  # (it slides); a round tip by its contact
    if sv[V_HAS_POSE] != 0.0:
        for i in range(6):
            inputs[20 + i] = sv[V_X + i]
    else:
        inputs[20], inputs[21] = b[10], b[11]
        for i in range(2, 6):
            inputs[20 + i] = 0.0
    inputs[26], inputs[27], inputs[28] = 0.0, 0.0, 0.0
    R = ks[K_R]
    inputs[29], inputs[30], inputs[31], inputs[32] = theta, R, R, f_cmd
    inputs[33], inputs[34] = m0, m1
    has_exp = sv[V_HAS_EXP] != 0.0
    for i in range(4):
        inputs[35 + i] = sv[V_PDES + i] if has_exp else 0.0
    phi_des = sv[V_PHIDES] if has_exp else 0.0
    ex0, ex1 = ks[K_EX0], ks[K_EX1]
    if ex0 != 0.0 and ks[K_USERVO] != 0.0:
        # the pad lies where it is, not where its reference ran on to (a wall holds it):
        # its orientation follows its centre's polar angle, and the servo sets the contact
        ref = math.atan2(sv[V_PDES + 1] - b[11], sv[V_PDES] - b[10])
        act = math.atan2(b[29] - b[11], b[28] - b[10])
        lag = act - ref
        phi_des += math.atan2(math.sin(lag), math.cos(lag)) + _contact_servo(b, ks, R)
        _bound_push(b, inputs)
    inputs[39] = phi_des if ex0 != 0.0 else 0.0
    inputs[40] = phi_des if ex1 != 0.0 else 0.0
    inputs[41], inputs[42] = b[10], 0.0
    inputs[43], inputs[44], inputs[45] = ks[K_GRASP], ex0, ex1
    inputs[46] = ks[S_HOLD] + (b[2 + h] - b[28 + h])
    inputs[47] = ks[S_HOLD + 1] + (b[3 + h] - b[29 + h])
    if sv[V_HAS_FNT] != 0.0:
        inputs[int(ks[K_F_NT])] = sv[V_FNT]


@njit(cache=True, nogil=True)
def _bound_push(b, inputs):  # pragma: no cover
    """Keeps the exploring pad's centre reference (``inputs[35:39]``: position, velocity)
    within :data:`USERVO_PUSH` of the pad's centre along the pad (``b[28:30]``, axis at
    ``b[32]``), its velocity along the pad dropped while it is bounded: the pad pushes a
    wall it meets with at most ``tip_kp * USERVO_PUSH`` [N] (its reference ran on to the
    ridge's near wall, 4 mm past the far wall it stopped at: 1 N rolled the held ball
    11 deg along the palm)."""
    ax, ay = math.cos(b[32]), math.sin(b[32])
    e = (inputs[35] - b[28]) * ax + (inputs[36] - b[29]) * ay
    if abs(e) > USERVO_PUSH:
        cut = e - math.copysign(USERVO_PUSH, e)
        inputs[35] -= cut * ax
        inputs[36] -= cut * ay
        v = inputs[37] * ax + inputs[38] * ay
        if v * e > 0.0:
            inputs[37] -= v * ax
            inputs[38] -= v * ay


@njit(cache=True, nogil=True)
def _contact_servo(b, ks, R):  # pragma: no cover
    """Orientation correction [rad] of the exploring pad that drives its tactile contact
    location ``u`` (``b[0]``) to ``ks[K_UTARGET]`` [m] (a PI on ``u``; integrates only while
    the pad touches, ``b[1]``). A pad lying on a circle of radius ``R`` touches it where
    it is tangent: turning the pad by ``d phi`` about its centre moves the contact by
    ``R d phi`` along the pad, so ``d phi = -(u - u_target) / R`` (the integral removes the
    steady deflection of the pad by its contact moment and its damping, 3-4 deg on the
    10 cm ball: the contact sat 5 mm from the pad's end where 1.5 mm was commanded)."""
    err = b[0] - ks[K_UTARGET]
    if b[1] != 0.0:
        acc = ks[S_UINT] + USERVO_KI * err * ks[K_DT]
        ks[S_UINT] = _max(-USERVO_MAX * R, _min(USERVO_MAX * R, acc))
    corr = -(USERVO_KP * err + ks[S_UINT]) / R
    return _max(-USERVO_MAX, _min(USERVO_MAX, corr))


@njit(cache=True, nogil=True)
def _events(q, b, ks, kind, tl):  # pragma: no cover
    """The event that ends the phase (code of :data:`EVENTS`, 0: none); its data in ``ks``:
    the joints at their limits (bit mask ``S_HIT``) and ε (``S_EPS``)."""
    margin = ks[K_MARGIN]
    if ks[S_TRIG] == 0.0:  # limit triggers from the phase's first reading (limit_triggers)
        for j in range(6):
            ks[S_LO + j] = _min(ks[K_LIM_LO + j] + margin, q[j] - margin)
            ks[S_HI + j] = _max(ks[K_LIM_HI + j] - margin, q[j] + margin)
        ks[S_TRIG] = 1.0
    started = tl > ks[K_STARTUP]
    first, last = (0, 6) if kind == 1 else ((3, 6) if kind == 2 else (0, 3))
    hit = 0
    for j in range(first, last):
        if q[j] < ks[S_LO + j] or q[j] > ks[S_HI + j]:
            hit |= 1 << j
    if hit != 0 and started:
        ks[S_HIT] = hit
        return 1
    lost = ks[K_LOST_F]
    if kind == 1:
        weak = b[18] < lost or b[19] < lost
    else:
        weak = b[18] < lost if kind == 2 else b[19] < lost
    ks[S_WEAK] = ks[S_WEAK] + ks[K_DT] if weak else 0.0
    if ks[S_WEAK] > ks[K_LOST_T] and started:
        return 2
    if kind == 1 and started:
        eps = epsilon_two_scalar(b[2], b[3], b[4], b[5], -b[6], -b[7], -b[8], -b[9], ks[K_MU])
        if eps < ks[K_MIN_EPS]:
            ks[S_EPS] = eps
            return 3
    if tl >= ks[K_DURATION]:
        return 4
    return 0


__all__ = ["EVENTS", "N_KS", "N_SV", "REJECTED", "gait_kernel"]
