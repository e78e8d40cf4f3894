"""``to_mjcf(world) -> str``: the same world as a MuJoCo model (issue 15, item 7), and
``mujoco_model(world, settings)``: that model loaded in MuJoCo at its default or best settings.

Dispatches on the world's type: :class:`PlanarWorld` to
:func:`planner.sim.planar.mjcf.planar_to_mjcf`, :class:`SpatialWorld` to
:func:`planner.sim.spatial.mjcf.spatial_to_mjcf` (engineer B2's).
"""

from __future__ import annotations

from planner.errors import InvalidParameter

__all__ = ["MUJOCO_SETTINGS", "mujoco_model", "to_mjcf"]

#: MuJoCo settings of the cross-checks: the exported model as is, and the best we found
#: (elliptic cone, impratio 100, 20 noslip iterations, contact time constant 2 dt)
MUJOCO_SETTINGS = {
    "default": "as exported (elliptic cone, default solref)",
    "best": "elliptic, impratio=100, noslip=20, solref 2dt",
}


def to_mjcf(world, **options) -> str:
    """The MJCF (XML text) of ``world``; ``options`` go to the world-specific exporter."""
    from planner.sim.planar.world import PlanarWorld

    if isinstance(world, PlanarWorld):
        from planner.sim.planar.mjcf import planar_to_mjcf

        return planar_to_mjcf(world, **options)
    try:
        from planner.sim.spatial.world import SpatialWorld
    except ImportError:  # pragma: no cover - the spatial world is optional here
        SpatialWorld = ()  # noqa: N806
    if SpatialWorld and isinstance(world, SpatialWorld):
        from planner.sim.spatial.mjcf import spatial_to_mjcf

        return spatial_to_mjcf(world, **options)
    raise InvalidParameter(
        f"world: expected a PlanarWorld or a SpatialWorld, got {type(world).__name__}"
    )


def mujoco_model(world, settings: str = "default"):
    """``world`` in MuJoCo: ``(mujoco, MjModel, MjData)`` reset to the world's keyframe.

    Args:
        world: a :class:`PlanarWorld` or :class:`SpatialWorld` (exported by :func:`to_mjcf`).
        settings: a key of :data:`MUJOCO_SETTINGS`.

    Raises:
        InvalidParameter: unknown settings. ImportError: MuJoCo is not installed
            (the ``[peers]`` extra).
    """
    if settings not in MUJOCO_SETTINGS:
        raise InvalidParameter(f"settings: {settings!r}; choices: {sorted(MUJOCO_SETTINGS)}")
    import mujoco

    m = mujoco.MjModel.from_xml_string(to_mjcf(world))
    if settings == "best":
        m.opt.cone = mujoco.mjtCone.mjCONE_ELLIPTIC
        m.opt.impratio = 100.0
        m.opt.noslip_iterations = 20
        m.geom_solref[:, 0] = 2 * world.dt
    d = mujoco.MjData(m)
    mujoco.mj_resetDataKeyframe(m, d, 0)
    return mujoco, m, d
