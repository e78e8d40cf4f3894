"""Two-contact grasp stability after Yoshikawa and Nagai (§2.2.3, eq. 2.9, Fig. 2.11).

With two contacts the grasping (internal) forces act along the contact line, with opposite
signs; the grasp is stable when that line lies inside both friction cones, i.e.
``f_t <= mu f_n`` (eq. 2.9) holds for the squeeze ``f = ±f_int u``. The margin reported is the
smallest angular distance of the contact line to a cone edge, ``atan(mu) - max(α_1, α_2)``
(positive: stable, as in Fig. 2.11 b; negative: unstable, Fig. 2.11 a).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.errors import InvalidParameter
from planner.grasp.wrenches import check_contacts


@dataclass(frozen=True)
class TwoContactStability:
    """Yoshikawa–Nagai stability of a two-contact grasp.

    Attributes:
        stable: the contact line lies strictly inside both friction cones.
        angles: (2,) angle between the contact line and each inward normal [rad].
        margin: ``atan(mu) - max(angles)`` [rad] (> 0 when stable).
        direction: (d,) unit contact-line direction from contact 1 to contact 2.
        forces: (2, d) internal grasp forces of unit magnitude applied on the object
            (``+direction`` at contact 1, ``-direction`` at contact 2) [N per N].
        tangential_ratio: (2,) ``f_t / f_n`` of those forces (eq. 2.9 holds iff <= mu).
    """

    stable: bool
    angles: np.ndarray
    margin: float
    direction: np.ndarray
    forces: np.ndarray
    tangential_ratio: np.ndarray


def two_contact_stability(points, normals, mu: float) -> TwoContactStability:
    """Yoshikawa–Nagai stability of two contacts (planar or spatial).

    Args:
        points: (2, 2) or (2, 3) contact points [m].
        normals: (2, d) inward unit normals.
        mu: friction coefficient (>= 0).

    Returns:
        The :class:`TwoContactStability` report.
    """
    p, n = check_contacts(points, normals, 2)
    mu = checks.nonnegative("mu", mu)
    if p.shape[0] != 2:
        raise InvalidParameter(f"points: expected exactly 2 contacts, got {p.shape[0]}")
    d = p[1] - p[0]
    dist = float(np.linalg.norm(d))
    if dist == 0.0:
        u = np.zeros_like(d)
        angles = np.array([np.pi, np.pi])
    else:
        u = d / dist
        # atan2(|sin|, cos): accurate near 0 and pi, where arccos of the dot product loses
        # half the digits (1e-8 rad off at antipodal contacts)
        cos = np.array([n[0] @ u, -n[1] @ u])
        sin = np.linalg.norm(n - cos[:, None] * np.stack([u, -u]), axis=1)
        angles = np.arctan2(sin, cos)
    forces = np.stack([u, -u])
    fn = np.array([forces[0] @ n[0], forces[1] @ n[1]])
    ft = np.linalg.norm(forces - fn[:, None] * n, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(fn > 0, ft / np.where(fn > 0, fn, 1.0), np.inf)
    margin = float(np.arctan(mu) - angles.max())
    return TwoContactStability(
        stable=bool(dist > 0 and margin > 0),
        angles=angles,
        margin=margin,
        direction=u,
        forces=forces,
        tangential_ratio=ratio,
    )


__all__ = ["TwoContactStability", "two_contact_stability"]
