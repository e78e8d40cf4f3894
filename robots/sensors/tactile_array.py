"""The 8x8 tactile array on the left fingertip's flat pad (thesis §2.3.2, Fig. 2.14).

Pressure model: Hertzian contact of a rigid object with the elastic pad (effective modulus
E* [Pa]), spread by the rubber skin (Gaussian of std ``spread`` [m]) and averaged over each
taxel (``oversample`` x ``oversample`` sub-points per taxel):

* sphere of radius R pressed with force F (circular Hertz): contact radius
  ``a = (3 F R / (4 E*))^(1/3)``, ``p(r) = p0 sqrt(1 - r²/a²)``, ``p0 = 3F/(2π a²)``;
* ridge (cylinder of crest radius R, axis at angle ``angle`` on the pad, length ℓ) pressed with
  F (line Hertz, load per length w = F/ℓ): half-width ``b = sqrt(4 w R/(π E*))``,
  ``p(d) = p0 sqrt(1 - d²/b²)``, ``p0 = 2w/(π b)``.

Pressures are sampled on the sub-taxel grid; a sphere's samples are rescaled so that they
integrate to F, a ridge's are averaged exactly across each sub-cell (a ridge can be narrower
than a sub-cell). A sphere gives a round blob and a ridge a sharp line — the change seen in
Fig. 2.14 when the pad slides over the ridge of the 10 cm ball. Pad coordinates (u, v) have
their origin at the pad centre; taxel (i, j) is centred at ``((j - 3.5) pitch, (i - 3.5) pitch)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter


@dataclass(frozen=True)
class TactileReading:
    """One processed tactile image.

    Attributes:
        image: (rows, cols) mean pressure per taxel [Pa].
        force: estimated normal force, Σ pressure x taxel area [N].
        centroid: (2,) pressure-weighted contact location (u, v) on the pad [m]; (0, 0)
            when there is no contact.
        in_contact: whether any taxel exceeds the threshold.
    """

    image: np.ndarray
    force: float
    centroid: np.ndarray
    in_contact: bool


def _cell_average(x: np.ndarray, width: float) -> np.ndarray:
    """Mean of sqrt(1 - t²) (0 outside [-1, 1]) over [x - width/2, x + width/2] [-]."""

    def prim(t):
        t = np.clip(t, -1.0, 1.0)
        return 0.5 * (t * np.sqrt(1.0 - t * t) + np.arcsin(t))

    return (prim(x + width / 2) - prim(x - width / 2)) / width


class TactileArray:
    """An 8x8 pressure-sensing array (thesis §2.3.2).

    Args:
        rows, cols: taxel counts (8, 8).
        pitch: taxel spacing [m] (2.5 mm: a 20 mm pad).
        modulus: effective contact modulus E* of the pad [Pa] (soft rubber, 1 MPa).
        spread: std of the skin's pressure spreading [m] (0 = none).
        oversample: sub-points per taxel side for area averaging (>= 1).
        threshold: pressure below which a taxel reads zero [Pa].
    """

    def __init__(
        self,
        rows: int = 8,
        cols: int = 8,
        pitch: float = 0.0025,
        modulus: float = 1.0e6,
        spread: float = 0.5e-3,
        oversample: int = 3,
        threshold: float = 50.0,
    ) -> None:
        self.rows = checks.integer("rows", rows, minimum=1)
        self.cols = checks.integer("cols", cols, minimum=1)
        self.oversample = checks.integer("oversample", oversample, minimum=1)
        self.pitch = checks.positive("pitch", pitch, "m")
        self.modulus = checks.positive("modulus", modulus, "Pa")
        self.spread = checks.nonnegative("spread", spread, "m")
        self.threshold = float(threshold)
        self.u = (np.arange(self.cols) - (self.cols - 1) / 2) * self.pitch
        self.v = (np.arange(self.rows) - (self.rows - 1) / 2) * self.pitch
        self._fu, self._Bu = self._blur(self.cols)
        self._fv, self._Bv = self._blur(self.rows)
        self._BuT = np.ascontiguousarray(self._Bu.T)

    def _blur(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """Fine sample points (n*os,) [m] and the (n, n*os) average-and-spread matrix."""
        os_ = self.oversample
        fine = (np.arange(n * os_) - (n * os_ - 1) / 2) * self.pitch / os_
        avg = np.kron(np.eye(n), np.full((1, os_), 1.0 / os_))
        if self.spread > 0:
            d = fine[:, None] - fine[None, :]
            G = (
                np.exp(-0.5 * (d / self.spread) ** 2)
                * (self.pitch / os_)
                / (np.sqrt(2 * np.pi) * self.spread)
            )
            avg = avg @ G
        return fine, avg

    def _conserve(self, P: np.ndarray, F: np.ndarray, c: np.ndarray) -> np.ndarray:
        """Rescale sampled pressures (N, V, U) [Pa] so each integrates to its force F (N,) [N];
        a contact smaller than one sub-cell deposits F in the sub-cell nearest to c (N, 2)."""
        cell = (self.pitch / self.oversample) ** 2
        tot = P.sum(axis=(1, 2)) * cell
        P = P * np.where(tot > 0, F / np.where(tot > 0, tot, 1.0), 0.0)[:, None, None]
        tiny = (tot <= 0) & (F > 0)
        if np.any(tiny):
            iu = np.abs(self._fu[None, :] - c[tiny, 0:1]).argmin(axis=1)
            iv = np.abs(self._fv[None, :] - c[tiny, 1:2]).argmin(axis=1)
            P[np.flatnonzero(tiny), iv, iu] = F[tiny] / cell
        return P

    @property
    def kernel_args(self) -> tuple:
        """The array's constants in the order of
        :func:`robots.sensors.tactile_kernel.sphere_image_add` (``fu, fv, Bv, BuT, modulus,
        cell, threshold``): its compiled twin of :meth:`sphere_images`."""
        cell = (self.pitch / self.oversample) ** 2
        return self._fu, self._fv, self._Bv, self._BuT, self.modulus, cell, self.threshold

    @property
    def extent(self) -> tuple[float, float]:
        """Half-widths of the pad (u, v) [m]."""
        return self.cols * self.pitch / 2, self.rows * self.pitch / 2

    def sphere_images(self, centers, radius: float, forces) -> np.ndarray:
        """Images of spheres pressed on the pad (vectorized over contacts).

        Args:
            centers: (N, 2) or (2,) contact centres (u, v) on the pad [m].
            radius: sphere radius [m] (the 10 cm ball: 0.05).
            forces: (N,) or scalar normal forces >= 0 [N].

        Returns:
            (N, rows, cols) or (rows, cols) taxel pressures [Pa].
        """
        c, single = checks.batch("centers", centers, 2)
        R = checks.positive("radius", radius, "m")
        F = np.broadcast_to(np.asarray(forces, float), (len(c),))
        if np.any(F < 0) or not np.all(np.isfinite(F)):
            raise InvalidParameter(f"forces must be finite and >= 0 [N], got {forces!r}")
        a = np.cbrt(3.0 * F * R / (4.0 * self.modulus))
        a_safe = np.where(a > 0, a, 1.0)
        p0 = np.where(a > 0, 3.0 * F / (2.0 * np.pi * a_safe**2), 0.0)
        du = (self._fu[None, :] - c[:, 0:1]) / a_safe[:, None]  # (N, U)
        dv = (self._fv[None, :] - c[:, 1:2]) / a_safe[:, None]  # (N, V)
        r2 = dv[:, :, None] ** 2 + du[:, None, :] ** 2
        P = p0[:, None, None] * np.sqrt(np.maximum(1.0 - r2, 0.0))
        P = self._conserve(P, F, c)
        img = self._Bv @ P @ self._BuT
        img[img < self.threshold] = 0.0
        return img[0] if single else img

    def ridge_image(
        self, center, angle: float, radius: float, force: float, length: float | None = None
    ) -> np.ndarray:
        """Image of a ridge (cylindrical crest) pressed on the pad.

        Args:
            center: (2,) a point of the ridge axis on the pad (u, v) [m].
            angle: direction of the ridge axis from +u [rad].
            radius: crest radius of the ridge [m] (a 4 mm wide ridge: ~0.002).
            force: normal force >= 0 [N].
            length: loaded ridge length [m] (default: the chord across the pad).

        Returns:
            (rows, cols) taxel pressures [Pa].
        """
        c, _ = checks.batch("center", center, 2)
        R = checks.positive("radius", radius, "m")
        force = checks.nonnegative("force", force, "N")
        ell = 2 * max(self.extent) if length is None else checks.positive("length", length, "m")
        w = force / ell
        b = np.sqrt(4.0 * w * R / (np.pi * self.modulus)) if w > 0 else 0.0
        if b == 0.0:
            return np.zeros((self.rows, self.cols))
        p0 = 2.0 * w / (np.pi * b)
        U, V = np.meshgrid(self._fu - c[0, 0], self._fv - c[0, 1])
        d = -np.sin(angle) * U + np.cos(angle) * V  # distance across the ridge
        s = np.cos(angle) * U + np.sin(angle) * V  # along the ridge
        h = (self.pitch / self.oversample) * (abs(np.cos(angle)) + abs(np.sin(angle)))
        P = p0 * _cell_average(d / b, h / b) * (np.abs(s) <= ell / 2)
        img = self._Bv @ P @ self._Bu.T
        img[img < self.threshold] = 0.0
        return img

    def read(self, image) -> TactileReading:
        """Force and centroid of an image (rows, cols) [Pa] (~1 mm localization)."""
        img = np.asarray(image, dtype=float)
        if img.shape != (self.rows, self.cols):
            raise InvalidParameter(
                f"image must have shape ({self.rows}, {self.cols}), got {img.shape}"
            )
        total = float(img.sum())
        if total <= 0.0:
            return TactileReading(img, 0.0, np.zeros(2), False)
        cu = float(img.sum(axis=0) @ self.u / total)
        cv = float(img.sum(axis=1) @ self.v / total)
        return TactileReading(img, total * self.pitch**2, np.array([cu, cv]), True)
