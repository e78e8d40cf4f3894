"""Controller presets for the verification scenes of the planar world.

These are deliberately simple (the grasp controllers of ch. 2 live in ``planner.control``):
they read only the :class:`Observation` (quantized encoders, velocity estimate) and the
hand's model, never the simulator's state.

:class:`FingertipForceControl` is Jacobian-transpose force control with a fingertip
impedance per finger,

.. math:: \\tau_f = J_f(q)^T \\big(F_f + K (x_f^* - x_f(q)) - D J_f(q) \\dot q_f\\big)
          + g_f(q) + K_q (q_f^* - q_f) - D_q \\dot q_f
          + [1, 1, 1]^T (K_\\phi (\\phi^* - \\phi) - D_\\phi \\dot\\phi),

where ``F_f`` is the commanded contact force (e.g. the squeeze of a pinch), ``x_f^*`` the
fingertip set point (optionally moving at a constant velocity), ``g(q)`` the gravity torques
of the hand's Pinocchio model, the joint terms keep the posture and the last term holds the
fingertip orientation ``phi = q1 + q2 + q3`` (so a round tip does not roll).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin

from planner import checks
from planner.jit import njit
from planner.sim.planar.step_kernel import hand_dynamics, hand_kinematics
from robots.planar_hand import PlanarHand

__all__ = ["FingerTask", "FingertipForceControl"]


@dataclass(frozen=True)
class FingerTask:
    """What one finger does.

    Attributes:
        finger: ``"left"`` or ``"right"``.
        target: (2,) fingertip set point at t = 0 [m].
        force: (2,) commanded force on the touched object [N].
        velocity: (2,) set-point velocity [m/s].
        stiffness: fingertip stiffness K [N/m]; damping: D [N s/m].
        angle_stiffness: stiffness of the fingertip orientation about its value at t = 0
            [N m/rad] (keeps a round tip from rolling); angle_damping [N m s/rad].
    """

    finger: str
    target: tuple[float, float]
    force: tuple[float, float] = (0.0, 0.0)
    velocity: tuple[float, float] = (0.0, 0.0)
    stiffness: float = 200.0
    damping: float = 4.0
    angle_stiffness: float = 0.5
    angle_damping: float = 0.005

    def __post_init__(self) -> None:
        checks.choice("finger", self.finger, ("left", "right"))
        checks.vector("target", self.target, 2, "m")
        checks.vector("force", self.force, 2, "N")
        checks.vector("velocity", self.velocity, 2, "m/s")
        checks.nonnegative("stiffness", self.stiffness, "N/m")
        checks.nonnegative("damping", self.damping, "N s/m")
        checks.nonnegative("angle_stiffness", self.angle_stiffness, "N m/rad")
        checks.nonnegative("angle_damping", self.angle_damping, "N m s/rad")


@dataclass
class FingertipForceControl:
    """Jacobian-transpose fingertip force/impedance control of the planar hand.

    Args:
        hand: the hand (its Pinocchio model gives the gravity torques).
        tasks: one :class:`FingerTask` per controlled finger; other fingers hold ``q_ref``.
        q_ref: (6,) posture set point [rad].
        joint_stiffness: K_q [N m/rad]; joint_damping: D_q [N m s/rad].
        gravity: (2,) gravity of the world [m/s^2] (for the compensation).
    """

    hand: PlanarHand
    tasks: tuple[FingerTask, ...]
    q_ref: np.ndarray
    joint_stiffness: float = 0.02
    joint_damping: float = 0.01
    gravity: tuple[float, float] = (0.0, -9.81)
    _model: object = field(default=None, init=False, repr=False)
    _data: object = field(default=None, init=False, repr=False)

    def __post_init__(self) -> None:
        self.q_ref = checks.vector("q_ref", self.q_ref, 6, "rad")
        self._model = self.hand.model.copy()
        self._model.gravity.linear = np.array([self.gravity[0], self.gravity[1], 0.0])
        self._data = self._model.createData()
        self._phi0 = {
            k.finger: float(self.q_ref[self.hand.finger_slice(k.finger)].sum()) for k in self.tasks
        }

        from planner.sim.planar.step_kernel import hand_parameters

        lengths = [self.hand.params.finger(f).lengths[2] for f in ("left", "right")]
        self._packed = hand_parameters(self._model, lengths)
        self._tasks = np.array(
            [
                (
                    0.0 if k.finger == "left" else 1.0,
                    *k.target,
                    *k.force,
                    *k.velocity,
                    k.stiffness,
                    k.damping,
                    k.angle_stiffness,
                    k.angle_damping,
                    self._phi0[k.finger],
                )
                for k in self.tasks
            ],
            float,
        ).reshape(-1, 12)

    def __call__(self, t: float, obs) -> np.ndarray:
        """Joint torques (6,) [N m] at time ``t`` [s] from the observation's encoders
        (compiled: :func:`_task_torques`; :meth:`reference` is the same law in Python)."""
        return _task_torques(
            float(t), np.asarray(obs.q, float), np.asarray(obs.qd, float), self.q_ref,
            self.joint_stiffness, self.joint_damping, self.gravity[0], self.gravity[1],
            self._packed, self._tasks,
        )  # fmt: skip

    def reference(self, t: float, obs) -> np.ndarray:
        """The control law with the hand's Pinocchio model and Python kinematics."""
        q, qd = obs.q, obs.qd
        tau = np.array(pin.computeGeneralizedGravity(self._model, self._data, q))
        tau += self.joint_stiffness * (self.q_ref - q) - self.joint_damping * qd
        for task in self.tasks:
            sl = self.hand.finger_slice(task.finger)
            J = self.hand.jacobian(q, task.finger)
            x = self.hand.fingertip_pose(q, task.finger).position
            xs = np.asarray(task.target) + t * np.asarray(task.velocity)
            v = J @ qd[sl]
            F = (
                np.asarray(task.force)
                + task.stiffness * (xs - x)
                - task.damping * (v - np.asarray(task.velocity))
            )
            tau[sl] += J.T @ F
            phi, phid = float(q[sl].sum()), float(qd[sl].sum())
            tau[sl] += task.angle_stiffness * (self._phi0[task.finger] - phi)
            tau[sl] -= task.angle_damping * phid
        return tau


@njit(cache=True)
def _task_torques(t, q, qd, q_ref, kq, dq, gx, gy, P, tasks):
    """The control law of :class:`FingertipForceControl` (module docstring), compiled."""
    M = np.zeros((6, 6))
    tau = np.zeros(6)
    hand_dynamics(q, np.zeros(6), gx, gy, P, M, tau)  # bias at qd = 0: g(q)
    joints = np.zeros((2, 3, 2))
    tips = np.zeros((2, 3))
    hand_kinematics(q, P, joints, tips)
    for i in range(6):
        tau[i] += kq * (q_ref[i] - q[i]) - dq * qd[i]
    for k in range(tasks.shape[0]):
        f = int(tasks[k, 0])
        o = 3 * f
        x, y = tips[f, 0], tips[f, 1]
        J = np.zeros((2, 3))
        for j in range(3):
            J[0, j] = -(y - joints[f, j, 1])
            J[1, j] = x - joints[f, j, 0]
        vx = J[0, 0] * qd[o] + J[0, 1] * qd[o + 1] + J[0, 2] * qd[o + 2]
        vy = J[1, 0] * qd[o] + J[1, 1] * qd[o + 1] + J[1, 2] * qd[o + 2]
        xs, ys = tasks[k, 1] + t * tasks[k, 5], tasks[k, 2] + t * tasks[k, 6]
        K, D = tasks[k, 7], tasks[k, 8]
        Fx = tasks[k, 3] + K * (xs - x) - D * (vx - tasks[k, 5])
        Fy = tasks[k, 4] + K * (ys - y) - D * (vy - tasks[k, 6])
        phi = q[o] + q[o + 1] + q[o + 2]
        phid = qd[o] + qd[o + 1] + qd[o + 2]
        extra = tasks[k, 9] * (tasks[k, 11] - phi) - tasks[k, 10] * phid
        for j in range(3):
            tau[o + j] += J[0, j] * Fx + J[1, j] * Fy + extra
    return tau
