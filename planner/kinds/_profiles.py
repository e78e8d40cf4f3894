"""Scenario models of 2-D profiles (shared by the ``trace`` and ``detect`` kinds).

Every profile block has a ``type`` and the constructor's arguments of
:mod:`planner.geometry.shapes`; lengths in metres, angles in degrees (``*_deg`` keys).
"""

from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from pydantic import Field, model_validator

from planner.scenario import StrictModel

Pos = Annotated[float, Field(gt=0, allow_inf_nan=False)]
Len = Annotated[float, Field(gt=0, allow_inf_nan=False, description="[m]")]
Real = Annotated[float, Field(allow_inf_nan=False)]
Point = tuple[Real, Real]


class _Open(StrictModel):
    x0: Real = Field(0.0, description="feature position along x [m]")
    length: Len = Field(0.06, description="span of the profile along x [m]")


class PlaneSpec(StrictModel):
    """A straight surface inclined by ``angle_deg``."""

    type: Literal["plane"]
    angle_deg: Real = Field(0.0, ge=-89, le=89)
    length: Len = 0.06
    x0: Real = 0.0


class StepSpec(_Open):
    """A sharp step of ``height`` [m] (negative: step down)."""

    type: Literal["step"]
    height: Real = Field(..., description="[m], non-zero")

    @model_validator(mode="after")
    def _nonzero(self):
        if self.height == 0:
            raise ValueError("height must be non-zero")
        return self


class RidgeSpec(_Open):
    """A rectangular ridge with rounded top corners."""

    type: Literal["ridge"]
    width: Len
    height: Len
    corner_radius: float = Field(0.0, ge=0, description="[m]")


class RavineSpec(_Open):
    """A rectangular groove with rounded rim corners."""

    type: Literal["ravine"]
    width: Len
    depth: Len
    corner_radius: float = Field(0.0, ge=0, description="[m]")


class BumpSpec(_Open):
    """A bump (or, with ``type: pit``, a depression) of the given shape."""

    type: Literal["bump", "pit"]
    height: Len = Field(..., description="height (bump) or depth (pit) [m]")
    width: Len = Field(..., description="base width, or Gaussian sigma [m]")
    shape: Literal["arc", "parabolic", "gaussian"] = "arc"


class WireSpec(StrictModel):
    """A round wire lying on an inclined plane (Fig. 3.12)."""

    type: Literal["wire"]
    diameter: Len
    angle_deg: Real = Field(0.0, ge=-89, le=89)
    x0: Real = Field(0.0, description="contact point along the plane [m]")
    length: Len = 0.06


class CuspSpec(_Open):
    """A convex corner with interior angle ``angle_deg``."""

    type: Literal["cusp"]
    angle_deg: float = Field(..., gt=0, lt=180)


class CircleSpec(StrictModel):
    type: Literal["circle"]
    radius: Len


class EllipseSpec(StrictModel):
    type: Literal["ellipse"]
    a: Len
    b: Len


class RoundedRectangleSpec(StrictModel):
    type: Literal["rounded_rectangle"]
    width: Len
    height: Len
    corner_radius: float = Field(0.0, ge=0, description="[m]")


class PointsSpec(StrictModel):
    """A polyline (open), polygon (closed) or spline through ``points`` [m]."""

    type: Literal["polyline", "polygon", "spline"]
    points: list[Point] = Field(..., min_length=2)
    closed: bool = Field(False, description="spline only: periodic")


ProfileSpec = Annotated[
    PlaneSpec
    | StepSpec
    | RidgeSpec
    | RavineSpec
    | BumpSpec
    | WireSpec
    | CuspSpec
    | CircleSpec
    | EllipseSpec
    | RoundedRectangleSpec
    | PointsSpec,
    Field(discriminator="type"),
]


def build_profile(spec):
    """The :class:`~planner.geometry.profiles.Profile` a profile block describes."""
    from planner.geometry import shapes

    t = spec.type
    if t == "plane":
        return shapes.plane(np.deg2rad(spec.angle_deg), spec.length, spec.x0)
    if t == "step":
        return shapes.step(spec.height, spec.x0, spec.length)
    if t == "ridge":
        return shapes.ridge(spec.width, spec.height, spec.corner_radius, spec.x0, spec.length)
    if t == "ravine":
        return shapes.ravine(spec.width, spec.depth, spec.corner_radius, spec.x0, spec.length)
    if t in ("bump", "pit"):
        fn = shapes.bump if t == "bump" else shapes.pit
        return fn(spec.height, spec.width, spec.shape, spec.x0, spec.length)
    if t == "wire":
        return shapes.wire_on_plane(spec.diameter, np.deg2rad(spec.angle_deg), spec.x0, spec.length)
    if t == "cusp":
        return shapes.cusp(np.deg2rad(spec.angle_deg), spec.x0, spec.length)
    if t == "circle":
        return shapes.circle(spec.radius)
    if t == "ellipse":
        return shapes.ellipse(spec.a, spec.b)
    if t == "rounded_rectangle":
        return shapes.rounded_rectangle(spec.width, spec.height, spec.corner_radius)
    if t == "polyline":
        return shapes.polyline(spec.points)
    if t == "polygon":
        return shapes.polygon(spec.points)
    return shapes.spline(spec.points, closed=spec.closed)


__all__ = ["ProfileSpec", "build_profile"]
