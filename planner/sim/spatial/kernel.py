"""Scalar kernels of the 3GM's contact step on a plate (the hot path; numba-compiled when
numba is installed, plain Python otherwise — same code, same results).

The profile of the 3GM ridge scene showed ~60 small numpy operations per step (3x3 products,
frames, copies), each costing more than its arithmetic. These kernels do the same
computations in scalar arithmetic:

* :func:`plate_eval` / :func:`plate_foot`: the plate's height and derivatives
  (:meth:`planner.sim.spatial.Plate.height_derivatives`, features packed by
  :func:`pack_plate`) and the Newton foot point of :mod:`planner.sim.spatial.closest`;
* :func:`owts_sample_decode` and :func:`joint_force_readings`: the sensors read from the
  state (the contact step itself is :mod:`planner.sim.spatial.step_kernel`).

Tests compare every kernel with the general path to round-off.
"""

from __future__ import annotations

import math

import numpy as np

from planner.jit import njit


def _jit(f):
    return njit(cache=True, fastmath=False)(f)


__all__ = [
    "finger_readings",
    "joint_force_readings",
    "owts_sample_decode",
    "pack_plate",
    "plate_eval",
    "plate_foot",
    "plate_other_feet",
    "plate_seed",
]

#: most feet besides the primary one that :func:`plate_other_feet` reports
MAX_OTHER_FEET = 3
#: grid samples per side of :func:`plate_other_feet`'s search under the sphere
OTHER_FEET_GRID = 11
#: feet nearer each other than this are one foot [m]
FOOT_SEPARATION = 1e-6

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
    return plate_eval_some(F, P, base, None, F.shape[0], x, y)


@_jit
def plate_eval_some(F, P, base, idx, n, x, y):
    """:func:`plate_eval` over the features ``idx[:n]`` alone (``idx`` None: the first ``n``)
    added to ``base``."""
    h, hx, hy, hxx, hxy, hyy = base, 0.0, 0.0, 0.0, 0.0, 0.0
    for j in range(n):
        i = j if idx is None else idx[j]
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
    ``(x, y, h, n_x, n_y, n_z, distance, converged)`` (as :func:`.closest._newton_graph`)."""
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
    return x, y, h, nx, ny, nz, dist, done


@_jit
def plate_seed(F, P, base, cx, cy, cz):
    """:func:`planner.sim.spatial.closest.graph_seed` on the packed plate: ``(x, y)`` of the
    grid sample nearest ``(cx, cy, cz)`` (plate frame) under the sphere."""
    radius = max(abs(cz - plate_eval(F, P, base, cx, cy)[0]), 1e-6)
    k = 33
    best, bx, by = 1e300, cx, cy
    for i in range(k):
        y = cy - radius + 2.0 * radius * i / (k - 1)
        for j in range(k):
            x = cx - radius + 2.0 * radius * j / (k - 1)
            z = plate_eval(F, P, base, x, y)[0]
            d2 = (x - cx) ** 2 + (y - cy) ** 2 + (z - cz) ** 2
            if d2 < best:
                best, bx, by = d2, x, y
    return bx, by


@_jit
def _support_distance(F, P, i, x, y):
    """Horizontal distance [m] from ``(x, y)`` to feature ``i``'s crest: its path (polyline or
    point), its centre (bump, pit) or its crest line."""
    kind, count = int(F[i, 0]), int(F[i, 9])
    if count == 0:
        if kind == 3 or kind == 4:
            return math.hypot(x - F[i, 3], y - F[i, 4])
        return abs((x - F[i, 3]) * F[i, 5] + (y - F[i, 4]) * F[i, 6])
    first = int(F[i, 8])
    best = math.hypot(x - P[first, 0], y - P[first, 1])
    for j in range(first, first + count - 1):
        ax, ay, ex, ey = P[j, 0], P[j, 1], P[j + 1, 0] - P[j, 0], P[j + 1, 1] - P[j, 1]
        t = min(max(((x - ax) * ex + (y - ay) * ey) / (ex * ex + ey * ey), 0.0), 1.0)
        best = min(best, math.hypot(x - ax - t * ex, y - ay - t * ey))
    return best


@_jit
def _influence(F, i):
    """Distance [m] from feature ``i``'s crest beyond which its profile is flat to the
    other-feet search: 5 w for the Gaussian and tanh profiles (a 4e-6 / 9e-5 fraction of the
    height left), 8 w for the Lorentzian bump and pit (1/65 of the height, curvature
    ~1e-4 h/w²), the wire's exact edge 2 sqrt(h ρ / 2); a cusp's flanks never flatten."""
    kind, w = int(F[i, 0]), F[i, 2]
    if kind <= 2:
        return 5.0 * w
    if kind <= 4:
        return 8.0 * w
    if kind == 5:
        return np.inf
    return 2.0 * math.sqrt(0.5 * F[i, 1] * F[i, 7])


@_jit
def plate_top(F, base, idx, n):
    """Upper bound of the packed plate's height [m] over the features ``idx[:n]`` (``idx``
    None: the first ``n``): the base plus every raised feature's height (ridge, step, bump,
    wire; ravines, pits and cusps only go down)."""
    top = base
    for j in range(n):
        i = j if idx is None else idx[j]
        kind = int(F[i, 0])
        if kind == 0 or kind == 2 or kind == 3 or kind == 6:
            top += F[i, 1]
    return top


@_jit
def plate_other_feet(F, P, base, cx, cy, cz, r, reach, fx, fy, out):
    """The sphere's other contacts: local feet of ``(cx, cy, cz)`` on the packed plate (plate
    frame) within ``reach`` [m] of the sphere of radius ``r`` [m], other than the foot
    ``(fx, fy)`` the warm Newton tracks. Returns their number ``n``; ``out[:n]`` holds rows
    ``(x, y, h, n_x, n_y, n_z, distance)`` as :func:`plate_foot`.

    Where the sphere is wider than a groove (``r`` above the plate's concave radius, or two
    features closer than the sphere), the distance to the plate has several local minima
    and each within reach is a contact point (thesis §4.2.1's fingertip bridging a ravine
    touches both rims). The search looks only at the features whose profile is not flat
    within the disc where the sphere's lower cap can reach the plate's top (:func:`plate_top`,
    :func:`_influence`; none: one foot, nothing sampled). It samples the distance ``d`` from
    the centre on an ``OTHER_FEET_GRID``² grid over that disc (the other features' height at
    the centre added), starts a Newton (:func:`plate_foot`) at every discrete local minimum
    of ``d`` no farther than ``reach`` plus three grid steps, and keeps a converged foot
    within reach and more than :data:`FOOT_SEPARATION` from ``(fx, fy)`` and from the feet
    already found (at most ``out.shape[0]``). Two feet closer than about two grid steps (a
    fifth of the disc's diameter) can share one sampled minimum: the search's resolution. A
    sphere just beyond the focal distance of a concave flank touches it at two such close
    points: the 3GM ridge slide with a tip 3 % over the ridge's concave radius still sinks
    0.28 um (7 % and 20 % over: exact, where one contact sinks 2.6 and 17 um)."""
    if F.shape[0] == 0:
        return 0
    clear = cz - plate_top(F, base, None, F.shape[0]) - reach
    if clear >= r:
        return 0
    rho = r if clear <= 0.0 else math.sqrt(r * r - clear * clear)
    near = np.empty(F.shape[0], np.int64)
    m = 0
    for i in range(F.shape[0]):
        if _support_distance(F, P, i, cx, cy) - _influence(F, i) < rho:
            near[m] = i
            m += 1
    if m == 0:  # flat under the sphere: one foot
        return 0
    # the features out of reach are constant under the sphere to the search: their height at
    # the centre joins the base; the near features' top gives a smaller disc, a finer grid
    level = (
        base + plate_eval(F, P, base, cx, cy)[0] - plate_eval_some(F, P, base, near, m, cx, cy)[0]
    )
    clear = cz - plate_top(F, level, near, m) - reach
    if clear >= r:
        return 0
    if clear > 0.0:
        rho = min(rho, math.sqrt(r * r - clear * clear))
    k = OTHER_FEET_GRID
    step = 2.0 * rho / (k - 1)
    D = np.empty((k, k))
    for i in range(k):
        y = cy - rho + step * i
        for j in range(k):
            x = cx - rho + step * j
            q2 = (x - cx) ** 2 + (y - cy) ** 2
            if q2 > rho * rho * (1.0 + 1e-12):
                D[i, j] = np.inf
            else:
                z = plate_eval_some(F, P, level, near, m, x, y)[0]
                D[i, j] = math.sqrt(q2 + (z - cz) ** 2)
    n = 0
    for i in range(k):
        for j in range(k):
            d = D[i, j]
            if not d - r <= reach + 3.0 * step:
                continue
            low = True
            for a in range(max(i - 1, 0), min(i + 2, k)):
                for b in range(max(j - 1, 0), min(j + 2, k)):
                    if D[a, b] < d:
                        low = False
            if not low:
                continue
            x0, y0 = cx - rho + step * j, cy - rho + step * i
            qx, qy, qz, nx, ny, nz, dist, done = plate_foot(F, P, base, cx, cy, cz, x0, y0)
            if not done or dist - r > reach:
                continue
            if math.hypot(qx - fx, qy - fy) <= FOOT_SEPARATION:
                continue
            new = True
            for q in range(n):
                if math.hypot(qx - out[q, 0], qy - out[q, 1]) <= FOOT_SEPARATION:
                    new = False
            if new:
                out[n, 0], out[n, 1], out[n, 2] = qx, qy, qz
                out[n, 3], out[n, 4], out[n, 5], out[n, 6] = nx, ny, nz, dist
                n += 1
                if n == out.shape[0]:
                    return n
    return n


@_jit
def joint_force_readings(x, noise, prm, out):
    """Encoder angles, velocity estimate and strain-gauge force of the 3GM from its state
    vector ``x`` (:mod:`planner.sim.spatial.step_kernel` layout), as
    :func:`planner.sim.observation.read_joints` / :func:`~planner.sim.observation.read_forces`
    compute them: ``out`` (9,) = ``q`` [rad], ``q̇`` [rad/s], force on the surface [N].
    ``prm`` = (encoder resolution (0: exact), velocity resolution (0: exact), force resolution
    (0: exact), has contact record); ``noise`` (3,): the force noise already drawn [N]."""
    res, vres, fres = prm[0], prm[1], prm[2]
    for i in range(3):
        th, thd = x[i], x[3 + i]
        out[i] = math.floor(th / res) * res if res > 0.0 else th
        out[3 + i] = np.rint(thd / vres) * vres if vres > 0.0 else thd
    active = x[40] > 0.0 and prm[3] > 0.0
    for i in range(3):
        f = -(x[41] * x[45 + i] + x[48 + i]) if active else 0.0
        if fres > 0.0:
            f = np.rint((f + noise[i]) / fres) * fres
        out[6 + i] = f


@_jit
def finger_readings(x, z, nf, sprm, rows, times, k, oprm, sigma, out, on):
    """Every reading of the 3GM in one call: :func:`joint_force_readings` and
    :func:`owts_sample_decode` of the ``k`` pending OWTS ``rows`` (sample ``times``).

    ``z``: standard normal draws, the force sensor's ``nf`` (3 or 0) first, then the OWTS'
    ``2k`` (x then y offsets) — the same numbers as the separate ``rng.normal`` calls of the
    numpy readers; ``sprm``: as :func:`joint_force_readings` plus the force noise σ [N] at 4;
    ``sigma``: the OWTS noise σ. ``out`` (9 + 11k,) = ``q, q̇, force, t (k), voltages (k, 4),
    point (k, 3), normal (k, 3)``; ``on`` (k,): in contact."""
    noise = np.zeros(3)
    if nf > 0:
        for i in range(3):
            noise[i] = sprm[4] * z[i]
    joint_force_readings(x, noise, sprm, out[0:9])
    for i in range(k):
        out[9 + i] = times[i]
    if k == 0:
        return
    on_noise = np.empty(2 * k)
    for i in range(2 * k):
        on_noise[i] = sigma * z[nf + i]
    v = out[9 + k : 9 + 5 * k].reshape((k, 4))
    p = out[9 + 5 * k : 9 + 8 * k].reshape((k, 3))
    n = out[9 + 8 * k : 9 + 11 * k].reshape((k, 3))
    owts_sample_decode(rows[:k], on_noise, oprm, v, p, n, on)


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
