"""Sensor readings of the planar world (issue 15, item 5).

* encoders: ``SensorSettings.encoder`` quantizes ``q``; the velocity estimate is ``qd``
  quantized to ``velocity_resolution``;
* strain gauges: the force each fingertip applies on what it touches (sum over its contacts
  of the last step, world frame), with the :class:`robots.sensors.ForceSensor` noise and
  quantization drawn from the world's seeded generator;
* tactile array of a flat fingertip: the 8x8 image of the actual contact pressure
  (:meth:`robots.sensors.TactileArray.sphere_images`) with the contact's position along the
  pad as ``u`` (``v = 0``: the plane of the hand cuts the pad's middle row) and the radius of
  the touching feature (1 mm for a corner, 1 m for a flat or gently curved piece).
"""

from __future__ import annotations

import math

import numpy as np

from planner.sim.observation import Observation, read_forces, read_joints
from planner.sim.planar.bodies import FREE, TIP

__all__ = ["observe"]

FINGERS = ("left", "right")


def _tip_forces(world):
    forces = np.zeros((2, 2))
    per_tip: list[list[tuple]] = [[], []]
    res = world._last
    if res is None:
        return forces, per_tip
    h = world.dt
    for k in range(len(res.gap)):
        if res.p_n[k] <= 0:
            continue
        n = res.normal[k]
        t = np.array([-n[1], n[0]])
        f_on_a = (res.p_n[k] * n + res.p_t[k] * t) / h
        for idx, sign in ((res.body_a[k], -1.0), (res.body_b[k], 1.0)):
            b = world.bodies[idx]
            if b.kind == TIP:
                forces[b.index] += sign * f_on_a
                point = res.point_a[k] if sign < 0 else res.point_b[k]
                per_tip[b.index].append((point, res.p_n[k] / h, res.curvature[k]))
    return forces, per_tip


def _tactile(world, per_tip):
    arr = world.sensors.tactile
    if arr is None or world.hand is None:
        return None
    out = {}
    P, _ = None, None
    for k, f in enumerate(FINGERS):
        if world.hand.hand.params.finger(f).tip != "flat":
            continue
        img = np.zeros((arr.rows, arr.cols))
        if per_tip[k]:
            _, tips = world.hand.frames(world.q)
            x, y, phi = tips[k]
            c, s = math.cos(phi), math.sin(phi)
            for point, fn, kappa in per_tip[k]:
                u = c * (point[0] - x) + s * (point[1] - y)
                radius = 1e-3 if math.isinf(kappa) else (1.0 if kappa < 1.0 else 1.0 / kappa)
                img += arr.sphere_images(np.array([u, 0.0]), radius, fn)
        out[f] = img
    del P
    return out


def observe(world, oracle: bool = False) -> Observation:
    """The :class:`Observation` of ``world`` now."""
    if world.hand is None:
        q = qd = np.zeros(0)
        forces = np.zeros((0, 2))
        fingers: tuple[str, ...] = ()
        tactile = None
    else:
        q, qd = read_joints(world.sensors, world.q, world.qd)
        true_f, per_tip = _tip_forces(world)
        forces = read_forces(world.sensors, true_f, world.rng)
        fingers = FINGERS
        tactile = _tactile(world, per_tip)
    truth = None
    if oracle:
        truth = {
            "q": world.q.copy(),
            "qd": world.qd.copy(),
            "poses": {b.name: world.pose(b.name) for b in world.bodies if b.kind == FREE},
            "velocities": {b.name: world.velocity(b.name) for b in world.bodies if b.kind == FREE},
            "contacts": world.contacts(),
        }
        if world.hand is not None:
            truth["tip_forces"] = _tip_forces(world)[0]
    return Observation(world.time, q, qd, fingers, forces, tactile, None, truth)
