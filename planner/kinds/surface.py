"""Scenario kind ``surface``: curvature maps, curvature features and macro features of a
catalogue surface or a height-field file for a fingertip radius (thesis §3.2, Figs. 3.6-3.7).

Keys (besides name/kind/description/seed/output):

- ``tip_radius`` [m]: fingertip radius r_f.
- ``surface``: the surface, a mapping with ``type`` and that type's parameters (see the
  ``*Spec`` models below; lengths in m): ``plane``; ``sphere`` (radius); ``cylinder``
  (radius); ``bump``/``pit`` (a, eq. 3.13); ``ridge``/``ravine`` (height, width,
  bend_radius); ``step`` (height, width); ``cusp`` (slope, rounding); ``wire_on_plane``
  (wire_radius, fillet_radius); ``height_field`` (file: ``.npz`` with ``x`` (nx,), ``y``
  (ny,), ``z`` (nx, ny) [m], relative to the scenario; smoothing).
- ``grid_size``: samples per axis of the curvature map (``--quick``: at most 41).
- ``slice_samples``: samples along the ``u`` slice (``--quick``: at most 201).
- ``slice_v``: the ``v`` of the slice (default: middle of the domain).
- ``multiscale_radii`` [m]: virtual fingertip radii r_i >= r_f (graph surfaces only).
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field, field_validator, model_validator

from planner.scenario import ScenarioBase, StrictModel


class PlaneSpec(StrictModel):
    """The plane z = 0 (no features)."""

    type: Literal["plane"]


class SphereSpec(StrictModel):
    """Sphere of eq. A.7."""

    type: Literal["sphere"]
    radius: float = Field(..., gt=0, description="sphere radius R [m]")


class CylinderSpec(StrictModel):
    """Circular cylinder about z."""

    type: Literal["cylinder"]
    radius: float = Field(..., gt=0, description="cylinder radius [m]")


class BumpSpec(StrictModel):
    """The bump of eqs. 3.12-3.13 (or the pit, its negation)."""

    type: Literal["bump", "pit"]
    a: float = Field(..., gt=-1, description="sharpness a of z = 1/(1 + a u^2) [1/m^2]")


class RidgeSpec(StrictModel):
    """Gaussian ridge (or ravine) swept along a line or a circular arc."""

    type: Literal["ridge", "ravine"]
    height: float = Field(1.0, gt=0, description="ridge height / ravine depth [m]")
    width: float = Field(1.0, gt=0, description="Gaussian width w of the cross-section [m]")
    bend_radius: float | None = Field(None, gt=0, description="sweep along a circle [m]")


class StepSpec(StrictModel):
    """Smoothed step z = h (1 + tanh(u/w)) / 2."""

    type: Literal["step"]
    height: float = Field(1.0, gt=0, description="step height h [m]")
    width: float = Field(0.5, gt=0, description="transition width w [m]")


class CuspSpec(StrictModel):
    """Rounded convex cusp (roof edge)."""

    type: Literal["cusp"]
    slope: float = Field(1.0, gt=0, description="flank slope (dimensionless)")
    rounding: float = Field(0.05, gt=0, description="crest rounding length [m]")


class WireSpec(StrictModel):
    """A wire lying on a plane, with filleted corners."""

    type: Literal["wire_on_plane"]
    wire_radius: float = Field(..., gt=0, description="wire radius R [m]")
    fillet_radius: float = Field(..., gt=0, description="fillet radius at the plane [m]")


class HeightFieldSpec(StrictModel):
    """Heights sampled on a regular grid, from an ``.npz`` file with ``x``, ``y``, ``z``."""

    type: Literal["height_field"]
    file: str = Field(..., min_length=1, description=".npz file, relative to the scenario")
    smoothing: float = Field(0.0, ge=0, description="spline smoothing factor s [m^2]")


SurfaceSpec = Annotated[
    PlaneSpec
    | SphereSpec
    | CylinderSpec
    | BumpSpec
    | RidgeSpec
    | StepSpec
    | CuspSpec
    | WireSpec
    | HeightFieldSpec,
    Field(discriminator="type"),
]


class Config(ScenarioBase):
    """Curvature and macro features of one surface for one fingertip."""

    kind: Literal["surface"]
    tip_radius: float = Field(..., gt=0, description="fingertip radius r_f [m]")
    surface: SurfaceSpec = Field(..., description="the surface to analyse")
    grid_size: int = Field(151, ge=16, le=2001, description="map samples per axis")
    slice_samples: int = Field(801, ge=16, le=100_001, description="samples along the slice")
    slice_v: float | None = Field(None, description="v of the u-slice (default: mid-domain)")
    multiscale_radii: tuple[Annotated[float, Field(gt=0, allow_inf_nan=False)], ...] = Field(
        (), description="virtual fingertip radii r_i >= tip_radius [m]"
    )

    @field_validator("multiscale_radii")
    @classmethod
    def _radii_at_least_tip_radius(cls, radii, info):
        rf = info.data.get("tip_radius")  # absent if tip_radius itself was invalid
        bad = [r for r in radii if rf is not None and r < rf]
        if bad:
            raise ValueError(
                f"expected radii >= tip_radius = {rf:g} m (a virtual fingertip is never "
                f"smaller than the real one), got {bad}"
            )
        return radii

    @model_validator(mode="after")
    def _buildable(self):
        """Rules of the surface constructors that a field bound cannot express."""
        if self.surface.type == "height_field":
            return self  # the file is read at run time (relative to the scenario)
        from planner.errors import HapexError

        try:
            build_surface(self.surface, base_dir=None)
        except HapexError as exc:
            raise ValueError(f"surface: {exc}") from None
        return self


def build_surface(spec, base_dir):
    """The surface object of a ``surface`` spec (height-field files resolved on base_dir)."""
    from planner.geometry import surfaces as S

    if spec.type == "height_field":
        return _load_height_field(spec, base_dir)
    params = spec.model_dump(exclude={"type"})
    return S.CATALOGUE[spec.type](**params)


def _load_height_field(spec, base_dir):
    from pathlib import Path

    import numpy as np

    from planner.errors import HapexError, InputIssue, ScenarioError
    from planner.geometry.surfaces import HeightField

    path = Path(spec.file)
    path = path if path.is_absolute() else Path(base_dir) / path
    src = str(path)
    try:
        data = np.load(path)
    except (OSError, ValueError) as exc:
        raise ScenarioError([InputIssue(src, 0, "(root)", f"cannot read .npz: {exc}")]) from None
    missing = [k for k in ("x", "y", "z") if k not in data]
    if missing:
        raise ScenarioError(
            [
                InputIssue(src, 0, k, "missing array; expected x (nx,), y (ny,), z (nx, ny) [m]")
                for k in missing
            ]
        )
    try:
        return HeightField(
            data["x"], data["y"], data["z"], smoothing=spec.smoothing, name=path.stem
        )
    except HapexError as exc:
        raise ScenarioError([InputIssue(src, 0, "z", str(exc))]) from None


def run(config: Config, ctx):
    """Analyse the surface: slice features, feature map, offsets, macro features."""
    import json

    import numpy as np

    from planner.geometry.feature_maps import multiscale_feature_maps
    from planner.geometry.surface_analysis import MAX_BALL_CELLS, map_analysis, slice_analysis
    from planner.results import RunResult

    rf = config.tip_radius
    n_map = min(config.grid_size, 41) if ctx.quick else config.grid_size
    n_slice = min(config.slice_samples, 201) if ctx.quick else config.slice_samples
    with ctx.timer("surface"):
        surface = build_surface(config.surface, ctx.base_dir)
    with ctx.timer("slice"):
        sl = slice_analysis(surface, rf, config.slice_v, n_slice)
    with ctx.timer("map"):
        ma = map_analysis(surface, rf, n_map)
    fm = ma.features
    multiscale = ()
    if config.multiscale_radii and ma.graph:
        with ctx.timer("multiscale"):
            step = max(ma.x[1] - ma.x[0], ma.y[1] - ma.y[0])
            k = max(1, int(np.ceil(rf / (MAX_BALL_CELLS * step))))  # closing uses r_f
            multiscale = multiscale_feature_maps(
                ma.x[::k], ma.y[::k], ma.height[::k, ::k], rf, config.multiscale_radii
            )
    files = {"features.json": json.dumps(_features_json(sl, fm), indent=1)}
    figures = _figures(surface, rf, sl, ma, 16 if ctx.quick else 40) if ctx.plots else {}
    return RunResult(
        metrics=_metrics(surface, sl, ma, multiscale),
        arrays=_arrays(sl, ma),
        events=_events(sl, ma),
        figures=figures,
        files=files,
    )


def _metrics(surface, sl, ma, multiscale) -> dict:
    fm = ma.features
    area = float(ma.inside.sum())
    kinds = [m.kind for m in fm.macros]
    metrics = {
        "surface": surface.name,
        "graph": ma.graph,
        "slice_features": len(sl.features),
        "slice_positive": sum(f.sign > 0 for f in sl.features),
        "slice_negative": sum(f.sign < 0 for f in sl.features),
        "slice_pattern": "".join("+" if f.sign > 0 else "-" for f in sl.features),
        "slice_macro_kinds": [m.kind for m in sl.macros],
        "map_regions": len(fm.regions),
        "map_positive": sum(r.sign > 0 for r in fm.regions),
        "map_negative": sum(r.sign < 0 for r in fm.regions),
        "macro_count": len(fm.macros),
        "macro_kinds": kinds,
        "k1_max": float(ma.k1[ma.inside].max()),
        "k1_min": float(ma.k1[ma.inside].min()),
        "caustic_fraction": float(ma.caustic.sum() / area),
        # unobservability is decided only farther than r_f from the map's border (the ball
        # would reach outside the sampled area): the fraction is over that interior, whose
        # share of the map is reported beside it (None: graph surfaces only / empty interior)
        "interior_fraction": float(ma.offsets.interior.mean()) if ma.offsets else None,
        "unobservable_fraction_of_interior": (
            ma.offsets.unobservable_fraction_of_interior if ma.offsets else None
        ),
        "interference_cells": int(ma.offsets.interference.sum()) if ma.offsets else None,
        "multiscale_regions": [len(m.regions) for m in multiscale],
        "multiscale_macro_kinds": [[x.kind for x in m.macros] for m in multiscale],
    }
    return metrics


def _events(sl, ma) -> list:
    import numpy as np

    from planner.results import Event

    fm = ma.features
    events = [
        Event(
            "slice_feature",
            f"{'+' if f.sign > 0 else '-'} feature from u = "
            f"{sl.to_u(f.start):.4g} to {sl.to_u(f.end):.4g}",
            data={
                "sign": f.sign,
                "u_start": sl.to_u(f.start),
                "u_end": sl.to_u(f.end),
                "u_peak": sl.to_u(f.peak),
                "peak_curvature": f.peak_curvature,
            },
        )
        for f in sl.features
    ]
    events += [
        Event(
            "macro_feature",
            f"{m.kind} at {np.round(m.centroid, 4).tolist()}",
            data={"kind": m.kind, "members": list(m.members), "centroid": m.centroid.tolist()},
        )
        for m in fm.macros
    ]
    return events


def _arrays(sl, ma) -> dict:
    fm = ma.features
    arrays = {
        "slice_u": sl.u,
        "slice_s": sl.s,
        "slice_k11": sl.k11,
        "slice_k22": sl.k22,
        "map_x": ma.x,
        "map_y": ma.y,
        "map_k1": ma.k1,
        "map_k2": ma.k2,
        "map_positive": fm.positive,
        "map_negative": fm.negative,
        "map_macro": fm.macro_labels,
        "map_caustic": ma.caustic,
    }
    if ma.graph:
        arrays["map_height"] = ma.height
    if ma.offsets is not None:
        arrays.update(
            offsets_x=ma.offsets.x,
            offsets_y=ma.offsets.y,
            traced=ma.offsets.traced,
            estimated=ma.offsets.estimated,
            unobservable=ma.offsets.unobservable,
            interference=ma.offsets.interference,
        )
    return arrays


def _features_json(sl, fm) -> dict:
    return {
        "tip_radius": fm.tip_radius,
        "slice": {
            "v": sl.v,
            "features": [
                {
                    "sign": f.sign,
                    "u_start": sl.to_u(f.start),
                    "u_end": sl.to_u(f.end),
                    "u_peak": sl.to_u(f.peak),
                    "s_start": f.start,
                    "s_end": f.end,
                    "peak_curvature": f.peak_curvature,
                }
                for f in sl.features
            ],
            "macros": [
                {"kind": m.kind, "pattern": m.pattern, "s_start": m.start, "s_end": m.end}
                for m in sl.macros
            ],
        },
        "map": {
            "regions": [
                {
                    "label": r.label,
                    "sign": r.sign,
                    "area": r.area,
                    "peak": r.peak.tolist(),
                    "peak_curvature": r.peak_curvature,
                    "second_curvature": r.second_curvature,
                    "centroid": r.centroid.tolist(),
                }
                for r in fm.regions
            ],
            "macros": [
                {"kind": m.kind, "members": list(m.members), "centroid": m.centroid.tolist()}
                for m in fm.macros
            ],
        },
    }


def _figures(surface, rf, sl, ma, mesh: int) -> dict:
    from planner.geometry.plots import (
        feature_map_figure,
        offsets_figure,
        slice_figure,
        surface_figure,
    )

    figs = {
        "surface": surface_figure(surface, rf, mesh),
        "k1_slice": slice_figure(sl, rf, surface.name),
        "feature_map": feature_map_figure(ma, surface.name),
    }
    off = offsets_figure(ma, surface.name)
    if off is not None:
        figs["offsets"] = off
    return figs
