"""The verification scenes of the planar world, built in one place (tests, benchmark, the
``contact_sim`` scenario kind all use these).

Each builder returns ``(world, controller, info)``: ``controller`` is ``None`` for passive
scenes; ``info`` holds the closed-form expectations of the scene.
"""

from __future__ import annotations

import math

import numpy as np

from planner import checks
from planner.errors import HapexError
from planner.geometry import shapes
from planner.sim.observation import SensorSettings
from planner.sim.planar.presets import FingerTask, FingertipForceControl
from planner.sim.planar.world import PlanarWorld
from robots.planar_hand import PlanarHand

__all__ = ["incline_scene", "pinch_scene", "palm_roll_scene", "palm_hold_slide_scene"]


def incline_scene(
    shape: str = "box",
    angle: float = 0.3,
    friction: float = 0.5,
    mass: float = 0.1,
    size: float = 0.02,
    dt: float = 1e-3,
    gravity: float = 9.81,
    seed: int = 0,
) -> tuple[PlanarWorld, None, dict]:
    """A box (``size`` x ``size``/2) or a disc (radius ``size``) resting on an incline.

    ``info``: ``tangent`` (2,) down-slope... up-slope unit vector, the expected acceleration
    along it ``a`` [m/s^2], whether it ``sticks`` / ``rolls``, and the disc's expected
    angular acceleration ``alpha`` [rad/s^2].
    """
    a = checks.in_range("angle", angle, 0.0, math.pi / 2 - 1e-6, "rad")
    mu = checks.nonnegative("friction", friction)
    checks.choice("shape", shape, ("box", "disc"))
    g = checks.positive("gravity", gravity, "m/s^2")
    world = PlanarWorld(dt=dt, gravity=(0.0, -g), seed=seed, sensors=SensorSettings.ideal())
    world.add_fixed(shapes.plane(a, 1e3), friction=mu, name="incline")
    n = np.array([-math.sin(a), math.cos(a)])
    t = np.array([math.cos(a), math.sin(a)])
    info: dict = {"tangent": t, "normal": n}
    if shape == "box":
        c = 0.5 * size / 2 * n
        world.add_body(
            shapes.rounded_rectangle(size, size / 2), (c[0], c[1], a), mass, friction=mu, name="box"
        )
        sticks = math.tan(a) <= mu
        info.update(sticks=sticks, a=0.0 if sticks else -g * (math.sin(a) - mu * math.cos(a)))
    else:
        c = size * n
        world.add_body(shapes.circle(size), (c[0], c[1], 0.0), mass, friction=mu, name="disc")
        rolls = mu >= math.tan(a) / 3.0
        if rolls:
            acc, alpha = -2.0 / 3.0 * g * math.sin(a), 2.0 / 3.0 * g * math.sin(a) / size
        else:
            acc = -g * (math.sin(a) - mu * math.cos(a))
            alpha = 2.0 * mu * g * math.cos(a) / size
        info.update(rolls=rolls, a=acc, alpha=alpha, radius=size)
    return world, None, info


def _grip_q(hand: PlanarHand, finger: str, point, q0=None) -> np.ndarray:
    return hand.inverse_kinematics(finger, point, q0=q0)


def pinch_scene(
    squeeze: float = 2.0,
    friction: float = 1.0,
    mass: float = 0.1,
    radius: float = 0.03,
    height: float = 0.12,
    dt: float = 1e-3,
    seed: int = 0,
    sensors: SensorSettings | None = None,
    gravity=(0.0, -9.81),
) -> tuple[PlanarWorld, FingertipForceControl, dict]:
    """A disc held between two round fingertips by Jacobian-transpose force control.

    The fingertips squeeze the disc horizontally with ``squeeze`` [N] each and carry half its
    weight ``-m g / 2`` each (``gravity``: (2,) [m/s^2]); the grasp holds by friction iff
    ``mu (F - m |g_x| / 2) > m |g_y| / 2`` (``2 mu F > m g`` under vertical gravity).
    ``info``: ``holds``, ``squeeze`` [N], ``weight`` ``m |g|`` [N].
    """
    F = checks.positive("squeeze", squeeze, "N")
    mu = checks.nonnegative("friction", friction)
    m = checks.positive("mass", mass, "kg")
    R = checks.positive("radius", radius, "m")
    hand = PlanarHand(left_tip="round", right_tip="round", friction=mu)
    rt = hand.params.right.tip_radius
    xl, xr = np.array([-(R + rt), height]), np.array([R + rt, height])
    q = np.concatenate([_grip_q(hand, "left", xl), _grip_q(hand, "right", xr)])
    world = PlanarWorld(dt=dt, gravity=gravity, seed=seed, sensors=sensors)
    world.add_hand(hand, q)
    world.add_body(shapes.circle(R), (0.0, height, 0.0), m, friction=mu, name="disc")
    gx, gy = world.gravity
    wx, wy = -0.5 * m * gx, -0.5 * m * gy  # each fingertip's share of the weight [N]
    tasks = (
        FingerTask("left", tuple(xl), (F + wx, wy)),
        FingerTask("right", tuple(xr), (-F + wx, wy)),
    )
    ctrl = FingertipForceControl(hand, tasks, q, gravity=world.gravity)
    holds = mu * (F - abs(wx)) > abs(wy)
    return world, ctrl, {"holds": holds, "squeeze": F, "weight": m * math.hypot(gx, gy)}


SPREAD_LEFT = (0.5, -0.3, -0.8)  # the left finger spread away from the palm [rad]


def palm_roll_scene(
    radius: float = 0.0075,
    force: float = 0.5,
    speed: float = 0.02,
    friction: float = 1.0,
    mass: float = 0.02,
    dt: float = 1e-3,
    seed: int = 0,
    gravity=(0.0, -9.81),
) -> tuple[PlanarWorld, FingertipForceControl, dict]:
    """A disc on the palm rolled by the right round fingertip pressing down with ``force``
    [N] while its set point moves along +x at ``speed`` [m/s]; rolling on the palm and under
    the fingertip, the disc's centre moves at half that speed. One revolution moves the tip
    by ``4 pi radius`` (the default fits the finger's reach). ``gravity``: (2,) [m/s^2].
    ``info``: ``radius``, ``revolution_time`` [s]."""
    R = checks.positive("radius", radius, "m")
    Fn = checks.positive("force", force, "N")
    v = checks.positive("speed", speed, "m/s")
    hand = PlanarHand(friction=friction)
    rt = hand.params.right.tip_radius
    x0 = -2.0 * math.pi * R
    tip = np.array([x0, 2 * R + rt])
    q = np.concatenate([SPREAD_LEFT, _grip_q(hand, "right", tip)])
    world = PlanarWorld(dt=dt, gravity=gravity, seed=seed)
    world.add_hand(hand, q)
    world.add_body(shapes.circle(R), (x0, R, 0.0), mass, friction=friction, name="disc")
    task = FingerTask("right", tuple(tip), (0.0, -Fn), (v, 0.0), stiffness=300.0, damping=3.0)
    ctrl = FingertipForceControl(hand, (task,), q, gravity=world.gravity)
    return world, ctrl, {"radius": R, "revolution_time": 2 * math.pi * R / (v / 2)}


def _pad_on_ball(hand: PlanarHand, centre: np.ndarray, R: float) -> tuple[np.ndarray, np.ndarray]:
    """Left flat pad touching the ball at the contact angle (100..150 deg) whose joint
    solution stays farthest from the joint limits: (q_left (3,), contact point (2,))."""
    lim = hand.finger_limits("left")
    best, best_margin = None, -1.0
    for deg in np.arange(150.0, 100.0, -2.0):
        a = math.radians(deg)
        p = centre + R * np.array([math.cos(a), math.sin(a)])
        axis = (centre - p) / R  # the pad's outward normal points into the ball
        phi = math.atan2(-axis[0], axis[1])
        try:
            q = hand.inverse_kinematics("left", p, angle=phi)
        except HapexError:
            continue
        margin = float(np.min(np.minimum(q - lim[:, 0], lim[:, 1] - q)))
        if margin > best_margin:
            best, best_margin = (q, p), margin
    if best is None:  # pragma: no cover - the default hand reaches it
        raise HapexError("the left pad cannot reach the ball")
    return best


def palm_hold_slide_scene(
    radius: float = 0.05,
    force: float = 2.0,
    slide_force: float = 0.3,
    slide_speed: float = 0.01,
    friction: float = 1.0,
    mass: float = 0.1,
    dt: float = 1e-3,
    seed: int = 0,
    gravity=(0.0, -9.81),
) -> tuple[PlanarWorld, FingertipForceControl, dict]:
    """The full hand: the flat left pad presses a ball against the palm with ``force`` [N]
    while the right round fingertip, pressing with ``slide_force`` [N], slides along the
    ball's top at ``slide_speed`` [m/s]. ``gravity``: (2,) [m/s^2]. ``info``: ``radius``, the
    left pad's ``pad_point``."""
    R = checks.positive("radius", radius, "m")
    F = checks.positive("force", force, "N")
    Fs = checks.positive("slide_force", slide_force, "N")
    hand = PlanarHand(friction=friction)
    rt = hand.params.right.tip_radius
    c = np.array([0.0, R])
    ql, lp = _pad_on_ball(hand, c, R)
    rp = c + (R + rt) * np.array([math.cos(1.2), math.sin(1.2)])
    q = np.concatenate([ql, _grip_q(hand, "right", rp)])
    world = PlanarWorld(dt=dt, gravity=gravity, seed=seed)
    world.add_hand(hand, q)
    world.add_body(shapes.circle(R), (0.0, R, 0.0), mass, friction=friction, name="ball")
    nl = (c - lp) / np.linalg.norm(c - lp)
    nr = (c - rp) / np.linalg.norm(c - rp)
    tr = np.array([-nr[1], nr[0]])
    tasks = (
        FingerTask("left", tuple(lp), tuple(F * nl)),
        FingerTask("right", tuple(rp), tuple(Fs * nr), tuple(slide_speed * tr), 300.0, 3.0),
    )
    ctrl = FingertipForceControl(hand, tasks, q, gravity=world.gravity)
    return world, ctrl, {"radius": R, "pad_point": lp}
