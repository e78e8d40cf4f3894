"""The per-step contact problem of one sphere contact with an EXACT circular Coulomb cone.

Formulation (velocity level, one contact, contact frame ``(n, t1, t2)``). The relative
velocity of the contact point after the step is affine in the contact impulse
``λ = (λ_n, λ_t) [N s]``:

.. math:: u^+ = \\tilde u + W \\lambda, \\qquad \\tilde u = u_{free} + (g/h, 0, 0),

where ``W = J M⁻¹ Jᵀ`` (3x3, symmetric positive definite) is the Delassus operator,
``u_free`` the contact velocity of the unconstrained step [m/s], ``g`` the gap [m] and ``h``
the time step [s] (the shift by ``g/h`` asks the step to close the gap exactly, not more:
``g + h u_n⁺ >= 0``). The conditions are Signorini and Coulomb with the circular cone:

.. math::

    0 \\le \\lambda_n \\perp \\tilde u_n^+ \\ge 0, \\qquad \\|\\lambda_t\\| \\le \\mu \\lambda_n,
    \\qquad \\|\\lambda_t\\| < \\mu\\lambda_n \\Rightarrow u_t^+ = 0, \\qquad
    u_t^+ \\ne 0 \\Rightarrow \\lambda_t = -\\mu\\lambda_n\\, u_t^+/\\|u_t^+\\|.

Solution by enumeration of the three cases, each solved exactly:

1. **separate**: ``λ = 0`` if ``ũ_n >= 0``;
2. **stick**: ``λ = -W⁻¹ ũ`` (then ``u⁺ = 0``) if ``λ_n >= 0`` and ``‖λ_t‖ <= μ λ_n``;
3. **slide** along the unit direction ``d = (cos φ, sin φ)`` of the tangent plane:
   ``λ = λ_n (1, -μ d)`` and ``u_t⁺ = s d`` with ``s > 0``. The normal row gives
   ``λ_n(φ) = -ũ_n / (W_nn - μ w·d)`` (``w = W_tn``); the tangential rows require
   ``u_t⁺(φ) = ũ_t + λ_n (w - μ T d)`` (``T = W_tt``) to be parallel to ``d``:
   ``p·u_t⁺ = 0`` with ``p = (-sin φ, cos φ)``. Multiplied by ``W_nn - μ w·d`` this is

   .. math:: g(\\varphi) = (W_{nn} - \\mu w\\cdot d)\\,p\\cdot\\tilde u_t
             + \\tilde u_n\\,(\\mu\\, p\\cdot T d - p\\cdot w) = 0,

   a trigonometric polynomial of degree 2 in ``φ``, i.e. a quartic in ``z = e^{iφ}``.
   Its coefficients are read exactly from 8 samples (a DFT), its roots on the unit circle
   by ``numpy.roots`` (companion-matrix eigenvalues), each polished by Newton on ``g`` to
   machine precision, and the root with ``λ_n > 0`` and ``s = d·u_t⁺ > 0`` is kept.

The result satisfies the conditions to round-off (:func:`residual` checks them; the tests
sweep random SPD ``W``). No polyhedral cone, no regularization, no iteration count to
tune: sticking contacts have ``u_t⁺ = 0`` exactly (no creep) and sliding contacts carry
``‖λ_t‖ = μ λ_n`` exactly with ``ũ_n⁺ = 0`` (no hovering).

Limits: existence is guaranteed for SPD ``W``; uniqueness holds for small ``μ`` (for large
``μ`` and strongly anisotropic ``W`` several sliding roots may be valid: the one whose slip
is closest to the free slip direction is returned). Several contacts are coupled by block
Gauss-Seidel over these exact 3x3 solves (:func:`solve_contacts`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from planner.errors import InfeasibleProblem

__all__ = ["ContactSolution", "residual", "solve_contact", "solve_contacts", "solve_impulse"]

_PHI8 = np.arange(8) * (2.0 * np.pi / 8.0)
_E8 = np.exp(-1j * np.outer(np.arange(-2, 3), _PHI8)) / 8.0  # DFT rows m = -2..2


@dataclass(frozen=True)
class ContactSolution:
    """Solution of one contact problem.

    Attributes:
        impulse: (3,) contact impulse ``(λ_n, λ_t1, λ_t2)`` in the contact frame [N s].
        velocity: (3,) contact velocity after the step ``u⁺`` (normal part without the
            gap shift) [m/s].
        mode: ``"separate"``, ``"stick"`` or ``"slide"``.
    """

    impulse: np.ndarray
    velocity: np.ndarray
    mode: str


def _slide_terms(W: np.ndarray, ut: np.ndarray, un: float, mu: float, phi: np.ndarray):
    """``λ_n(φ)``, ``u_t⁺(φ)`` (2, N), ``d`` (2, N) for an array of slip angles."""
    d = np.array([np.cos(phi), np.sin(phi)])
    w = W[1:, 0]
    T = W[1:, 1:]
    den = W[0, 0] - mu * (w @ d)
    lam_n = -un / den
    u_t = ut[:, None] + lam_n * (w[:, None] - mu * (T @ d))
    return lam_n, u_t, d, den


def _g(W, ut, un, mu, phi):
    d = np.array([np.cos(phi), np.sin(phi)])
    p = np.array([-np.sin(phi), np.cos(phi)])
    w = W[1:, 0]
    T = W[1:, 1:]
    den = W[0, 0] - mu * (w @ d)
    return den * (p.T @ ut) + un * (mu * np.einsum("in,ij,jn->n", p, T, d) - p.T @ w)


def _slide(W: np.ndarray, ut: np.ndarray, un: float, mu: float) -> np.ndarray | None:
    """Exact sliding impulse (3,) or None when no valid sliding root exists."""
    G = _E8 @ _g(W, ut, un, mu, _PHI8)  # complex coefficients of e^{imφ}, m = -2..2
    coeffs = G[::-1]  # z^4 .. z^0 of z^2 g
    scale = np.max(np.abs(coeffs))
    if scale == 0.0:
        return None
    c = coeffs.copy()
    while abs(c[0]) <= 1e-13 * scale:
        c = c[1:]
    roots = np.roots(c) if len(c) > 1 else np.array([])
    m = np.arange(-2, 3)
    best, best_key = None, np.inf
    free_dir = ut / (np.linalg.norm(ut) + 1e-300)
    for z in roots:
        if not np.isfinite(z) or abs(abs(z) - 1.0) > 1e-3:
            continue
        phi = float(np.angle(z))
        for _ in range(8):  # Newton polish on the trig polynomial
            e = np.exp(1j * m * phi)
            gv = float(np.real(G @ e))
            dg = float(np.real((1j * m * G) @ e))
            if dg == 0.0:
                break
            step = gv / dg
            phi -= step
            if abs(step) < 1e-16:
                break
        lam_n, u_t, d, den = _slide_terms(W, ut, un, mu, np.array([phi]))
        lam_n, u_t, d = float(lam_n[0]), u_t[:, 0], d[:, 0]
        s = float(d @ u_t)
        if den[0] <= 0.0 or lam_n < 0.0 or s < -1e-14 * (1.0 + np.abs(ut).sum()):
            continue
        key = -float(d @ free_dir)
        if key < best_key:
            best_key = key
            best = np.array([lam_n, -mu * lam_n * d[0], -mu * lam_n * d[1]])
    return best


def _fixed_point(W: np.ndarray, u0: np.ndarray, mu: float, iters: int = 2000) -> np.ndarray:
    """Fallback: projected fixed point on the De Saxcé cone (converged to round-off)."""
    rho = 1.0 / np.max(np.linalg.eigvalsh(W))
    lam = np.zeros(3)
    for _ in range(iters):
        u = u0 + W @ lam
        y = lam - rho * (u + np.array([mu * np.linalg.norm(u[1:]), 0.0, 0.0]))
        new = _project_cone(y, mu)
        if np.max(np.abs(new - lam)) <= 1e-16 * (1.0 + np.max(np.abs(new))):
            return new
        lam = new
    return lam


def _project_cone(y: np.ndarray, mu: float) -> np.ndarray:
    n, t = y[0], y[1:]
    r = float(np.linalg.norm(t))
    if r <= mu * n:
        return y.copy()
    if mu * r <= -n:
        return np.zeros(3)
    a = (n + mu * r) / (1.0 + mu * mu)
    return np.array([a, *(mu * a * t / r)])


def _slide_newton(W, ut0: float, ut1: float, un: float, mu: float, phi: float):
    """Newton on ``g(φ)`` in scalar arithmetic from ``φ`` (the fast path); the impulse
    (3,) or None when it does not converge to a valid root."""
    (a, _, _), (w1, t11, t12), (w2, _, t22) = W
    dt_ = t22 - t11
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
            return None
        step = g / dg
        phi -= step
        if abs(step) <= 1e-15:
            break
    else:
        return None
    c, s = math.cos(phi), math.sin(phi)
    den = a - mu * (w1 * c + w2 * s)
    if den <= 0.0:
        return None
    lam_n = -un / den
    u0 = ut0 + lam_n * (w1 - mu * (t11 * c + t12 * s))
    u1 = ut1 + lam_n * (w2 - mu * (t12 * c + t22 * s))
    slip = c * u0 + s * u1
    if lam_n < 0.0 or slip < 0.0 or abs(-s * u0 + c * u1) > 1e-12 * (abs(slip) + 1e-300) + 1e-15:
        return None
    return np.array([lam_n, -mu * lam_n * c, -mu * lam_n * s])


def _stick(W, un: float, ut0: float, ut1: float) -> tuple[float, float, float]:
    """``-W⁻¹ (un, ut0, ut1)`` by the adjugate (``W`` nested lists, scalar arithmetic)."""
    (a, b, c), (d, e, f), (g, h, i) = W
    A, B, C = e * i - f * h, f * g - d * i, d * h - e * g
    det = a * A + b * B + c * C
    D, E, F = c * h - b * i, a * i - c * g, b * g - a * h
    G, H, I_ = b * f - c * e, c * d - a * f, a * e - b * d
    return (
        -(A * un + D * ut0 + G * ut1) / det,
        -(B * un + E * ut0 + H * ut1) / det,
        -(C * un + F * ut0 + I_ * ut1) / det,
    )


def solve_impulse(W: np.ndarray, u_free: np.ndarray, gap_rate: float, mu: float):
    """The impulse (3,) [N s] and the mode of one contact (see :func:`solve_contact`)."""
    u0, ut0, ut1 = u_free.tolist() if isinstance(u_free, np.ndarray) else u_free
    un = u0 + gap_rate
    if un >= 0.0:
        return np.zeros(3), "separate"
    Wl = W.tolist()
    lam = _stick(Wl, un, ut0, ut1)
    if lam[0] >= 0.0 and math.hypot(lam[1], lam[2]) <= mu * lam[0]:
        return np.array(lam), "stick"
    if mu <= 1e-14:  # frictionless (a friction force below 1e-14 λ_n is not resolved)
        return np.array([-un / Wl[0][0], 0.0, 0.0]), "slide"
    # slip opposes the friction impulse that sticking would need: a good first guess
    phi0 = math.atan2(-lam[2], -lam[1]) if lam[1] or lam[2] else math.atan2(ut1, ut0)
    out = _slide_newton(Wl, ut0, ut1, un, mu, phi0)
    if out is None:
        out = _slide(W, np.array([ut0, ut1]), un, mu)
        if out is None:
            out = _fixed_point(W, np.array([un, ut0, ut1]), mu)
    return out, "slide"


def solve_contact(W: np.ndarray, u_free: np.ndarray, gap_rate: float, mu: float) -> ContactSolution:
    """Solve one sphere contact exactly (see the module docstring).

    The sliding root is first sought by Newton on ``g(φ)`` from the direction opposite to
    the sticking impulse (scalar arithmetic, 2-4 iterations); when that does not give a
    valid root, all roots of the quartic are examined (numpy.roots), and as a last resort a
    projected fixed point on the cone is iterated to round-off.

    Args:
        W: (3, 3) Delassus operator in the contact frame ``(n, t1, t2)`` [(m/s)/(N s)],
            symmetric positive definite.
        u_free: (3,) contact velocity of the contact-free step [m/s].
        gap_rate: ``gap / dt`` [m/s] (the normal velocity that closes the gap in one step).
        mu: Coulomb friction coefficient [-] (>= 0).

    Returns:
        the :class:`ContactSolution`.
    """
    lam, mode = solve_impulse(W, u_free, gap_rate, mu)
    return ContactSolution(lam, np.asarray(u_free, float) + W @ lam, mode)


def residual(W: np.ndarray, u_free: np.ndarray, gap_rate: float, mu: float, lam: np.ndarray):
    """Violation of the contact conditions by ``lam`` (3,) [m/s and N s mixed]: the largest of
    normal complementarity, cone, stick and slide-direction residuals (0 for an exact
    solution). For tests and diagnostics."""
    u = np.asarray(u_free, float) + W @ lam
    un = u[0] + gap_rate
    lt = float(np.linalg.norm(lam[1:]))
    st = float(np.linalg.norm(u[1:]))
    r = [max(-lam[0], 0.0), max(-un, 0.0), abs(lam[0] * un), max(lt - mu * lam[0], 0.0)]
    inside = mu * lam[0] - lt > 1e-9 * lam[0]
    if lam[0] > 0 and inside:
        r.append(st)  # strictly inside the cone: must stick
    elif st > 1e-12 and lam[0] > 0:  # on the cone's boundary: friction opposes the slip
        r.append(float(np.linalg.norm(lam[1:] + mu * lam[0] * u[1:] / st)))
    return float(max(r))


#: under-relaxation factors tried in turn: plain block Gauss-Seidel first; when its sweeps
#: cycle (strong coupling, large mu) a relaxed restart converges (measured on random SPD W)
RELAXATION = (1.0, 0.8, 0.5, 0.3)


def solve_contacts(
    W: np.ndarray,
    u_free: np.ndarray,
    gap_rates: np.ndarray,
    mu: np.ndarray,
    tol: float = 1e-13,
    max_sweeps: int = 200,
    rates: np.ndarray | None = None,
) -> tuple[np.ndarray, list[str]]:
    """Several coupled contacts (and unilateral limit rows): block Gauss-Seidel over exact
    3x3 solves.

    Each sweep solves every contact's 3x3 problem exactly (:func:`solve_impulse`) given the
    others' impulses, then every scalar limit row ``0 <= λ ⊥ u + rate >= 0``. Plain sweeps
    converge for weakly coupled contacts (the compiled step runs the same sweeps). When they do
    not: first the all-sticking guess, every row active and ``W λ = -(u + rates)`` solved
    directly (for a well-conditioned ``W`` only), kept when every normal impulse is positive,
    every friction impulse inside its cone and every limit impulse non-negative (sweeps on an
    ill-conditioned ``W`` approach it only linearly); then restarts under-relaxed (``λ ← (1-ω) λ
    + ω λ_new``, ω in :data:`RELAXATION`), since with strong coupling and large ``μ`` plain
    sweeps can cycle. Where every relaxation cycles (a few in a thousand random strongly coupled
    pairs with ``μ >= 1``), the Alart-Curnier equations are solved by Powell's hybrid method
    (:func:`scipy.optimize.root`) from the last sweep, the (least-squares) all-sticking guess
    and zero, and a root is kept only when it satisfies every contact's conditions
    (:func:`residual`) to round-off (0 of 12000 random pairs left unsolved).
    A sweep solve is accepted when an update changes no impulse by more than ``tol`` (relative).

    Args:
        W: (3k + m, 3k + m) Delassus operator (contact frames stacked, then the limit rows).
        u_free: (3k + m,) free contact velocities [m/s] (joint rates [rad/s] for limit rows).
        gap_rates: (k,) ``gap/dt`` [m/s].
        mu: (k,) friction coefficients.
        tol: convergence threshold on the impulse change, relative [-].
        max_sweeps: sweep limit per relaxation factor.
        rates: (m,) ``gap/dt`` of the limit rows [rad/s] (default: none).

    Returns:
        ``(impulse (3k + m,) [N s], modes of the k contacts)``. With one contact and no limit
        row this is :func:`solve_contact`.

    Raises:
        InfeasibleProblem: no relaxation converged (the world's run turns it into a failed
            status with this reason).
    """
    k = len(gap_rates)
    rates = np.zeros(0) if rates is None else np.asarray(rates, float)
    if k == 1 and len(rates) == 0:
        lam, mode = solve_impulse(W, u_free, gap_rates[0], mu[0])
        return lam, [mode]
    for omega in RELAXATION:
        lam, modes, ok = _sweeps(W, u_free, gap_rates, mu, rates, tol, max_sweeps, omega)
        if ok:
            return lam, modes
        if omega == 1.0:
            stick = _all_stick(W, u_free, gap_rates, mu, rates)
            if stick is not None:
                return stick, ["stick"] * k
    found = _alart_curnier(W, u_free, gap_rates, mu, rates, lam)
    if found is not None:
        return found
    raise InfeasibleProblem(
        f"{k} coupled contacts and {len(rates)} limit rows: block Gauss-Seidel did not converge "
        f"(relaxations {RELAXATION}, {max_sweeps} sweeps each) and no Alart-Curnier root",
        problem={"W": W, "u_free": u_free, "gap_rates": gap_rates, "mu": mu, "rates": rates},
        solver="block Gauss-Seidel",
    )


def _all_stick(W, u_free, gap_rates, mu, rates):
    """``λ`` with every contact sticking and every limit row held, or ``None`` when that
    ``λ`` leaves a cone (or the system is singular)."""
    k = len(gap_rates)
    rhs = -np.asarray(u_free, float).copy()
    rhs[0 : 3 * k : 3] -= gap_rates
    rhs[3 * k :] -= rates
    if k and np.any(rhs[0 : 3 * k : 3] <= 0.0):
        return None  # a contact that would separate does not stick
    if np.linalg.cond(W) > 1e10:
        return None  # rank-deficient W (more rows than joints): sticking impulses not unique
    lam = np.linalg.solve(W, rhs)
    n, t1, t2 = lam[0 : 3 * k : 3], lam[1 : 3 * k : 3], lam[2 : 3 * k : 3]
    if np.any(n <= 0.0) or np.any(np.hypot(t1, t2) > np.asarray(mu) * n):
        return None
    if np.any(lam[3 * k :] < 0.0):
        return None
    return lam


def _alart_curnier(W, u_free, gap_rates, mu, rates, guess):
    """A verified root of the Alart-Curnier function (Alart & Curnier 1991), or ``None``:
    ``λ_n - max(0, λ_n - ρ u_n)``, ``λ_t - P_{|·| <= μ λ_n'}(λ_t - ρ u_t)`` per contact and
    ``λ_r - max(0, λ_r - ρ u_r)`` per limit row, ``u = u_free + W λ`` (+ gap and limit rates).
    """
    from scipy.optimize import root

    k = len(gap_rates)
    shift = np.zeros(len(u_free))
    shift[0 : 3 * k : 3] = gap_rates
    shift[3 * k :] = rates
    base = np.asarray(u_free, float) + shift

    def equations(lam, rho):
        v = base + W @ lam
        f = lam - np.maximum(0.0, lam - rho * v)  # normal and limit rows
        for i in range(k):
            s = 3 * i
            ln = max(0.0, lam[s] - rho * v[s])
            t = lam[s + 1 : s + 3] - rho * v[s + 1 : s + 3]
            nt, r = math.hypot(t[0], t[1]), mu[i] * ln
            f[s + 1 : s + 3] = lam[s + 1 : s + 3] - (t if nt <= r else t * (r / nt))
        return f

    def solved(lam):
        v = base + W @ lam
        scale = 1e-10 * (1.0 + float(np.abs(lam).sum()))
        for i in range(k):
            s = slice(3 * i, 3 * i + 3)
            u_i = v[s] - W[s, s] @ lam[s] - np.array([gap_rates[i], 0.0, 0.0])
            if residual(W[s, s], u_i, gap_rates[i], mu[i], lam[s]) > scale:
                return False
        lr, vr = lam[3 * k :], v[3 * k :]
        return bool(
            np.all(lr >= -scale) and np.all(vr >= -scale) and np.all(np.abs(lr * vr) <= scale)
        )

    stick = np.linalg.lstsq(W, -base, rcond=None)[0]  # W may be rank-deficient
    starts = [np.asarray(guess, float), stick, np.zeros(len(base))]
    rhos = (
        len(base) / float(np.trace(W)),
        1.0 / float(np.max(np.diag(W))),
        0.1 / float(np.min(np.diag(W))),
    )
    for start in starts:
        for rho in rhos:
            lam = root(equations, start, args=(rho,), method="hybr", tol=1e-15).x
            if np.all(np.isfinite(lam)) and solved(lam):
                modes = [_mode(lam[3 * i : 3 * i + 3], mu[i]) for i in range(k)]
                return lam, modes
    return None


def _mode(lam, mu) -> str:
    if lam[0] <= 0.0:
        return "separate"
    return "slide" if math.hypot(lam[1], lam[2]) >= mu * lam[0] * (1.0 - 1e-9) else "stick"


def _sweeps(W, u_free, gap_rates, mu, rates, tol, max_sweeps, omega):
    """Block Gauss-Seidel sweeps with relaxation ``omega``: ``(λ, modes, converged)``."""
    k, m = len(gap_rates), len(rates)
    lam = np.zeros(3 * k + m)
    modes = ["separate"] * k
    for _ in range(max_sweeps):
        change = 0.0
        for i in range(k):
            s = slice(3 * i, 3 * i + 3)
            u_i = u_free[s] + W[s] @ lam - W[s, s] @ lam[s]
            new, modes[i] = solve_impulse(W[s, s], u_i, gap_rates[i], mu[i])
            if omega != 1.0:
                new = (1.0 - omega) * lam[s] + omega * new
            change = max(change, float(np.max(np.abs(new - lam[s]))))
            lam[s] = new
        for j in range(m):
            r = 3 * k + j
            u = u_free[r] + W[r] @ lam + rates[j]
            new = (1.0 - omega) * lam[r] + omega * max(0.0, lam[r] - u / W[r, r])
            change = max(change, abs(new - lam[r]))
            lam[r] = new
        if change <= tol * (1.0 + float(np.max(np.abs(lam)))):
            return lam, modes, True
    return lam, modes, False
