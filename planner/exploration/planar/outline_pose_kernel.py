"""Compiled residuals of the posed outline (:func:`.outline_pose.residuals`, same maths).

Why compiled: the least-squares pose fits evaluate the residuals tens of thousands of times
per run (3-point Jacobians, the global search's starts), and on a 3-4 vertex polygon each
numpy evaluation was ~290 us of array-call overhead for microseconds of arithmetic: the
posed-outline runs of a triangle spent 25 of 50 s there (3 s simulated). Here one
evaluation is a few microseconds; the numpy functions of :mod:`.outline_pose` stay the
reference (``tests/test_gait_shape.py`` compares the two).

The reading is packed in one float array (:func:`pack`), so that the kernel's signature
does not depend on which constraints are sensed:
``[has_pad, pad_x, pad_y, pad_angle, pad_u (NaN: unused), half_width, u_max, has_tip,
tip_x, tip_y, tip_radius, palm, theta_prior (NaN: none), theta_weight, flat_tol,
u_weight]``.
"""

from __future__ import annotations

import math

import numpy as np

from planner.jit import njit

#: length of a packed reading (:func:`pack`)
NREAD = 16
#: corners of an outline beside the pad's strip whose distances from it differ by less than
#: this are tied [m]; the highest of them (along the pad's normal) is taken. A face across
#: the strip's edge has two: which one the nearest-distance search returned depended on the
#: last bit of the distances (NumPy's matrix product against this loop), and the pad
#: residual jumped by the face's length (0.11 m on an 11 cm square). The highest is what
#: the window gives once it reaches the face, so the residual is continuous there.
BESIDE_TIE = 1e-12


def pack(rd, theta_prior, theta_weight: float, flat_tol: float, u_weight: float) -> np.ndarray:
    """The ``Readings`` ``rd`` and the rotation prior as the kernel's float array."""
    r = np.zeros(NREAD)
    if rd.pad_point is not None:
        r[0], r[1], r[2] = 1.0, float(rd.pad_point[0]), float(rd.pad_point[1])
        r[3], r[4] = float(rd.pad_angle), float(rd.pad_u)
    r[5], r[6] = float(rd.pad_half_width), float(rd.pad_u_max)
    if rd.tip_centre is not None:
        r[7], r[8], r[9] = 1.0, float(rd.tip_centre[0]), float(rd.tip_centre[1])
    r[10], r[11] = float(rd.tip_radius), 1.0 if rd.palm else 0.0
    use_prior = theta_prior is not None and theta_weight > 0
    r[12] = float(theta_prior) if use_prior else math.nan
    r[13], r[14], r[15] = float(theta_weight), float(flat_tol), float(u_weight)
    return r


@njit(cache=True, nogil=True)
def _clip(P, n, ax, ay, b, out):
    """Sutherland-Hodgman: the part ``a . x <= b`` of the closed polygon ``P[:n]`` into
    ``out`` (vertex, then the crossing after it, as :func:`.outline_pose.clip_halfplane`);
    returns its vertex count."""
    m = 0
    for i in range(n):
        j = i + 1 if i + 1 < n else 0
        sp = P[i, 0] * ax + P[i, 1] * ay - b
        sq = P[j, 0] * ax + P[j, 1] * ay - b
        if sp <= 0.0:
            out[m, 0], out[m, 1] = P[i, 0], P[i, 1]
            m += 1
        if (sp <= 0.0) != (sq <= 0.0):
            w = sp / (sp - sq)
            out[m, 0] = P[i, 0] + w * (P[j, 0] - P[i, 0])
            out[m, 1] = P[i, 1] + w * (P[j, 1] - P[i, 1])
            m += 1
    return m


@njit(cache=True, nogil=True)
def _nearest_distance(W, n, px, py):
    """Distance [m] of ``(px, py)`` from the closed polygon ``W[:n]`` (over its segments)."""
    best = math.inf
    for i in range(n):
        j = i + 1 if i + 1 < n else 0
        abx, aby = W[j, 0] - W[i, 0], W[j, 1] - W[i, 1]
        t = ((px - W[i, 0]) * abx + (py - W[i, 1]) * aby) / max(abx * abx + aby * aby, 1e-300)
        t = min(max(t, 0.0), 1.0)
        d = math.hypot(W[i, 0] + t * abx - px, W[i, 1] + t * aby - py)
        if d < best:
            best = d
    return best


@njit(cache=True, nogil=True)
def residuals(P, x, y, a, rd, out):
    """The residuals [m] of the outline ``P`` (M, 2) (object frame) at the pose
    ``(x, y, a)`` for the packed reading ``rd`` into ``out`` (at least 5 long), in the order
    pad line, pad centroid, tip, palm, rotation prior (unsensed ones left out); returns
    their count."""
    M = P.shape[0]
    c, s = math.cos(a), math.sin(a)
    W = np.empty((M, 2))
    for i in range(M):
        W[i, 0] = x + c * P[i, 0] - s * P[i, 1]
        W[i, 1] = y + s * P[i, 0] + c * P[i, 1]
    k = 0
    if rd[0] != 0.0:
        px, py, hw = rd[1], rd[2], rd[5]
        cn, sn = math.cos(rd[3]), math.sin(rd[3])
        nx, ny, tx, ty = sn, -cn, cn, sn
        A = np.empty((2 * M, 2))
        B = np.empty((4 * M, 2))
        m = _clip(W, M, tx, ty, tx * px + ty * py + hw, A)
        if m > 0:
            m = _clip(A, m, -tx, -ty, -(tx * px + ty * py) + hw, B)
        if m == 0:  # the outline is beside the pad: its nearest corner to the strip
            dmin = math.inf
            for i in range(M):
                dmin = min(dmin, abs((W[i, 0] - px) * tx + (W[i, 1] - py) * ty))
            j, hj = 0, -math.inf
            for i in range(M):  # of tied corners (BESIDE_TIE) the highest
                d = abs((W[i, 0] - px) * tx + (W[i, 1] - py) * ty)
                h = W[i, 0] * nx + W[i, 1] * ny
                if d <= dmin + BESIDE_TIE and h > hj:
                    j, hj = i, h
            B[0, 0], B[0, 1] = W[j, 0], W[j, 1]
            m = 1
        hmax = -math.inf
        for i in range(m):
            hmax = max(hmax, B[i, 0] * nx + B[i, 1] * ny)
        out[k] = hmax - (nx * px + ny * py)
        k += 1
        if not math.isnan(rd[4]):
            lo, hi = math.inf, -math.inf
            for i in range(m):
                if B[i, 0] * nx + B[i, 1] * ny >= hmax - rd[14]:
                    along = (B[i, 0] - px) * tx + (B[i, 1] - py) * ty
                    lo, hi = min(lo, along), max(hi, along)
            mid = min(max(0.5 * (lo + hi), -rd[6]), rd[6])
            out[k] = rd[15] * (mid - rd[4])
            k += 1
    if rd[7] != 0.0:
        out[k] = _nearest_distance(W, M, rd[8], rd[9]) - rd[10]
        k += 1
    if rd[11] != 0.0:
        low = math.inf
        for i in range(M):
            low = min(low, W[i, 1])
        out[k] = low
        k += 1
    if not math.isnan(rd[12]):
        out[k] = rd[13] * (a - rd[12])
        k += 1
    return k


#: scipy's relative step of a 3-point difference, ``EPS ** (1 / 3)``
#: (``scipy.optimize._numdiff._eps_for_method``)
REL_STEP_3POINT = np.finfo(float).eps ** (1.0 / 3.0)


@njit(cache=True, nogil=True)
def jacobian(P, x, rd, J):
    """The residuals' 3-point (central) difference Jacobian at the pose ``x`` (3,) into
    ``J`` (at least (5, 3)); returns the residual count. Exactly scipy's
    ``approx_derivative(method="3-point")`` without bounds (the step
    ``REL_STEP_3POINT * sign(x) * max(1, |x|)`` with ``sign(0) = 1``, the divisor the
    difference of the two perturbed coordinates), so a fit with this Jacobian equals one
    with ``jac="3-point"`` - without scipy's per-evaluation Python."""
    lo = np.empty(5)
    hi = np.empty(5)
    k = 0
    for i in range(3):
        sign = 1.0 if x[i] >= 0.0 else -1.0
        h = REL_STEP_3POINT * sign * max(1.0, abs(x[i]))
        a = x.copy()
        b = x.copy()
        a[i] = x[i] - h
        b[i] = x[i] + h
        k = residuals(P, a[0], a[1], a[2], rd, lo)
        residuals(P, b[0], b[1], b[2], rd, hi)
        dx = b[i] - a[i]
        for r in range(k):
            J[r, i] = (hi[r] - lo[r]) / dx
    return k


__all__ = ["NREAD", "REL_STEP_3POINT", "jacobian", "pack", "residuals"]
