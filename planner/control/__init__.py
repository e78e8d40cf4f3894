"""Controllers of the hand and the explorer, and the grasp-force distribution QP.

* the grasp gait of chapter 2 (§2.2.2-2.2.3): object impedance (eq. 2.7,
  :mod:`.object_impedance`), explicit rolling PD on the contact locations (eq. 2.8,
  :mod:`.rolling_pd`), the internal-force PI (:mod:`.internal_force`), the exploring finger's
  fingertip impedance (:mod:`.fingertip_impedance`), and the per-step grasp QP that turns them
  into joint torques: :func:`grasp_qp_function` (CasADi), :class:`GraspStep` (generated C +
  DAQP, one call), :func:`grasp_reference_step` (the same step in numpy + qpsolvers), and the
  compiled stability check :func:`epsilon_two_contacts`;
* the hybrid force/velocity law of the surface explorer (§4.3): :class:`HybridController`,
  :class:`HybridSettings` (normal-force control variants :data:`FORCE_CONTROLS`, the
  torque-limited :class:`TorqueLimitQP`), its frames and :func:`hybrid_reference_step`;
* :class:`GraspForceQP` builds the grasp-force distribution problem of one grasp once and
  re-solves it in place (eqs. 2.1, 2.6, 2.9).

Names are loaded on first use (``from planner.control import GraspStep`` imports only the
modules it needs: the compiled controllers pull in numba, CasADi and a C compiler).
"""

from __future__ import annotations

import importlib

#: public name -> (module of this package, name in that module)
_EXPORTS = {
    # grasp-force distribution
    "OBJECTIVES": ("force_distribution", "OBJECTIVES"),
    "ForceDistribution": ("force_distribution", "ForceDistribution"),
    "GraspForceQP": ("force_distribution", "GraspForceQP"),
    "distribute_forces": ("force_distribution", "distribute_forces"),
    # object impedance (eq. 2.7)
    "ObjectImpedanceGains": ("object_impedance", "ObjectImpedanceGains"),
    "contact_accelerations": ("object_impedance", "contact_accelerations"),
    "object_twist_two_contacts": ("object_impedance", "object_twist_two_contacts"),
    "object_wrench": ("object_impedance", "object_wrench"),
    # explicit rolling (eq. 2.8)
    "RollingGains": ("rolling_pd", "RollingGains"),
    "contact_arclength": ("rolling_pd", "contact_arclength"),
    "contact_offset": ("rolling_pd", "contact_offset"),
    "rolling_moment": ("rolling_pd", "rolling_moment"),
    # internal force PI
    "InternalForceGains": ("internal_force", "InternalForceGains"),
    "InternalForcePI": ("internal_force", "InternalForcePI"),
    "sensed_internal_force": ("internal_force", "sensed_internal_force"),
    # fingertip impedance of the exploring finger
    "FingertipImpedanceGains": ("fingertip_impedance", "FingertipImpedanceGains"),
    "fingertip_force": ("fingertip_impedance", "fingertip_force"),
    "holding_force": ("fingertip_impedance", "holding_force"),
    "orientation_moment": ("fingertip_impedance", "orientation_moment"),
    # the per-step grasp QP
    "FINGER_JOINTS": ("grasp_kinematics", "FINGER_JOINTS"),
    "finger_terms_sx": ("grasp_kinematics", "finger_terms_sx"),
    "numeric_finger_terms": ("grasp_kinematics", "numeric_finger_terms"),
    "grasp_qp_function": ("grasp_qp", "grasp_qp_function"),
    "GraspStep": ("grasp_step", "GraspStep"),
    "grasp_reference_step": ("grasp_reference", "reference_step"),
    "epsilon_two_contacts": ("grasp_stability", "epsilon_two_contacts"),
    "epsilon_two_scalar": ("grasp_stability", "epsilon_two_scalar"),
    # the surface explorer's hybrid force/velocity law (§4.3)
    "GRAVITY_MODES": ("hybrid_law", "GRAVITY_MODES"),
    "HybridController": ("hybrid_law", "HybridController"),
    "HybridSettings": ("hybrid_law", "HybridSettings"),
    "FORCE_CONTROLS": ("hybrid_variants", "FORCE_CONTROLS"),
    "TorqueLimitQP": ("hybrid_variants", "TorqueLimitQP"),
    "owts_voltages": ("hybrid_law", "owts_voltages"),
    "force_parameters": ("hybrid_law", "force_parameters"),
    "tip_force": ("hybrid_law", "tip_force"),
    "SWITCH_SIN2": ("hybrid_frames", "SWITCH_SIN2"),
    "filter_normal": ("hybrid_frames", "filter_normal"),
    "gain_matrix": ("hybrid_frames", "gain_matrix"),
    "surface_frame": ("hybrid_frames", "surface_frame"),
    "tcs_rotation": ("hybrid_frames", "tcs_rotation"),
    "gravity_torque": ("hybrid_reference", "gravity_torque"),
    "hybrid_reference_step": ("hybrid_reference", "reference_step"),
    "hybrid_reference_closed_loop_step": ("hybrid_reference", "reference_closed_loop_step"),
    "hybrid_reference_normal_force_pi": ("hybrid_reference", "reference_normal_force_pi"),
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name not in _EXPORTS:
        raise AttributeError(f"module 'planner.control' has no attribute {name!r}")
    module, attr = _EXPORTS[name]
    value = getattr(importlib.import_module(f"planner.control.{module}"), attr)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
