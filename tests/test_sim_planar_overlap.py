"""PlanarWorld.logged_overlap (bench_sim's penetration column, contact_sim's
max_penetration_m): the overlap of the states the steps leave.

The log's ``gap`` is measured at the start of a step, after the position projection removed
what the step before left beyond ``projection_tolerance``; a contact point running fast
along a curved outline leaves an overlap of about ``(h v_t)^2 kappa / 2`` (first-order
step; ``planner/sim/planar/stepper.py``, Limits) that only the logged poses show.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.geometry import shapes
from planner.sim import PlanarWorld

A, B, TILT = 0.03, 0.01, 0.4  # ellipse semi-axes [m], release tilt [rad]


def _rocking_ellipse() -> PlanarWorld:
    world = PlanarWorld()
    world.add_fixed(shapes.plane(0, 1), friction=0.5, name="floor")
    rest = math.hypot(A * math.sin(TILT), B * math.cos(TILT))  # centre height when touching
    world.add_body(shapes.ellipse(A, B), (0.0, rest + 1e-5, TILT), 0.1, name="e")
    return world


def test_the_logged_overlap_is_what_the_steps_leave():
    """A 30 x 10 mm ellipse released tilted rolls onto its flat side: the contact point runs
    along the 90 mm radius of curvature at omega * rho and each step leaves an overlap of
    (h omega rho)^2 / (2 rho), 12 um at the fastest; the log's gap shows < 0.1 um."""
    world = _rocking_ellipse()
    log = world.run(0.5)
    left = float(world.logged_overlap(log).max())
    assert -np.nanmin(log.gap) <= world.projection_tolerance
    omega, angle = np.abs(log.velocities["e"][:, 2]), log.poses["e"][:, 2]
    # the outline point touching the floor has the body-frame normal angle -pi/2 - angle;
    # its ellipse parameter t and radius of curvature (closed forms)
    normal = -0.5 * math.pi - angle
    t = np.arctan2(B * np.sin(normal), A * np.cos(normal))
    rho = np.hypot(A * np.sin(t), B * np.cos(t)) ** 3 / (A * B)
    predicted = (world.dt * omega * rho) ** 2 / (2.0 * rho)
    assert predicted.max() == pytest.approx(1.16e-5, rel=0.02)  # at 16 rad/s, rho 90 mm
    assert left == pytest.approx(predicted.max(), rel=0.15)
