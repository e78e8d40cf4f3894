"""The map-space prior during an executed gait (§2.2.1, §2.2.3): where the executor parts
from ``planner.grasp.plan_gait``'s gait.

``plan_gait`` on the planner's model (the nominal shape) is the prior: its first phase-1
grasp is the executor's start grasp (:func:`.setup.prior_world_grasp`), and every later
phase is planned again from the sensed estimate (the NLP for phase 1, the §2.2.3
heuristics for the regrasps). :class:`PriorTrack` looks up, for the object rotation the
executor has sensed, the prior's phase of the same kind and says where the executed one
differs: the start grasp, a phase-1 plan far shorter than the prior's (or none where the
prior turns the object), a regrasp to another contact, transition 4 where the prior goes on
(or the reverse). Each difference is one ``"prior"`` event of the run.

Poses: the prior's object rotates by ``-2 pi k / resolution`` at pose index ``k`` and its
contact angles are object-frame polar angles; the executor's object rests unturned at pose
0, so a sensed rotation ``theta`` [rad] is pose ``round(-theta resolution / 2 pi)``
(modulo the resolution: the prior is cyclic), and a prior contact angle ``a`` at pose ``k``
is the world polar angle ``a - 2 pi k / resolution`` about the object's centre (the
executor's ``beta``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

#: contact angles closer than this are the same handoff [rad] (3 cells of the 72-cell grid)
SAME_CONTACT = math.radians(15.0)
#: a phase-1 plan shorter than this fraction of the prior's rotation is reported [-]
SHORT_PLAN = 0.5
#: ... unless it differs from the prior's by less than this [rad] (one 5 deg grid cell)
ROTATION_TOL = math.radians(5.0)


def world_angle(alpha: float, pose: int, resolution: int) -> float:
    """World polar angle [rad] about the object's centre of the prior's object-frame contact
    angle ``alpha`` [rad] at pose index ``pose`` of a ``resolution``-pose grid (the object
    turned by ``-2 pi pose / resolution``); not wrapped."""
    return float(alpha) - 2.0 * math.pi * pose / resolution


def _deg(a: float) -> str:
    """World angle ``a`` [rad] in degrees, wrapped to [0, 360)."""
    return f"{math.degrees(a) % 360.0:.0f}"


@dataclass(frozen=True)
class PriorStep:
    """The prior's phase of one kind at one pose.

    Attributes:
        index: its position in the prior's phases.
        kind: 1, 2 or 3 (Fig. 2.3).
        pose: pose index at its start.
        rotation: object rotation of the phase [rad] (negative: clockwise).
        start, end: world polar angles ``(left, right)`` of the contacts about the object
            centre at its start / end [rad] (NaN for a free finger).
        transition: ``"forward"`` or ``"skip"`` (transition 4) into the next phase.
    """

    index: int
    kind: int
    pose: int
    rotation: float
    start: tuple[float, float]
    end: tuple[float, float]
    transition: str


@dataclass(frozen=True)
class PriorTrack:
    """The prior gait, indexed by phase kind and pose (see the module docstring).

    Attributes:
        steps: the prior's phases as :class:`PriorStep` (one period of its cyclic gait).
        resolution: its pose grid size (poses per full turn).
    """

    steps: tuple[PriorStep, ...]
    resolution: int

    @classmethod
    def of(cls, gait) -> PriorTrack | None:
        """The track of ``plan_gait``'s :class:`planner.grasp.Gait`, or None (no gait, or
        an infeasible one: nothing to follow)."""
        if gait is None or not gait.feasible or not gait.phases or gait.resolution <= 0:
            return None
        n = int(gait.resolution)
        steps = []
        for i, ph in enumerate(gait.phases):
            k0, k1 = ph.pose_start, ph.pose_end
            steps.append(PriorStep(
                index=i, kind=int(ph.phase), pose=int(k0) % n,
                rotation=float(ph.rotation),
                start=tuple(world_angle(ph.start[f], k0, n) for f in ("left", "right")),
                end=tuple(world_angle(ph.end[f], k1, n) for f in ("left", "right")),
                transition=str(ph.transition),
            ))  # fmt: skip
        return cls(tuple(steps), n)

    def pose_index(self, theta: float) -> int:
        """Pose index of a sensed object rotation ``theta`` [rad] (clockwise negative)."""
        return round(-theta * self.resolution / (2.0 * math.pi)) % self.resolution

    def step(self, kind: int, theta: float) -> PriorStep | None:
        """The prior's phase of ``kind`` whose start pose is nearest (cyclically) the pose
        of rotation ``theta`` [rad]; the first such phase on a tie; None if the prior has
        no phase of that kind."""
        k, n = self.pose_index(theta), self.resolution
        best, arg = n + 1, None
        for st in self.steps:
            if st.kind != kind:
                continue
            d = abs(st.pose - k) % n
            d = min(d, n - d)
            if d < best:
                best, arg = d, st
        return arg

    def start_deviation(self, beta) -> str:
        """Why the start grasp at world angles ``beta = (left, right)`` [rad] is not the
        prior's first phase-1 grasp, or "" (it is, within :data:`SAME_CONTACT`)."""
        first = next((st for st in self.steps if st.kind == 1), None)
        if first is None:
            return ""
        pairs = zip(beta, first.start, strict=True)
        off = [abs(math.remainder(float(b) - a, 2 * math.pi)) for b, a in pairs]
        if max(off) <= SAME_CONTACT:
            return ""
        return (f"start grasp at left {_deg(beta[0])} deg, right {_deg(beta[1])} deg (world); "
                f"the prior's at {_deg(first.start[0])} / {_deg(first.start[1])} deg did not "
                "hold on the true object (not stable, out of reach or colliding)")  # fmt: skip

    def phase1_deviation(self, theta: float, planned: float | None) -> str:
        """Why the phase-1 plan from rotation ``theta`` [rad] (``planned`` [rad]; None: no
        plan) parts from the prior's phase 1 there, or "": it turns at least
        :data:`SHORT_PLAN` of the prior's rotation, or within :data:`ROTATION_TOL` of it."""
        st = self.step(1, theta)
        if st is None or st.rotation == 0.0:
            return ""
        prior = f"the prior's phase 1 at this pose turns {math.degrees(st.rotation):.1f} deg"
        if planned is None:
            return f"no phase-1 plan; {prior}"
        ratio = planned / st.rotation
        if ratio >= SHORT_PLAN or abs(planned - st.rotation) <= ROTATION_TOL:
            return ""
        return f"phase 1 plans {math.degrees(planned):.1f} deg; {prior}"

    def regrasp_deviation(self, kind: int, theta: float, target: float) -> str:
        """Why the regrasp of phase ``kind`` (2: the right finger, 3: the left pad) to the
        world angle ``target`` [rad] from rotation ``theta`` [rad] is not the prior's
        handoff there, or "" (within :data:`SAME_CONTACT`)."""
        st = self.step(kind, theta)
        if st is None or kind not in (2, 3):
            return ""
        finger = 1 if kind == 2 else 0
        aim = st.end[finger]
        if not math.isfinite(aim) or abs(math.remainder(target - aim, 2 * math.pi)) <= SAME_CONTACT:
            return ""
        name = "the right finger's contact" if kind == 2 else "the left pad's contact"
        return (f"phase {kind} moves {name} to {_deg(target)} deg (world); the prior's "
                f"handoff at this pose is at {_deg(aim)} deg")  # fmt: skip

    def transition_deviation(self, theta: float, skip: bool, why: str = "") -> str:
        """Why the transition after a phase 2 ended at rotation ``theta`` [rad] (``skip``:
        transition 4 into phase 1, else on to phase 3) is not the prior's there, or ""."""
        st = self.step(2, theta)
        if st is None or (st.transition == "skip") == skip:
            return ""
        if skip:
            return f"transition 4 ({why}); the prior goes on to phase 3 at this pose"
        return "on to phase 3; the prior skips it at this pose (transition 4)"


def infeasible_message(gait, error: str = "") -> str:
    """The ``"prior"`` event of a run without a prior gait to follow ("" when it has one, or
    when the run was asked for none): ``gait`` is ``plan_gait``'s result on the planner's
    model, or None with ``error`` the message of the error it raised."""
    if gait is None:
        if not error:
            return ""
        return (f"the prior (plan_gait on the planner's model) failed: {error}; every phase "
                "is planned from the sensed estimate alone")  # fmt: skip
    if gait.feasible and gait.phases:
        return ""
    why = gait.reason or "no cyclic gait"
    return (f"the prior (plan_gait on the planner's model) has no gait: {why}; every phase "
            "is planned from the sensed estimate alone")  # fmt: skip


__all__ = ["PriorStep", "PriorTrack", "infeasible_message", "world_angle"]
