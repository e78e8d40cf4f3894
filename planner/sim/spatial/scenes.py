"""Ready-made spatial scenes: the 3GM fingertip sliding over a ridge, a ball on an incline.

:func:`ridge_slide_scene` builds the benchmark scene of issue 15: the 3GM's 8 mm fingertip
pressed with 0.3 N on a plate carrying a 1 mm ridge and dragged across it at 10 mm/s
(μ = 0.3), with :class:`TipForceVelocityController`
(:mod:`planner.sim.spatial.tip_controller`: open-loop normal force along the OWTS normal,
PD on the tangential position, gravity compensation). :func:`centre_path_error` measures the logged
tip-centre path against the exact offset surface, computed independently of the simulator's
Newton iteration (bounded scalar minimization over the ridge's cross-section).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from planner.sim.spatial.plate import Plate, PlateFeature
from planner.sim.spatial.tip_controller import TipForceVelocityController
from planner.sim.spatial.world import SpatialWorld

__all__ = [
    "PathError",
    "RidgeScene",
    "TipForceVelocityController",
    "centre_path_error",
    "path_error",
    "ridge_slide_scene",
]


@dataclass(frozen=True)
class RidgeScene:
    """What :func:`ridge_slide_scene` built.

    Attributes:
        world: the :class:`SpatialWorld`; controller: the tip controller.
        plate: the :class:`Plate` (in the WCS, identity pose); ridge: its feature.
        finger, surface: handles; duration: suggested run time [s] (ridge fully crossed).
        tip_radius [m]; friction [-]; normal_force [N]; speed [m/s].
    """

    world: SpatialWorld
    controller: TipForceVelocityController
    plate: Plate
    ridge: PlateFeature
    finger: str
    surface: str
    duration: float
    tip_radius: float
    friction: float
    normal_force: float
    speed: float


def ridge_slide_scene(
    normal_force: float = 0.3,
    speed: float = 0.01,
    ridge_height: float = 1e-3,
    ridge_width: float = 3e-3,
    friction: float = 0.3,
    tip_radius: float = 0.008,
    dt: float = 1e-3,
    seed: int = 0,
    travel: float = 0.03,
    sensors=None,
    gravity=(0.0, 0.0, -9.81),
    kind: str = "ridge",
    all_contacts: bool = False,
) -> RidgeScene:
    """The 3GM fingertip sliding across a Gaussian ridge (issue 15's benchmark scene).

    The plate ``z = z_p`` lies so that the tip touches it at the workspace centre; the ridge
    (``height`` [m], Gaussian ``width`` [m], running along ``y``) sits ``travel/2`` ahead of the
    start along ``+x``; the tip slides at ``speed`` [m/s] for ``travel`` [m]. ``gravity``: (3,)
    in the WCS [m/s²] (the controller compensates the finger's weight under it). ``kind``:
    ``"ridge"``, or ``"ravine"`` for the same profile sunk into the plate (a tip wider than
    the ravine bridges it on both rims: ``all_contacts`` True, see :class:`SpatialWorld`).

    Returns:
        a :class:`RidgeScene` (``scene.world.run(scene.duration, scene.controller)``).
    """
    from robots.three_gm import ThreeGM

    checks.positive("speed", speed, "m/s")
    checks.positive("travel", travel, "m")
    gm = ThreeGM()
    centre = gm.workspace_center
    start = centre - np.array([travel / 2, 0.0, 0.0])
    theta = gm.inverse_kinematics(start)
    if kind not in ("ridge", "ravine"):
        raise InvalidParameter(f"kind: expected 'ridge' or 'ravine', got {checks.shown(kind)}")
    ridge = PlateFeature(kind, ridge_height, ridge_width, position=(float(centre[0]), 0.0))
    xs = np.linspace(start[0] - tip_radius, start[0] + tip_radius, 201)
    bump = float(np.max(Plate((ridge,)).height(xs, 0.0)))  # highest point under the tip
    z_plate = float(start[2]) - tip_radius - bump - 1e-4  # the tip starts 0.1 mm above
    plate = Plate((ridge,), base=z_plate, name="ridge_plate")
    world = SpatialWorld(
        dt=dt, gravity=gravity, seed=seed, sensors=sensors, all_contacts=all_contacts
    )
    surface = world.add_surface(plate, friction=friction, name="plate")
    finger = world.add_finger(gm, theta, tip_radius=tip_radius)
    ctrl = TipForceVelocityController(
        gm, start, (speed, 0.0, 0.0), normal_force, gravity=tuple(world.gravity)
    )
    return RidgeScene(
        world,
        ctrl,
        plate,
        ridge,
        finger,
        surface,
        travel / speed,
        tip_radius,
        friction,
        normal_force,
        speed,
    )


@dataclass(frozen=True)
class PathError:
    """Centre path against the exact offset surface (over the steps in contact).

    Attributes:
        rms, max: distance error of the tip centre from the offset surface [m].
        lost_steps: steps without contact force after the first contact.
        steps: steps evaluated; errors: (steps,) signed errors [m] (> 0: above).
    """

    rms: float
    max: float
    lost_steps: int
    steps: int
    errors: np.ndarray


def _profile_distance(plate: Plate, c: np.ndarray, r: float) -> float:
    """Distance of ``c`` from the plate surface, by bounded scalar minimization in the
    cross-section ``y = c_y`` (independent of the simulator's Newton; straight features
    along ``y`` only)."""
    from scipy.optimize import minimize_scalar

    def d2(x):
        return (x - c[0]) ** 2 + (plate.height_derivatives(x, c[1])[0] - c[2]) ** 2

    res = minimize_scalar(
        d2, bounds=(c[0] - 1.2 * r, c[0] + 1.2 * r), method="bounded", options={"xatol": 1e-13}
    )
    return math.sqrt(res.fun)


def centre_path_error(scene: RidgeScene, log) -> PathError:
    """:class:`PathError` of a run of ``scene`` (``log`` from ``scene.world.run``)."""
    active = (log.normal_force > 0).any(axis=1)
    return path_error(scene, log.poses[scene.finger][:, :3], active)


def path_error(scene: RidgeScene, centres: np.ndarray, active: np.ndarray) -> PathError:
    """:class:`PathError` of tip ``centres`` (T, 3) [m] with ``active`` (T,) flags (the tip
    carried a contact force at that row); for any engine (see
    :func:`planner.sim.spatial.mujoco_peer.mujoco_ridge_rollout`)."""
    first = int(np.argmax(active)) if active.any() else len(active)
    rows = np.arange(first, len(active))
    errs = np.array(
        [
            _profile_distance(scene.plate, centres[k], scene.tip_radius) - scene.tip_radius
            for k in rows
        ]
    )
    lost = int((~active[rows]).sum())
    ok = active[rows]
    e = errs[ok] if ok.any() else np.zeros(1)
    return PathError(float(np.sqrt(np.mean(e**2))), float(np.max(np.abs(e))), lost, len(rows), errs)
