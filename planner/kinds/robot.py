"""Scenario kind ``robot``: draw a robot in a configuration and map its workspace.

* ``robot: planar_hand`` — the hand (thesis §2.2, Fig. 2.13) with a ball resting on the palm;
  the workspace map of each finger on the ball (which contact angles it can reach: IK inside
  the joint limits, fingertip orientation range, no penetration), sampled reachable sets, and
  the left pad's 8x8 tactile images sliding over the ball's ridge (Fig. 2.14).
* ``robot: three_gm`` — the 3GM finger (App. C.2) in a configuration and its well-conditioned
  trapezoid: IK, condition number and force capacity on a grid of the trapezoid.
"""

from __future__ import annotations

from typing import Literal

from pydantic import Field, model_validator

from planner.scenario import ScenarioBase, StrictModel

FINGERS = ("left", "right")


class HandOptions(StrictModel):
    """Options of the planar hand."""

    left_tip: Literal["flat", "round"] = Field(
        "flat", description="left fingertip: flat pad with the 8x8 array, or round"
    )
    right_tip: Literal["flat", "round"] = Field("round", description="right fingertip")
    tip_radius: float = Field(0.025, gt=0.0, le=0.1, description="round fingertip radius [m]")
    ball_diameter: float = Field(
        0.10, gt=0.0, le=0.3, description="diameter of the ball resting on the palm [m]"
    )
    angle_step_deg: float = Field(
        2.0, gt=0.0, le=45.0, description="contact-angle step of the workspace map [deg]"
    )
    max_tip_contact_angle_deg: float = Field(
        60.0,
        ge=0.0,
        le=90.0,
        description="round tips: largest angle between the fingertip axis and the contact [deg]",
    )
    samples: int = Field(
        3000, ge=10, le=200000, description="joint-space samples of each finger's reachable set"
    )
    tactile_force: float = Field(
        0.3,
        gt=0.0,
        le=20.0,
        description="normal force on the 8x8 array for the tactile images (0.3 N, §2.3.2) [N]",
    )
    ridge_width_mm: float = Field(
        4.0, gt=0.0, le=20.0, description="width of the ball's ridge (Fig. 2.15) [mm]"
    )
    ridge_height_mm: float = Field(
        3.0, gt=0.0, le=20.0, description="height of the ball's ridge (Fig. 2.15) [mm]"
    )


class ThreeGMOptions(StrictModel):
    """Options of the 3GM."""

    grid: int = Field(9, ge=2, le=30, description="trapezoid grid points per axis")


class Config(ScenarioBase):
    """Draw a robot (planar hand or 3GM) in a configuration, with its workspace."""

    kind: Literal["robot"]
    robot: Literal["planar_hand", "three_gm"] = Field(..., description="which robot")
    configuration_deg: tuple[float, ...] | None = Field(
        None,
        description="joint angles to draw [deg]: 6 for planar_hand (left j1..j3, right "
        "j1..j3), 3 for three_gm (θ1, θ2, θ3); default: a grasp of the ball / the "
        "workspace centre",
    )
    hand: HandOptions = Field(default_factory=HandOptions)
    three_gm: ThreeGMOptions = Field(default_factory=ThreeGMOptions)

    @model_validator(mode="after")
    def _check_configuration(self) -> Config:
        n = {"planar_hand": 6, "three_gm": 3}[self.robot]
        if self.configuration_deg is None:
            return self
        if len(self.configuration_deg) != n:
            raise ValueError(
                f"configuration_deg must have {n} angles for robot "
                f"{self.robot!r}, got {len(self.configuration_deg)}"
            )
        import numpy as np

        lim = self.robot_model().joint_limits
        q = np.deg2rad(np.array(self.configuration_deg))
        if not (np.all(q >= lim[:, 0] - 1e-9) and np.all(q <= lim[:, 1] + 1e-9)):
            raise ValueError(
                f"configuration_deg {list(self.configuration_deg)} is outside the joint "
                f"limits {np.rad2deg(lim).round(1).tolist()} deg"
            )
        return self

    def robot_model(self):
        """The :class:`robots.planar_hand.PlanarHand` or :class:`robots.three_gm.ThreeGM`."""
        if self.robot == "three_gm":
            from robots.three_gm import ThreeGM

            return ThreeGM()
        from robots.planar_hand import PlanarHand

        o = self.hand
        return PlanarHand(left_tip=o.left_tip, right_tip=o.right_tip, tip_radius=o.tip_radius)


def run(config: Config, ctx):
    """Run a ``robot`` scenario (see the module docstring)."""
    if config.robot == "planar_hand":
        return _run_hand(config, ctx)
    return _run_three_gm(config, ctx)


def _hand_configuration(hand, config: Config, maps: dict, events: list):
    """The configuration drawn: the scenario's, or each finger mid-way on its reachable arc."""
    import numpy as np

    from planner.results import Event

    if config.configuration_deg is not None:  # inside the limits: checked by Config
        return np.deg2rad(np.array(config.configuration_deg))
    q = hand.neutral()
    for f, m in maps.items():
        if m.reachable.any():
            idx = np.flatnonzero(m.reachable)
            q[hand.finger_slice(f)] = m.q[idx[len(idx) // 2]]
        else:
            events.append(Event("unreachable", f"{f} finger cannot touch the ball"))
    return q


def _tactile(o: HandOptions, ctx, radius: float):
    """The 8x8 array sliding over the ball's ridge, and its localization error [m]."""
    import numpy as np

    from robots.sensors import TactileArray, ridge_crossing_images

    arr = TactileArray()
    crossing = ridge_crossing_images(
        arr,
        np.linspace(-0.015, 0.015, 7 if ctx.quick else 31),
        o.tactile_force,
        radius,
        o.ridge_width_mm / 1000,
        o.ridge_height_mm / 1000,
    )
    centers = ctx.rng.uniform(-0.006, 0.006, size=(50 if ctx.quick else 500, 2))
    imgs = arr.sphere_images(centers, radius, o.tactile_force)
    pairs = zip(imgs, centers, strict=True)
    err = np.array(
        [
            np.linalg.norm(arr.read(im).centroid - c)
            for im, c in ctx.progress(pairs, "tactile reads", total=len(centers))
        ]
    )
    return arr, crossing, err


def _hand_metrics(o: HandOptions, angles, step: float, maps: dict, err, pos) -> dict:
    import numpy as np

    metrics = {"ball_diameter_m": o.ball_diameter, "n_angles": int(len(angles))}
    for f, m in maps.items():
        metrics[f"reachable_fraction_{f}"] = m.fraction
        metrics[f"reachable_arc_deg_{f}"] = float(m.reachable.sum() * step)
        if m.reachable.any():
            a = np.rad2deg(m.angles[m.reachable])
            metrics[f"reachable_angle_min_deg_{f}"] = float(a.min())
            metrics[f"reachable_angle_max_deg_{f}"] = float(a.max())
    metrics["tactile_localization_rms_mm"] = float(np.sqrt(np.mean(err**2)) * 1000)
    metrics["tactile_localization_max_mm"] = float(err.max() * 1000)
    metrics.update({f"tip_{f}_{c}": float(pos[f][i]) for f in pos for i, c in enumerate("xy")})
    return metrics


def _hand_figures(ctx, hand, q, center, radius, maps, sets, arr, crossing, o) -> dict:
    from robots.plotting import plot_hand, plot_reachable_sets

    figures = {
        "hand": plot_hand(
            hand,
            q,
            center,
            radius,
            maps,
            title=f"Planar hand and a {o.ball_diameter * 100:.0f} cm ball: reachable contacts",
        )
    }
    if not ctx.quick:  # one figure is enough for a smoke test
        from robots.sensors.tactile_scenes import draw_ridge_crossing

        figures["reachable_sets"] = plot_reachable_sets(
            {f: s.positions for f, s in sets.items()}, center, radius
        )
        figures["tactile_ridge_crossing"] = draw_ridge_crossing(arr, crossing)
    return figures


def _run_hand(config: Config, ctx):
    import numpy as np

    from planner.results import RunResult
    from robots.planar_hand import ball_workspace, sample_reachable

    o = config.hand
    hand = config.robot_model()
    radius = o.ball_diameter / 2
    center = np.array([0.0, radius])
    step = max(o.angle_step_deg, 10.0) if ctx.quick else o.angle_step_deg
    angles = np.deg2rad(np.arange(0.0, 360.0, step))
    tip_angle = np.deg2rad(o.max_tip_contact_angle_deg)
    with ctx.timer("workspace_map"):
        maps = {f: ball_workspace(hand, f, center, radius, angles, tip_angle) for f in FINGERS}
    with ctx.timer("reachable_set"):
        n = min(o.samples, 300) if ctx.quick else o.samples
        sets = {f: sample_reachable(hand, f, n, ctx.rng) for f in FINGERS}
    events: list = []
    q = _hand_configuration(hand, config, maps, events)
    with ctx.timer("tactile"):
        arr, crossing, err = _tactile(o, ctx, radius)
    metrics = _hand_metrics(o, angles, step, maps, err, hand.fingertip_positions(q))
    arrays = {"contact_angles": angles, "q": q}
    for f in FINGERS:
        arrays[f"reachable_{f}"] = maps[f].reachable
        arrays[f"q_{f}"] = maps[f].q
        arrays[f"reachable_set_{f}"] = sets[f].positions
    arrays["tactile_ridge_offsets"] = crossing.offsets
    arrays["tactile_ridge_images"] = crossing.images
    figures = {}
    if ctx.plots:
        with ctx.timer("plots"):
            figures = _hand_figures(ctx, hand, q, center, radius, maps, sets, arr, crossing, o)
    touches = any(m.reachable.any() for m in maps.values())
    return RunResult(
        status="ok" if touches else "failed",
        reason="" if touches else "neither finger can touch the ball",
        metrics=metrics,
        arrays=arrays,
        events=events,
        figures=figures,
    )


def _run_three_gm(config: Config, ctx):
    import numpy as np

    from planner.errors import SingularConfiguration
    from planner.results import RunResult
    from robots.three_gm import check_conditioned_workspace, trapezoid_grid
    from robots.three_gm.workspace import trapezoid_volume

    gm = config.robot_model()
    if config.configuration_deg is not None:  # inside the limits: checked by Config
        theta = np.deg2rad(np.array(config.configuration_deg))
    else:
        theta = gm.center_theta
    try:
        x = gm.forward_kinematics(theta)
        J = gm.jacobian(theta)
    except SingularConfiguration as exc:
        return RunResult(status="failed", reason=str(exc))
    n = min(config.three_gm.grid, 4) if ctx.quick else config.three_gm.grid
    with ctx.timer("workspace"):
        ws = check_conditioned_workspace(gm, trapezoid_grid(n))
    ok = ws.reachable
    metrics = {
        "endpoint_x": float(x[0]),
        "endpoint_y": float(x[1]),
        "endpoint_z": float(x[2]),
        "jacobian_condition": float(np.linalg.cond(J)),
        "force_capacity_N": gm.force_capacity(theta),
        "workspace_volume_in3": trapezoid_volume() / 0.0254**3,
        "workspace_reachable_fraction": float(ok.mean()),
        "workspace_max_condition": float(ws.condition[ok].max()) if ok.any() else None,
        "workspace_min_force_N": float(ws.force_capacity[ok].min()) if ok.any() else None,
        "force_at_center_N": gm.force_capacity(gm.center_theta),
        "encoder_resolution_rad": gm.encoder_resolution,
    }
    arrays = {
        "theta": theta,
        "endpoint": x,
        "workspace_points": ws.points,
        "workspace_theta": ws.theta,
        "workspace_condition": ws.condition,
        "workspace_force_capacity": ws.force_capacity,
    }
    figures = {}
    if ctx.plots:
        from robots.plotting import plot_three_gm

        with ctx.timer("plots"):
            figures["three_gm"] = plot_three_gm(gm, theta, ws)
    if not ok.all():
        return RunResult(
            status="failed",
            reason=f"{int((~ok).sum())} trapezoid points are unreachable",
            metrics=metrics,
            arrays=arrays,
            figures=figures,
        )
    return RunResult(metrics=metrics, arrays=arrays, figures=figures)
