"""The spatial world (ch. 4): spheres and the 3GM fingertip on exact surfaces.

Frames and units: everything is in the WCS of §4.3.2 — the 3GM's base frame, ``z`` vertical
(up, against gravity), SI units (m, kg, s, rad, N). Surfaces are placed by a 4x4 ``pose``
``T_WS`` (surface frame -> WCS).

Time stepping (semi-implicit, velocity level, the same scheme as the planar world), per step
of length ``h``:

1. free velocities ``ν_f = ν + h M⁻¹ (τ - b)`` (spheres: ``v + h g``; the 3GM: reduced
   dynamics of :mod:`planner.sim.spatial.finger`, torques clipped by the run loop);
2. contact candidates: for each sphere (and the fingertip sphere) and each surface, the exact
   foot point, normal and gap at the current positions (:mod:`planner.sim.spatial.closest`);
   a candidate enters the contact problem when its gap is below ``2 h |ν| + 10 µm``;
3. the contact problem with the EXACT circular Coulomb cone
   (:mod:`planner.sim.spatial.friction_cone`), ``W = J M⁻¹ Jᵀ`` from the contact-point
   Jacobian ``J`` in the contact frame ``(n, t1, t2)``; ``ν⁺ = ν_f + M⁻¹ Jᵀ λ``;
4. positions ``x⁺ = x + h ν⁺`` (quaternions by the exact exponential map; the 3GM's motor
   angles, the loop closed in closed form);
5. projection (post-stabilization): every contact that carried force (``λ_n > 0``) is
   projected onto its offset surface, ``g = 0``, and every candidate that ends the step
   penetrating (a curvature effect of the linearized gap, ``O(h² |v|² κ)``) back onto it, by
   a mass-weighted Gauss-Newton step along the centre Jacobian (spheres: a translation along
   ``n``), until ``|g| <= 1e-12 m``. So a sliding or sticking sphere centre stays on the
   exact offset surface to round-off (no penetration, no hovering), without any stiffness or
   Baumgarte gain.

Joint limits of the 3GM (``three_gm.joint_limits``) are unilateral constraints of the same
problem: a joint within reach of a limit adds the row ``±e_i`` with
``0 <= λ_i ⊥ (θ_i - θ_lim)/h ± θ̇_i⁺ >= 0`` (a joint already beyond is held, not pushed back),
coupled with the contact by block Gauss-Seidel over the exact cone and the scalar rows; the
projection of step 5 keeps held joints fixed (``M⁻¹`` conditioned on them). A joint that
starts to be held emits a ``joint_limit`` event (data: ``joint``, ``side``, ``limit``,
``theta``).

One finger over one :class:`Plate`/:class:`Plane` (dynamics compiled) runs as
ONE compiled call per step (:mod:`planner.sim.spatial.step_kernel`: dynamics, foot, cone,
limits, integration, projection, contact record, OWTS rows), with compiled ``record`` and
``observe``; everything else through :mod:`planner.sim.spatial.stepping`, the reference; both
give the same trajectories (tested on random states to ~1e-12).

Contact records (``contacts()``): the contacts of the last step that carried force
(``λ_n > 0``); forces are impulses / h; ``tangential_force`` and ``slip_velocity`` are
(3,) WCS vectors in the tangent plane, the slip of the sphere's material point relative to
the surface after the step. Friction of a contact: the larger of the coefficients given to
the surface and to the body (a body's ``None`` leaves the surface's value): MuJoCo's rule,
as in the planar world, so that :func:`planner.sim.to_mjcf` builds the same scene (until
2026-11-25 it was the smaller one here, and the export differed when a body's was smaller).

Limits: one contact per sphere and surface (a sphere wider than a concave groove touches
it at two points: only the nearest foot is modelled); spheres do not collide with each other
or with the finger.
"""

from __future__ import annotations

import math

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from planner.sim.events import SimEvent
from planner.sim.observation import Observation, SensorSettings
from planner.sim.records import Contact
from planner.sim.spatial import step_kernel as sk
from planner.sim.spatial.bodies import FingerBody, SphereBody
from planner.sim.spatial.closest import PlacedSurface
from planner.sim.spatial.fast_step import KernelContact, fast_plate
from planner.sim.spatial.observing import observe, record_owts
from planner.sim.spatial.recording import record
from planner.sim.spatial.sensing import (
    SAMPLE_RATE,
    OWTSRecorder,
)
from planner.sim.spatial.step_kernel import FALLBACK
from planner.sim.spatial.stepping import step_body
from planner.sim.world import WorldBase, check_joint_limits, joint_torques

__all__ = ["SpatialWorld"]


class SpatialWorld(WorldBase):
    """Spheres and the 3GM fingertip in contact with fixed surfaces (see the module doc).

    Args:
        dt: time step [s].
        gravity: (3,) gravity in the WCS [m/s²].
        seed: seed of the world's generator (the only source of sensor noise).
        sensors: sensor models (None: defaults; the 3GM's encoder resolution of App. C.2.1
            and an ideal-geometry :class:`~robots.sensors.OWTS` of the tip's radius).
        all_contacts: find every point where a sphere touches a :class:`Plate` (a groove
            narrower than the sphere is touched on both rims, a step at its foot and edge;
            :meth:`.closest.PlacedSurface.other_feet`) and solve them together. False: one
            contact per sphere and surface, the one the warm Newton tracks: exact while the
            sphere is narrower than every groove (``Plate.concave_radius``), else it can sink
            into the far rim (0.87 mm for the 8 mm tip across a 2 mm ravine). True costs a
            search under the sphere near features and runs the steps with several contacts
            through the general (Python) path.
    """

    pose_size = 7
    velocity_size = 6
    contact_dim = 3

    def __init__(
        self, dt=1e-3, gravity=(0.0, 0.0, -9.81), seed=0, sensors=None, all_contacts=False
    ) -> None:
        self.dt = checks.positive("dt", dt, "s")
        self.all_contacts = checks.boolean("all_contacts", all_contacts)
        self.gravity = checks.vector("gravity", gravity, 3, "m/s^2")
        self.seed = checks.integer("seed", seed, 0)
        self.rng = np.random.default_rng(self.seed)
        self._user_sensors = sensors
        self.sensors = sensors if sensors is not None else SensorSettings()
        self.time = 0.0
        self.surfaces: dict[str, tuple[PlacedSurface, float]] = {}
        self.spheres: dict[str, SphereBody] = {}
        self.finger: FingerBody | None = None
        self._hints: dict[tuple[str, str], object] = {}
        self._contacts: tuple[Contact, ...] = ()
        self._events: list[SimEvent] = []
        self._owts: OWTSRecorder | None = None
        self._held_mask = 0  # joints held at a limit after the last step (bits)
        self._from_kernel = False  # the last step's contact lives in finger.x
        self._zero3 = np.zeros(3)
        self._rec = None  # (log, its arrays, pair index) of the compiled record
        self._sense = False  # packed sensor settings (False: not built yet)
        self.steps = 0
        self._fast = False  # packed plate of the kernel path (False: not built yet)
        #: use the scalar kernels for one finger over one Plate/Plane (same results)
        self.use_kernels = True

    # ------------------------------------------------------------------ building
    def _name(self, name, prefix: str) -> str:
        taken = (
            set(self.surfaces) | set(self.spheres) | ({self.finger.name} if self.finger else set())
        )
        if name is None:
            k = 0
            while f"{prefix}{k}" in taken:
                k += 1
            return f"{prefix}{k}"
        name = str(name)
        if name in taken or "|" in name or not name:
            raise InvalidParameter(f"name: {name!r} is empty, contains '|' or is already used")
        return name

    def add_surface(self, surface, friction: float = 0.5, name=None, pose=None) -> str:
        """Add a fixed surface; returns its handle.

        Args:
            surface: a :class:`~planner.sim.spatial.Plane` (any tilt), a
                :class:`~planner.sim.spatial.Plate` of catalogue features, a
                :class:`~planner.geometry.surfaces.HeightField` or any
                :class:`~planner.geometry.surfaces.ParametricSurface` of the catalogue.
            friction: Coulomb coefficient μ [-] (>= 0).
            name: handle (default ``surface<k>``).
            pose: 4x4 ``T_WS`` placing the surface frame in the WCS (default identity).
        """
        mu = checks.nonnegative("friction", friction)
        placed = PlacedSurface(surface, pose)
        name = self._name(name, "surface")
        for b in self._bodies():
            self._check_clear(b, placed, name)
        self.surfaces[name] = (placed, mu)
        self._fast = False
        return name

    def add_sphere(
        self,
        radius: float,
        mass: float,
        position,
        velocity=(0.0, 0.0, 0.0),
        friction: float | None = None,
        name=None,
        angular_velocity=(0.0, 0.0, 0.0),
    ) -> str:
        """Add a free solid ball (uniform density) centred at ``position`` (3,) [m].

        Args:
            radius: [m]; mass: [kg]; velocity, angular_velocity: (3,) WCS [m/s, rad/s].
            friction: μ of the ball (None: the surfaces' values; a contact takes the larger
                of the ball's and the surface's).
        """
        r = checks.positive("radius", radius, "m")
        m = checks.positive("mass", mass, "kg")
        p = checks.vector("position", position, 3, "m")
        v = checks.vector("velocity", velocity, 3, "m/s")
        w = checks.vector("angular_velocity", angular_velocity, 3, "rad/s")
        mu = None if friction is None else checks.nonnegative("friction", friction)
        body = SphereBody(self._name(name, "sphere"), r, m, p, v, w, mu)
        for sname, (surf, _) in self.surfaces.items():
            self._check_clear(body, surf, sname)
        self.spheres[body.name] = body
        self._fast = False
        return body.name

    def add_finger(
        self,
        three_gm,
        theta,
        tip_radius: float = 0.008,
        name: str = "finger",
        theta_dot=(0.0, 0.0, 0.0),
        friction: float | None = None,
    ) -> str:
        """Add the 3GM finger at motor angles ``theta`` = (θ1, θ2, θ3) [rad].

        The fingertip is a sphere of ``tip_radius`` [m] centred at the 3GM endpoint, rigid
        with the distal link. Inputs of ``step`` are the motor torques (3,) [N m] (limits:
        ``three_gm.torque_limits``, App. C.2.1). ``theta_dot``: (3,) motor speeds [rad/s];
        ``friction``: μ of the fingertip (None: the surfaces' values; a contact takes the
        larger of the tip's and the surface's).

        Raises:
            InvalidParameter: a second finger, a motor angle outside
                ``three_gm.joint_limits``, or a start in penetration.
            SingularConfiguration: the loop cannot close at ``theta``.
        """
        from robots.three_gm import ThreeGM

        if self.finger is not None:
            raise InvalidParameter("add_finger: the spatial world holds one 3GM finger")
        if not isinstance(three_gm, ThreeGM):
            raise InvalidParameter(f"three_gm: expected a ThreeGM, got {type(three_gm).__name__}")
        th = checks.vector("theta", theta, 3, "rad")
        check_joint_limits("theta", th, three_gm.joint_limits, ("theta1", "theta2", "theta3"))
        thd = checks.vector("theta_dot", theta_dot, 3, "rad/s")
        r = checks.positive("tip_radius", tip_radius, "m")
        mu = None if friction is None else checks.nonnegative("friction", friction)
        body = FingerBody(self._name(name, "finger"), three_gm, th, thd, r, mu, self.gravity)
        for sname, (surf, _) in self.surfaces.items():
            self._check_clear(body, surf, sname)
        self.finger = body
        self._fast = False
        self._tau_max = np.array(three_gm.torque_limits, float)
        self._tau_max.flags.writeable = False
        self._owts_per_step = int(math.ceil(self.dt * SAMPLE_RATE)) + 1
        from robots.sensors import OWTS, Encoder

        if self._user_sensors is None:
            self.sensors = SensorSettings(
                encoder=Encoder(three_gm.encoder_resolution), tactile=None, owts=OWTS(radius=r)
            )
        self._owts = OWTSRecorder(self.sensors.owts or OWTS(radius=r), self.rng)
        self._sense = False
        return body.name

    def _check_clear(self, body, surf: PlacedSurface, sname: str) -> None:
        foot = surf.foot(body.center)
        if foot is not None and foot.distance - body.radius < -1e-9:
            raise InvalidParameter(
                f"{body.name}: starts in penetration with {sname} "
                f"(gap {foot.distance - body.radius:.3g} m < 0)"
            )

    def _bodies(self) -> list:
        return [*self.spheres.values(), *([self.finger] if self.finger else [])]

    # ------------------------------------------------------------------ protocol
    @property
    def body_names(self) -> tuple[str, ...]:
        """Logged bodies: the spheres, then the finger (its pose: tip centre + TCS)."""
        return tuple(b.name for b in self._bodies())

    @property
    def n_joints(self) -> int:
        return 3 if self.finger else 0

    @property
    def torque_limits(self) -> np.ndarray | None:
        """(3,) motor torque limits [N m] (read-only) or None without a finger."""
        return self._tau_max if self.finger else None

    def _body(self, handle: str):
        if handle in self.spheres:
            return self.spheres[handle]
        if self.finger is not None and handle == self.finger.name:
            return self.finger
        raise InvalidParameter(f"handle: unknown body {handle!r}; bodies: {list(self.body_names)}")

    def pose(self, handle: str) -> np.ndarray:
        """(7,) centre [m] and orientation quaternion (wxyz) in the WCS (finger: tip centre
        and the TCS)."""
        return self._body(handle).pose()

    def velocity(self, handle: str) -> np.ndarray:
        """(6,) linear velocity of the centre [m/s] and angular velocity [rad/s], WCS."""
        return self._body(handle).velocity()

    def joint_state(self) -> tuple[np.ndarray, np.ndarray]:
        """The 3GM's true motor angles (θ1, θ2, θ3) [rad] and rates [rad/s]."""
        if self.finger is None:
            return np.zeros(0), np.zeros(0)
        return self.finger.th.copy(), self.finger.thd.copy()

    def contacts(self) -> tuple[Contact, ...]:
        """The contacts of the last step that carried force (records built on demand)."""
        if self._contacts is None:  # the kernel's step: its contact lives in finger.x
            x = self.finger.x
            self._contacts = (
                (KernelContact((self.finger.name, self._fast.name), x[sk.FN : sk.GAP + 1].copy()),)
                if x[sk.ACT] > 0.0
                else ()
            )
        return self._contacts

    def state_vector(self) -> np.ndarray:
        """Every position and velocity (for the run loop's NaN guard; a view of the state
        when the world holds the finger alone: read it, do not keep it)."""
        if not self.spheres and self.finger is not None:
            return self.finger.state_view
        parts = [np.concatenate([b.pose(), b.velocity()]) for b in self.spheres.values()]
        if self.finger:
            parts.append(np.concatenate([self.finger.th, self.finger.thd]))
        return np.concatenate(parts) if parts else np.zeros(0)

    def velocity_vector(self) -> np.ndarray:
        """Every velocity (for the runaway guard; a view as :meth:`state_vector`)."""
        if not self.spheres and self.finger is not None:
            return self.finger.rate_view
        parts = [b.velocity() for b in self.spheres.values()]
        if self.finger:
            parts.append(self.finger.thd)
        return np.concatenate(parts) if parts else np.zeros(0)

    def record(self, log, k: int, tau: np.ndarray) -> None:
        """Write the current state into row ``k`` of ``log`` (the rows of
        :meth:`WorldBase.record`, faster: :func:`planner.sim.spatial.recording.record`)."""
        record(self, log, k, tau)

    # ------------------------------------------------------------------ stepping
    def step(self, tau=None) -> None:
        """Advance by ``dt``. ``tau``: (3,) motor torques of the 3GM [N m] (None: zeros);
        clipped at the torque limits (the run loop reports the saturation).

        Raises:
            InvalidParameter: ``tau`` is not 3 finite numbers, or torques were given to a
                world without a finger.
            SingularConfiguration: the 3GM reached a configuration where its loop cannot
                close or its passive links align (the run loop makes it a "singular" event).
        """
        f = self.finger
        if f is None and tau is not None and np.size(tau):
            raise InvalidParameter("tau: this world has no finger to apply motor torques to")
        if f is not None:
            t = self._zero3 if tau is None else joint_torques(tau, 3, "motor torques")
            if self._fast is False:
                self._fast = fast_plate(self) if self.use_kernels else None
            if self._fast is not None:
                code = self._step_kernel(f, t)
                if code >= 0:
                    self.time += self.dt
                    self.steps += 1
                    return
        contacts: list[Contact] = []
        for body in self.spheres.values():
            contacts += step_body(self, body, None)[0]
        if f is not None:
            t = np.clip(t, -self._tau_max, self._tau_max)
            got, held = step_body(self, f, t)
            f.x[sk.LIM : sk.LIM + 3] = held
            contacts += got
            self._limit_events(f, [int(i) for i in np.flatnonzero(held)])
        self.time += self.dt
        self.steps += 1
        self._contacts = tuple(contacts)
        self._from_kernel = False
        if f is not None:
            self._record_owts(contacts)

    def _step_kernel(self, f, tau) -> int:
        """One step through :class:`.fast_step.FingerKernel`; the kernel's code (< 0: the
        general path must run, nothing has been changed)."""
        self._owts.reserve(self._owts_per_step)
        code = self._fast.step(f.x, tau, self.time + self.dt, self._owts)
        if code == FALLBACK:
            return code
        if code < 0:
            raise f._singular(f.x[sk.SIN])
        self._from_kernel = True
        self._contacts = None  # built on demand from f.x
        held = code & 7
        if held != self._held_mask:
            self._limit_events(f, [i for i in range(3) if held >> i & 1])
        return code

    def drain_events(self) -> list[SimEvent]:
        """The world events since the last call (and forget them)."""
        if not self._events:
            return []
        out, self._events = self._events, []
        return out

    def _limit_events(self, f, held: list[int]) -> None:
        """A ``joint_limit`` event for every joint that starts to be held at a limit."""
        mask = sum(1 << i for i in held)
        new = mask & ~self._held_mask
        self._held_mask = mask
        for i in range(3):
            if new >> i & 1:
                side = "lower" if f.x[sk.LIM + i] > 0 else "upper"
                lim = float(f.limits[i, 0 if side == "lower" else 1])
                self._events.append(
                    SimEvent(
                        self.time + self.dt,
                        "joint_limit",
                        f"3GM joint {i} held at its {side} limit {lim:.6g} rad",
                        {"joint": i, "side": side, "limit": lim, "theta": f.th.tolist()},
                    )
                )

    # ------------------------------------------------------------------ sensing
    def _record_owts(self, contacts) -> None:
        record_owts(self, contacts)

    def observe(self, oracle: bool = False) -> Observation:
        """Sensor readings: 3GM encoders (θ1, θ2, θ3) [rad] and rates [rad/s], the fingertip
        force sensor (``tip_forces`` (1, 3): force the tip applies on the surface, WCS [N]),
        and ``owts``: the :class:`~planner.sim.spatial.OWTSReading` of the 5 kHz samples since
        the previous call. ``truth`` (oracle only): poses, velocities, joints, contacts.
        (:func:`planner.sim.spatial.observing.observe`.)"""
        return observe(self, oracle)
