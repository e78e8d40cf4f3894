"""Tactile image sequences of the thesis experiments (§2.3.2, Fig. 2.14).

:func:`ridge_crossing_images` slides the flat pad over a ball carrying a ridge (Fig. 2.15: a
10 cm ball with a ridge about 3 mm high and 4 mm wide). A flat pad tangent to the ball at the
pad centre sees the ball's surface fall away by ``d²/(2R)`` at distance d; the ridge is
taller than that over the whole pad (3 mm >= (10 mm)²/(2·50 mm) = 1 mm), so while the ridge is
under the pad it lifts the pad off the ball and carries the whole normal force (a line
contact), and otherwise the ball does (a round Hertzian blob). This is the change of pattern
"from the characteristic pattern of a spherical contact to a ridge" of Fig. 2.14.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks
from robots.sensors.tactile_array import TactileArray


@dataclass(frozen=True)
class RidgeCrossing:
    """Images of the pad sliding over a ridge.

    Attributes:
        offsets: (K,) ridge position across the pad, from the pad centre [m].
        images: (K, rows, cols) taxel pressures [Pa].
        on_ridge: (K,) whether the ridge carries the load.
        centroids: (K, 2) pressure centroids on the pad [m].
    """

    offsets: np.ndarray
    images: np.ndarray
    on_ridge: np.ndarray
    centroids: np.ndarray


def ridge_crossing_images(
    array: TactileArray,
    offsets,
    force: float = 0.3,
    ball_radius: float = 0.05,
    ridge_width: float = 0.004,
    ridge_height: float = 0.003,
    angle: float = np.pi / 2,
) -> RidgeCrossing:
    """Tactile images while a ridge on a ball crosses the pad.

    Args:
        array: the tactile array.
        offsets: (K,) ridge positions across the pad (along the pad's u axis rotated by
            ``angle - pi/2``), from the pad centre [m].
        force: normal force held by the controller (0.3 N in §2.3.2) [N].
        ball_radius: ball radius [m].
        ridge_width: ridge width [m]; its crest radius is taken as half of it.
        ridge_height: ridge height [m].
        angle: direction of the ridge axis on the pad from +u [rad] (default: along v).
    """
    off = checks.series("offsets", np.atleast_1d(np.asarray(offsets, dtype=float)), unit="m")
    force = checks.positive("force", force, "N")
    ball_radius = checks.positive("ball_radius", ball_radius, "m")
    ridge_width = checks.positive("ridge_width", ridge_width, "m")
    ridge_height = checks.positive("ridge_height", ridge_height, "m")
    half = max(array.extent)
    across = np.array([np.sin(angle), -np.cos(angle)])  # unit normal to the ridge axis
    # the ridge lifts the pad while its crest is on the pad and taller than the ball's sag there
    on = (np.abs(off) <= half) & (ridge_height >= off**2 / (2 * ball_radius))
    images = np.empty((len(off), array.rows, array.cols))
    ball = array.sphere_images([0.0, 0.0], ball_radius, force)
    for k, d in enumerate(off):
        if on[k]:
            images[k] = array.ridge_image(d * across, angle, ridge_width / 2, force)
        else:
            images[k] = ball
    cents = np.array([array.read(im).centroid for im in images])
    return RidgeCrossing(off, images, on, cents)


def draw_ridge_crossing(array: TactileArray, crossing: RidgeCrossing, max_panels: int = 8):
    """A row of tactile images (Fig. 2.14 style); returns a matplotlib Figure."""
    from matplotlib.figure import Figure

    idx = np.unique(np.linspace(0, len(crossing.offsets) - 1, max_panels).round().astype(int))
    fig = Figure(figsize=(1.6 * len(idx) + 1.0, 2.4), layout="constrained")
    axes = fig.subplots(1, len(idx), squeeze=False)[0]
    vmax = float(crossing.images.max()) / 1000.0 or 1.0
    u0, v0 = array.extent
    ext = [-u0 * 1000, u0 * 1000, -v0 * 1000, v0 * 1000]
    for ax, k in zip(axes, idx, strict=True):
        im = ax.imshow(
            crossing.images[k] / 1000.0, origin="lower", extent=ext, vmin=0, vmax=vmax, cmap="magma"
        )
        ax.set_title(f"ridge at {crossing.offsets[k] * 1000:+.0f} mm", fontsize=8)
        ax.set_xlabel("u [mm]", fontsize=7)
        ax.tick_params(labelsize=6)
    axes[0].set_ylabel("v [mm]", fontsize=7)
    fig.colorbar(im, ax=list(axes), label="pressure [kPa]", shrink=0.8)
    fig.suptitle("8x8 tactile array sliding over the ridge of the ball (cf. Fig. 2.14)", fontsize=9)
    return fig
