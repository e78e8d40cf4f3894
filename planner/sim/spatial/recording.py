"""Log rows of the spatial world (:meth:`planner.sim.world.WorldBase.record`'s rows, faster).

After a compiled step the row is written by one compiled call, :func:`record_row`, from the
finger's state vector (its pose, velocity, joints, torque and contact); otherwise from the
bodies and the contact records.
"""

from __future__ import annotations

import math

import numpy as np

from planner.sim.spatial import step_kernel as sk
from planner.sim.spatial.step_kernel import (
    ACT,
    FN,
    FT,
    G1,
    GAP,
    JW,
    NRM,
    PT,
    SLIP,
    TH,
    THD,
    C,
    J,
    njit,
)

__all__ = ["record", "record_row"]


def record(world, log, k: int, tau: np.ndarray) -> None:
    """Write the current state into row ``k`` of ``log`` (a faster
    :meth:`WorldBase.record`: same rows; one compiled call after a kernel step)."""
    if world._from_kernel and world.finger.name in log.poses and len(log.poses) == 1:
        _record_kernel(world, log, k, tau)
        return
    log.t[k] = world.time
    for b in world._bodies():
        log.poses[b.name][k] = b.pose()
        log.velocities[b.name][k] = b.velocity()
    if world.finger is not None:
        log.q[k], log.qd[k], log.tau[k] = world.finger.th, world.finger.thd, tau
    log.write_contacts(k, world.contacts())


def _record_kernel(world, log, k: int, tau: np.ndarray) -> None:
    """One compiled call (:func:`record_row`) after a compiled step."""
    f = world.finger
    x = f.x
    rec = world._rec
    if rec is None or rec[0] is not log:
        name = f.name
        arrays = (
            log.t, log.poses[name], log.velocities[name], log.q, log.qd, log.tau,
            log.contact_count, log.contact_pair, log.contact_point, log.contact_normal,
            log.normal_force, log.tangential_force, log.slip_velocity, log.gap,
        )  # fmt: skip
        rec = world._rec = [log, arrays, -1]
    if rec[2] < 0 and x[sk.ACT] > 0.0:
        rec[2] = log.pair_index(f.name, world._fast.name)
    t = tau if isinstance(tau, np.ndarray) and tau.dtype == np.float64 else np.asarray(tau, float)
    record_row(x, k, world.time, t, rec[2], *rec[1])


@njit(cache=True)
def record_row(
    x, k, time, tau, pair, t, pose, vel, q, qd, taus, count, cpair, pt, nrm, fn, ft, sl, gap
):
    """Row ``k`` of a :class:`~planner.sim.log.SimLog` from the state ``x`` (the finger's
    pose, velocity, joints, torque and its contact; ``pair``: the log's pair index)."""
    t[k] = time
    a, b = 0.5 * x[TH + 2], 0.5 * (math.pi / 2 - x[G1])
    ca, sa, cb, sb = math.cos(a), math.sin(a), math.cos(b), math.sin(b)
    for i in range(3):
        pose[k, i] = x[C + i]
        vel[k, i] = (
            x[J + 3 * i] * x[THD] + x[J + 3 * i + 1] * x[THD + 1] + x[J + 3 * i + 2] * x[THD + 2]
        )
        vel[k, 3 + i] = (
            x[JW + 3 * i] * x[THD] + x[JW + 3 * i + 1] * x[THD + 1] + x[JW + 3 * i + 2] * x[THD + 2]
        )
        q[k, i], qd[k, i], taus[k, i] = x[TH + i], x[THD + i], tau[i]
    pose[k, 3], pose[k, 4], pose[k, 5], pose[k, 6] = ca * cb, -sa * sb, ca * sb, sa * cb
    if x[ACT] > 0.0:
        count[k] = 1
        cpair[k, 0] = pair
        fn[k, 0], gap[k, 0] = x[FN], x[GAP]
        for i in range(3):
            pt[k, 0, i], nrm[k, 0, i] = x[PT + i], x[NRM + i]
            ft[k, 0, i], sl[k, 0, i] = x[FT + i], x[SLIP + i]
    else:
        count[k] = 0
