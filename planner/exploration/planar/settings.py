"""Settings of the ch. 2 gait executor (one frozen, self-validating object)."""

from __future__ import annotations

from dataclasses import dataclass, fields

from planner import checks
from planner.control.internal_force import InternalForceGains
from planner.errors import InvalidParameter


@dataclass(frozen=True)
class GaitSettings:
    """Everything :func:`explore_object` can tune.

    Attributes:
        mu: friction coefficient the planner assumes [-] (the world uses the true one).
        friction_margin: fraction of ``mu`` kept in reserve in the controllers' cones [-].
            The planners use ``planning_mu = mu (1 - friction_margin)`` too. With it and
            ``min_epsilon`` the map space of the rounded squares
            (``benchmarks/bench_gait.py``, ``rest_turn_reserve_deg``) turns them only 80-85
            deg from rest (12 cm: 45, 14 cm: 20 deg) where the full mu turns them fully,
            and the executor stops about there.
            Lowering it does not help: rounded squares 6-14 cm, the true outline, seeds
            0-2, 60 s, turned 1306 deg in total with 0.2, 1027 with 0.1 and 876 with 0
            (measured 2026-11-24), because grasps planned at the cones' edges slip.
        mu_cap: the planners and the controllers count on at most this friction
            coefficient [-]: ``planning_mu = min(mu, mu_cap) (1 - friction_margin)``; the
            friction above it is a reserve. With the full cones of a higher ``mu`` the
            start grasp and the phase-1 plans went lower on the object and deeper into the
            fingers' workspace, and the gait lost more than it gained (a 3 cm circle at
            mu 1.5: right contact at 5 deg, each phase 2 ended at the right finger's joint
            stop after 0.1 s while the held ball rolled back 15-16 deg; dropped at 13 s).
            ``explore_object`` defaults, full turns in 90 s, the 10 cm ridge ball (ridge at
            170 and 45 deg), circles of 2/3/5/7 cm, a 1.1:1 ellipse and an 8 cm rounded
            square, seeds 0-1 (measured 2026-11-25): at mu 1.25/1.5/2/3 without the cap
            4, 6, 2, 0 of 16; capped at 1: 14, 14, 12, 7 of 16 (at mu 1: 15 of 16); capped
            at 1.25: as without; at 0.875: fewer (19 of 48 at mu 1.5-3). What is left at
            mu 3 is the sliding explorer's drag (``mu explore_force``): 12 of 16 with a
            0.15 N explorer. At ``mu <= mu_cap`` it changes nothing.
        internal_force: commanded internal (squeeze) force of the phase-1 grasp [N].
        carry_weight: after a phase 1 that ended at a workspace limit with the object more
            than the NLP's travel (1 cm) from where its plan put it (it rolled along the
            palm instead of being carried), the next phase 1 raises its squeeze to what its
            planned grasp needs to carry the object's weight and lift inside the cones
            (:func:`.phase_planning.carry_squeeze`, :mod:`.carry_squeeze`; round nominal
            shapes). With the 1 N squeeze alone a 3 cm circle grasped at 150/20 deg
            (needing 1.1-1.8 N) stayed on the palm and rolled 12 mm right per phase 1 where
            the plan moved it 10 mm left, until every phase 1 ended at the right base
            joint's stop ("no progress" at 54 deg); now it turns 364 deg in 40.6 s.
            Measured alternatives on ball_with_ridge (seeds 0-3): raising it in every phase
            1 from the start failed at 14-15 deg (its phases 3 then rolled the ball back
            11.6 deg each); keeping it raised in every phase 1 after the first trigger (the
            3 cm circle: 27.5 of 27.5 deg per phase 1, 373 deg in 30.3 s) failed seeds 2
            and 3 after their full turn. With this rule the ball triggers it once or twice
            (seed 0 at 253 and 383 deg, seeds 1-3 at 363 deg); the phantom concave feature
            it gave seed 1 (a phase 3 whose held ball moved 4.5 mm) is gone since the
            curvature detector skips such phases (:func:`.metrics.held_still`).
        carry_margin: the squeeze is ``1 + carry_margin`` times the carrying one [-].
        max_squeeze: cap of the raised squeeze [N].
        hold_force: force of the right finger pressing the object against the palm in
            phase 3 [N]. With
            1 N the explorer's friction rolled the ball back along the palm (1-3.4 deg per
            phase 3) and a 3 mm ridge under the sliding right tip dragged it 30 deg; with
            2 N the tip slides over the ridge and phase 3 loses 0.6-1.3 deg.
        left_hold_force: force of the left pad pressing the object against the palm in
            phase 2 [N]. It sets the sign of Fig. 2.14's phase-2 tangential force: in
            equilibrium the pad's tangential force is ``-(N cos beta + M / R) / (1 + sin
            beta)`` (:func:`.segments.hold_tangential_force`; ``M`` the right finger's
            moment about the palm contact), the squeeze's sign (that of phase 3's sliding
            friction) above ``N = M / (R |cos beta|)`` and the right finger's drag's below
            it. On ball_with_ridge the threshold was 0.9 N (beta 140 deg, M / R 0.7 N;
            the statics predicted the sensed tangential force within 0.01 N): 2 N gave
            0/20 sign changes at the 2 -> 3 switches, 1 N 1-2 of 20, 0.6 N 18-21 of 23,
            0.4 N (the scenario's value; 0.5-0.6 N sensed, a tangential 0.18 N, a third of
            the friction cone) 18-21 of 20-22, the ball still held (0.5-1 deg per phase 2,
            as with 2 N). Default 2 N (the threshold depends on the object and the grasp).
        sensed_features: use the macro features the pad senses in phase 3 (see
            :mod:`.sensed_features`): a back-stroke onto a crossed ridge's far side and a
            phase-1 rotation cap that keeps it off the palm. Measured on ball_with_ridge
            (2 N hold): coverage 0.981-0.986 instead of 0.972-0.975, a phantom groove
            beside the true ridge, and seed 3 failed at 18 deg; with the 0.6 N hold the
            pad never crossed the ridge far enough for a back-stroke (coverage 0.972-0.975).
            Off by default.
        corner_probe: after a phase 3 whose pad's leading end stalled at a wall and then
            got past it (it jumped a ridge), one extra phase 3 sends the pad's end, tilted,
            back into the corner beyond the wall (:mod:`.corner_probe`; round nominal
            shapes only).
        stroke_overlap: a phase 3 whose pad starts more than a few degrees past the
            outline explored so far first goes back into it (:mod:`.stroke_overlap`; round
            nominal shapes only). Off by default: on ``ball_with_ridge`` (seeds 0-3) it
            raises the explorer-only coverage from 0.961-0.975 to 0.983-0.986 (the ridge's
            wall shadows are what is left), but each overlap stroke starts backwards, so the
            pad keeps phase 2's tangential sign at that 2 -> 3 switch: Fig. 2.14's sign
            changes drop from 80/91 to 58/85 switches (11/19 on seed 3).
        wall_approach: a phase 3 whose stroke runs towards a wall the pad stalled at before
            leads with the pad's end (:func:`.corner_probe.approach_segment`): the contact
            gets within 2.9 deg of the ridge's near wall instead of 11.3. Off by default:
            on ``ball_with_ridge`` (with ``stroke_overlap``) it raised the explorer-only
            coverage to 0.992-0.994 (seeds 0-3) but on seed 0 its rows beside the wall
            diluted the Fig. 2.14 ridge measures (tangential 0.27 vs 0.28 N off the ridge,
            elongation 1.26) and the ridge came out 6.0 deg off. Re-measured 2026-11-24
            with the mapping estimate (:func:`.metrics.object_rotation`): both options on
            ``ball_with_ridge`` seeds 0-3 give the explorer-only coverage 0.992-0.994, the
            ridge 3.8/0.3/0.1/2.7 deg off, no other feature, tangential 0.43-0.46 vs
            0.28-0.30 N and elongation 2.0 at the ridge, 382-384 deg in the 60 s; Fig.
            2.14's sign change at 52 of 87 switches (80 of 91 without): kept off.
        top_sweep: a phase 2 whose right tip starts on a ridge's top, just past a wall the
            pad stalled at, first sweeps back over the top towards that wall, at most 4 deg
            (:func:`.corner_probe.top_sweep_back`): phase 1 rolled the tip onto the top,
            and its contacts there are no exploring ones. Off by default, like the two
            options above that it completes: on ``ball_with_ridge`` (with both) the
            explorer-only coverage rose from 0.983-0.992 (3 of seeds 0-7 at or above 0.99)
            to 0.994-0.997 on 7 of them; seed 2 stays at 0.983 (its rotation estimate is
            9.6 deg off there after a phase 2 whose held ball turned 22 deg, so no sweep
            is planned). Fig. 2.14's sign change: 110 of 188 switches (108 of 189 without).
        left_regrasp: when phase 1 cannot be planned a second time in a row (after the
            right finger's regrasp, phase 2), the left pad regrasps too (phase 3) before
            the gait ends (§2.2.3: "If a stable grasp within the finger workspace still
            cannot be found, the algorithm terminates"). Without it the gait ended after
            the right finger's regrasp alone. Measured 2026-11-24 (27 runs: rounded
            squares 8/10 cm with corner radii 0.2/0.3/0.4 of the side, ellipses 1.1/1.15/
            1.2:1, seeds 0-2, 60 s): full turns 9 instead of 8, the mean turn 192 deg
            instead of 176; a run that never fails to plan twice in a row is unchanged
            (``ball_with_ridge``).
        last_resort: where the gait would end for want of a phase-1 plan (after both
            regrasps), phase 1 is planned once more from the grasp as it is, with the round
            tip's contact allowed to start beyond the tip's rolling range but not to roll
            further (``RollingNLP(relax_start=True)``; round nominal shapes): a phase 2 that
            ends at a joint stop can leave the tip touching the object 92-107 deg from its
            axis where the NLP's range is 69 deg. The friction cones stay as they are.
        follow_prior: on a posed nominal outline (a non-round ``nominal``), phases 2/3 move
            the explorer to the handoff of the prior (``plan_gait`` on that outline, found
            stable and reachable in map space) at the sensed rotation
            (:class:`.prior_track.PriorTrack`) instead of back to the start grasp's world
            angle; the right tip's pivot regrasp (:mod:`.pivot_planning`) still takes
            precedence in phase 2. Measured 2026-11-24 (rounded squares 6-14 cm, the true
            outline as model, seeds 0-2, 60 s): the 15 runs turned 656 deg in all instead
            of 407 (10 cm: 141/127/38 deg instead of 3/23/24; 12 cm: 12 deg each instead
            of 54/2/100); no run reached a full turn either way. Round nominal shapes plan
            their regrasps by the §2.2.3 heuristics, which land within 15 deg of the
            circle prior's handoffs.
            Measured with ``left_regrasp`` on the 27 runs above: 10 full turns instead of
            9. The tip's relaxation in every plan (not only the last) gave 6 (the regrasp
            it replaces was the better move where it was possible). Relaxing the start's
            planning cones the same way (a contact line outside a cone may stay as far out)
            once gave 12 but jammed ``long_thin_gait``; re-measured 2026-11-24 on today's
            executor (jams no longer fatal; 18 runs: those rounded squares and ellipses
            of 1.1/1.15/1.2:1, seeds 0/1, 30 s; and the batch's 12/14 cm rounded squares)
            it changed nothing: the same 9 runs ok, rotations within 2 deg but one (-78
            instead of -97 deg); the 12 cm square, stopped 1 deg outside the cones, got
            its relaxed plan and hit a joint stop 0.2 deg on. Not kept.
        explore_force: normal force of the exploring finger (0.3 N, §2.3.2) [N].
        object_mass: the planner's guess of the object mass [kg].
        object_kp, object_kv: object impedance gains (eq. 2.7), each >= 0: stiffness
            [N/m, N/m, N m/rad] and damping [N s/m, N s/m, N m s/rad] in (x, y, theta).
        rolling_gains: (kp [N m/m], kv [N m s/m], max_moment [N m]) of the rolling PD
            (eq. 2.8); the gains >= 0, the saturation > 0.
        hold_kp, hold_kv: orientation stiffness [N m/rad] and damping [N m s/rad] of the
            grasping/holding fingertips about their planned orientation.
        internal_gains: the internal-force PI gains.
        tip_kp, tip_kv, phi_kp, phi_kv: fingertip impedance of the explorer ([N/m],
            [N s/m], [N m/rad], [N m s/rad]). 200 N/m and 4 N s/m, as in
            ``ball_with_ridge``: with the former 60 N/m and 2 N s/m the default call on the
            ridge ball kept the ridge's wall shadows untouched (coverage 0.97-0.98; >= 0.99
            in 3 of 16 runs with the ridge at 0-315 deg against 12 of 16), with the same
            full turns (14/16) and the batch's verdicts unchanged; the ridge within 5 deg
            in 9 rather than 11 of 16 (``bench_gait_ridge.py``, 2026-11-24).
        hold_stiffness, hold_damping: 2-D impedance of the holding fingertip about its
            anchor in phases 2/3 [N/m, N s/m] (it must out-hold the explorer's friction).
        min_force: minimum normal force of every touching finger in the QP [N].
        torque_limit: joint torque limit used by the QP [N m].
        rotation_speed: object rotation speed of phase 1 [rad/s].
        explore_speed: contact speed of the exploring finger [m/s].
        startup_time: duration of the startup segments (splines, ramps) [s].
        joint_margin: a finger within this of a joint limit is at its workspace limit [rad].
        min_epsilon: phase-1 grasps with a sensed epsilon below this are unstable [-].
        lost_force: a touching finger below this normal force [N] for ``lost_time`` [s] has
            lost its contact.
        dt: simulator step [s]; control_rate: controller rate [Hz].
        nlp_knots: intervals of the phase-1 NLP; nlp_margin: its stability margin [rad].
        max_phases: phases before the executor stops (safety bound).
        gravity: magnitude of the world's gravity in the hand's plane [m/s^2], pointing
            from the object to the palm (the world's -y; the simulator's and the
            controllers' gravity alike, and the weight the phase-1 squeeze carries).
            9.81: the hand stands in a vertical plane, palm down (the default); 0: it lies
            in a horizontal plane, the object's weight borne out of the plane by a
            frictionless support (an air table). In the horizontal plane nothing but the
            holding finger keeps a tilted object on the palm, and nothing tips it back
            onto a face. Measured 2026-11-25 (``benchmarks/bench_gait.py --gravity 0``,
            ``bench_gait_g0``, circle model, 10 s, seeds 0-2, against the vertical hand):
            rounded squares succeed on 3/5 objects, 7/15 runs (2/5, 8/15), full turns in
            120 s on 3/15 runs (the 6 cm one twice, 372-520 deg, the 8 cm one once; 2/15);
            sharp squares 0/18 either way; circles 21/21 runs (20/21); the 1.1:1 ellipse
            0/3 (3/3): the weight is not what stops the squares.
    """

    mu: float = 1.0
    friction_margin: float = 0.2
    mu_cap: float = 1.0
    internal_force: float = 1.0
    carry_weight: bool = True
    carry_margin: float = 0.2
    max_squeeze: float = 3.0
    hold_force: float = 2.0
    left_hold_force: float = 2.0
    sensed_features: bool = False
    corner_probe: bool = True
    stroke_overlap: bool = False
    wall_approach: bool = False
    top_sweep: bool = False
    left_regrasp: bool = True
    last_resort: bool = True
    follow_prior: bool = True
    explore_force: float = 0.3
    object_mass: float = 0.05
    object_kp: tuple[float, float, float] = (80.0, 80.0, 0.8)
    object_kv: tuple[float, float, float] = (3.0, 3.0, 0.02)
    rolling_gains: tuple[float, float, float] = (1.0, 0.05, 0.04)
    internal_gains: InternalForceGains = InternalForceGains()
    hold_kp: float = 0.3
    hold_kv: float = 0.004
    tip_kp: float = 200.0
    tip_kv: float = 4.0
    phi_kp: float = 0.15
    phi_kv: float = 0.004
    hold_stiffness: float = 300.0
    hold_damping: float = 3.0
    min_force: float = 0.05
    torque_limit: float = 2.0
    rotation_speed: float = 0.4
    explore_speed: float = 0.03
    startup_time: float = 0.08
    joint_margin: float = 0.03
    min_epsilon: float = 0.01
    lost_force: float = 0.03
    lost_time: float = 0.04
    dt: float = 2e-3
    control_rate: float = 500.0
    nlp_knots: int = 6
    nlp_margin: float = 0.15
    max_phases: int = 200
    gravity: float = 9.81

    @property
    def planning_mu(self) -> float:
        """Friction coefficient of the planners' and controllers' cones, ``min(mu,
        mu_cap) (1 - friction_margin)`` [-] (0.8 by default)."""
        return min(self.mu, self.mu_cap) * (1 - self.friction_margin)

    def __post_init__(self) -> None:
        for f in fields(self):  # the switches: a string "false" would read as true
            v = getattr(self, f.name)
            if f.type == "bool" and not isinstance(v, bool):
                raise InvalidParameter(f"{f.name}: expected true or false, got {v!r}")
        checks.positive("mu", self.mu)
        checks.positive("mu_cap", self.mu_cap)
        checks.in_range("friction_margin", self.friction_margin, 0.0, 0.9)
        for name in ("internal_force", "hold_force", "left_hold_force", "explore_force",
                     "object_mass", "tip_kp", "phi_kp", "rotation_speed", "explore_speed",
                     "startup_time", "dt", "max_squeeze",
                     "control_rate", "lost_time", "torque_limit", "hold_stiffness"):  # fmt: skip
            checks.positive(name, getattr(self, name))
        for name in ("tip_kv", "phi_kv", "min_force", "joint_margin", "min_epsilon",
                     "lost_force", "nlp_margin", "hold_damping", "carry_margin", "hold_kp",
                     "hold_kv"):  # fmt: skip
            checks.nonnegative(name, getattr(self, name))
        for name in ("object_kp", "object_kv", "rolling_gains"):
            gains = checks.vector(name, getattr(self, name), 3)
            for i, g in enumerate(gains):  # a negative gain pushes away from the reference
                checks.nonnegative(f"{name}[{i}]", float(g))
        # eq. (2.8)'s moment saturates at rolling_gains[2]: 0 would switch the law off
        checks.positive("rolling_gains[2] (max_moment)", float(self.rolling_gains[2]), "N m")
        checks.integer("nlp_knots", self.nlp_knots, 2)
        checks.integer("max_phases", self.max_phases, 1)
        checks.in_range("gravity", self.gravity, 0.0, 100.0, unit="m/s^2")


__all__ = ["GaitSettings"]
