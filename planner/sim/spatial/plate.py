"""Contact surfaces of the spatial world: a plane of any tilt and a plate of catalogue features.

Both are described in their own frame (``z`` up, away from the material) and placed in the
WCS by ``add_surface(..., pose=...)``. A :class:`Plate` is the graph

.. math:: z = h(x, y) = z_0 + \\sum_k Z_k(s_k), \\qquad s_k = (x - x_k)\\cos\\psi_k
          + (y - y_k)\\sin\\psi_k

of the catalogue's cross-sections (:mod:`planner.geometry.surfaces.catalogue`, Table 3.1),
each with closed-form first and second derivatives, so the closest point of a sphere centre
is found by a Newton iteration on exact derivatives (:mod:`planner.sim.spatial.closest`).
Bumps and pits are of revolution about ``(x_k, y_k)`` (``s_k`` is then the distance).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from planner import checks
from planner.errors import InvalidParameter

__all__ = ["FEATURE_KINDS", "Plane", "Plate", "PlateFeature"]

FEATURE_KINDS = ("ridge", "ravine", "step", "bump", "pit", "wire", "cusp")


@dataclass(frozen=True)
class Plane:
    """The plane through ``point`` with unit normal ``normal`` (pointing out of the material).

    Attributes:
        point: (3,) a point of the plane [m].
        normal: (3,) outward normal (normalized here) [-].
    """

    point: tuple[float, float, float] = (0.0, 0.0, 0.0)
    normal: tuple[float, float, float] = (0.0, 0.0, 1.0)

    def __post_init__(self) -> None:
        p = checks.vector("point", self.point, 3, "m")
        n = checks.vector("normal", self.normal, 3)
        norm = float(np.linalg.norm(n))
        if norm < 1e-12:
            raise InvalidParameter(f"normal: expected a non-zero vector, got {n.tolist()}")
        object.__setattr__(self, "point", tuple(p.tolist()))
        object.__setattr__(self, "normal", tuple((n / norm).tolist()))

    @classmethod
    def tilted(cls, angle: float, point=(0.0, 0.0, 0.0)) -> Plane:
        """The plane ``z = -x tan(angle)`` rotated about ``y``: downhill is ``+x`` [rad]."""
        a = checks.in_range("angle", angle, -math.pi / 2, math.pi / 2, "rad")
        return cls(point, (math.sin(a), 0.0, math.cos(a)))


@dataclass(frozen=True)
class PlateFeature:
    """One macro feature on a plate (profiles of :mod:`planner.geometry.surfaces.catalogue`).

    Profiles ``Z(s)`` of the across coordinate ``s`` [m]:

    * ``ridge``: ``h exp(-s²/(2w²))``; ``ravine``: its negative;
    * ``step``: ``h (1 + tanh(s/w))/2`` (going up towards ``+s``);
    * ``bump``: ``h / (1 + r²/w²)`` of the distance ``r`` (the catalogue's ``1/(1 + a u²)``
      with ``a = 1/w²``, scaled by ``h``); ``pit``: its negative;
    * ``cusp``: ``-(h/w)(sqrt(s² + ρ²) - ρ)`` (flank slope ``h/w``, crest rounding ``ρ``);
    * ``wire``: a wire of radius ``R = h/2`` lying on the plate along the feature's axis,
      its two concave corners filleted with radius ``ρ`` (exact arcs: wire ``k = 1/R``,
      fillets ``k = -1/ρ``), as :func:`~planner.geometry.surfaces.wire_on_plane`; a plate
      is a graph ``z = h(x, y)``, so ``ρ >= R`` is required (with ``ρ < R`` the fillets
      meet the wire below its equator and the profile overhangs).

    Attributes:
        kind: one of :data:`FEATURE_KINDS`.
        height: ``h`` [m] (> 0; the wire's diameter).
        width: ``w`` [m] (> 0; unused by ``wire``).
        position: ``(x_k, y_k)`` of the crest / centre on the plate [m].
        across: direction ``ψ`` of the profile coordinate ``s`` in the plate's xy plane [rad]
            (0: the profile runs along ``x``, the feature along ``y``).
        rounding: ``ρ`` [m] for ``cusp`` (default ``w/10``) and ``wire`` (default and
            minimum ``R``).
        path: optional polyline skeleton ``((x0, y0), (x1, y1), ...)`` [m] of a finite or bent
            feature (all kinds but ``step``, whose profile is odd): ``s`` is then the distance
            to the polyline — along a segment's interior the exact line formula (a straight
            feature), near a vertex the radial one (round end caps, round outer corners; one
            point: a bump-like dome). ``position`` and ``across`` are then unused. Inside a
            bend, where two segments are equally near, ``s`` has a kink (the profiles are
            even, so ``h`` stays continuous; keep bends wide compared with the width).
    """

    kind: str
    height: float
    width: float = 1e-3
    position: tuple[float, float] = (0.0, 0.0)
    across: float = 0.0
    rounding: float | None = None
    path: tuple[tuple[float, float], ...] | None = None

    def __post_init__(self) -> None:
        checks.choice("kind", self.kind, FEATURE_KINDS)
        h = checks.positive("height", self.height, "m")
        w = checks.positive("width", self.width, "m")
        pos = checks.vector("position", self.position, 2, "m")
        psi = checks.in_range("across", self.across, -2 * math.pi, 2 * math.pi, "rad")
        default = w / 10 if self.kind == "cusp" else h / 2
        rho = default if self.rounding is None else checks.positive("rounding", self.rounding, "m")
        if self.kind == "wire" and rho < h / 2 * (1 - 1e-12):
            raise InvalidParameter(
                f"rounding: expected >= the wire radius {h / 2:g} m (the plate is a graph; "
                f"smaller fillets overhang), got {rho!r}"
            )
        object.__setattr__(self, "height", h)
        object.__setattr__(self, "width", w)
        object.__setattr__(self, "position", (float(pos[0]), float(pos[1])))
        object.__setattr__(self, "across", psi)
        object.__setattr__(self, "rounding", rho)
        if self.path is not None:
            if self.kind == "step":
                raise InvalidParameter(
                    "path: a step has an odd profile and no skeleton; use position and across"
                )
            pts = checks.points("path", self.path, dims=(2,), unit="m")
            if len(pts) > 1 and np.any(np.linalg.norm(np.diff(pts, axis=0), axis=1) <= 0):
                raise InvalidParameter("path: consecutive points must differ")
            object.__setattr__(self, "path", tuple(tuple(map(float, p)) for p in pts))

    def profile(self, s: float) -> tuple[float, float, float]:
        """``(Z, Z', Z'')`` at ``s`` [m, -, 1/m] (``s`` the distance for bumps and pits)."""
        h, w, k = self.height, self.width, self.kind
        if k in ("ridge", "ravine"):
            e = h * math.exp(-s * s / (2 * w * w))
            sg = 1.0 if k == "ridge" else -1.0
            return sg * e, -sg * s / (w * w) * e, sg * (s * s / w**4 - 1 / (w * w)) * e
        if k == "step":
            t = math.tanh(s / w)
            return h * (1 + t) / 2, h / (2 * w) * (1 - t * t), -h / (w * w) * t * (1 - t * t)
        if k in ("bump", "pit"):
            sg = 1.0 if k == "bump" else -1.0
            d = 1.0 + s * s / (w * w)
            return (
                sg * h / d,
                -sg * 2 * h * s / (w * w * d * d),
                sg * h * (6 * s * s / w**2 - 2) / (w * w * d**3),
            )
        if k == "cusp":
            rho, m = self.rounding, h / w
            q = math.sqrt(s * s + rho * rho)
            return -m * (q - rho), -m * s / q, -m * rho * rho / q**3
        return _wire(s, h / 2, self.rounding)

    def _across_curvature(self, s: float) -> float:
        _, z1, z2 = self.profile(s)
        return z2 / (1.0 + z1 * z1) ** 1.5

    def _around_curvature(self, r: float) -> float:
        _, z1, z2 = self.profile(r)
        if r == 0.0:  # both curvatures tend to Z''(0) (Z'(0) = 0)
            return z2
        return max(z2 / (1.0 + z1 * z1) ** 1.5, z1 / (r * math.sqrt(1.0 + z1 * z1)))

    def concave_radius(self) -> float:
        """The smallest radius of curvature [m] of the feature's concave (valley) parts, alone
        on a flat plate (``inf`` when it has none: a cusp). A sphere touches such a surface
        at a single point, as the simulator models it (:mod:`planner.sim.spatial.closest`),
        only while its radius is below this.

        The graph's principal curvatures: across a straight feature
        ``Z'' / (1 + Z'^2)^(3/2)`` (along it 0); about a bump, pit or a path's vertex the
        radial one and the tangential ``Z' / (r sqrt(1 + Z'^2))``. Their largest positive
        value over the profile is found on a fine grid and refined by a bounded scalar search
        (closed forms: a ravine ``w^2 / h``, a pit ``w^2 / (2 h)``, a wire its fillets
        ``rho``, a ridge ``w^2 e^(3/2) / (2 h)`` to first order in ``(h / w)^2``)."""

        reach = 8.0 * self.width + 4.0 * (self.rounding + self.height)
        revolved = self.kind in ("bump", "pit")
        path = self.path
        parts = []
        if (path is None and not revolved) or (path is not None and len(path) > 1):
            parts.append((self._across_curvature, -reach))  # a straight stretch
        if revolved or path is not None:
            parts.append((self._around_curvature, 0.0))  # about a centre or a path's vertex
        best = max((_peak(kappa, lo, reach) for kappa, lo in parts), default=0.0)
        return 1.0 / best if best > 0.0 else math.inf


def _peak(kappa, lo: float, hi: float) -> float:
    """The largest value of ``kappa`` over ``[lo, hi]``: a grid of 8001 points, then a
    bounded scalar search between the best point's neighbours."""
    from scipy.optimize import minimize_scalar

    grid = np.linspace(lo, hi, 8001)
    values = np.array([kappa(float(g)) for g in grid])
    k = int(np.argmax(values))
    a, b = grid[max(k - 1, 0)], grid[min(k + 1, len(grid) - 1)]
    res = minimize_scalar(
        lambda g: -kappa(g), bounds=(a, b), method="bounded", options={"xatol": 1e-12 * hi}
    )
    return max(float(values[k]), -float(res.fun))


def _wire(s: float, R: float, rho: float) -> tuple[float, float, float]:
    """Profile of a wire of radius R on z = 0 with fillets of radius rho: (Z, Z', Z'')."""
    xc = 2 * math.sqrt(R * rho)  # fillet centres (±xc, rho)
    xt = R * xc / (R + rho)  # tangency of wire and fillet
    a = abs(s)
    sg = 1.0 if s >= 0 else -1.0
    if a <= xt:  # top of the wire, centre (0, R)
        q = math.sqrt(R * R - s * s)
        return R + q, -s / q, -(R * R) / q**3
    if a < xc:  # concave fillet, lower arc of the circle centred (xc, rho)
        e = a - xc
        q = math.sqrt(rho * rho - e * e)
        return rho - q, sg * e / q, rho * rho / q**3
    return 0.0, 0.0, 0.0


def _radial(f: PlateFeature, dx: float, dy: float):
    """Height and derivatives of ``Z(r)``, ``r = |(dx, dy)|`` (bumps, pits, path vertices)."""
    r = math.hypot(dx, dy)
    Z, Z1, Z2 = f.profile(r)
    if r < 1e-300:
        return Z, 0.0, 0.0, Z2, 0.0, Z2
    ux, uy = dx / r, dy / r
    t = Z1 / r  # tangential curvature part
    return (
        Z,
        Z1 * ux,
        Z1 * uy,
        Z2 * ux * ux + t * (1 - ux * ux),
        (Z2 - t) * ux * uy,
        Z2 * uy * uy + t * (1 - uy * uy),
    )


def _path_feature(f: PlateFeature, x: float, y: float):
    """Height and derivatives of a feature along its polyline skeleton (see PlateFeature)."""
    pts = f.path
    best, vertex, sd, nrm = math.inf, pts[0], 0.0, (0.0, 0.0)
    if len(pts) == 1:
        return _radial(f, x - pts[0][0], y - pts[0][1])
    for (ax, ay), (bx, by) in zip(pts[:-1], pts[1:], strict=True):
        ex, ey = bx - ax, by - ay
        L2 = ex * ex + ey * ey
        t = ((x - ax) * ex + (y - ay) * ey) / L2
        if 0.0 < t < 1.0:
            L = math.sqrt(L2)
            nx, ny = -ey / L, ex / L
            dist = (x - ax) * nx + (y - ay) * ny
            if abs(dist) < best:
                best, vertex, sd, nrm = abs(dist), None, dist, (nx, ny)
        else:
            vx, vy = (ax, ay) if t <= 0.0 else (bx, by)
            dist = math.hypot(x - vx, y - vy)
            if dist < best:
                best, vertex = dist, (vx, vy)
    if vertex is not None:
        return _radial(f, x - vertex[0], y - vertex[1])
    Z, Z1, Z2 = f.profile(sd)
    nx, ny = nrm
    return Z, Z1 * nx, Z1 * ny, Z2 * nx * nx, Z2 * nx * ny, Z2 * ny * ny


@dataclass(frozen=True)
class Plate:
    """A flat plate ``z = base`` carrying macro features (a graph ``z = h(x, y)``).

    Attributes:
        features: the :class:`PlateFeature`s (their heights add up).
        base: height of the plate surface far from the features [m].
        name: label.
    """

    features: tuple[PlateFeature, ...] = field(default_factory=tuple)
    base: float = 0.0
    name: str = "plate"

    def __post_init__(self) -> None:
        feats = tuple(self.features)
        for f in feats:
            if not isinstance(f, PlateFeature):
                raise InvalidParameter(
                    f"features: expected PlateFeature items, got {checks.shown(f)}"
                )
        object.__setattr__(self, "features", feats)
        object.__setattr__(self, "base", float(checks.vector("base", [self.base], 1, "m")[0]))

    def height_derivatives(
        self, x: float, y: float
    ) -> tuple[float, float, float, float, float, float]:
        """``(h, h_x, h_y, h_xx, h_xy, h_yy)`` at ``(x, y)`` in the plate frame [m, -, 1/m]."""
        h, hx, hy, hxx, hxy, hyy = self.base, 0.0, 0.0, 0.0, 0.0, 0.0
        for f in self.features:
            if f.path is not None:
                d = _path_feature(f, x, y)
                h, hx, hy = h + d[0], hx + d[1], hy + d[2]
                hxx, hxy, hyy = hxx + d[3], hxy + d[4], hyy + d[5]
                continue
            dx, dy = x - f.position[0], y - f.position[1]
            if f.kind in ("bump", "pit"):
                r = math.hypot(dx, dy)
                Z, Z1, Z2 = f.profile(r)
                if r < 1e-300:
                    h, hxx, hyy = h + Z, hxx + Z2, hyy + Z2
                    continue
                ux, uy = dx / r, dy / r
                h += Z
                hx += Z1 * ux
                hy += Z1 * uy
                t = Z1 / r  # tangential curvature part
                hxx += Z2 * ux * ux + t * (1 - ux * ux)
                hxy += (Z2 - t) * ux * uy
                hyy += Z2 * uy * uy + t * (1 - uy * uy)
                continue
            c, s = math.cos(f.across), math.sin(f.across)
            Z, Z1, Z2 = f.profile(dx * c + dy * s)
            h += Z
            hx += Z1 * c
            hy += Z1 * s
            hxx += Z2 * c * c
            hxy += Z2 * c * s
            hyy += Z2 * s * s
        return h, hx, hy, hxx, hxy, hyy

    def concave_radius(self) -> float:
        """The smallest :meth:`PlateFeature.concave_radius` of the features [m] (``inf`` for
        none): a sphere of a larger radius can touch the plate at two points, where the
        simulator finds one. Each feature is taken alone; where features overlap their
        curvatures add, which this does not see."""
        return min((f.concave_radius() for f in self.features), default=math.inf)

    def height(self, x, y) -> np.ndarray:
        """Heights ``h(x, y)`` [m] over arrays (for plots and meshes)."""
        xx, yy = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        out = np.empty(xx.shape)
        for idx in np.ndindex(xx.shape):
            out[idx] = self.height_derivatives(float(xx[idx]), float(yy[idx]))[0]
        return out
