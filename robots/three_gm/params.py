"""Dimensions of the 3GM finger (thesis App. C.2) — chosen here, the thesis gives none.

App. C.2.1 describes the well-conditioned workspace: a trapezoid about 4 in high, 4 in long,
4 in wide in front and 10 in wide at the back (~120 in³). Seen from above, a trapezoid of
widths 4 in and 10 in, 4 in apart, swept by the base rotation θ3 is an annular sector with
front radius 8/3 in (67.7 mm), back radius 20/3 in (169.3 mm) and a θ3 range of 1.5 rad
(±43°); 4 in high in z. Its volume is 4 x 4 x (4 + 10)/2 = 112 in³ (~120 in³).

The link lengths below were picked by a grid search over (l1, l3, l5, h1) with l2 = l4 = 40 mm
(short motor and coupler links, as in the device of Fig. C.4): for each candidate the planar
Jacobian of the five-bar was evaluated on a dense grid of (θ1, θ2) and the box
``r + h2 in [67.7, 169.3] mm, z in [-125, -23.4] mm`` was checked to be covered by
configurations with condition number <= 4 and smallest singular value >= 30 mm/rad.
``robots.three_gm.workspace.check_conditioned_workspace`` repeats this check (and the
tests run it): every point of the trapezoid has an elbow-up IK solution inside the joint limits
with a condition number below 7 (the search criterion, 4, was evaluated on a sampled
grid with 4 mm tolerance; the exact IK check finds at most 6.7 at the trapezoid corners).
The θ3 range is ±60°: the ±43° of the trapezoid plus the angle of the lateral offset h3.
"""

from __future__ import annotations

import numpy as np

INCH = 0.0254  # [m]

DEFAULT_PARAMS: dict[str, float] = {
    "l1": 0.10,  # motor-1 link [m]
    "l2": 0.04,  # motor-2 link [m]
    "l3": 0.10,  # passive link from P2 [m]
    "l4": 0.04,  # P1 to the l3 joint along the distal link [m]
    "l5": 0.12,  # P1 to the endpoint along the distal link [m]
    "h1": 0.03,  # motor 2 below motor 1 [m]
    "h2": 0.015,  # radial offset of the endpoint from the base axis [m]
    "h3": 0.01,  # lateral offset of the five-bar plane [m]
}

DEFAULT_JOINT_LIMITS = np.deg2rad(np.array([[-45.0, 100.0], [-120.0, 170.0], [-60.0, 60.0]]))

#: The well-conditioned workspace of App. C.2.1 for these dimensions: horizontal distance
#: from the base axis [m], z range [m], theta3 half-range [rad].
WORKSPACE_RADII = (8.0 / 3.0 * INCH, 20.0 / 3.0 * INCH)
WORKSPACE_Z = (-0.125, -0.125 + 4.0 * INCH)
WORKSPACE_HALF_ANGLE = 0.75

MAX_FORCE_AT_CENTER = 9.0  # [N] App. C.2.1

#: Link masses [kg] of the dynamic model (the thesis gives none; chosen here). Links are
#: hollow aluminium bars of ~6 x 6 mm section (about 0.3 kg/m with bearings and screws):
#: ``l1`` (motor-1 link, 100 mm) 30 g, ``l2`` (motor-2 crank, 40 mm) 15 g, ``l3`` (passive
#: link, 100 mm) 25 g, distal link (``l5``, 120 mm, carries the sensor's fibre bundle) 35 g.
#: Each is modelled as a uniform rod along its axis (inertia m l²/12 about its centre).
LINK_MASSES: dict[str, float] = {"l1": 0.030, "l2": 0.015, "l3": 0.025, "l5": 0.035}
#: The OWTS fingertip [kg]: "its low weight, 27g" (App. C.1.3), modelled as a solid sphere of
#: radius 8 mm centred at the endpoint (inertia 2/5 m r²).
FINGERTIP_MASS = 0.027
#: Reflected rotor inertia ("armature") of each motor, about its joint axis [kg m²]
#: (small DC motors, ~1e-6 kg m² rotor through a 1:3 cable reduction). Order (θ1, θ2, θ3).
MOTOR_ARMATURE = (1e-5, 1e-5, 1e-5)
#: Inertia of the rotating base (the five-bar's support plate) about the θ3 axis [kg m²].
BASE_INERTIA = 2e-4
POSITION_RESOLUTION = 0.05e-3  # [m] App. C.2.1
