"""One time step of the planar world: Stewart-Trinkle velocity-level time stepping.

With generalized velocity ``nu`` (free bodies' ``(vx, vy, omega)`` then the hand's ``qd``),
inertia ``M`` (bodies: ``diag(m, m, I)``; hand: Pinocchio's ``M(q)``) and forces ``f``
(gravity, joint torques minus ``C qd + g``), one step of length ``h`` is

.. math::

    M (\\nu^+ - \\nu) = h f + N^T p_n + T^T (\\beta^+ - \\beta^-), \\qquad
    q^+ = q + h \\nu^+

with, for every contact i (gap ``phi_i``, normal row ``N_i``, tangent row ``T_i``, friction
``mu_i``) and the two edges ``+-t`` of the planar friction cone (exact in the plane),

.. math::

    0 \\le p_{n,i} \\perp N_i \\nu^+ + \\phi_i / h \\ge 0, \\quad
    0 \\le \\beta^\\pm_i \\perp \\lambda_i \\pm T_i \\nu^+ \\ge 0, \\quad
    0 \\le \\lambda_i \\perp \\mu_i p_{n,i} - \\beta^+_i - \\beta^-_i \\ge 0

(Stewart & Trinkle 1996, with the gap term of their eq. 17). Eliminating ``nu+`` gives an LCP
in ``(p_n, beta, lambda)`` of size ``4 n_c`` plus one row per active joint limit
(``q - q_lo >= 0``, ``q_hi - q >= 0``: frictionless unilateral constraints), solved exactly by
Lemke's method (:mod:`planner.sim.lcp`). Its solution is exact Coulomb friction: a sticking
contact has ``T nu+ = 0`` exactly (no creep), a sliding one carries ``mu p_n`` opposite to the
slip (``lambda`` = slip speed), and the normal velocity closes the gap exactly at the end of
the step, so a sliding contact neither hovers nor sinks (no Anitescu relaxation).

**Penetration.** The gap term drives ``phi`` to zero to first order every step; the
second-order residue (curvature x (h v)^2) and any initial overlap are removed by a position
projection (post-stabilization, Cline & Pai 2003) when a gap is below
``-projection_tolerance``: the minimum-kinetic-metric displacement ``dq = M^-1 N^T z`` with
``0 <= z perp phi + N M^-1 N^T z >= 0``, velocities untouched.

**Verification.** Every LCP answer is checked (``z >= 0``, ``w >= 0``, ``z.w = 0`` to 1e-9
relative, :func:`planner.sim.lcp.lcp_residual`); a projection whose Lemke path fails is
retried on the regularized ``N M^-1 N^T + eps I`` and still checked on the original problem,
to 1e-6 (so is a step's LCP that Lemke fails on in floating point, :data:`STEP_REGULARIZE`,
the shift raised tenfold up to three times, :data:`REGULARIZE_STEPS`); a
step whose problem has no verified answer raises :class:`planner.errors.InfeasibleProblem`
(a ``stopped`` event of the run), never returns an unchecked impulse. One exception, where
no answer exists: a *jam*, contacts and joint limits that oppose each other so that no
displacement removes every penetration (a disc squeezed between walls closer than its
diameter; a finger at its joint limit pressing the object into the palm). Its projection
is the exact answer of the regularized problem (equal stiff springs at the penetrating
rows: what can be removed is, the rest is shared), the world emits a ``jammed`` event with
the penetration left, and the step's LCP keeps that from growing (its fallback closes gaps
only). Until 2026-11-24 a jam raised ("position projection: Lemke stopped on a ray") and
ended a gait as a simulator fault instead of on its own reason. Open outlines (pads,
the palm) are one-sided faces: beyond their ends the distance to them is unsigned
(:func:`_unsigned_at_open_end`), so no phantom penetration enters a projection.

**Limits.** Restitution is zero (inelastic impacts). Contact forces are impulses / h (step
averages). Contact sets are re-detected every step within ``margin`` plus twice the distance
each body's points can travel in the step (no tunnelling at the scene's speeds). Rolling
resistance and compliance are not modelled. The step is first order in the motion: a
body that turns a large angle in one step outruns the linearized contact rows, and a contact
point that runs fast along a curved outline leaves an overlap of about ``(h v_t)^2 kappa / 2``
(``v_t`` its speed along the outline, ``kappa`` the relative curvature) that the next step's
projection removes before it detects its contacts. The state a step leaves (what the log's
poses and ``PlanarWorld.penetrations`` show) can then overlap by more than
``projection_tolerance``, while the log's ``gap`` (measured after that projection) does not
show it: an ellipse of 30 x 10 mm rocking on a floor at 1 ms overlaps by up to 10 um after
its steps (released tilted by 0.4 rad, it rolls onto its flat side at 16 rad/s, where the
contact point runs along its 90 mm radius of curvature at 1.5 m/s); in the benchmark's pinch,
palm-roll and hold-slide scenes the deepest overlap the steps leave is 7 nm
(``benchmarks/bench_sim.py`` measures it from the logged poses). The planar
hand's 50 g links carry no motor inertia or speed limit, so a finger that has let go and
is driven at its 2 N m torque limit can reach 240 rad/s (0.48 rad per 2 ms step); the next
step's projection then meets a "penetration" of centimetres (19 cm), and the run loop's
runaway check ends the run as a simulator fault (status "failed", with the reason). That
case was examined step by step (2026-11-24: a 10 cm sharp square tumbling out of the grasp,
with a hold-check variant since reverted). On the same day 2 of the 192 runs of
``bench_gait`` ended with a runaway velocity too (posed-outline runs on the 12 and 14 cm
rounded squares, seed 2; not examined; none in the re-run after the posed-outline planner
was compiled, bfbe9e3, whose rounding moved those failing paths: chance, not a fix).
Sub-stepping such steps is not done. Tried on
2026-11-24 and not kept: a torque-speed envelope for the actuators (no driving torque above
twice the URDF's rated 5 rad/s, braking in full, in both steps). It removed those two faults
but cannot touch a third kind, found in the same re-run (12 cm rounded square, posed
outline, seed 0): with the object jammed among 30 contacts the 500 Hz controllers' damping
and the step alternate each step, joint speeds flip sign and grow (-99, 81, -225, 182, ...,
460 rad/s) at +-2 N m - braking torque, which the envelope delivers in full. Both kinds come
from the links' missing motor inertia (a geared motor's reflected rotor inertia is far
above a 50 g link's); adding it means re-tuning every controller, not done. The envelope
also moved the chaotic gaits: ``ellipse_gait`` full turns 7/8 -> 6/8 seeds (its default
seed 0 failing at -268 deg), the batch 11 -> 12 objects with the circle model. On an
AVX-512 machine (NumPy rounding otherwise, 2026-11-24) ``long_thin_gait --seed 2`` ends in
this runaway: in phase 3 the left finger, its joint 1 at its stop after the object slipped,
spins its distal link (about 3e-5 kg m^2 about its joint) from 13 to 108 rad/s in 8 ms under
0.4 N m, and the fingers collide. A motor armature of 1e-4 kg m^2 per joint in the simulator
alone (the controllers unaware) removed it but moved the batch (circle model 11 -> 9
objects, two Lemke-ray faults on posed-outline runs): not kept.

**Energy.** With friction the LCP can have more than one answer (Painleve's paradox; in the
plane a wedge of two contacts at a friction angle past their opening), and an answer with
huge impulses is exact too. Its kinetic energy gain ``z.R v + z.G.z / 2``, with the
complementarity conditions, is ``sum p_n (-phi) / h - sum lambda mu p_n - z.G.z / 2``: only
the gap term of a penetrating contact can add energy, in proportion to the impulse. A
regular 5-gon of 2.55 cm at mu 3 (``explore_object``, seed 363, t = 0.836 s) wedged an
object corner under the left pad's face 60 um from its end, the pad's end against the next
side; the projection left a 12 um overlap, and Lemke's answer carried 376 N s at it: the
kinetic energy went from 7 mJ to 0.94 J, the object to 201 rad/s, in one step. An answer
that adds more than :data:`planner.sim.planar.step_kernel.ENERGY_ALLOWANCE` (100) times the
energy that gives each penetrating row's effective mass its speed ``-phi / h`` is refused
(:func:`~planner.sim.planar.step_kernel.gains_energy`) and the step closes gaps only
(``b + max(phi, 0) / h``), whose every answer adds no energy (the gap term is gone). The rule
changed no row of ``bench_gait`` (198), ``bench_gait_friction`` (144) or
``bench_gait_ridge`` (96) (2026-11-25): it only acts on such answers.

**Open outlines have no side walls.** Behind a pad's (or the palm's) face within its slab
is inside, at the depth behind the face, however near the slab's side: a corner that comes
round the pad's end is pushed out through the face. Taking the nearer of the face and the
side walls (the signed distance to a sharp-edged slab; tried in 777c608, reverted in
7688cae) was measured on 2026-11-25 with ``bench_gait_ridge``: full turns 43 -> 29 of 48
(scenario configuration) and 46 -> 28 (defaults), coverage lower on every ridge angle.
The pad's sharp end catches the ball's 3 mm ridge, which the face-only rule lets it ride
over as a rounded edge would (the thesis' flat fingertip slid over its ridge). A pad with
thickness and rounded ends of at least the ridge's height would model both; not done. The
face has a depth, though: a point more than :data:`~planner.sim.planar.hand.PAD_DEPTH`
(5 mm) behind a fingertip pad is beyond its body and makes no contact (the palm's depth is
unbounded). Before 2026-11-25 it was pushed out through the face however deep: a 2.8 cm
7-gon tumbling in a failed gait (mu 1, seed 687) brought a corner round the left pad's end
25 mm behind its face, the projection left 23 mm of it, and the gap term at that depth
(which the energy rule allows in proportion) took the kinetic energy from 0.08 to 1.25 J
and the object to 235 rad/s in one step.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from planner.errors import InfeasibleProblem
from planner.sim.lcp import COVERS, lcp_residual, solve_lcp
from planner.sim.planar.bodies import FIXED, FREE, TIP
from planner.sim.planar.contacts import Pose, candidates
from planner.sim.planar.step_kernel import gains_energy

__all__ = ["StepResult", "find_contacts", "point_velocity", "step", "step_fast"]


class StepResult(NamedTuple):
    """What a step leaves behind for contact records and events (n contacts); a named
    tuple (built after every step: cheaper than a frozen dataclass).

    Attributes:
        body_a, body_b: (n,) body indices; gap: (n,) [m] at the step's start;
        point_a, point_b: (n, 2) touching points [m]; normal: (n, 2) from b toward a;
        curvature: (n,) of the touching feature [1/m]; mu: (n,);
        p_n, p_t: (n,) normal / tangential impulses on a over the step [N s];
        slip: (n,) tangential velocity of a relative to b after the step [m/s];
        limit_joints, limit_impulses: joint-limit rows (joint index, impulse [N m s]).
    """

    body_a: np.ndarray
    body_b: np.ndarray
    gap: np.ndarray
    point_a: np.ndarray
    point_b: np.ndarray
    normal: np.ndarray
    curvature: np.ndarray
    mu: np.ndarray
    p_n: np.ndarray
    p_t: np.ndarray
    slip: np.ndarray
    limit_joints: np.ndarray
    limit_impulses: np.ndarray


def _placements(world):
    frames = world.hand.frames(world.q) if world.hand is not None else None
    out = []
    for b in world.bodies:
        if b.kind == FIXED:
            out.append(Pose(*b.pose))
        elif b.kind == FREE:
            out.append(Pose(*world._x[b.index].tolist()))
        else:
            out.append(Pose(*frames[1][b.index]))
    return out, frames


def find_contacts(world, margin: float, placements=None) -> list[tuple]:
    """Candidates ``(i, j, gap, pax, pay, pbx, pby, nx, ny, curvature)`` of every pair."""
    P = placements if placements is not None else _placements(world)[0]
    bodies = world.bodies
    reach = _reach(world) if margin > 0 else [0.0] * len(bodies)
    out = []
    for i in range(len(bodies)):
        for j in range(i + 1, len(bodies)):
            a, b = bodies[i], bodies[j]
            if a.kind == FIXED and b.kind == FIXED:
                continue
            m = margin + reach[i] + reach[j]
            cs = candidates(a.outline, P[i], b.outline, P[j], m)
            if not (a.outline.closed and b.outline.closed) and any(c[0] < 0.0 for c in cs):
                cs = _fix_open_ends(cs, a, P[i], b, P[j], m)
            out.extend((i, j, *c) for c in cs)
    return out


def _fix_open_ends(cs: list, a, pa, b, pb, margin: float) -> list:
    """Candidates of a pair with an open outline, penetrations through its ends re-signed."""
    ca = [pa.to_world(*p) for p in a.outline.corner_list]
    cb = [pb.to_world(*p) for p in b.outline.corner_list]
    ea = ca[-2:] if not a.outline.closed else []
    eb = cb[-2:] if not b.outline.closed else []
    kept: list[tuple] = []
    for c in cs:
        if c[0] < 0.0:
            c = _unsigned_at_open_end(c, ca, ea, cb, eb)
            if c[0] >= margin:
                continue
        if not any(
            abs(c[1] - k[1]) + abs(c[2] - k[2]) + abs(c[3] - k[3]) + abs(c[4] - k[4]) < 4e-9
            for k in kept
        ):
            kept.append(c)
    return kept


def _at(px: float, py: float, points: list) -> bool:
    return any(abs(px - ex) + abs(py - ey) <= 1e-12 for ex, ey in points)


def _unsigned_at_open_end(c: tuple, corners_a, ends_a, corners_b, ends_b) -> tuple:
    """Re-sign a candidate whose closest point is the END of an open outline.

    An open outline (a pad, the palm) is a one-sided face: a point is behind it only within
    the face's slab. Beyond its ends the distance to it is unsigned, but the closest-point
    query of :mod:`planner.sim.planar.outline` signs it by the face normal, so a corner or
    an arc centre anywhere in the half-plane behind the face came back as a deep phantom
    penetration (the left pad's corner 9 cm "inside" the palm threw the fingers to their
    limits in the ball_with_ridge gait at t = 8.64 s). A candidate is of this kind when its
    point on an open outline is an end and the query was the other body's corner (its
    point there is a corner too) or arc (finite curvature: the query was the arc's centre).
    Returns the candidate with the unsigned gap, normal and touching points (unchanged
    when the sign was right).
    """
    gap, pax, pay, pbx, pby, nx, ny, k = c
    end_a, end_b = _at(pax, pay, ends_a), _at(pbx, pby, ends_b)
    if math.isinf(k):  # a corner of one body against the other's outline
        if (end_b and _at(pax, pay, corners_a)) or (end_a and _at(pbx, pby, corners_b)):
            d = math.hypot(pax - pbx, pay - pby)
            if d > 0.0:
                return (d, pax, pay, pbx, pby, (pax - pbx) / d, (pay - pby) / d, k)
        return c
    if k <= 0.0 or end_a == end_b:  # parametric pieces have their own (inner) rules
        return c
    r = 1.0 / k
    if end_b:  # the arc is A's: centre w = p_a + r n
        wx, wy = pax + r * nx, pay + r * ny
        d = math.hypot(wx - pbx, wy - pby)
        ux, uy = (wx - pbx) / d, (wy - pby) / d
        return (d - r, wx - r * ux, wy - r * uy, pbx, pby, ux, uy, k)
    wx, wy = pbx - r * nx, pby - r * ny  # the arc is B's
    d = math.hypot(pax - wx, pay - wy)
    ux, uy = (pax - wx) / d, (pay - wy) / d
    return (d - r, pax, pay, wx + r * ux, wy + r * uy, ux, uy, k)


def _reach(world) -> list[float]:
    """How far any point of each body can move in the coming step, twice over [m]."""
    h = world.dt
    out = []
    tip_speed = 0.0
    if world.hand is not None:
        tip_speed = float(np.abs(world.qd).max()) * 0.25  # links + tip radius < 0.25 m
    for b in world.bodies:
        if b.kind == FREE:
            vx, vy, w = world._v[b.index]
            out.append(2.0 * h * (math.hypot(vx, vy) + abs(w) * b.outline.bound))
        elif b.kind == TIP:
            out.append(2.0 * h * tip_speed)
        else:
            out.append(0.0)
    return out


def _jac_into(world, frames, body, px, py, dx, dy, row, sign):
    """Add ``sign * d . (velocity of body's material point p)`` coefficients to ``row``."""
    if body.kind == FREE:
        k = 3 * body.index
        cx, cy = world._x[body.index, 0], world._x[body.index, 1]
        row[k] += sign * dx
        row[k + 1] += sign * dy
        row[k + 2] += sign * (-dx * (py - cy) + dy * (px - cx))
    elif body.kind == TIP:
        off = 3 * len(world._x) + 3 * body.index
        for k, (jx, jy) in enumerate(frames[0][body.index]):
            row[off + k] += sign * (-dx * (py - jy) + dy * (px - jx))


def point_velocity(world, body, px: float, py: float) -> tuple[float, float]:
    """World velocity (2,) [m/s] of ``body``'s material point at (px, py)."""
    frames = world.hand.frames(world.q) if world.hand is not None else None
    nu = np.concatenate([world._v.ravel(), world.qd])
    rx, ry = np.zeros(len(nu)), np.zeros(len(nu))
    _jac_into(world, frames, body, px, py, 1.0, 0.0, rx, 1.0)
    _jac_into(world, frames, body, px, py, 0.0, 1.0, ry, 1.0)
    return float(rx @ nu), float(ry @ nu)


def _dynamics(world, tau):
    """Inverse inertia (nv, nv) and generalized force (nv,)."""
    nb = len(world._x)
    nv = 3 * nb + (6 if world.hand is not None else 0)
    Minv = np.zeros((nv, nv))
    f = np.zeros(nv)
    gx, gy = world.gravity
    for b in world.bodies:
        if b.kind == FREE:
            k = 3 * b.index
            Minv[k, k] = Minv[k + 1, k + 1] = 1.0 / b.mass
            Minv[k + 2, k + 2] = 1.0 / b.inertia
            f[k], f[k + 1] = b.mass * gx, b.mass * gy
    if world.hand is not None:
        M, h = world.hand.mass_bias(world.q, world.qd)
        o = 3 * nb
        for s in (slice(o, o + 3), slice(o + 3, o + 6)):
            Minv[s, s] = np.linalg.inv(M[s.start - o : s.stop - o, s.start - o : s.stop - o])
        f[o:] = tau - h
    return Minv, f


def _rows(world, frames, cands, nv):
    """Normal rows N (n, nv), tangent rows T (n, nv), gaps and friction of the candidates."""
    n = len(cands)
    N, T = np.zeros((n, nv)), np.zeros((n, nv))
    mu = np.zeros(n)
    bodies = world.bodies
    for r, (i, j, _gap, pax, pay, pbx, pby, nx, ny, _k) in enumerate(cands):
        a, b = bodies[i], bodies[j]
        _jac_into(world, frames, a, pax, pay, nx, ny, N[r], 1.0)
        _jac_into(world, frames, b, pbx, pby, nx, ny, N[r], -1.0)
        _jac_into(world, frames, a, pax, pay, -ny, nx, T[r], 1.0)
        _jac_into(world, frames, b, pbx, pby, -ny, nx, T[r], -1.0)
        mu[r] = max(a.friction, b.friction)
    return N, T, mu


def _limit_rows(world, nv, h):
    if world.hand is None:
        return np.zeros((0, nv)), np.zeros(0), np.zeros(0, int)
    lim = world.hand.limits
    o = nv - 6
    rows, phi, idx = [], [], []
    for k in range(6):
        near = max(0.01, 2.0 * abs(world.qd[k]) * h)
        for side, gap in ((1.0, world.q[k] - lim[k, 0]), (-1.0, lim[k, 1] - world.q[k])):
            if gap < near:
                r = np.zeros(nv)
                r[o + k] = side
                rows.append(r)
                phi.append(gap)
                idx.append(k)
    if not rows:
        return np.zeros((0, nv)), np.zeros(0), np.zeros(0, int)
    return np.array(rows), np.array(phi), np.array(idx)


#: relative diagonal shift of the step's LCP when Lemke fails on it even with gaps only
#: closed (:func:`step`): a dense, nearly parallel contact set (a 12 cm rounded square's
#: corner arc on a flat pad, 30 contacts: condition number 3e21) defeated Lemke's
#: degeneracy handling in floating point; ``A + 1e-12 max(diag A) I`` was solved there with
#: residual 1.2e-8 on the original problem, still checked (<= 1e-6) before it is used
STEP_REGULARIZE = 1e-12
#: the shifts :func:`_solve` tries, in units of its ``regularize``, until one is verified: a
#: 26-row jam of a rounded rectangle on the palm between both fingers at their limits
#: (explore_object fuzzing, 2026-11-25; condition number 5e18) defeated Lemke at 1e-12 and
#: was solved at 1e-10 with residual 2.2e-8 on the original problem (1e-8: 2.2e-6, refused)
REGULARIZE_STEPS = (1.0, 10.0, 100.0, 1000.0)


def _solve(M, q, what, regularize: float = 0.0, compliant: bool = False):
    """Lemke's solution of the LCP (M, q), verified (see :func:`planner.sim.lcp.solve_lcp`).

    With ``regularize > 0`` a failed solve is retried on ``M + eps I`` (eps = ``regularize``
    times the largest diagonal entry, then 10, 100, 1000 times that,
    :data:`REGULARIZE_STEPS`, until an answer passes): for the position projection, whose matrix
    ``N M^-1 N^T`` is only positive semidefinite when contacts jam, that makes it a P-matrix
    with a unique solution - a projection that is exact to eps, which is all a projection
    needs. The answer is still checked on the original problem (residual <= 1e-6).

    With ``compliant``, a regularized answer that fails that check (the original problem
    has no solution: no displacement removes every penetration, e.g. a disc squeezed
    between two walls closer than its diameter) is returned as it is: the exact solution
    of ``M + eps I``, i.e. the equilibrium of equal stiff springs at the penetrating rows,
    which removes what can be removed and shares the rest (:func:`_project`).
    """
    z, status, _ = solve_lcp(M, q)
    if status == 0:
        return z
    if regularize > 0.0 and len(q):
        scale = regularize * max(1.0, float(np.abs(np.diag(M)).max()))
        for k in REGULARIZE_STEPS:
            zr, st, _ = solve_lcp(M + k * scale * np.eye(len(q)), q)
            if st == 0 and (compliant or lcp_residual(M, q, zr) <= 1e-6):
                return zr
    raise InfeasibleProblem(
        f"{what}: Lemke stopped on a {'ray' if status == 1 else 'pivot limit'}",
        problem={"M": M, "q": q},
        solver="lemke",
    )


def _project(world, frames, cands, Minv):
    """Post-stabilization: move positions out of penetration (velocities untouched).

    A jam (no displacement removes every penetration: contacts and joint limits that
    oppose each other) gets the compliant projection of :func:`_solve`; what penetration
    leaves beyond ``projection_tolerance`` [m] is put in ``world.jam`` for the ``jammed``
    event (0 otherwise). The step's LCP then keeps it from growing (its fallback closes
    gaps only)."""
    nv = Minv.shape[0]
    N, _, _ = _rows(world, frames, cands, nv)
    phi = np.array([c[2] for c in cands])
    L, lphi, _ = _limit_rows(world, nv, 0.0)
    N, phi = np.vstack([N, L]), np.concatenate([phi, lphi])
    G = N @ Minv @ N.T
    try:
        z = _solve(G, phi, "position projection", regularize=1e-9, compliant=True)
    except InfeasibleProblem as exc:
        raise InfeasibleProblem(
            f"{exc}; {_deepest(world, cands)}", problem=exc.problem, solver=exc.solver
        ) from None
    # the deepest penetration left [m] (contact rows; the limit rows' gaps are in rad)
    left = float(-np.min((phi + G @ z)[: len(cands)], initial=0.0))
    world.jam = left if left > world.projection_tolerance else 0.0
    dq = Minv @ (N.T @ z)
    nb = len(world._x)
    world._x += dq[: 3 * nb].reshape(nb, 3)
    if world.hand is not None:
        world.q += dq[3 * nb :]


def _deepest(world, cands) -> str:
    """What a failed projection met, for its message: the deepest penetration [mm], its
    bodies, and the fastest joint of the hand [rad/s] (a penetration of centimetres is a
    body that went through another in one step: a runaway, see the module docstring)."""
    i, j, gap = min(cands, key=lambda c: c[2])[:3]
    names = [b.name for b in world.bodies]
    msg = f"deepest penetration {-1e3 * gap:.1f} mm, {names[int(i)]} into {names[int(j)]}"
    if world.hand is not None and len(world.qd):
        k = int(np.argmax(np.abs(world.qd)))
        msg += f" (fastest joint: {k} at {abs(float(world.qd[k])):.3g} rad/s)"
    return msg


def step(world, tau) -> StepResult:
    """Advance ``world`` by one step (see the module docstring)."""
    h = world.dt
    P, frames = _placements(world)
    cands = find_contacts(world, world.margin, P)
    Minv, f = _dynamics(world, tau)
    if cands and min(c[2] for c in cands) < -world.projection_tolerance:
        _project(world, frames, cands, Minv)
        P, frames = _placements(world)
        cands = find_contacts(world, world.margin, P)
        Minv, f = _dynamics(world, tau)
    nv = Minv.shape[0]
    nu = np.concatenate([world._v.ravel(), world.qd])
    v_free = nu + h * (Minv @ f)
    N, T, mu = _rows(world, frames, cands, nv)
    gap = np.array([c[2] for c in cands])
    L, lphi, lidx = _limit_rows(world, nv, h)
    nc, nl = len(cands), len(L)
    pn, pt, pl = np.zeros(nc), np.zeros(nc), np.zeros(nl)
    if nc + nl:
        fr = np.flatnonzero(mu > 0)
        nf = len(fr)
        Nall = np.vstack([N, L])
        R = np.vstack([Nall, T[fr], -T[fr]])
        G = R @ Minv @ R.T
        nn = nc + nl
        m = nn + 3 * nf
        A = np.zeros((m, m))
        A[: nn + 2 * nf, : nn + 2 * nf] = G
        for k, c in enumerate(fr):
            e = nn + 2 * nf + k
            A[nn + k, e] = A[nn + nf + k, e] = 1.0
            A[e, c] = mu[c]
            A[e, nn + k] = A[e, nn + nf + k] = -1.0
        b = np.concatenate([R @ v_free, np.zeros(nf)])
        phi = np.concatenate([gap, lphi])
        z, status, _ = solve_lcp(A, b + np.concatenate([phi / h, np.zeros(m - nn)]))
        if status == 0 and gains_energy(G, b, z, phi, nn + 2 * nf, nn, h):
            status = 1  # a wedged answer (module docstring, "Energy"): close gaps only
        if status != 0:  # a jam with sub-tolerance penetration: close gaps only (see lcp.py)
            b[:nn] += np.maximum(phi, 0.0) / h
            z = _solve(A, b, "contact problem", regularize=STEP_REGULARIZE)
        pn, pl = z[:nc], z[nc:nn]
        pt[fr] = z[nn : nn + nf] - z[nn + nf : nn + 2 * nf]
        nu_new = v_free + Minv @ (R.T @ z[: nn + 2 * nf])
    else:
        nu_new = v_free
    nb = len(world._x)
    world._v = nu_new[: 3 * nb].reshape(nb, 3).copy()
    world._x += h * world._v
    if world.hand is not None:
        world.qd = nu_new[3 * nb :].copy()
        world.q += h * world.qd
    return _result(np.array(cands, float).reshape(-1, 10), mu, pn, pt, T @ nu_new, lidx, pl)


class _Compiled:
    """What the compiled step needs of a world's bodies (rebuilt when bodies are added)."""

    def __init__(self, world) -> None:
        from planner.sim.planar.packed_outlines import PackedOutlines

        bodies = world.bodies
        free = [b for b in bodies if b.kind == FREE]
        self.count = len(bodies)
        self.kind = np.array([b.kind for b in bodies], np.int64)
        self.index = np.array([b.index for b in bodies], np.int64)
        self.mu = np.array([b.friction for b in bodies], float)
        self.mass = np.array([b.mass for b in free], float)
        self.inertia = np.array([b.inertia for b in free], float)
        self.packed = PackedOutlines.from_bodies(bodies)
        self.poses = np.array([b.pose for b in bodies], float).reshape(-1, 3)
        self.out = np.empty((32, 10))
        self.counts = np.empty(len(self.packed.pairs), np.int64)


def _compiled(world) -> _Compiled:
    ck = getattr(world, "_compiled_data", None)
    if ck is None or ck.count != len(world.bodies):
        ck = _Compiled(world)
        world._compiled_data = ck
    return ck


_NO_HAND = (np.zeros(6), np.zeros((2, 4, 6)), np.zeros((6, 2)))


def step_fast(world, tau) -> StepResult:
    """:func:`step` with the whole step in one compiled call (same state to ~1e-15).

    Kinematics, the contact search (:mod:`planner.sim.planar.geometry_kernel`), dynamics,
    contact rows, the position projection and the LCP and the update run in
    :func:`planner.sim.planar.step_kernel.full_step`. A step whose projection or LCP the
    kernel cannot answer is done by :func:`step` instead (which retries and raises); bodies
    with pieces the compiled search does not know (Gaussian bumps, splines) use the Python
    search with the compiled rest.
    """
    from planner.sim.planar.step_kernel import full_step

    ck = _compiled(world)
    hand = world.hand
    if hand is not None:
        q, qd, tau_arr, packed, limits = world.q, world.qd, tau, hand.packed, hand.limits
    else:
        q, qd, tau_arr = _NO_HAND[0].copy(), _NO_HAND[0].copy(), _NO_HAND[0]
        packed, limits = _NO_HAND[1], _NO_HAND[2]
    tau_arr = np.asarray(tau_arr, float)
    gx, gy = world.gravity
    pk = ck.packed
    while True:
        status, n, pn, pt, slip, mu, lj, lp = full_step(
            world.dt, gx, gy, world.margin, world.projection_tolerance, pk.F, pk.I,
            pk.pairs, ck.poses, ck.kind, ck.index, ck.mu, world._x, world._v, ck.mass,
            ck.inertia, hand is not None, q, qd, tau_arr, packed, limits, COVERS, ck.out,
            ck.counts,
        )  # fmt: skip
        if status != 4:
            break
        ck.out = np.empty((2 * n, 10))
    if status == 5:
        return _step_python_search(world, tau, ck, q, qd, tau_arr, packed, limits)
    if status != 0:  # nothing was updated
        return step(world, tau)
    return _result(ck.out[:n].copy(), mu, pn, pt, slip, lj, lp)


def _result(arr, mu, pn, pt, slip, lj, lp) -> StepResult:
    return StepResult(
        arr[:, 0].astype(int),
        arr[:, 1].astype(int),
        arr[:, 2],
        arr[:, 3:5],
        arr[:, 5:7],
        arr[:, 7:9],
        arr[:, 9],
        mu,
        pn,
        pt,
        slip,
        lj,
        lp,
    )


def _step_python_search(world, tau, ck, q, qd, tau_arr, packed, limits) -> StepResult:
    """The compiled step after the Python contact search (bodies the kernel does not know)."""
    from planner.sim.planar.step_kernel import contact_step

    P, _ = _placements(world)
    cands = find_contacts(world, world.margin, P)
    if cands and min(c[2] for c in cands) < -world.projection_tolerance:
        return step(world, tau)
    arr = np.array(cands, float).reshape(-1, 10)
    gx, gy = world.gravity
    status, pn, pt, slip, mu, lj, lp = contact_step(
        world.dt, gx, gy, arr, ck.kind, ck.index, ck.mu, world._x, world._v, ck.mass,
        ck.inertia, world.hand is not None, q, qd, tau_arr, packed, limits, COVERS,
    )  # fmt: skip
    if status != 0:  # nothing was updated
        return step(world, tau)
    return _result(arr, mu, pn, pt, slip, lj, lp)
