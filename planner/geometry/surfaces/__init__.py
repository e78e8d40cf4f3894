"""Parametric surfaces, their Gauss frames and forms, and offset surfaces (thesis App. A.1,
§3.2.1).

``sphere(radius)``, ``bump(a)``, ``plane()`` and the other catalogue constructors return a
:class:`ParametricSurface`; :class:`HeightField` builds a surface from sampled heights and
:func:`offset_surfaces` its traced and estimated surfaces.
"""

from planner.geometry.surfaces.catalogue import (
    CATALOGUE,
    bump,
    cusp,
    cylinder,
    pit,
    plane,
    ravine,
    ridge,
    sphere,
    step,
    swept_profile,
    wire_on_plane,
)
from planner.geometry.surfaces.height_field import (
    HeightField,
    grid_principal_curvatures,
    monge_principal_curvatures,
)
from planner.geometry.surfaces.offsets import OffsetSurfaces, offset_surfaces
from planner.geometry.surfaces.parametric import (
    ParametricSurface,
    SurfaceGeometry,
    principal_from_k,
)

__all__ = [
    "CATALOGUE",
    "HeightField",
    "OffsetSurfaces",
    "grid_principal_curvatures",
    "monge_principal_curvatures",
    "offset_surfaces",
    "ParametricSurface",
    "SurfaceGeometry",
    "bump",
    "cusp",
    "cylinder",
    "pit",
    "plane",
    "principal_from_k",
    "ravine",
    "ridge",
    "sphere",
    "step",
    "swept_profile",
    "wire_on_plane",
]
