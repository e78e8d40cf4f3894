"""The registry of robots that ``hapex list robots`` prints."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class RobotInfo:
    """One robot of the catalogue.

    Attributes:
        name: identifier (also the ``robot:`` value of a ``kind: robot`` scenario).
        description: one line.
        params: parameter name -> value, SI units (m, rad, N, N m, kg, m³) unless the key names
            its unit (``..._deg``, ``..._in3``).
    """

    name: str
    description: str
    params: dict[str, float] = field(default_factory=dict)


def _hand_info() -> RobotInfo:
    from robots.planar_hand import PlanarHand

    hand = PlanarHand()
    p: dict[str, float] = {}
    for side in ("left", "right"):
        f = hand.params.finger(side)
        p[f"{side}_base_x"], p[f"{side}_base_y"] = f.base
        for k in range(3):
            p[f"{side}_l{k + 1}"] = f.lengths[k]
            p[f"{side}_q{k + 1}_min"], p[f"{side}_q{k + 1}_max"] = f.lower[k], f.upper[k]
        if f.tip == "round":
            p[f"{side}_tip_radius"] = f.tip_radius
        else:
            p[f"{side}_pad_half_width"] = f.pad_half_width
    p["palm_half_width"] = hand.params.palm_half_width
    p["friction"] = hand.params.friction
    p["joint_range_deg"] = float(
        np.rad2deg(hand.params.right.upper[0] - hand.params.right.lower[0])
    )
    p = {k: float(v) + 0.0 for k, v in p.items()}
    return RobotInfo(
        "planar_hand",
        "two planar 3-DOF fingers (left flat pad with 8x8 tactile array, right "
        "2.5 cm soft round tip) and a passive palm (thesis §2.2, Fig. 2.13)",
        p,
    )


def _three_gm_info() -> RobotInfo:
    from robots.three_gm import ThreeGM, trapezoid_volume

    gm = ThreeGM()
    p = dict(gm.params)
    for k, name in enumerate(("theta1", "theta2", "theta3")):
        p[f"{name}_min"], p[f"{name}_max"] = (float(v) for v in gm.joint_limits[k])
    for k, tau in enumerate(gm.torque_limits):
        p[f"tau{k + 1}_max"] = float(tau)
    p["encoder_resolution"] = gm.encoder_resolution
    p["max_force_at_center"] = 9.0
    p["workspace_volume"] = trapezoid_volume()
    p["workspace_volume_in3"] = trapezoid_volume() / 0.0254**3
    p = {k: float(v) + 0.0 for k, v in p.items()}
    return RobotInfo(
        "three_gm",
        "3GM five-bar finger on a rotating base with the OWTS fingertip (thesis App. C.2, §4.3.1)",
        p,
    )


def catalogue() -> list[RobotInfo]:
    """Every robot hapex models, with its parameters (for ``hapex list robots``)."""
    return [_hand_info(), _three_gm_info()]
