"""Simulated fingertip traces over a feature on an inclined plane, for the detection tests:
the geometry package's profiles (:mod:`planner.geometry.shapes`) rotated by ``angle`` and
traced by :func:`planner.geometry.measurement.simulate_trace`."""

import numpy as np

from planner.geometry import shapes
from planner.geometry.measurement import (
    THESIS_CENTER_SIGMA,
    THESIS_CONTACT_SIGMA,
    THESIS_NORMAL_SIGMA,
    simulate_trace,
)


def feature_profile(kind="wire", size=0.65e-3, width=4e-3, angle=0.0, length=0.03):
    """A ``kind`` feature (size [m]: wire diameter, step height, ridge height, ravine/pit
    depth) on a plane of ``length`` [m] on each side, inclined by ``angle`` [rad]."""
    span = 2 * length
    if kind == "plane":
        prof = shapes.plane(0.0, span)
    elif kind == "wire":
        prof = shapes.wire_on_plane(size, 0.0, 0.0, span)
    elif kind == "step":
        prof = shapes.step(size, 0.0, span)
    elif kind == "ridge":
        prof = shapes.ridge(width, size, 0.0, 0.0, span)
    elif kind == "ravine":
        prof = shapes.ravine(width, size, 0.0, 0.0, span)
    elif kind == "pit":
        prof = shapes.pit(size, width, "arc", 0.0, span)
    else:
        raise ValueError(kind)
    return prof.transformed(angle) if angle else prof


def feature_trace(
    kind="wire",
    size=0.65e-3,
    *,
    angle=0.0,
    width=4e-3,
    length=0.03,
    r=0.01,
    spacing=2e-5,
    noise=1.0,
    seed=0,
    center_sigma=None,
    contact_sigma=None,
    normal_sigma=None,
):
    """A trace over :func:`feature_profile` with the thesis' sensor noise times ``noise``
    (or the sigmas given)."""
    return simulate_trace(
        feature_profile(kind, size, width, angle, length),
        r,
        spacing=spacing,
        center_sigma=THESIS_CENTER_SIGMA * noise if center_sigma is None else center_sigma,
        contact_sigma=THESIS_CONTACT_SIGMA * noise if contact_sigma is None else contact_sigma,
        normal_sigma=THESIS_NORMAL_SIGMA * noise if normal_sigma is None else normal_sigma,
        rng=np.random.default_rng(seed),
    )
