"""MJCF export of a :class:`~planner.sim.spatial.SpatialWorld` (for cross-checks with MuJoCo).

:func:`spatial_to_mjcf` writes the same scene as a MuJoCo model:

* a :class:`~planner.sim.spatial.Plane` -> a ``plane`` geom (its normal as ``zaxis``);
* a :class:`~planner.sim.spatial.Plate` or ``HeightField`` -> an ``hfield`` asset sampled on
  a regular grid (``hfield_cells`` per side over the plate's features, or the height field's
  rectangle), elevation data inline; a ``ParametricSurface`` -> a ``mesh`` asset sampled on its
  (clipped) domain. Poses become the geom's ``pos``/``quat``. Sampling is the only
  approximation of the export: MuJoCo collides spheres with hfield prisms and mesh convex
  hulls, not with the exact surfaces;
* each ball -> a body with a ``freejoint`` and a ``sphere`` geom of its mass (uniform
  density inertia) and velocity (``qvel`` in a ``key``);
* the 3GM -> its Pinocchio tree as bodies and ``hinge`` joints (MuJoCo's ``qpos`` of the finger
  is Pinocchio's ``q = (θ3, θ1, γ1-θ1, θ2, γ2-θ2)``), link inertias and motor armature from
  the Pinocchio model, the fingertip ``sphere`` geom on the distal link, ``motor`` actuators
  with the App. C torque limits, and the loop closure as an ``equality`` ``connect`` between
  the sites ``closure_a`` (distal link) and ``closure_b`` (link l3).

The keyframe ``initial`` holds the world's current state (``qpos``, ``qvel``; the finger's loop
closed): reset to it (``mujoco.mj_resetDataKeyframe(model, data, 0)``) before stepping.

Contact settings are MuJoCo's defaults (``condim`` 3, ``friction`` = the contact's μ), with
``cone="elliptic"`` (MuJoCo's circular cone); peers tune them as they see fit.
"""

from __future__ import annotations

import numpy as np

from planner.errors import InvalidParameter
from planner.sim.spatial.bodies import quat_from_matrix

__all__ = ["spatial_to_mjcf"]


def _f(x) -> str:
    return " ".join(f"{float(v):.12g}" for v in np.ravel(x))


def _surface_xml(name, placed, mu, cells, extent) -> tuple[list[str], list[str]]:
    """(asset lines, geom lines) of one surface."""
    from planner.geometry.surfaces import HeightField, ParametricSurface
    from planner.sim.spatial.plate import Plane, Plate

    s = placed.surface
    quat = quat_from_matrix(placed.R)
    pose = f'pos="{_f(placed.t)}" quat="{_f(quat)}"'
    fr = f'friction="{mu:.12g} 0.005 0.0001"'
    if isinstance(s, Plane):
        n = placed.R @ np.array(s.normal)
        p = placed.R @ np.array(s.point) + placed.t
        return [], [
            f'<geom name="{name}" type="plane" size="0 0 1" pos="{_f(p)}" zaxis="{_f(n)}" {fr}/>'
        ]
    if isinstance(s, Plate | HeightField):
        if isinstance(s, Plate):
            xs = [f.position[0] for f in s.features] or [0.0]
            ys = [f.position[1] for f in s.features] or [0.0]
            cx, cy = 0.5 * (min(xs) + max(xs)), 0.5 * (min(ys) + max(ys))
            hx = 0.5 * (max(xs) - min(xs)) + extent
            hy = 0.5 * (max(ys) - min(ys)) + extent
            x = np.linspace(cx - hx, cx + hx, cells)
            y = np.linspace(cy - hy, cy + hy, cells)
            Z = s.height(x[None, :], y[:, None])  # rows along y
        else:
            x, y = s.x, s.y
            cx, cy, hx, hy = x.mean(), y.mean(), 0.5 * np.ptp(x), 0.5 * np.ptp(y)
            Z = s.height(x[None, :], y[:, None])
        lo, hi = float(Z.min()), float(Z.max())
        span = max(hi - lo, 1e-9)
        base = max(span, 1e-3)
        data = (Z - lo) / span
        asset = (
            f'<hfield name="{name}_hf" nrow="{Z.shape[0]}" ncol="{Z.shape[1]}" '
            f'size="{hx:.12g} {hy:.12g} {span:.12g} {base:.12g}" elevation="{_f(data)}"/>'
        )
        centre = placed.R @ np.array([cx, cy, lo]) + placed.t
        geom = (
            f'<geom name="{name}" type="hfield" hfield="{name}_hf" pos="{_f(centre)}" '
            f'quat="{_f(quat)}" {fr}/>'
        )
        return [asset], [geom]
    if isinstance(s, ParametricSurface):
        dom = np.clip(s.domain, -extent * 10, extent * 10)
        u = np.linspace(dom[0, 0], dom[0, 1], cells)
        v = np.linspace(dom[1, 0], dom[1, 1], cells)
        U, V = np.meshgrid(u, v, indexing="ij")
        P = s.point(U.ravel(), V.ravel())
        k = np.arange(cells * cells).reshape(cells, cells)
        a, b, c, d = k[:-1, :-1], k[1:, :-1], k[1:, 1:], k[:-1, 1:]
        faces = np.concatenate([np.stack([a, b, c], -1), np.stack([a, c, d], -1)]).reshape(-1, 3)
        tri = " ".join(map(str, faces.ravel()))
        asset = f'<mesh name="{name}_mesh" vertex="{_f(P)}" face="{tri}"/>'
        return [asset], [f'<geom name="{name}" type="mesh" mesh="{name}_mesh" {pose} {fr}/>']
    raise InvalidParameter(f"cannot export surface {name!r} of type {type(s).__name__}")


def _finger_xml(f, mu) -> tuple[list[str], list[str], list[str]]:
    """(body lines, actuator lines, equality lines) of the 3GM at its current state."""

    from planner.sim.spatial.finger import FingerDynamics

    m = FingerDynamics(f.gm).model
    children: dict[int, list[int]] = {}
    for i in range(1, m.njoints):
        children.setdefault(m.parents[i], []).append(i)
    tau = f.gm.torque_limits
    limit = {"theta1": tau[0], "theta2": tau[1], "theta3": tau[2]}
    arm = np.asarray(m.armature)
    fr = f'friction="{mu:.12g} 0.005 0.0001"'

    def body(i: int, indent: str) -> list[str]:
        rel = m.jointPlacements[i]  # the zero configuration: MuJoCo's qpos = Pinocchio's q
        name = m.names[i]
        Y = m.inertias[i]
        quat = _f(quat_from_matrix(rel.rotation))
        out = [f'{indent}<body name="{name}" pos="{_f(rel.translation)}" quat="{quat}">']
        out.append(
            f'{indent}  <joint name="{name}" type="hinge" axis="0 0 1" '
            f'armature="{arm[m.idx_vs[i]]:.12g}" damping="0"/>'
        )
        if Y.mass > 0:
            inertia = _f(np.maximum(np.diag(Y.inertia), 1e-12))
            out.append(
                f'{indent}  <inertial pos="{_f(Y.lever)}" mass="{Y.mass:.12g}" '
                f'diaginertia="{inertia}"/>'
            )
        else:
            izz = max(float(Y.inertia[2, 2]), 1e-9)  # the base plate: a disc about z
            disc = _f([izz / 2, izz / 2, izz])
            out.append(f'{indent}  <inertial pos="0 0 0" mass="1e-6" diaginertia="{disc}"/>')
        if name == "gamma1":
            tip = m.frames[m.getFrameId("endpoint")].placement.translation
            out.append(
                f'{indent}  <geom name="{f.name}_tip" type="sphere" size="{f.radius:.12g}" '
                f'pos="{_f(tip)}" mass="0" {fr}/>'
            )
            out.append(f'{indent}  <site name="{f.name}_tip" pos="{_f(tip)}"/>')
        for fname in ("closure_a", "closure_b"):
            fr_ = m.frames[m.getFrameId(fname)]
            if fr_.parentJoint == i:
                pos = _f(fr_.placement.translation)
                out.append(f'{indent}  <site name="{f.name}_{fname}" pos="{pos}"/>')
        for c in children.get(i, []):
            out += body(c, indent + "  ")
        out.append(f"{indent}</body>")
        return out

    bodies = []
    for c in children.get(0, []):
        bodies += body(c, "    ")
    acts = [
        f'    <motor name="{n}" joint="{n}" ctrllimited="true" ctrlrange="{-t:.12g} {t:.12g}"/>'
        for n, t in limit.items()
    ]
    eq = [
        f'    <connect name="{f.name}_loop" site1="{f.name}_closure_a" site2="{f.name}_closure_b"/>'
    ]
    return bodies, acts, eq


def spatial_to_mjcf(world, hfield_cells: int = 201, extent: float = 0.03) -> str:
    """The MJCF (XML text) of ``world`` at its current state (see the module docstring).

    Args:
        world: the :class:`~planner.sim.spatial.SpatialWorld`.
        hfield_cells: grid points per side of height fields and meshes.
        extent: half-size of the sampled plate beyond its features [m].
    """
    assets, geoms, bodies, acts, eqs = [], [], [], [], []
    for name, (placed, mu) in world.surfaces.items():
        a, g = _surface_xml(name, placed, mu, int(hfield_cells), float(extent))
        assets += ["    " + x for x in a]
        geoms += ["    " + x for x in g]
    mus = [mu for _, mu in world.surfaces.values()] or [1.0]
    qpos, qvel = [], []
    for b in world.spheres.values():
        mu = b.friction if b.friction is not None else max(mus)
        bodies += [
            f'    <body name="{b.name}" pos="{_f(b.p)}" quat="{_f(b.quat)}">',
            "      <freejoint/>",
            f'      <geom name="{b.name}" type="sphere" size="{b.radius:.12g}" '
            f'mass="{b.mass:.12g}" '
            f'friction="{mu:.12g} 0.005 0.0001"/>',
            "    </body>",
        ]
        R = quat_to_matrix(b.quat)
        qpos += [*b.p, *b.quat]
        qvel += [*b.v, *(R.T @ b.w)]  # MuJoCo's free-joint angular velocity is in the body frame
    if world.finger is not None:
        f = world.finger
        mu = f.friction if f.friction is not None else max(mus)
        fb, acts, eqs = _finger_xml(f, mu)
        bodies += fb
        from planner.sim.spatial.finger import FingerDynamics

        st = FingerDynamics(f.gm, world.gravity).evaluate(f.th, f.thd)
        qpos += list(st.q)
        qvel += list(st.v)  # tree velocity S(q) θ̇: consistent with the loop closure
    g = world.gravity
    lines = [
        '<mujoco model="hapex_spatial">',
        f'  <option timestep="{world.dt:.12g}" gravity="{_f(g)}" cone="elliptic"/>',
        "  <asset>",
        *assets,
        "  </asset>",
        "  <worldbody>",
        *geoms,
        *bodies,
        "  </worldbody>",
    ]
    if acts:
        lines += ["  <actuator>", *acts, "  </actuator>", "  <equality>", *eqs, "  </equality>"]
    if qpos:
        lines += [
            "  <keyframe>",
            f'    <key name="initial" qpos="{_f(qpos)}" qvel="{_f(qvel)}"/>',
            "  </keyframe>",
        ]
    lines.append("</mujoco>")
    return "\n".join(lines) + "\n"


def quat_to_matrix(q) -> np.ndarray:
    """Rotation matrix of the unit quaternion ``q`` (wxyz)."""
    w, x, y, z = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )
