"""The 3GM's step on one plate or plane through the scalar kernels (the hot path).

Same scheme and results as :func:`planner.sim.spatial.stepping.step_body` (tested equal),
for the case that matters for speed: the finger alone over one :class:`Plate` or
:class:`Plane`. The free step uses the generated reduced dynamics; the contact problem and
the foot points run in :mod:`planner.sim.spatial.kernel`; the projection onto the offset
surface is the same mass-weighted Gauss-Newton step. Anything the kernel does not resolve
(status -1: a sliding root it could not certify) goes through the general path.
"""

from __future__ import annotations

import numpy as np

from planner.sim.records import Contact
from planner.sim.spatial.kernel import finger_contact, pack_plate, plate_foot_world
from planner.sim.spatial.plate import Plane, Plate

__all__ = ["FastPlate", "fast_plate"]

_PROJ_TOL = 1e-12  # [m]
_MARGIN = 1e-5  # [m]


class FastPlate:
    """A plate (or plane) packed for the kernels: features, base, pose ``T_WS``."""

    def __init__(self, name, placed, mu) -> None:
        s = placed.surface
        self.name, self.mu = name, mu
        if isinstance(s, Plane):
            n = np.array(s.normal)
            a = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
            t1 = a - (a @ n) * n
            t1 /= np.linalg.norm(t1)
            Rn = np.column_stack([t1, np.cross(n, t1), n])
            self.R = placed.R @ Rn
            self.t = placed.R @ np.array(s.point) + placed.t
            self.F, self.P, self.base = np.zeros((0, 10)), np.zeros((0, 2)), 0.0
        else:
            self.R, self.t = placed.R.copy(), placed.t.copy()
            (self.F, self.P), self.base = pack_plate(s), float(s.base)
        self.R = np.ascontiguousarray(self.R)
        self.hint: tuple[float, float] | None = None
        self.out = np.zeros(26)
        self._foot = np.zeros(9)

    def foot(self, c: np.ndarray):
        """(point (3,), normal (3,), distance) of ``c`` [m, WCS]; updates the warm start."""
        if self.hint is None:
            cs = self.R.T @ (c - self.t)
            self.hint = (cs[0], cs[1])
        o = self._foot
        plate_foot_world(self.F, self.P, self.base, self.R, self.t, c, *self.hint, o)
        self.hint = (o[7], o[8])
        return o[0:3].copy(), o[3:6].copy(), o[6]


def fast_plate(world) -> FastPlate | None:
    """The packed surface when the world is one finger over one Plate/Plane, else None."""
    if world.spheres or world.finger is None or len(world.surfaces) != 1:
        return None
    ((name, (placed, mu)),) = world.surfaces.items()
    if not isinstance(placed.surface, Plate | Plane):
        return None
    f = world.finger
    mu = mu if f.friction is None else min(mu, f.friction)
    return FastPlate(name, placed, mu)


def _project(f, fp: FastPlate):
    """Mass-weighted Gauss-Newton onto the offset surface; ``(point, normal, gap)``."""
    for _ in range(20):
        p, n, d = fp.foot(f.center)
        gap = d - f.radius
        if abs(gap) <= _PROJ_TOL:
            break
        jn = n @ f.J
        mj = f.minv @ jn
        f.project(None, -gap * mj / (jn @ mj))
    return p, n, gap


def step_finger(world, f, tau, fp: FastPlate) -> list[Contact] | None:
    """One step of the finger on ``fp``; None when the kernel asks for the general path
    (nothing has been changed then)."""
    h = world.dt
    thd_f = f.free_velocity(h, world.gravity, tau)
    reach = 2.0 * h * float(np.max(np.abs(thd_f))) * 0.2 + _MARGIN
    if fp.hint is None:
        cs = fp.R.T @ (f.center - fp.t)
        fp.hint = (cs[0], cs[1])
    out = fp.out
    finger_contact(
        fp.F, fp.P, fp.base, fp.R, fp.t, f.center, fp.hint[0], fp.hint[1], f.radius,
        f.J, f.Jw, f.minv, thd_f, h, fp.mu, reach, out,
    )  # fmt: skip
    status = out[0]
    if status < 0:
        return None
    fp.hint = (out[24], out[25])
    active = status >= 2.0 and out[1] > 0.0
    f.thd = out[4:7].copy() if status > 0 else thd_f
    f.th = f.th + h * f.thd
    f._refresh_center()
    if not active:
        if status == 1.0:  # a candidate that separated: it must not end up penetrating
            _, _, d = fp.foot(f.center)
            if d - f.radius < -_PROJ_TOL:
                _project(f, fp)
        return []
    p, n, gap = _project(f, fp)
    lam = out[1:4]
    t1, t2 = out[16:19], out[19:22]
    u = out[13:16]
    return [
        Contact(
            (f.name, fp.name),
            p,
            n,
            float(lam[0] / h),
            (lam[1] * t1 + lam[2] * t2) / h,
            u[1] * t1 + u[2] * t2,
            float(gap),
        )
    ]
