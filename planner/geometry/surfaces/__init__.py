"""Parametric surfaces, their Gauss frames and forms, and offset surfaces (thesis App. A.1,
§3.2.1).

``sphere(radius)``, ``bump(a)``, ``plane()`` and the other catalogue constructors return a
:class:`ParametricSurface`; :func:`height_field` builds a surface from sampled heights.
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
from planner.geometry.surfaces.parametric import (
    ParametricSurface,
    SurfaceGeometry,
    principal_from_k,
)

__all__ = [
    "CATALOGUE",
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
