"""The Optical Waveguide Tactile Sensor (OWTS), noise-free and calibrated (thesis App. C.1).

Voltage model. The four PSD electrode voltages of a light spot at normalized PSD coordinates
``(s_x, s_y)`` (each in [-1, 1]) with total light ``S`` are taken as the tetra-lateral PSD's
bilinear split

.. math::

    v_1 = S(1+s_x)(1-s_y)/4,\\; v_2 = S(1-s_x)(1+s_y)/4,\\;
    v_3 = S(1+s_x)(1+s_y)/4,\\; v_4 = S(1-s_x)(1-s_y)/4,

which is exactly what eq. C.1 inverts: ``(v1 - v2 + v3 - v4)/Σv = s_x`` and
``(-v1 + v2 + v3 - v4)/Σv = s_y``. Then (eq. C.1) ``x_d = (s_x - x_o) L/2``,
``y_d = (s_y - y_o) L/2``; (eq. C.2) ``φ = atan2(y_d, x_d)``, ``θ = K sqrt(x_d² + y_d²)``;
(eq. C.3) ``n = (cos φ sin θ, sin φ sin θ, cos θ)`` and ``x = R n`` in the TCS (origin at the
sphere centre, z along the pole). ``S`` is the contact intensity times the 5 V full scale.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter

FULL_SCALE_V = 5.0  # [V] A/D input range of each channel


@dataclass(frozen=True)
class DetectionPoint:
    """Detection coordinates of eq. C.1 and spherical angles of eq. C.2.

    Attributes:
        x, y: (N,) detection coordinates [m].
        phi: (N,) azimuth [rad]; theta: (N,) polar angle from the pole [rad].
        intensity: (N,) contact intensity Σv / 5 V [-].
    """

    x: np.ndarray
    y: np.ndarray
    phi: np.ndarray
    theta: np.ndarray
    intensity: np.ndarray


class OWTS:
    """Hemispherical optical waveguide tactile sensor (thesis App. C.1, eqs. C.1-C.3).

    Args:
        radius: fingertip radius R [m] (16 mm diameter sensor: 0.008).
        psd_side: PSD side length L [m].
        scale: K of eq. C.2 [rad/m]; default maps the 75° field of detection to 40 % of L.
        offsets: calibration offsets (x_o, y_o) of eq. C.1 [-] (fractions of L/2).
        field_of_detection: half-angle of the detection cone about the pole [rad] (75°).
        contact_threshold: total voltage below which there is no contact [V].
    """

    def __init__(
        self,
        radius: float = 0.008,
        psd_side: float = 0.01,
        scale: float | None = None,
        offsets: tuple[float, float] = (0.0, 0.0),
        field_of_detection: float = np.deg2rad(75.0),
        contact_threshold: float = 1e-3,
    ) -> None:
        self.radius = checks.positive("radius", radius, "m")
        self.psd_side = checks.positive("psd_side", psd_side, "m")
        self.field_of_detection = checks.in_range(  # at most the hemisphere
            "field_of_detection", field_of_detection, 0.0, np.pi / 2, "rad", closed=(False, True)
        )
        self.scale = (
            self.field_of_detection / (0.4 * self.psd_side)
            if scale is None
            else checks.positive("scale", scale, "rad/m")
        )
        xo, yo = checks.vector("offsets", offsets, 2)
        self.offsets = (xo, yo)
        reach = 2.0 * self.field_of_detection / self.scale / self.psd_side
        if reach + max(abs(xo), abs(yo)) > 1.0:
            raise InvalidParameter(
                f"the field of detection does not fit on the PSD: 2 theta_max/(K L) + "
                f"max|offset| = {reach + max(abs(xo), abs(yo)):.3g} > 1; increase scale K or "
                "psd_side, or reduce the offsets"
            )
        self.contact_threshold = float(contact_threshold)
        self.sample_rate = 5000.0  # [Hz] App. C.1.2

    # ------------------------------------------------------------------ eqs. C.1, C.2
    def detection(self, voltages) -> DetectionPoint:
        """Eqs. C.1-C.2 for (4,) or (N, 4) voltages [V] (rows without contact give zeros)."""
        v, _ = checks.batch("voltages", voltages, 4)
        S = v.sum(axis=1)
        on = S > self.contact_threshold
        Ss = np.where(on, S, 1.0)
        sx = (v[:, 0] - v[:, 1] + v[:, 2] - v[:, 3]) / Ss
        sy = (-v[:, 0] + v[:, 1] + v[:, 2] - v[:, 3]) / Ss
        half = 0.5 * self.psd_side
        x = np.where(on, (sx - self.offsets[0]) * half, 0.0)
        y = np.where(on, (sy - self.offsets[1]) * half, 0.0)
        return DetectionPoint(
            x, y, np.arctan2(y, x), self.scale * np.hypot(x, y), np.where(on, S / FULL_SCALE_V, 0.0)
        )

    def contact_from_voltages(self, voltages) -> tuple[np.ndarray, np.ndarray]:
        """Contact point and normal on the fingertip from PSD voltages (eqs. C.1-C.3).

        Args:
            voltages: (4,) or (N, 4) ``v1..v4`` [V].

        Returns:
            ``(point, normal)``: (3,) or (N, 3) each, in the TCS — point [m] on the sphere,
            unit outward normal [-]. No contact (Σv below ``contact_threshold``, e.g. all
            zeros) gives point = normal = (0, 0, 0).
        """
        v, single = checks.batch("voltages", voltages, 4)
        S = v.sum(axis=1)
        on = S > self.contact_threshold
        inv = np.where(on, 1.0 / np.where(on, S, 1.0), 0.0)
        half = 0.5 * self.psd_side
        x = ((v[:, 0] - v[:, 1] + v[:, 2] - v[:, 3]) * inv - self.offsets[0] * on) * half
        y = ((-v[:, 0] + v[:, 1] + v[:, 2] - v[:, 3]) * inv - self.offsets[1] * on) * half
        K = self.scale
        theta = K * np.hypot(x, y)
        k = K * np.sinc(theta / np.pi)  # sin(theta)/rho, finite at rho = 0
        n = np.column_stack([x * k, y * k, np.where(on, np.cos(theta), 0.0)])
        p = self.radius * n
        return (p[0], n[0]) if single else (p, n)

    # ------------------------------------------------------------------ inverse
    def voltages_from_contact(self, normal, intensity: float | np.ndarray = 0.5) -> np.ndarray:
        """PSD voltages of a contact with outward normal ``normal`` (inverse of C.1-C.3).

        Args:
            normal: (3,) or (N, 3) contact normal in the TCS (normalized here; a zero vector
                means no contact) [-].
            intensity: contact intensity in [0, 1] (Σv = intensity x 5 V), scalar or (N,).

        Returns:
            (4,) or (N, 4) voltages [V]; zeros for no contact and for normals outside the
            field of detection.
        """
        n, single = checks.batch("normal", normal, 3)
        inten = np.broadcast_to(np.asarray(intensity, dtype=float), (len(n),))
        if np.any(inten < 0) or np.any(inten > 1) or not np.all(np.isfinite(inten)):
            raise InvalidParameter(f"intensity: expected numbers in [0, 1], got {intensity!r}")
        norm = np.linalg.norm(n, axis=1)
        on = norm > 1e-12
        u = n / np.where(on, norm, 1.0)[:, None]
        # atan2 of (sin, cos) instead of arccos(u_z): near the pole u_z = 1 - theta^2/2 rounds
        # to a multiple of eps ~ 1.1e-16, so arccos returns theta with an absolute error of
        # ~eps/theta (4e-11 at theta = 1e-7, 100 % at theta < 1e-8); atan2 keeps the full
        # relative precision of the tangential components at every theta.
        theta = np.arctan2(np.hypot(u[:, 0], u[:, 1]), u[:, 2])
        on &= theta <= self.field_of_detection + 1e-12
        rho = theta / self.scale
        phi = np.arctan2(u[:, 1], u[:, 0])
        sx = 2.0 * rho * np.cos(phi) / self.psd_side + self.offsets[0]
        sy = 2.0 * rho * np.sin(phi) / self.psd_side + self.offsets[1]
        S = np.where(on, inten * FULL_SCALE_V, 0.0) / 4.0
        v = np.column_stack(
            [
                S * (1 + sx) * (1 - sy),
                S * (1 - sx) * (1 + sy),
                S * (1 + sx) * (1 + sy),
                S * (1 - sx) * (1 - sy),
            ]
        )
        return v[0] if single else v
