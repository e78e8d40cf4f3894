"""Lemke's complementary pivoting for small dense LCPs (the per-step contact problem).

Solves: find z >= 0 with w = M z + q >= 0 and w.z = 0 (Cottle, Pang & Stone, *The Linear
Complementarity Problem*, §4.4). The covering vector is all ones; the artificial variable z0
enters first, then each leaving variable's complement enters until z0 leaves (a solution) or
no row bounds the entering column (a secondary ray: no solution found).

Degenerate pivots are resolved with the **lexicographic minimum-ratio rule**: ties of the
ratio ``rhs_i / col_i`` are broken by comparing the rows of the current basis inverse divided
by ``col_i``; together with the standard preference for z0 leaving, this prevents cycling
(Cottle-Pang-Stone Thm. 4.4.4). The per-step matrices of Stewart-Trinkle time stepping are
copositive, and Lemke terminates with a solution when ``q.z >= 0`` for every ``z >= 0``
with ``M z >= 0`` and ``z.M z = 0`` (Cottle-Pang-Stone Thm. 3.8.6; Anitescu & Potra 1997).
For contact LCPs those ``z`` are self-balancing impulse sets (jammed, redundant contacts),
and ``q.z = phi.p_n / h >= 0`` holds when no contact penetrates - which is why the stepper
projects penetrations out *before* its velocity LCP. Rays are reported, not hidden.

Pivot elements below ``1e-9`` of the entering column's largest entry are treated as zero:
Stewart-Trinkle matrices carry exactly duplicated rows (two corners of a face share their
tangent row) whose roundoff differences would otherwise be chosen as pivots and wreck the
basis.

Speed: the dense tableau pivoting is compiled with numba (``cache=True``; a few microseconds
for the 4-20 unknowns of a few planar contacts). Without numba the same code runs as plain
Python (correct, ~100x slower).
"""

from __future__ import annotations

import math

import numpy as np

from planner.checks import shown
from planner.errors import InvalidParameter
from planner.jit import njit

__all__ = [
    "COVERS",
    "LCP_OK",
    "LCP_RAY",
    "LCP_MAX_ITER",
    "lcp_residual",
    "lemke_verified",
    "solve_lcp",
]

LCP_OK, LCP_RAY, LCP_MAX_ITER = 0, 1, 2


@njit(cache=True)
def _pivot(T, r, c):
    n, m = T.shape
    p = T[r, c]
    for j in range(m):
        T[r, j] /= p
    for i in range(n):
        if i != r:
            f = T[i, c]
            if f != 0.0:
                for j in range(m):
                    T[i, j] -= f * T[r, j]


@njit(cache=True)
def _lex_less(T, a, b, col, n, rhs):
    """Whether row a is lexicographically smaller than row b in (rhs, B^-1) / col."""
    ra = T[a, rhs] / T[a, col]
    rb = T[b, rhs] / T[b, col]
    tol = 1e-13 * max(1.0, abs(ra), abs(rb))
    if ra < rb - tol:
        return True
    if ra > rb + tol:
        return False
    for j in range(n):
        va = T[a, j] / T[a, col]
        vb = T[b, j] / T[b, col]
        if va < vb - 1e-13 * max(1.0, abs(va), abs(vb)):
            return True
        if va > vb + 1e-13 * max(1.0, abs(va), abs(vb)):
            return False
    return False


@njit(cache=True)
def _lemke(M, q, d, max_iter):
    n = q.shape[0]
    z = np.zeros(n)
    if n == 0:
        return z, 0, 0
    qmin = q[0] / d[0]
    r = 0
    for i in range(1, n):
        if q[i] / d[i] < qmin:
            qmin = q[i] / d[i]
            r = i
    if qmin >= 0.0:
        return z, 0, 0
    z0 = 2 * n
    rhs = 2 * n + 1
    T = np.zeros((n, 2 * n + 2))
    for i in range(n):
        T[i, i] = 1.0
        for j in range(n):
            T[i, n + j] = -M[i, j]
        T[i, z0] = -d[i]
        T[i, rhs] = q[i]
    basis = np.arange(n)
    # first pivot: z0 enters at the most negative q (ties broken lexicographically)
    for i in range(n):
        if i != r and abs(q[i] / d[i] - qmin) <= 1e-13 * max(1.0, abs(qmin)):
            if _lex_less(T, i, r, z0, n, rhs):
                r = i
    _pivot(T, r, z0)
    leaving = basis[r]
    basis[r] = z0
    entering = leaving + n
    it = 1
    while it < max_iter:
        it += 1
        cmax = 0.0
        for i in range(n):
            cmax = max(cmax, abs(T[i, entering]))
        tol = 1e-9 * cmax
        r = -1
        for i in range(n):
            if T[i, entering] > tol:
                if r < 0 or _lex_less(T, i, r, entering, n, rhs):
                    r = i
        if r < 0:
            return z, 1, it
        # prefer z0 leaving when it ties with the chosen row
        for i in range(n):
            if basis[i] == z0 and T[i, entering] > tol and i != r:
                ri = T[i, rhs] / T[i, entering]
                rr = T[r, rhs] / T[r, entering]
                if abs(ri - rr) <= 1e-13 * max(1.0, abs(rr)):
                    r = i
        _pivot(T, r, entering)
        leaving = basis[r]
        basis[r] = entering
        if leaving == z0:
            for i in range(n):
                b = basis[i]
                if n <= b < 2 * n:
                    z[b - n] = max(T[i, rhs], 0.0)
            return z, 0, it
        entering = leaving + n if leaving < n else leaving - n
    return z, 2, it


@njit(cache=True)
def _residual(M, q, z):
    n = q.shape[0]
    if n == 0:
        return 0.0
    scale = 1.0
    zmax = 1.0
    bad = 0.0
    wz = 0.0
    for i in range(n):
        scale = max(scale, abs(q[i]))
        zmax = max(zmax, z[i])
        bad = max(bad, -z[i])
        w = q[i]
        for j in range(n):
            w += M[i, j] * z[j]
        if not (math.isfinite(w) and math.isfinite(z[i])):
            return np.inf  # max() would drop a NaN: NaN in M, q or z is never verified
        bad = max(bad, -w)
        wz += w * z[i]
    return max(bad, abs(wz) / zmax) / scale


def lcp_residual(M: np.ndarray, q: np.ndarray, z: np.ndarray) -> float:
    """Largest violation of ``z >= 0, w = M z + q >= 0, z.w = 0``, relative to ``max(1, |q|)``.

    The complementarity gap ``|z.w|`` is divided by ``max(1, max z)``. A non-finite ``w`` or
    ``z`` (NaN or inf in ``M``, ``q`` or ``z``) gives ``inf``: such an answer never passes.
    """
    M = np.ascontiguousarray(M, dtype=float)
    return float(_residual(M, np.ascontiguousarray(q, float), np.ascontiguousarray(z, float)))


@njit(cache=True)
def lemke_verified(M, q, covers, max_iter, tol):
    """Scaled Lemke with verified answers and cover retries (compiled core of solve_lcp).

    Returns ``(z, status, pivots)``; see :func:`solve_lcp`.
    """
    n = q.shape[0]
    s = np.ones(n)
    for i in range(n):
        if M[i, i] > 0.0:
            s[i] = 1.0 / np.sqrt(M[i, i])
    Ms = np.empty((n, n))
    qs = np.empty(n)
    for i in range(n):
        qs[i] = s[i] * q[i]
        for j in range(n):
            Ms[i, j] = s[i] * M[i, j] * s[j]
    status, pivots = 1, 0
    z = np.zeros(n)
    d = np.ones(n)
    for k in range(covers.shape[0] + 1):
        if k > 0:
            for i in range(n):
                d[i] = covers[k - 1, i % covers.shape[1]]
        zs, status, pivots = _lemke(Ms, qs, d, max_iter)
        for i in range(n):
            z[i] = s[i] * zs[i]
        if status == 0:
            if _residual(M, q, z) <= tol:
                return z, 0, pivots
            status = 1
    return z, status, pivots


def solve_lcp(M: np.ndarray, q: np.ndarray, max_iter: int | None = None, tol: float = 1e-9):
    """Solve the LCP ``w = M z + q >= 0, z >= 0, w.z = 0`` by Lemke's method.

    The problem is first scaled symmetrically by ``1/sqrt(M_ii)`` (rows and columns with a
    positive diagonal), which leaves the solution set unchanged and evens out the mixed
    units of contact LCPs. Lemke runs with the covering vector of ones; if it ends on a ray
    or its answer fails the residual check (w >= -tol, |w.z| <= tol, relative to max|q|),
    it is rerun with up to eight other fixed positive covering vectors (deterministic) - a
    different complementary path, the standard remedy when roundoff in degenerate pivots
    leads the first path astray. Every answer returned passed the residual check; a NaN or
    an infinity in ``M`` or ``q`` fails it (status ``LCP_RAY``, never ``LCP_OK``).

    Args:
        M: (n, n) matrix of numbers.
        q: (n,) vector of numbers.
        max_iter: pivot limit per path (default ``50 n + 10``).
        tol: residual tolerance (relative to ``max(1, max|q|)``).

    Returns:
        ``(z, status, pivots)``: the (n,) solution, ``LCP_OK`` (0), ``LCP_RAY`` (1: every
        path ended on a ray or failed the check) or ``LCP_MAX_ITER`` (2), and the pivot count
        of the last path.

    Raises:
        InvalidParameter: ``q`` is not a vector of numbers, or ``M`` not a matching square
            matrix of numbers.
    """
    q = _numbers("q", q, "(n,)")
    if q.ndim != 1:
        raise InvalidParameter(f"q: expected a vector of shape (n,), got shape {q.shape}")
    n = q.shape[0]
    M = _numbers("M", M, f"({n}, {n})")
    if M.shape != (n, n):
        raise InvalidParameter(f"M must have shape ({n}, {n}) to match q, got {M.shape}")
    it = int(max_iter if max_iter is not None else 50 * n + 10)
    z, status, pivots = lemke_verified(M, q, COVERS, it, float(tol))
    return z, int(status), int(pivots)


def _numbers(name: str, value: object, shape: str) -> np.ndarray:
    """``value`` as a contiguous float array, or InvalidParameter naming ``name``."""
    try:
        return np.ascontiguousarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InvalidParameter(
            f"{name}: expected an array of numbers of shape {shape}, got {shown(value)}"
        ) from None


COVERS = np.random.default_rng(20260101).uniform(0.5, 2.0, size=(8, 64))
"""Covering vectors of the retries (fixed: runs are deterministic)."""
