"""How far the map-space gait can turn an object from the pose it rests in (§2.2.1).

``planner.grasp.plan_gait`` looks for a *cyclic* gait from its most promising phase-1
grasps (a greedy depth-first walk that keeps the best few successors of every phase 1);
the executor (:func:`.machine.explore_object`) starts from the object resting unturned on
the palm. :func:`start_reach` asks the executor's question on the same map-space tables
(:func:`planner.grasp.gait.gait_problem`: force closure, the fingers' reach at every pose,
the fingertips' rolling range): from every phase-1 grasp at the resting pose (pose 0),
following **every** handoff (forward 1 → 2 → 3 → 1 and the two transitions 4), how far
can the object turn? A full turn, or the furthest rotation and the constraint that blocks
it there (the batch table of ``benchmarks/bench_gait.py`` reports it).

Measured with it (ball_with_ridge hand, mu = 1, 5 deg grid): the batch's 1.5:1 ellipses
turn a full turn (a state comes back after whole turns: a cyclic gait exists, which
``plan_gait`` with its 6 successors per phase does not find); the 2:1 ones 10 deg (their
only force-closure grasps lying flat are across the long axis, left 165-170 deg, and the
left pad reaches no contact beyond 170 deg); the 3:1 and 4:1 ones have no force-closure
grasp within reach lying flat. With the friction the executor plans with (``mu (1 -
friction_margin)`` = 0.8) the 1.5:1 ones turn only 25 / 15 deg (ellipses of 1.3:1 still a
full turn, 1.4:1 95 deg), and the rounded squares 80-90 deg.
"""

from __future__ import annotations

import heapq
import math
from dataclasses import dataclass

import numpy as np

from planner import checks

#: the search stops after this many phase-1 entries (a guard; the batch needs < 10 000)
MAX_STATES = 200_000


@dataclass(frozen=True)
class StartReach:
    """Outcome of :func:`start_reach`.

    Attributes:
        rotation: furthest clockwise object rotation reachable from the resting pose [rad]
            (``2 pi`` when a full turn is reachable).
        full_turn: a full turn is reachable.
        start_grasps: phase-1 grasps (force closure, both contacts within reach) at the
            resting pose.
        states: phase-1 entries ``(pose, left, right)`` visited.
        blocking: what stops the object at ``rotation`` ("" for a full turn).
        start: ``(beta_left, beta_right)`` world polar angles [rad] about the object
            origin of the start grasp of the furthest-turning path (right in (-pi, pi]),
            or None without a start grasp.
    """

    rotation: float
    full_turn: bool
    start_grasps: int
    states: int
    blocking: str
    start: tuple[float, float] | None = None


def _extent(prob, horizon: int, k: int, i: int, j: int) -> tuple[int, str]:
    """Grid steps phase 1 can rotate from grasp ``(i, j)`` at pose ``k`` and what stops
    it (the rules of ``planner.grasp.gait``: force closure, reach, rolling range)."""
    n, s = prob.theta.size, prob.sign
    cum_l = cum_r = 0.0
    for t in range(1, horizon + 1):
        il, jr = (i + s * (t - 1)) % n, (j + s * (t - 1)) % n
        cum_l += prob.arc[il]
        cum_r += prob.arc[jr]
        ii, jj, kk = (i + s * t) % n, (j + s * t) % n, (k + t) % n
        why = [w for w, bad in (
            ("force closure lost", not prob.fc_lr[ii, jj]),
            ("the left finger's reach", not prob.reach["left"][kk, ii]),
            ("the right finger's reach", not prob.reach["right"][kk, jj]),
            ("the fingertip rolling range", cum_l > prob.roll["left"] + 1e-12
             or cum_r > prob.roll["right"] + 1e-12),
        ) if bad]  # fmt: skip
        if why:
            return t - 1, ", ".join(why)
    return horizon, ""


def _horizon(prob) -> int:
    n = prob.theta.size
    roll = min(prob.roll["left"], prob.roll["right"])
    arc = float(np.min(prob.arc))
    return n if not (math.isfinite(roll) and arc > 0) else min(n, int(roll / arc + 1e-9) + 1)


def _handoffs(prob, horizon: int, k2: int, i2: int, j2: int) -> set[tuple[int, int]]:
    """Phase-1 grasps ``(left, right)`` that a handoff at pose ``k2`` reaches from the
    grasp ``(i2, j2)`` where phase 1 ended (each able to rotate again)."""
    from planner.grasp.gait_result import component_run

    rl, rr = prob.reach["left"][k2], prob.reach["right"][k2]
    comp_l, comp_r = component_run(rl, i2), component_run(rr, j2)
    out: set[tuple[int, int]] = set()
    if prob.fc_lp[k2, i2]:  # the left holds on the palm: the right moves (then the left)
        for jt in comp_r[prob.fc_rp[k2][comp_r]]:  # route A: 1 -> 2 -> 3 -> 1
            out.update((int(x), int(jt)) for x in comp_l[prob.fc_lr[comp_l, jt]])
        out.update((i2, int(x)) for x in comp_r[prob.fc_lr[i2][comp_r]])  # B: 1 -> 2 -> 1
    if prob.fc_rp[k2, j2]:  # C: 1 -> 3 -> 1, the right holds on the palm
        out.update((int(x), j2) for x in comp_l[prob.fc_lr[comp_l, j2]])
    return {g for g in out if _extent(prob, horizon, k2, *g)[0] >= 1}


def _stuck(prob, k: int, i: int, j: int, why: str) -> str:
    """Why the object cannot turn past the end ``(k, i, j)`` of a phase 1."""
    n = prob.theta.size
    deg = np.degrees(prob.theta)
    holds = [name for name, ok in (("left", prob.fc_lp[k % n, i]), ("right", prob.fc_rp[k % n, j]))
             if ok]  # fmt: skip
    after = (f"phase 1 (left at {deg[i]:.0f} deg, right at {deg[j]:.0f} deg, object frame) is "
             f"stopped by {why or 'nothing'}; ")  # fmt: skip
    if not holds:
        return after + "neither finger holds the object on the palm in force closure there"
    return after + (
        f"the {' or '.join(holds)} finger holds it on the palm, but the free "
        "finger reaches no contact that restores a rotating force-closure grasp"
    )


def _no_start_grasp(prob, profile) -> str:
    """Why no phase-1 grasp exists at the resting pose: the best contact line of a pair
    both fingers reach, against the friction cone."""
    from planner.grasp.maps import profile_contacts

    rl, rr = prob.reach["left"][0], prob.reach["right"][0]
    if not rl.any() or not rr.any():
        return "reach: a finger reaches no contact of the resting object"
    pts, nin = profile_contacts(profile, prob.theta)
    il, jr = np.nonzero(rl)[0], np.nonzero(rr)[0]
    d = pts[jr][None, :, :] - pts[il][:, None, :]
    d /= np.maximum(np.linalg.norm(d, axis=2, keepdims=True), 1e-12)
    a_l = np.arccos(np.clip(np.einsum("abk,ak->ab", d, nin[il]), -1, 1))
    a_r = np.arccos(np.clip(-np.einsum("abk,bk->ab", d, nin[jr]), -1, 1))
    best = float(np.degrees(np.min(np.maximum(a_l, a_r))))
    return (f"force closure within reach: at the resting pose the best pair of contacts the "
            f"fingers reach has its contact line {best:.0f} deg off a normal")  # fmt: skip


def start_reach(
    profile,
    hand,
    mu: float = 1.0,
    *,
    resolution: int = 72,
    min_epsilon: float = 0.0,
    max_states: int = MAX_STATES,
) -> StartReach:
    """The furthest clockwise rotation of ``profile`` resting unturned on the palm that
    map-space gaits reach (module docstring).

    Args:
        profile: closed star-shaped profile, object frame, resting with angle 0 [m].
        hand: ``robots.planar_hand.PlanarHand`` (or a reachability model).
        mu: friction coefficient [-] (> 0).
        resolution: contact-angle grid size (rotation step ``2 pi / resolution``).
        min_epsilon: grasps must have a Ferrari-Canny epsilon above this, in [0, 1).
        max_states: cap on the visited phase-1 entries (>= 1).

    Returns:
        the :class:`StartReach`.

    Raises:
        InvalidParameter: bad arguments.
    """
    from planner.grasp.gait import gait_problem

    checks.positive("mu", mu)
    max_states = checks.integer("max_states", max_states, 1)
    prob = gait_problem(profile, hand, mu, resolution=resolution, min_epsilon=min_epsilon)
    n = prob.theta.size
    horizon = _horizon(prob)
    rl, rr = prob.reach["left"][0], prob.reach["right"][0]
    ii, jj = np.nonzero(prob.fc_lr & rl[:, None] & rr[None, :])
    if ii.size == 0:
        return StartReach(0.0, False, 0, 0, _no_start_grasp(prob, profile))
    heap = [(0, int(i), int(j)) for i, j in zip(ii, jj, strict=True)]
    heapq.heapify(heap)
    seen: dict = dict.fromkeys(heap)  # entry -> the entry whose phase 1 led to it
    best = (-1, "", heap[0])
    while heap:
        node = heapq.heappop(heap)  # deepest first: a full turn is found fast
        k, i, j = -node[0], node[1], node[2]
        m, why = _extent(prob, horizon, k % n, i, j)
        if k + m > best[0]:
            best = (k + m, _stuck(prob, k + m, (i + prob.sign * m) % n,
                                  (j + prob.sign * m) % n, why), node)  # fmt: skip
        if k + m >= n:
            start = _root(prob, seen, node)
            return StartReach(2 * math.pi, True, int(ii.size), len(seen), "", start)
        for t in range(m, 0, -1):
            k2, i2, j2 = k + t, (i + prob.sign * t) % n, (j + prob.sign * t) % n
            for g in _handoffs(prob, horizon, k2 % n, i2, j2):
                key = (-k2, *g)
                if key not in seen:
                    seen[key] = node
                    heapq.heappush(heap, key)
        if len(seen) >= max_states:
            break
    rot = 2 * math.pi * best[0] / n
    cap = (
        ""
        if len(seen) < max_states
        else f" (search stopped: {len(seen)} entries, cap {max_states})"
    )
    return StartReach(rot, False, int(ii.size), len(seen), best[1] + cap,
                      _root(prob, seen, best[2]))  # fmt: skip


def _root(prob, parent: dict, node) -> tuple[float, float]:
    """World polar angles [rad] of the start grasp (pose 0) of the path to ``node``."""
    while parent[node] is not None:
        node = parent[node]
    th = prob.theta
    return float(th[node[1]]), float(math.remainder(th[node[2]], 2 * math.pi))


__all__ = ["MAX_STATES", "StartReach", "start_reach"]
