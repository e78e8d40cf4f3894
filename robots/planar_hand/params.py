"""Parameters of the planar two-finger hand with a passive palm (thesis §2.2.1, Fig. 2.2/2.13).

The thesis does not give the dimensions of its test bed ("Marvin", Fig. 2.13); it gives the
joint ranges (about 110° per joint), the fingertips (a 2.5 cm radius soft fingertip on the
right, a flat fingertip carrying the 8x8 tactile array on the left), the friction coefficient
(1.0, Fig. 2.4) and the object (a 10 cm ball). The defaults below were chosen so that a 10 cm
ball resting on the palm can be grasped against the palm by either finger and between the two
fingers (checked by ``tests/test_planar_hand_workspace.py`` with the workspace map):

* the palm is the segment ``y = 0, |x| <= palm_half_width`` of the hand plane, its surface
  facing +y; the ball rests on it with its centre at ``(0, 0.05)``;
* each finger's first joint sits beside the palm at ``(±0.10, 0)``; at q = 0 every link points
  along +y, positive angles turn counter-clockwise (about +z);
* links of 100 mm, 60 mm and 40 mm (joint 3 to the fingertip point), i.e. a 200 mm reach;
* joint ranges of 110°: right finger [-40°, 70°], [0°, 110°], [-10°, 100°], left mirrored.

These were picked by a grid search over base placement, link lengths and joint-1 range that
maximized the reachable part of the ball's surface (workspace map, contact angles -60°..120°
for the right finger, mirrored for the left): the round right tip reaches contact angles of
about 10°..90° (counter-clockwise from +x about the ball centre), the flat left pad about
115°..155° (its orientation is fixed by the contact), enough for the palm + finger grasps of
the thesis' exploration phases.

Coordinates of the hand plane: x to the right, y up (away from the palm), z out of the plane.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

from planner import checks
from planner.errors import InvalidParameter

FINGERS = ("left", "right")
TIP_KINDS = ("round", "flat")


def _deg(*values: float) -> tuple[float, ...]:
    return tuple(float(np.deg2rad(v)) for v in values)


@dataclass(frozen=True)
class FingerParams:
    """One planar 3-DOF finger.

    Attributes:
        base: (2,) position of joint 1 in the hand plane [m].
        lengths: (3,) link lengths: joint 1->2, joint 2->3, joint 3->fingertip centre [m].
        lower: (3,) lower joint limits [rad].
        upper: (3,) upper joint limits [rad].
        tip: ``"round"`` (soft disc of radius ``tip_radius``, the fingertip point is the disc
            centre) or ``"flat"`` (a pad perpendicular to the distal link, the fingertip point
            is the pad centre and the pad's outward normal is the distal link direction).
        tip_radius: fingertip radius r_f of a round tip [m] (unused for a flat tip).
        pad_half_width: half-width of a flat pad along its surface [m] (8 taxels x 2.5 mm).
    """

    base: tuple[float, float]
    lengths: tuple[float, float, float]
    lower: tuple[float, float, float]
    upper: tuple[float, float, float]
    tip: str = "round"
    tip_radius: float = 0.025
    pad_half_width: float = 0.01

    def __post_init__(self) -> None:
        if self.tip not in TIP_KINDS:
            raise InvalidParameter(f"tip must be one of {list(TIP_KINDS)}, got {self.tip!r}")
        if len(self.lengths) != 3 or min(self.lengths) <= 0:
            raise InvalidParameter(f"lengths must be three values > 0 [m], got {self.lengths}")
        if (
            len(self.lower) != 3
            or len(self.upper) != 3
            or np.any(np.asarray(self.lower) >= np.asarray(self.upper))
        ):
            raise InvalidParameter(
                f"joint limits must be 3 pairs with lower < upper [rad], got lower="
                f"{self.lower}, upper={self.upper}"
            )
        if self.tip_radius <= 0 or self.pad_half_width <= 0:
            raise InvalidParameter(
                "tip_radius and pad_half_width must be > 0 [m], got "
                f"{self.tip_radius}, {self.pad_half_width}"
            )

    @property
    def round_radius(self) -> float:
        """Radius of a round tip [m]; 0.0 for a flat pad."""
        return float(self.tip_radius) if self.tip == "round" else 0.0


@dataclass(frozen=True)
class HandParams:
    """The whole hand: two fingers and a palm.

    Attributes:
        left: the left finger (flat pad with the 8x8 tactile array by default).
        right: the right finger (2.5 cm soft round tip by default).
        palm_half_width: half-length of the palm segment along x [m].
        friction: default Coulomb friction coefficient of the contacts (Fig. 2.4) [-].
    """

    left: FingerParams = field(default_factory=lambda: default_finger("left"))
    right: FingerParams = field(default_factory=lambda: default_finger("right"))
    palm_half_width: float = 0.08
    friction: float = 1.0

    def finger(self, name: str) -> FingerParams:
        """The parameters of finger ``name`` (``"left"`` or ``"right"``)."""
        if name not in FINGERS:
            raise InvalidParameter(f"finger must be one of {list(FINGERS)}, got {name!r}")
        return self.left if name == "left" else self.right


def default_finger(side: str, tip: str | None = None, tip_radius: float = 0.025) -> FingerParams:
    """The default finger of ``side`` (see the module docstring for the choice).

    Joint ranges are 110° each. The right finger curls counter-clockwise (towards the palm
    centre), the left one is its mirror image.

    Args:
        side: ``"left"`` or ``"right"``.
        tip: ``"round"`` or ``"flat"``; default flat on the left, round on the right.
        tip_radius: radius of a round tip [m].
    """
    if side not in FINGERS:
        raise InvalidParameter(f"side must be one of {list(FINGERS)}, got {side!r}")
    lo = np.array(_deg(-40.0, 0.0, -10.0))
    hi = np.array(_deg(70.0, 110.0, 100.0))
    if side == "left":
        lo, hi = -hi, -lo
        base = (-0.10, 0.0)
        tip = tip or "flat"
    else:
        base = (0.10, 0.0)
        tip = tip or "round"
    return FingerParams(
        base=base,
        lengths=(0.10, 0.06, 0.04),
        lower=tuple(lo),
        upper=tuple(hi),
        tip=tip,
        tip_radius=tip_radius,
    )


#: joint ranges of the right finger of the executed grasp gait's hand [deg] (the left finger
#: mirrors them): the default fingers with joint 1 to 90 deg, joint 2 folding to 150 deg and
#: joint 3 to 130 deg. Measured with ``explore_object`` (10 s, mu = 1): with the 110 deg
#: ranges of :func:`default_finger` circles of 2-3 cm radius do not fit the hand and 4-5 cm
#: ones stall after 16-42 deg (every phase 1 ends at a joint stop after 1-10 deg); with these
#: ranges the 10 cm ball with a ridge turns 365 deg in 60 s and the batch's 2-7 cm circles
#: keep turning (``benchmarks/bench_gait.py``).
GAIT_LOWER_DEG = (-40.0, 0.0, -10.0)
GAIT_UPPER_DEG = (90.0, 150.0, 130.0)


def ranged_hand_params(
    lower_deg, upper_deg, friction: float = 1.0, left_tip_radius: float | None = None
) -> HandParams:
    """The default fingers with the right finger's joint ranges ``lower_deg``..``upper_deg``
    [deg] (3 each; the left finger mirrors them) and ``friction`` [-].

    ``left_tip_radius`` [m]: None for the default flat left pad (with the 8x8 tactile
    array), else a round left tip of that radius (§2.3.2's alternative: the right tip's
    2.5 cm, or the curved 1.5 cm tip the thesis wished for).

    Raises:
        InvalidParameter: a negative friction, a non-positive ``left_tip_radius``, or ranges
            that are not 3 pairs of ``lower < upper`` (checked by :class:`FingerParams`).
    """
    friction = checks.nonnegative("friction", friction)
    lo = tuple(float(np.deg2rad(v)) for v in lower_deg)
    hi = tuple(float(np.deg2rad(v)) for v in upper_deg)
    right = replace(default_finger("right"), lower=lo, upper=hi)
    if left_tip_radius is None:
        left = default_finger("left")
    else:
        radius = checks.positive("left_tip_radius", left_tip_radius, "m")
        left = default_finger("left", tip="round", tip_radius=radius)
    left = replace(left, lower=tuple(-v for v in hi), upper=tuple(-v for v in lo))
    return HandParams(left=left, right=right, friction=float(friction))


def gait_hand_params(friction: float = 1.0, left_tip_radius: float | None = None) -> HandParams:
    """The hand of the executed grasp gait (``GAIT_LOWER_DEG``..``GAIT_UPPER_DEG``); with
    ``left_tip_radius`` [m] a round left tip instead of the flat pad
    (:func:`ranged_hand_params`)."""
    return ranged_hand_params(GAIT_LOWER_DEG, GAIT_UPPER_DEG, friction, left_tip_radius)
