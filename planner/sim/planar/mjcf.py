"""The planar world as MJCF: the same scene for MuJoCo, by construction.

Mapping (MuJoCo's x-y plane is the world's plane; gravity ``(g_x, g_y, 0)``):

* a free body: a body at its centre of mass with joints slide-x, slide-y, hinge-z (so it
  stays in the plane), its mass and planar inertia (``diaginertia = I I I``); a disc is a
  sphere (its section by the plane is the disc: MuJoCo's analytic sphere colliders), an
  ellipse an ellipsoid, any other outline the convex hull of its dense samples extruded
  +-``depth`` (a mesh: **non-convex outlines are convexified**);
* a fixed outline: each line piece a box whose face lies on the line (material behind it),
  each convex arc a cylinder about z, any other piece (concave arcs, parametric pieces) a
  chain of boxes on 200 chords (an approximation - MuJoCo has no exact arcs/curves);
* the hand: two chains of hinge-z bodies with the link masses/inertias of its Pinocchio
  model, joint ranges as limits, one torque motor per joint (``ctrlrange`` = the torque
  limit), fingertips as spheres (round) or thin boxes (flat pads); links do not collide;
* friction ``mu`` per geom (MuJoCo takes the pair's maximum, as the planar world does),
  torsional and rolling friction 0, ``condim="3"``; a keyframe ``init`` holds the state.

Contacts in MuJoCo are soft (solref/solimp) and regularized; the benchmark compares the
two engines on the same model with MuJoCo's default and its best settings.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial import ConvexHull

from planner.geometry.primitives import Arc, Line
from planner.sim.planar.bodies import FIXED, FREE, TIP

__all__ = ["planar_to_mjcf"]

DEPTH = 0.02  # half-thickness of every extruded shape along z [m]
SLAB = 0.005  # half-thickness of the box behind a fixed line [m]


def _f(*xs) -> str:
    return " ".join(f"{float(x):.12g}" for x in xs)


def _fixed_geoms(body, mu) -> list[str]:
    x0, y0, a0 = body.pose
    c, s = math.cos(a0), math.sin(a0)

    def world(p):
        return x0 + c * p[0] - s * p[1], y0 + s * p[0] + c * p[1]

    out = []
    k = 0

    def box(p, q):
        nonlocal k
        (ax, ay), (bx, by) = world(p), world(q)
        L = math.hypot(bx - ax, by - ay)
        if L <= 0:
            return
        ang = math.atan2(by - ay, bx - ax)
        nx, ny = -(by - ay) / L, (bx - ax) / L
        cx, cy = (ax + bx) / 2 - SLAB * nx, (ay + by) / 2 - SLAB * ny
        out.append(
            f'<geom name="{body.name}/{k}" type="box" size="{_f(L / 2, SLAB, DEPTH)}" '
            f'pos="{_f(cx, cy, 0)}" euler="0 0 {ang:.12g}" friction="{_f(mu, 0, 0)}"/>'
        )
        k += 1

    for piece in body.outline.profile.pieces:
        if isinstance(piece, Line):
            box(piece.p0, piece.p1)
        elif isinstance(piece, Arc) and piece.sweep < 0:
            cx, cy = world(piece.center)
            out.append(
                f'<geom name="{body.name}/{k}" type="cylinder" size="{_f(piece.radius, DEPTH)}" '
                f'pos="{_f(cx, cy, 0)}" friction="{_f(mu, 0, 0)}"/>'
            )
            k += 1
        else:
            P, _, _ = piece.evaluate(np.linspace(0.0, piece.length, 201))
            for i in range(200):
                box(P[i], P[i + 1])
    return out


def _free_geom(body, world_angle, assets) -> str:
    prof = body.outline.profile
    mu = body.friction
    pieces = prof.pieces
    fr = f'friction="{_f(mu, 0, 0)}"'
    if len(pieces) == 1 and isinstance(pieces[0], Arc):
        return f'<geom name="{body.name}" type="sphere" size="{_f(pieces[0].radius)}" {fr}/>'
    if prof.name == "ellipse":
        P, _, _ = prof.evaluate(np.array([0.0, prof.length / 4]))
        a, b = float(np.hypot(*P[0])), float(np.hypot(*P[1]))
        e = f'euler="0 0 {world_angle:.12g}"'
        return f'<geom name="{body.name}" type="ellipsoid" size="{_f(a, b, min(a, b))}" {e} {fr}/>'
    P = prof.sample(prof.length / 400).points
    c, s = math.cos(world_angle), math.sin(world_angle)
    P = P @ np.array([[c, s], [-s, c]])
    P = P[ConvexHull(P).vertices]
    V = np.vstack([np.column_stack([P, np.full(len(P), z)]) for z in (-DEPTH, DEPTH)])
    assets.append(f'<mesh name="{body.name}_mesh" vertex="{_f(*V.ravel())}"/>')
    return f'<geom name="{body.name}" type="mesh" mesh="{body.name}_mesh" {fr}/>'


def _finger_xml(world, side: int) -> tuple[list[str], list[str]]:
    from robots.planar_hand.model import EFFORT_LIMIT

    hand = world.hand.hand
    name = ("left", "right")[side]
    f = hand.params.finger(name)
    model = world.hand.model
    tip = world.bodies[[b.kind == TIP and b.index == side for b in world.bodies].index(True)]
    lines, acts = [], []
    pos = (f.base[0], f.base[1])
    for k in range(3):
        jid = model.getJointId(f"{name}_j{k + 1}")
        Y = model.inertias[jid]
        I3 = np.diag(Y.inertia)
        lines.append(f'<body name="{world.hand_name}.{name}_link{k + 1}" pos="{_f(*pos, 0)}">')
        lines.append(
            f'<joint name="{name}_j{k + 1}" type="hinge" axis="0 0 1" limited="true" '
            f'range="{_f(f.lower[k], f.upper[k])}"/>'
        )
        lines.append(
            f'<inertial pos="{_f(*Y.lever)}" mass="{Y.mass:.12g}" diaginertia="{_f(*I3)}"/>'
        )
        L = f.lengths[k]
        lines.append(
            f'<geom type="capsule" fromto="0 0 0 0 {L:.12g} 0" size="0.004" contype="0" '
            f'conaffinity="0" mass="0"/>'
        )
        acts.append(
            f'<motor name="{name}_m{k + 1}" joint="{name}_j{k + 1}" ctrllimited="true" '
            f'ctrlrange="{_f(-EFFORT_LIMIT, EFFORT_LIMIT)}"/>'
        )
        pos = (0.0, L)
    fr = f'friction="{_f(tip.friction, 0, 0)}"'
    L3 = f.lengths[2]
    if f.tip == "round":
        lines.append(
            f'<geom name="{tip.name}" type="sphere" size="{_f(f.tip_radius)}" '
            f'pos="0 {L3:.12g} 0" mass="0" {fr}/>'
        )
    else:
        lines.append(
            f'<geom name="{tip.name}" type="box" size="{_f(f.pad_half_width, SLAB, DEPTH)}" '
            f'pos="0 {L3 - SLAB:.12g} 0" mass="0" {fr}/>'
        )
    lines += ["</body>"] * 3
    return lines, acts


def planar_to_mjcf(world, name: str = "hapex_planar") -> str:
    """The MJCF text of a :class:`PlanarWorld` (see the module docstring for the mapping)."""
    gx, gy = world.gravity
    assets: list[str] = []
    body_xml: list[str] = []
    acts: list[str] = []
    qpos: list[float] = []
    qvel: list[float] = []
    if world.hand is not None:
        for side in (0, 1):
            lines, a = _finger_xml(world, side)
            body_xml += lines
            acts += a
        qpos += list(world.q)
        qvel += list(world.qd)
    for b in world.bodies:
        if b.kind == FIXED:
            body_xml += _fixed_geoms(b, b.friction)
        elif b.kind == FREE:
            x, y, a = world._x[b.index]
            geom = _free_geom(b, a, assets)
            body_xml += [
                f'<body name="{b.name}" pos="{_f(x, y, 0)}">',
                f'<joint name="{b.name}_x" type="slide" axis="1 0 0"/>',
                f'<joint name="{b.name}_y" type="slide" axis="0 1 0"/>',
                f'<joint name="{b.name}_a" type="hinge" axis="0 0 1"/>',
                f'<inertial pos="0 0 0" mass="{b.mass:.12g}" '
                f'diaginertia="{_f(b.inertia, b.inertia, b.inertia)}"/>',
                geom,
                "</body>",
            ]
            qpos += [0.0, 0.0, 0.0]
            qvel += list(world._v[b.index])
    out = [
        f'<mujoco model="{name}">',
        '<compiler angle="radian"/>',
        f'<option timestep="{world.dt:.12g}" gravity="{_f(gx, gy, 0)}"/>',
        '<default><geom condim="3" solref="0.02 1"/></default>',
    ]
    if assets:
        out += ["<asset>", *assets, "</asset>"]
    out += ["<worldbody>", *body_xml, "</worldbody>"]
    if acts:
        out += ["<actuator>", *acts, "</actuator>"]
    out += [
        "<keyframe>",
        f'<key name="init" qpos="{_f(*qpos)}" qvel="{_f(*qvel)}"/>' if qpos else "",
        "</keyframe>",
        "</mujoco>",
    ]
    return "\n".join(line for line in out if line) + "\n"
