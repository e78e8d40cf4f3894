"""The phase machine of Fig. 2.3 executed in the planar world: :func:`explore_object`.

Cycle 1 -> 2 -> 3 -> 1 ...: phase 1 rotates the object clockwise with both fingers (the
rolling NLP planned from the current estimate), phase 2 lets the right finger slide back to
its next grasp while the left finger holds the object against the palm, phase 3 mirrors it.
A phase ends on an event (path finished, workspace limit, grasp stability lost, contact
lost). When phase 2 ends before the right finger can hold the object with the palm, phase 3
is skipped (transition 4) and the object is rotated again with two fingers; when no stable
grasp remains (phase 1 cannot be planned after the right finger's and then the left pad's
regrasp and a last relaxed try, or a contact is lost) the gait terminates with the reason.
The planner knows only the nominal shape and what was sensed; the world holds the true
shape.
"""

from __future__ import annotations

import math
import time

import numpy as np

from planner.exploration.planar import phase_planning, shape_planning
from planner.exploration.planar.arguments import check_arguments
from planner.exploration.planar.controller import TRACE_NAMES, GaitController, trace_arrays
from planner.exploration.planar.corner_probe import CornerProbe
from planner.exploration.planar.gait_loop import PhaseStop
from planner.exploration.planar.logs import concat_logs
from planner.exploration.planar.metrics import pad_rolling
from planner.exploration.planar.objects import mean_radius
from planner.exploration.planar.prior_track import PriorTrack, infeasible_message
from planner.exploration.planar.result import ExplorationResult, PhaseRecord
from planner.exploration.planar.settings import GaitSettings
from planner.exploration.planar.setup import build_world, gait_prior
from planner.exploration.planar.shape_tracking import ShapeTracker
from planner.exploration.planar.stroke_overlap import ExploredOutline

FULL_TURN = 2 * math.pi
CX = TRACE_NAMES.index("cx")
#: phases 2/3 end when the sensed object centre (circle model) or the holding fingertip
#: (posed outline) moved this far from its start [m] (:class:`.gait_loop.PhaseStop`; a
#: safety net: the sliding pad rolls the ball 1-5 mm per phase 3, more over the ridge)
HOLD_SLIP = 0.01
#: the gait terminates when this many cycles together turned the object less than
#: ``STALL_ROTATION`` [rad] ...
STALL_CYCLES = 3
STALL_ROTATION = math.radians(5.0)
#: ... unless the phase 1 just run turned it ``RESUME_ROTATION`` [rad] or more
#: (:func:`stall_verdict`)
RESUME_ROTATION = math.radians(15.0)
#: phase-1 end events of a stalled gait and the constraint each names (the issue's three:
#: workspace, force closure, reach)
STALL_CONSTRAINTS = {"grasp stability lost": "force closure", "workspace limit": "workspace"}
#: simulated time between two calls of ``on_progress`` [s]
PROGRESS_STEP = 0.1


def explore_object(
    profile,
    hand=None,
    mu: float = 1.0,
    nominal=None,
    *,
    seed: int = 0,
    duration: float | None = None,
    settings: GaitSettings | None = None,
    max_rotation: float = FULL_TURN,
    use_prior: bool = True,
    on_progress=None,
) -> ExplorationResult:
    """Explore a planar object with the two-finger hand and palm (thesis ch. 2).

    Args:
        profile: the TRUE closed object profile (object frame, star-shaped about its origin)
            [m]; the simulated object has this shape.
        hand: ``robots.planar_hand.PlanarHand`` (default: the gait's hand,
            ``robots.planar_hand.params.gait_hand_params``: flat left pad with the 8x8
            array, 2.5 cm round right tip, joint ranges widened from the thesis' 110 deg,
            with which no circle keeps turning). A hand with a round left tip runs too
            (no tactile array: sensed like the right tip, no pad strokes; a round
            ``nominal`` only).
        mu: true friction coefficient of fingers, palm and object [-] (> 0).
        nominal: the planner's model of the object (a closed profile; default a feature-less
            circle of the object's area). A round one is used through its mean radius; a
            non-round one is also posed from the sensed contacts at every phase start
            (:class:`.shape_tracking.ShapeTracker`).
        seed: seed of the sensor noise.
        duration: simulated time limit [s] (default: until ``max_rotation`` or failure).
        settings: :class:`GaitSettings` (gains, speeds, thresholds, time step).
        max_rotation: stop once the object has turned this much (true rotation) [rad];
            checked between phases, so the run ends with the phase during which the
            object passed it (a phase 1 turns it 10-40 deg).
        use_prior: run ``planner.grasp.plan_gait`` on the nominal shape: its first grasp is
            the start grasp, and every phase planned from the estimate that parts from the
            prior's phase at the sensed rotation is a ``"prior"`` event
            (:mod:`.prior_track`).
        on_progress: ``callable(t)`` called with the simulated time [s] (e.g. to advance
            a progress bar): at most every :data:`PROGRESS_STEP` simulated seconds, and at
            least every ``PROGRESS_STEP + CHUNK * settings.dt`` (0.61 s by default: the
            compiled loop reports after each chunk of up to
            :data:`.gait_loop.CHUNK` steps).

    Returns:
        the :class:`ExplorationResult`.

    Raises:
        InvalidParameter: bad arguments, named in the message (an open profile, mu <= 0, a
            negative seed, a duration shorter than one step, max_rotation <= 0, a wrong type
            of hand / settings / on_progress, a hand whose right tip is not round, a round
            left tip with a non-round nominal, an object that does not fit the hand).
    """
    wall0 = time.perf_counter()
    mu, seed, duration, max_rotation = check_arguments(
        profile, hand, mu, nominal, seed=seed, duration=duration, settings=settings,
        max_rotation=max_rotation, use_prior=use_prior, on_progress=on_progress,
    )  # fmt: skip
    s = settings or GaitSettings(mu=mu)
    if hand is None:
        from robots.planar_hand import PlanarHand
        from robots.planar_hand.params import gait_hand_params

        hand = PlanarHand(gait_hand_params(mu))
    R = mean_radius(nominal if nominal is not None else profile)
    prior, prior_error = gait_prior(nominal, R, hand, s.mu) if use_prior else (None, "")
    world, start = build_world(profile, hand, mu, R, prior, s, seed)
    ctrl = GaitController(hand, s, R, world.gravity)
    from planner.trajectory import RollingNLP

    t_build = time.perf_counter()
    nlp = RollingNLP(hand, knots=s.nlp_knots)
    nlp_build = time.perf_counter() - t_build
    runner = _Runner(world, ctrl, nlp, s, hand, start, duration, max_rotation)
    runner.on_progress = on_progress
    runner.prior = PriorTrack.of(prior)
    first = infeasible_message(prior, prior_error)
    if runner.prior is not None:
        first = runner.prior.start_deviation(start["beta"])
    if first:
        runner.events.append({"t": world.time, "kind": "prior", "message": first})
    runner.shape = ShapeTracker.of(nominal, hand, float(np.abs(ctrl.sensing.taxel_u).max()))
    runner.execute()
    log = concat_logs(runner.logs)
    rotation = runner.rotation()
    from planner.exploration.planar.metrics import coverage_of, detect_pad_features

    trace = trace_arrays(ctrl)
    # phases whose pad trace is not a tangent contact on a held object: the held object
    # moved, or a back-stroke (the pad touches with its edge; its rows gave a phantom groove)
    moved = [(p.start, p.end) for p in runner.records if p.event == "object moved"]
    back = [(p.start, p.end) for p in runner.records
            if p.backstroke and p.event != "object moved"]  # fmt: skip
    tip_r = hand.params.right.tip_radius
    features = detect_pad_features(trace, profile, start["rest"], R, s.explore_force, tip_r,
                                   moved, keep_images=back)  # fmt: skip
    timings = {
        "nlp_build_s": nlp_build,
        "nlp_solve_ms": [1e3 * p.nlp_time_s for p in runner.records if p.phase == 1],
        "nlp_solve_cpu_ms": [1e3 * p.nlp_cpu_s for p in runner.records if p.phase == 1],
        "nlp_iterations": [p.nlp_iterations for p in runner.records if p.phase == 1],
        "control_step_us": list(1e6 * np.asarray(ctrl.step_times)),
        "control_steps_compiled": ctrl.compiled_calls,
        "wall_s": time.perf_counter() - wall0,
    }
    eps = [p.epsilon for p in runner.records if p.phase == 1 and np.isfinite(p.epsilon)]
    return ExplorationResult(
        status=runner.status,
        reason=runner.reason,
        phases=tuple(runner.records),
        rotation=rotation,
        coverage=coverage_of(log, "object", profile, phases=runner.records),
        contact_coverage=coverage_of(log, "object", profile),
        min_epsilon=float(min(eps)) if eps else float("nan"),
        features=tuple(features),
        log=log,
        trace=trace,
        prior=prior,
        timings=timings,
        events=tuple(runner.events),
    )


class _Runner:
    """State of one execution (kept out of :func:`explore_object` to keep it short)."""

    def __init__(self, world, ctrl, nlp, s, hand, start, duration, max_rotation):
        self.world, self.ctrl, self.nlp, self.s, self.hand = world, ctrl, nlp, s, hand
        self.start = start
        self.t_end = math.inf if duration is None else float(duration)
        self.max_rotation = max_rotation
        self.logs, self.records, self.events = [], [], []
        self.status, self.reason = "ok", ""
        self.theta = 0.0
        self.angle0 = float(world.pose("object")[2])
        self._traces: list = []
        self.R_nominal = float(ctrl.sensing.radius)
        self._rows = (0, 0)  # trace rows of the last phase
        self.on_progress = None
        self._reported = 0.0  # simulated time of the last on_progress call [s]
        self._via: float | None = None  # the pending back-stroke's turning angle [rad]
        self._stroking = False  # the phase being run is a back-stroke
        self._plan1 = None  # the last phase-1 plan (its solve statistics)
        self.sensed_features: list[float] = []  # object-frame angles of sensed bumps [rad]
        self.shape: ShapeTracker | None = None  # the posed nominal outline (non-round only)
        self.nlps: dict = {}  # the shape planner's NLPs, built at first use
        # the pad's tactile strokes (corner probes, overlaps, back-strokes over features it
        # slid across) need the flat pad; a round left tip explores like the right one
        pad = not ctrl.sensing.r_left
        self.corner = (CornerProbe(hand.params.left.pad_half_width, len(ctrl.sensing.taxel_u))
                       if s.corner_probe and pad else None)  # fmt: skip
        self.explored = ExploredOutline() if s.stroke_overlap and pad else None
        self.backstrokes = s.sensed_features and pad
        self.prior: PriorTrack | None = None  # the map-space prior, indexed by pose
        self._posed = True  # the posed outline's fit at the phase start was used
        self._again = False  # the phase 2 being run repeats one planned from a rejected fit
        self._deferred: int | None = None  # the phase 1 whose stall verdict was deferred

    def rotation(self) -> float:
        """True rotation of the object so far [rad] (unwrapped from the logs)."""
        if not self.logs:
            return 0.0
        a = np.unwrap(np.concatenate([lg.poses["object"][:, 2] for lg in self.logs]))
        return float(a[-1] - a[0])

    def execute(self) -> None:
        kind, skip, failures = 1, False, 0
        while True:
            if len(self.records) >= self.s.max_phases:
                self._end("ok", f"phase limit {self.s.max_phases} reached")
                return
            if self._time_up():
                self._end("ok", f"duration {self.t_end:g} s reached")
                return
            if abs(self.rotation()) >= self.max_rotation:
                self._end("ok", f"object turned {math.degrees(abs(self.rotation())):.1f} deg")
                return
            obs = self.world.observe()
            est = self.ctrl.sensing.update(obs, {1: "auto", 2: "pad", 3: "palm"}[kind])
            if self.shape is not None:
                self._posed = self.shape.update(est, self.theta)
                self._again = self._again and kind == 2
            seg, planned, nlp_t, why = self._plan(kind, est, obs.q)
            if seg is None and kind == 1 and self._after_no_plan(1, failures + 1) is None:
                seg, planned, nlp_t, why = self._last_resort(est, obs.q, why)
            self._follow(kind, seg, planned)
            if seg is None:
                failures += 1
                nxt = self._no_plan(kind, failures, why)
                if nxt is None:
                    return
                kind, skip = nxt, False
                continue
            event, rec = self._run(kind, skip, seg, planned, nlp_t)
            if event in ("contact lost", "object dropped", "sim fault"):
                # the simulator's own message says why it stopped (a Lemke ray, ...)
                log = self.logs[-1]
                why = f": {log.reason}" if log.status == "failed" else ""
                self._end("failed", f"{event} in phase {kind}{why}{self._last_blocked()}")
                return
            if event == "time limit" and self._time_up():
                # cut by the run's duration: not judged (a run given more time goes on
                # from here); the loop's top ends it "duration reached"
                continue
            if kind == 1:
                # only a rotation that happened clears the failures (phases 2/3 always run)
                failures = 0 if abs(rec.rotation) >= math.radians(1.0) else failures + 1
                if failures >= 2:
                    rot = math.degrees(rec.rotation)
                    self._end("failed", "no stable grasp within the workspace: phase 1 "
                              f"rotated {rot:.1f} deg ({event})")  # fmt: skip
                    return
                if self._stalled():
                    self._end(*stall_outcome(self.rotation(), self._blocking_now()))
                    return
            nxt = self._next(kind, event, est)
            if kind == 2 and nxt[0] != 2 and self.prior is not None:
                self._prior_event(2, self.prior.transition_deviation(
                    self.theta, nxt[1], f"phase 2 ended by {event}"))  # fmt: skip
            kind, skip = nxt

    def _follow(self, kind: int, seg, planned: float) -> None:
        """A ``prior`` event where the plan of phase ``kind`` (``seg``, None: no plan;
        ``planned`` [rad], phase 1) parts from the prior's phase at the sensed rotation
        (:class:`.prior_track.PriorTrack`; phase 1: a far shorter turn or none, phases 2/3:
        a regrasp to another contact)."""
        if self.prior is None:
            return
        if kind == 1:
            msg = self.prior.phase1_deviation(self.theta, planned if seg is not None else None)
        elif seg is not None and seg.target is not None:
            msg = self.prior.regrasp_deviation(kind, self.theta, seg.target)
        else:
            msg = ""
        self._prior_event(kind, msg)

    def _prior_event(self, kind: int, msg: str) -> None:
        """Record the ``prior`` event ``msg`` of phase ``kind`` (nothing for "")."""
        if msg:
            self.events.append({"t": self.world.time, "kind": "prior", "phase": kind,
                                "message": msg})  # fmt: skip

    def _last_blocked(self) -> str:
        """What the gait was last found blocked by, for a run that ends on a symptom (a lost
        contact, a dropped object, a simulator fault): `` (last blocked at T s: blocking:
        ...)`` from the latest ``no_plan`` event that named a constraint (its ``blocking``,
        :func:`.phase_planning.blocking_phrase`), or "" (none did).
        A long thin ellipse whose phase-1 plans failed twice on force closure (the contact
        line 5-8 deg outside the cones) and whose next phase 1 then lost both contacts
        reported only "contact lost in phase 1"."""
        for e in reversed(self.events):
            what = e.get("blocking", "") if e.get("kind") == "no_plan" else ""
            if what:
                return f" (last blocked at {e['t']:.2f} s: {what})"
        return ""

    def _time_up(self) -> bool:
        """The run's ``duration`` is over."""
        return self.world.time >= self.t_end - 1e-9

    def _last_resort(self, est, q, why: str):
        """The phase-1 plan of :meth:`_plan` once more, the round tip's contact allowed to
        start beyond its rolling range but not to roll further (``RollingNLP(relax_start=
        True)``), when the gait would otherwise end (round nominal shapes;
        ``settings.last_resort``). Returns what :meth:`_plan` returns (the first reason
        when this plan fails too)."""
        if not self.s.last_resort or self.shape is not None:
            return None, 0.0, 0.0, why
        if "relaxed" not in self.nlps:
            from planner.trajectory import RollingNLP

            self.nlps["relaxed"] = RollingNLP(self.hand, knots=self.s.nlp_knots,
                                              relax_start=True)  # fmt: skip
        nlp, self.nlp = self.nlp, self.nlps["relaxed"]
        try:
            seg, planned, nlp_t, why2 = phase_planning.plan(self, 1, est, q)
        finally:
            self.nlp = nlp
        if seg is None:
            return None, 0.0, nlp_t, why
        self.events.append({"t": self.world.time, "kind": "last_resort", "phase": 1,
                            "message": f"{why}: planned with the right tip's contact "
                            "beyond its rolling range (not rolling further)"})  # fmt: skip
        return seg, planned, nlp_t, why2

    def _no_plan(self, kind: int, failures: int, why: str) -> int | None:
        """Phase ``kind`` could not be planned (``why``), the ``failures``-th time in a row:
        the events (``no_plan``; ``regrasp`` when the left pad regrasps too) and the phase to
        run next (:meth:`_after_no_plan`), or None after ending the gait "failed"."""
        t = self.world.time
        self.events.append({"t": t, "kind": "no_plan", "phase": kind, "message": why,
                            "blocking": phase_planning.blocking_phrase(why)})  # fmt: skip
        nxt = self._after_no_plan(kind, failures)
        if nxt is None:
            self._end("failed", f"no stable grasp within the workspace ({why})")
        elif kind == 1 and nxt == 3:
            self.events.append({"t": t, "kind": "regrasp", "phase": 3,
                                "message": "no phase-1 plan after the right finger's regrasp: "
                                "the left pad regrasps too before giving up"})  # fmt: skip
        return nxt

    def _after_no_plan(self, kind: int, failures: int) -> int | None:
        """The phase to run after phase ``kind`` could not be planned, the ``failures``-th
        failure in a row, or None: the gait ends (§2.2.3, "If a stable grasp within the
        finger workspace still cannot be found, the algorithm terminates"). A phase 1
        without a plan is followed by the right finger's regrasp (phase 2); after the
        second, with ``settings.left_regrasp``, by the left pad's (phase 3; the caller's
        event says so); a phase 2/3 without a plan by phase 1. No side effects."""
        if kind != 1:
            return 1 if failures < 2 else None
        if failures == 1:
            return 2
        if failures == 2 and self.s.left_regrasp:
            return 3
        return None

    def _blocking_now(self) -> str:
        """What blocked phase 1 in the stalled cycles, for a stalled gait's reason: the
        constraints their phases 1 ended on (``grasp stability lost``: force closure, the
        sensed epsilon below ``min_epsilon``; ``workspace limit``: workspace), else the
        static check of :func:`.phase_planning.blocking` at the sensed grasp now."""
        ones = [p for p in self.records if p.phase == 1][-STALL_CYCLES - 1 :]
        parts = []
        for event, name in STALL_CONSTRAINTS.items():
            hit = [p for p in ones if p.event == event]
            if not hit:
                continue
            more = ""
            if name == "force closure":
                eps = [p.epsilon for p in hit if math.isfinite(p.epsilon)]
                if eps:
                    more = f", epsilon down to {min(eps):.3f} < {self.s.min_epsilon:g}"
            parts.append(f"{name} (phase 1 ended by {event} x{len(hit)}{more})")
        if parts:
            return phase_planning.BLOCKING + ", ".join(parts)
        obs = self.world.observe()
        est = self.ctrl.sensing.update(obs, "auto")
        mu = self.s.planning_mu
        return phase_planning.blocking(self, est, obs.q, mu)

    def _stalled(self) -> bool:
        """Whether the gait is stalled after the phase 1 just run (:func:`stall_verdict`);
        a deferred verdict is a ``stall_deferred`` event."""
        stalled, deferred = stall_verdict(self.records, self._deferred)
        if deferred != self._deferred:
            self._deferred = deferred
            turned = math.degrees(abs(self.records[-1].rotation))
            msg = (f"the last {STALL_CYCLES} cycles turned the object less than "
                   f"{math.degrees(STALL_ROTATION):.0f} deg, but this phase 1 turned "
                   f"{turned:.1f} deg: going on")  # fmt: skip
            self.events.append({"t": self.world.time, "kind": "stall_deferred", "message": msg})
        return stalled

    def _plan(self, kind, est, q):
        """``(segment or None, planned rotation [rad], solve time [s], why no plan)`` of the
        next phase: the posed outline's planner (:mod:`.shape_planning`) or the round
        one (:mod:`.phase_planning`)."""
        if self.shape is not None:
            if kind == 1:
                mu = self.s.planning_mu
                return shape_planning.plan_phase1(self, q, mu)
            return shape_planning.plan_explore(self, kind, est, q)
        return phase_planning.plan(self, kind, est, q)

    def _run(self, kind, skip, seg, planned, nlp_t):
        w, c = self.world, self.ctrl
        t0 = w.time
        c.start(seg, t0)
        n0 = len(c.trace)
        eps_min = [math.inf]
        horizon = min(seg.duration + 0.5, self.t_end - t0)
        # phases 2/3: the held object must stay where it is; a sensed centre (circle model)
        # or holding fingertip (posed outline) that moved HOLD_SLIP means the explorer drags
        # the object (a ridge caught the round right tip and rolled the ball 30 deg back
        # along the palm before this check). A PhaseStop (not a closure): the planar world's
        # compiled loop runs the phase with it compiled in, on posed outlines too
        holder = None if self.shape is None else (0 if kind == 2 else 1)
        stop = PhaseStop(c, HOLD_SLIP if kind != 1 else None, self._progress, holder,
                         centre=self.shape is None)  # fmt: skip
        log = w.run(max(horizon, w.dt), c, control_rate=self.s.control_rate, stop=stop)
        self.logs.append(log)
        self._rows = (n0, len(c.trace))
        self.theta = c.theta
        if kind != 1 and self.explored is not None:
            self.explored.observe(c.trace[n0:], kind, self.ctrl.sensing.radius)
        if kind != 1 and len(c.trace) > n0 + 1:
            # phases 2/3 hold the object on the palm, where it rolls: phase 2 reads its turn
            # from the object rolling on the holding pad (eq. 2.4; a drag over the ridge
            # turned the ball +19.4 deg where the palm's -dx/R said -10.6 deg), phase 3 from
            # the centre rolling on the palm (theta -= dx / R)
            rows = np.asarray(c.trace[n0:], dtype=float)
            if kind == 2:
                cols = {k: rows[:, i] for i, k in enumerate(TRACE_NAMES)}
                sens = self.ctrl.sensing
                roll = pad_rolling(cols, sens.radius, round_tip=sens.r_left > 0.0)
                self.theta += float(roll[-1] - roll[0])
            else:
                self.theta -= (rows[-1, CX] - rows[0, CX]) / self.ctrl.sensing.radius
        event = "object moved" if stop.moved else (c.event or "time limit")
        if c.event_data:
            self.events.append({"t": w.time, "kind": "phase_end", "phase": kind,
                                "message": f"{event}: {c.event_data}"})  # fmt: skip
        if log.status == "failed":
            event = "object dropped" if "drop" in log.reason else "sim fault"
            self.events.append({"t": w.time, "kind": "sim", "message": log.reason})
        for ev in log.events:
            if ev.kind == "object_dropped":
                event = "object dropped"
        a = np.unwrap(log.poses["object"][:, 2])
        if kind == 1:
            from planner.grasp import epsilon_two_planar

            tr = np.array(c.trace[n0:], dtype=float)
            if len(tr):
                p, n = tr[:, 4:8].reshape(-1, 2, 2), tr[:, 8:12].reshape(-1, 2, 2)
                e = epsilon_two_planar(p[:, 0], -n[:, 0], p[:, 1], -n[:, 1], self.s.mu)
                eps_min[0] = float(np.min(e))
        # the phase ends where its log does: a step that blew up (a simulator fault) moved
        # the world's clock but left no row, and the rotation is read from the rows
        end = float(log.t[-1]) if len(log.t) else w.time
        rec = PhaseRecord(
            kind=kind, skip=skip, start=t0, end=end, rotation=float(a[-1] - a[0]),
            planned_rotation=planned, event=event,
            epsilon=eps_min[0] if math.isfinite(eps_min[0]) else float("nan"),
            nlp_time_s=nlp_t, backstroke=self._stroking,
            nlp_cpu_s=self._plan1.solve_cpu_s if kind == 1 else 0.0,
            nlp_iterations=self._plan1.iterations if kind == 1 else 0,
        )  # fmt: skip
        self._stroking = False
        self.records.append(rec)
        if kind == 1 and abs(rec.rotation) < 0.5 * abs(planned):
            msg = (f"rotated {math.degrees(rec.rotation):.1f} deg of the planned "
                   f"{math.degrees(planned):.1f} deg ({event})")  # fmt: skip
            self.events.append({"t": w.time, "kind": "deviation", "phase": 1, "message": msg})
        return event, rec

    def _progress(self, t: float) -> None:
        """``on_progress(t)`` every :data:`PROGRESS_STEP` simulated seconds [s]."""
        if self.on_progress is not None and t - self._reported >= PROGRESS_STEP:
            self._reported = t
            self.on_progress(t)

    def _next(self, kind, event, est):
        if kind == 1:
            return 2, False
        if kind == 2:
            if event == "path finished" and self.shape is None:
                return 3, False
            # phase 2 ended early (or, on a posed outline, at all): can the right finger
            # hold the object with the palm?
            from planner.grasp import epsilon_two_planar

            obs = self.world.observe()
            e = self.ctrl.sensing.update(obs, "pad")
            if self.shape is not None:
                if self._phase2_again(self.shape.update(e, self.theta)):
                    return 2, False
                eps = self.shape.right_palm_epsilon(e, self.s.mu)
            else:
                palm = np.array([e.centre[0], 0.0])
                eps = float(epsilon_two_planar(e.p[1], -e.n[1], palm, np.array([0.0, 1.0]),
                                               self.s.mu))  # fmt: skip
            if eps < self.s.min_epsilon:
                self.events.append({"t": self.world.time, "kind": "transition_4",
                                    "message": f"phase 2 ended by {event}; right-palm grasp "
                                    f"epsilon {eps:.3f}: skip phase 3, rotate again"})  # fmt: skip
                return 1, True
            return 3, False
        if self.corner is not None and self.shape is None and not self.records[-1].backstroke:
            rows = np.asarray(self.ctrl.trace[self._rows[0] : self._rows[1]], dtype=float)
            self.corner.observe(rows, self.ctrl.sensing.radius)
        if self.backstrokes and not self.records[-1].backstroke:
            self._via = phase_planning.feature_behind(self, event)
            if self._via is not None:
                self.events.append({"t": self.world.time, "kind": "backstroke",
                                    "message": "the pad slid over a feature at "
                                    f"{math.degrees(self._via):.0f} deg (world): back-stroke "
                                    "onto its far side"})  # fmt: skip
                return 3, False
        return 1, False

    def _phase2_again(self, posed_now: bool) -> bool:
        """Whether the phase 2 that ended is planned again: it was planned from a rejected
        fit of the posed outline (the object still moving after phase 1: the 6 cm square
        tipped 42 deg while the estimate said 12) and the outline is posed now (once)."""
        if not posed_now or self._posed or self._again:
            return False
        self._again = True
        msg = "phase 2 was planned from a rejected pose fit; the outline is posed now: again"
        self.events.append({"t": self.world.time, "kind": "replan", "message": msg})
        return True

    def _end(self, status: str, reason: str) -> None:
        self.status, self.reason = status, reason
        last = self.records[-1].kind if self.records else 0
        self.events.append({"t": self.world.time, "kind": "end", "status": status,
                            "message": reason, "last_phase": last})  # fmt: skip


def stall_verdict(records, deferred: int | None = None) -> tuple[bool, int | None]:
    """``(stalled, deferred)`` after the phase 1 just run, ``records[-1]``.

    Stalled: the last :data:`STALL_CYCLES` cycles before it (phase-1 start to phase-1 start)
    together turned the object less than :data:`STALL_ROTATION` (their phases 2/3 gave
    back what their phases 1 turned), and the phase 1 just run turned it less than
    :data:`RESUME_ROTATION`. A phase 1 that turned more defers the verdict to the next phase
    1 (``deferred``: the index in ``records`` of the phase 1 whose verdict was deferred,
    returned updated), but not twice in a row: a gait whose phases 2/3 give back every 20
    deg its phases 1 turn still ends.

    Before, the verdict came right after a phase 1 that turned the object 16-29 deg, on
    the cycles before it alone: every stalled run of ``ball_with_ridge`` with its ridge at
    0-315 deg that was looked at (5) ended so. ``bench_gait_ridge.py`` (8 ridge angles,
    seeds 0-5): full turns 34 -> 43 of 48 with the scenario's settings, 44 -> 46 with the
    library's defaults; the bundled ridge (170 deg) unchanged.
    """
    starts = [i for i, p in enumerate(records) if p.phase == 1]
    if len(starts) <= STALL_CYCLES or starts[-1] != len(records) - 1:
        return False, deferred
    net = sum(p.rotation for p in records[starts[-STALL_CYCLES - 1] : starts[-1]])
    if abs(net) >= STALL_ROTATION:
        return False, deferred
    if abs(records[-1].rotation) >= RESUME_ROTATION and deferred != starts[-2]:
        return False, starts[-1]
    return True, deferred


def stall_outcome(rotation: float, blocking: str = "") -> tuple[str, str]:
    """``(status, reason)`` of a gait whose last :data:`STALL_CYCLES` cycles turned the
    object less than :data:`STALL_ROTATION`, after a total ``rotation`` [rad]: failed,
    unless the full turn was done (then only the extra cycle of ``max_rotation`` stalled).
    A failure names what ``blocking`` says stops phase 1 where the gait stalled
    (:func:`.phase_planning.blocking`: force closure, workspace or reach), when given."""
    why = (f"no progress: the last {STALL_CYCLES} cycles turned the object less than "
           f"{math.degrees(STALL_ROTATION):.0f} deg")  # fmt: skip
    turned = abs(rotation)
    if turned >= FULL_TURN:
        return "ok", (f"object turned {math.degrees(turned):.1f} deg (a full turn); the cycle "
                      f"after it stopped: {why}")  # fmt: skip
    return "failed", f"{why} ({blocking})" if blocking else why


__all__ = ["explore_object"]
