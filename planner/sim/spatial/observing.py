"""What the spatial world's controller observes (the sensors of the 3GM, issue 15 item 5).

:func:`observe` turns the finger's state into an :class:`~planner.sim.observation.Observation`:
encoders, the fingertip force sensor and the OWTS samples of the steps since the last call.
After a compiled step everything is read in one compiled call
(:func:`planner.sim.spatial.kernel.finger_readings`: the same random draws and numbers as the
numpy readers :func:`~planner.sim.observation.read_joints`,
:func:`~planner.sim.observation.read_forces` and :meth:`.sensing.OWTSRecorder.read`, which
serve the general path; tested equal).
"""

from __future__ import annotations

import numpy as np

from planner.sim.observation import Observation, read_forces, read_joints
from planner.sim.spatial.kernel import finger_readings
from planner.sim.spatial.sensing import FULL_INTENSITY_FORCE, OWTSReading

__all__ = ["observe", "record_owts", "sense_params", "tip_force"]


def record_owts(world, contacts) -> None:
    """Record the tip's strongest contact for the OWTS samples of the step (general path)."""
    f = world.finger
    mine = [c for c in contacts if c.bodies[0] == f.name]
    if mine:
        c = max(mine, key=lambda c: c.normal_force)
        R = f.tcs()
        n = c.normal.tolist()
        ft = c.tangential_force.tolist()
        n_t = [-(R[0, j] * n[0] + R[1, j] * n[1] + R[2, j] * n[2]) for j in range(3)]
        f_t = [R[0, j] * ft[0] + R[1, j] * ft[1] + R[2, j] * ft[2] for j in range(3)]
        inten = min(c.normal_force / FULL_INTENSITY_FORCE, 1.0)
    else:
        n_t, inten, f_t = (0.0, 0.0, 0.0), 0.0, (0.0, 0.0, 0.0)
    world._owts.advance(world.time, n_t, inten, f_t)


def tip_force(world) -> np.ndarray:
    """(3,) force the tip applies on what it touches [N] (WCS)."""
    f = world.finger
    force = np.zeros(3)
    for c in world.contacts():
        if c.bodies[0] == f.name:
            force -= c.normal_force * c.normal + c.tangential_force
    return force


def sense_params(world) -> np.ndarray | None:
    """Packed sensor settings of :func:`.kernel.joint_force_readings` (None: sensors the
    kernel does not model; the numpy readers run)."""
    if world._sense is False:
        from robots.sensors import Encoder, ForceSensor

        s = world.sensors
        enc, fs = s.encoder, s.force
        ok = (enc is None or type(enc) is Encoder) and (fs is None or type(fs) is ForceSensor)
        world._sense = None
        if ok:
            world._sense = np.array(
                [
                    0.0 if enc is None else enc.resolution,
                    s.velocity_resolution,
                    0.0 if fs is None else fs.resolution,
                    0.0,  # set per call: whether finger.x holds the contact
                    0.0 if fs is None else fs.noise_std,
                    1.0 if fs is not None and fs.noise_std > 0 else 0.0,
                ]
            )
    return world._sense


def observe(world, oracle: bool = False) -> Observation:
    """Sensor readings: 3GM encoders (θ1, θ2, θ3) [rad] and rates [rad/s], the fingertip
    force sensor (``tip_forces`` (1, 3): force the tip applies on the surface, WCS [N]),
    and ``owts``: the :class:`~planner.sim.spatial.OWTSReading` of the 5 kHz samples since
    the previous call. ``truth`` (oracle only): poses, velocities, joints, contacts."""
    truth = None
    if oracle:
        truth = {
            "poses": {b: world.pose(b) for b in world.body_names},
            "velocities": {b: world.velocity(b) for b in world.body_names},
            "joints": world.joint_state(),
            "contacts": world.contacts(),
        }
    if world.finger is None:
        return Observation(world.time, np.zeros(0), np.zeros(0), truth=truth)
    f = world.finger
    prm = sense_params(world) if world._from_kernel or not world.contacts() else None
    if prm is None:  # the numpy readers (general path, or sensors the kernel lacks)
        q, qd = read_joints(world.sensors, f.th, f.thd)
        tip = read_forces(world.sensors, tip_force(world)[None, :], world.rng)
        return Observation(world.time, q, qd, (f.name,), tip, None, world._owts.read(), truth)
    # one compiled call for encoders, force sensor and OWTS (same draws, same numbers)
    rec = world._owts
    k = int(rec.state[1])
    nf = 3 if prm[5] else 0
    z = world.rng.standard_normal(nf + 2 * k) if nf or k else world._zero3
    prm[3] = 1.0 if world._from_kernel else 0.0
    out, on = np.empty(9 + 11 * k), np.empty(k, np.bool_)
    finger_readings(f.x, z, nf, prm, rec.rows, rec.times, k, rec._params, rec._sigma, out, on)
    rec.state[1] = 0.0
    owts = OWTSReading(
        out[9 : 9 + k],
        out[9 + k : 9 + 5 * k].reshape(k, 4),
        out[9 + 5 * k : 9 + 8 * k].reshape(k, 3),
        out[9 + 8 * k :].reshape(k, 3),
        on,
    )
    q, qd, tip = out[0:3], out[3:6], out[6:9].reshape(1, 3)
    return Observation(world.time, q, qd, (f.name,), tip, None, owts, truth)
