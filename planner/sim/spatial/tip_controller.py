"""A Jacobian-transpose force/velocity controller of the 3GM fingertip (the benchmark's).

:class:`TipForceVelocityController` presses the tip along the normal sensed by the OWTS and
drags it at a set velocity. Its per-call work (the finger's kinematics from the encoders, the
OWTS normal to the WCS, the force law, ``Jᵀ f``) runs in one compiled call,
:func:`tip_torques`, when numba is installed and the generated kinematics are compiled;
otherwise the same law in numpy (tested equal).
"""

from __future__ import annotations

import math

import numpy as np

from planner import checks
from planner.jit import njit
from planner.sim.spatial.finger import tcs_rotation
from planner.sim.spatial.finger_codegen import CompiledFunction, reduced_dynamics_function
from planner.sim.spatial.step_kernel import call_compiled

__all__ = ["TipForceVelocityController", "tip_torques"]


@njit(cache=True)
def tip_torques(q, qd, t, normals, on, st, prm, kin, kp, tau):
    """The controller's law (class docstring) in one call.

    Args:
        q, qd: (3,) encoder angles [rad] and rates [rad/s]; t: time [s].
        normals: (K, 3) OWTS tip normals (TCS); on: (K,) in-contact flags.
        st: (4,) state ``(n_W (3), touched)`` (updated).
        prm: (9,) ``start (3) [m], v_d (3) [m/s], f_n [N], K_p [N/m], K_v [N s/m]``.
        kin, kp: buffer and addresses of the generated kinematics.
        tau: (3,) output motor torques [N m].
    """
    kin[0], kin[1], kin[2] = q[0], q[1], q[2]
    call_compiled(kp[0], kp[1], kp[2], kp[3], kp[4])
    # outputs: centre 3:6, J 6:15 (column-major), gamma1 24, gravity torques 26:29
    v = np.zeros(3)
    for i in range(3):
        v[i] = kin[6 + i] * qd[0] + kin[9 + i] * qd[1] + kin[12 + i] * qd[2]
    s0, s1, s2, hit = 0.0, 0.0, 0.0, False
    for k in range(normals.shape[0]):
        if on[k]:
            s0, s1, s2, hit = s0 + normals[k, 0], s1 + normals[k, 1], s2 + normals[k, 2], True
    if hit:
        c3, s3 = math.cos(q[2]), math.sin(q[2])
        cg, sg = math.cos(kin[24]), math.sin(kin[24])
        n0 = -(c3 * sg * s0 - s3 * s1 + c3 * cg * s2)
        n1 = -(s3 * sg * s0 + c3 * s1 + s3 * cg * s2)
        n2 = -(-cg * s0 + sg * s2)
        nn = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
        st[0], st[1], st[2], st[3] = n0 / nn, n1 / nn, n2 / nn, 1.0
    kp_, kv_, fn = prm[7], prm[8], prm[6]
    e = np.zeros(3)
    for i in range(3):
        xd = prm[i] + prm[3 + i] * t if st[3] > 0.0 else prm[i]
        e[i] = kp_ * (xd - kin[3 + i]) + kv_ * (prm[3 + i] - v[i])
    if st[3] > 0.0:
        d = st[0] * e[0] + st[1] * e[1] + st[2] * e[2]
        for i in range(3):
            e[i] -= st[i] * d
    else:
        e[2] = -kv_ * v[2]
    for j in range(3):
        acc = 0.0
        for i in range(3):
            acc += kin[6 + 3 * j + i] * (e[i] - fn * st[i])
        tau[j] = acc + kin[26 + j]


class TipForceVelocityController:
    """Jacobian-transpose fingertip controller: press along the sensed normal, slide at a speed.

    The commanded tip force (WCS) is ``f = -f_n n_W + P_t (K_p (x_d - x) + K_v (v_d - v))``
    with ``n_W`` the OWTS contact normal (TCS -> WCS with the encoders, averaged over the
    5 kHz samples since the last call; ``+z`` before the first contact),
    ``P_t = I - n_W n_Wᵀ``, ``x``, ``v`` the tip centre and velocity from the encoders,
    ``x_d = x_0 + v_d t``; torques ``τ = Jᵀ f + g(θ)`` (gravity of the controller's own
    model). Before the first contact it holds ``x_0`` in the plane and presses down
    (``f = K_p (x_0 - x) + K_v (v_d - v)`` with the vertical part ``-K_v v_z``).

    Args:
        gm: the :class:`~robots.three_gm.ThreeGM`.
        start: (3,) tip-centre position at t = 0 [m]; velocity: (3,) desired velocity [m/s].
        normal_force: pressing force [N]; kp [N/m]; kv [N s/m].
        gravity: (3,) [m/s²] for the gravity compensation.
    """

    def __init__(
        self, gm, start, velocity, normal_force=0.3, kp=300.0, kv=3.0, gravity=(0, 0, -9.81)
    ):
        self.gm = gm
        self.start = checks.vector("start", start, 3, "m")
        self.vd = checks.vector("velocity", velocity, 3, "m/s")
        self.fn = checks.nonnegative("normal_force", normal_force, "N")
        self.kp = checks.nonnegative("kp", kp, "N/m")
        self.kv = checks.nonnegative("kv", kv, "N s/m")
        # the controller's own model (its own buffers)
        self.model = reduced_dynamics_function(gm, gravity, kinematics=True).clone()
        self._state = np.array([0.0, 0.0, 1.0, 0.0])  # n_W, touched
        self._prm = np.array([*self.start, *self.vd, self.fn, self.kp, self.kv])
        self._compiled = isinstance(self.model, CompiledFunction)
        self._none = (np.zeros((0, 3)), np.zeros(0, bool))

    @property
    def normal(self) -> np.ndarray:
        """(3,) the current estimate of the surface normal in the WCS."""
        return self._state[:3].copy()

    @property
    def touched(self) -> bool:
        """Whether the OWTS has reported a contact."""
        return bool(self._state[3])

    def __call__(self, t: float, obs) -> np.ndarray:
        r = obs.owts
        normals, on = (r.normal, r.in_contact) if r is not None else self._none
        if self._compiled:
            tau = np.empty(3)
            m = self.model
            tip_torques(
                obs.q, obs.qd, float(t), normals, on, self._state, self._prm, m.buffer,
                m.pointers, tau,
            )  # fmt: skip
            return tau
        return self.reference(t, obs.q, obs.qd, normals, on)

    def reference(self, t, q, qd, normals, on) -> np.ndarray:
        """The same law in numpy (no compiled code); updates the state like a call."""
        x, J, _, g1, _, grav = (np.array(o) for o in self.model(q))
        x, J, g1 = x.ravel(), J.reshape(3, 3), float(np.ravel(g1)[0])
        v = J @ qd
        if np.any(on):
            n_t = normals[on].sum(axis=0)
            n_w = -(tcs_rotation(g1, float(q[2])) @ n_t)  # surface normal = -tip normal
            self._state[:3] = n_w / math.sqrt(n_w @ n_w)
            self._state[3] = 1.0
        n = self._state[:3].copy()
        if self._state[3]:
            e = self.kp * (self.start + self.vd * t - x) + self.kv * (self.vd - v)
            e -= n * (n @ e)  # tangential part only
        else:  # approach: hold x, y, press down
            e = self.kp * (self.start - x) + self.kv * (self.vd - v)
            e[2] = -self.kv * v[2]
        return J.T @ (e - self.fn * n) + np.ravel(grav)
