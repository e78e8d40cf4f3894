"""Scenario kind ``gait``: the ch. 2 grasp gait executed in the planar world (§2.2-2.3).

Keys (SI units)::

    task: explore                # explore (Fig. 2.3 phase machine) | explicit_rolling (Fig. 2.10)
    object:                      # the TRUE object (closed, star-shaped about its origin)
      shape: circle_with_ridge   # circle | circle_with_ridge | ellipse | rounded_rectangle |
                               # polygon
      radius: 0.05               # circle(_with_ridge) [m]
      ridge_width: 0.004         # [m]
      ridge_height: 0.003        # [m]
      ridge_angle_deg: 170       # polar angle of the ridge on the object [deg]
      a: 0.06, b: 0.04           # ellipse semi-axes [m]
      width, height, corner_radius  # rounded_rectangle [m]
      points: [[x, y], ...]      # polygon [m]
    nominal: null                # the planner's model (same keys); default: feature-less circle
    mu: 1.0                      # friction of fingers/palm/object [-]
    mu_cap: 1.0                  # the planners and controllers count on at most this mu [-]
    explore_force: 0.3           # normal force of the exploring finger [N]
    internal_force: 1.0          # squeeze of the two-finger grasp (phase 1) [N]
    hold_force: 2.0              # press of the right finger against the palm (phase 3) [N]
    left_hold_force: 2.0         # press of the left pad against the palm (phase 2) [N]
    sensed_features: false       # back-stroke over sensed ridges, palm cap (GaitSettings)
    corner_probe: true           # the pad's end back into the corner beyond a jumped wall
    stroke_overlap: false        # phase-3 strokes first go back into the pad's last one
    wall_approach: false         # the pad leads with its end towards a known wall
    top_sweep: false             # the right tip first sweeps back over a ridge's top
    left_regrasp: true           # no phase-1 plan twice: the left pad regrasps before giving up
    last_resort: true            # then phase 1 with the tip's range relaxed (GaitSettings)
    follow_prior: true           # posed nominal outline: regrasp to plan_gait's handoffs
    object_mass: 0.05            # [kg]
    gravity: 9.81                # in the hand's plane, towards the palm [m/s^2]; 0: the hand
                                 # lies in a horizontal plane (frictionless support)
    rotation_speed: 0.4          # phase-1 rotation speed [rad/s]
    explore_speed: 0.03          # exploring contact speed [m/s]
    duration: 40.0               # simulated time limit [s]
    quick_duration: 0.6          # with --quick [s]
    max_rotation_deg: 360        # stop after this rotation [deg]
    dt: 0.002                    # simulator step [s]
    control_rate: 500            # [Hz]
    hand:                        # joint ranges of the RIGHT finger (the left one mirrors it)
      joint_lower_deg: [-40, 0, -10]
      joint_upper_deg: [90, 150, 130]   # the gait's hand (the thesis' fingers: [70, 110, 100])
      left_tip_radius: null      # [m] a round left tip (e.g. 0.025, the right one's) instead
                                 # of the flat pad; with a round (or no) nominal model only
    gains: {...}                 # see GainsConfig
    rolling: {amplitude: 0.003, period: 1.0}   # explicit_rolling only
    output: {animation: false}   # true: plots/animation.gif (+ the usual plots/formats/dpi)

Outputs: ``result.json`` metrics (phases, transitions_4, rotation_deg, coverage,
min_epsilon, slip_distance_m, explore_force_rms_error_N, internal_force_rms_error_N,
features found vs the true features with angle errors, real_time_factor, NLP and control-step
timings, last_phase, noise_seed: the seed ``explore_object`` got, left_tip_radius_m: null
for the flat pad), ``phases.json``,
``trajectory.npz`` (the simulator log ``log/*`` and the controller's sensed series
``trace/*``), plots ``snapshots`` (Fig. 2.12), ``forces`` (Fig. 2.14), ``contacts``
(Fig. 2.10), ``timeline``, and ``plots/animation.gif``.
A gait that cannot go on ends with status "failed" (exit 1), the reason and the last phase,
and the same complete outputs up to the failure.
"""

from __future__ import annotations

import math
from typing import Literal

from pydantic import Field, model_validator

from planner.scenario import OutputSettings, ScenarioBase, StrictModel

#: the keys of :class:`ObjectSpec` that give a shape function's parameters of other names
_SHAPE_KEYS = {
    "circle_with_ridge": {
        "width": "ridge_width",
        "height": "ridge_height",
        "angle": "ridge_angle_deg",
    },
}


class ObjectSpec(StrictModel):
    """A closed planar object profile (object frame)."""

    shape: Literal["circle", "circle_with_ridge", "ellipse", "rounded_rectangle", "polygon"]
    radius: float | None = Field(None, gt=0, le=0.2, description="circle radius [m]")
    ridge_width: float = Field(0.004, gt=0, le=0.02, description="ridge width [m]")
    ridge_height: float = Field(0.003, gt=0, le=0.02, description="ridge height [m]")
    ridge_angle_deg: float = Field(170.0, ge=-360, le=360, description="ridge position [deg]")
    a: float | None = Field(None, gt=0, le=0.3, description="ellipse semi-axis x [m]")
    b: float | None = Field(None, gt=0, le=0.3, description="ellipse semi-axis y [m]")
    width: float | None = Field(None, gt=0, le=0.3, description="rectangle width [m]")
    height: float | None = Field(None, gt=0, le=0.3, description="rectangle height [m]")
    corner_radius: float = Field(0.0, ge=0, description="rectangle corner radius [m]")
    points: list[tuple[float, float]] | None = Field(None, min_length=3, description="[m]")

    @model_validator(mode="after")
    def _needs(self):
        need = {
            "circle": ("radius",), "circle_with_ridge": ("radius",), "ellipse": ("a", "b"),
            "rounded_rectangle": ("width", "height"), "polygon": ("points",),
        }[self.shape]  # fmt: skip
        missing = [k for k in need if getattr(self, k) is None]
        if missing:
            raise ValueError(f"shape {self.shape!r} needs key(s) {missing}")
        from planner.errors import HapexError

        try:
            self.profile().point_at_polar_angle([0.0, 2.0, 4.0])
        except HapexError as exc:  # named by its key here (circle_with_ridge's "width")
            head, sep, rest = str(exc).partition(": ")
            key = _SHAPE_KEYS.get(self.shape, {}).get(head, head)
            raise ValueError(f"{key}{sep}{rest}") from None
        return self

    def profile(self):
        """The :class:`planner.geometry.profiles.Profile`."""
        from planner.exploration.planar import circle_with_ridge
        from planner.geometry import shapes

        if self.shape == "circle":
            return shapes.circle(self.radius)
        if self.shape == "circle_with_ridge":
            return circle_with_ridge(self.radius, self.ridge_width, self.ridge_height,
                                     math.radians(self.ridge_angle_deg))  # fmt: skip
        if self.shape == "ellipse":
            return shapes.ellipse(self.a, self.b)
        if self.shape == "rounded_rectangle":
            return shapes.rounded_rectangle(self.width, self.height, self.corner_radius)
        return shapes.polygon([list(p) for p in self.points])


class GainsConfig(StrictModel):
    """Controller gains (defaults of :class:`planner.exploration.planar.GaitSettings`)."""

    object_kp: tuple[float, float, float] = Field((80.0, 80.0, 0.8), description="eq. 2.7")
    object_kv: tuple[float, float, float] = Field((3.0, 3.0, 0.02), description="eq. 2.7")
    rolling: tuple[float, float, float] = Field((1.0, 0.05, 0.04), description="eq. 2.8")
    hold_kp: float = Field(0.3, ge=0, le=5, description="[N m/rad]")
    hold_kv: float = Field(0.004, ge=0, le=0.1, description="[N m s/rad]")
    tip_kp: float = Field(200.0, gt=0, le=1000, description="[N/m]")
    tip_kv: float = Field(4.0, ge=0, le=50, description="[N s/m]")

    @model_validator(mode="after")
    def _ranges(self):
        for name in ("object_kp", "object_kv", "rolling"):
            v = getattr(self, name)
            if any(not (0 <= x <= 1e4) for x in v):
                raise ValueError(f"{name}: every gain must be in [0, 1e4], got {list(v)}")
        if not self.rolling[2] > 0:
            raise ValueError(
                f"rolling: its third entry, the moment saturation [N m], must be > 0 "
                f"(0 switches eq. 2.8 off), got {list(self.rolling)}"
            )
        return self


class HandConfig(StrictModel):
    """Joint ranges of the two-finger hand (right finger; the left finger mirrors them) and
    its left fingertip: the flat pad with the 8x8 tactile array (default, the thesis' hand)
    or a round tip of ``left_tip_radius`` [m] (no tactile array: its contact is sensed like
    the right tip's; §2.3.2 found the flat-and-round pair "fairly restrictive").

    The default is the gait's hand (``robots.planar_hand.params.GAIT_LOWER_DEG`` ..
    ``GAIT_UPPER_DEG``). The thesis' fingers had about 110 deg per joint
    (``[-40, 0, -10]`` .. ``[70, 110, 100]`` here): with them circles of 2-3 cm radius do not
    fit the hand and 4-5 cm ones stall after 16-42 deg (every phase 1 ends at a joint stop).
    """

    # robots.planar_hand's GAIT_LOWER_DEG / GAIT_UPPER_DEG, written out: importing robots here
    # would load Pinocchio on every CLI start (tests/test_gait_default_hand.py checks they agree)
    joint_lower_deg: tuple[float, float, float] = Field((-40.0, 0.0, -10.0))
    joint_upper_deg: tuple[float, float, float] = Field((90.0, 150.0, 130.0))
    left_tip_radius: float | None = Field(
        None, ge=0.005, le=0.05,
        description="round left tip [m] (null: the flat pad with the 8x8 tactile array)",
    )  # fmt: skip

    @model_validator(mode="after")
    def _ranges(self):
        for lo, hi in zip(self.joint_lower_deg, self.joint_upper_deg, strict=True):
            if not (-180.0 <= lo < hi <= 180.0):
                raise ValueError(
                    f"joint ranges must satisfy -180 <= lower < upper <= 180 deg, got "
                    f"{list(self.joint_lower_deg)} / {list(self.joint_upper_deg)}"
                )
        return self

    def hand(self, mu: float):
        """The ``robots.planar_hand.PlanarHand`` with these ranges."""
        from robots.planar_hand import PlanarHand
        from robots.planar_hand.params import ranged_hand_params

        params = ranged_hand_params(
            self.joint_lower_deg, self.joint_upper_deg, mu, self.left_tip_radius
        )
        return PlanarHand(params)


class RollingConfig(StrictModel):
    """The explicit-rolling task (Figs. 2.9/2.10)."""

    amplitude: float = Field(0.003, gt=0, le=0.008, description="contact amplitude [m]")
    period: float = Field(1.0, gt=0, le=20, description="[s]")


class GaitOutput(OutputSettings):
    """Output settings plus the animation switch."""

    animation: bool = Field(False, description="write plots/animation.gif")


class Config(ScenarioBase):
    """The executed grasp gait (or explicit rolling) on one object."""

    kind: Literal["gait"]
    task: Literal["explore", "explicit_rolling"] = "explore"
    object: ObjectSpec
    nominal: ObjectSpec | None = None
    mu: float = Field(1.0, gt=0, le=10, description="friction coefficient [-]")
    mu_cap: float = Field(1.0, gt=0, le=10, description="friction counted on, at most [-]")
    explore_force: float = Field(0.3, gt=0, le=5, description="[N]")
    internal_force: float = Field(1.0, gt=0, le=20, description="[N]")
    hold_force: float = Field(2.0, gt=0, le=20, description="phase 3 right finger press [N]")
    left_hold_force: float = Field(2.0, gt=0, le=20, description="phase 2 left pad press [N]")
    sensed_features: bool = Field(False, description="back-stroke + palm cap (GaitSettings)")
    corner_probe: bool = Field(True, description="corner probe beyond a jumped wall")
    stroke_overlap: bool = Field(False, description="overlapping phase-3 strokes")
    wall_approach: bool = Field(False, description="pad's end first towards a known wall")
    top_sweep: bool = Field(False, description="right tip back over a ridge's top (phase 2)")
    left_regrasp: bool = Field(True, description="left pad regrasp before giving up")
    last_resort: bool = Field(True, description="last phase-1 plan, tip's range relaxed")
    follow_prior: bool = Field(True, description="regrasp to the prior's handoffs (outline)")
    object_mass: float = Field(0.05, gt=0, le=2, description="[kg]")
    gravity: float = Field(9.81, ge=0, le=100, description="towards the palm [m/s^2]")
    rotation_speed: float = Field(0.4, gt=0, le=3, description="[rad/s]")
    explore_speed: float = Field(0.03, gt=0, le=0.5, description="[m/s]")
    duration: float = Field(40.0, gt=0, le=3600, description="simulated time limit [s]")
    quick_duration: float = Field(0.6, gt=0, le=60, description="--quick time limit [s]")
    max_rotation_deg: float = Field(360.0, gt=0, le=3600, description="[deg]")
    dt: float = Field(0.002, gt=0, le=0.01, description="simulator step [s]")
    control_rate: float = Field(500.0, ge=50, le=5000, description="[Hz]")
    hand: HandConfig = Field(default_factory=HandConfig)
    gains: GainsConfig = Field(default_factory=GainsConfig)
    rolling: RollingConfig = Field(default_factory=RollingConfig)
    output: GaitOutput = Field(default_factory=GaitOutput)

    @model_validator(mode="after")
    def _fits(self):
        from planner.errors import InvalidParameter
        from planner.exploration.planar.arguments import check_tips
        from planner.exploration.planar.setup import check_fits

        tip = "flat" if self.hand.left_tip_radius is None else "round"
        nominal = None if self.nominal is None else self.nominal.profile()
        try:
            check_tips(tip, "round", nominal)
        except InvalidParameter as err:
            raise ValueError(str(err)) from None
        from planner.exploration.planar import GaitSettings

        fit = GaitSettings(mu=self.mu, mu_cap=self.mu_cap)  # the start grasp's cones
        why = check_fits(self.object.profile(), self.mu, self.hand.hand(self.mu), settings=fit)
        if why:
            raise ValueError(f"object: {why}")
        return self

    def settings(self):
        from planner.exploration.planar import GaitSettings

        g = self.gains
        return GaitSettings(
            mu=self.mu, mu_cap=self.mu_cap, internal_force=self.internal_force,
            hold_force=self.hold_force, left_hold_force=self.left_hold_force,
            sensed_features=self.sensed_features,
            corner_probe=self.corner_probe, stroke_overlap=self.stroke_overlap,
            wall_approach=self.wall_approach, top_sweep=self.top_sweep,
            left_regrasp=self.left_regrasp,
            last_resort=self.last_resort, follow_prior=self.follow_prior,
            explore_force=self.explore_force,
            object_mass=self.object_mass, object_kp=g.object_kp, object_kv=g.object_kv,
            rolling_gains=g.rolling, hold_kp=g.hold_kp, hold_kv=g.hold_kv, tip_kp=g.tip_kp,
            tip_kv=g.tip_kv, rotation_speed=self.rotation_speed,
            explore_speed=self.explore_speed, dt=self.dt, control_rate=self.control_rate,
            gravity=self.gravity,
        )  # fmt: skip


def run(config: Config, ctx):
    """Execute the gait (or explicit rolling); metrics, arrays, events and figures."""
    from planner.exploration.planar import explore_object
    from planner.exploration.planar.rolling_demo import explicit_rolling

    profile = config.object.profile()
    nominal = config.nominal.profile() if config.nominal is not None else None
    duration = config.quick_duration if ctx.quick else config.duration
    s = config.settings()
    hand = _hand(config)
    seed = int(ctx.rng.integers(2**31))
    bar = ctx.progress(total=round(duration, 1), desc="gait [sim s]")
    done = [0.0]

    def advance(t: float) -> None:
        bar.update(round(min(t, duration) - done[0], 1))
        done[0] = round(min(t, duration), 1)

    with ctx.timer("simulation"), bar:
        if config.task == "explicit_rolling":
            res = explicit_rolling(profile, hand=hand, mu=config.mu,
                                   amplitude=config.rolling.amplitude,
                                   period=config.rolling.period, duration=duration, seed=seed,
                                   settings=s)  # fmt: skip
        else:
            res = explore_object(profile, hand=hand, mu=config.mu, nominal=nominal,
                                 seed=seed,
                                 duration=duration, settings=s,
                                 max_rotation=math.radians(config.max_rotation_deg),
                                 on_progress=advance)  # fmt: skip
    from planner.kinds._gait_report import report

    return report(config, ctx, res, profile, duration, hand, noise_seed=seed)


def _hand(config: Config):
    return config.hand.hand(config.mu)
