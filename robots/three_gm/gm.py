"""The 3GM finger: closed-form kinematics, Jacobian, statics, IK, limits (thesis App. C.2)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from planner import checks
from planner.errors import InvalidParameter, SingularConfiguration
from robots.errors import UnreachableTarget
from robots.three_gm import closed_form as cf
from robots.three_gm.params import (
    DEFAULT_JOINT_LIMITS,
    DEFAULT_PARAMS,
    MAX_FORCE_AT_CENTER,
    POSITION_RESOLUTION,
    WORKSPACE_HALF_ANGLE,
    WORKSPACE_RADII,
    WORKSPACE_Z,
)

PARAM_KEYS = ("l1", "l2", "l3", "l4", "l5", "h1", "h2", "h3")


class ThreeGM:
    """The 3GM five-bar finger on a rotating base (thesis App. C.2, Fig. C.5).

    ``theta = (θ1, θ2, θ3)``: the two five-bar motor angles and the base rotation [rad].

    Args:
        params: any of ``l1..l5, h1..h3`` [m] to override :data:`DEFAULT_PARAMS`.
        joint_limits: (3, 2) lower/upper limits of θ [rad].
    """

    def __init__(self, params: Mapping[str, float] | None = None, joint_limits=None) -> None:
        p = dict(DEFAULT_PARAMS)
        for k, v in (params or {}).items():
            if k not in PARAM_KEYS:
                raise InvalidParameter(f"params: expected keys in {list(PARAM_KEYS)}, got {k!r}")
            if k.startswith("l"):
                p[k] = checks.positive(k, v, "m")
            else:
                p[k] = checks.in_range(k, v, -np.inf, np.inf, "m", closed=(False, False))
        self.params: dict[str, float] = p
        lim = (
            DEFAULT_JOINT_LIMITS
            if joint_limits is None
            else checks.points("joint_limits", joint_limits, dims=(2,), n=3, unit="rad")
        )
        if np.any(lim[:, 0] >= lim[:, 1]):
            raise InvalidParameter(
                f"joint_limits: expected lower < upper in every row [rad], got {lim.tolist()}"
            )
        self.joint_limits: np.ndarray = lim.copy()
        self._model = None
        self._center_theta: np.ndarray | None = None
        self._tau_max: np.ndarray | None = None
        self._seed_grid: np.ndarray | None = None

    # ------------------------------------------------------------------ closed form
    def state(self, theta) -> cf.FiveBarState:
        """All intermediate quantities of eqs. C.4-C.6 (see :class:`FiveBarState`)."""
        return cf.five_bar_state(self.params, checks.vector("theta", theta, 3, "rad"))

    def forward_kinematics(self, theta) -> np.ndarray:
        """Endpoint (x, y, z) in the WCS [m] by eqs. C.4-C.6 (elbow-up).

        Args:
            theta: (3,) joint angles (θ1, θ2, θ3) [rad].

        Returns:
            (3,) position [m].

        Raises:
            SingularConfiguration: the arccos argument of eq. C.5 leaves [-1, 1].
        """
        return self.state(theta).position

    def passive_angles(self, theta) -> tuple[float, float]:
        """The passive angles (γ1, γ2) of eq. C.5, elbow-up branch [rad]."""
        st = self.state(theta)
        return st.gamma1, st.gamma2

    def jacobian(self, theta) -> np.ndarray:
        """The (3, 3) Jacobian d(x, y, z)/dθ of eq. C.7 (C.8 corrected, C.9) [m/rad].

        Raises:
            SingularConfiguration: outside the closure domain, or l3 and l4 aligned.
        """
        th = checks.vector("theta", theta, 3, "rad")
        return cf.jacobian_from_state(self.params, th, cf.five_bar_state(self.params, th))

    def forward_kinematics_and_jacobian(self, theta) -> tuple[np.ndarray, np.ndarray]:
        """Endpoint (3,) [m] and Jacobian (3, 3) [m/rad] from one evaluation of eqs. C.4-C.9."""
        th = checks.vector("theta", theta, 3, "rad")
        st = cf.five_bar_state(self.params, th)
        return st.position, cf.jacobian_from_state(self.params, th, st)

    def endpoint_velocity(self, theta, theta_dot) -> np.ndarray:
        """(3,) endpoint velocity v = J θ̇ [m/s] (eq. C.10); ``theta_dot`` (3,) [rad/s]."""
        return self.jacobian(theta) @ checks.vector("theta_dot", theta_dot, 3, "rad/s")

    def joint_torques(self, theta, force) -> np.ndarray:
        """(3,) motor torques τ = Jᵀ f [N m] producing endpoint force ``force`` (3,) [N] (C.10)."""
        return self.jacobian(theta).T @ checks.vector("force", force, 3, "N")

    def gravity_torque(self, theta, mass: float) -> np.ndarray:
        """Gravity-compensation torques (eq. C.11): only motor 1, τ_g = M g l5 cos θ1.

        The thesis' empirical M absorbs g; here ``mass`` is in kg and g = 9.81 m/s².

        Returns:
            (3,) torques [N m]: ``(M g l5 cos θ1, 0, 0)``.
        """
        th = checks.vector("theta", theta, 3, "rad")
        m = checks.nonnegative("mass", mass, "kg")
        return np.array([m * 9.81 * self.params["l5"] * np.cos(th[0]), 0.0, 0.0])

    def rotation_tcs_to_wcs(self, theta) -> np.ndarray:
        """R_TW of eq. 4.1 (3, 3): maps TCS (fingertip sensor) coordinates into the WCS."""
        th = checks.vector("theta", theta, 3, "rad")
        return cf.rotation_tcs_to_wcs(self.state(th).gamma1, th[2])

    # ------------------------------------------------------------------ limits
    def within_limits(self, theta, tol: float = 1e-9) -> bool:
        """Whether θ respects the joint limits."""
        th = checks.vector("theta", theta, 3, "rad")
        return bool(
            np.all(th >= self.joint_limits[:, 0] - tol)
            and np.all(th <= self.joint_limits[:, 1] + tol)
        )

    @property
    def workspace_center(self) -> np.ndarray:
        """(3,) centre of the well-conditioned trapezoid (App. C.2.1) in the WCS [m]."""
        rho = 0.5 * sum(WORKSPACE_RADII)
        return np.array([rho, 0.0, 0.5 * sum(WORKSPACE_Z)])

    @property
    def center_theta(self) -> np.ndarray:
        """(3,) joint angles at :attr:`workspace_center` [rad]."""
        if self._center_theta is None:
            self._center_theta = self.inverse_kinematics(
                self.workspace_center, np.deg2rad([30.0, 45.0, 0.0])
            )
        return self._center_theta.copy()

    @property
    def torque_limits(self) -> np.ndarray:
        """(3,) motor torque limits [N m], sized so that the force available in every
        direction at the workspace centre is 9 N (App. C.2.1): τ_max,i = 9 N ||J[:, i]||."""
        if self._tau_max is None:
            J = self.jacobian(self.center_theta)
            self._tau_max = MAX_FORCE_AT_CENTER * np.linalg.norm(J, axis=0)
        return self._tau_max.copy()

    def force_capacity(self, theta) -> float:
        """Largest force [N] the motors can apply in *every* direction at θ.

        With |Jᵀ f|_i <= τ_max,i the feasible forces form a parallelepiped whose inscribed
        sphere has radius min_i τ_max,i / ||J[:, i]||.
        """
        J = self.jacobian(theta)
        return float(np.min(self.torque_limits / np.linalg.norm(J, axis=0)))

    @property
    def encoder_resolution(self) -> float:
        """Encoder quantum [rad] such that one count moves the endpoint by at most 0.05 mm at
        the workspace centre (App. C.2.1)."""
        J = self.jacobian(self.center_theta)
        return float(POSITION_RESOLUTION / np.max(np.linalg.norm(J, axis=0)))

    def in_conditioned_workspace(self, x, tol: float = 1e-9) -> bool:
        """Whether ``x`` (3,) [m] lies inside the trapezoid of App. C.2.1 (``tol`` [m] of
        slack on every face, for points computed on its boundary)."""
        p = checks.vector("x", x, 3, "m")
        rho, ang = np.hypot(p[0], p[1]), np.arctan2(p[1], p[0])
        return bool(
            WORKSPACE_RADII[0] - tol <= rho <= WORKSPACE_RADII[1] + tol
            and abs(ang) <= WORKSPACE_HALF_ANGLE + tol / WORKSPACE_RADII[0]
            and WORKSPACE_Z[0] - tol <= p[2] <= WORKSPACE_Z[1] + tol
        )

    # ------------------------------------------------------------------ inverse kinematics
    def inverse_kinematics(
        self, x, theta0=None, tol: float = 1e-12, max_iter: int = 100
    ) -> np.ndarray:
        """Joint angles that put the endpoint at ``x`` (numerical, with joint limits).

        Damped Gauss-Newton on the closed-form FK (eqs. C.4-C.6) and Jacobian (C.7-C.9),
        iterates projected onto the joint limits, steps halved when they leave the closure
        domain of eq. C.5. Starts from ``theta0`` (or the workspace centre with θ3 pointing at
        the target); when that start does not converge, up to 12 more starts are taken from a
        precomputed grid of elbow-up configurations nearest to the target in the five-bar
        plane.

        Args:
            x: (3,) target endpoint in the WCS [m].
            theta0: (3,) initial guess [rad] (default: the workspace-centre configuration).
            tol: position tolerance [m].
            max_iter: iteration limit per start.

        Returns:
            (3,) θ within the joint limits, elbow-up [rad].

        Raises:
            UnreachableTarget: no start converged to ``tol`` inside the joint limits.
        """
        target = checks.vector("x", x, 3, "m")
        lo, hi = self.joint_limits[:, 0], self.joint_limits[:, 1]
        p = self.params
        rho = float(np.hypot(target[0], target[1]))
        r_h2 = float(np.sqrt(max(rho**2 - p["h3"] ** 2, 0.0)))  # r + h2
        t3 = float(
            np.clip(np.arctan2(target[1], target[0]) + np.arctan2(p["h3"], r_h2), lo[2], hi[2])
        )
        if theta0 is None:
            first = (
                self.center_theta
                if self._center_theta is not None
                else np.deg2rad([30.0, 45.0, 0.0])
            )
            first = np.array([first[0], first[1], t3])
        else:
            first = checks.vector("theta0", theta0, 3, "rad")
        best = np.inf
        for k, start in enumerate(self._starts(first, r_h2 - p["h2"], float(target[2]), t3)):
            th, res = self._newton(target, np.clip(start, lo, hi), tol, max_iter)
            if res <= max(tol, 1e-10):
                return th
            best = min(best, res)
            if k >= 12:
                break
        raise UnreachableTarget(
            f"3GM cannot reach x = {target.tolist()} m within the joint limits "
            f"{np.rad2deg(self.joint_limits).round(1).tolist()} deg (best residual "
            f"{best:.3g} m)"
        )

    def _starts(self, first: np.ndarray, r: float, z: float, t3: float):
        """Initial guesses: ``first``, then grid configurations nearest to (r, z) [m]."""
        yield first
        if self._seed_grid is None:
            lo, hi = self.joint_limits[:, 0], self.joint_limits[:, 1]
            rows = []
            for t1 in np.linspace(lo[0], hi[0], 15):
                for t2 in np.linspace(lo[1], hi[1], 15):
                    try:
                        st = cf.five_bar_state(self.params, np.array([t1, t2, 0.0]))
                    except SingularConfiguration:
                        continue
                    rows.append((t1, t2, st.r, st.position[2]))
            self._seed_grid = np.array(rows)
        g = self._seed_grid
        order = np.argsort((g[:, 2] - r) ** 2 + (g[:, 3] - z) ** 2)
        for i in order:
            yield np.array([g[i, 0], g[i, 1], t3])

    def _newton(
        self, target: np.ndarray, th: np.ndarray, tol: float, max_iter: int
    ) -> tuple[np.ndarray, float]:
        """Projected damped Gauss-Newton from ``th``; returns (θ, residual norm [m])."""
        lo, hi = self.joint_limits[:, 0], self.joint_limits[:, 1]
        try:
            err = target - self.forward_kinematics(th)
        except SingularConfiguration:
            return th, np.inf
        lam = 1e-9  # Levenberg-Marquardt damping, relative to the scale of J^T J
        J = None
        for _ in range(max_iter):
            if np.linalg.norm(err) <= tol:
                break
            if J is None:
                try:
                    J = self.jacobian(th)
                except SingularConfiguration:
                    break
            JtJ = J.T @ J
            step = np.linalg.solve(JtJ + lam * np.trace(JtJ) * np.eye(3), J.T @ err)
            alpha, improved = 1.0, False
            while alpha > 1e-3:
                cand = np.clip(th + alpha * step, lo, hi)
                try:
                    e2 = target - self.forward_kinematics(cand)
                except SingularConfiguration:
                    alpha *= 0.5
                    continue
                if np.linalg.norm(e2) < np.linalg.norm(err):
                    th, err, improved, J = cand, e2, True, None
                    break
                alpha *= 0.5
            if improved:
                lam = max(lam * 0.1, 1e-15)
            else:
                lam *= 100.0
                if lam > 1e3:
                    break
        return th, float(np.linalg.norm(err))

    # ------------------------------------------------------------------ Pinocchio
    @property
    def model(self):
        """The Pinocchio model (tree + loop closure, see :mod:`robots.three_gm.model`)."""
        if self._model is None:
            from robots.three_gm.model import build_model

            self._model = build_model(self.params, self.joint_limits)
        return self._model
