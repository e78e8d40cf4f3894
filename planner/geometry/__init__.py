"""Geometry of objects and fingertips (thesis §3.2).

Modules: ``shapes`` (the catalogue of 2-D profiles), ``profiles`` (the :class:`Profile`
type), ``curves`` (parallel, traced and estimated curves of a fingertip on a profile),
``envelope``/``offset_removal`` (their construction), ``primitives`` (lines, arcs,
parametric pieces), ``measurement`` (simulated fingertip traces), ``features`` and
``feature_maps`` (curvature and macro features, Definition 1, Table 3.1), ``surfaces``
(parametric surfaces, height fields, offset surfaces), ``surface_analysis`` (feature slices
and maps of a surface) and ``plots`` (figures of profiles and surfaces: the package's one
plotting module).

The names below are re-exported lazily (on first use), so importing one submodule does not
load the others (``curves`` pulls in scipy and shapely; ``surfaces`` pulls in CasADi).
"""

from importlib import import_module
from typing import TYPE_CHECKING

_LAZY = {
    "Profile": "profiles",
    "CurveSamples": "profiles",
    "EstimatedCurve": "curves",
    "ParallelCurve": "curves",
    "TracedCurve": "curves",
    "arclength": "curves",
    "distance_to_profile": "curves",
    "estimated_curve": "curves",
    "parallel_curve": "curves",
    "resample_equal_arclength": "curves",
    "traced_curve": "curves",
    "bump": "shapes",
    "circle": "shapes",
    "cusp": "shapes",
    "ellipse": "shapes",
    "pit": "shapes",
    "plane": "shapes",
    "polygon": "shapes",
    "polyline": "shapes",
    "ravine": "shapes",
    "ridge": "shapes",
    "rounded_rectangle": "shapes",
    "spline": "shapes",
    "step": "shapes",
    "wire_on_plane": "shapes",
    "MapAnalysis": "surface_analysis",
    "SliceAnalysis": "surface_analysis",
    "map_analysis": "surface_analysis",
    "slice_analysis": "surface_analysis",
}


def __getattr__(name: str):
    """Import the defining submodule on first use of a re-exported name."""
    if name in _LAZY:
        value = getattr(import_module(f"planner.geometry.{_LAZY[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'planner.geometry' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(__all__)


if TYPE_CHECKING:  # pragma: no cover
    from planner.geometry.curves import (
        EstimatedCurve,
        ParallelCurve,
        TracedCurve,
        arclength,
        distance_to_profile,
        estimated_curve,
        parallel_curve,
        resample_equal_arclength,
        traced_curve,
    )
    from planner.geometry.profiles import CurveSamples, Profile
    from planner.geometry.shapes import (
        bump,
        circle,
        cusp,
        ellipse,
        pit,
        plane,
        polygon,
        polyline,
        ravine,
        ridge,
        rounded_rectangle,
        spline,
        step,
        wire_on_plane,
    )
    from planner.geometry.surface_analysis import (
        MapAnalysis,
        SliceAnalysis,
        map_analysis,
        slice_analysis,
    )

__all__ = [
    "CurveSamples",
    "EstimatedCurve",
    "MapAnalysis",
    "ParallelCurve",
    "Profile",
    "SliceAnalysis",
    "TracedCurve",
    "arclength",
    "bump",
    "circle",
    "cusp",
    "distance_to_profile",
    "ellipse",
    "estimated_curve",
    "map_analysis",
    "parallel_curve",
    "pit",
    "plane",
    "polygon",
    "polyline",
    "ravine",
    "resample_equal_arclength",
    "ridge",
    "rounded_rectangle",
    "slice_analysis",
    "spline",
    "step",
    "traced_curve",
    "wire_on_plane",
]
