"""Simulated fingertip measurements over a 2-D profile (thesis §3.4.1-3.4.2).

A spherical fingertip of radius r_f slides over the profile; joint sensing gives the
fingertip-centre position (noise ±0.2 mm in the thesis' experiments), a tactile sensor gives
the contact point (±0.5 mm) and the contact normal (±1°). Samples are equally spaced along the
traced curve (constant finger speed and sample rate).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner.errors import InvalidParameter
from planner.geometry.curves import arclength, traced_curve
from planner.geometry.profiles import Profile

DEFAULT_SPEED = 0.03  # average finger speed in the experiments of §3.4.2 [m/s]


@dataclass(frozen=True)
class FingertipTrace:
    """A fingertip trace: measurements and the ground truth they were drawn from.

    Attributes:
        t: (N,) time stamps [s].
        s: (N,) arclength of the true fingertip-centre path [m].
        centers: (N, 2) measured fingertip-centre positions [m].
        contacts: (N, 2) measured contact points [m].
        normals: (N, 2) measured outward contact normals (unit).
        true_centers, true_contacts, true_normals: the noise-free values.
        tip_radius: r_f [m].
        interference_points: (K, 2) true interference points of the traced curve [m].
    """

    t: np.ndarray
    s: np.ndarray
    centers: np.ndarray
    contacts: np.ndarray
    normals: np.ndarray
    true_centers: np.ndarray
    true_contacts: np.ndarray
    true_normals: np.ndarray
    tip_radius: float
    interference_points: np.ndarray


def simulate_trace(
    profile: Profile,
    tip_radius: float,
    *,
    spacing: float,
    center_sigma: float = 0.0,
    contact_sigma: float = 0.0,
    normal_sigma: float = 0.0,
    speed: float | None = None,
    rng: np.random.Generator | None = None,
) -> FingertipTrace:
    """Sample a fingertip sliding over ``profile`` at equal arclength steps.

    Args:
        profile: the object profile.
        tip_radius: fingertip radius r_f [m].
        spacing: distance between samples along the fingertip-centre path [m]
            (= speed / sample rate).
        center_sigma: standard deviation of the centre noise, per coordinate [m].
        contact_sigma: standard deviation of the contact-point noise, per coordinate [m].
        normal_sigma: standard deviation of the normal direction noise [rad].
        speed: finger speed for the time stamps [m/s] (default 0.03, §3.4.2).
        rng: random generator (required when any sigma > 0).

    Returns:
        :class:`FingertipTrace`.
    """
    for name, v in (
        ("center_sigma", center_sigma),
        ("contact_sigma", contact_sigma),
        ("normal_sigma", normal_sigma),
    ):
        if not np.isfinite(v) or v < 0:
            raise InvalidParameter(f"{name} must be >= 0, got {v!r}")
    if not np.isfinite(spacing) or not spacing > 0:
        raise InvalidParameter(f"spacing must be a finite number > 0 [m], got {spacing!r}")
    speed = DEFAULT_SPEED if speed is None else speed
    if not np.isfinite(speed) or not speed > 0:
        raise InvalidParameter(f"speed must be > 0 [m/s], got {speed!r}")
    noisy = center_sigma > 0 or contact_sigma > 0 or normal_sigma > 0
    if noisy and rng is None:
        raise InvalidParameter("a random generator is needed when noise is requested")
    traced = traced_curve(profile, tip_radius, spacing=min(spacing / 4, tip_radius / 50))
    s_all = traced.s
    if s_all[-1] / spacing > 2_000_000:
        raise InvalidParameter(f"spacing {spacing:g} m gives too many samples")
    s = np.arange(0.0, s_all[-1] + 1e-12, spacing)
    C = np.stack([np.interp(s, s_all, traced.points[:, j]) for j in range(2)], axis=-1)
    Nn = np.stack([np.interp(s, s_all, traced.normals[:, j]) for j in range(2)], axis=-1)
    Nn /= np.linalg.norm(Nn, axis=1, keepdims=True)
    K = C - tip_radius * Nn
    n = len(s)
    if noisy:
        Cm = C + rng.normal(0.0, center_sigma, (n, 2)) if center_sigma > 0 else C.copy()
        Km = K + rng.normal(0.0, contact_sigma, (n, 2)) if contact_sigma > 0 else K.copy()
        if normal_sigma > 0:
            a = rng.normal(0.0, normal_sigma, n)
            c, sn = np.cos(a), np.sin(a)
            Nm = np.stack([c * Nn[:, 0] - sn * Nn[:, 1], sn * Nn[:, 0] + c * Nn[:, 1]], axis=-1)
        else:
            Nm = Nn.copy()
    else:
        Cm, Km, Nm = C.copy(), K.copy(), Nn.copy()
    return FingertipTrace(
        s / speed,
        arclength(C) if n > 1 else s,
        Cm,
        Km,
        Nm,
        C,
        K,
        Nn,
        float(tip_radius),
        traced.interference_points,
    )


__all__ = ["DEFAULT_SPEED", "FingertipTrace", "simulate_trace"]
