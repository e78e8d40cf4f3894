"""planner.control exports the controllers' public names (loaded on first use)."""

from __future__ import annotations

import importlib
import subprocess
import sys

import pytest

import planner.control as control

GAIT_MODULES = ("object_impedance", "rolling_pd", "internal_force", "fingertip_impedance",
                "grasp_qp", "grasp_step", "grasp_stability", "force_distribution")  # fmt: skip


def test_every_exported_name_resolves_to_its_module_object():
    for name in control.__all__:
        module, attr = control._EXPORTS[name]
        expected = getattr(importlib.import_module(f"planner.control.{module}"), attr)
        assert getattr(control, name) is expected


@pytest.mark.parametrize("module", GAIT_MODULES)
def test_gait_controller_modules_are_fully_exported(module):
    mod = importlib.import_module(f"planner.control.{module}")
    exported = {(m, a) for m, a in control._EXPORTS.values()}
    missing = [n for n in mod.__all__ if (module, n) not in exported and n != "STEP_INPUTS"]
    assert missing == []


def test_hybrid_names_are_exported():
    for module in ("hybrid_law", "hybrid_frames", "hybrid_reference", "hybrid_variants"):
        mod = importlib.import_module(f"planner.control.{module}")
        for n in mod.__all__:
            # the numpy reference implementations carry the prefix hybrid_ in the package
            alias = f"hybrid_{n}" if n.startswith("reference_") else n
            assert control._EXPORTS[alias] == (module, n)


def test_star_import_and_unknown_name():
    ns: dict = {}
    exec("from planner.control import *", ns)
    assert {"GraspStep", "HybridController", "InternalForcePI", "rolling_moment"} <= set(ns)
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        _ = control.nope


def test_importing_the_package_loads_no_compiled_controller():
    code = ("import sys, planner.control; "
            "print(any(m in sys.modules for m in ('numba', 'casadi', "
            "'planner.control.grasp_step', 'planner.control.hybrid_kernel')))")  # fmt: skip
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)  # fmt: skip
    assert out.stdout.strip() == "False"
