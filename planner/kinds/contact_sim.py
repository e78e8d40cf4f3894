"""Scenario kind ``contact_sim``: a verification scene of the contact simulator (issue 15).

Either a custom planar world (fixed outlines + free bodies, no controller) or a named scene
with its controller preset. Keys (SI units; angles in degrees only where the key ends in
``_deg``)::

    dt: 0.001                    # time step [s]
    duration: 2.0                # simulated time [s] (scenes: default = their own)
    gravity: [0.0, -9.81]        # [m/s^2]: (gx, gy) for planar worlds (the default), and
                                 # (gx, gy, gz) for ridge_3gm (default [0, 0, -9.81])
    fixed:                       # fixed outlines (any catalogue profile)
      - name: incline
        profile: {type: plane, angle_deg: 20, length: 2.0}
        position: [0.0, 0.0]     # x, y of the profile's frame [m]
        angle_deg: 0.0           # its rotation [deg]
        friction: 0.5
    bodies:                      # free rigid bodies (closed profiles)
      - name: box
        profile: {type: rounded_rectangle, width: 0.02, height: 0.01}
        position: [0.0, 0.005]   # x, y of the profile's frame [m]
        angle_deg: 0.0           # its rotation [deg]
        mass: 0.1                # [kg]
        inertia: null            # [kg m^2] (default: uniform density)
        velocity: [0, 0, 0]      # vx, vy [m/s], omega [rad/s]
        friction: 0.5
    scene:                       # instead of fixed/bodies: a scene with its controller
      preset: pinch              # pinch | palm_roll | hold_slide | ridge_3gm
      params: {squeeze: 1.96}    # keyword arguments of the scene builder

Metrics (the unit ends each key): per body ``<body>.displacement_m`` and
``<body>.rotation_rad``, ``final_velocity_m_s`` / ``final_angular_velocity_rad_s`` and
``mean_acceleration_m_s2`` / ``mean_angular_acceleration_rad_s2``; the largest
penetration; the integrated slip of every contact pair; the events; for ``ridge_3gm`` the
centre-path error against the exact offset surface. Plots: trajectories, contact forces, slip.
"""

from __future__ import annotations

from functools import cache
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import BaseModel, Field, create_model, field_validator, model_validator

from planner.kinds._profiles import ProfileSpec, build_profile
from planner.results import Event, RunResult
from planner.scenario import ScenarioBase, StrictModel

Real = Annotated[float, Field(allow_inf_nan=False)]

SCENES = ("pinch", "palm_roll", "hold_slide", "ridge_3gm")


class _Placed(StrictModel):
    """An outline placed by ``position`` [m] and ``angle_deg`` [deg]. The key these replace,
    ``pose: [x, y, angle]`` (until 2026-11-25; its angle in degrees, which its name did not
    say), is still read with that meaning, so older files keep their placements; given
    beside either new key it is refused."""

    @model_validator(mode="before")
    @classmethod
    def _pose_read(cls, data):
        if not (isinstance(data, dict) and "pose" in data):
            return data
        p = data["pose"]
        both = [k for k in ("position", "angle_deg") if k in data]
        if both:
            _raise_at([(("pose",), f"give either pose or {' and '.join(both)}, not both")])
        if not (isinstance(p, (list, tuple)) and len(p) == 3):
            _raise_at([(("pose",), f"expected [x, y, angle in degrees], got {p!r} (or use "
                                   "position: [x, y] [m] and angle_deg)")])  # fmt: skip
        out = {k: v for k, v in data.items() if k != "pose"}
        return {**out, "position": [p[0], p[1]], "angle_deg": p[2]}


class FixedSpec(_Placed):
    """A fixed outline."""

    name: str = Field(..., pattern=r"^[A-Za-z0-9_.-]+$")
    profile: ProfileSpec
    position: tuple[Real, Real] = Field((0.0, 0.0), description="x, y of the profile [m]")
    angle_deg: Real = Field(0.0, description="rotation of the profile [deg]")
    friction: float = Field(0.5, ge=0, allow_inf_nan=False, description="Coulomb mu [-]")


class BodySpec(_Placed):
    """A free rigid body."""

    name: str = Field(..., pattern=r"^[A-Za-z0-9_.-]+$")
    profile: ProfileSpec
    position: tuple[Real, Real] = Field(..., description="x, y of the profile's frame [m]")
    angle_deg: Real = Field(0.0, description="rotation of the profile [deg]")
    mass: float = Field(..., gt=0, allow_inf_nan=False, description="[kg]")
    inertia: float | None = Field(None, gt=0, allow_inf_nan=False, description="[kg m^2]")
    velocity: tuple[Real, Real, Real] = Field((0.0, 0.0, 0.0), description="[m/s, rad/s]")
    friction: float = Field(0.5, ge=0, allow_inf_nan=False, description="Coulomb mu [-]")


class SceneSpec(StrictModel):
    """A named verification scene of :mod:`planner.sim` with its controller preset.

    ``params`` are keyword arguments of the preset's scene builder, in its units; each must
    be finite and > 0 (``friction`` >= 0). A value out of range or not finite is reported at
    its own key, all of them at once."""

    preset: Literal["pinch", "palm_roll", "hold_slide", "ridge_3gm"]
    params: dict[str, Any] = Field(default_factory=dict)

    @field_validator("params")
    @classmethod
    def _params(cls, params, info):
        preset = info.data.get("preset")
        if preset is None:  # an unknown preset is reported at its own key
            return params
        model = _params_model(preset)
        names = sorted(model.model_fields)
        bad = sorted(set(params) - set(names))
        if bad:
            raise ValueError(
                f"params: unknown {'parameter' if len(bad) == 1 else 'parameters'} "
                f"{', '.join(bad)} of the {preset} scene; valid: {', '.join(names)}"
            )
        # its errors are located at scene.params.<name>
        return model.model_validate(params).model_dump(exclude_unset=True)


#: scene builder arguments that are not scene parameters (given by other keys)
_NOT_PARAMS = frozenset({"dt", "seed", "sensors", "gravity"})


@cache
def _params_model(preset: str) -> type[BaseModel]:
    """The model of a preset's ``params``: every builder argument a finite float, > 0
    (``friction`` >= 0)."""
    import inspect

    fields: dict[str, Any] = {}
    for name in inspect.signature(_builder(preset)).parameters:
        if name not in _NOT_PARAMS:
            bound = {"ge": 0} if name == "friction" else {"gt": 0}
            fields[name] = (float, Field(0.0, allow_inf_nan=False, **bound))
    return create_model(f"{preset}_params", __config__=StrictModel.model_config, **fields)


def _taken_names(items, key: str, names: dict[str, str]) -> list[tuple[tuple, str]]:
    """``((i, "name"), message)`` of every item of ``items`` (the list at ``key``) whose name
    is in ``names`` (name -> key path of its owner; the items' names are added)."""
    errors = []
    for i, item in enumerate(items):
        if item.name in names:
            errors.append(((i, "name"), f"{item.name!r} is already the name of {names[item.name]}"))
        else:
            names[item.name] = f"{key}[{i}]"
    return errors


def _raise_at(errors: list[tuple[tuple, str]]) -> None:
    """Raise every ``(location, message)`` at once, each at its location inside the field
    being validated (a list item's key: ``bodies[0].name``), not at the field."""
    if errors:
        from pydantic_core import InitErrorDetails, PydanticCustomError, ValidationError

        details = [
            InitErrorDetails(
                type=PydanticCustomError("value_error", "{message}", {"message": msg}),
                loc=loc,
                input=None,
            )
            for loc, msg in errors
        ]
        raise ValidationError.from_exception_data("contact_sim", details)


def _builder(preset: str):
    if preset == "ridge_3gm":
        from planner.sim.spatial.scenes import ridge_slide_scene

        return ridge_slide_scene
    from planner.sim.planar import scenes

    return {
        "pinch": scenes.pinch_scene,
        "palm_roll": scenes.palm_roll_scene,
        "hold_slide": scenes.palm_hold_slide_scene,
    }[preset]


class Config(ScenarioBase):
    """A contact-simulator scene: a custom planar world or a named scene."""

    kind: Literal["contact_sim"]
    dt: float = Field(1e-3, gt=0, le=0.1, allow_inf_nan=False, description="time step [s]")
    duration: float | None = Field(None, gt=0, allow_inf_nan=False, description="[s]")
    scene: SceneSpec | None = None
    gravity: tuple[Real, ...] | None = Field(
        None,
        validate_default=True,
        description="[m/s^2]: (gx, gy) planar (default (0, -9.81)); ridge_3gm: (gx, gy, gz)",
    )
    fixed: list[FixedSpec] = Field(default_factory=list)
    bodies: list[BodySpec] = Field(default_factory=list)

    @field_validator("gravity")
    @classmethod
    def _gravity_of_the_world(cls, gravity, info):
        """The gravity the run uses, so that the saved scenario records it: (gx, gy) for a
        custom world and the planar scenes, (gx, gy, gz) for the spatial ``ridge_3gm``; the
        default when not given."""
        if "scene" not in info.data:  # the scene is invalid (reported): nothing to check
            return gravity
        scene = info.data["scene"]
        spatial = scene is not None and scene.preset == "ridge_3gm"
        if gravity is None:
            return (0.0, 0.0, -9.81) if spatial else (0.0, -9.81)
        n = 3 if spatial else 2
        if len(gravity) != n:
            why = ": the ridge_3gm scene is spatial, (gx, gy, gz) [m/s^2]" if spatial else ""
            raise ValueError(f"expected {n} items, got {len(gravity)}{why}")
        return gravity

    @field_validator("fixed")
    @classmethod
    def _fixed_names(cls, fixed):
        _raise_at(_taken_names(fixed, "fixed", {}))
        return fixed

    @field_validator("bodies")
    @classmethod
    def _bodies_fit(cls, bodies, info):
        """Each body's name is free, its profile closed, and no body starts in penetration:
        each problem reported at its body's key (``bodies[i].name``, ``bodies[i].profile``,
        ``bodies[i]``)."""
        fixed = info.data.get("fixed")
        if fixed is None or not bodies:
            return bodies
        names = {f.name: f"fixed[{i}]" for i, f in enumerate(fixed)}
        errors = _taken_names(bodies, "bodies", names)
        for i, b in enumerate(bodies):
            if not build_profile(b.profile).closed:
                msg = f"a free body needs a closed profile, got an open {b.profile.type!r}"
                errors.append(((i, "profile"), msg))
        _raise_at(errors)
        from planner.errors import HapexError

        try:
            world = _custom_world(fixed, bodies, info.data.get("dt") or 1e-3, (0.0, -9.81), 0)
        except HapexError as exc:
            raise ValueError(str(exc)) from None
        over = world.penetrations(1e-9)
        if over:
            a, b, gap = over[0]
            index = {body.name: i for i, body in enumerate(bodies)}
            at = max(index[n] for n in (a, b) if n in index)  # the later body of the pair
            _raise_at(
                [
                    (
                        (at,),
                        f"{len(over)} {'pair starts' if len(over) == 1 else 'pairs start'} in "
                        f"penetration, {'' if len(over) == 1 else 'the deepest '}{a!r} and "
                        f"{b!r} overlapping by {-gap:.3g} m; move the bodies apart",
                    )
                ]
            )
        return bodies

    @model_validator(mode="after")
    def _one_world(self):
        if self.scene is not None and (self.fixed or self.bodies):
            raise ValueError("scene: give either a scene or fixed/bodies, not both")
        if self.scene is None and not self.bodies:
            raise ValueError("give a scene, or at least one body")
        if self.scene is None and self.duration is None:
            raise ValueError("duration is required for a custom world")
        return self


def _custom_world(fixed, bodies, dt, gravity, seed):
    from planner.sim import PlanarWorld

    world = PlanarWorld(dt=dt, gravity=gravity, seed=seed)
    for f in fixed:
        pose = (*f.position, np.deg2rad(f.angle_deg))
        world.add_fixed(build_profile(f.profile), pose, f.friction, f.name)
    for b in bodies:
        world.add_body(
            build_profile(b.profile),
            (*b.position, np.deg2rad(b.angle_deg)),
            b.mass,
            b.inertia,
            b.velocity,
            b.friction,
            b.name,
        )
    return world


def _build(cfg: Config, quick: bool):
    """(world, controller, duration, extra) of the configured scene."""
    if cfg.scene is None:
        world = _custom_world(cfg.fixed, cfg.bodies, cfg.dt, cfg.gravity, cfg.seed)
        return world, None, cfg.duration, None
    params = dict(cfg.scene.params)
    fn = _builder(cfg.scene.preset)
    if cfg.scene.preset == "ridge_3gm":
        if quick:
            params["travel"] = min(params.get("travel", 0.03), 0.004)
        sc = fn(dt=cfg.dt, seed=cfg.seed, gravity=cfg.gravity, **params)
        return sc.world, sc.controller, cfg.duration or sc.duration, sc
    world, ctrl, info = fn(dt=cfg.dt, seed=cfg.seed, gravity=cfg.gravity, **params)
    T = cfg.duration or info.get("revolution_time", 2.0)
    return world, ctrl, T, info


def _rotation_rad(p0: np.ndarray, p1: np.ndarray) -> float | list[float]:
    """The rotation from pose ``p0`` to ``p1``: planar (x, y, angle) poses: the signed angle
    turned [rad] (every turn counted: the logged angle is continuous); spatial poses (7,):
    the angle of the relative rotation of their wxyz quaternions, in [0, pi] [rad]."""
    if len(p0) == 3:
        return float(p1[2] - p0[2])
    return float(2.0 * np.arccos(min(1.0, abs(float(np.dot(p0[3:], p1[3:]))))))


def _split(x: np.ndarray, d: int) -> tuple[list[float], float | list[float]]:
    """A velocity-like row as its linear part (d,) and its angular part (a float in the
    plane, d = 2; a (3,) list in space, d = 3)."""
    return x[:d].tolist(), (float(x[d]) if d == 2 else x[d:].tolist())


def _metrics(world, log) -> dict[str, Any]:
    """Run metrics; the unit ends every key's name (m, rad, m_s, rad_s2 ...). Per body:
    the displacement of its frame origin [m] and its rotation [rad], the final and the mean
    accelerations, linear and angular, each under its own key."""
    T = float(log.t[-1]) if len(log.t) > 1 else 0.0
    out: dict[str, Any] = {"duration_s": T, "steps": len(log.t) - 1}
    for name, p in log.poses.items():
        v = log.velocities[name]
        d = 2 if p.shape[1] == 3 else 3  # planar (x, y, angle) / spatial (xyz, wxyz)
        out[f"{name}.displacement_m"] = (p[-1, :d] - p[0, :d]).tolist()
        out[f"{name}.rotation_rad"] = _rotation_rad(p[0], p[-1])
        lin, ang = _split(v[-1], d)
        out[f"{name}.final_velocity_m_s"] = lin
        out[f"{name}.final_angular_velocity_rad_s"] = ang
        if T > 0:
            lin, ang = _split((v[-1] - v[0]) / T, d)
            out[f"{name}.mean_acceleration_m_s2"] = lin
            out[f"{name}.mean_angular_acceleration_rad_s2"] = ang
    gaps = log.gap[np.isfinite(log.gap)]
    out["max_penetration_m"] = max(0.0, -float(gaps.min())) if gaps.size else 0.0
    if hasattr(world, "logged_overlap"):  # planar: what the steps left (the gap is measured
        # after the next step's projection removed it; stepper.py, Limits)
        out["max_penetration_m"] = max(
            out["max_penetration_m"], float(world.logged_overlap(log).max(initial=0.0))
        )
    slips = {}
    for k, pair in enumerate(log.pairs):
        s = log.slip_velocity[log.contact_pair == k]
        speed = np.abs(s) if s.ndim == 1 else np.linalg.norm(s, axis=-1)
        slips[pair] = float(speed.sum() * world.dt)
    out["integrated_slip_m"] = slips
    out["max_normal_force_n"] = float(log.normal_force.max()) if log.normal_force.size else 0.0
    return out


def run(cfg: Config, ctx) -> RunResult:
    with ctx.timer("build"):
        world, ctrl, T, extra = _build(cfg, ctx.quick)
    if ctx.quick:
        T = min(T, 0.25 if cfg.scene is None or cfg.scene.preset != "ridge_3gm" else T)
    with ctx.timer("simulate"):
        log = world.run(T, ctrl)
    metrics = _metrics(world, log)
    if cfg.scene is not None and cfg.scene.preset == "ridge_3gm":
        from planner.sim.spatial.scenes import centre_path_error

        pe = centre_path_error(extra, log)
        metrics.update(path_rms_m=pe.rms, path_max_m=pe.max, lost_contact_steps=pe.lost_steps)
    events = [Event(e.kind, e.message, float(e.t), dict(e.data)) for e in log.events]
    figures = {}
    if ctx.plots:
        from planner.kinds._contact_sim_plots import figures as make_figures

        figures = make_figures(cfg.name, log)
    arrays = {k.replace("/", "__"): v for k, v in log.arrays().items()}
    return RunResult(
        status="ok" if log.status == "ok" else "failed",
        reason=log.reason if log.status != "ok" else "",
        metrics=metrics,
        arrays=arrays,
        events=events,
        figures=figures,
    )
