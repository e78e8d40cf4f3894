"""One time step of the spatial world (the scheme is documented in :mod:`.world`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner.sim.records import Contact
from planner.sim.spatial.friction_cone import solve_contacts

__all__ = ["held_inverse_mass", "limit_rows", "solve_with_limits", "step_body"]

_PROJ_TOL = 1e-12  # [m]
_MARGIN = 1e-5  # [m] candidate margin beyond the distance travelled in a step
_LIM_MARGIN = 1e-9  # [rad] candidate margin of a joint limit


@dataclass
class _Candidate:
    surface: str
    placed: object
    mu: float
    foot: object
    gap: float
    C: np.ndarray  # (3, 3) rows n, t1, t2
    other: bool = False  # a second foot on the same surface (re-found from its own hint)

    def refresh(self, world, body):
        """The foot at the body's current centre (None: it left a bounded surface)."""
        if self.other:
            return self.placed.local_foot(body.center, self.foot.hint)
        key = (body.name, self.surface)
        foot = self.placed.foot(body.center, world._hints.get(key))
        if foot is not None:
            world._hints[key] = foot.hint
        return foot


def _frame(n: np.ndarray) -> np.ndarray:
    """(3, 3) rows ``(n, t1, t2)``: a right-handed orthonormal contact frame."""
    x, y, z = n.tolist()
    if abs(x) < 0.9:  # t1 = normalize(e_x - x n)
        a, b, c = 1.0 - x * x, -x * y, -x * z
    else:  # t1 = normalize(e_y - y n)
        a, b, c = -y * x, 1.0 - y * y, -y * z
    k = 1.0 / math.sqrt(a * a + b * b + c * c)
    a, b, c = a * k, b * k, c * k
    return np.array([[x, y, z], [a, b, c], [y * c - z * b, z * a - x * c, x * b - y * a]])


def _candidates(world, body, nu_free) -> list[_Candidate]:
    reach = 2.0 * world.dt * float(np.max(np.abs(nu_free))) * max(body.radius, 0.2) + _MARGIN
    out = []
    for sname, (placed, mu_s) in world.surfaces.items():
        key = (body.name, sname)
        foot = placed.foot(body.center, world._hints.get(key))
        if foot is None:
            world._hints.pop(key, None)
            continue
        world._hints[key] = foot.hint
        mu = mu_s if body.friction is None else max(mu_s, body.friction)
        gap = foot.distance - body.radius
        if gap <= reach:
            out.append(_Candidate(sname, placed, mu, foot, gap, _frame(foot.normal)))
        if not world.all_contacts:
            continue
        for other in placed.other_feet(body.center, body.radius, reach, foot):
            g = other.distance - body.radius
            out.append(_Candidate(sname, placed, mu, other, g, _frame(other.normal), True))
    return out


def _project(world, body, active: list[_Candidate], minv=None) -> list[float]:
    """Project the centre onto the offset surfaces of the active contacts; final gaps.
    ``minv``: the finger's inverse mass conditioned on its held joints (default M_r⁻¹).
    Several contacts on one surface (a sphere bridging a groove) are projected together
    (:func:`_project_together`); otherwise one contact after the other."""
    if any(c.other for c in active):
        return _project_together(body, active, world, minv)
    gaps = [c.gap for c in active]
    for _ in range(20):
        worst = 0.0
        for i, c in enumerate(active):
            key = (body.name, c.surface)
            foot = c.placed.foot(body.center, world._hints.get(key))
            if foot is None:
                continue
            world._hints[key] = foot.hint
            c.foot = foot
            g = foot.distance - body.radius
            gaps[i] = g
            if abs(g) <= _PROJ_TOL:
                continue
            worst = max(worst, abs(g))
            n = foot.normal
            if body.minv is None or np.ndim(body.minv) == 1:  # sphere: translate along n
                body.project(-g * n)
            else:  # finger: mass-weighted Gauss-Newton step on the motor angles
                jn = n @ body.centre_jacobian()
                mj = (body.minv if minv is None else minv) @ jn
                den = jn @ mj
                if not den > 0.0:  # every joint held: nothing can move
                    break
                body.project(None, -g * mj / den)
        if worst <= _PROJ_TOL:
            break
    return gaps


def _project_together(body, active: list[_Candidate], world, minv=None) -> list[float]:
    """Gauss-Newton onto the intersection of the active contacts' offset surfaces: the
    smallest correction in the metric ``M⁻¹`` (``minv``) that closes every gap to first
    order, ``Δq = -M⁻¹Jₙᵀ (Jₙ M⁻¹ Jₙᵀ)⁺ g`` (a sphere: ``Δx = -Nᵀ (N Nᵀ)⁺ g``), repeated
    until every ``|g| <= 1e-12 m``; the final gaps."""
    gaps = [c.gap for c in active]
    for _ in range(20):
        rows, g = [], []
        for i, c in enumerate(active):
            foot = c.refresh(world, body)
            if foot is None:
                continue
            c.foot = foot
            gaps[i] = foot.distance - body.radius
            rows.append(foot.normal)
            g.append(gaps[i])
        if not g or max(abs(v) for v in g) <= _PROJ_TOL:
            break
        N, g = np.array(rows), np.array(g)
        if body.minv is None or np.ndim(body.minv) == 1:  # sphere: translate
            body.project(-N.T @ (np.linalg.pinv(N @ N.T) @ g))
            continue
        Jn = N @ body.centre_jacobian()
        MJ = (body.minv if minv is None else minv) @ Jn.T
        A = Jn @ MJ
        if not np.trace(A) > 0.0:  # every joint held: nothing can move
            break
        body.project(None, -MJ @ (np.linalg.pinv(A, rcond=1e-12) @ g))
    return gaps


def _unpenetrate(world, body, idle: list[_Candidate], minv=None) -> None:
    """Project candidates that did not carry force but end the step penetrating."""
    for c in idle:
        foot = (
            c.refresh(world, body)
            if c.other
            else c.placed.foot(body.center, world._hints.get((body.name, c.surface)))
        )
        if foot is not None and foot.distance - body.radius < -_PROJ_TOL:
            c.gap = foot.distance - body.radius
            _project(world, body, [c], minv)


def limit_rows(body, nu_free, h: float) -> list[tuple[int, float, float]]:
    """The finger's joint-limit rows within reach: ``(joint, sign, rate)`` with sign +1 for
    the lower and -1 for the upper limit and ``rate = gap / h`` [rad/s] (a round-off violation
    above ``-_LIM_MARGIN`` is corrected; a joint further beyond its limit is held there, not
    pushed back: rate 0). Spheres: none."""
    lims = getattr(body, "limits", None)
    if lims is None:
        return []
    reach = 2.0 * h * float(np.max(np.abs(nu_free))) + _LIM_MARGIN
    out = []
    for i, (th, (lo, hi)) in enumerate(zip(body.th.tolist(), lims.tolist(), strict=True)):
        gl, gu = th - lo, hi - th
        if gl <= reach:
            out.append((i, 1.0, (gl if gl >= -_LIM_MARGIN else 0.0) / h))
        elif gu <= reach:
            out.append((i, -1.0, (gu if gu >= -_LIM_MARGIN else 0.0) / h))
    return out


def solve_with_limits(W, u_free, gap_rates, mus, rates, tol=1e-13, max_sweeps=200):
    """Contacts (3x3 exact-cone blocks) and ``m`` scalar unilateral limit rows (last rows of
    ``W``: ``0 <= λ ⊥ u + rate >= 0``); the impulse (3k + m,). One block Gauss-Seidel with
    relaxed restarts: :func:`.friction_cone.solve_contacts`."""
    return solve_contacts(W, u_free, gap_rates, mus, tol, max_sweeps, rates=np.asarray(rates))[0]


def held_inverse_mass(minv: np.ndarray, held: list[int]) -> np.ndarray:
    """``M⁻¹`` conditioned on the joints ``held`` at their limits:
    ``P = M⁻¹ - M⁻¹Eᵀ(E M⁻¹ Eᵀ)⁻¹E M⁻¹`` by successive rank-one downdates."""
    P = np.array(minv, float)
    for i in held:
        if P[i, i] > 0.0:
            P = P - np.outer(P[:, i], P[i, :]) / P[i, i]
    return P


def step_body(world, body, tau) -> tuple[list[Contact], np.ndarray]:
    """Advance one body by ``world.dt``; returns its contact records and the joint-limit
    impulses (3,) [N m s] (signed: + lower, - upper; spheres: empty)."""
    h = world.dt
    nu_f = body.free_velocity(h, world.gravity, tau)
    cands = _candidates(world, body, nu_f)
    rows = limit_rows(body, nu_f, h)
    lam = np.zeros(0)
    held = np.zeros(3 if rows or getattr(body, "limits", None) is not None else 0)
    if cands or rows:
        minv = body.minv if np.ndim(body.minv) == 2 else np.diag(body.minv)
        Js = [c.C @ body.point_jacobian(c.foot.normal) for c in cands]
        for i, sign, _ in rows:
            e = np.zeros((1, len(nu_f)))
            e[0, i] = sign
            Js.append(e)
        J = np.vstack(Js)
        MJt = minv @ J.T
        W = J @ MJt
        W = 0.5 * (W + W.T)
        u_free = J @ nu_f
        gap_rates = np.array([c.gap / h for c in cands])
        mus = np.array([c.mu for c in cands])
        lam = solve_with_limits(W, u_free, gap_rates, mus, [r for _, _, r in rows])
        nu = nu_f + MJt @ lam
        u_after = J @ nu
        for j, (i, sign, _) in enumerate(rows):
            held[i] = sign * lam[3 * len(cands) + j]
    else:
        nu = nu_f
    body.apply(nu)
    body.integrate(h)
    hold = [i for i in range(len(held)) if held[i] != 0.0]
    pminv = held_inverse_mass(body.minv, hold) if hold else None
    active = [c for i, c in enumerate(cands) if lam[3 * i] > 0.0]
    idx = [i for i, c in enumerate(cands) if lam[3 * i] > 0.0]
    gaps = _project(world, body, active, pminv) if active else []
    idle = [c for i, c in enumerate(cands) if not lam[3 * i] > 0.0]
    _unpenetrate(world, body, idle, pminv)
    out = []
    for c, i, g in zip(active, idx, gaps, strict=True):
        lam_i = lam[3 * i : 3 * i + 3]
        u_i = u_after[3 * i : 3 * i + 3]
        C = c.C
        out.append(
            Contact(
                (body.name, c.surface),
                c.foot.point.copy(),
                c.foot.normal.copy(),
                float(lam_i[0] / h),
                C[1:].T @ lam_i[1:] / h,
                C[1:].T @ u_i[1:],
                float(g),
            )
        )
    return out, held
