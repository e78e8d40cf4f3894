"""What a controller sees: sensor readings, not the simulator's state (issue 15, item 5).

:class:`SensorSettings` chooses the sensor models of :mod:`robots.sensors` (joint encoders,
strain-gauge fingertip force sensors, the 8x8 tactile array of flat fingertips, the OWTS of the
3GM); a world turns its true state into an :class:`Observation` with :func:`read_joints` and
:func:`read_forces`. Noise comes only from the world's seeded ``numpy.random.Generator``.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from planner import checks
from robots.sensors import Encoder, ForceSensor, TactileArray

__all__ = ["Observation", "SensorSettings", "read_forces", "read_joints"]


@dataclass(frozen=True)
class SensorSettings:
    """Sensor models of a world.

    Attributes:
        encoder: joint encoder (quantization to ``encoder.resolution`` [rad]); ``None``: exact
            angles.
        velocity_resolution: quantization of the joint-velocity estimate of the encoder
            interface [rad/s]; 0: exact.
        force: strain-gauge fingertip force sensor (noise ``noise_std`` [N], quantization
            ``resolution`` [N]); ``None``: exact forces.
        tactile: the 8x8 tactile array of flat fingertips; ``None``: no images.
        owts: the OWTS model of the 3GM tip (used by the spatial world; any object).
    """

    encoder: Encoder | None = field(default_factory=Encoder)
    velocity_resolution: float = 1e-4
    force: ForceSensor | None = field(default_factory=ForceSensor)
    tactile: TactileArray | None = field(default_factory=TactileArray)
    owts: Any = None

    def __post_init__(self) -> None:
        checks.nonnegative("velocity_resolution", self.velocity_resolution, "rad/s")

    @classmethod
    def ideal(cls) -> SensorSettings:
        """Exact readings: no quantization, no noise, no tactile images."""
        return cls(encoder=None, velocity_resolution=0.0, force=None, tactile=None)


@dataclass(frozen=True)
class Observation:
    """Sensor readings at time ``t``.

    Attributes:
        t: time of the reading [s].
        q: (n,) joint encoder angles (quantized) [rad].
        qd: (n,) joint velocity estimate (quantized) [rad/s].
        fingers: names of the fingers, in the order of the rows of ``tip_forces``.
        tip_forces: (n_fingers, 2|3) strain-gauge fingertip forces in the world frame
            (force the finger applies on what it touches) [N] (noisy, quantized).
        tactile: ``{finger: (8, 8) taxel pressures [Pa]}`` of flat fingertips (a read-only
            mapping; the planar world computes each image when it is first read), or
            ``None``.
        owts: the OWTS reading of the 3GM tip (spatial world), or ``None``.
        truth: ``None`` unless observed with ``oracle=True``: then a dict of the true state
            (for debugging controllers only).
    """

    t: float
    q: np.ndarray
    qd: np.ndarray
    fingers: tuple[str, ...] = ()
    tip_forces: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    tactile: Mapping[str, np.ndarray] | None = None
    owts: Any = None
    truth: dict[str, Any] | None = None

    def tip_force(self, finger: str) -> np.ndarray:
        """The strain-gauge reading of ``finger`` [N]."""
        return self.tip_forces[self.fingers.index(finger)]


def read_joints(
    settings: SensorSettings, q: np.ndarray, qd: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Encoder angles [rad] and the quantized velocity estimate [rad/s] of true ``q``, ``qd``."""
    qm = q.copy() if settings.encoder is None else settings.encoder.measure(q)
    r = settings.velocity_resolution
    qdm = qd.copy() if r == 0 else np.round(qd / r) * r
    return qm, qdm


def read_forces(
    settings: SensorSettings, forces: np.ndarray, rng: np.random.Generator
) -> np.ndarray:
    """Strain-gauge readings [N] of true fingertip forces ``forces`` (any shape) [N]."""
    if settings.force is None:
        return np.array(forces, float)
    return settings.force.measure(forces, rng)
