"""Parallel, traced and estimated curves of a circular fingertip on a 2-D profile (§3.2.1).

* **parallel curve** (eq. 3.10 in the plane): every profile point moved by r_f along its
  outward normal; it has *caustic points* where the profile curvature crosses -1/r_f.
* **traced curve**: the path of the fingertip centre, the envelope of circles of radius r_f
  centred on the profile = the parallel curve less every point closer than r_f to the
  profile, with fans of radius r_f around convex corners. Where the parallel curve is cut the
  traced curve has a corner: an **interference point** (Fig. 3.3).
* **estimated curve** (eq. 3.11): the negative traced curve of the traced curve,
  s_e = s_t - r_f z_t. Around each interference point it is an arc of radius r_f about that
  point — the **unobservable region** of the profile (Fig. 3.4).

Closed forms used as tests: a step of height h >= r climbed from the left at x0 has its
interference point at (x0 - r, r); for h < r at (x0 - sqrt(r² - (r - h)²), r). A wire of
radius a on a plane gives two, at ±2 sqrt(r a) along the plane from its contact point, at
height r above the plane.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from planner.geometry.envelope import offset_envelope, polyline_normals
from planner.geometry.offset_removal import polyline_distance
from planner.geometry.profiles import CurveSamples, Profile

MAX_SAMPLES = 2_000_000


@dataclass(frozen=True)
class ParallelCurve:
    """The parallel curve of a profile at a given offset.

    Attributes:
        points: (N, 2) offset points [m] (fans at corners included).
        normals: (N, 2) outward normals of the profile samples.
        caustic_points: (K, 2) where the profile curvature crosses -1/offset [m].
        offset: the offset distance [m].
    """

    points: np.ndarray
    normals: np.ndarray
    caustic_points: np.ndarray
    offset: float


@dataclass(frozen=True)
class TracedCurve:
    """The path of the fingertip centre over a profile.

    Attributes:
        points: (N, 2) fingertip-centre positions [m], in order, interference points included.
        normals: (N, 2) outward unit normals (the profile normal at the contact; the bisector
            at an interference point).
        s: (N,) arclength along the traced curve [m].
        contacts: (N, 2) the contact point on the profile for each centre [m] (at an
            interference point: the nearest of the two contacts is not unique; the point
            ``points - tip_radius * normals`` is given).
        interference_points: (K, 2) corners of the traced curve [m].
        interference_index: (K,) their indices in ``points``.
        tip_radius: the fingertip radius r_f [m].
        unobservable_length: profile arclength the fingertip never touches [m].
        closed: whether the curve is closed.
    """

    points: np.ndarray
    normals: np.ndarray
    s: np.ndarray
    contacts: np.ndarray
    interference_points: np.ndarray
    interference_index: np.ndarray
    tip_radius: float
    unobservable_length: float
    closed: bool = False


@dataclass(frozen=True)
class EstimatedCurve:
    """The object surface estimated from a traced curve (eq. 3.11).

    Attributes:
        points: (N, 2) estimated surface points [m].
        normals: (N, 2) outward unit normals.
        s: (N,) arclength along the estimated curve [m].
        unobservable: (N,) True on the arcs of radius r_f around interference points, where
            the fingertip never touched the object.
        tip_radius: r_f [m].
        source: (N,) index of the fingertip centre (in the input given to
            :func:`estimated_curve`) each point was generated from; -1 for the corners
            inserted where two branches cross.
    """

    points: np.ndarray
    normals: np.ndarray
    s: np.ndarray
    unobservable: np.ndarray
    tip_radius: float
    source: np.ndarray

    @property
    def unobservable_length(self) -> float:
        """Arclength of the estimated curve inside unobservable regions [m]."""
        ds = np.diff(self.s)
        return float(np.sum(ds[self.unobservable[1:] & self.unobservable[:-1]]))


def arclength(points: np.ndarray) -> np.ndarray:
    """Cumulative arclength (N,) [m] of a polyline (N, 2) starting at 0."""
    P = np.asarray(points, float)
    if len(P) == 0:
        return np.zeros(0)
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P, axis=0), axis=1))])


def _default_spacing(profile: Profile, tip_radius: float, spacing: float | None) -> float:
    if spacing is None:
        spacing = min(tip_radius / 100.0, profile.length / 400.0)
    spacing = checks.positive("spacing", spacing, "m")
    if profile.length / spacing > MAX_SAMPLES:
        raise InvalidParameter(
            f"spacing: expected at least length / {MAX_SAMPLES} = "
            f"{profile.length / MAX_SAMPLES:g} [m] (at most {MAX_SAMPLES} samples on a "
            f"profile {profile.length:g} m long), got {spacing!r}"
        )
    return float(spacing)


def parallel_curve(profile: Profile, offset: float, spacing: float | None = None) -> ParallelCurve:
    """The parallel curve at ``offset`` [m] (eq. 3.10), with its caustic points.

    Args:
        profile: the object profile.
        offset: normal offset [m] (> 0 outward, the fingertip side).
        spacing: sampling of the profile [m] (default min(offset/100, length/400)).
    """
    offset = checks.in_range("offset", offset, -np.inf, np.inf, "m", closed=(False, False))
    if offset == 0:
        raise InvalidParameter("offset: expected a non-zero finite number [m], got 0")
    smp = profile.sample(_default_spacing(profile, abs(offset), spacing), fan_radius=abs(offset))
    Q = smp.points + offset * smp.normals
    # caustics: 1 + offset * k changes sign (k crosses -1/offset)
    g = 1.0 + offset * np.where(
        np.isinf(smp.curvature), np.sign(smp.curvature) * 1e300, smp.curvature
    )
    sign = np.sign(g)
    idx = np.flatnonzero(sign[1:] * sign[:-1] < 0)
    caustics = []
    for i in idx:
        if np.isinf(smp.curvature[i]) or np.isinf(smp.curvature[i + 1]):
            j = i + 1 if np.isinf(smp.curvature[i + 1]) else i
            caustics.append(Q[j])
        else:
            w = g[i] / (g[i] - g[i + 1])
            caustics.append((1 - w) * Q[i] + w * Q[i + 1])
    return ParallelCurve(Q, smp.normals, np.array(caustics).reshape(-1, 2), float(offset))


def traced_curve(profile: Profile, tip_radius: float, spacing: float | None = None) -> TracedCurve:
    """The path of the centre of a fingertip of radius ``tip_radius`` [m] over ``profile``.

    The envelope of circles centred on the profile (§3.2.1, §3.4.1), built as the parallel
    curve less its points closer than r_f to the profile; interference points at the
    crossing of the parallel curve's branches.

    Args:
        profile: the object profile (:mod:`planner.geometry.shapes`).
        tip_radius: fingertip radius r_f [m].
        spacing: profile sampling [m] (default min(r_f/100, length/400)).

    Returns:
        :class:`TracedCurve`.
    """
    r = checks.positive("tip_radius", tip_radius, "m")
    if not isinstance(profile, Profile):
        raise InvalidParameter(
            f"profile: expected a planner.geometry.profiles.Profile, got {type(profile).__name__}"
        )
    smp = profile.sample(_default_spacing(profile, r, spacing), fan_radius=r)
    # concave corners: their fans, and the two samples that meet there, never touch
    concave = np.isneginf(smp.curvature)
    exclude = concave.copy()
    exclude[:-1] |= concave[1:]
    exclude[1:] |= concave[:-1]
    if profile.closed:
        exclude[-1] |= concave[0]
        exclude[0] |= concave[-1]
    env = offset_envelope(smp.points, smp.normals, r, profile.closed, exclude=exclude)
    if len(env.points) == 0:
        raise InvalidParameter("the fingertip cannot touch this profile anywhere")
    unobs = _unobserved_length(smp, env.removed)
    return TracedCurve(
        env.points,
        env.normals,
        arclength(env.points),
        env.points - r * env.normals,
        env.crossings,
        env.crossing_index,
        r,
        unobs,
        profile.closed,
    )


def _unobserved_length(smp: CurveSamples, removed: np.ndarray) -> float:
    ds = np.diff(smp.s)
    weight = 0.5 * (removed[1:].astype(float) + removed[:-1])
    return float(np.sum(ds * weight))


def estimated_curve(
    traced: TracedCurve | np.ndarray,
    tip_radius: float,
    *,
    closed: bool | None = None,
    corner_angle: float = np.deg2rad(5.0),
    normals: np.ndarray | None = None,
) -> EstimatedCurve:
    """Estimate the object surface from the fingertip-centre path (eq. 3.11).

    The negative traced curve of the traced curve: every centre moved by r_f against the
    outward normal, with fans of radius r_f at the traced curve's corners, less every point
    closer than r_f to the traced curve (the envelope of r_f circles, §3.3.3).

    Args:
        traced: a :class:`TracedCurve`, or fingertip centres (N, 2) [m] in path order (the
            object on the right of travel, as for profiles). Smooth noisy data first.
        tip_radius: r_f [m].
        closed: whether the path is closed (default: the TracedCurve's, else False).
        corner_angle: vertices turning more than this [rad] are corners and get fans; the
            fans at concave corners (interference points) form the unobservable regions.
        normals: outward unit normals (N, 2) of the centres; default: from the polyline
            (segment normals, bisected at smooth vertices).

    Returns:
        :class:`EstimatedCurve`.
    """
    r = checks.positive("tip_radius", tip_radius, "m")
    if isinstance(traced, TracedCurve):
        P = traced.points
        closed = traced.closed if closed is None else closed
    else:
        P = np.asarray(traced, float)
        closed = bool(closed)
    P = checks.points("traced", P, dims=(2,), min_count=2)
    step = np.linalg.norm(np.diff(P, axis=0), axis=1)
    keep = np.concatenate([[True], step > 1e-15])
    P = P[keep]
    h = float(np.median(step[step > 1e-15])) if np.any(step > 1e-15) else r / 100
    G, Nv, vid, turn = polyline_normals(P, closed, corner_angle, min(h / r, np.deg2rad(5)))
    if normals is not None:
        Nu = np.asarray(normals, float)[keep]
        smooth = np.abs(turn) <= corner_angle
        Nv = np.where(smooth[:, None], Nu[vid], Nv)
    # fans of vertices turning right (convex kinks) lie on the inner side: never envelope
    exclude = (turn < -corner_angle) & (np.abs(turn) > corner_angle)
    env = offset_envelope(G, Nv, -r, closed, exclude=exclude)
    src = env.source
    unobs = np.zeros(len(env.points), bool)
    ok = src >= 0
    unobs[ok] = turn[src[ok]] > corner_angle
    source = np.full(len(src), -1)
    source[ok] = np.flatnonzero(keep)[vid[src[ok]]]  # generator -> vertex -> caller's index
    return EstimatedCurve(env.points, env.normals, arclength(env.points), unobs, r, source)


def resample_equal_arclength(points: np.ndarray, spacing: float) -> np.ndarray:
    """Resample a polyline (N, 2) [m] at equal arclength ``spacing`` [m] (linear
    interpolation); the first point is kept, the last sample lies within ``spacing`` of the
    end."""
    P = checks.points("points", points, min_count=2)
    spacing = checks.positive("spacing", spacing, "m")
    s = arclength(P)
    if s[-1] / spacing > MAX_SAMPLES:
        raise InvalidParameter(
            f"spacing: expected at least {s[-1] / MAX_SAMPLES:g} [m] (at most {MAX_SAMPLES} "
            f"samples on a polyline {s[-1]:g} m long), got {spacing!r}"
        )
    q = np.arange(0.0, s[-1] + 1e-12 * max(s[-1], 1.0), spacing)
    return np.stack([np.interp(q, s, P[:, j]) for j in range(P.shape[1])], axis=-1)


def distance_to_profile(
    points: np.ndarray, profile: Profile, spacing: float | None = None
) -> np.ndarray:
    """Distance (M,) [m] from points (M, 2) to a profile (sampled at ``spacing``)."""
    sp = spacing or profile.length / 20000.0
    smp = profile.sample(sp)
    return polyline_distance(np.asarray(points, float), smp.points, profile.closed)


def __getattr__(name: str):
    """The profile constructors live in :mod:`planner.geometry.shapes` (also re-exported by
    :mod:`planner.geometry`); ``curves.step`` and the like keep working for old code."""
    from planner.geometry import shapes

    if name in shapes.__all__:
        return getattr(shapes, name)
    raise AttributeError(f"module 'planner.geometry.curves' has no attribute {name!r}")


__all__ = [
    "CurveSamples",
    "EstimatedCurve",
    "ParallelCurve",
    "Profile",
    "TracedCurve",
    "arclength",
    "distance_to_profile",
    "estimated_curve",
    "parallel_curve",
    "resample_equal_arclength",
    "traced_curve",
]
