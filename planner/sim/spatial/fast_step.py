"""The 3GM's step on one plate or plane through :func:`.step_kernel.finger_step` (the hot
path: one numba call per step).

Same scheme and results as :func:`planner.sim.spatial.stepping.step_body` (tested equal on
random states), for the case that matters for speed: the finger alone over one
:class:`Plate` or :class:`Plane` and the generated dynamics compiled to C.
Anything the kernel does not resolve (a sliding root it could not certify) goes through the
general path.
"""

from __future__ import annotations

import numpy as np

from planner.sim.records import Contact
from planner.sim.spatial import step_kernel as sk
from planner.sim.spatial.finger_codegen import CompiledFunction
from planner.sim.spatial.kernel import pack_plate
from planner.sim.spatial.plate import Plane, Plate

__all__ = ["FingerKernel", "KernelContact", "fast_plate"]


class FingerKernel:
    """Everything :func:`.step_kernel.finger_step` needs, packed once: the plate (or plane)
    with its pose, μ, the tip radius, joint and torque limits, the generated functions.

    Args:
        name: the surface's handle; placed: its :class:`.closest.PlacedSurface`; mu: μ.
        finger: the :class:`.bodies.FingerBody` (its state vector is stepped in place).
        dt: time step [s]; all_contacts: look for the tip's other contacts (the
            world's setting; several found: the step falls back to the general path).
    """

    def __init__(self, name, placed, mu, finger, dt, all_contacts=False) -> None:
        from planner.sim.spatial.sensing import FULL_INTENSITY_FORCE, SAMPLE_RATE

        s = placed.surface
        self.name, self.mu = name, mu
        if isinstance(s, Plane):
            n = np.array(s.normal)
            a = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
            t1 = a - (a @ n) * n
            t1 /= np.linalg.norm(t1)
            R = placed.R @ np.column_stack([t1, np.cross(n, t1), n])
            t = placed.R @ np.array(s.point) + placed.t
            self.F, self.P, base = np.zeros((0, 10)), np.zeros((0, 2)), 0.0
        else:
            R, t = placed.R, placed.t
            (self.F, self.P), base = pack_plate(s), float(s.base)
        prm = np.zeros(sk.PARAM_SIZE)
        prm[sk.P_H], prm[sk.P_MU], prm[sk.P_R], prm[sk.P_BASE] = dt, mu, finger.radius, base
        prm[sk.P_ROT : sk.P_ROT + 9] = np.asarray(R, float).ravel()
        prm[sk.P_T : sk.P_T + 3] = t
        prm[sk.P_LIM : sk.P_LIM + 6] = np.asarray(finger.gm.joint_limits, float).ravel()
        prm[sk.P_TAU : sk.P_TAU + 3] = finger.gm.torque_limits
        prm[sk.P_RATE], prm[sk.P_FULL], prm[sk.P_SIN] = (
            SAMPLE_RATE,
            FULL_INTENSITY_FORCE,
            sk.SINGULAR_SIN,
        )
        prm[sk.P_ALL] = 1.0 if all_contacts else 0.0
        self.prm = prm
        self.dyn, self.kin = finger.fn, finger.kin
        _check_layout(self.dyn, self.kin)

    def step(self, x, tau, t_end, owts) -> int:
        """:func:`.step_kernel.finger_step` on the state ``x``; returns its code."""
        d, k = self.dyn, self.kin
        return sk.finger_step(
            x, tau, t_end, self.prm, self.F, self.P, d.buffer, d.pointers, k.buffer,
            k.pointers, owts.rows, owts.times, owts.state,
        )  # fmt: skip


def _check_layout(dyn, kin) -> None:
    """The buffer offsets the kernel hard-codes equal the generated functions' ones."""
    want_d = [sk.D_C, sk.D_J, sk.D_JW, sk.D_MINV, sk.D_THDF, sk.D_G1]
    want_k = [sk.K_C, sk.K_J, sk.K_JW, sk.K_G1, sk.K_SIN]
    if list(dyn.output_offsets[:6]) != want_d or dyn.output_offsets[8] != sk.D_SIN:
        raise RuntimeError(f"dynamics buffer layout changed: {dyn.output_offsets}")
    if list(kin.output_offsets[:5]) != want_k:
        raise RuntimeError(f"kinematics buffer layout changed: {kin.output_offsets}")


def fast_plate(world) -> FingerKernel | None:
    """The packed kernel when the world is one finger over one Plate/Plane (its
    dynamics compiled), else None."""
    if world.spheres or world.finger is None or len(world.surfaces) != 1:
        return None
    f = world.finger
    if not (isinstance(f.fn, CompiledFunction) and isinstance(f.kin, CompiledFunction)):
        return None
    ((name, (placed, mu)),) = world.surfaces.items()
    if not isinstance(placed.surface, Plate | Plane):
        return None
    mu = mu if f.friction is None else max(mu, f.friction)
    f.x[sk.HINT_OK] = 0.0  # the warm start of the foot belongs to the previous surface
    return FingerKernel(name, placed, mu, f, world.dt, world.all_contacts)


class KernelContact(Contact):
    """The :class:`~planner.sim.records.Contact` of a kernel step, read lazily from a snapshot
    ``s`` = ``(f_n, point (3), normal (3), tangential force (3), slip (3), gap)`` of the
    state vector (same fields and values as the general path's records)."""

    def __init__(self, bodies: tuple[str, str], s: np.ndarray) -> None:  # noqa: D107
        object.__setattr__(self, "bodies", bodies)
        object.__setattr__(self, "_s", s)

    normal_force = property(lambda self: float(self._s[0]))
    point = property(lambda self: self._s[1:4])
    normal = property(lambda self: self._s[4:7])
    tangential_force = property(lambda self: self._s[7:10])
    slip_velocity = property(lambda self: self._s[10:13])
    gap = property(lambda self: float(self._s[13]))
