"""Map-space tables of the grasp-gait search (§2.2.1): grasp maps of the finger pair and of
each finger with the palm at every object pose, the fingers' workspace tables and the
fingertip rolling limits (see :mod:`planner.grasp.gait` for the model)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planner import checks
from planner.grasp.closure import force_closure_two_planar
from planner.grasp.maps import ClosureKernel, contact_angles, profile_contacts
from planner.grasp.quality import epsilon_two_planar
from planner.grasp.workspace import WorkspaceTables, as_reachability, rotation, workspace_tables


@dataclass(frozen=True)
class GaitProblem:
    """All tables of a gait search (map space), built by :func:`gait_problem`.

    Attributes:
        theta: (n,) contact angles [rad]; sign: +1 clockwise object rotation, -1 ccw.
        fc_lr, eps_lr: (n, n) left–right grasp map (``[i_left, i_right]``).
        fc_lp, eps_lp, fc_rp, eps_rp: (n, n) finger–palm grasps ``[pose k, finger index]``.
        reach: ``{"left": (n, n), "right": (n, n)}`` reachability ``[pose k, index]``.
        arc: (n,) object arclength between contact angles i and i+sign [m].
        roll: ``{"left", "right"}`` rolling travel limit per phase 1 [m].
        tables: the workspace tables (object placements, palm contacts).
    """

    theta: np.ndarray
    sign: int
    fc_lr: np.ndarray
    eps_lr: np.ndarray
    fc_lp: np.ndarray
    eps_lp: np.ndarray
    fc_rp: np.ndarray
    eps_rp: np.ndarray
    reach: dict[str, np.ndarray]
    arc: np.ndarray
    roll: dict[str, float]
    tables: WorkspaceTables


def gait_problem(
    profile,
    hand=None,
    mu: float = 1.0,
    *,
    mu_palm: float | None = None,
    resolution: int = 72,
    direction: str = "clockwise",
    x0: float = 0.0,
    roll_length: float | None = None,
    min_epsilon: float = 0.0,
) -> GaitProblem:
    """Build the map-space tables of a gait search (see :func:`plan_gait` for arguments)."""
    checks.in_range("min_epsilon", min_epsilon, 0.0, 1.0, closed=(True, False))
    checks.choice("direction", direction, ("clockwise", "counterclockwise"))
    mu = checks.nonnegative("mu", mu)
    mu_p = mu if mu_palm is None else checks.nonnegative("mu_palm", mu_palm)
    reach = as_reachability(hand)
    theta = contact_angles(resolution)
    n = theta.size
    sign = 1 if direction == "clockwise" else -1
    pts, nin = profile_contacts(profile, theta)
    fc_lr = ClosureKernel(n, mu)(pts[:, 0], pts[:, 1], nin[:, 0], nin[:, 1]).copy()
    eps_lr = np.where(
        fc_lr, epsilon_two_planar(pts[:, None], nin[:, None], pts[None], nin[None], mu), 0.0
    )
    tables = workspace_tables(profile, reach, theta, -sign * theta, x0)
    # palm contact of each pose, in the object frame: point on the profile, normal R^T (+y)
    place = tables.placement
    ok_palm = tables.palm_index >= 0
    pp, _ = profile_contacts(profile, np.nan_to_num(place.palm_theta))
    R = rotation(place.angles)
    np_in = R[:, 1, :]  # R^T e_y = second row of R
    fcs, epss = [], []
    for _ in ("left", "right"):
        fc = force_closure_two_planar(pts[None], nin[None], pp[:, None], np_in[:, None], mu, mu_p)
        fc &= ok_palm[:, None]
        eps = epsilon_two_planar(pts[None], nin[None], pp[:, None], np_in[:, None], mu, mu_p)
        fcs.append(fc)
        epss.append(np.where(fc, eps, 0.0))
    arc = np.linalg.norm(np.roll(pts, -sign, axis=0) - pts, axis=1)
    if roll_length is not None:
        roll = {f: checks.positive("roll_length", roll_length, "m") for f in ("left", "right")}
    else:
        rl = getattr(reach, "roll_length", None)
        roll = {f: (float(rl(f)) if rl else np.inf) for f in ("left", "right")}
    if min_epsilon > 0:  # a grasp must also keep a robustness margin (Ferrari–Canny ε)
        fc_lr = fc_lr & (eps_lr > min_epsilon)
        fcs = [fc & (e > min_epsilon) for fc, e in zip(fcs, epss, strict=True)]
    return GaitProblem(
        theta,
        sign,
        fc_lr,
        eps_lr,
        fcs[0],
        epss[0],
        fcs[1],
        epss[1],
        {f: tables.reachable[f] for f in ("left", "right")},
        arc,
        roll,
        tables,
    )


def infeasible_reason(prob: GaitProblem) -> str | None:
    """A global reason no gait can exist, or None."""
    rl, rr = prob.reach["left"], prob.reach["right"]
    if not rl.any() or not rr.any():
        who = "left" if not rl.any() else "right"
        return f"workspace: the {who} finger cannot reach the object at any orientation"
    p1 = prob.fc_lr[None, :, :] & rl[:, :, None] & rr[:, None, :]
    if not p1.any():
        return (
            "workspace and force closure: at no orientation can the two fingers reach a "
            "pair of contacts in force closure (object too long/thin for the finger "
            f"workspaces; the left finger reaches {rl.mean():.0%} and the right finger "
            f"{rr.mean():.0%} of (pose, contact) cells)"
        )
    lp = (prob.fc_lp & rl).any()
    rp = (prob.fc_rp & rr).any()
    if not lp and not rp:
        if prob.fc_lp.any() or prob.fc_rp.any():
            return (
                "workspace (palm grasps): the contacts that would hold the object in force "
                "closure against the palm lie outside both fingers' workspaces at every "
                "orientation, so no finger is ever free to relocate"
            )
        return (
            "force closure (palm grasps): no contact forms a force-closure grasp with the "
            "palm contact at any orientation, so no finger is ever free to relocate"
        )
    return None


__all__ = ["GaitProblem", "gait_problem", "infeasible_reason"]
