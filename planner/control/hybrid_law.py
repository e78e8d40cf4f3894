"""Hybrid force/velocity control of the 3GM with the OWTS (thesis §4.3, App. C.2.2).

PD control parallel to the surface, open-loop force along the sensed contact normal, gravity
compensation and ``τ = Jᵀ f`` within the motor limits - the law of eqs. 4.1-4.13 as one
controller callable ``controller(t, observation) -> τ`` for :mod:`planner.sim`. The step
itself is compiled (:func:`planner.control.hybrid_kernel.hybrid_step`);
:mod:`planner.control.hybrid_reference` is the same law in plain numpy.
``HybridSettings.control`` selects the normal-force variant: the open loop of the thesis, a PI
loop on the sensed normal force, or a QP that respects the torque limits keeping the normal
force first (:mod:`planner.control.hybrid_variants`).

Usage::

    ctl = HybridController(ThreeGM(), HybridSettings(normal_force=0.3))
    ctl.command_velocity([0.01, 0.0, 0.0])   # desired contact-point velocity [m/s]
    log = world.run(2.0, controller=ctl)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.control import hybrid_kernel as hk
from planner.control.hybrid_frames import SWITCH_SIN2
from planner.control.hybrid_variants import FORCE_CONTROLS, TorqueLimitQP
from planner.errors import InvalidParameter

__all__ = [
    "GRAVITY_MODES",
    "HybridController",
    "HybridSettings",
    "force_parameters",
    "owts_voltages",
    "tip_force",
]

GRAVITY_MODES = ("model", "c11", "none")
G = 9.81  # [m/s^2]


@dataclass(frozen=True)
class HybridSettings:
    """Gains and options of the hybrid law (all validated at construction).

    Attributes:
        kp: stiffness parallel to the surface ``k_p`` of eq. 4.10 [N/m].
        kv: damping parallel to the surface ``k_v`` of eq. 4.10 [N s/m].
        normal_force: desired normal force ``f_des`` of eq. 4.12 [N].
        alpha: weight of the new normal sample in the low-pass filter of eq. 4.2 [-].
        rate: servo frequency ``ω`` of eq. 4.9 [Hz].
        ramp: slope of the linear ramp of the desired velocity (eq. 4.9 text) [m/s²].
        tip_radius: fingertip radius ``R_f`` of eq. 4.7 [m].
        gravity: ``"model"`` (gradient of the weights of the bodies of the finger's Pinocchio
            model - links and fingertip - exact for the rigid model), ``"c11"`` (the thesis'
            ``τ_g = M g l5 cos θ1``, eq. C.11) or ``"none"``.
        tip_mass: extra mass at the endpoint beyond the model's (a payload) [kg].
        c11_mass: ``M`` of eq. C.11 [kg] (used when ``gravity == "c11"``).
        max_error: bound of the tangential tracking error; the desired point is dragged
            along beyond it (wind-up guard) [m].
        control: normal-force variant, one of :data:`~planner.control.hybrid_variants.
            FORCE_CONTROLS`: ``"open_loop"`` (eq. 4.12), ``"closed_loop"`` (PI on the sensed
            normal force) or ``"qp"`` (torque limits by a QP that keeps the normal force).
        force_kp: proportional gain of the closed-loop variant [-] (N per N of error).
        force_ki: integral gain of the closed-loop variant [1/s].
        force_imax: bound of the closed-loop integral [N s].
        force_max: largest normal force the closed loop may command [N] (None: 3 f_des).
        qp_weights: ``(w_t, w_n)`` weights of the tangential and normal force errors of the
            QP variant [1/N²] (``w_n >> w_t``: the normal force goes first).
    """

    kp: float = 300.0
    kv: float = 4.0
    normal_force: float = 0.3
    alpha: float = 0.05
    rate: float = 1000.0
    ramp: float = 0.1
    tip_radius: float = 0.008
    gravity: str = "model"
    tip_mass: float = 0.0
    c11_mass: float = 0.1
    max_error: float = 0.003
    control: str = "open_loop"
    force_kp: float = 0.2
    force_ki: float = 50.0
    force_imax: float = 0.01
    force_max: float | None = None
    qp_weights: tuple[float, float] = (1.0, 100.0)

    def __post_init__(self) -> None:
        checks.nonnegative("kp", self.kp, "N/m")
        checks.nonnegative("kv", self.kv, "N s/m")
        checks.nonnegative("normal_force", self.normal_force, "N")
        checks.in_range("alpha", self.alpha, 0.0, 1.0, closed=(False, True))
        checks.positive("rate", self.rate, "Hz")
        checks.positive("ramp", self.ramp, "m/s^2")
        checks.positive("tip_radius", self.tip_radius, "m")
        checks.choice("gravity", self.gravity, GRAVITY_MODES)
        checks.nonnegative("tip_mass", self.tip_mass, "kg")
        checks.nonnegative("c11_mass", self.c11_mass, "kg")
        checks.positive("max_error", self.max_error, "m")
        checks.choice("control", self.control, FORCE_CONTROLS)
        checks.nonnegative("force_kp", self.force_kp)
        checks.nonnegative("force_ki", self.force_ki, "1/s")
        checks.nonnegative("force_imax", self.force_imax, "N s")
        if self.force_max is None:
            object.__setattr__(self, "force_max", 3.0 * self.normal_force)
        checks.nonnegative("force_max", self.force_max, "N")
        w = checks.vector("qp_weights", self.qp_weights, 2)
        checks.positive("qp_weights[0]", w[0])
        checks.positive("qp_weights[1]", w[1])
        object.__setattr__(self, "qp_weights", (float(w[0]), float(w[1])))


def body_weights(finger) -> tuple[np.ndarray, np.ndarray]:
    """Weights m g [N] (4,) and in-plane centres of mass (4, 2) [m] of the bodies carried by
    theta1, gamma1 (distal link with the fingertip), theta2, gamma2 in the finger's Pinocchio
    model, in their joint frames (x along the link, y in the five-bar plane)."""
    m = finger.model
    w, c = [], []
    for name in ("theta1", "gamma1", "theta2", "gamma2"):
        inertia = m.inertias[m.getJointId(name)]
        w.append(float(inertia.mass) * G)
        c.append(np.asarray(inertia.lever, float)[:2])
    return np.array(w), np.array(c)


def kernel_parameters(finger, settings: HybridSettings, owts=None) -> np.ndarray:
    """The (NPAR,) parameter vector of :func:`~planner.control.hybrid_kernel.hybrid_step`."""
    from robots.sensors import OWTS

    s = settings
    sensor = owts if owts is not None else OWTS(radius=s.tip_radius)
    p = finger.params
    par = np.zeros(hk.NPAR)
    par[: hk.P_KP] = [p[k] for k in ("l1", "l2", "l3", "l4", "l5", "h1", "h2", "h3")]
    par[hk.P_KP : hk.P_RTIP] = [s.kp, s.kv, s.normal_force, s.alpha, s.rate, s.ramp]
    par[hk.P_RTIP] = s.tip_radius
    par[hk.P_OWTS_HALF] = 0.5 * sensor.psd_side
    par[hk.P_OWTS_K] = sensor.scale
    par[hk.P_OWTS_XO], par[hk.P_OWTS_YO] = sensor.offsets
    par[hk.P_OWTS_THR] = sensor.contact_threshold
    if s.gravity == "model":
        par[hk.P_G1 : hk.P_GT], com = body_weights(finger)
        par[hk.P_C1X : hk.P_C3Y + 1] = com.ravel()
        par[hk.P_GT] = s.tip_mass * G
    elif s.gravity == "c11":
        par[hk.P_GC11] = s.c11_mass * G
    par[hk.P_TAU1 : hk.P_TAU3 + 1] = finger.torque_limits
    par[hk.P_SWITCH] = SWITCH_SIN2
    par[hk.P_EMAX] = s.max_error
    return par


def force_parameters(settings: HybridSettings) -> np.ndarray:
    """The (NFPAR,) gains of :func:`~planner.control.hybrid_kernel.normal_force_pi`."""
    f = np.zeros(hk.NFPAR)
    f[hk.F_KP], f[hk.F_KI] = settings.force_kp, settings.force_ki
    f[hk.F_IMAX], f[hk.F_FMAX] = settings.force_imax, settings.force_max
    return f


def tip_force(obs, out: np.ndarray) -> np.ndarray:
    """Write the sensed fingertip force (3,) [N] of an observation into ``out`` (the first
    row of ``obs.tip_forces``: force the tip applies on the surface; zeros without one)."""
    f = getattr(obs, "tip_forces", None)
    if f is None or len(f) == 0 or np.shape(f)[-1] != 3:
        out[:] = 0.0
    else:
        out[:] = f[0]
    return out


def owts_voltages(obs, out: np.ndarray, threshold: float = 1e-3) -> np.ndarray:
    """Write the OWTS voltages (4,) [V] of an observation into ``out`` (zeros: no contact).

    Accepts ``obs.owts`` as None, a (4,) or (k, 4) voltage array, or an object with a
    ``voltages`` attribute of those shapes (:class:`planner.sim.spatial.sensing.OWTSReading`).
    The k samples taken at 5 kHz since the last 1 kHz observation are averaged over those in
    contact (total light above ``threshold``) - the oversampling App. C.1.2 allows.
    """
    o = getattr(obs, "owts", None)
    if o is None:
        out[:] = 0.0
        return out
    a = np.asarray(getattr(o, "voltages", o), dtype=float)
    if a.ndim == 1:
        out[:] = a
        return out
    on = a.sum(axis=1) > threshold if len(a) else np.zeros(0, bool)
    out[:] = a[on].mean(axis=0) if on.any() else 0.0
    return out


class HybridController:
    """The hybrid force/velocity law as a controller callable (eqs. 4.1-4.13, C.10-C.11).

    Args:
        finger: the :class:`robots.three_gm.ThreeGM`.
        settings: :class:`HybridSettings`.
        owts: the :class:`robots.sensors.OWTS` whose voltages the observations carry
            (default ``OWTS(radius=settings.tip_radius)``).

    After each call, :attr:`out` holds the step's outputs (see :mod:`hybrid_kernel`); the
    properties below read them. ``settings.control`` selects the normal-force variant
    (:mod:`planner.control.hybrid_variants`).
    """

    def __init__(self, finger, settings: HybridSettings | None = None, owts=None) -> None:
        self.finger = finger
        self.settings = settings or HybridSettings()
        self.par = kernel_parameters(finger, self.settings, owts)
        self.state = np.zeros(12)
        self.target = np.zeros(3)
        self.out = np.zeros(hk.NOUT)
        self.mode = self.settings.control
        self.fpar = force_parameters(self.settings)
        self.fstate = np.zeros(hk.NFSTATE)
        self.qp = (
            TorqueLimitQP(finger.torque_limits, self.settings.qp_weights)
            if self.mode == "qp"
            else None
        )
        self._force = np.zeros(3)
        self._volts = np.zeros(4)
        self._anchored = False
        self.saturated_steps = 0

    # ------------------------------------------------------------------ commands
    def command_velocity(self, velocity) -> None:
        """Set the desired contact-point velocity [m/s] (WCS); reached by the linear ramp."""
        self.target[:] = checks.vector("velocity", velocity, 3, "m/s")

    def set_normal_force(self, force: float) -> None:
        """Change ``f_des`` of eq. 4.12 [N]."""
        self.par[hk.P_FN] = checks.nonnegative("normal_force", force, "N")

    def reanchor(self) -> None:
        """Put the desired point back on the current contact point (at the next step)."""
        self._anchored = False

    def stop(self) -> None:
        """Command zero velocity and drop the ramped velocity at once."""
        self.target[:] = 0.0
        self.state[6:12] = 0.0

    # ------------------------------------------------------------------ the step
    def step(self, theta, theta_dot, volts, force=None) -> np.ndarray:
        """One servo period from raw readings; returns τ (3,) [N m] (a view of ``out``).

        Args:
            theta, theta_dot: (3,) encoder angles [rad] and rates [rad/s].
            volts: (4,) OWTS voltages [V].
            force: (3,) sensed fingertip force on the surface [N] (closed loop only).
        """
        self.anchor(theta)
        if self.mode == "closed_loop":
            f = self._force if force is None else np.asarray(force, dtype=float)
            hk.hybrid_step_closed_loop(
                theta, theta_dot, volts, f, self.state, self.fstate, self.target, self.par,
                self.fpar, self.out,
            )  # fmt: skip
        else:
            hk.hybrid_step(theta, theta_dot, volts, self.state, self.target, self.par, self.out)
            if self.qp is not None:
                self.qp.apply(self.out, self.state[:3])
        if self.out[13]:
            self.saturated_steps += 1
        return self.out[:3]

    def __call__(self, t: float, obs) -> np.ndarray:
        q = np.asarray(obs.q, dtype=float)
        qd = np.asarray(obs.qd, dtype=float)
        volts = owts_voltages(obs, self._volts)
        return self.step(q, qd, volts, tip_force(obs, self._force)).copy()

    def anchor(self, theta) -> None:
        """Put the desired point on the contact point at ``theta`` (3,) [rad] when a
        :meth:`reanchor` (or the first step) asks for it; the compiled step's callers call
        this before :func:`~planner.control.hybrid_kernel.hybrid_step`."""
        if not self._anchored:
            self._anchor(theta)

    def _anchor(self, theta) -> None:
        st = self.finger.state(theta)
        from planner.control.hybrid_frames import tcs_rotation

        pole = tcs_rotation(st.gamma1, float(theta[2]))[:, 2]
        if not self.state[:3].any():
            self.state[:3] = pole
        n = self.state[:3]
        self.state[3:6] = st.position + self.settings.tip_radius * n
        self._anchored = True

    # ------------------------------------------------------------------ read-outs
    @property
    def normal(self) -> np.ndarray:
        """(3,) filtered contact normal n_W (into the surface) [-]."""
        return self.state[:3].copy()

    @property
    def contact_point(self) -> np.ndarray:
        """(3,) estimated contact point x of eq. 4.7 [m]."""
        return self.out[3:6].copy()

    @property
    def tip_center(self) -> np.ndarray:
        """(3,) fingertip centre x_f [m]."""
        return self.out[6:9].copy()

    @property
    def in_contact(self) -> bool:
        """Whether the OWTS reported a contact at the last step."""
        return bool(self.out[12])

    @property
    def saturated(self) -> bool:
        """Whether the last step's torques were limited (App. C.2.1 torque limits)."""
        return bool(self.out[13])


def check_force_feasible(finger, theta, normal_force: float, margin: float = 0.8) -> None:
    """Raise :class:`InvalidParameter` when ``normal_force`` [N] exceeds ``margin`` times the
    force the motors can apply in every direction at ``theta`` (App. C.2.1)."""
    cap = finger.force_capacity(theta)
    if normal_force > margin * cap:
        raise InvalidParameter(
            f"normal_force: expected at most {margin * cap:.3g} N ({margin:g} x the force "
            f"capacity {cap:.3g} N of the 3GM at this pose), got {normal_force!r}"
        )
