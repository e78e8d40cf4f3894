"""The 3GM as a Pinocchio model: a kinematic tree plus a loop-closure constraint (App. C.2).

Tree (joint order of ``q``, nq == 5): ``theta3`` (base rotation about the vertical z axis),
``theta1`` (motor 1), ``gamma1`` (passive, relative angle γ1 - θ1, carries the distal link),
``theta2`` (motor 2), ``gamma2`` (passive, relative angle γ2 - θ2, carries link l3). The two
motor joints sit in the five-bar plane, rotated by ``Rx(π/2)`` so that their local z axis is
normal to the plane and local (x, y) are the in-plane (r, z) coordinates of eqs. C.4-C.6.
Frames: ``endpoint`` (l5 along the distal link), ``closure_a`` (l4 along the distal link),
``closure_b`` (l3 along link l3). The loop closes where ``closure_a == closure_b``; the
constraint is also provided as a ``pin.RigidConstraintModel`` (CONTACT_3D between the two
joints) for Pinocchio's constrained algorithms.

Dynamics (the thesis gives no masses; values and reasons in :mod:`robots.three_gm.params`):
uniform rods of ``LINK_MASSES`` along each link (``l1`` on theta1, ``l2`` on theta2, ``l3``
on gamma2, the distal link ``l5`` on gamma1), the fingertip sphere ``FINGERTIP_MASS`` at the
endpoint, the rotating base ``BASE_INERTIA`` on theta3, and the motors' reflected rotor
inertia ``MOTOR_ARMATURE`` as Pinocchio ``armature`` of the actuated joints. Gravity is
Pinocchio's default ``(0, 0, -9.81)`` m/s² (the WCS z axis is vertical, up).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from planner.errors import SingularConfiguration
from robots.three_gm.params import (
    BASE_INERTIA,
    FINGERTIP_MASS,
    LINK_MASSES,
    MOTOR_ARMATURE,
)

JOINTS = ("theta3", "theta1", "gamma1", "theta2", "gamma2")
ACTUATED = (1, 3, 0)  # q indices of (θ1, θ2, θ3)
PASSIVE = (2, 4)
FINGERTIP_RADIUS = 0.008  # [m] radius of the fingertip sphere used for its inertia


def _rot_x(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _rod_x(mass: float, length: float) -> pin.Inertia:
    """A uniform rod of ``mass`` [kg] and ``length`` [m] along the local x axis."""
    i = mass * length**2 / 12.0
    return pin.Inertia(mass, np.array([length / 2, 0.0, 0.0]), np.diag([1e-9 * mass, i, i]))


def _distal(p: dict[str, float]) -> pin.Inertia:
    """The distal link (rod of length l5) plus the fingertip sphere at its end."""
    tip_i = 0.4 * FINGERTIP_MASS * FINGERTIP_RADIUS**2
    tip = pin.Inertia(FINGERTIP_MASS, np.array([p["l5"], 0.0, 0.0]), np.eye(3) * tip_i)
    return _rod_x(LINK_MASSES["l5"], p["l5"]) + tip


def build_model(p: dict[str, float], joint_limits: np.ndarray) -> pin.Model:
    """Build the tree model of the 3GM.

    Args:
        p: parameters ``l1..l5, h1..h3`` [m].
        joint_limits: (3, 2) limits of (θ1, θ2, θ3) [rad]; passive joints are unlimited.
    """
    m = pin.Model()
    m.name = "three_gm"
    big = np.array([4 * np.pi])
    eff, vel = np.array([5.0]), np.array([20.0])

    def add(parent, name, placement, lo, hi, inertia):
        jid = m.addJoint(
            parent, pin.JointModelRZ(), placement, name, eff, vel, np.array([lo]), np.array([hi])
        )
        if inertia is not None:
            m.appendBodyToJoint(jid, inertia, pin.SE3.Identity())
        return jid

    plane = _rot_x(np.pi / 2)
    lim = np.asarray(joint_limits, float)
    base = pin.Inertia(0.0, np.zeros(3), np.diag([0.0, 0.0, BASE_INERTIA]))
    j3 = add(0, "theta3", pin.SE3.Identity(), lim[2, 0], lim[2, 1], base)
    j1 = add(
        j3,
        "theta1",
        pin.SE3(plane, np.array([p["h2"], -p["h3"], 0.0])),
        lim[0, 0],
        lim[0, 1],
        _rod_x(LINK_MASSES["l1"], p["l1"]),
    )
    g1 = add(
        j1,
        "gamma1",
        pin.SE3(np.eye(3), np.array([p["l1"], 0.0, 0.0])),
        -big[0],
        big[0],
        _distal(p),
    )
    j2 = add(
        j3,
        "theta2",
        pin.SE3(plane, np.array([p["h2"], -p["h3"], -p["h1"]])),
        lim[1, 0],
        lim[1, 1],
        _rod_x(LINK_MASSES["l2"], p["l2"]),
    )
    g2 = add(
        j2,
        "gamma2",
        pin.SE3(np.eye(3), np.array([p["l2"], 0.0, 0.0])),
        -big[0],
        big[0],
        _rod_x(LINK_MASSES["l3"], p["l3"]),
    )
    arm = np.zeros(m.nv)
    for jid, a in zip((j1, j2, j3), MOTOR_ARMATURE, strict=True):
        arm[m.idx_vs[jid]] = a
    m.armature = arm
    for name, jid, d in (
        ("endpoint", g1, p["l5"]),
        ("closure_a", g1, p["l4"]),
        ("closure_b", g2, p["l3"]),
    ):
        m.addFrame(
            pin.Frame(
                name, jid, pin.SE3(np.eye(3), np.array([d, 0.0, 0.0])), pin.FrameType.OP_FRAME
            )
        )
    return m


def closure_constraint(model: pin.Model, p: dict[str, float]) -> pin.RigidConstraintModel:
    """The loop closure as a Pinocchio CONTACT_3D constraint between gamma1 and gamma2."""
    ja, jb = model.getJointId("gamma1"), model.getJointId("gamma2")
    return pin.RigidConstraintModel(
        pin.ContactType.CONTACT_3D,
        model,
        ja,
        pin.SE3(np.eye(3), np.array([p["l4"], 0, 0.0])),
        jb,
        pin.SE3(np.eye(3), np.array([p["l3"], 0, 0.0])),
        pin.ReferenceFrame.LOCAL,
    )


def configuration(theta: np.ndarray, gamma1: float, gamma2: float) -> np.ndarray:
    """(5,) tree configuration q from θ (3,) and the passive angles [rad]."""
    t1, t2, t3 = theta
    return np.array([t3, t1, gamma1 - t1, t2, gamma2 - t2])


@dataclass(frozen=True)
class PinKinematics:
    """Endpoint kinematics computed with Pinocchio on the closed loop.

    Attributes:
        q: (5,) tree configuration with the loop closed [rad].
        position: (3,) endpoint in the WCS [m].
        jacobian: (3, 3) d endpoint / d(θ1, θ2, θ3) [m/rad].
        closure_residual: distance between the two closure frames [m].
    """

    q: np.ndarray
    position: np.ndarray
    jacobian: np.ndarray
    closure_residual: float


def _frames(model, data, q):
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    ids = [model.getFrameId(n) for n in ("endpoint", "closure_a", "closure_b")]
    pos = [data.oMf[i].translation.copy() for i in ids]
    jac = [pin.getFrameJacobian(model, data, i, pin.LOCAL_WORLD_ALIGNED)[:3] for i in ids]
    return pos, jac


def solve_closed_loop(
    model: pin.Model,
    theta: np.ndarray,
    q_guess: np.ndarray | None = None,
    tol: float = 1e-13,
    max_iter: int = 50,
) -> PinKinematics:
    """Close the loop with Pinocchio (Newton on the passive joints) and differentiate it.

    The closure Jacobian ``J_c = J_a - J_b`` splits into actuated and passive columns; the
    passive velocities follow from ``J_c,p q̇_p = -J_c,a θ̇`` and the endpoint Jacobian is
    ``J = J_e,a + J_e,p dq_p/dθ``.

    Raises:
        SingularConfiguration: Newton did not close the loop (no closure or l3 ∥ l4).
    """
    data = model.createData()
    q = np.zeros(5) if q_guess is None else np.array(q_guess, float)
    q[list(ACTUATED)] = theta
    act, pas = list(ACTUATED), list(PASSIVE)
    for _ in range(max_iter):
        pos, jac = _frames(model, data, q)
        res = pos[1] - pos[2]
        if np.linalg.norm(res) < tol:
            break
        Jc = jac[1] - jac[2]
        q[pas] -= np.linalg.lstsq(Jc[:, pas], res, rcond=None)[0]
    pos, jac = _frames(model, data, q)
    res = float(np.linalg.norm(pos[1] - pos[2]))
    Jc = jac[1] - jac[2]
    if res > 1e-9 or np.linalg.matrix_rank(Jc[:, pas], tol=1e-10) < 2:
        raise SingularConfiguration(
            f"Pinocchio could not close the 3GM loop at theta = "
            f"{np.asarray(theta).tolist()} rad (residual {res:.3g} m)",
            value=res,
        )
    dqp = -np.linalg.lstsq(Jc[:, pas], Jc[:, act], rcond=None)[0]
    J = jac[0][:, act] + jac[0][:, pas] @ dqp
    return PinKinematics(q, pos[0], J, res)
