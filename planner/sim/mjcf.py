"""``to_mjcf(world) -> str``: the same world as a MuJoCo model (issue 15, item 7).

Dispatches on the world's type: :class:`PlanarWorld` to
:func:`planner.sim.planar.mjcf.planar_to_mjcf`, :class:`SpatialWorld` to
:func:`planner.sim.spatial.mjcf.spatial_to_mjcf` (engineer B2's).
"""

from __future__ import annotations

from planner.errors import InvalidParameter

__all__ = ["to_mjcf"]


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
