"""Scenario kind ``grasp_map``: grasp maps, workspace maps and a grasp gait (§2.2.1, Fig. 2.4).

Keys (SI units)::

    object:                      # closed planar profile, star-shaped about its origin
      type: circle               # circle | ellipse | rounded_rectangle | polygon
      radius: 0.05               # circle [m]
      a: 0.06                    # ellipse semi-axis along x [m]
      b: 0.04                    # ellipse semi-axis along y [m]
      width: 0.08                # rounded_rectangle [m]
      height: 0.08               # rounded_rectangle [m]
      corner_radius: 0.01        # rounded_rectangle [m]
      points: [[x, y], ...]      # polygon vertices [m]
    mu: 1.0                      # finger-object friction coefficient [-]
    mu_palm: null                # palm-object friction (default: mu) [-]
    resolution: 360              # grasp-map grid (contact angles per axis)
    gait_resolution: 72          # grid of the gait search (rotation step 360/n deg)
    direction: clockwise         # object rotation of the gait
    object_x: 0.0                # x of the object origin on the palm [m]
    roll_length: null            # fingertip rolling travel per phase 1 [m] (default: hand)
    min_epsilon: 0.0             # ε margin every holding grasp of the gait must keep
    require_gait: true           # no gait -> status "failed" (exit 1) with the reason
    hand: {left_tip: flat, right_tip: round, tip_radius: 0.025,
           max_tip_contact_angle_deg: 60}
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from planner.scenario import ScenarioBase, StrictModel


class ObjectConfig(StrictModel):
    """The object's closed profile (object frame; star-shaped about its origin)."""

    type: Literal["circle", "ellipse", "rounded_rectangle", "polygon"] = Field(
        ..., description="profile type (the ``profile: {type: ...}`` spelling of every kind)"
    )
    radius: float | None = Field(None, gt=0, description="circle radius [m]")
    a: float | None = Field(None, gt=0, description="ellipse semi-axis along x [m]")
    b: float | None = Field(None, gt=0, description="ellipse semi-axis along y [m]")
    width: float | None = Field(None, gt=0, description="rounded rectangle width [m]")
    height: float | None = Field(None, gt=0, description="rounded rectangle height [m]")
    corner_radius: float = Field(0.0, ge=0, description="rounded rectangle corner radius [m]")
    points: list[tuple[float, float]] | None = Field(
        None, min_length=3, description="polygon vertices [m]"
    )

    @model_validator(mode="after")
    def _needs(self):
        need = {
            "circle": ("radius",),
            "ellipse": ("a", "b"),
            "rounded_rectangle": ("width", "height"),
            "polygon": ("points",),
        }[self.type]
        missing = [k for k in need if getattr(self, k) is None]
        if missing:
            raise ValueError(f"type {self.type!r} needs key(s) {missing}")
        if self.type == "rounded_rectangle" and 2 * self.corner_radius > min(
            self.width, self.height
        ):
            raise ValueError("corner_radius must be at most half of width and height")
        from planner.errors import InvalidParameter
        from planner.grasp.maps import profile_contacts

        try:  # the profile must exist and be star-shaped about its origin
            profile_contacts(self.profile(), [0.0, 2.0, 4.0])
        except InvalidParameter as exc:
            raise ValueError(str(exc)) from None
        return self

    def profile(self):
        """The :mod:`planner.geometry.curves` profile."""
        from planner.geometry import curves

        if self.type == "circle":
            return curves.circle(self.radius)
        if self.type == "ellipse":
            return curves.ellipse(self.a, self.b)
        if self.type == "rounded_rectangle":
            return curves.rounded_rectangle(self.width, self.height, self.corner_radius)
        return curves.polygon([list(p) for p in self.points])


class HandConfig(StrictModel):
    """The planar two-finger hand with a palm (robots.planar_hand defaults)."""

    left_tip: Literal["flat", "round"] = Field("flat", description="left fingertip type")
    right_tip: Literal["flat", "round"] = Field("round", description="right fingertip type")
    tip_radius: float = Field(0.025, gt=0, le=0.1, description="round fingertip radius [m]")
    max_tip_contact_angle_deg: float = Field(
        60.0, ge=0, le=90, description="round tips: largest contact angle off the tip axis [deg]"
    )


class Config(ScenarioBase):
    """Grasp maps (three finger pairs), workspace map and gait search for one object."""

    kind: Literal["grasp_map"]
    object: ObjectConfig
    mu: float = Field(1.0, ge=0, le=10, description="finger-object friction coefficient [-]")
    mu_palm: float | None = Field(
        None, ge=0, le=10, description="palm-object friction (default mu) [-]"
    )
    resolution: int = Field(360, ge=8, le=1440, description="grasp-map contact angles per axis")
    gait_resolution: int = Field(
        72, ge=8, le=360, description="contact-angle grid of the gait search"
    )
    direction: Literal["clockwise", "counterclockwise"] = Field(
        "clockwise", description="object rotation direction of the gait"
    )
    object_x: float = Field(0.0, ge=-0.1, le=0.1, description="object origin x on the palm [m]")
    roll_length: float | None = Field(None, gt=0, description="rolling travel per phase 1 [m]")
    min_epsilon: float = Field(
        0.0, ge=0, lt=1, description="ε margin every holding grasp of the gait must keep [-]"
    )
    require_gait: bool = Field(True, description="fail the run when no gait exists")
    hand: HandConfig = Field(default_factory=HandConfig)


def _maps(config: Config, res: int):
    """Profile, hand, reachability model and the left–right / finger–palm grasp maps."""
    import numpy as np

    from planner.errors import InputIssue, InvalidParameter, ScenarioError
    from planner.grasp.maps import grasp_map
    from planner.grasp.workspace import HandReachability
    from robots.planar_hand import PlanarHand

    try:
        profile = config.object.profile()
        hand = PlanarHand(
            left_tip=config.hand.left_tip,
            right_tip=config.hand.right_tip,
            tip_radius=config.hand.tip_radius,
            friction=config.mu,
        )
        reach = HandReachability(
            hand, max_tip_contact_angle=np.deg2rad(config.hand.max_tip_contact_angle_deg)
        )
        mu_p = config.mu if config.mu_palm is None else config.mu_palm
        g_lr = grasp_map(profile, config.mu, res)
        g_fp = grasp_map(profile, config.mu, res, mu2=mu_p)
    except InvalidParameter as exc:
        raise ScenarioError([InputIssue("(scenario)", 0, "object", str(exc))]) from None
    return profile, hand, reach, g_lr, g_fp


def _metrics(res: int, gres: int, g_lr, g_fp, ws, gait) -> dict:
    import numpy as np

    rl, rr = ws.reachable["left"][0], ws.reachable["right"][0]
    return {
        "resolution": res,
        "gait_resolution": gres,
        "closure_fraction": g_lr.closure_fraction,
        "closure_fraction_finger_palm": g_fp.closure_fraction,
        "max_epsilon": float(g_lr.epsilon.max()),
        "workspace_fraction_left": float(rl.mean()),
        "workspace_fraction_right": float(rr.mean()),
        "palm_contact_angle_deg": float(np.rad2deg(ws.placement.palm_theta[0])),
        "feasible_left_right_fraction": float(
            (g_lr.force_closure & rl[:, None] & rr[None, :]).mean()
        ),
        "gait_feasible": gait.feasible,
        "gait_reason": gait.reason,
        "rotation_per_cycle_deg": float(np.rad2deg(gait.rotation_per_cycle)),
        "gait_cycles": gait.cycles,
        "gait_turns": gait.turns,
        "gait_phases": len(gait.phases),
        "gait_min_epsilon": gait.min_epsilon,
        "coverage": gait.coverage,
    }


def _arrays(res: int, g_lr, g_fp, ws, gait) -> dict:
    import numpy as np

    rl, rr = ws.reachable["left"][0], ws.reachable["right"][0]
    palm = (np.arange(res) == int(ws.palm_index[0]))[None, :]
    return {
        "theta": g_lr.theta,
        "force_closure_left_right": g_lr.force_closure,
        "epsilon_left_right": g_lr.epsilon,
        "force_closure_left_palm": g_fp.force_closure,
        "epsilon_left_palm": g_fp.epsilon,
        "force_closure_right_palm": g_fp.force_closure.T,
        "epsilon_right_palm": g_fp.epsilon.T,
        "reachable_left": rl,
        "reachable_right": rr,
        "workspace_left_right": rl[:, None] & rr[None, :],
        "workspace_left_palm": rl[:, None] & palm,
        "workspace_right_palm": rr[:, None] & palm,
        "gait_path": gait.path,
    }


def _events(gait) -> list:
    import numpy as np

    from planner.results import Event

    events = [
        Event(
            "gait",
            "cyclic gait found" if gait.feasible else gait.reason,
            data={"feasible": gait.feasible},
        )
    ]
    for k, ph in enumerate(gait.phases):
        events.append(
            Event(
                "phase",
                f"phase {ph.phase} ({'+'.join(ph.holding)}), "
                f"rotation {np.rad2deg(ph.rotation):.1f} deg",
                t=float(k),
                data=ph.to_json(),
            )
        )
    return events


def _figures(config: Config, g_lr, ws, gait, prob, profile, hand) -> dict:
    """``grasp_map`` (workspace and gait grasps at the initial pose), ``gait_map`` (phase by
    phase, each over its own pose's workspace) and ``gait_phases`` (hand and object)."""
    from planner.grasp.plotting import plot_gait_map, plot_gait_phases, plot_grasp_map

    figures = {
        "grasp_map": plot_grasp_map(
            g_lr, ws, gait, title=f"{config.name}: grasp map, μ = {config.mu:g}"
        )
    }
    if gait.feasible:
        figures["gait_map"] = plot_gait_map(prob, gait)
        figures["gait_phases"] = plot_gait_phases(profile, gait, prob, hand=hand)
    return figures


def run(config: Config, ctx):
    """Build the maps, search the gait, return metrics, arrays, gait.json and figures."""
    import json

    from planner.grasp.gait import gait_problem, search_gait
    from planner.grasp.workspace import workspace_tables
    from planner.results import RunResult

    res = min(config.resolution, 90) if ctx.quick else config.resolution
    gres = min(config.gait_resolution, 48) if ctx.quick else config.gait_resolution
    with ctx.timer("grasp_map"):
        profile, hand, reach, g_lr, g_fp = _maps(config, res)
    with ctx.timer("workspace_map"):
        ws = workspace_tables(profile, reach, g_lr.theta, [0.0], config.object_x)
    with ctx.timer("gait_search"):
        prob = gait_problem(
            profile,
            reach,
            config.mu,
            mu_palm=config.mu_palm,
            resolution=gres,
            direction=config.direction,
            x0=config.object_x,
            roll_length=config.roll_length,
            min_epsilon=config.min_epsilon,
        )
        gait = search_gait(prob)
    ctx.log(f"gait feasible={gait.feasible} {gait.reason}")
    figures = {}
    if ctx.plots:
        with ctx.timer("plots"):
            figures = _figures(config, g_lr, ws, gait, prob, profile, hand)
    status = "ok" if (gait.feasible or not config.require_gait) else "failed"
    return RunResult(
        status=status,
        reason="" if status == "ok" else f"no grasp gait: {gait.reason}",
        metrics=_metrics(res, gres, g_lr, g_fp, ws, gait),
        arrays=_arrays(res, g_lr, g_fp, ws, gait),
        events=_events(gait),
        figures=figures,
        files={"gait.json": json.dumps(gait.to_json(), indent=2)},
    )
