"""Realistic OWTS readings: nonlinearity, sheath pulling, noise, 12-bit A/D (App. C.1.2-C.1.3).

:class:`OWTSSampler` turns true contacts into raw voltages the way the real sensor would:

1. **Sheath pulling** (App. C.1.3, optional): under sliding friction the rubber cover is pulled
   over the glass, so the detected spot moves along the tangential force; modelled as a
   rotation of the normal towards the tangential force by ``min(gain |f_t|, max_bias)``.
2. **Nonlinearity** (App. C.1.2, "the relationship ... is not linear"): the detection radius
   is distorted smoothly, ``ρ_raw = ρ (1 + k1 ρ_n² + k2 ρ_n⁴)`` with ``ρ_n = ρ/ρ_max``,
   ``ρ_max`` the radius of the field-of-detection edge (:class:`RadialNonlinearity`).
3. **Noise**: Gaussian on the detection coordinates, ``noise_angle`` (1 σ) in polar angle —
   0.5° by default so that ±1° (App. C.1, §3.3) is ~2 σ (≈ ±0.15 mm on an 8 mm tip;
   the 0.5 mm "resolution" of App. C.1.2 is the 12-bit A/D step at low intensity).
4. **12-bit A/D** on each channel over [0, 5 V].

:func:`fit_nonlinearity` is the calibration routine: from samples of known normals and raw
voltages it fits (k1, k2) and the offsets (x_o, y_o) of eq. C.1 by linear least squares;
:meth:`RadialNonlinearity.correct` then undoes the distortion before
:meth:`OWTS.contact_from_voltages`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from robots.sensors.owts import FULL_SCALE_V, OWTS


def _split(S: np.ndarray, sx: np.ndarray, sy: np.ndarray) -> np.ndarray:
    q = S / 4.0
    return np.column_stack(
        [
            q * (1 + sx) * (1 - sy),
            q * (1 - sx) * (1 + sy),
            q * (1 + sx) * (1 + sy),
            q * (1 - sx) * (1 - sy),
        ]
    )


def _normalized(v: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    S = v.sum(axis=1)
    Ss = np.where(S > 0, S, 1.0)
    return (
        S,
        (v[:, 0] - v[:, 1] + v[:, 2] - v[:, 3]) / Ss,
        (-v[:, 0] + v[:, 1] + v[:, 2] - v[:, 3]) / Ss,
        S > 0,
    )


@dataclass(frozen=True)
class RadialNonlinearity:
    """Smooth radial distortion of the PSD spot: ``ρ_raw = ρ (1 + k1 ρ_n² + k2 ρ_n⁴)``.

    Attributes:
        k1, k2: distortion coefficients [-] (monotone for |k1| + |k2| < ~0.3).
        rho_max: normalizing radius on the PSD [m] (the field-of-detection edge).
    """

    k1: float
    k2: float
    rho_max: float

    def apply_radius(self, rho: np.ndarray) -> np.ndarray:
        """Distorted radius (N,) [m] of true radius (N,) [m]."""
        r = rho / self.rho_max
        return rho * (1.0 + self.k1 * r**2 + self.k2 * r**4)

    def invert_radius(self, rho_raw: np.ndarray, iterations: int = 8) -> np.ndarray:
        """True radius from distorted radius (Newton, vectorized) [m]."""
        rho = np.array(rho_raw, dtype=float)
        for _ in range(iterations):
            r = rho / self.rho_max
            f = rho * (1.0 + self.k1 * r**2 + self.k2 * r**4) - rho_raw
            df = 1.0 + 3.0 * self.k1 * r**2 + 5.0 * self.k2 * r**4
            rho = rho - f / df
        return rho

    def correct(self, sensor: OWTS, voltages) -> np.ndarray:
        """Undo the distortion: raw voltages (N, 4) -> linearized voltages (N, 4) [V]."""
        v, single = checks.batch("voltages", voltages, 4)
        S, sx, sy, _ = _normalized(v)
        half = 0.5 * sensor.psd_side
        x, y = (sx - sensor.offsets[0]) * half, (sy - sensor.offsets[1]) * half
        raw = np.hypot(x, y)
        scale = np.where(raw > 0, self.invert_radius(raw) / np.where(raw > 0, raw, 1.0), 1.0)
        out = _split(S, x * scale / half + sensor.offsets[0], y * scale / half + sensor.offsets[1])
        return out[0] if single else out


@dataclass(frozen=True)
class Calibration:
    """Result of :func:`fit_nonlinearity`.

    Attributes:
        nonlinearity: the fitted distortion.
        offsets: fitted (x_o, y_o) of eq. C.1 [-].
        rms_residual: RMS fit residual in normalized PSD coordinates [-].
    """

    nonlinearity: RadialNonlinearity
    offsets: tuple[float, float]
    rms_residual: float


def fit_nonlinearity(sensor: OWTS, normals, voltages) -> Calibration:
    """Calibrate: fit (k1, k2, x_o, y_o) from known contact normals and raw voltages.

    The model ``s = (2/L) ρ (1 + k1 ρ_n² + k2 ρ_n⁴) (cos φ, sin φ) + (x_o, y_o)`` is linear in
    the four unknowns once the true (ρ, φ) are known from the normals (eq. C.2 inverted), so
    one least-squares solve fits them.

    Args:
        sensor: the sensor (its L and K are taken as known).
        normals: (N, 3) true unit normals in the TCS, inside the field of detection [-].
        voltages: (N, 4) raw voltages [V] measured at those contacts.

    Raises:
        InvalidParameter: fewer than 4 usable samples or mismatched shapes.
    """
    n, _ = checks.batch("normals", normals, 3)
    v, _ = checks.batch("voltages", voltages, 4)
    if len(n) != len(v):
        raise InvalidParameter(
            f"normals and voltages must have the same length, got {len(n)} and {len(v)}"
        )
    _, sx, sy, on = _normalized(v)
    if on.sum() < 4:
        raise InvalidParameter(f"need at least 4 samples with contact, got {int(on.sum())}")
    n = n[on] / np.linalg.norm(n[on], axis=1)[:, None]
    sx, sy = sx[on], sy[on]
    theta = np.arccos(np.clip(n[:, 2], -1, 1))
    phi = np.arctan2(n[:, 1], n[:, 0])
    rho = theta / sensor.scale
    rho_max = sensor.field_of_detection / sensor.scale
    r = rho / rho_max
    g = 2.0 / sensor.psd_side
    m = len(n)
    A = np.zeros((2 * m, 4))
    b = np.concatenate([sx - g * rho * np.cos(phi), sy - g * rho * np.sin(phi)])
    for k, c in enumerate((np.cos(phi), np.sin(phi))):
        A[k * m : (k + 1) * m, 0] = g * rho * r**2 * c
        A[k * m : (k + 1) * m, 1] = g * rho * r**4 * c
        A[k * m : (k + 1) * m, 2 + k] = 1.0
    sol, *_ = np.linalg.lstsq(A, b, rcond=None)
    res = float(np.sqrt(np.mean((A @ sol - b) ** 2)))
    return Calibration(
        RadialNonlinearity(float(sol[0]), float(sol[1]), rho_max),
        (float(sol[2]), float(sol[3])),
        res,
    )


class OWTSSampler:
    """Seeded sampling of raw OWTS voltages (what the simulator calls at 5 kHz).

    Args:
        sensor: the ideal sensor model (its offsets are the true PSD offsets).
        rng: the random generator (the run's ``ctx.rng``).
        nonlinearity: the sensor's true distortion, or None for a linear sensor.
        noise_angle: 1 σ noise on the polar angle [rad] (default 0.5°).
        bits: A/D resolution (12).
        sheath_gain: sheath-pulling bias per tangential force [rad/N] (0 = off).
        sheath_max: largest sheath-pulling bias [rad].
    """

    def __init__(
        self,
        sensor: OWTS,
        rng: np.random.Generator,
        nonlinearity: RadialNonlinearity | None = None,
        noise_angle: float = np.deg2rad(0.5),
        bits: int = 12,
        sheath_gain: float = 0.0,
        sheath_max: float = np.deg2rad(15.0),
    ) -> None:
        noise_angle = checks.nonnegative("noise_angle", noise_angle, "rad")
        sheath_gain = checks.nonnegative("sheath_gain", sheath_gain)
        sheath_max = checks.nonnegative("sheath_max", sheath_max, "rad")
        bits = int(checks.in_range("bits", checks.integer("bits", bits), 1, 24))
        self.sensor, self.rng, self.nonlinearity = sensor, rng, nonlinearity
        self.noise_angle, self.bits = float(noise_angle), int(bits)
        self.sheath_gain, self.sheath_max = float(sheath_gain), float(sheath_max)

    @property
    def lsb(self) -> float:
        """A/D quantum [V]."""
        return FULL_SCALE_V / (2**self.bits - 1)

    def sample(self, normals, intensity=0.5, tangential_force=None) -> np.ndarray:
        """Raw voltages (N, 4) [V] for true contact normals (N, 3) in the TCS.

        Args:
            normals: (N, 3) or (3,) true normals (zero rows: no contact) [-].
            intensity: contact intensity in [0, 1], scalar or (N,).
            tangential_force: optional (N, 3) friction force on the fingertip in the TCS [N]
                (drives the sheath-pulling bias).
        """
        n, single = checks.batch("normals", normals, 3)
        s = self.sensor
        norm = np.linalg.norm(n, axis=1)
        on = norm > 1e-12
        u = n / np.where(on, norm, 1.0)[:, None]
        if tangential_force is not None and self.sheath_gain > 0:
            ft, _ = checks.batch("tangential_force", tangential_force, 3)
            ft = ft - np.sum(ft * u, axis=1)[:, None] * u  # tangential part only
            mag = np.linalg.norm(ft, axis=1)
            ang = np.minimum(self.sheath_gain * mag, self.sheath_max)
            t = ft / np.where(mag > 0, mag, 1.0)[:, None]
            u = np.cos(ang)[:, None] * u + np.sin(ang)[:, None] * t
        theta = np.arccos(np.clip(u[:, 2], -1.0, 1.0))
        on &= theta <= s.field_of_detection
        phi = np.arctan2(u[:, 1], u[:, 0])
        rho = theta / s.scale
        if self.nonlinearity is not None:
            rho = self.nonlinearity.apply_radius(rho)
        sigma = self.noise_angle / s.scale
        x = rho * np.cos(phi) + self.rng.normal(0.0, sigma, len(u))
        y = rho * np.sin(phi) + self.rng.normal(0.0, sigma, len(u))
        g = 2.0 / s.psd_side
        sx = np.clip(g * x + s.offsets[0], -1, 1)
        sy = np.clip(g * y + s.offsets[1], -1, 1)
        inten = np.broadcast_to(np.asarray(intensity, float), (len(u),))
        v = _split(np.where(on, inten * FULL_SCALE_V, 0.0), sx, sy)
        v = np.clip(np.round(v / self.lsb) * self.lsb, 0.0, FULL_SCALE_V)
        return v[0] if single else v
