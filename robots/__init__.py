"""Robot models of hapex: the planar two-finger hand with palm and the 3GM finger (Pinocchio),
and the sensors they carry (OWTS, 8x8 tactile array, force gauges, encoders).

Sub-packages: :mod:`robots.planar_hand`, :mod:`robots.three_gm`, :mod:`robots.sensors`;
:func:`catalogue` lists the robots (``hapex list robots``).
"""

from robots import planar_hand, sensors, three_gm
from robots.catalogue import RobotInfo, catalogue

__all__ = ["RobotInfo", "catalogue", "planar_hand", "sensors", "three_gm"]
