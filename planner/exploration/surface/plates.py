"""Plates for the explorer: fast heights, the true outlines and skeletons, random plates.

The plate itself is the simulator's :class:`planner.sim.spatial.plate.Plate` (macro features
with closed-form cross-sections ``Z(s)``). This module adds what the explorer and its metrics
need: a vectorized height function, the **true outline** of each feature - the level line
of the traced surface (fingertip centre) a little above the plate level next to the feature
(its foot, :func:`foot_levels`), which the boundary tracer of Fig. 4.8 servoes on - and the
**true skeleton** (the crest/axis line, a point for a bump or pit), plus seeded random plates
for the benchmark.

The plate level next to a feature is the traced surface's height at the feature's *foot*,
where the surface stops being the plane of travel (§4.4.2: the finger traces "staying in the
plane of travel before the feature was encountered"): going out from the feature's flank,
the first place where the contact tilt has fallen to :data:`FOOT_TILT`. It is not the
asymptotic plate: a bump's or pit's ``h / (1 + s^2/w^2)`` tails fall off as ``1/s^2``, so
inside a 40 mm region a 4 mm pit 5 mm wide still lowers the plate by 0.24 mm at the border,
and a level line ``rise`` = 0.25 mm below the asymptotic plate lies 19 mm from its centre,
where the flank slope is 0.024 - no explorer inside the region can see that plate, and 0.01
mm of its level moves that line by 0.4 mm. At the foot the slope is known (``FOOT_TILT``),
so the level is read to a few hundredths of a millimetre by the tracer
(:func:`planner.exploration.surface.tracing.find_outline`) and by the truth alike.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter

__all__ = [
    "CLOSED_KINDS",
    "FOOT_TILT",
    "TruthFeature",
    "feature_height",
    "foot_levels",
    "plate_height",
    "random_plate",
    "truth_features",
]

#: kinds whose outline is a closed curve on an unbounded plate
CLOSED_KINDS = ("bump", "pit")
#: a feature's foot is where its traced surface's tilt (the sine of the contact normal's angle
#: to the plate normal) has fallen to this, going out from its flank [-]: 5 deg, ten times the
#: filtered OWTS normal's scatter on the bare plate at 3 deg of sensor noise (0.005) and a
#: fraction of every feature's steepest flank (a 1 mm bump 2 mm wide: 0.31)
FOOT_TILT = math.sin(math.radians(5.0))
#: the explorer's name for each simulator kind (a wire lying on a plate is a ridge, §3.4.2)
KIND_OF = {
    "ridge": "ridge",
    "ravine": "ravine",
    "step": "step",
    "bump": "bump",
    "pit": "pit",
    "wire": "ridge",
    "cusp": "cusp",
}


def _profile(f, s: np.ndarray) -> np.ndarray:
    """Vectorized ``Z(s)`` of a :class:`~planner.sim.spatial.plate.PlateFeature` [m]."""
    h, w, k = f.height, f.width, f.kind
    if k in ("ridge", "ravine"):
        return (1.0 if k == "ridge" else -1.0) * h * np.exp(-(s**2) / (2 * w * w))
    if k == "step":
        return h * (1 + np.tanh(s / w)) / 2
    if k in ("bump", "pit"):
        return (1.0 if k == "bump" else -1.0) * h / (1.0 + s**2 / (w * w))
    if k == "cusp":
        rho = f.rounding
        return -(h / w) * (np.sqrt(s**2 + rho**2) - rho)
    R, rho = h / 2, f.rounding  # wire with fillets
    xc = 2 * math.sqrt(R * rho)
    xt = R * xc / (R + rho)
    a = np.abs(s)
    top = R + np.sqrt(np.maximum(R * R - s**2, 0.0))
    fil = rho - np.sqrt(np.maximum(rho * rho - (a - xc) ** 2, 0.0))
    return np.where(a <= xt, top, np.where(a < xc, fil, 0.0))


def _polyline_distance(path, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Distance [m] from ``(u, v)`` to the polyline ``path`` ((K, 2) [m])."""
    P = np.asarray(path, float)
    if len(P) == 1:
        return np.hypot(u - P[0, 0], v - P[0, 1])
    best = np.full(np.shape(u), np.inf)
    for a, b in zip(P[:-1], P[1:], strict=True):
        e = b - a
        t = np.clip(((u - a[0]) * e[0] + (v - a[1]) * e[1]) / float(e @ e), 0.0, 1.0)
        best = np.minimum(best, np.hypot(u - a[0] - t * e[0], v - a[1] - t * e[1]))
    return best


def _across(f, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    if getattr(f, "path", None) is not None:
        return _polyline_distance(f.path, u, v)
    du, dv = u - f.position[0], v - f.position[1]
    if f.kind in ("bump", "pit"):
        return np.hypot(du, dv)
    return du * math.cos(f.across) + dv * math.sin(f.across)


def feature_height(f, u, v) -> np.ndarray:
    """Height contributed by one feature at ``(u, v)`` (plate frame) [m]."""
    u, v = np.broadcast_arrays(np.asarray(u, float), np.asarray(v, float))
    return _profile(f, _across(f, u, v))


def plate_height(plate):
    """Vectorized ``h(u, v)`` [m] of a simulator plate (plate frame)."""
    feats = tuple(plate.features)
    base = float(plate.base)

    def h(u, v):
        u, v = np.broadcast_arrays(np.asarray(u, float), np.asarray(v, float))
        out = np.full(u.shape, base)
        for f in feats:
            out = out + _profile(f, _across(f, u, v))
        return out

    return h


def _traced_profile(f, tip_radius: float, s: np.ndarray) -> np.ndarray:
    """Height [m] above the plate of the fingertip's resting centre, minus ``tip_radius``,
    over the cross-section ``s`` ((N,) evenly spaced [m]) of the feature ``f`` alone: the
    grey dilation of ``Z(s)`` by a disc of radius r_f (§3.2.1). Exact for a straight
    feature, and along a meridian of a bump or pit (the normals of a surface of revolution
    meet its axis, so the ball resting off the axis touches in its own meridian plane)."""
    z = _profile(f, np.asarray(s, float))
    ds = float(s[1] - s[0])
    k = int(tip_radius // ds)
    t = np.arange(-k, k + 1) * ds
    cap = np.sqrt(np.maximum(tip_radius**2 - t * t, 0.0)) - tip_radius
    padded = np.pad(z, k, mode="edge")
    out = np.full(len(z), -np.inf)
    for j in range(2 * k + 1):  # one offset of the disc at a time: O(N) memory
        np.maximum(out, padded[j : j + len(z)] + cap[j], out=out)
    return out


@functools.lru_cache(maxsize=256)
def foot_levels(f, tip_radius: float, tilt: float = FOOT_TILT) -> tuple[float, float]:
    """``(low, high)``: the traced surface's height above the plate [m] at the feet of the
    feature ``f`` (a :class:`~planner.sim.spatial.plate.PlateFeature`), the plate level
    next to it (module doc): on each side of its cross-section, going out from the
    steepest point of that side's flank, the first place where the traced surface's tilt
    has fallen to ``tilt`` (sine of the slope angle [-]), linearly interpolated.

    ``low`` is the side ``s < 0`` (a step's lower level), ``high`` the side ``s > 0`` (its
    upper one); for the even profiles both are the same. A cusp has no plate next to it
    (its plate falls away from the crest): ``(nan, nan)``."""
    if f.kind == "cusp":
        return math.nan, math.nan
    slope = math.tan(math.asin(tilt))
    ds = max(min(f.width, tip_radius) / 50.0, 5e-6)
    span = 8.0 * f.width + 4.0 * (f.height + f.rounding) + 2.0 * tip_radius
    for _ in range(8):  # a Lorentzian's tails fall as 1/s^2: widen until both feet are met
        n = int(span / ds)
        s = np.arange(-n, n + 1) * ds
        T = _traced_profile(f, tip_radius, s)
        g = np.abs(np.gradient(T, ds))
        feet = []
        for side in (slice(n, None, -1), slice(n, None)):  # outwards from s = 0
            gs, Ts = g[side], T[side]
            k0 = int(np.argmax(gs))
            flat = np.flatnonzero(gs[k0:] <= slope)
            if flat.size == 0:
                break
            k = k0 + int(flat[0])
            a = (gs[k - 1] - slope) / max(gs[k - 1] - gs[k], 1e-300)  # between k - 1 and k
            feet.append(float(Ts[k - 1] + a * (Ts[k] - Ts[k - 1])))
        if len(feet) == 2:
            return feet[0], feet[1]
        span *= 2.0
    raise InvalidParameter(  # pragma: no cover - every catalogue profile flattens out
        f"{f.kind}: expected a feature whose flanks flatten to a tilt of {tilt:g}, none within "
        f"{span * 1e3:.0f} mm"
    )


@dataclass(frozen=True)
class TruthFeature:
    """Ground truth of one feature inside a region.

    Attributes:
        kind: explorer kind (a wire is a ``"ridge"``).
        outline: tuple of (K, 2) polylines of the true outline in the plate frame [m].
        closed: whether the outline is a closed curve inside the region.
        skeleton: (M, 2) polyline of the true skeleton (1 row for a bump or pit) [m].
        centre: (2,) a reference point (crest point / centre) [m].
    """

    kind: str
    outline: tuple[np.ndarray, ...]
    closed: bool
    skeleton: np.ndarray
    centre: np.ndarray


def _clip_line(p: np.ndarray, d: np.ndarray, region: np.ndarray) -> np.ndarray:
    """The segment of the line ``p + t d`` inside the box ``region`` ((2, 2) [m])."""
    lo, hi = -1e9, 1e9
    for i in range(2):
        if abs(d[i]) < 1e-15:
            continue
        a, b = (region[i, 0] - p[i]) / d[i], (region[i, 1] - p[i]) / d[i]
        lo, hi = max(lo, min(a, b)), min(hi, max(a, b))
    if hi <= lo:
        return np.array([p, p])
    return np.array([p + lo * d, p + hi * d])


def truth_features(
    plate,
    region,
    tip_radius: float = 0.008,
    rise=2.5e-4,
    grid: float = 3e-4,
    foot_tilt: float | None = FOOT_TILT,
) -> list[TruthFeature]:
    """True outline and skeleton of each feature (each feature alone on the plate).

    The outline is the level line of the traced surface (the fingertip centre resting on the
    feature, grey dilation of its heights by the ball, :func:`planner.geometry.surfaces.
    offset_surfaces`) ``rise`` above the plate level next to the feature, its foot
    (:func:`foot_levels`; below it for pits and ravines): the line
    :mod:`~planner.exploration.surface.tracing` servoes on. A step has two: ``rise`` above
    its lower foot and ``rise`` below its upper one (the tracer follows the one of the side
    it starts from); a cusp's are ``rise`` below its crest, on both flanks.

    Args:
        plate: a :class:`~planner.sim.spatial.plate.Plate`.
        region: ((u0, u1), (v0, v1)) box in the plate frame [m].
        tip_radius: r_f [m].
        rise: the outline level above/below the plate level [m], one for all or one per
            feature.
        grid: sampling of the traced surface [m].
        foot_tilt: the tilt of the feet [-] (:data:`FOOT_TILT`); None: ``rise`` is measured
            from the asymptotic plate (the plate without the feature), as for a level line
            given by its height.
    """
    import contourpy

    from planner.geometry.surfaces import offset_surfaces

    reg = np.asarray(region, float)
    pad = tip_radius + 2 * grid
    u = np.arange(reg[0, 0] - pad, reg[0, 1] + pad + grid / 2, grid)
    v = np.arange(reg[1, 0] - pad, reg[1, 1] + pad + grid / 2, grid)
    U, V = np.meshgrid(u, v, indexing="ij")
    inside = (U >= reg[0, 0]) & (U <= reg[0, 1]) & (V >= reg[1, 0]) & (V <= reg[1, 1])
    out = []
    rises = np.broadcast_to(np.asarray(rise, float), (len(plate.features),))
    for f, rise in zip(plate.features, rises, strict=True):
        H = feature_height(f, U, V)
        traced = offset_surfaces(u, v, H, tip_radius).traced - tip_radius
        sunken = f.kind in ("pit", "ravine")
        low, high = (0.0, f.height)  # the asymptotic plate on either side
        if foot_tilt is not None and f.kind != "cusp":
            low, high = foot_levels(f, tip_radius, foot_tilt)
        level = low - rise if sunken else low + rise
        if f.kind == "cusp":  # the plate falls away from the crest: no plate level
            level = float(traced[inside].max()) - rise
        field = np.where(inside, traced, np.nan)
        gen = contourpy.contour_generator(V, U, field)  # x = v, y = u: returns (v, u) pairs
        lines = [ln[:, ::-1] for ln in gen.lines(level) if len(ln) > 2]
        if f.kind == "step":  # seen from the upper side: ``rise`` below the upper level
            lines += [ln[:, ::-1] for ln in gen.lines(high - rise) if len(ln) > 2]
        centre = np.array(f.position, float)
        path = getattr(f, "path", None)
        if f.kind in CLOSED_KINDS or path is not None:
            skel = centre[None].copy() if path is None else np.array(path, float)
            if path is not None:
                centre = skel.mean(axis=0)
            closed = bool(lines) and all(np.allclose(ln[0], ln[-1], atol=2 * grid) for ln in lines)
            if lines:  # the outer contour: the longest
                lines = [max(lines, key=lambda ln: float(np.sum(np.hypot(*np.diff(ln, axis=0).T))))]
        else:
            a = f.across
            axis = np.array([-math.sin(a), math.cos(a)])
            skel = _clip_line(centre, axis, reg)
            closed = False
            if len(lines) > 2 and f.kind != "step":
                lines = sorted(lines, key=lambda ln: -len(ln))[:2]
        out.append(TruthFeature(KIND_OF[f.kind], tuple(lines), closed, skel, centre))
    return out


def random_plate(
    rng: np.random.Generator, kind: str, size: float, angle: float, position=(0.0, 0.0)
):
    """A plate with one feature of ``kind`` and characteristic ``size`` [m] (height ~ size).

    Widths are chosen so that every feature is sharper than the fingertip (curvature above
    1/r_f for r_f = 8 mm) - features in the thesis' sense (Definition 1).

    Args:
        rng: generator (varies the width within its band).
        kind: explorer kind (``bump``, ``pit``, ``ridge``, ``ravine``, ``step``, ``cusp``).
        size: feature height [m], 1-5 mm in the benchmark.
        angle: direction ``across`` of the profile [rad].
        position: (2,) centre [m].
    """
    from planner.sim.spatial.plate import Plate, PlateFeature

    checks.choice("kind", kind, ("bump", "pit", "ridge", "ravine", "step", "cusp"))
    h = checks.positive("size", size, "m")
    jitter = float(rng.uniform(0.8, 1.2))
    if kind in ("bump", "pit"):
        w = (h + 1e-3) * jitter
    elif kind in ("ridge", "ravine"):
        w = 0.9 * h * jitter + 0.6e-3
    elif kind == "step":
        w = 0.5 * h * jitter
    else:
        w = 3.0 * h * jitter  # cusp: flank slope h/w = 1/3
    feat = PlateFeature(kind, h, w, tuple(float(x) for x in position), float(angle))
    return Plate((feat,), name=f"{kind}_{h * 1e3:.1f}mm")
