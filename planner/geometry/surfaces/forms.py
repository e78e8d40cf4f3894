"""Plain data and shared formulas of surface differential geometry (thesis App. A.1, §3.2.1)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class SurfaceGeometry:
    """Differential geometry of a surface at an array of points.

    Attributes:
        point: (..., 3) surface points ``f(u, v)`` [m].
        gauss_frame: (..., 3, 3) normalized Gauss frame, columns ``x, y, z`` (eq. A.1).
        curvature_matrix: (..., 2, 2) curvature form ``K`` (eq. A.2) [1/m].
        torsion: (..., 1, 2) torsion form ``T`` (eq. A.3) [1/m].
        metric: (..., 2, 2) metric ``M`` (eq. A.4) [m per unit of u, v].
    """

    point: np.ndarray
    gauss_frame: np.ndarray
    curvature_matrix: np.ndarray
    torsion: np.ndarray
    metric: np.ndarray


def principal_from_k(kmat: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Principal curvatures and directions from curvature forms ``K`` (eqs. 3.5-3.8).

    Args:
        kmat: (..., 2, 2) curvature forms in an orthonormal tangent frame [1/m].

    Returns:
        ``(k1, k2, p1, p2)``: (...) principal curvatures with ``|k1| >= |k2|`` [1/m] and
        (..., 2) unit principal directions in the frame's ``(x, y)`` coordinates. At umbilic
        points (``k1 == k2``) the directions are undefined; ``p1 = (1, 0)`` is returned.
    """
    a = kmat[..., 0, 0]
    d = kmat[..., 1, 1]
    b = 0.5 * (kmat[..., 0, 1] + kmat[..., 1, 0])
    mean = 0.5 * (a + d)
    disc = np.hypot(0.5 * (a - d), b)
    first_is_plus = mean >= 0.0
    k1 = np.where(first_is_plus, mean + disc, mean - disc)
    k2 = np.where(first_is_plus, mean - disc, mean + disc)
    # eigenvector of k1: (b, k1 - a) or (k1 - d, b), whichever is longer
    e1 = np.stack([b, k1 - a], axis=-1)
    e2 = np.stack([k1 - d, b], axis=-1)
    n1 = np.linalg.norm(e1, axis=-1)
    n2 = np.linalg.norm(e2, axis=-1)
    p1 = np.where((n1 >= n2)[..., None], e1, e2)
    norm = np.maximum(n1, n2)
    umbilic = norm <= 1e-12 * np.maximum(1.0, np.abs(k1))
    p1 = np.where(
        umbilic[..., None], np.array([1.0, 0.0]), p1 / np.where(umbilic, 1.0, norm)[..., None]
    )
    p2 = np.stack([-p1[..., 1], p1[..., 0]], axis=-1)
    return k1, k2, p1, p2


__all__ = ["SurfaceGeometry", "principal_from_k"]
