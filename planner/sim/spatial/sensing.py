"""The OWTS reading of the simulated 3GM fingertip (App. C.1), sampled at 5 kHz.

At every OWTS sample time ``k / 5000 s`` the world records the true contact of the tip: the
outward normal of the fingertip at the contact, ``-n`` (``n`` the surface normal), expressed
in the TCS (:func:`planner.sim.spatial.finger.tcs_rotation`), the contact intensity
``min(f_n / FULL_INTENSITY_FORCE, 1)`` and the friction force (for the sheath-pulling bias).
When the controller observes, the pending samples are turned into raw PSD voltages by
:class:`robots.sensors.OWTSSampler` (nonlinearity, noise, 12-bit A/D; noise drawn from the
world's seeded generator only) and decoded by :meth:`robots.sensors.OWTS.contact_from_voltages`
(eqs. C.1-C.3) into the contact location on the tip, as the real sensor software does. The
sampling and decoding run in :func:`planner.sim.spatial.kernel.owts_sample_decode`, the same
arithmetic and the same random draws as those two numpy routines in scalar code (tested
equal; numpy's per-call overhead on 5-row batches dominated the profile).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.sim.spatial.kernel import owts_sample_decode
from robots.sensors import FULL_SCALE_V, OWTS, OWTSSampler

__all__ = ["FULL_INTENSITY_FORCE", "OWTSReading", "OWTSRecorder"]

#: Normal force [N] at which the OWTS intensity reaches full scale (linear below).
FULL_INTENSITY_FORCE = 1.0
SAMPLE_RATE = 5000.0  # [Hz] App. C.1.2


@dataclass(frozen=True)
class OWTSReading:
    """OWTS samples since the previous observation (``Observation.owts`` of the 3GM).

    Attributes:
        t: (K,) sample times [s] (5 kHz; K = 5 between observations at 1 kHz).
        voltages: (K, 4) raw PSD voltages ``v1..v4`` [V] (noise, nonlinearity, 12-bit A/D).
        point: (K, 3) decoded contact location on the tip in the TCS [m] (origin at the tip
            centre, z along the sensor's pole); zeros when there is no contact.
        normal: (K, 3) decoded unit outward normal of the tip at the contact, in the TCS;
            zeros when there is no contact (the thesis' ``n_T = {0, 0, 0}``).
        in_contact: (K,) whether the total light exceeded the sensor's threshold.
    """

    t: np.ndarray
    voltages: np.ndarray
    point: np.ndarray
    normal: np.ndarray
    in_contact: np.ndarray

    @property
    def latest_point(self) -> np.ndarray:
        """(3,) the newest decoded contact location in the TCS [m] (zeros: none)."""
        return self.point[-1] if len(self.t) else np.zeros(3)

    @property
    def latest_normal(self) -> np.ndarray:
        """(3,) the newest decoded normal in the TCS (zeros: no contact)."""
        return self.normal[-1] if len(self.t) else np.zeros(3)


class OWTSRecorder:
    """Buffers the true tip contact at 5 kHz and samples the sensor when observed.

    Args:
        sensor: an :class:`~robots.sensors.OWTS` (ideal sensor, ``radius`` = tip radius) or an
            :class:`~robots.sensors.OWTSSampler` whose settings are kept.
        rng: the world's generator (the only source of noise).
    """

    def __init__(self, sensor, rng: np.random.Generator) -> None:
        if isinstance(sensor, OWTSSampler):
            s = sensor
            self.sampler = OWTSSampler(
                s.sensor,
                rng,
                s.nonlinearity,
                s.noise_angle,
                s.bits,
                s.sheath_gain,
                s.sheath_max,
            )
        else:
            self.sampler = OWTSSampler(sensor if sensor is not None else OWTS(), rng)
        self.sensor: OWTS = self.sampler.sensor
        self._params = _params(self.sampler)
        self._sigma = self.sampler.noise_angle / self.sensor.scale
        #: pending samples: (cap, 7) rows ``(normal_tcs (3), intensity, friction_tcs (3))``,
        #: their times [s] and ``state = (next sample index, count)`` (written in place by
        #: :func:`planner.sim.spatial.step_kernel.finger_step`; preallocated, grown by
        #: :meth:`reserve` when a slow controller leaves many samples pending)
        self.rows = np.zeros((64, 7))
        self.times = np.zeros(64)
        self.state = np.array([1.0, 0.0])  # sample k is taken at k / SAMPLE_RATE

    @property
    def next_index(self) -> int:
        return int(self.state[0])

    def reserve(self, n: int) -> None:
        """Make room for ``n`` more samples."""
        k = int(self.state[1])
        if k + n > len(self.times):
            cap = 2 * (k + n)
            rows, times = np.zeros((cap, 7)), np.zeros(cap)
            rows[:k], times[:k] = self.rows[:k], self.times[:k]
            self.rows, self.times = rows, times

    def advance(self, t_end: float, normal_tcs, intensity: float, friction_tcs) -> None:
        """Record the true contact for every sample time ``<= t_end`` [s]."""
        st = self.state
        while st[0] / SAMPLE_RATE <= t_end + 1e-12:
            self.push(st[0] / SAMPLE_RATE, [*normal_tcs, intensity, *friction_tcs])
            st[0] += 1.0

    def push(self, t: float, row) -> None:
        """Append one pending sample: time [s] and row ``(normal_tcs (3), intensity,
        friction_tcs (3))``."""
        self.reserve(1)
        k = int(self.state[1])
        self.rows[k], self.times[k] = row, t
        self.state[1] = k + 1

    def read(self) -> OWTSReading:
        """Sample the pending contacts into voltages and decode them (clears the buffer)."""
        k = int(self.state[1])
        if k == 0:
            z = np.zeros((0, 3))
            return OWTSReading(np.zeros(0), np.zeros((0, 4)), z, z, np.zeros(0, bool))
        rows = self.rows[:k]
        t = self.times[:k].copy()
        self.state[1] = 0.0
        noise = self.sampler.rng.normal(0.0, self._sigma, 2 * k)  # x offsets, then y offsets
        v, p, n = np.empty((k, 4)), np.empty((k, 3)), np.empty((k, 3))
        on = np.empty(k, np.bool_)
        owts_sample_decode(rows, noise, self._params, v, p, n, on)
        return OWTSReading(t, v, p, n, on)

    def read_reference(self, rows) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The same reading through :class:`~robots.sensors.OWTSSampler` and
        :meth:`~robots.sensors.OWTS.contact_from_voltages` (numpy, for tests):
        ``(voltages, point, normal)`` of rows ``(normal_tcs (3), intensity, friction (3))``."""
        r = np.atleast_2d(np.asarray(rows, float))
        v = self.sampler.sample(r[:, :3], r[:, 3], tangential_force=r[:, 4:])
        v = np.atleast_2d(v)
        p, n = self.sensor.contact_from_voltages(v)
        return v, np.atleast_2d(p), np.atleast_2d(n)


def _params(sampler: OWTSSampler) -> np.ndarray:
    """The sensor and sampler settings packed for :func:`kernel.owts_sample_decode`."""
    s, nl = sampler.sensor, sampler.nonlinearity
    return np.array(
        [
            s.scale,
            s.psd_side,
            s.offsets[0],
            s.offsets[1],
            s.field_of_detection,
            sampler.lsb,
            sampler.sheath_gain,
            sampler.sheath_max,
            0.0 if nl is None else 1.0,
            0.0 if nl is None else nl.k1,
            0.0 if nl is None else nl.k2,
            1.0 if nl is None else nl.rho_max,
            s.radius,
            s.contact_threshold,
            FULL_SCALE_V,
        ]
    )
