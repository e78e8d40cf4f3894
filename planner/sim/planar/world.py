"""The planar world (thesis ch. 2): fixed outlines, free rigid bodies and the planar hand.

State: free bodies by their centre-of-mass pose ``(x, y, theta)`` and velocity
``(vx, vy, omega)`` in the world frame; the hand by ``q, qd`` (6,). The generalized velocity
is ``nu = (v_body_1, ..., v_body_n, qd)``. Every call of :meth:`PlanarWorld.step` runs one
step of the Stewart-Trinkle scheme (:mod:`planner.sim.planar.stepper`): exact contact
geometry (:mod:`planner.sim.planar.contacts`), a position projection when a contact
penetrates by more than ``projection_tolerance``, the per-step LCP with two friction cone
edges per contact, solved exactly by Lemke's method, and the semi-implicit update.

Friction of a pair is the larger of the two bodies' coefficients (MuJoCo's rule, so that
:func:`planner.sim.to_mjcf` builds the same scene).
"""

from __future__ import annotations

import math

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from planner.geometry.profiles import Profile
from planner.sim.observation import Observation, SensorSettings
from planner.sim.planar.bodies import FIXED, FREE, TIP, Body, area_properties
from planner.sim.planar.contacts import Pose
from planner.sim.planar.hand import PAD_DEPTH, HandModel, tip_profile
from planner.sim.planar.outline import compile_outline
from planner.sim.planar.records import contact_records
from planner.sim.planar.sensing import observe as _observe
from planner.sim.planar.stepper import StepResult, step, step_fast
from planner.sim.records import Contact
from planner.sim.world import WorldBase, check_joint_limits, joint_torques

__all__ = ["PlanarWorld"]

FINGER_NAMES = ("left", "right")
JOINT_NAMES = tuple(f"{f}_j{k}" for f in FINGER_NAMES for k in (1, 2, 3))


class PlanarWorld(WorldBase):
    """A planar world with exact contacts and Coulomb friction.

    Args:
        dt: time step [s].
        gravity: (2,) gravity in the plane [m/s^2].
        seed: seed of the generator of every sensor noise.
        sensors: sensor models (default :class:`SensorSettings`).
        margin: contacts closer than this are in the step's contact problem [m].
        projection_tolerance: penetration above which positions are projected out [m].
        drop_time: a body touched by a fingertip and then by none for this long is reported
            ``object_dropped`` [s].
        compiled: run the step's dynamics, contact rows and LCP in the compiled kernel
            (:func:`planner.sim.planar.stepper.step_fast`); False: the Python reference
            (:func:`planner.sim.planar.stepper.step`). Both give the same state to ~1e-15.
            With ``compiled``, :meth:`run` also uses the compiled run loop
            (:mod:`planner.sim.planar.fast_run`; the same log as ``loop="python"``).
    """

    pose_size, velocity_size, contact_dim = 3, 3, 2

    def __init__(
        self,
        dt: float = 1e-3,
        gravity=(0.0, -9.81),
        seed: int = 0,
        sensors: SensorSettings | None = None,
        margin: float = 1e-3,
        projection_tolerance: float = 1e-7,
        drop_time: float = 0.1,
        compiled: bool = True,
    ) -> None:
        self.dt = checks.positive("dt", dt, "s")
        self.gravity = tuple(checks.vector("gravity", gravity, 2, "m/s^2"))
        self.margin = checks.positive("margin", margin, "m")
        self.projection_tolerance = checks.positive(
            "projection_tolerance", projection_tolerance, "m"
        )
        self.drop_time = checks.positive("drop_time", drop_time, "s")
        self.compiled = bool(compiled)
        if sensors is not None and not isinstance(sensors, SensorSettings):
            raise InvalidParameter(
                f"sensors: expected a SensorSettings or None, got {checks.shown(sensors)}"
            )
        self.sensors = sensors if sensors is not None else SensorSettings()
        self.rng = np.random.default_rng(checks.integer("seed", seed, 0))
        self.time = 0.0
        self.bodies: list[Body] = []
        self._names: dict[str, Body] = {}
        self._x = np.zeros((0, 3))
        self._v = np.zeros((0, 3))
        self.hand: HandModel | None = None
        self.q = np.zeros(0)
        self.qd = np.zeros(0)
        self._events = []
        self._pending: tuple | None = None  # a compiled step's raw result (see _last)
        self._last_result: StepResult | None = None
        self._records: tuple[Contact, ...] | None = None
        self._touch: dict[str, float] = {}
        self._dropped: set[str] = set()
        self._limits_on: set[int] = set()
        #: penetration [m] a jammed position projection left in the last step (0: none;
        #: set by :func:`planner.sim.planar.stepper._project`)
        self.jam = 0.0
        self._jammed = False
        #: the world's time after its last Python step (the step ``jam`` speaks of) [s]
        self._jam_time = 0.0

    # ------------------------------------------------------------------ last step
    @property
    def _last(self) -> StepResult | None:
        """The last step's :class:`StepResult`; the compiled run loop leaves its raw arrays
        (:meth:`_set_pending`), turned into the result only when something reads it."""
        if self._pending is not None:
            from planner.sim.planar.stepper import _result

            self._last_result, self._pending = _result(*self._pending), None
        return self._last_result

    @_last.setter
    def _last(self, res: StepResult | None) -> None:
        self._last_result, self._pending = res, None

    def _set_pending(self, rows: np.ndarray, mu, pn, pt, slip, lj, lp) -> None:
        """The last step's result as the kernel's arrays: candidate rows (n, 10) (a copy;
        columns of :func:`planner.sim.planar.stepper._result`), mu, impulses, slip, limit
        rows."""
        self._pending, self._last_result, self._records = (
            (rows, mu, pn, pt, slip, lj, lp),
            None,
            None,
        )

    def _step_rows(self) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """``(rows (n, 10), p_n (n,), p_t (n,))`` of the last step (None before the first):
        the kernel's arrays when pending, else rebuilt from the :class:`StepResult`."""
        if self._pending is not None:
            return self._pending[0], self._pending[2], self._pending[3]
        res = self._last_result
        if res is None:
            return None
        rows = np.column_stack(
            [res.body_a, res.body_b, res.gap, res.point_a, res.point_b, res.normal, res.curvature]
        ).astype(float)
        return rows.reshape(-1, 10), res.p_n, res.p_t

    # ------------------------------------------------------------------ building
    def _name(self, name: str | None, stem: str) -> str:
        if name is None:
            k = sum(1 for b in self.bodies if b.name.startswith(stem))
            name = f"{stem}{k}"
        if name in self._names:
            raise InvalidParameter(f"name: {name!r} is already used by another body")
        return str(name)

    def _add(self, body: Body) -> str:
        self.bodies.append(body)
        self._names[body.name] = body
        self._last, self._records = None, None
        return body.name

    def add_fixed(self, profile: Profile, pose=(0.0, 0.0, 0.0), friction: float = 0.5, name=None):
        """Add a fixed outline (palm, incline, table...) at ``pose`` (x, y, angle) [m, rad]."""
        p = checks.vector("pose", pose, 3, "m, m, rad")
        mu = checks.nonnegative("friction", friction)
        b = Body(self._name(name, "fixed"), FIXED, compile_outline(profile), mu, pose=tuple(p))
        return self._add(b)

    def add_body(
        self,
        profile: Profile,
        pose,
        mass: float,
        inertia: float | None = None,
        velocity=(0.0, 0.0, 0.0),
        friction: float = 0.5,
        name: str | None = None,
    ) -> str:
        """Add a free rigid body bounded by the closed ``profile``.

        Args:
            profile: closed outline in the body's own frame.
            pose: (x, y, angle) of the profile's frame [m, rad].
            mass: [kg] > 0.
            inertia: about the centre of mass [kg m^2]; default: uniform density.
            velocity: (vx, vy, omega) of the profile frame's origin [m/s, rad/s].
            friction: Coulomb coefficient [-].
            name: handle (default ``body0``, ``body1``...).
        """
        if not isinstance(profile, Profile):
            raise InvalidParameter(
                f"profile: expected a closed planner.geometry Profile, got {checks.shown(profile)}"
            )
        m = checks.positive("mass", mass, "kg")
        p = checks.vector("pose", pose, 3, "m, m, rad")
        v = checks.vector("velocity", velocity, 3, "m/s, m/s, rad/s")
        mu = checks.nonnegative("friction", friction)
        area, com, J = area_properties(profile)
        arcs = profile.pieces
        if len(arcs) == 1 and getattr(arcs[0], "radius", None) is not None:
            J = area * arcs[0].radius ** 2 / 2.0  # a disc: exact
        I = checks.positive("inertia", inertia, "kg m^2") if inertia is not None else m * J / area
        local = profile.transformed(0.0, -com)
        ol = compile_outline(local)
        c, s = math.cos(p[2]), math.sin(p[2])
        cw = p[:2] + np.array([c * com[0] - s * com[1], s * com[0] + c * com[1]])
        # velocity of the centre of mass from that of the frame origin
        rx, ry = cw[0] - p[0], cw[1] - p[1]
        vc = np.array([v[0] - v[2] * ry, v[1] + v[2] * rx, v[2]])
        body = Body(self._name(name, "body"), FREE, ol, mu, index=len(self._x), mass=m, inertia=I)
        body.com = (float(com[0]), float(com[1]))
        self._x = np.vstack([self._x, [cw[0], cw[1], p[2]]])
        self._v = np.vstack([self._v, vc])
        return self._add(body)

    def add_hand(
        self, hand, q, qd=None, name: str = "hand", palm: bool = True, pad_depth=PAD_DEPTH
    ) -> str:
        """Add the planar two-finger hand with joint angles ``q`` (6,) [rad] within its joint
        limits (``hand.joint_limits``; InvalidParameter naming the joint otherwise).

        Its fingertips become bodies ``<name>.left`` and ``<name>.right``; with ``palm`` the
        palm segment becomes the fixed outline ``<name>.palm`` (y = 0, facing +y).
        ``pad_depth`` [m] > 0: how deep a flat fingertip's body reaches behind its pad
        (:data:`~planner.sim.planar.hand.PAD_DEPTH`; ``inf`` to see everything behind a pad
        as inside it, as a start-pose overlap check wants).
        """
        if self.hand is not None:
            raise InvalidParameter("add_hand: this world already has a hand")
        from planner.geometry import shapes
        from robots.planar_hand import PlanarHand

        if not isinstance(hand, PlanarHand):
            raise InvalidParameter(
                f"hand: expected a robots.planar_hand.PlanarHand, got {checks.shown(hand)}"
            )
        q = checks.vector("q", q, 6, "rad")
        check_joint_limits("q", q, hand.joint_limits, JOINT_NAMES)
        qd = np.zeros(6) if qd is None else checks.vector("qd", qd, 6, "rad/s")
        self.hand = HandModel(hand, self.gravity)
        self.q, self.qd = q.copy(), qd.copy()
        self.hand_name = str(name)
        mu = float(hand.params.friction)
        pad_depth = checks.positive("pad_depth", pad_depth, "m", allow_inf=True)
        for k, f in enumerate(FINGER_NAMES):
            tip = tip_profile(hand, f)
            ol = compile_outline(tip, depth=math.inf if tip.closed else pad_depth)
            self._add(Body(self._name(f"{name}.{f}", ""), TIP, ol, mu, index=k))
        if palm:
            w = hand.params.palm_half_width
            self.add_fixed(shapes.plane(0.0, 2 * w), (0.0, 0.0, 0.0), mu, f"{name}.palm")
        return self.hand_name

    # ------------------------------------------------------------------ state access
    @property
    def body_names(self) -> tuple[str, ...]:
        """Handles of the free bodies (logged)."""
        return tuple(b.name for b in self.bodies if b.kind == FREE)

    @property
    def n_joints(self) -> int:
        return 0 if self.hand is None else 6

    @property
    def torque_limits(self):
        return None if self.hand is None else self.hand.torque_limits

    def _body(self, handle: str) -> Body:
        try:
            return self._names[handle]
        except KeyError:
            raise InvalidParameter(
                f"unknown body {handle!r}; bodies: {sorted(self._names)}"
            ) from None

    def placement(self, body: Body) -> Pose:
        """World placement of a body's outline frame."""
        if body.kind == FIXED:
            return Pose(*body.pose)
        if body.kind == FREE:
            return Pose(*self._x[body.index])
        _, tips = self.hand.frames(self.q)
        return Pose(*tips[body.index])

    def pose(self, handle: str) -> np.ndarray:
        """(x, y, angle) of the body's frame (free: the profile's frame) [m, rad]."""
        b = self._body(handle)
        if b.kind == FREE:
            x, y, a = self._x[b.index]
            c, s = math.cos(a), math.sin(a)
            return np.array([x - c * b.com[0] + s * b.com[1], y - s * b.com[0] - c * b.com[1], a])
        P = self.placement(b)
        return np.array([P.x, P.y, math.atan2(P.s, P.c)])

    def velocity(self, handle: str) -> np.ndarray:
        """(vx, vy, omega) of the body's frame origin [m/s, rad/s] (fixed: zeros)."""
        b = self._body(handle)
        if b.kind == FIXED:
            return np.zeros(3)
        if b.kind == FREE:
            vx, vy, w = self._v[b.index]
            px, py, _ = self.pose(handle)
            rx, ry = px - self._x[b.index, 0], py - self._x[b.index, 1]
            return np.array([vx - w * ry, vy + w * rx, w])
        from planner.sim.planar.stepper import point_velocity

        P = self.placement(b)
        vx, vy = point_velocity(self, b, P.x, P.y)
        sl = slice(3 * b.index, 3 * b.index + 3)
        return np.array([vx, vy, float(self.qd[sl].sum())])

    def joint_state(self) -> tuple[np.ndarray, np.ndarray]:
        return self.q.copy(), self.qd.copy()

    def state_vector(self) -> np.ndarray:
        return np.concatenate([self._x.ravel(), self._v.ravel(), self.q, self.qd])

    def velocity_vector(self) -> np.ndarray:
        return np.concatenate([self._v.ravel(), self.qd])

    def set_state(self, handle: str, pose=None, velocity=None) -> None:
        """Reset a free body's centre-of-mass pose/velocity (x, y, angle) / (vx, vy, omega)."""
        b = self._body(handle)
        if b.kind != FREE:
            raise InvalidParameter(f"{handle!r} is not a free body")
        if pose is not None:
            self._x[b.index] = checks.vector("pose", pose, 3)
        if velocity is not None:
            self._v[b.index] = checks.vector("velocity", velocity, 3)
        self._last, self._records = None, None

    # ------------------------------------------------------------------ stepping
    def step(self, tau=None) -> None:
        """Advance one step ``dt`` with joint torques ``tau`` (6,) [N m] (None: zeros).

        Raises:
            InvalidParameter: ``tau`` is not 6 finite numbers, or torques were given to a
                world without a hand.
        """
        if self.hand is not None:
            tau = np.zeros(6) if tau is None else joint_torques(tau, 6, "joint torques of the hand")
        elif tau is not None and np.size(tau):
            raise InvalidParameter("tau: this world has no hand to apply joint torques to")
        self.jam = 0.0
        res = step_fast(self, tau) if self.compiled else step(self, tau)
        self._last, self._records = res, None
        self.time += self.dt
        self._jam_time = self.time
        self._watch(res)

    def _unjam_after_kernel(self) -> None:
        """Clear the jam state when the compiled run kernel stepped since the last Python
        step (the kernel hands every position projection back to Python, so its steps never
        jam): the next jam is a new ``jammed`` event, as in the reference loop. Called by
        :class:`planner.sim.planar.fast_run.FastLoop` whenever it hands the world back."""
        if self.time > self._jam_time + 0.5 * self.dt:
            self.jam, self._jammed = 0.0, False

    def _watch(self, res: StepResult) -> None:
        """World events: joint limits reached, objects dropped by the fingers, contacts
        jammed."""
        if (self.jam > 0.0) != self._jammed:
            self._jammed = self.jam > 0.0
            if self._jammed:
                self._events.append(
                    _event(self.time, "jammed", "contacts jammed: no displacement removes every "
                           f"penetration; {1e3 * self.jam:.3f} mm left", penetration=self.jam)
                )  # fmt: skip
        lj, lp = res.limit_joints.tolist(), res.limit_impulses.tolist()
        on = {int(k) for k, p in zip(lj, lp, strict=True) if p > 0}
        for k in sorted(on - self._limits_on):
            self._events.append(
                _event(self.time, "joint_limit", f"joint {k} reached its limit", joint=k)
            )
        self._limits_on = on
        ia, ib, pns = res.body_a.tolist(), res.body_b.tolist(), res.p_n.tolist()
        for i, j, pn in zip(ia, ib, pns, strict=True):
            a, b = self.bodies[i], self.bodies[j]
            if pn > 0 and (a.kind == TIP or b.kind == TIP):
                other = b if a.kind == TIP else a
                if other.kind == FREE:
                    self._touch[other.name] = self.time
                    self._dropped.discard(other.name)
        for name, t in self._touch.items():
            if name not in self._dropped and self.time - t >= self.drop_time - 1e-12:
                self._dropped.add(name)
                self._events.append(
                    _event(self.time, "object_dropped", f"{name} left the fingers", body=name)
                )

    def compiled_loop(self, state):
        """The compiled run loop for ``state`` (:mod:`planner.sim.planar.fast_run`), or
        None with ``compiled=False`` (then :func:`planner.sim.loop.run` runs the reference
        loop)."""
        if not self.compiled:
            return None
        from planner.sim.planar.fast_run import FastLoop

        return FastLoop(state)

    def active_pairs(self) -> set[tuple[str, str]]:
        """Body-name pairs carrying a normal force after the last step."""
        res = self._last
        if res is None:
            return set()
        b = self.bodies
        ia, ib, pn = res.body_a.tolist(), res.body_b.tolist(), res.p_n.tolist()
        return {(b[i].name, b[j].name) for i, j, p in zip(ia, ib, pn, strict=True) if p > 0.0}

    def record(self, log, k: int, tau) -> None:
        """Write the current state into row ``k`` of ``log`` (from the step's arrays; the
        same values as :meth:`WorldBase.record` from :meth:`contacts`)."""
        log.t[k] = self.time
        for name in log.poses:
            b = self._names[name]
            if b.kind != FREE:
                log.poses[name][k] = self.pose(name)
                log.velocities[name][k] = self.velocity(name)
                continue
            x, y, a = self._x[b.index].tolist()
            vx, vy, w = self._v[b.index].tolist()
            c, s = math.cos(a), math.sin(a)
            rx, ry = -c * b.com[0] + s * b.com[1], -s * b.com[0] - c * b.com[1]
            log.poses[name][k] = (x + rx, y + ry, a)
            log.velocities[name][k] = (vx - w * ry, vy + w * rx, w)
        if self.hand is not None:
            log.q[k], log.qd[k], log.tau[k] = self.q, self.qd, tau
        res = self._last
        n = 0 if res is None else len(res.gap)
        log.contact_count[k] = n
        m = min(n, log.max_contacts)
        if m == 0:
            return
        h = self.dt
        b = self.bodies
        ia, ib = res.body_a[:m].tolist(), res.body_b[:m].tolist()
        cache = log.__dict__.setdefault("_pair_of_bodies", {})
        for i, key in enumerate(zip(ia, ib, strict=True)):
            p = cache.get(key)
            if p is None:
                p = cache[key] = log.pair_index(b[key[0]].name, b[key[1]].name)
            log.contact_pair[k, i] = p
        log.contact_point[k, :m] = res.point_b[:m]
        log.contact_normal[k, :m] = res.normal[:m]
        log.normal_force[k, :m] = res.p_n[:m] / h
        log.tangential_force[k, :m] = res.p_t[:m] / h
        log.slip_velocity[k, :m] = res.slip[:m]
        log.gap[k, :m] = res.gap[:m]

    def contacts(self) -> tuple[Contact, ...]:
        """Contacts of the last step: geometry at its start, forces over it, slip after it."""
        if self._last is None:
            return ()
        if self._records is None:
            self._records = contact_records(self, self._last)
        return self._records

    def penetrations(self, tolerance: float = 1e-9) -> list[tuple[str, str, float]]:
        """Body pairs overlapping by more than ``tolerance`` [m] now: ``(a, b, gap)`` once
        per pair, ``gap`` < 0 its deepest contact point's [m] (a pair may touch at several
        points: a box flat on a plane at two), deepest pair first."""
        from planner.sim.planar.stepper import find_contacts

        deepest: dict[tuple[int, int], float] = {}
        for c in find_contacts(self, 0.0):
            if c[2] < -tolerance:
                key = (c[0], c[1])
                deepest[key] = min(c[2], deepest.get(key, 0.0))
        pairs = sorted(deepest.items(), key=lambda kv: kv[1])
        return [(self.bodies[i].name, self.bodies[j].name, gap) for (i, j), gap in pairs]

    def logged_overlap(self, log) -> np.ndarray:
        """(T,) the deepest overlap [m] of any two bodies in each state ``log`` (a run of
        this world) recorded, 0 where none touch too deep. A step can leave more than the
        log's ``gap`` shows: that gap is measured at the start of the next step, after its
        projection (``planner/sim/planar/stepper.py``, Limits). The world's state is
        restored afterwards."""
        from planner.sim.planar.stepper import find_contacts

        saved = (self._x.copy(), self._v.copy(), self.q.copy(), self.qd.copy())
        cache = (self._last, self._records)
        free = [b for b in self.bodies if b.kind == FREE]
        out = np.zeros(len(log.t))
        try:
            for k in range(len(log.t)):
                for b in free:
                    self._x[b.index] = log.poses[b.name][k]
                if self.hand is not None:
                    self.q = np.array(log.q[k], float)
                gaps = [c[2] for c in find_contacts(self, 0.0)]
                out[k] = max(0.0, -min(gaps, default=0.0))
        finally:
            self._x, self._v, self.q, self.qd = saved
            self._last, self._records = cache
        return out

    # ------------------------------------------------------------------ sensing
    def observe(self, oracle: bool = False) -> Observation:
        """Sensor readings now (encoders, fingertip gauges, tactile images of flat pads)."""
        return _observe(self, oracle)


def _event(t, kind, message, **data):
    from planner.sim.events import SimEvent

    return SimEvent(t, kind, message, data)
