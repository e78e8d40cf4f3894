"""Traced and estimated surfaces of a height field (thesis §3.2.1, eqs. 3.10-3.11).

For a surface ``z = h(x, y)`` explored from above by a ball of radius ``r``:

* the **traced surface** (locus of the ball centre, the envelope of spheres centred on the
  surface) is the grey-scale *dilation* of ``h`` by the spherical structuring element
  ``b(d) = sqrt(r^2 - |d|^2)``: ``t(p) = max_{|d| <= r} h(p + d) + b(d)``. It equals the
  parallel surface ``f + r z`` (eq. 3.10) except where the ball cannot follow it;
* the **estimated surface** (eq. 3.11, ``s_e = s_t - r z_t``) is the *erosion* of the traced
  surface by the same element, i.e. the morphological *closing* of ``h`` by the ball;
* **unobservable regions** are where the estimated surface lies above the true one
  (``e - h > tol``): the ball never touches there (concave features sharper than ``1/r``);
* **interference curves** are the creases of the traced surface, where the ball touches the
  surface at two separate points (§3.2.1). Over an unobservable point ``q`` the estimated
  surface is the lower cap of exactly such a ball, so its centre is ``q + r n_e(q)``
  (``n_e`` the estimated surface's normal): those centres, rasterized, form the mask.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter


@dataclass(frozen=True)
class OffsetSurfaces:
    """Traced and estimated surfaces of a height grid for one fingertip radius.

    Attributes:
        x: (nx,) grid abscissae [m]; y: (ny,) ordinates [m].
        tip_radius: ``r`` [m].
        height: (nx, ny) the original heights [m].
        traced: (nx, ny) height of the fingertip centre (traced surface) [m].
        estimated: (nx, ny) estimated surface, the closing of the heights by the ball [m].
        unobservable: (nx, ny) bool, the ball never touches the true surface there.
        interference: (nx, ny) bool, creases of the traced surface (interference curves).
        interior: (nx, ny) bool, the cells farther than ``r`` from the grid's border, the only
            ones where ``unobservable`` is decided (near the border the ball would reach
            outside the sampled area); ``unobservable`` is ``False`` elsewhere.
    """

    x: np.ndarray
    y: np.ndarray
    tip_radius: float
    height: np.ndarray
    traced: np.ndarray
    estimated: np.ndarray
    unobservable: np.ndarray
    interference: np.ndarray
    interior: np.ndarray

    @property
    def unobservable_fraction_of_interior(self) -> float | None:
        """Fraction of the interior cells that are unobservable (``None``: empty interior).

        Cells within ``r`` of the border are never marked unobservable, so the fraction over
        the whole grid would understate it (and be 0 by construction when the grid is no
        wider than ``2 r``); this one is over the cells where it was decided.
        """
        n = int(self.interior.sum())
        return float(self.unobservable.sum() / n) if n else None


def ball_element(dx: float, dy: float, radius: float) -> np.ndarray:
    """Spherical structuring element ``sqrt(r^2 - d^2)`` on a grid (``-inf`` outside the disc).

    Returns:
        (2a+1, 2b+1) heights [m], ``a = floor(r/dx)``, ``b = floor(r/dy)``.
    """
    a, b = int(radius // dx), int(radius // dy)
    ox = np.arange(-a, a + 1)[:, None] * dx
    oy = np.arange(-b, b + 1)[None, :] * dy
    d2 = ox**2 + oy**2
    return np.where(d2 <= radius**2, np.sqrt(np.maximum(radius**2 - d2, 0.0)), -np.inf)


def _uniform_step(a: np.ndarray, name: str) -> float:
    steps = np.diff(a)
    if steps.size == 0 or np.any(steps <= 0) or np.ptp(steps) > 1e-6 * steps.mean():
        raise InvalidParameter(
            f"{name} must be uniformly spaced and increasing for the morphological offsets"
        )
    return float(steps.mean())


def offset_surfaces(
    x, y, z, tip_radius: float, *, tolerance: float | None = None
) -> OffsetSurfaces:
    """Traced surface, estimated surface, unobservable regions and interference curves.

    Args:
        x: (nx,) uniformly spaced [m]; y: (ny,) uniformly spaced [m].
        z: (nx, ny) heights ``z[i, j] = h(x[i], y[j])`` [m].
        tip_radius: fingertip radius ``r`` [m]; at least one grid step.
        tolerance: height difference above which a point is unobservable [m] (default
            ``max(1e-3 r, grid step)``: the discrete ball is exact to about ``h^2 k / 8``).

    Returns:
        :class:`OffsetSurfaces`. The ball only sees the sampled area and its centre stays
        above it, so within ``r`` of the border the estimated surface is not reliable; the
        ``unobservable`` and ``interference`` masks are left ``False`` in that band.
    """
    from scipy import ndimage

    x, y, z = (np.asarray(a, float) for a in (x, y, z))
    if z.shape != (x.size, y.size):
        raise InvalidParameter(
            f"z must have shape (len(x), len(y)) = {(x.size, y.size)}, got {z.shape}"
        )
    dx, dy = _uniform_step(x, "x"), _uniform_step(y, "y")
    r = checks.positive("tip_radius", tip_radius, "m")
    if r < max(dx, dy):
        raise InvalidParameter(
            f"tip_radius: expected a number >= one grid step = {max(dx, dy):g} [m], got {r!r}"
        )
    tol = max(1e-3 * r, dx, dy) if tolerance is None else float(tolerance)
    ball = ball_element(dx, dy, r)
    footprint = np.isfinite(ball)
    structure = np.where(footprint, ball, 0.0)
    traced = ndimage.grey_dilation(
        z, footprint=footprint, structure=structure, mode="constant", cval=-np.inf
    )
    estimated = ndimage.grey_erosion(
        traced, footprint=footprint, structure=structure, mode="constant", cval=np.inf
    )
    interior = np.zeros(z.shape, dtype=bool)
    a, b = int(math.ceil(r / dx)), int(math.ceil(r / dy))
    interior[a : -a or None, b : -b or None] = True
    unobservable = (estimated - z > tol) & interior
    interference = _interference(estimated, unobservable, x, y, r)
    return OffsetSurfaces(x, y, r, z, traced, estimated, unobservable, interference, interior)


def _interference(
    e: np.ndarray, unobservable: np.ndarray, x: np.ndarray, y: np.ndarray, r: float
) -> np.ndarray:
    """Grid mask of the ball centres ``q + r n_e(q)`` over unobservable points ``q``."""
    out = np.zeros(e.shape, dtype=bool)
    if not unobservable.any():
        return out
    ex, ey = np.gradient(e, x, y)
    i, j = np.nonzero(unobservable)
    w = np.sqrt(1 + ex[i, j] ** 2 + ey[i, j] ** 2)
    cx = x[i] - r * ex[i, j] / w
    cy = y[j] - r * ey[i, j] / w
    ii = np.clip(np.rint((cx - x[0]) / (x[1] - x[0])).astype(int), 0, x.size - 1)
    jj = np.clip(np.rint((cy - y[0]) / (y[1] - y[0])).astype(int), 0, y.size - 1)
    out[ii, jj] = True
    return out


__all__ = ["OffsetSurfaces", "ball_element", "offset_surfaces"]
