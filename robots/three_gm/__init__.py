"""The 3GM five-bar robotic finger (thesis App. C.2, §4.3.1-4.3.2).

Public names: :class:`ThreeGM` (``.params``, ``.joint_limits``, ``.forward_kinematics``,
``.passive_angles``, ``.jacobian``, ``.inverse_kinematics``, ``.model`` and statics),
:func:`trapezoid_grid`, :func:`check_conditioned_workspace`, :func:`solve_closed_loop`.
"""

from robots.three_gm.closed_form import FiveBarState, rotation_tcs_to_wcs
from robots.three_gm.gm import PARAM_KEYS, ThreeGM
from robots.three_gm.model import PinKinematics, closure_constraint, solve_closed_loop
from robots.three_gm.params import DEFAULT_JOINT_LIMITS, DEFAULT_PARAMS
from robots.three_gm.workspace import (
    ConditionedWorkspace,
    check_conditioned_workspace,
    trapezoid_grid,
    trapezoid_volume,
)

__all__ = [
    "DEFAULT_JOINT_LIMITS",
    "DEFAULT_PARAMS",
    "PARAM_KEYS",
    "ConditionedWorkspace",
    "FiveBarState",
    "PinKinematics",
    "ThreeGM",
    "check_conditioned_workspace",
    "closure_constraint",
    "rotation_tcs_to_wcs",
    "solve_closed_loop",
    "trapezoid_grid",
    "trapezoid_volume",
]
