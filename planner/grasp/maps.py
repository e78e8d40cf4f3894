"""Grasp maps of planar objects (§2.2.1, Fig. 2.4, after Leveroni).

A contact is located by its *contact angle* θ: the polar angle of the contact point about the
object frame's origin, counter-clockwise from the object's x-axis, in [0, 2π). The grasp map
of a finger pair is the force-closure indicator (and the ε quality) over a grid of
``(θ1, θ2)``. Both are computed by the exact closed forms of
:func:`planner.grasp.closure.force_closure_two_planar` and
:func:`planner.grasp.quality.epsilon_two_planar`, broadcast over the whole grid: the closure
map is a component-wise numpy kernel on preallocated buffers.

Rotating the object by φ slides the map along the diagonal (Leveroni): the map of the
rotated object, indexed by *world* polar angles, is the original map shifted by ``(φ, φ)``;
see :func:`shift_diagonal`.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from planner.grasp.closure import STRICT
from planner.grasp.quality import epsilon_two_planar


@dataclass(frozen=True)
class GraspMap:
    """Force closure and ε over a grid of contact-angle pairs.

    Attributes:
        theta: (n,) contact angles [rad], ``2π i / n``.
        points: (n, 2) contact points in the object frame [m].
        normals: (n, 2) inward unit normals in the object frame.
        force_closure: (n, n) bool, ``[i, j]`` for contact 1 at ``theta[i]`` and contact 2 at
            ``theta[j]``.
        epsilon: (n, n) Ferrari–Canny ε (L1, torques about the contacts' midpoint divided by
            half their distance; 0 where not in force closure), or all-NaN when not computed.
        mu: friction coefficient at contact 1; mu2: at contact 2.
    """

    theta: np.ndarray
    points: np.ndarray
    normals: np.ndarray
    force_closure: np.ndarray
    epsilon: np.ndarray
    mu: float
    mu2: float

    @property
    def resolution(self) -> int:
        """Number of contact angles per axis."""
        return int(self.theta.size)

    @property
    def closure_fraction(self) -> float:
        """Fraction of grid cells in force closure [-]."""
        return float(np.mean(self.force_closure))


def contact_angles(resolution: int) -> np.ndarray:
    """The grid ``2π i / resolution``, i = 0..resolution-1 [rad]."""
    resolution = checks.integer("resolution", resolution, 4)
    return 2.0 * np.pi * np.arange(resolution) / resolution


def profile_contacts(profile, theta) -> tuple[np.ndarray, np.ndarray]:
    """Contact points and inward normals of a closed star-shaped profile at contact angles.

    Args:
        profile: an object with ``point_at_polar_angle(theta) -> (points (n,2), outward
            normals (n,2))`` (e.g. ``planner.geometry.curves.circle(0.05)``).
        theta: (n,) contact angles [rad].

    Returns:
        ``(points (n, 2) [m], inward unit normals (n, 2))``.
    """
    if not hasattr(profile, "point_at_polar_angle"):
        raise InvalidParameter(
            f"profile: expected a closed profile with point_at_polar_angle(), "
            f"got {type(profile).__name__}"
        )
    try:
        pts, out = profile.point_at_polar_angle(np.asarray(theta, dtype=float))
    except InvalidParameter:
        if not getattr(profile, "closed", False) or not hasattr(profile, "sample"):
            raise
        pts, out = _polar_from_samples(profile, np.asarray(theta, dtype=float))
    pts = np.asarray(pts, dtype=float)
    nrm = -np.asarray(out, dtype=float)
    if not (np.all(np.isfinite(pts)) and np.all(np.isfinite(nrm))):
        raise InvalidParameter("profile: expected finite points and normals, got NaN/inf")
    return pts, nrm


def _polar_from_samples(profile, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Polar lookup from dense samples, for profiles with sharp corners.

    Works around ``Profile.point_at_polar_angle`` rejecting polygons with sharp corners (the
    corner's fan samples share one polar angle). At a corner the outward normal is taken as
    the bisector of the two sides' normals (the contact normal is undefined there).
    """
    smp = profile.sample(profile.length / 8192.0)
    P, N = smp.points, smp.normals
    if np.any(np.hypot(P[:, 0], P[:, 1]) < 1e-12):
        raise InvalidParameter(
            "profile: expected a profile star-shaped about its origin, got one through it"
        )
    turn = np.diff(np.unwrap(np.arctan2(P[:, 1], P[:, 0])))
    if not (np.all(turn <= 1e-12) or np.all(turn >= -1e-12)):
        raise InvalidParameter(
            "profile: expected a profile star-shaped about its origin, got one whose polar "
            "angle is not monotonic along the outline"
        )
    phi = np.mod(np.arctan2(P[:, 1], P[:, 0]), 2 * np.pi)
    order = np.argsort(phi, kind="stable")
    phi, P, N = phi[order], P[order], N[order]
    # merge samples sharing a polar angle (corner fans): mean point and bisector normal
    uniq, start = np.unique(np.round(phi, 12), return_index=True)
    counts = np.diff(np.r_[start, phi.size])
    P = np.add.reduceat(P, start) / counts[:, None]
    N = np.add.reduceat(N, start)
    N /= np.linalg.norm(N, axis=1, keepdims=True)
    phi = np.r_[uniq[-1] - 2 * np.pi, uniq, uniq[0] + 2 * np.pi]
    P = np.vstack([P[-1:], P, P[:1]])
    N = np.vstack([N[-1:], N, N[:1]])
    th = np.mod(theta, 2 * np.pi)
    pts = np.stack([np.interp(th, phi, P[:, 0]), np.interp(th, phi, P[:, 1])], axis=-1)
    nrm = np.stack([np.interp(th, phi, N[:, 0]), np.interp(th, phi, N[:, 1])], axis=-1)
    return pts, nrm / np.linalg.norm(nrm, axis=1, keepdims=True)


class ClosureKernel:
    """Two-contact force-closure map kernel with preallocated (n, n) buffers.

    ``kernel(x, y, nx, ny)`` evaluates Nguyen's condition for every pair ``(i, j)`` of n
    contacts (points ``(x, y)``, inward normals ``(nx, ny)``, each (n,)) into a reused boolean
    array; the returned array is overwritten by the next call.

    With ``d = p_j - p_i``, the dot and cross products of contact i's normal with ``d`` are
    ``A = N P^T - (n_i . p_i)`` and ``B = N_rot P^T - (n_i x p_i)`` (two BLAS outer
    products); contact j sees ``-d``, whose products are the transposes ``A^T``, ``B^T``.
    Closure: ``|B| < mu |A|`` at i (strict by the relative margin ``STRICT``),
    ``|B^T| < mu2 |A^T|`` at j and ``A * A^T > 0``
    (forces opposed along the line, squeezing or expanding).
    """

    def __init__(self, n: int, mu: float, mu2: float | None = None):
        self.n = int(n)
        self.mu = checks.nonnegative("mu", mu)
        self.mu2 = self.mu if mu2 is None else checks.nonnegative("mu2", mu2)
        shape = (self.n, self.n)
        self._a = np.empty(shape)
        self._b = np.empty(shape)
        self._c = np.empty(shape)
        self._ok = np.empty(shape, dtype=bool)
        self._t = np.empty(shape, dtype=bool)
        self._u = np.empty(shape, dtype=bool)
        self._N = np.empty((self.n, 2))
        self._Nr = np.empty((self.n, 2))
        self._P = np.empty((2, self.n))

    def __call__(self, x, y, nx, ny) -> np.ndarray:
        a, b, c, ok, t, u = self._a, self._b, self._c, self._ok, self._t, self._u
        N, Nr, P = self._N, self._Nr, self._P
        N[:, 0], N[:, 1] = nx, ny
        Nr[:, 0], Nr[:, 1] = -ny, nx
        P[0], P[1] = x, y
        np.matmul(N, P, out=a)
        a -= np.diagonal(a)[:, None].copy()  # A[i, j] = n_i . (p_j - p_i)
        np.matmul(Nr, P, out=b)
        b -= np.diagonal(b)[:, None].copy()  # B[i, j] = n_i x (p_j - p_i)
        np.abs(b, out=b)
        b *= STRICT
        np.abs(a, out=c)
        if self.mu == self.mu2:
            c *= self.mu
            np.less(b, c, out=t)
            np.logical_and(t, t.T, out=ok)
        else:
            np.multiply(c, self.mu, out=c)
            np.less(b, c, out=t)
            np.abs(a, out=c)
            c *= self.mu2
            np.less(b, c, out=u)
            np.logical_and(t, u.T, out=ok)
        np.greater(a, 0.0, out=t)
        np.equal(t, t.T, out=u)
        ok &= u
        np.not_equal(a, 0.0, out=t)
        ok &= t
        return ok


_KERNELS = threading.local()


def closure_kernel(n: int, mu: float, mu2: float | None = None) -> ClosureKernel:
    """A cached :class:`ClosureKernel` (per thread, a few most recent sizes/frictions), so that
    repeated maps reuse their buffers instead of touching fresh memory."""
    cache = getattr(_KERNELS, "cache", None)
    if cache is None:
        cache = _KERNELS.cache = {}
    key = (int(n), float(mu), float(mu if mu2 is None else mu2))
    k = cache.get(key)
    if k is None:
        if len(cache) >= 4:
            cache.pop(next(iter(cache)))
        k = cache[key] = ClosureKernel(*key)
    return k


def grasp_map(
    profile, mu: float, resolution: int = 360, *, mu2: float | None = None, epsilon: bool = True
) -> GraspMap:
    """The two-contact grasp map of a closed planar profile (Fig. 2.4).

    Args:
        profile: closed profile star-shaped about its origin (``point_at_polar_angle``).
        mu: friction coefficient at both contacts (>= 0), or at contact 1 if ``mu2`` given.
        resolution: number of contact angles per axis (>= 4); ``theta = 2π i / resolution``.
        mu2: friction coefficient at contact 2 (e.g. the palm).
        epsilon: also compute the ε map (else it is all-NaN).

    Returns:
        The :class:`GraspMap`; ``force_closure[i, j]`` is Nguyen's exact test and
        ``epsilon[i, j]`` equals ``epsilon_quality`` of the same two contacts.
    """
    theta = contact_angles(resolution)
    mu = checks.nonnegative("mu", mu)
    mu2 = mu if mu2 is None else checks.nonnegative("mu2", mu2)
    pts, nrm = profile_contacts(profile, theta)
    fc = closure_kernel(theta.size, mu, mu2)(pts[:, 0], pts[:, 1], nrm[:, 0], nrm[:, 1]).copy()
    if epsilon:  # only on force-closure cells (ε = 0 elsewhere), one triangle when symmetric
        eps = np.zeros(fc.shape)
        ii, jj = np.nonzero(np.triu(fc, 1) if mu == mu2 else fc)
        eps[ii, jj] = epsilon_two_planar(pts[ii], nrm[ii], pts[jj], nrm[jj], mu, mu2)
        if mu == mu2:
            eps[jj, ii] = eps[ii, jj]
    else:
        eps = np.full(fc.shape, np.nan)
    return GraspMap(theta, pts, nrm, fc, eps, mu, mu2)


def hand_grasp_maps(
    profile, mu: float, resolution: int = 360, *, mu_palm: float | None = None, epsilon: bool = True
) -> dict[tuple[str, str], GraspMap]:
    """Grasp maps of the three contact pairs of a two-finger hand with a palm.

    Args:
        profile: closed star-shaped profile.
        mu: finger–object friction (>= 0); mu_palm: palm–object friction (default ``mu``).
        resolution: contact angles per axis; epsilon: also compute ε.

    Returns:
        ``{("left", "right"): map, ("left", "palm"): map, ("right", "palm"): map}``; the
        first axis of each map is the first contact of the pair.
    """
    lr = grasp_map(profile, mu, resolution, epsilon=epsilon)
    fp = (
        lr
        if mu_palm is None or mu_palm == mu
        else grasp_map(profile, mu, resolution, mu2=mu_palm, epsilon=epsilon)
    )
    return {("left", "right"): lr, ("left", "palm"): fp, ("right", "palm"): fp}


def shift_diagonal(values: np.ndarray, steps: int) -> np.ndarray:
    """Slide a map along its diagonal by ``steps`` grid cells (Leveroni's rotation rule).

    If an object is rotated counter-clockwise by ``φ = 2π steps / n``, its map indexed by world
    contact angles is ``shift_diagonal(map, steps)``: entry ``[i, j]`` of the result is entry
    ``[i - steps, j - steps]`` of the original (indices mod n).
    """
    return np.roll(np.roll(np.asarray(values), steps, axis=0), steps, axis=1)


__all__ = [
    "ClosureKernel",
    "GraspMap",
    "contact_angles",
    "grasp_map",
    "profile_contacts",
    "shift_diagonal",
]
