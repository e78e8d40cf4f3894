"""Input layout of the planar grasp control step (shared by the fast and reference paths).

One control step of the two-finger hand takes five flat float arrays:

* ``q`` (6,) joint encoders [rad], ``qd`` (6,) joint rates [rad/s];
* ``geo`` (8,) sensed contact geometry: the contact points in the left and right fingertip
  frames ``off_L, off_R`` [m] and the fingertip-frame unit normals pointing into the object
  ``nt_L, nt_R`` [-];
* ``ref`` (:data:`N_REF`,) references and mode (slices :data:`REF`);
* ``par`` (:data:`N_PAR`,) gains and object parameters (slices :data:`PAR`).

Modes (``ref[flags]`` = ``(grasp, explore_left, explore_right)``): phase 1 is ``(1, 0, 0)``
(object impedance + internal force on both fingers); phase 2 is ``(0, 0, 1)`` (left holds
the object against the palm with the internal force, right explores with fingertip
impedance); phase 3 is ``(0, 1, 0)``.
"""

from __future__ import annotations

import numpy as np

#: slices of the reference vector
REF = {
    "x_des": slice(0, 3),  # desired object pose (x, y, theta) [m, m, rad]
    "xd_des": slice(3, 6),  # desired object twist
    "xdd_des": slice(6, 9),  # desired object acceleration
    "theta_est": slice(9, 10),  # object orientation estimate [rad]
    "rho": slice(10, 12),  # nominal object radius at each contact [m]
    "f_int": slice(12, 13),  # commanded internal force (PI output) [N]
    "m_roll": slice(13, 15),  # rolling moments of the two fingers (eq. 2.8) [N m]
    "p_des": slice(15, 17),  # exploring contact point command [m]
    "v_des": slice(17, 19),  # its velocity [m/s]
    "phi_des": slice(19, 21),  # fingertip orientation commands (explorer) [rad]
    "palm": slice(21, 23),  # estimated object-palm contact point [m]
    "flags": slice(23, 26),  # (grasp, explore_left, explore_right)
    "p_hold": slice(26, 28),  # anchor of the holding finger's contact (phases 2/3) [m]
}
N_REF = 28

#: slices of the parameter vector
PAR = {
    "kp": slice(0, 3),
    "kv": slice(3, 6),
    "mass": slice(6, 7),
    "inertia": slice(7, 8),
    "gravity": slice(8, 10),
    "mu": slice(10, 11),  # friction coefficient used in the cones (with margin) [-]
    "f_min": slice(11, 12),  # minimum normal force [N]
    "tau_max": slice(12, 13),  # joint torque limit [N m]
    "kp_tip": slice(13, 14),
    "kv_tip": slice(14, 15),
    "f_n_tip": slice(15, 16),  # exploring normal force [N]
    "k_phi": slice(16, 17),
    "d_phi": slice(17, 18),
    "w_wrench": slice(18, 19),
    "w_int": slice(19, 20),
    "w_track": slice(20, 21),
    "w_reg": slice(21, 22),
    "kp_hold": slice(22, 23),  # holding finger's stiffness about its anchor [N/m]
    "kv_hold": slice(23, 24),  # its damping [N s/m]
}
N_PAR = 24

#: QP size: forces of the two fingers on the object (f_L, f_R), and constraint rows:
#: 4 friction-cone rows, 2 minimum-normal-force rows, 6 torque-limit rows
N_VAR = 4
N_CON = 12
#: diagnostic outputs: p_L, p_R, n_L, n_R (2 each), x_est (3), xd_est (3), wrench (3)
N_DIAG = 17
DAQP_INF = 1e30
#: regularization of the damped inverse of the augmented finger Jacobian
DAMPING = 1e-8


def pack(values: dict[str, object], layout: dict[str, slice], size: int) -> np.ndarray:
    """A flat vector of ``size`` with each named entry set (missing entries are 0)."""
    out = np.zeros(size)
    for key, value in values.items():
        out[layout[key]] = value
    return out


__all__ = [
    "DAMPING",
    "DAQP_INF",
    "N_CON",
    "N_DIAG",
    "N_PAR",
    "N_REF",
    "N_VAR",
    "PAR",
    "REF",
    "pack",
]
