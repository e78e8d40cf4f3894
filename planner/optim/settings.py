"""The backends hapex knows, which of them are installed, and their default settings.

Tolerances are tightened per backend so that force errors stay far below sensor resolution
(OSQP's default 1e-3 leaves ~1e-2 N errors); ProxQP gets ``eps_primal_inf = 1e-12`` because
its default reports false "primal infeasible" on SI-scaled problems, and a duality-gap check:
without it ProxQP stops at KKT points whose complementarity is off by ~1e-5 (measured on the
closed-form problem of ``tests/test_optim.py``).
"""

from __future__ import annotations

from functools import lru_cache
from importlib.util import find_spec

__all__ = ["DEFAULT_SETTINGS", "KNOWN_SOLVERS", "available_solvers"]

#: Backends the entry point knows how to drive (those installed: :func:`available_solvers`).
KNOWN_SOLVERS = ("osqp", "daqp", "proxqp", "clarabel", "quadprog")

_MODULES = {"proxqp": "proxsuite"}

#: Settings applied unless the caller overrides them (keyword arguments of the solve calls).
DEFAULT_SETTINGS: dict[str, dict[str, object]] = {
    "osqp": {"eps_abs": 1e-9, "eps_rel": 1e-9, "max_iter": 40000, "polishing": True},
    "proxqp": {
        "eps_abs": 1e-9,
        "eps_rel": 0.0,
        "eps_primal_inf": 1e-12,
        "eps_dual_inf": 1e-12,
        "check_duality_gap": True,
        "eps_duality_gap_abs": 1e-9,
        "eps_duality_gap_rel": 0.0,
    },
    "clarabel": {"tol_gap_abs": 1e-10, "tol_gap_rel": 1e-10, "tol_feas": 1e-10},
    "daqp": {},
    "quadprog": {},
}


@lru_cache(maxsize=1)
def available_solvers() -> tuple[str, ...]:
    """Backends of :data:`KNOWN_SOLVERS` that are installed on this machine."""
    return tuple(s for s in KNOWN_SOLVERS if find_spec(_MODULES.get(s, s)) is not None)
