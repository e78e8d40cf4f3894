"""Sensor readings of the planar world (issue 15, item 5).

* encoders: ``SensorSettings.encoder`` quantizes ``q``; the velocity estimate is ``qd``
  quantized to ``velocity_resolution``;
* strain gauges: the force each fingertip applies on what it touches (sum over its contacts
  of the last step, world frame), with the :class:`robots.sensors.ForceSensor` noise and
  quantization drawn from the world's seeded generator;
* tactile array of a flat fingertip: the 8x8 image of the actual contact pressure
  (:meth:`robots.sensors.TactileArray.sphere_images`) with the contact's position along the
  pad as ``u`` (``v = 0``: the plane of the hand cuts the pad's middle row) and the radius of
  the touching feature (1 mm for a corner, 1 m for a flat or gently curved piece).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from planner.jit import njit
from planner.sim.observation import Observation, read_forces, read_joints
from planner.sim.planar.bodies import FREE, TIP
from robots.sensors import Encoder, ForceSensor, TactileArray
from robots.sensors.tactile_kernel import sphere_image_add

__all__ = ["TactileImages", "observe"]

FINGERS = ("left", "right")


@njit(cache=True)
def _tip_force_sum(ia, ib, kind, index, pn, pt, normal, h, out):
    """Sum into ``out`` (2, 2) the force each fingertip applies on what it touches [N]."""
    out[:, :] = 0.0
    for k in range(pn.shape[0]):
        if pn[k] <= 0:
            continue
        a, b = ia[k], ib[k]
        if kind[a] != TIP and kind[b] != TIP:
            continue
        nx, ny = normal[k, 0], normal[k, 1]
        fx, fy = (pn[k] * nx - pt[k] * ny) / h, (pn[k] * ny + pt[k] * nx) / h  # on a
        if kind[a] == TIP:
            out[index[a], 0] -= fx
            out[index[a], 1] -= fy
        if kind[b] == TIP:
            out[index[b], 0] += fx
            out[index[b], 1] += fy


@njit(cache=True)
def _read_hand(q, qd, enc, vres, ia, ib, kind, index, pn, pt, normal, h, qm, qdm, forces):
    """Encoder angles ``qm`` [rad] (``floor`` to ``enc``; exact when 0), the velocity
    estimate ``qdm`` [rad/s] (``rint`` to ``vres``; exact when 0) and the true fingertip
    forces (2, 2) [N]: :func:`planner.sim.observation.read_joints` and
    :func:`_tip_force_sum` in one call (same operations, same results)."""
    for i in range(q.shape[0]):
        qm[i] = q[i] if enc == 0.0 else np.floor(q[i] / enc) * enc
        qdm[i] = qd[i] if vres == 0.0 else np.rint(qd[i] / vres) * vres
    _tip_force_sum(ia, ib, kind, index, pn, pt, normal, h, forces)


@njit(cache=True)
def pad_image(img, finger, rows, pn, h, kind, index, q, base, lengths,
              fu, fv, Bv, BuT, modulus, cell, threshold):  # fmt: skip  # pragma: no cover
    """The tactile image of fingertip ``finger``'s pad into ``img`` (rows, cols) [Pa]: the
    sum of the sphere images (:func:`robots.sensors.tactile_kernel.sphere_image_add`) of
    its touches in the step's candidate ``rows`` (n, 10) (bodies, gap, points a and b,
    normal, curvature: the columns of :func:`planner.sim.planar.stepper._result`) with
    normal impulses ``pn`` (n,) [N s], placed along the pad by the fingertip frame of the true
    ``q`` (the operations of :meth:`HandModel.frames`; ``base`` (2, 2), ``lengths``
    (2, 3) [m]). Compiled :meth:`TactileImages._image_reference` (same operations, same
    order: equal images)."""
    img[:, :] = 0.0
    x = y = c = s = 0.0
    framed = False
    for k in range(pn.shape[0]):
        if pn[k] <= 0:
            continue
        a, b = int(rows[k, 0]), int(rows[k, 1])
        if kind[a] == TIP and index[a] == finger:
            px, py = rows[k, 3], rows[k, 4]
        elif kind[b] == TIP and index[b] == finger:
            px, py = rows[k, 5], rows[k, 6]
        else:
            continue
        if not framed:
            l1, l2, l3 = lengths[finger, 0], lengths[finger, 1], lengths[finger, 2]
            s1 = q[3 * finger]
            s2 = s1 + q[3 * finger + 1]
            s3 = s2 + q[3 * finger + 2]
            x2, y2 = base[finger, 0] - l1 * math.sin(s1), base[finger, 1] + l1 * math.cos(s1)
            x3, y3 = x2 - l2 * math.sin(s2), y2 + l2 * math.cos(s2)
            x, y = x3 - l3 * math.sin(s3), y3 + l3 * math.cos(s3)
            c, s = math.cos(s3), math.sin(s3)
            framed = True
        u = c * (px - x) + s * (py - y)
        kappa = rows[k, 9]
        radius = 1e-3 if math.isinf(kappa) else (1.0 if kappa < 1.0 else 1.0 / kappa)
        sphere_image_add(img, u, 0.0, radius, pn[k] / h, fu, fv, Bv, BuT, modulus, cell,
                         threshold)  # fmt: skip


def _hand_geometry(hand) -> tuple[np.ndarray, np.ndarray]:
    """(2, 2) finger bases and (2, 3) link lengths [m] of the world's hand (cached)."""
    geo = getattr(hand, "_pad_geometry", None)
    if geo is None:
        geo = hand._pad_geometry = (np.array(hand.base, float), np.array(hand.lengths, float))
    return geo


def _kinds(world) -> tuple[np.ndarray, np.ndarray]:
    """(nb,) body kinds and indices (cached until a body is added)."""
    cached = getattr(world, "_kinds_cache", None)
    if cached is None or len(cached[0]) != len(world.bodies):
        cached = (
            np.array([b.kind for b in world.bodies], np.int64),
            np.array([b.index for b in world.bodies], np.int64),
        )
        world._kinds_cache = cached
    return cached


def _true_tip_forces(world) -> np.ndarray:
    """True fingertip forces (2, 2) [N] over the last step (world frame, on the touched)."""
    out = np.zeros((2, 2))
    res = world._last
    if res is None or len(res.p_n) == 0:
        return out
    kind, index = _kinds(world)
    _tip_force_sum(res.body_a, res.body_b, kind, index, res.p_n, res.p_t, res.normal,
                   world.dt, out)  # fmt: skip
    return out


def _touches(world, res) -> list[list[tuple]]:
    """Each fingertip's touches ``(point (2,), f_n [N], curvature [1/m])`` in ``res``."""
    per_tip: list[list[tuple]] = [[], []]
    if res is None:
        return per_tip
    h = world.dt
    bodies = world.bodies
    pn = res.p_n.tolist()
    for k, (ia, ib) in enumerate(zip(res.body_a.tolist(), res.body_b.tolist(), strict=True)):
        if pn[k] <= 0:
            continue
        a, b = bodies[ia], bodies[ib]
        if a.kind == TIP:
            per_tip[a.index].append((res.point_a[k], pn[k] / h, float(res.curvature[k])))
        if b.kind == TIP:
            per_tip[b.index].append((res.point_b[k], pn[k] / h, float(res.curvature[k])))
    return per_tip


class TactileImages(Mapping):
    """``{finger: (8, 8) taxel pressures [Pa]}`` of the flat fingertips, computed on access.

    A read-only mapping (what :attr:`Observation.tactile` holds): the keys are known at
    once, each image is computed the first time it is read (about 100-250 us each, the
    largest part of an observation) and then kept. The contacts it is computed from are
    those of the step result held at observation time (immutable), so a late read gives the
    image of that instant.

    Args:
        array: the :class:`robots.sensors.TactileArray`; hand: the world's hand model;
        q: (6,) true joint angles at observation time [rad] (a copy);
        fingers: ``{finger: index}`` of the flat fingertips;
        touches: ``{finger: [(point (2,), normal force [N], curvature [1/m])]}``, or None
            with ``source``: ``(world, (rows (n, 10), p_n (n,)) or None)``: the world and
            its last step's candidate rows and normal impulses
            (:meth:`PlanarWorld._step_rows`, immutable copies) to find them on first access.
    """

    def __init__(
        self, array, hand, q: np.ndarray, fingers: dict, touches: dict | None, source=None
    ) -> None:
        self._array = array
        self._hand, self._q = hand, q  # the fingertip frames are computed when needed
        self._frames = fingers  # finger -> its index (0 left, 1 right)
        self._touches = touches  # finger -> [(point (2,), normal force [N], curvature)]
        self._source = source
        self._images: dict[str, np.ndarray] = {}

    def __getitem__(self, finger: str) -> np.ndarray:
        img = self._images.get(finger)
        if img is None:
            if finger not in self._frames:
                raise KeyError(finger)
            img = self._image(finger)
            self._images[finger] = img
        return img

    def __contains__(self, finger) -> bool:
        return finger in self._frames

    def __iter__(self):
        return iter(self._frames)

    def __len__(self) -> int:
        return len(self._frames)

    def _image(self, finger: str) -> np.ndarray:
        if self._touches is not None or type(self._array) is not TactileArray:
            return self._image_reference(finger)  # given touches, another array model
        arr = self._array
        img = np.zeros((arr.rows, arr.cols))
        world, step = self._source
        if step is None or len(step[1]) == 0:
            return img
        kind, index = _kinds(world)
        pad_image(img, self._frames[finger], step[0], step[1], world.dt, kind, index, self._q,
                  *_hand_geometry(self._hand), *arr.kernel_args)  # fmt: skip
        return img

    def _image_reference(self, finger: str) -> np.ndarray:
        """:meth:`_image` in Python with :meth:`TactileArray.sphere_images` (the reference
        of the compiled :func:`pad_image`)."""
        arr = self._array
        img = np.zeros((arr.rows, arr.cols))
        if self._touches is None:
            per_tip = _touches(self._source[0], self._result())
            self._touches = {f: per_tip[k] for f, k in self._frames.items()}
        touches = self._touches[finger]
        if touches:
            x, y, phi = self._hand.frames(self._q)[1][self._frames[finger]]
            c, s = math.cos(phi), math.sin(phi)
            for point, fn, kappa in touches:
                u = c * (point[0] - x) + s * (point[1] - y)
                radius = 1e-3 if math.isinf(kappa) else (1.0 if kappa < 1.0 else 1.0 / kappa)
                img += arr.sphere_images(np.array([u, 0.0]), radius, fn)
        return img

    def _result(self):
        """The source's step as a :class:`StepResult` (bodies, points, curvature, impulses)."""
        from planner.sim.planar.stepper import _result

        step = self._source[1]
        if step is None:
            return None
        z = np.zeros(0)
        return _result(step[0], z, step[1], z, z, np.zeros(0, np.int64), z)

    def __repr__(self) -> str:
        return f"TactileImages({sorted(self._frames)})"


def _tactile(world):
    arr = world.sensors.tactile
    if arr is None or world.hand is None:
        return None
    flat = getattr(world.hand, "_flat", None)
    if flat is None:
        params = world.hand.hand.params
        flat = tuple(k for k, f in enumerate(FINGERS) if params.finger(f).tip == "flat")
        world.hand._flat = flat
    if not flat:
        return {}
    fingers = {FINGERS[k]: k for k in flat}
    return TactileImages(arr, world.hand, world.q.copy(), fingers, None,
                         (world, world._step_rows()))  # fmt: skip


_EMPTY = (np.zeros(0, np.int64), np.zeros(0), np.zeros((0, 2)))


def _read(world) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Encoder angles, velocity estimate and strain-gauge forces of the hand now."""
    sens = world.sensors
    enc, force = sens.encoder, sens.force
    if (enc is not None and type(enc) is not Encoder) or (
        force is not None and type(force) is not ForceSensor
    ):  # other sensor models: their own measure()
        q, qd = read_joints(sens, world.q, world.qd)
        return q, qd, read_forces(sens, _true_tip_forces(world), world.rng)
    reading = getattr(world, "_reading", None)
    noise = getattr(world, "_noise", None)
    if reading is not None:  # read by the compiled loop for this call (fast_run)
        q, qd, f = (a.copy() for a in reading)
        return q, qd, _gauges(force, f, world.rng, noise)
    if noise is not None:  # a read outside the compiled loop's: the generator first
        noise.sync()
        world._noise = None
    res = world._last
    kind, index = _kinds(world)
    if res is None:
        ia = ib = _EMPTY[0]
        pn, pt, normal = _EMPTY[1], _EMPTY[1], _EMPTY[2]
    else:
        ia, ib, pn, pt, normal = res.body_a, res.body_b, res.p_n, res.p_t, res.normal
    q, qd, f = np.empty(6), np.empty(6), np.empty((2, 2))
    _read_hand(world.q, world.qd, 0.0 if enc is None else enc.resolution,
               sens.velocity_resolution, ia, ib, kind, index, pn, pt, normal, world.dt, q, qd,
               f)  # fmt: skip
    return q, qd, _gauges(force, f, world.rng)


def _gauges(force, f: np.ndarray, rng, noise: GaugeNoise | None = None) -> np.ndarray:
    """:meth:`robots.sensors.ForceSensor.measure` of true forces ``f`` (2, 2) [N] (same
    draws and operations; ``force`` None: exact); the draw from ``noise`` when given."""
    if force is None:
        return f
    if force.noise_std > 0:
        f = f + (rng.normal(0.0, force.noise_std, f.shape) if noise is None else noise.take())
    return np.rint(f / force.resolution) * force.resolution


class GaugeNoise:
    """The strain gauges' noise drawn ahead from a world's generator, one (2, 2) reading
    per :meth:`take` (for the compiled run loop: one draw call per block instead of one per
    controller call).

    ``Generator.normal`` fills a block element by element from the same stream, so the
    readings equal those of one draw per reading; :meth:`sync` rewinds the generator and
    redraws what was taken, leaving it where the reference's draws leave it (call it
    before anything else draws from the generator).

    Args:
        rng: the world's ``numpy.random.Generator``; std: the gauge noise std [N].
    """

    BLOCK = 256

    def __init__(self, rng, std: float) -> None:
        self.rng, self.std = rng, float(std)
        self._state = rng.bit_generator.state
        self._taken = 0  # readings handed out since the saved state
        self._buf = rng.normal(0.0, self.std, (self.BLOCK, 2, 2))
        self._pos = 0

    def take(self) -> np.ndarray:
        """The next reading's noise (2, 2) [N]."""
        if self._pos == len(self._buf):
            self._buf, self._pos = self.rng.normal(0.0, self.std, (self.BLOCK, 2, 2)), 0
        self._pos += 1
        self._taken += 1
        return self._buf[self._pos - 1]

    def sync(self) -> None:
        """Leave the generator as if only the readings taken had been drawn."""
        self.rng.bit_generator.state = self._state
        if self._taken:
            self.rng.normal(0.0, self.std, (self._taken, 2, 2))
        self._state, self._taken = self.rng.bit_generator.state, 0
        self._buf, self._pos = self._buf[:0], 0


def observe(world, oracle: bool = False) -> Observation:
    """The :class:`Observation` of ``world`` now."""
    if world.hand is None:
        q = qd = np.zeros(0)
        forces = np.zeros((0, 2))
        fingers: tuple[str, ...] = ()
        tactile = None
    else:
        q, qd, forces = _read(world)
        fingers = FINGERS
        tactile = _tactile(world)
    truth = None
    if oracle:
        truth = {
            "q": world.q.copy(),
            "qd": world.qd.copy(),
            "poses": {b.name: world.pose(b.name) for b in world.bodies if b.kind == FREE},
            "velocities": {b.name: world.velocity(b.name) for b in world.bodies if b.kind == FREE},
            "contacts": world.contacts(),
        }
        if world.hand is not None:
            truth["tip_forces"] = _true_tip_forces(world)
    return Observation(world.time, q, qd, fingers, forces, tactile, None, truth)
