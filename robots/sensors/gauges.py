"""Strain-gauge force sensors and joint encoders/potentiometers (thesis §2.3.2, App. C.2.1)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter


@dataclass(frozen=True)
class ForceSensor:
    """Strain-gauge fingertip force sensor: ~0.02 N accuracy (§2.3.2).

    Attributes:
        resolution: quantization step [N].
        noise_std: Gaussian noise (1 σ) [N].
    """

    resolution: float = 0.02
    noise_std: float = 0.01

    def __post_init__(self) -> None:
        checks.positive("resolution", self.resolution, "N")
        checks.nonnegative("noise_std", self.noise_std, "N")

    def measure(self, force, rng: np.random.Generator) -> np.ndarray:
        """Reading of the true force(s) ``force`` (any shape) [N]: noise, then quantization."""
        f = np.asarray(force, dtype=float)
        noisy = f + rng.normal(0.0, self.noise_std, f.shape) if self.noise_std > 0 else f
        return np.round(noisy / self.resolution) * self.resolution


@dataclass(frozen=True)
class Encoder:
    """Incremental optical joint encoder (3GM: App. C.2.1).

    Attributes:
        resolution: one count [rad] (e.g. ``ThreeGM().encoder_resolution``).
    """

    resolution: float = 2 * np.pi / 4096

    def __post_init__(self) -> None:
        checks.positive("resolution", self.resolution, "rad")

    @property
    def counts_per_revolution(self) -> float:
        """Counts per joint revolution [-]."""
        return 2 * np.pi / self.resolution

    def measure(self, angle) -> np.ndarray:
        """Quantized angle(s) [rad] (truncation to the count below, as a counter does)."""
        return np.floor(np.asarray(angle, float) / self.resolution) * self.resolution


@dataclass(frozen=True)
class Potentiometer:
    """Analog joint potentiometer read by an A/D converter (the hand's joints).

    Attributes:
        lower, upper: angle range mapped onto the A/D range [rad].
        bits: A/D resolution.
        noise_std: Gaussian noise (1 σ) [rad].
    """

    lower: float = -np.pi
    upper: float = np.pi
    bits: int = 12
    noise_std: float = 0.001

    def __post_init__(self) -> None:
        if not self.lower < self.upper:
            raise InvalidParameter(
                f"upper: expected a number > lower = {self.lower!r} [rad], got {self.upper!r}"
            )
        checks.in_range("bits", checks.integer("bits", self.bits), 1, 24)
        checks.nonnegative("noise_std", self.noise_std, "rad")

    @property
    def resolution(self) -> float:
        """One A/D step [rad]."""
        return (self.upper - self.lower) / (2**self.bits - 1)

    def measure(self, angle, rng: np.random.Generator) -> np.ndarray:
        """Reading(s) [rad]: noise, clipping to the range, quantization."""
        a = np.asarray(angle, float)
        if self.noise_std > 0:
            a = a + rng.normal(0.0, self.noise_std, a.shape)
        a = np.clip(a, self.lower, self.upper)
        return self.lower + np.round((a - self.lower) / self.resolution) * self.resolution
