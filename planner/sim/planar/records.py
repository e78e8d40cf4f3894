"""Contact records of the planar world from the last step's result."""

from __future__ import annotations

import numpy as np

from planner.sim.records import Contact

__all__ = ["contact_records"]


def contact_records(world, res) -> tuple[Contact, ...]:
    """:class:`Contact` records (forces = impulses / dt) of a :class:`StepResult`."""
    h = world.dt
    out = []
    for k in range(len(res.gap)):
        out.append(
            Contact(
                bodies=(world.bodies[res.body_a[k]].name, world.bodies[res.body_b[k]].name),
                point=np.array(res.point_b[k]),
                normal=np.array(res.normal[k]),
                normal_force=float(res.p_n[k] / h),
                tangential_force=float(res.p_t[k] / h),
                slip_velocity=float(res.slip[k]),
                gap=float(res.gap[k]),
            )
        )
    return tuple(out)
