"""Scalar kernels of the 3GM's contact step on a plate (the hot path; numba-compiled when
numba is installed, plain Python otherwise — same code, same results).

The profile of the 3GM ridge scene showed ~60 small numpy operations per step (3x3 products,
frames, copies), each costing more than its arithmetic. These kernels do the same
computations in scalar arithmetic:

* :func:`plate_eval` / :func:`plate_foot`: the plate's height and derivatives
  (:meth:`planner.sim.spatial.Plate.height_derivatives`, features packed by
  :func:`pack_plate`) and the Newton foot point of :mod:`planner.sim.spatial.closest`;
* :func:`finger_contact`: the fingertip's candidate contact, its Delassus operator
  ``W = J_c M_r⁻¹ J_cᵀ``, the exact circular-cone solution
  (:mod:`planner.sim.spatial.friction_cone`: separate / stick / slide by Newton on ``g(φ)``)
  and the post-contact velocities. When the sliding Newton does not return a valid root it
  reports ``status = -1`` and the caller falls back to the general numpy path (roots of the
  quartic).

Tests compare every kernel with the general path to round-off.
"""

from __future__ import annotations

import math

import numpy as np

try:  # optional accelerator
    from numba import njit as _njit

    def _jit(f):
        return _njit(cache=True, fastmath=False)(f)

    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - depends on the environment

    def _jit(f):
        return f

    HAVE_NUMBA = False

__all__ = [
    "HAVE_NUMBA",
    "finger_contact",
    "owts_sample_decode",
    "pack_plate",
    "plate_eval",
    "plate_foot",
    "plate_foot_world",
]

_KINDS = {"ridge": 0, "ravine": 1, "step": 2, "bump": 3, "pit": 4, "cusp": 5, "wire": 6}


def pack_plate(plate) -> tuple[np.ndarray, np.ndarray]:
    """``(F, P)``: (k, 10) rows ``(kind code, h, w, x_k, y_k, cos ψ, sin ψ, ρ, first, count)``
    of a plate's features and the (m, 2) points of their paths (``count`` 0: no path)."""
    rows, pts = [], []
    for f in plate.features:
        c, s = math.cos(f.across), math.sin(f.across)
        path = f.path or ()
        row = (_KINDS[f.kind], f.height, f.width, *f.position, c, s, f.rounding)
        rows.append((*row, len(pts), len(path)))
        pts += list(path)
    return np.array(rows, float).reshape(-1, 10), np.array(pts, float).reshape(-1, 2)


@_jit
def _profile(kind, h, w, rho, s):
    if kind <= 1:
        sg = 1.0 if kind == 0 else -1.0
        e = h * math.exp(-s * s / (2 * w * w))
        return sg * e, -sg * s / (w * w) * e, sg * (s * s / w**4 - 1 / (w * w)) * e
    if kind == 2:
        t = math.tanh(s / w)
        return h * (1 + t) / 2, h / (2 * w) * (1 - t * t), -h / (w * w) * t * (1 - t * t)
    if kind <= 4:
        sg = 1.0 if kind == 3 else -1.0
        d = 1.0 + s * s / (w * w)
        return (
            sg * h / d,
            -sg * 2 * h * s / (w * w * d * d),
            sg * h * (6 * s * s / w**2 - 2) / (w * w * d**3),
        )
    if kind == 5:
        m = h / w
        q = math.sqrt(s * s + rho * rho)
        return -m * (q - rho), -m * s / q, -m * rho * rho / q**3
    R = h / 2
    xc = 2 * math.sqrt(R * rho)
    xt = R * xc / (R + rho)
    a = abs(s)
    sg = 1.0 if s >= 0 else -1.0
    if a <= xt:
        q = math.sqrt(R * R - s * s)
        return R + q, -s / q, -(R * R) / q**3
    if a < xc:
        e = a - xc
        q = math.sqrt(rho * rho - e * e)
        return rho - q, sg * e / q, rho * rho / q**3
    return 0.0, 0.0, 0.0


@_jit
def _radial(kind, h, w, rho, dx, dy):
    r = math.hypot(dx, dy)
    Z, Z1, Z2 = _profile(kind, h, w, rho, r)
    if r < 1e-300:
        return Z, 0.0, 0.0, Z2, 0.0, Z2
    ux, uy = dx / r, dy / r
    t = Z1 / r
    return (
        Z,
        Z1 * ux,
        Z1 * uy,
        Z2 * ux * ux + t * (1 - ux * ux),
        (Z2 - t) * ux * uy,
        Z2 * uy * uy + t * (1 - uy * uy),
    )


@_jit
def _path(kind, h, w, rho, P, first, count, x, y):
    if count == 1:
        return _radial(kind, h, w, rho, x - P[first, 0], y - P[first, 1])
    best, on_vertex, vx, vy, sd, nx, ny = 1e300, True, P[first, 0], P[first, 1], 0.0, 0.0, 0.0
    for j in range(first, first + count - 1):
        ax, ay, bx, by = P[j, 0], P[j, 1], P[j + 1, 0], P[j + 1, 1]
        ex, ey = bx - ax, by - ay
        L2 = ex * ex + ey * ey
        t = ((x - ax) * ex + (y - ay) * ey) / L2
        if 0.0 < t < 1.0:
            L = math.sqrt(L2)
            mx, my = -ey / L, ex / L
            dist = (x - ax) * mx + (y - ay) * my
            if abs(dist) < best:
                best, on_vertex, sd, nx, ny = abs(dist), False, dist, mx, my
        else:
            qx, qy = (ax, ay) if t <= 0.0 else (bx, by)
            dist = math.hypot(x - qx, y - qy)
            if dist < best:
                best, on_vertex, vx, vy = dist, True, qx, qy
    if on_vertex:
        return _radial(kind, h, w, rho, x - vx, y - vy)
    Z, Z1, Z2 = _profile(kind, h, w, rho, sd)
    return Z, Z1 * nx, Z1 * ny, Z2 * nx * nx, Z2 * nx * ny, Z2 * ny * ny


@_jit
def plate_eval(F, P, base, x, y):
    """``(h, h_x, h_y, h_xx, h_xy, h_yy)`` of the packed plate ``(F, P)`` at ``(x, y)``."""
    h, hx, hy, hxx, hxy, hyy = base, 0.0, 0.0, 0.0, 0.0, 0.0
    for i in range(F.shape[0]):
        kind = int(F[i, 0])
        count = int(F[i, 9])
        if count > 0 or kind == 3 or kind == 4:
            if count > 0:
                d = _path(kind, F[i, 1], F[i, 2], F[i, 7], P, int(F[i, 8]), count, x, y)
            else:
                d = _radial(kind, F[i, 1], F[i, 2], F[i, 7], x - F[i, 3], y - F[i, 4])
            h += d[0]
            hx += d[1]
            hy += d[2]
            hxx += d[3]
            hxy += d[4]
            hyy += d[5]
            continue
        dx, dy = x - F[i, 3], y - F[i, 4]
        c, s = F[i, 5], F[i, 6]
        Z, Z1, Z2 = _profile(kind, F[i, 1], F[i, 2], F[i, 7], dx * c + dy * s)
        h += Z
        hx += Z1 * c
        hy += Z1 * s
        hxx += Z2 * c * c
        hxy += Z2 * c * s
        hyy += Z2 * s * s
    return h, hx, hy, hxx, hxy, hyy


@_jit
def plate_foot(F, P, base, cx, cy, cz, x, y):
    """Foot of ``(cx, cy, cz)`` on the plate (plate frame), Newton from ``(x, y)``:
    ``(x, y, h, n_x, n_y, n_z, distance)`` (as :func:`.closest._newton_graph`)."""
    h, hx, hy = 0.0, 0.0, 0.0
    done = False
    for _ in range(50):
        h, hx, hy, hxx, hxy, hyy = plate_eval(F, P, base, x, y)
        e = h - cz
        gx = x - cx + e * hx
        gy = y - cy + e * hy
        a = 1.0 + hx * hx + e * hxx
        b = hx * hy + e * hxy
        d = 1.0 + hy * hy + e * hyy
        det = a * d - b * b
        if a <= 0.0 or det <= 1e-12 * (a * d + 1e-300):
            lam = abs(min(a, d)) + 1.0
            a, d = a + lam, d + lam
            det = a * d - b * b
        dx = (d * gx - b * gy) / det
        dy = (a * gy - b * gx) / det
        x -= dx
        y -= dy
        if abs(dx) + abs(dy) <= 1e-13:
            h -= hx * dx + hy * dy
            done = True
            break
    if not done:
        h, hx, hy, hxx, hxy, hyy = plate_eval(F, P, base, x, y)
    nrm = math.sqrt(1.0 + hx * hx + hy * hy)
    nx, ny, nz = -hx / nrm, -hy / nrm, 1.0 / nrm
    dist = (cx - x) * nx + (cy - y) * ny + (cz - h) * nz
    return x, y, h, nx, ny, nz, dist


@_jit
def plate_foot_world(F, P, base, R, t, c, x, y, out):
    """:func:`plate_foot` of a WCS point ``c`` (3,) for the plate placed by ``(R, t)``:
    ``out`` (9,) = foot point (3) and normal (3) in the WCS, distance, plate-frame hint (2)."""
    d0, d1, d2 = c[0] - t[0], c[1] - t[1], c[2] - t[2]
    cx = R[0, 0] * d0 + R[1, 0] * d1 + R[2, 0] * d2
    cy = R[0, 1] * d0 + R[1, 1] * d1 + R[2, 1] * d2
    cz = R[0, 2] * d0 + R[1, 2] * d1 + R[2, 2] * d2
    x, y, h, nx, ny, nz, dist = plate_foot(F, P, base, cx, cy, cz, x, y)
    for i in range(3):
        out[i] = R[i, 0] * x + R[i, 1] * y + R[i, 2] * h + t[i]
        out[3 + i] = R[i, 0] * nx + R[i, 1] * ny + R[i, 2] * nz
    out[6], out[7], out[8] = dist, x, y


@_jit
def _slide(W, ut0, ut1, un, mu, phi):
    a, w1, w2 = W[0, 0], W[1, 0], W[2, 0]
    t11, t12, t22 = W[1, 1], W[1, 2], W[2, 2]
    dt_ = t22 - t11
    ok = False
    for _ in range(30):
        c, s = math.cos(phi), math.sin(phi)
        A = a - mu * (w1 * c + w2 * s)
        B = -s * ut0 + c * ut1
        P = dt_ * c * s + t12 * (c * c - s * s)
        Q = -s * w1 + c * w2
        g = A * B + un * (mu * P - Q)
        dA = -mu * (-w1 * s + w2 * c)
        dB = -c * ut0 - s * ut1
        dP = dt_ * (c * c - s * s) - 4.0 * t12 * c * s
        dQ = -c * w1 - s * w2
        dg = dA * B + A * dB + un * (mu * dP - dQ)
        if dg == 0.0:
            break
        step = g / dg
        phi -= step
        if abs(step) <= 1e-15:
            ok = True
            break
    c, s = math.cos(phi), math.sin(phi)
    den = a - mu * (w1 * c + w2 * s)
    if not ok or den <= 0.0:
        return False, 0.0, 0.0, 0.0
    lam_n = -un / den
    u0 = ut0 + lam_n * (w1 - mu * (t11 * c + t12 * s))
    u1 = ut1 + lam_n * (w2 - mu * (t12 * c + t22 * s))
    slip = c * u0 + s * u1
    if lam_n < 0.0 or slip < 0.0 or abs(-s * u0 + c * u1) > 1e-12 * abs(slip) + 1e-15:
        return False, 0.0, 0.0, 0.0
    return True, lam_n, -mu * lam_n * c, -mu * lam_n * s


@_jit
def finger_contact(F, P, base, R, t, center, hx0, hy0, radius, J, Jw, Minv, thd, h, mu, reach, out):
    """Candidate contact of the fingertip with a placed plate and its exact solution.

    Args:
        F, P, base: packed plate (:func:`pack_plate`); R, t: its pose ``T_WS``;
        center: (3,) tip centre [m, WCS]; hx0, hy0: warm start of the foot (plate frame);
        radius [m]; J, Jw, Minv (3, 3);
        thd: (3,) free joint rates; h: time step [s]; mu; reach: candidate margin [m].
        out: (26,) output buffer: ``status`` (0 no candidate, 1 separate, 2 stick, 3 slide,
        -1 fall back), ``λ`` (3) [N s], ``θ̇⁺`` (3), normal (3), foot point (3), ``u⁺`` (3),
        ``t1`` (3), ``t2`` (3), gap [m], foot hint (2).
    """
    cs0 = center[0] - t[0]
    cs1 = center[1] - t[1]
    cs2 = center[2] - t[2]
    cx = R[0, 0] * cs0 + R[1, 0] * cs1 + R[2, 0] * cs2
    cy = R[0, 1] * cs0 + R[1, 1] * cs1 + R[2, 1] * cs2
    cz = R[0, 2] * cs0 + R[1, 2] * cs1 + R[2, 2] * cs2
    x, y, hz, nx_, ny_, nz_, dist = plate_foot(F, P, base, cx, cy, cz, hx0, hy0)
    gap = dist - radius
    out[24], out[25], out[23] = x, y, gap
    for i in range(3):
        out[7 + i] = R[i, 0] * nx_ + R[i, 1] * ny_ + R[i, 2] * nz_
        out[10 + i] = R[i, 0] * x + R[i, 1] * y + R[i, 2] * hz + t[i]
    if gap > reach:
        out[0] = 0.0
        return
    n0, n1, n2 = out[7], out[8], out[9]
    if abs(n0) < 0.9:
        a, b, c = 1.0 - n0 * n0, -n0 * n1, -n0 * n2
    else:
        a, b, c = -n1 * n0, 1.0 - n1 * n1, -n1 * n2
    k = 1.0 / math.sqrt(a * a + b * b + c * c)
    a, b, c = a * k, b * k, c * k
    C = np.empty((3, 3))
    C[0, 0], C[0, 1], C[0, 2] = n0, n1, n2
    C[1, 0], C[1, 1], C[1, 2] = a, b, c
    C[2, 0], C[2, 1], C[2, 2] = n1 * c - n2 * b, n2 * a - n0 * c, n0 * b - n1 * a
    # contact-point Jacobian J + r [n]x Jw, in the contact frame
    Jp = np.empty((3, 3))
    for j in range(3):
        w0, w1, w2 = Jw[0, j], Jw[1, j], Jw[2, j]
        Jp[0, j] = J[0, j] + radius * (n1 * w2 - n2 * w1)
        Jp[1, j] = J[1, j] + radius * (n2 * w0 - n0 * w2)
        Jp[2, j] = J[2, j] + radius * (n0 * w1 - n1 * w0)
    Jc = C @ Jp
    MJt = Minv @ Jc.T
    W = Jc @ MJt
    W = 0.5 * (W + W.T)
    u = Jc @ thd
    un = u[0] + gap / h
    lam0, lam1, lam2 = 0.0, 0.0, 0.0
    status = 1.0
    if un < 0.0:
        # stick: -W^-1 (un, u1, u2)
        A_, B_, C_ = (
            W[1, 1] * W[2, 2] - W[1, 2] * W[2, 1],
            W[1, 2] * W[2, 0] - W[1, 0] * W[2, 2],
            W[1, 0] * W[2, 1] - W[1, 1] * W[2, 0],
        )
        det = W[0, 0] * A_ + W[0, 1] * B_ + W[0, 2] * C_
        D_, E_, F_ = (
            W[0, 2] * W[2, 1] - W[0, 1] * W[2, 2],
            W[0, 0] * W[2, 2] - W[0, 2] * W[2, 0],
            W[0, 1] * W[2, 0] - W[0, 0] * W[2, 1],
        )
        G_, H_, I_ = (
            W[0, 1] * W[1, 2] - W[0, 2] * W[1, 1],
            W[0, 2] * W[1, 0] - W[0, 0] * W[1, 2],
            W[0, 0] * W[1, 1] - W[0, 1] * W[1, 0],
        )
        lam0 = -(A_ * un + D_ * u[1] + G_ * u[2]) / det
        lam1 = -(B_ * un + E_ * u[1] + H_ * u[2]) / det
        lam2 = -(C_ * un + F_ * u[1] + I_ * u[2]) / det
        status = 2.0
        if not (lam0 >= 0.0 and math.hypot(lam1, lam2) <= mu * lam0):
            status = 3.0
            if mu <= 1e-14:
                lam0, lam1, lam2 = -un / W[0, 0], 0.0, 0.0
            else:
                if lam1 != 0.0 or lam2 != 0.0:
                    phi = math.atan2(-lam2, -lam1)
                else:
                    phi = math.atan2(u[2], u[1])
                ok, lam0, lam1, lam2 = _slide(W, u[1], u[2], un, mu, phi)
                if not ok:
                    out[0] = -1.0
                    return
    out[0] = status
    out[1], out[2], out[3] = lam0, lam1, lam2
    for i in range(3):
        v = thd[i] + MJt[i, 0] * lam0 + MJt[i, 1] * lam1 + MJt[i, 2] * lam2
        out[4 + i] = v
    for i in range(3):
        out[13 + i] = Jc[i, 0] * out[4] + Jc[i, 1] * out[5] + Jc[i, 2] * out[6]
        out[16 + i] = C[1, i]
        out[19 + i] = C[2, i]
    out[22] = 0.0


@_jit
def owts_sample_decode(rows, noise, prm, v_out, p_out, n_out, on_out):
    """:meth:`robots.sensors.OWTSSampler.sample` then :meth:`robots.sensors.OWTS.
    contact_from_voltages` (eqs. C.1-C.3) for K rows ``(normal_tcs (3), intensity,
    friction_tcs (3))`` with the sampler's noise ``noise`` (2K,) (x then y offsets) and the
    packed settings ``prm`` (:func:`planner.sim.spatial.sensing._params`)."""
    scale, side, xo, yo, fod, lsb = prm[0], prm[1], prm[2], prm[3], prm[4], prm[5]
    gain, smax, nl, k1, k2, rmax = prm[6], prm[7], prm[8], prm[9], prm[10], prm[11]
    radius, thresh, full = prm[12], prm[13], prm[14]
    k = rows.shape[0]
    g = 2.0 / side
    half = 0.5 * side
    for i in range(k):
        nx, ny, nz = rows[i, 0], rows[i, 1], rows[i, 2]
        norm = math.sqrt(nx * nx + ny * ny + nz * nz)
        on = norm > 1e-12
        if on:
            nx, ny, nz = nx / norm, ny / norm, nz / norm
        else:
            nx, ny, nz = 0.0, 0.0, 0.0
        if gain > 0:
            fx, fy, fz = rows[i, 4], rows[i, 5], rows[i, 6]
            d = fx * nx + fy * ny + fz * nz
            fx, fy, fz = fx - d * nx, fy - d * ny, fz - d * nz
            mag = math.sqrt(fx * fx + fy * fy + fz * fz)
            ang = min(gain * mag, smax)
            m = mag if mag > 0 else 1.0
            ca, sa = math.cos(ang), math.sin(ang)
            nx, ny, nz = ca * nx + sa * fx / m, ca * ny + sa * fy / m, ca * nz + sa * fz / m
        theta = math.acos(min(max(nz, -1.0), 1.0))
        on = on and theta <= fod
        phi = math.atan2(ny, nx)
        rho = theta / scale
        if nl > 0:
            r = rho / rmax
            rho = rho * (1.0 + k1 * r * r + k2 * r**4)
        x = rho * math.cos(phi) + noise[i]
        y = rho * math.sin(phi) + noise[k + i]
        sx = min(max(g * x + xo, -1.0), 1.0)
        sy = min(max(g * y + yo, -1.0), 1.0)
        q = (rows[i, 3] * full if on else 0.0) / 4.0
        v_out[i, 0] = q * (1 + sx) * (1 - sy)
        v_out[i, 1] = q * (1 - sx) * (1 + sy)
        v_out[i, 2] = q * (1 + sx) * (1 + sy)
        v_out[i, 3] = q * (1 - sx) * (1 - sy)
        for j in range(4):
            v_out[i, j] = min(max(np.rint(v_out[i, j] / lsb) * lsb, 0.0), full)
        v1, v2, v3, v4 = v_out[i, 0], v_out[i, 1], v_out[i, 2], v_out[i, 3]
        S = v1 + v2 + v3 + v4
        on_out[i] = S > thresh
        if not on_out[i]:
            for j in range(3):
                p_out[i, j] = 0.0
                n_out[i, j] = 0.0
            continue
        xd = ((v1 - v2 + v3 - v4) / S - xo) * half
        yd = ((-v1 + v2 + v3 - v4) / S - yo) * half
        th = scale * math.hypot(xd, yd)
        kk = scale * (math.sin(th) / th if th > 0 else 1.0)
        n_out[i, 0], n_out[i, 1], n_out[i, 2] = xd * kk, yd * kk, math.cos(th)
        for j in range(3):
            p_out[i, j] = radius * n_out[i, j]
