"""Fingertip paths as signals: planar frame, block decimation, Gaussian-derivative curvature.

The curvature of a planar curve is invariant under reparametrization (thesis eq. B.5),

.. math:: k = \\frac{x' y'' - y' x''}{(x'^2 + y'^2)^{3/2}},

so it is computed from derivatives with respect to the sample index (time, for data taken at a
constant rate, App. B.1) of the Gaussian-smoothed coordinates; no resampling is needed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view


@dataclass(frozen=True, eq=False)
class PlanarFrame:
    """Where a 2-D analysis of (N, D) data lives.

    Attributes:
        origin: (D,) origin of the plane [m].
        axes: (2, D) orthonormal in-plane axes (rows).
    """

    origin: np.ndarray
    axes: np.ndarray

    def to_plane(self, pts: np.ndarray) -> np.ndarray:
        """(N, D) points -> (N, 2) in-plane coordinates [m]."""
        if pts.shape[1] == 2 and not self.origin.any() and (self.axes == np.eye(2)).all():
            return pts
        return self.vectors_to_plane(pts - self.origin)

    def vectors_to_plane(self, vec: np.ndarray) -> np.ndarray:
        """(N, D) vectors -> (N, 2) in-plane components."""
        if vec.shape[1] == 2 and (self.axes == np.eye(2)).all():
            return vec
        # column sums instead of a matmul with a tiny inner dimension (much faster)
        out = np.empty((vec.shape[0], 2))
        for k in range(2):
            out[:, k] = sum(vec[:, j] * self.axes[k, j] for j in range(vec.shape[1]))
        return out

    def from_plane(self, uv: np.ndarray) -> np.ndarray:
        """(N, 2) in-plane coordinates -> (N, D) points [m]."""
        return self.origin + uv @ self.axes


def planar_frame(points: np.ndarray, outward_hint: np.ndarray | None = None) -> PlanarFrame:
    """The plane of a fingertip path.

    2-D data keep their own coordinates. 3-D data are projected on their best-fit plane
    (principal components); the second in-plane axis points to the side of ``outward_hint``
    ((D,) mean measured outward normal) when given, else to world +z.

    Args:
        points: (N, D) fingertip-centre positions [m], D = 2 or 3.
        outward_hint: (D,) a vector pointing away from the object, or ``None``.
    """
    d = points.shape[1]
    if d == 2:
        return PlanarFrame(np.zeros(2), np.eye(2))
    origin = points.mean(axis=0)
    _, _, vt = np.linalg.svd(points - origin, full_matrices=False)
    e1, e2 = vt[0], vt[1]
    travel = points[-1] - points[0]
    if e1 @ travel < 0:
        e1 = -e1
    hint = np.array([0.0, 0.0, 1.0]) if outward_hint is None else outward_hint
    if e2 @ hint < 0:
        e2 = -e2
    return PlanarFrame(origin, np.vstack([e1, e2]))


def median_spacing(points: np.ndarray) -> float:
    """Robust mean distance between consecutive samples of a noisy path [m].

    Uses displacements over ``k`` samples (k ~ N/100) so that measurement noise, which
    inflates sample-to-sample distances, does not dominate.
    """
    n = points.shape[0]
    k = max(1, n // 100)
    stride = max(1, (n - k) // 50_000)  # a strided subset is plenty for a median
    diff = points[k::stride] - points[: n - k : stride][: points[k::stride].shape[0]]
    d = np.sqrt(np.einsum("ij,ij->i", diff, diff))
    h = float(np.median(d)) / k
    if h <= 0:
        h = float(np.linalg.norm(np.diff(points, axis=0), axis=1).mean())
    return h


def block_means(arr: np.ndarray, block: int) -> tuple[np.ndarray, np.ndarray]:
    """Average consecutive blocks of ``block`` samples (the decimation of App. B.2 step 2,
    done by averaging rather than dropping so that the noise shrinks by sqrt(block)).

    Only whole blocks are kept: the ``N mod block`` samples left over are dropped, half at
    each end. A shorter last block sat closer to its neighbour than ``block`` samples, a
    jump in the path's speed per decimated sample that the Gaussian derivatives read as a
    kink: a spurious convex feature 0.16 mm long at the end of a trace read backwards (1521
    samples in blocks of 4; found by Hypothesis), and its mean was noisier by sqrt(block).

    Args:
        arr: (N, ...) samples.
        block: samples per block (>= 1; at most N).

    Returns:
        ``(means (M, ...), centre_index (M,))``, ``M = N // block``, with the (fractional)
        input index of each block's centre.
    """
    n = arr.shape[0]
    if block <= 1:
        return arr.astype(float, copy=True), np.arange(n, dtype=float)
    m = n // block
    first = (n - m * block) // 2
    means = arr[first : first + m * block].reshape((m, block) + arr.shape[1:]).mean(axis=1)
    return means, first + block * np.arange(m, dtype=float) + (block - 1) / 2.0


def _odd_pad(x: np.ndarray, pad: int) -> tuple[np.ndarray, int]:
    """Pad (N, ...) along axis 0 by point reflection about each end (keeps linear trends).

    The centre of reflection is the end value of a straight-line fit over the last ``pad``
    samples rather than the noisy end sample itself, so that the padding does not turn the
    end sample's noise into a kink (a spurious curvature peak at the ends of a trace).
    """
    n = x.shape[0]
    pad = min(pad, n - 1)
    m = min(max(pad, 2), n)
    u = np.arange(m, dtype=float)
    flat = x.reshape(n, -1)
    c0 = np.polynomial.polynomial.polyfit(u, flat[:m], 1)
    c1 = np.polynomial.polynomial.polyfit(u, flat[n - m :][::-1], 1)
    a0 = c0[0].reshape(x.shape[1:])
    a1 = c1[0].reshape(x.shape[1:])
    head = 2 * a0 - x[pad:0:-1]
    tail = 2 * a1 - x[-2 : -pad - 2 : -1]
    return np.concatenate([head, x, tail], axis=0), pad


def derivative_kernels(sigma: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sampled Gaussian smoothing, first- and second-derivative kernels (radius 4 sigma),
    corrected to be exact on constants, ramps and parabolas: the raw sampled derivative
    kernels of a truncated Gaussian do not sum to zero, which leaks the absolute position
    (metres away from the origin) into the derivatives."""
    rad = max(1, int(4 * sigma + 0.5))
    j = np.arange(-rad, rad + 1, dtype=float)
    g = np.exp(-0.5 * (j / sigma) ** 2)
    k0 = g / g.sum()
    k1 = j * g / np.sum(j * j * g)
    m = np.sum(j * j * g) / g.sum()
    q = (j * j - m) * g
    k2 = 2 * q / np.sum(q * j * j)
    return k0, k1, k2


def gaussian_derivatives(x: np.ndarray, sigma: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Gaussian-smoothed value, first and second derivative with respect to sample index.

    Args:
        x: (N, D) samples.
        sigma: Gaussian standard deviation [samples]; 0 means finite differences only.

    Returns:
        ``(x_s, dx, ddx)``, each (N, D).
    """
    if sigma <= 0:
        return x, np.gradient(x, axis=0), np.gradient(np.gradient(x, axis=0), axis=0)
    k0, k1, k2 = derivative_kernels(sigma)
    xp, pad = _odd_pad(x, k0.size // 2 + 1)
    # correlation with edge ("nearest") extension, as a dot product with each window: numpy
    # only (importing scipy.ndimage for this took 1 s, most of a gait run's feature detection)
    h = k0.size // 2
    ext = np.pad(xp, [(h, h)] + [(0, 0)] * (xp.ndim - 1), mode="edge")
    windows = sliding_window_view(ext[pad : pad + x.shape[0] + 2 * h], k0.size, axis=0)
    return windows @ k0, windows @ k1, windows @ k2


def signed_curvature(dx: np.ndarray, ddx: np.ndarray) -> np.ndarray:
    """Counter-clockwise-positive curvature of a planar curve, eq. (B.5) [1/m].

    Args:
        dx: (N, 2) first derivative with respect to any parameter.
        ddx: (N, 2) second derivative with respect to the same parameter.
    """
    num = dx[:, 0] * ddx[:, 1] - dx[:, 1] * ddx[:, 0]
    den = np.maximum(np.hypot(dx[:, 0], dx[:, 1]), 1e-300) ** 3
    return num / den


def left_normals(dx: np.ndarray) -> np.ndarray:
    """(N, 2) unit left normals of the direction of travel ``dx`` (N, 2)."""
    speed = np.maximum(np.hypot(dx[:, 0], dx[:, 1]), 1e-300)
    return np.column_stack([-dx[:, 1], dx[:, 0]]) / speed[:, None]


def arclength(points: np.ndarray, start: float = 0.0) -> np.ndarray:
    """(N,) cumulative arclength of an (N, D) polyline, starting at ``start`` [m]."""
    seg = np.linalg.norm(np.diff(points, axis=0), axis=1)
    return start + np.concatenate([[0.0], np.cumsum(seg)])


#: expected false alarms: the default smoothing makes the noise of the curvature signal this
#: many times smaller than the detection threshold
NOISE_MARGIN = 5.0


def noise_sigma(values: np.ndarray) -> float:
    """Robust white-noise standard deviation of (N,) or (N, D) samples, from the median
    absolute second difference (``var(x[i+1] - 2x[i] + x[i-1]) = 6 sigma^2``); smooth signal
    content contributes only ``h^2 x''``."""
    v = values.reshape(values.shape[0], -1)
    stride = max(1, v.shape[0] // 100_000)  # a strided subset is plenty for a median
    i = np.arange(1, v.shape[0] - 1, stride)
    d2 = v[i + 1] - 2 * v[i] + v[i - 1]
    return float(np.median(np.abs(d2)) / 0.6745 / np.sqrt(6.0))


def auto_scale(
    sigma: float, spacing: float, threshold: float, order: int, lo: float, hi: float
) -> float:
    """Gaussian smoothing scale [m] that keeps the noise of a derivative signal at
    ``threshold / NOISE_MARGIN``.

    For white noise of standard deviation ``sigma`` sampled every ``spacing`` [m], the
    ``order``-th Gaussian derivative at scale ``s`` has standard deviation
    ``sigma * sqrt(spacing * c) / s^(order + 1/2)`` with ``c = 1/(4 sqrt(pi))`` (order 1) or
    ``3/(8 sqrt(pi))`` (order 2). Solved for ``s`` and clipped to ``[lo, hi]``.
    """
    c = 1 / (4 * np.sqrt(np.pi)) if order == 1 else 3 / (8 * np.sqrt(np.pi))
    if sigma <= 0:
        return lo
    s = (sigma * np.sqrt(spacing * c) * NOISE_MARGIN / threshold) ** (1.0 / (order + 0.5))
    return float(np.clip(s, lo, hi))


def curvature_by_arclength(points: np.ndarray, spacing: float, sigma: float = 1.5) -> np.ndarray:
    """Counter-clockwise curvature of a sampled curve, computed on an equal-arclength
    resampling (so that samples bunched where the curve dwells, e.g. a contact point resting
    on a corner while the fingertip rolls over it, neither amplify noise nor hide the
    corner) and read back at every input sample [1/m].

    Args:
        points: (M, 2) curve samples in order [m].
        spacing: arclength step of the resampling [m].
        sigma: Gaussian smoothing on the resampled curve [samples].
    """
    s = arclength(points)
    if s[-1] <= 2 * spacing:
        _, d1, d2 = gaussian_derivatives(points, sigma)
        return signed_curvature(d1, d2)
    grid = np.arange(0.0, s[-1] + spacing / 2, spacing)
    res = np.column_stack([np.interp(grid, s, points[:, j]) for j in range(points.shape[1])])
    _, d1, d2 = gaussian_derivatives(res, sigma)
    k = signed_curvature(d1, d2)
    idx = np.clip(np.rint(s / spacing).astype(int), 0, grid.size - 1)
    return k[idx]
