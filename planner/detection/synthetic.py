"""Synthetic fingertip traces over 2-D feature profiles, with exact ground truth.

Used by the benchmark, the filter study and the tests: a profile is a graph ``y = f(x)``
(material below) on a plane inclined by ``angle``; the fingertip-centre path is the upper
envelope of the circles of radius ``r_f`` centred on the profile (the traced curve of thesis
§3.2.1, interference points included), sampled at equal arclength and perturbed with
Gaussian noise. Ground-truth curvature features follow Definition 1 exactly for the shapes
here (corners are features of infinite curvature).

Shapes (``kind``; sizes in metres): ``plane``; ``wire`` (``size`` = diameter, a circular wire
lying on the plane: ``-+-``); ``step`` (``size`` = height, negative for a step down:
``-+`` or ``+-``); ``ridge`` (rectangular, ``width`` x ``size``: ``-++-``); ``ravine``
(rectangular groove, ``width`` x ``size`` deep: ``+--+``); ``pit`` (circular dent of radius
``width/2`` and depth ``size``: ``+-+``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.detection.observable import observable_truth
from planner.detection.types import CurvatureFeature
from planner.errors import InvalidParameter

SHAPES = ("plane", "wire", "step", "ridge", "ravine", "pit")
#: centre-position noise of the thesis' apparatus, 1 sigma [m] (App. B Table B.1: ~0.9-1.0e-4)
THESIS_CENTER_SIGMA = 1.0e-4
#: contact-position noise, 1 sigma [m] (§3.4.2: contact location within +-0.5 mm)
THESIS_CONTACT_SIGMA = 2.5e-4
#: contact-normal noise, 1 sigma [rad] (§3.4.2: the sensor error is about +-1 degree)
THESIS_NORMAL_SIGMA = np.deg2rad(1.0)


@dataclass(frozen=True)
class Shape:
    """A feature on an inclined plane.

    Attributes:
        kind: one of :data:`SHAPES`.
        size: diameter (wire), height (step, ridge), depth (ravine, pit) [m].
        width: width of ridge/ravine, diameter of pit [m].
        angle: inclination of the plane, counter-clockwise from the x-axis [rad].
        length: length of the plane on each side of the feature [m].
    """

    kind: str = "wire"
    size: float = 0.65e-3
    width: float = 4e-3
    angle: float = 0.0
    length: float = 0.03

    def __post_init__(self) -> None:
        if self.kind not in SHAPES:
            raise InvalidParameter(f"kind: got {self.kind!r}; expected one of {list(SHAPES)}")
        if self.kind != "step" and self.kind != "plane" and not self.size > 0:
            raise InvalidParameter(f"size: expected a positive size [m], got {self.size!r}")
        if self.kind == "pit" and not 0 < self.size <= self.width / 2:
            raise InvalidParameter(
                f"size: a pit's depth must be in (0, width/2], got "
                f"{self.size!r} with width {self.width!r}"
            )
        if not self.length > 0 or not self.width > 0:
            raise InvalidParameter("length and width must be positive [m]")

    def height(self, x: np.ndarray) -> np.ndarray:
        """Upper graph ``f(x)`` of the profile in the plane's frame [m]; (M,) -> (M,)."""
        k, h, w = self.kind, self.size, self.width
        f = np.zeros_like(x)
        if k == "wire":
            r = h / 2
            m = np.abs(x) <= r
            f[m] = r + np.sqrt(np.maximum(r * r - x[m] ** 2, 0.0))
        elif k == "step":
            f[x >= 0] = h
        elif k == "ridge":
            f[np.abs(x) <= w / 2] = h
        elif k == "ravine":
            f[np.abs(x) < w / 2] = -h
        elif k == "pit":
            rho = w / 2
            c = rho - h
            a = np.sqrt(rho**2 - c**2)
            m = np.abs(x) < a
            f[m] = c - np.sqrt(rho**2 - x[m] ** 2)
        return f

    def truth_local(self) -> list[tuple[int, float, float, float, float]]:
        """Ground-truth features as ``(sign, x_start, x_end, x_peak, y_peak)`` in the plane's
        frame [m] (Definition 1; corners have zero extent)."""
        k, h, w = self.kind, self.size, self.width
        if k == "wire":
            r = h / 2
            return [(-1, -r, -r, -r, 0.0), (1, -r, r, 0.0, h), (-1, r, r, r, 0.0)]
        if k == "step":
            if h > 0:
                return [(-1, 0, 0, 0, 0.0), (1, 0, 0, 0, h)]
            return [(1, 0, 0, 0, 0.0), (-1, 0, 0, 0, h)]
        if k == "ridge":
            a = w / 2
            return [(-1, -a, -a, -a, 0.0), (1, -a, -a, -a, h), (1, a, a, a, h), (-1, a, a, a, 0.0)]
        if k == "ravine":
            a = w / 2
            return [
                (1, -a, -a, -a, 0.0),
                (-1, -a, -a, -a, -h),
                (-1, a, a, a, -h),
                (1, a, a, a, 0.0),
            ]
        if k == "pit":
            rho = w / 2
            a = np.sqrt(rho**2 - (rho - h) ** 2)
            return [(1, -a, -a, -a, 0.0), (-1, -a, a, 0.0, -h), (1, a, a, a, 0.0)]
        return []


@dataclass(frozen=True, eq=False)
class SyntheticTrace:
    """A simulated fingertip trace and its ground truth.

    Attributes:
        t: (N,) time stamps [s].
        centers, contacts, normals: (N, 2) measured (noisy) fingertip centres [m], contact
            points [m] and outward unit contact normals.
        true_centers, true_contacts, true_normals: (N, 2) the same without noise.
        s: (N,) arclength of the true fingertip-centre path from its first sample [m].
        truth: ground-truth curvature features (``position`` on the object profile [m];
            ``start/end/peak`` are coordinates along the plane [m], or the profile's
            arclength [m] for :func:`planner.detection.profile_trace.simulate_profile`).
        observable: the ground truth as a fingertip can know it
            (:func:`planner.detection.observable.observable_truth`): same-sign features
            inside one unobservable region (a gap of the contact locus, between the two
            contacts of an interference point), or passed by the fingertip within r_f/4 of
            path length, count as one, at their mean position.
        observable_index: (K,) sample index at which the fingertip passes each observable
            feature (its contact point crosses the feature), for scoring in time.
        profile: (K, 2) dense points of the object profile [m].
        tip_radius: r_f [m].
    """

    t: np.ndarray
    centers: np.ndarray
    contacts: np.ndarray
    normals: np.ndarray
    true_centers: np.ndarray
    true_contacts: np.ndarray
    true_normals: np.ndarray
    s: np.ndarray
    truth: tuple[CurvatureFeature, ...]
    observable: tuple[CurvatureFeature, ...]
    observable_index: np.ndarray
    profile: np.ndarray
    tip_radius: float


def _rot(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s], [s, c]])


def simulate(
    shape: Shape,
    tip_radius: float,
    *,
    spacing: float = 5e-5,
    speed: float = 0.03,
    center_sigma: float = 0.0,
    contact_sigma: float = 0.0,
    normal_sigma: float = 0.0,
    rng: np.random.Generator | None = None,
    resolution: float | None = None,
) -> SyntheticTrace:
    """Simulate a fingertip tracing ``shape`` in +x (material below).

    Args:
        shape: the profile.
        tip_radius: fingertip radius r_f [m].
        spacing: arclength between samples of the centre path [m].
        speed: fingertip speed, sets the time stamps [m/s].
        center_sigma, contact_sigma: Gaussian noise per coordinate [m].
        normal_sigma: Gaussian noise of the normal direction [rad].
        rng: random generator (required when any noise is non-zero).
        resolution: grid step of the profile [m] (default ``min(spacing, r_f/50, size/50)/2``).

    Returns:
        A :class:`SyntheticTrace` with ground truth.
    """
    r = float(tip_radius)
    if not r > 0 or not spacing > 0 or not speed > 0:
        raise InvalidParameter("tip_radius, spacing and speed must be positive")
    if rng is None:
        if center_sigma or contact_sigma or normal_sigma:
            raise InvalidParameter("rng: a numpy Generator is required for noisy traces")
        rng = np.random.default_rng(0)
    feat = min(abs(shape.size), shape.width) if shape.kind != "plane" else r
    dx = resolution or min(spacing, r / 50, feat / 50) / 2
    half = shape.length + max(shape.width, abs(shape.size)) + r
    x = np.arange(-half, half + dx / 2, dx)
    f = shape.height(x)
    w = int(np.ceil(r / dx))
    xc = x[w:-w]
    best = np.full(xc.shape, -np.inf)
    arg = np.zeros(xc.shape, dtype=int)
    for j in range(-w, w + 1):
        dxj = j * dx
        if abs(dxj) > r:
            continue
        cand = f[w + j : len(x) - w + j] + np.sqrt(r * r - dxj * dxj)
        better = cand > best
        best[better] = cand[better]
        arg[better] = j
    cen = np.column_stack([xc, best])
    con = np.column_stack([x[w + np.arange(xc.size) + arg], f[w + np.arange(xc.size) + arg]])
    keep = np.abs(xc) <= shape.length + max(shape.width, abs(shape.size)) / 2
    cen, con = cen[keep], con[keep]
    s_dense = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(cen, axis=0), axis=1))])
    s = np.arange(0.0, s_dense[-1], spacing)
    idx = np.clip(np.searchsorted(s_dense, s, side="right") - 1, 0, len(s_dense) - 1)
    tc = np.column_stack([np.interp(s, s_dense, cen[:, 0]), np.interp(s, s_dense, cen[:, 1])])
    tp = con[idx]
    nv = tc - tp
    tn = nv / np.linalg.norm(nv, axis=1)[:, None]
    rot = _rot(shape.angle)
    tc, tp, tn = tc @ rot.T, tp @ rot.T, tn @ rot.T
    n = s.size
    mc = tc + center_sigma * rng.standard_normal((n, 2))
    mp = tp + contact_sigma * rng.standard_normal((n, 2))
    ang = normal_sigma * rng.standard_normal(n)
    ca, sa = np.cos(ang), np.sin(ang)
    mn = np.column_stack([ca * tn[:, 0] - sa * tn[:, 1], sa * tn[:, 0] + ca * tn[:, 1]])
    truth = tuple(
        CurvatureFeature(sign=sg, start=a, end=b, peak=pk, position=np.array([pk, yp]) @ rot.T)
        for sg, a, b, pk, yp in shape.truth_local()
    )
    observable, obs_idx = observable_truth(
        truth,
        [loc[3] for loc in shape.truth_local()],
        con[:, 0],
        (tp @ _rot(-shape.angle).T)[:, 0],
        s,
        r,
        gap=max(20 * dx, r / 100),
    )
    prof = np.column_stack([x, f]) @ rot.T
    return SyntheticTrace(
        t=s / speed,
        centers=mc,
        contacts=mp,
        normals=mn,
        true_centers=tc,
        true_contacts=tp,
        true_normals=tn,
        s=s,
        truth=truth,
        observable=observable,
        observable_index=obs_idx.astype(int),
        profile=prof,
        tip_radius=r,
    )


__all__ = [
    "SHAPES",
    "THESIS_CENTER_SIGMA",
    "THESIS_CONTACT_SIGMA",
    "THESIS_NORMAL_SIGMA",
    "Shape",
    "SyntheticTrace",
    "simulate",
]
