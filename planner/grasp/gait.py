"""Grasp-gait search in map space (§2.2.1, Fig. 2.3, after Leveroni).

The hand has three contacts (left finger, right finger, passive palm) and three phases
(Fig. 2.3): **phase 1** — left and right grasp the object and rotate it (clockwise by
default) by pure rolling; **phase 2** — left holds the object against the palm while the right
finger rolls/slides to a new contact; **phase 3** — right and palm hold while the left finger
relocates. The object rests on the palm; its rotation is discretized with the contact-angle
grid (step ``Δ = 2π/n``).

In map space (object-frame contact angles) a phase-1 rotation by ``Δ`` is one step along
the grasp map's diagonal (Leveroni: fingers fixed in the world, the object turning under
them), and a relocation is a move parallel to one axis. A grasp is *feasible* when it is in
force closure (exact Nguyen test) and every holding finger reaches its contact at the
current object pose (:mod:`planner.grasp.workspace`). Phase 1 also ends when a fingertip has
rolled over its whole sensing range (``roll_length``). A relocating finger stays in contact
along a connected arc of its reachable set (it explores that arc).

Search: from the phase-1 grasp with the most rotation potential, the planner follows the
prototype *forward gait* 1 → 2 → 3 → 1, rotating as far as possible in phase 1 while a
handoff exists; when the nominal next phase is impossible it uses transition 4 (skip a
phase: 1 → 2 → 1 or 1 → 3 → 1). Each relocation target is chosen to maximize the next phase's
rotation, then ε. Because every cycle rotates the object by at least one grid step and the
state space is finite, the walk either dead-ends or returns to a visited state after whole
turns: that loop is the cyclic gait (it rotates the object by a multiple of 360°, so every
point of the outline passes the fingers). Other start grasps are tried before the search
reports that no gait exists, with the constraint that blocked it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from planner.errors import InvalidParameter
from planner.grasp.closure import force_closure_two_planar
from planner.grasp.cones import check_mu
from planner.grasp.maps import ClosureKernel, contact_angles, profile_contacts
from planner.grasp.quality import epsilon_two_planar
from planner.grasp.workspace import WorkspaceTables, as_reachability, rotation, workspace_tables

PHASE_NAMES = {
    1: "left-right (rotate object)",
    2: "left-palm (right relocates)",
    3: "right-palm (left relocates)",
}


@dataclass(frozen=True)
class GaitPhase:
    """One phase of a gait.

    Attributes:
        phase: 1, 2 or 3 (Fig. 2.3).
        holding: the two contacts holding the object, e.g. ``("left", "palm")``.
        moving: the finger that relocates (phases 2, 3) or None (phase 1).
        pose_start, pose_end: object-rotation indices at start/end (rotation ``-Δ k``
            for a clockwise gait).
        rotation: object rotation during the phase [rad] (negative: clockwise).
        start, end: contact angles ``{"left", "right", "palm"}`` in the object frame at the
            start/end of the phase [rad] (NaN for a free finger).
        min_epsilon: smallest ε of the holding grasp during the phase.
        transition: ``"forward"`` or ``"skip"`` (transition 4) into the next phase.
    """

    phase: int
    holding: tuple[str, str]
    moving: str | None
    pose_start: int
    pose_end: int
    rotation: float
    start: dict[str, float]
    end: dict[str, float]
    min_epsilon: float
    transition: str

    def to_json(self) -> dict:
        """JSON-ready dict (angles in degrees, suffixed ``_deg``)."""

        def deg(d: dict[str, float]) -> dict[str, float | None]:
            return {
                k: (round(float(np.rad2deg(v)), 3) if np.isfinite(v) else None)
                for k, v in d.items()
            }

        return {
            "phase": self.phase,
            "name": PHASE_NAMES[self.phase],
            "holding": list(self.holding),
            "moving": self.moving,
            "pose_start": self.pose_start,
            "pose_end": self.pose_end,
            "rotation_deg": round(float(np.rad2deg(self.rotation)), 3),
            "start_deg": deg(self.start),
            "end_deg": deg(self.end),
            "min_epsilon": round(float(self.min_epsilon), 6),
            "transition": self.transition,
        }


@dataclass(frozen=True)
class Gait:
    """Result of :func:`plan_gait`.

    Attributes:
        feasible: a cyclic gait rotating the object by whole turns was found.
        reason: why not (empty when feasible): the constraint that blocked the search.
        phases: the phases of one period of the cyclic gait, in order.
        rotation_per_cycle: mean object rotation per phase-1 → phase-1 cycle [rad]
            (negative for clockwise).
        turns: full object turns of one period (>= 1 when feasible).
        min_epsilon: smallest ε of any holding grasp along the gait.
        coverage: fraction of the outline (contact-angle cells) touched by the fingers.
        resolution: contact-angle grid size n used by the search.
        path: (M, 3) map-space path ``(pose index, left index, right index)`` (-1: free).
    """

    feasible: bool
    reason: str
    phases: tuple[GaitPhase, ...] = ()
    rotation_per_cycle: float = 0.0
    turns: int = 0
    min_epsilon: float = 0.0
    coverage: float = 0.0
    resolution: int = 0
    path: np.ndarray = field(default_factory=lambda: np.zeros((0, 3), dtype=int))

    @property
    def cycles(self) -> int:
        """Number of phase-1 → phase-1 cycles in one period."""
        return sum(1 for p in self.phases if p.phase == 1)

    def to_json(self) -> dict:
        """JSON-ready summary (``gait.json``)."""
        return {
            "feasible": self.feasible,
            "reason": self.reason,
            "rotation_per_cycle_deg": round(float(np.rad2deg(self.rotation_per_cycle)), 4),
            "turns": self.turns,
            "cycles": self.cycles,
            "min_epsilon": round(float(self.min_epsilon), 6),
            "coverage": round(float(self.coverage), 6),
            "resolution": self.resolution,
            "phases": [p.to_json() for p in self.phases],
        }


@dataclass(frozen=True)
class GaitProblem:
    """All tables of a gait search (map space), built by :func:`gait_problem`.

    Attributes:
        theta: (n,) contact angles [rad]; sign: +1 clockwise object rotation, -1 ccw.
        fc_lr, eps_lr: (n, n) left–right grasp map (``[i_left, i_right]``).
        fc_lp, eps_lp, fc_rp, eps_rp: (n, n) finger–palm grasps ``[pose k, finger index]``.
        reach: ``{"left": (n, n), "right": (n, n)}`` reachability ``[pose k, index]``.
        arc: (n,) object arclength between contact angles i and i+sign [m].
        roll: ``{"left", "right"}`` rolling travel limit per phase 1 [m].
        tables: the workspace tables (object placements, palm contacts).
    """

    theta: np.ndarray
    sign: int
    fc_lr: np.ndarray
    eps_lr: np.ndarray
    fc_lp: np.ndarray
    eps_lp: np.ndarray
    fc_rp: np.ndarray
    eps_rp: np.ndarray
    reach: dict[str, np.ndarray]
    arc: np.ndarray
    roll: dict[str, float]
    tables: WorkspaceTables


def gait_problem(
    profile,
    hand=None,
    mu: float = 1.0,
    *,
    mu_palm: float | None = None,
    resolution: int = 72,
    direction: str = "clockwise",
    x0: float = 0.0,
    roll_length: float | None = None,
    min_epsilon: float = 0.0,
) -> GaitProblem:
    """Build the map-space tables of a gait search (see :func:`plan_gait` for arguments)."""
    if not np.isfinite(min_epsilon) or not 0.0 <= min_epsilon < 1.0:
        raise InvalidParameter(f"min_epsilon must be in [0, 1), got {min_epsilon!r}")
    if direction not in ("clockwise", "counterclockwise"):
        raise InvalidParameter(
            f"direction must be 'clockwise' or 'counterclockwise', got {direction!r}"
        )
    mu = check_mu(mu)
    mu_p = mu if mu_palm is None else check_mu(mu_palm)
    reach = as_reachability(hand)
    theta = contact_angles(resolution)
    n = theta.size
    sign = 1 if direction == "clockwise" else -1
    pts, nin = profile_contacts(profile, theta)
    fc_lr = ClosureKernel(n, mu)(pts[:, 0], pts[:, 1], nin[:, 0], nin[:, 1]).copy()
    eps_lr = np.where(
        fc_lr, epsilon_two_planar(pts[:, None], nin[:, None], pts[None], nin[None], mu), 0.0
    )
    tables = workspace_tables(profile, reach, theta, -sign * theta, x0)
    # palm contact of each pose, in the object frame: point on the profile, normal R^T (+y)
    place = tables.placement
    ok_palm = tables.palm_index >= 0
    pp, _ = profile_contacts(profile, np.nan_to_num(place.palm_theta))
    R = rotation(place.angles)
    np_in = R[:, 1, :]  # R^T e_y = second row of R
    fcs, epss = [], []
    for _ in ("left", "right"):
        fc = force_closure_two_planar(pts[None], nin[None], pp[:, None], np_in[:, None], mu, mu_p)
        fc &= ok_palm[:, None]
        eps = epsilon_two_planar(pts[None], nin[None], pp[:, None], np_in[:, None], mu, mu_p)
        fcs.append(fc)
        epss.append(np.where(fc, eps, 0.0))
    arc = np.linalg.norm(np.roll(pts, -sign, axis=0) - pts, axis=1)
    if roll_length is not None:
        if not np.isfinite(roll_length) or roll_length <= 0:
            raise InvalidParameter(f"roll_length must be > 0 [m], got {roll_length!r}")
        roll = {f: float(roll_length) for f in ("left", "right")}
    else:
        rl = getattr(reach, "roll_length", None)
        roll = {f: (float(rl(f)) if rl else np.inf) for f in ("left", "right")}
    if min_epsilon > 0:  # a grasp must also keep a robustness margin (Ferrari–Canny ε)
        fc_lr = fc_lr & (eps_lr > min_epsilon)
        fcs = [fc & (e > min_epsilon) for fc, e in zip(fcs, epss, strict=True)]
    return GaitProblem(
        theta,
        sign,
        fc_lr,
        eps_lr,
        fcs[0],
        epss[0],
        fcs[1],
        epss[1],
        {f: tables.reachable[f] for f in ("left", "right")},
        arc,
        roll,
        tables,
    )


def _component(r: np.ndarray, j: int) -> np.ndarray:
    """Indices of the circular run of True in ``r`` containing ``j`` (sorted by offset)."""
    n = r.size
    if not r[j]:
        return np.zeros(0, dtype=int)
    if r.all():
        return np.arange(n)
    fwd = 0
    while r[(j + fwd + 1) % n]:
        fwd += 1
    back = 0
    while r[(j - back - 1) % n]:
        back += 1
    return np.mod(np.arange(j - back, j + fwd + 1), n)


def _arc_path(j: int, j2: int, n: int, comp: np.ndarray) -> np.ndarray:
    """Cells swept moving from ``j`` to ``j2`` inside the component ``comp``."""
    if comp.size == n:  # whole circle: the shorter way
        d = (j2 - j) % n
        return np.mod(j + (np.arange(d + 1) if d <= n - d else -np.arange(n - d + 1)), n)
    pos = {int(c): t for t, c in enumerate(comp)}
    a, b = sorted((pos[j], pos[j2]))
    return comp[a : b + 1]


class _Search:
    """Greedy forward-gait walk with transition 4 (see the module docstring)."""

    def __init__(self, prob: GaitProblem):
        self.p = prob
        self.n = prob.theta.size
        # phase 1 cannot roll further than the shortest fingertip roll length allows
        roll = min(prob.roll["left"], prob.roll["right"])
        arc_min = float(np.min(prob.arc)) if prob.arc.size else 0.0
        horizon = self.n
        if np.isfinite(roll) and arc_min > 0:
            horizon = min(self.n, int(np.floor(roll / arc_min + 1e-9)) + 1)
        self.diag = np.arange(horizon + 1)

    def p1_extent(self, k: int, i, j, explain: bool = False) -> tuple[np.ndarray, list[str]]:
        """Steps phase 1 can rotate from entries (k, i, j) (arrays), and (``explain``) what
        stops it."""
        p, n, s = self.p, self.n, self.p.sign
        i = np.atleast_1d(i)[:, None]
        j = np.atleast_1d(j)[:, None]
        t = self.diag[None, :]
        ii, jj, kk = (i + s * t) % n, (j + s * t) % n, (k + t) % n
        fc = p.fc_lr[ii, jj]
        rl = p.reach["left"][kk, ii]
        rr = p.reach["right"][kk, jj]
        cum_l = np.concatenate([np.zeros((ii.shape[0], 1)), np.cumsum(p.arc[ii[:, :-1]], 1)], 1)
        cum_r = np.concatenate([np.zeros((jj.shape[0], 1)), np.cumsum(p.arc[jj[:, :-1]], 1)], 1)
        roll = (cum_l <= p.roll["left"] + 1e-12) & (cum_r <= p.roll["right"] + 1e-12)
        valid = fc & rl & rr & roll
        ext = np.where(valid.all(1), min(n, t.shape[1] - 1), np.argmin(valid, axis=1) - 1)
        stops: list[str] = []
        for r in range(ii.shape[0] if explain else 0):
            e = ext[r]
            if e >= n or e < 0:
                stops.append("none" if e >= n else "start grasp infeasible")
                continue
            c = e + 1
            why = [
                w
                for w, bad in (
                    ("force closure lost", not fc[r, c]),
                    ("left finger leaves its workspace", not rl[r, c]),
                    ("right finger leaves its workspace", not rr[r, c]),
                    ("fingertip rolling range exhausted", not roll[r, c]),
                )
                if bad
            ]
            stops.append(", ".join(why))
        return np.maximum(ext, -1), stops

    def relocate(self, finger: str, k: int, cur: int, ok_target: np.ndarray):
        """Candidate targets of a relocation of ``finger`` at pose k (component of ``cur``)."""
        comp = _component(self.p.reach[finger][k], cur)
        return comp[ok_target[comp]] if comp.size else comp

    def successors(self, k: int, i: int, j: int, m_max: int, limit: int = 6):
        """Phase-1 entries reachable from entry (k, i, j) by one cycle, best first.

        Returns:
            list of ``(t, route, (i3, j3), extent)``: rotate ``t`` steps in phase 1, then
            ``route`` "A" (forward 1→2→3→1), "B" (1→2→1, skip 3) or "C" (1→3→1, skip 2),
            re-entering phase 1 at ``(k + t, i3, j3)`` which can rotate ``extent`` >= 1 steps.
        """
        p, n, s = self.p, self.n, self.p.sign
        out = []
        seen = set()
        for route in ("A", "B", "C"):
            for t in range(m_max, 0, -1):
                k2, i2, j2 = (k + t) % n, (i + s * t) % n, (j + s * t) % n
                ci, cj = [], []
                if route in "AB":
                    if not p.fc_lp[k2, i2]:
                        continue
                    if route == "A":
                        for jt in self.relocate("right", k2, j2, p.fc_rp[k2]):
                            ti = self.relocate("left", k2, i2, p.fc_lr[:, jt])
                            ci.append(ti)
                            cj.append(np.full(ti.size, jt))
                    else:
                        tj = self.relocate("right", k2, j2, p.fc_lr[i2])
                        ci.append(np.full(tj.size, i2))
                        cj.append(tj)
                else:
                    if not p.fc_rp[k2, j2]:
                        continue
                    ti = self.relocate("left", k2, i2, p.fc_lr[:, j2])
                    ci.append(ti)
                    cj.append(np.full(ti.size, j2))
                ci = np.concatenate(ci) if ci else np.zeros(0, dtype=int)
                cj = np.concatenate(cj) if cj else np.zeros(0, dtype=int)
                if ci.size == 0:
                    continue
                ext, _ = self.p1_extent(k2, ci, cj)
                good = ext >= 1
                ci, cj, ext = ci[good], cj[good], ext[good]
                order = np.argsort(-(ext * 10.0 + p.eps_lr[ci, cj]), kind="stable")
                for a in order[:limit]:
                    key = (k2, int(ci[a]), int(cj[a]))
                    if key not in seen:
                        seen.add(key)
                        out.append((t, route, (int(ci[a]), int(cj[a])), int(ext[a])))
                if len(out) >= limit:
                    return out
        return out


def _arc_fraction(cells: set[int], n: int) -> float:
    return len(cells) / n


def plan_gait(
    profile,
    hand=None,
    mu: float = 1.0,
    *,
    mu_palm: float | None = None,
    resolution: int = 72,
    direction: str = "clockwise",
    x0: float = 0.0,
    roll_length: float | None = None,
    min_epsilon: float = 0.0,
    max_starts: int = 12,
    max_nodes: int = 400,
) -> Gait:
    """Find a cyclic grasp gait that turns the object by whole turns (§2.2.1, Fig. 2.3).

    Args:
        profile: closed planar profile, star-shaped about its origin (object frame) [m].
        hand: ``robots.planar_hand.PlanarHand`` (default ``PlanarHand()``) or any
            :class:`planner.grasp.workspace.ReachabilityModel`.
        mu: finger–object friction coefficient (>= 0).
        mu_palm: palm–object friction coefficient (default ``mu``).
        resolution: contact-angle grid size n (rotation step 2π/n), >= 8.
        direction: ``"clockwise"`` (thesis) or ``"counterclockwise"`` object rotation.
        x0: x position of the object origin on the palm [m].
        roll_length: rolling travel limit per phase 1 on each fingertip [m] (default: from
            the hand, e.g. ``2 r_f max_tip_contact_angle``; inf when the model has none).
        min_epsilon: a holding grasp must also have ε above this margin, in [0, 1) (0: force
            closure suffices).
        max_starts: phase-1 start grasps tried before giving up (>= 1).
        max_nodes: phase-1 entries expanded by the depth-first search, over all starts.

    Returns:
        The :class:`Gait` (``feasible`` False with a ``reason`` when none exists).
    """
    if int(resolution) != resolution or resolution < 8:
        raise InvalidParameter(f"resolution must be an integer >= 8, got {resolution!r}")
    if int(max_starts) < 1:
        raise InvalidParameter(f"max_starts must be >= 1, got {max_starts!r}")
    prob = gait_problem(
        profile,
        hand,
        mu,
        mu_palm=mu_palm,
        resolution=resolution,
        direction=direction,
        x0=x0,
        roll_length=roll_length,
        min_epsilon=min_epsilon,
    )
    return search_gait(prob, max_starts=max_starts, max_nodes=max_nodes)


def _infeasible_reason(prob: GaitProblem) -> str | None:
    """A global reason no gait can exist, or None."""
    rl, rr = prob.reach["left"], prob.reach["right"]
    if not rl.any() or not rr.any():
        who = "left" if not rl.any() else "right"
        return f"workspace: the {who} finger cannot reach the object at any orientation"
    p1 = prob.fc_lr[None, :, :] & rl[:, :, None] & rr[:, None, :]
    if not p1.any():
        return (
            "workspace and force closure: at no orientation can the two fingers reach a "
            "pair of contacts in force closure (object too long/thin for the finger "
            f"workspaces; the left finger reaches {rl.mean():.0%} and the right finger "
            f"{rr.mean():.0%} of (pose, contact) cells)"
        )
    lp = (prob.fc_lp & rl).any()
    rp = (prob.fc_rp & rr).any()
    if not lp and not rp:
        if prob.fc_lp.any() or prob.fc_rp.any():
            return (
                "workspace (palm grasps): the contacts that would hold the object in force "
                "closure against the palm lie outside both fingers' workspaces at every "
                "orientation, so no finger is ever free to relocate"
            )
        return (
            "force closure (palm grasps): no contact forms a force-closure grasp with the "
            "palm contact at any orientation, so no finger is ever free to relocate"
        )
    return None


def search_gait(prob: GaitProblem, max_starts: int = 12, max_nodes: int = 400) -> Gait:
    """Run the gait search on prebuilt tables (see :func:`plan_gait`)."""
    n = prob.theta.size
    why = _infeasible_reason(prob)
    if why is not None:
        return Gait(False, why, resolution=n)
    srch = _Search(prob)
    rl, rr = prob.reach["left"], prob.reach["right"]
    # start candidates: every feasible phase-1 grasp, best rotation potential first
    starts = []
    for k in range(n):
        ii, jj = np.nonzero(prob.fc_lr & rl[k][:, None] & rr[k][None, :])
        if ii.size:
            ext, _ = srch.p1_extent(k, ii, jj)
            for a in np.argsort(-(ext * 10.0 + prob.eps_lr[ii, jj]))[:2]:
                starts.append((int(ext[a]), k, int(ii[a]), int(jj[a])))
    starts.sort(key=lambda x: -x[0])
    first_reason = None
    srch.dead = set()
    budget = [max_nodes]
    for _, k0, i0, j0 in starts[:max_starts]:
        if (k0, i0, j0) in srch.dead:
            continue
        result = _walk(srch, k0, i0, j0, budget)
        if isinstance(result, Gait):
            return result
        first_reason = first_reason or result
    return Gait(False, first_reason or "no start grasp", resolution=n)


def _walk(srch: _Search, k: int, i: int, j: int, budget: list[int]):
    """Depth-first search for a cycle of phase-1 entries from (k, i, j).

    Returns a :class:`Gait` or the reason string of the first dead end. ``budget`` (a
    one-element list) caps the number of node expansions shared by all starts.
    """
    prob, n = srch.p, srch.n
    th = prob.theta
    dead: set = srch.dead
    path: list[tuple[int, int, int]] = []
    on_path: dict[tuple[int, int, int], int] = {}
    edges: list = []  # edge taken from path[d] to path[d+1]
    iters: dict[tuple[int, int, int], list] = {}
    reason = None
    node = (k, i, j)
    path.append(node)
    on_path[node] = 0
    while path:
        node = path[-1]
        if node not in iters:
            if budget[0] <= 0:
                break
            budget[0] -= 1
            ext, stops = srch.p1_extent(node[0], node[1], node[2], explain=True)
            m = int(min(ext[0], n))
            if m < 1:
                reason = reason or (
                    f"phase 1 cannot rotate the object from grasp "
                    f"left={np.rad2deg(th[node[1]]):.1f}°, right="
                    f"{np.rad2deg(th[node[2]]):.1f}° at pose {node[0]}: {stops[0]}"
                )
                iters[node] = []
            else:
                iters[node] = srch.successors(*node, m)
                if not iters[node]:
                    reason = reason or (
                        f"after rotating up to {np.rad2deg(2 * np.pi * m / n):.1f}° in phase 1 "
                        f"(stopped by: {stops[0]}) no handoff exists: no finger–palm grasp in "
                        "force closure within reach, or no relocation of the free finger "
                        "restores a left–right grasp that can rotate further"
                    )
        advanced = False
        while iters[node]:
            t, route, (i3, j3), _ = iters[node].pop(0)
            nxt = ((node[0] + t) % n, i3, j3)
            if nxt in on_path:  # a cycle: every edge rotates >= 1 step, so whole turns
                loop_edges = edges[on_path[nxt] :] + [(node, t, route, (i3, j3))]
                return _build_gait(
                    prob, [(a[0][0], a[0][1], a[0][2], a[1], a[2], (*a[3], 0)) for a in loop_edges]
                )
            if nxt in dead:
                continue
            edges.append((node, t, route, (i3, j3)))
            path.append(nxt)
            on_path[nxt] = len(path) - 1
            advanced = True
            break
        if not advanced:
            dead.add(node)
            path.pop()
            del on_path[node]
            if edges:
                edges.pop()
    return reason or "search budget exhausted before a cyclic gait was found"


def _build_gait(prob: GaitProblem, loop) -> Gait:
    n, s = prob.theta.size, prob.sign
    th = prob.theta
    step = 2 * np.pi / n
    phases: list[GaitPhase] = []
    covered: set[int] = set()
    path = []
    eps_all = []
    for k, i, j, t, route, (i3, j3, _) in loop:
        k2, i2, j2 = (k + t) % n, (i + s * t) % n, (j + s * t) % n
        di = np.mod(i + s * np.arange(t + 1), n)
        dj = np.mod(j + s * np.arange(t + 1), n)
        covered.update(di.tolist())
        covered.update(dj.tolist())
        for a in range(t + 1):
            path.append(((k + a) % n, int(di[a]), int(dj[a])))
        e1 = float(prob.eps_lr[di, dj].min())
        eps_all.append(e1)
        palm = lambda kk: float(prob.tables.placement.palm_theta[kk])  # noqa: E731
        phases.append(
            GaitPhase(
                1,
                ("left", "right"),
                None,
                k,
                k2,
                -s * step * t,
                {"left": th[i], "right": th[j], "palm": palm(k)},
                {"left": th[i2], "right": th[j2], "palm": palm(k2)},
                e1,
                "forward" if route in "AB" else "skip",
            )
        )
        if route in "AB":  # phase 2: left + palm hold, right relocates
            jt = j3 if route == "B" else j3
            comp = _component(prob.reach["right"][k2], j2)
            covered.update(_arc_path(j2, jt, n, comp).tolist())
            e2 = float(prob.eps_lp[k2, i2])
            eps_all.append(e2)
            path.append((k2, i2, -1))
            path.append((k2, i2, jt))
            phases.append(
                GaitPhase(
                    2,
                    ("left", "palm"),
                    "right",
                    k2,
                    k2,
                    0.0,
                    {"left": th[i2], "right": th[j2], "palm": palm(k2)},
                    {"left": th[i2], "right": th[jt], "palm": palm(k2)},
                    e2,
                    "forward" if route == "A" else "skip",
                )
            )
            if route == "A":  # phase 3: right + palm hold, left relocates
                comp = _component(prob.reach["left"][k2], i2)
                covered.update(_arc_path(i2, i3, n, comp).tolist())
                e3 = float(prob.eps_rp[k2, jt])
                eps_all.append(e3)
                path.append((k2, -1, jt))
                path.append((k2, i3, jt))
                phases.append(
                    GaitPhase(
                        3,
                        ("right", "palm"),
                        "left",
                        k2,
                        k2,
                        0.0,
                        {"left": th[i2], "right": th[jt], "palm": palm(k2)},
                        {"left": th[i3], "right": th[jt], "palm": palm(k2)},
                        e3,
                        "forward",
                    )
                )
        else:  # route C: phase 3 directly
            comp = _component(prob.reach["left"][k2], i2)
            covered.update(_arc_path(i2, i3, n, comp).tolist())
            e3 = float(prob.eps_rp[k2, j2])
            eps_all.append(e3)
            path.append((k2, -1, j2))
            path.append((k2, i3, j2))
            phases.append(
                GaitPhase(
                    3,
                    ("right", "palm"),
                    "left",
                    k2,
                    k2,
                    0.0,
                    {"left": th[i2], "right": th[j2], "palm": palm(k2)},
                    {"left": th[i3], "right": th[j2], "palm": palm(k2)},
                    e3,
                    "forward",
                )
            )
    total = sum(rec[3] for rec in loop)
    turns = total // n
    return Gait(
        True,
        "",
        tuple(phases),
        rotation_per_cycle=-s * step * total / len(loop),
        turns=int(turns),
        min_epsilon=float(min(eps_all)),
        coverage=_arc_fraction(covered, n),
        resolution=n,
        path=np.array(path, dtype=int),
    )


__all__ = [
    "Gait",
    "GaitPhase",
    "GaitProblem",
    "PHASE_NAMES",
    "gait_problem",
    "plan_gait",
    "search_gait",
]
