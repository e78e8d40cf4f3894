"""Sensor models: the OWTS (App. C.1), the 8x8 tactile array (§2.3.2), force gauges, encoders.

Public names: :class:`OWTS` (``.contact_from_voltages``, ``.voltages_from_contact``),
:class:`OWTSSampler`, :class:`RadialNonlinearity`, :func:`fit_nonlinearity`,
:class:`TactileArray`, :class:`ForceSensor`, :class:`Encoder`, :class:`Potentiometer`.
"""

from robots.sensors.gauges import Encoder, ForceSensor, Potentiometer
from robots.sensors.owts import FULL_SCALE_V, OWTS, DetectionPoint
from robots.sensors.owts_sampling import (
    Calibration,
    OWTSSampler,
    RadialNonlinearity,
    fit_nonlinearity,
)
from robots.sensors.tactile_array import TactileArray, TactileReading
from robots.sensors.tactile_scenes import RidgeCrossing, ridge_crossing_images

__all__ = [
    "FULL_SCALE_V",
    "OWTS",
    "Calibration",
    "DetectionPoint",
    "Encoder",
    "ForceSensor",
    "OWTSSampler",
    "Potentiometer",
    "RadialNonlinearity",
    "RidgeCrossing",
    "TactileArray",
    "TactileReading",
    "fit_nonlinearity",
    "ridge_crossing_images",
]
