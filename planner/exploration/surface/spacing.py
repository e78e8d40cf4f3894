"""Features closer than a fingertip diameter: the §4.2.1 assumption the explorer checks."""

from __future__ import annotations

__all__ = ["spacing_warnings"]

FOOTPRINT_PROBE = 3.1e-4  # [m] radius of the thin ball whose level lines are the footprints


def spacing_warnings(plate, region, tip_radius: float) -> list[str]:
    """Messages for pairs of features closer than a fingertip diameter (§4.2.1).

    The distance of two features is that between their footprints, the outlines where each
    rises a quarter of its height above the plate far from it (the asymptotic plate: a
    property of the plate, not the level a tracer reads at the feature's foot), traced by a
    thin ball of radius ``FOOTPRINT_PROBE``
    (:func:`~planner.exploration.surface.plates.truth_features` with ``foot_tilt=None``).

    Args:
        plate: a :class:`planner.sim.spatial.plate.Plate`.
        region: ((u0, u1), (v0, v1)) explored box of the plate frame [m].
        tip_radius: fingertip radius r_f [m]; pairs closer than 2 r_f are reported.

    Returns:
        One human-readable line per pair (distance in [mm]; "overlap" when the footprints
        meet), empty when all are far enough.
    """
    import shapely

    from planner.exploration.surface.plates import truth_features

    rise = [0.25 * f.height for f in plate.features]
    truth = truth_features(plate, region, FOOTPRINT_PROBE, rise, foot_tilt=None)
    geoms = []
    for t in truth:
        lines = [ln for ln in t.outline if len(ln) >= 2]
        geoms.append(shapely.MultiLineString(lines) if lines else shapely.Point(*t.centre))
    out = []
    for i in range(len(geoms)):
        for j in range(i + 1, len(geoms)):
            d = float(geoms[i].distance(geoms[j]))
            if d < 2 * tip_radius:
                gap = "overlap" if d == 0.0 else f"are {d * 1e3:.1f} mm apart"
                out.append(
                    f"features {i} ({truth[i].kind}) and {j} ({truth[j].kind}) {gap}, "
                    f"closer than a fingertip diameter ({2e3 * tip_radius:.0f} mm): the "
                    "finger may not tell them apart"
                )
    return out
