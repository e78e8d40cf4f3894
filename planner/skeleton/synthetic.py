"""Synthetic features for the ``skeleton`` scenario kind: ridges (straight, curved, sharply
turning, branching), rings, rectangles and ellipses, with their true medial axes.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.errors import InvalidParameter
from planner.skeleton import shapes as sh

SHAPES = ("straight", "curved", "sharp_turn", "branching", "ring", "rectangle", "ellipse")


@dataclass(frozen=True)
class SyntheticFeature:
    """A sampled synthetic feature.

    Attributes:
        name: feature name.
        samples: (M, 2) boundary samples (traced around) or path samples (traced along) [m].
        traced: ``"around"`` or ``"along"``.
        truth: (P, 2) dense samples of the true medial axis [m], or ``None`` when no closed
            form is at hand (sharp turns, whose ridge arms overlap near the turn).
    """

    name: str
    samples: np.ndarray
    traced: str
    truth: np.ndarray | None


def _rot(angle_deg: float) -> np.ndarray:
    a = np.deg2rad(angle_deg)
    return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])


def make_feature(
    name: str,
    shape: str,
    *,
    center=(0.0, 0.0),
    angle_deg: float = 0.0,
    length: float = 0.03,
    width: float = 0.006,
    radius: float = 0.02,
    sweep_deg: float = 120.0,
    turn_deg: float = 150.0,
    arms: int = 3,
    height: float = 0.01,
    spacing: float = 0.0005,
    noise: float = 0.0,
    traced: str = "around",
    rng: np.random.Generator | None = None,
) -> SyntheticFeature:
    """Sample a synthetic feature (all lengths [m], angles [deg]).

    Args:
        name: feature name.
        shape: one of :data:`SHAPES`.
        center: (2,) position of the feature's reference point [m].
        angle_deg: rotation of the feature [deg].
        length: ridge (arm) length [m] (straight, sharp_turn, branching) or rectangle width.
        width: ridge width [m]; also the ellipse minor diameter.
        radius: arc radius (curved) or ring mid radius [m]; ellipse semi-major axis.
        sweep_deg: arc sweep of a curved ridge [deg].
        turn_deg: heading change at the vertex of a sharp turn [deg] (180 = folds back).
        arms: number of arms of a branching ridge (>= 3).
        height: rectangle height [m].
        spacing: boundary sample spacing [m].
        noise: standard deviation of the sample noise [m].
        traced: ``"around"`` (boundary samples) or ``"along"`` (centre-line path samples,
            for the pseudo-skeleton of a cusp or step).
        rng: random generator (noise).

    Returns:
        :class:`SyntheticFeature`.
    """
    if shape not in SHAPES:
        raise InvalidParameter(f"shape: expected one of {SHAPES}, got {shape!r}")
    if traced not in ("around", "along"):
        raise InvalidParameter(f"traced: expected 'around' or 'along', got {traced!r}")
    truth: np.ndarray | None
    lines: list[np.ndarray] | None = None
    if shape == "straight":
        lines = [np.array([[-length / 2, 0.0], [length / 2, 0.0]])]
    elif shape == "curved":
        c = sh.arc_centerline(
            radius, sweep_deg, n=max(16, int(abs(sweep_deg) / 2)), start_deg=-90.0 - sweep_deg / 2
        )
        lines = [c - np.array([0.0, -radius])]
    elif shape == "sharp_turn":
        t = np.deg2rad(180.0 - turn_deg)
        lines = [np.array([[-length, 0.0], [0.0, 0.0], [-length * np.cos(t), length * np.sin(t)]])]
    elif shape == "branching":
        if arms < 3:
            raise InvalidParameter(f"arms: expected >= 3 for a branching ridge, got {arms}")
        a = np.deg2rad(np.arange(arms) * 360.0 / arms)
        lines = [np.array([[0.0, 0.0], [length * np.cos(x), length * np.sin(x)]]) for x in a]
    if lines is not None:
        geom = sh.ridge_polygon(lines if len(lines) > 1 else lines[0], width)
        truth = (
            None
            if shape == "sharp_turn"
            else np.concatenate([sh.densify(x, spacing / 4) for x in lines])
        )
        path = lines[0] if shape != "branching" else None
    elif shape == "ring":
        geom = sh.ring_polygon(radius, width)
        truth = sh.arc_centerline(radius, 360.0, n=2000)
        path = truth
    elif shape == "rectangle":
        import shapely

        geom = shapely.box(-length / 2, -height / 2, length / 2, height / 2)
        truth = sh.rectangle_medial_axis(length, height, n=2000)
        path = np.array([[-length / 2, 0.0], [length / 2, 0.0]])
    else:  # ellipse
        import shapely

        t = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
        geom = shapely.Polygon(np.column_stack([radius * np.cos(t), width / 2 * np.sin(t)]))
        truth = sh.ellipse_medial_axis(radius, width / 2, n=2000)
        path = truth
    R, c0 = _rot(angle_deg), np.asarray(center, dtype=float)
    if traced == "along":
        if path is None:
            raise InvalidParameter(
                "traced 'along' needs a single centre line; a branching "
                "ridge can only be traced around"
            )
        pts = sh.densify(path, spacing)
        if noise > 0:
            pts = pts + rng.normal(0.0, noise, pts.shape)
        truth = sh.densify(path, spacing / 4)
    else:
        pts = sh.sample_outline(geom, spacing, noise, rng)
    pts = pts @ R.T + c0
    truth = None if truth is None else truth @ R.T + c0
    return SyntheticFeature(name, pts, traced, truth)


__all__ = ["SHAPES", "SyntheticFeature", "make_feature"]
