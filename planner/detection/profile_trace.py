"""Simulated fingertip traces over the geometry package's exact 2-D profiles, with the ground
truth their detections are scored against (thesis §3.2.1-3.2.2, §3.4.1-3.4.2).

The trace is :func:`planner.geometry.measurement.simulate_trace` (samples at equal arclength
of the exact traced curve, Gaussian sensor noise); the ground truth is the profile's own
:meth:`~planner.geometry.profiles.Profile.curvature_features` (Definition 1, exact), and the
observable truth follows :func:`planner.detection.observable.observable_truth`, with the
profile's arclength as the coordinate of both the features and the contact point.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from planner.detection._validate import positive
from planner.detection.observable import observable_truth
from planner.detection.synthetic import SyntheticTrace
from planner.detection.types import CurvatureFeature
from planner.errors import InvalidParameter
from planner.geometry.curves import traced_curve
from planner.geometry.measurement import DEFAULT_SPEED, simulate_trace
from planner.geometry.profiles import Profile


def _contact_arclength(profile: Profile, points: np.ndarray, spacing: float) -> np.ndarray:
    """Profile arclength (M,) [m] of contact points (M, 2) lying on ``profile``: that of the
    nearest sample at ``spacing`` [m], made non-decreasing (the contact point of a fingertip
    moving forward over an open profile never goes back)."""
    smp = profile.sample(spacing)
    _, j = cKDTree(smp.points).query(points, workers=-1)
    return np.maximum.accumulate(smp.s[j])


def simulate_profile(
    profile: Profile,
    tip_radius: float,
    *,
    spacing: float = 5e-5,
    speed: float = DEFAULT_SPEED,
    center_sigma: float = 0.0,
    contact_sigma: float = 0.0,
    normal_sigma: float = 0.0,
    rng: np.random.Generator | None = None,
) -> SyntheticTrace:
    """Simulate a fingertip tracing an open ``profile`` from end to end.

    Args:
        profile: an open profile (:mod:`planner.geometry.shapes`), material below.
        tip_radius: fingertip radius r_f [m].
        spacing: arclength between samples of the fingertip-centre path [m].
        speed: fingertip speed, sets the time stamps [m/s].
        center_sigma, contact_sigma: Gaussian noise per coordinate [m].
        normal_sigma: Gaussian noise of the normal direction [rad].
        rng: random generator (required when any noise is non-zero).

    Returns:
        A :class:`~planner.detection.synthetic.SyntheticTrace`; ``truth`` holds the profile's
        exact curvature features (``start/end/peak`` in profile arclength [m], ``position``
        on the profile [m]), ``observable`` and ``observable_index`` what a fingertip can
        know of them and when it passes each.

    Raises:
        InvalidParameter: a closed profile, a non-positive radius or spacing, noise without
            ``rng``.
    """
    if not isinstance(profile, Profile):
        raise InvalidParameter(f"profile: expected a Profile, got {type(profile).__name__}")
    if profile.closed:
        raise InvalidParameter(
            f"profile: {profile.name!r} is closed; a trace runs over an open profile from end "
            "to end (plane, step, ridge, ravine, bump, pit, wire, cusp, polyline, open spline)"
        )
    r = positive("tip_radius", tip_radius)
    spacing = positive("spacing", spacing)
    tr = simulate_trace(
        profile,
        r,
        spacing=spacing,
        center_sigma=center_sigma,
        contact_sigma=contact_sigma,
        normal_sigma=normal_sigma,
        speed=speed,
        rng=rng,
    )
    # the dense noise-free trace simulate_trace samples (same resolution), without the
    # interference points: their "contact" is not on the profile
    h = min(spacing / 4, r / 50)
    dense = traced_curve(profile, r, spacing=h)
    keep = np.ones(len(dense.points), dtype=bool)
    keep[dense.interference_index] = False
    contact_u = _contact_arclength(profile, dense.contacts[keep], h)
    sample_u = np.interp(np.arange(len(tr.t)) * spacing, dense.s[keep], contact_u)
    feats = profile.curvature_features(r)
    truth = tuple(
        CurvatureFeature(f.sign, f.start, f.end, f.peak, np.array(f.position)) for f in feats
    )
    observable, obs_idx = observable_truth(
        truth,
        [f.peak for f in feats],
        contact_u,
        sample_u,
        tr.s,
        r,
        gap=max(20 * h, r / 100),
        tie=h,
    )
    return SyntheticTrace(
        t=tr.t,
        centers=tr.centers,
        contacts=tr.contacts,
        normals=tr.normals,
        true_centers=tr.true_centers,
        true_contacts=tr.true_contacts,
        true_normals=tr.true_normals,
        s=tr.s,
        truth=truth,
        observable=observable,
        observable_index=obs_idx,
        profile=profile.sample(profile.length / 4000).points,
        tip_radius=r,
    )


__all__ = ["simulate_profile"]
