"""Shared test set-up: headless plotting, the repository root, a CLI runner."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

os.environ.setdefault("MPLBACKEND", "Agg")

# Hypothesis profiles. "ci" is deterministic: the same examples on every run and machine
# (derandomize), no example database carried between runs, no per-example deadline (the
# machine is shared; timing must never fail a test). "dev" (the default) explores new random
# examples on every run and remembers failures in .hypothesis/, without deadlines either.
# Select with HYPOTHESIS_PROFILE=ci or ``pytest --hypothesis-profile=ci`` (.ci/run does).
settings.register_profile(
    "ci",
    derandomize=True,
    database=None,
    deadline=None,
    print_blob=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile("dev", deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "dev"))

ROOT = Path(__file__).resolve().parent.parent


def benchmark_module(name: str):
    """The benchmark script ``benchmarks/<name>.py`` imported as a module (with the
    helpers it imports from that folder; the folder is not left on ``sys.path``)."""
    import importlib

    folder = str(ROOT / "benchmarks")
    sys.path.insert(0, folder)
    try:
        return importlib.import_module(name)
    finally:
        sys.path.remove(folder)


def _import_every_local_module() -> None:
    """Import every module of ``planner`` and ``robots`` and every benchmark script before
    any test runs (~2 s per process).

    Hypothesis draws some numbers from the literals of the *local* modules loaded so far
    (``sys.modules``, outside site-packages and tests/). Under pytest-xdist which modules a
    worker has loaded when a property test runs depends on which tests it ran before, so a
    derandomized test could draw other examples from run to run. With everything loaded up
    front the pool is the same for every test in every run. (This needs every package
    export to survive the import of a same-named submodule: tests/test_package_names.py.)"""
    import importlib
    import pkgutil

    import planner
    import robots

    for pkg in (planner, robots):
        for info in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + "."):
            if not info.name.endswith("__main__"):
                importlib.import_module(info.name)
    for script in sorted((ROOT / "benchmarks").glob("*.py")):
        benchmark_module(script.stem)


_import_every_local_module()


def run_cli(
    *args: str, cwd: Path | None = None, timeout: float = 300
) -> subprocess.CompletedProcess:
    """Run ``hapex ARGS`` in a subprocess (``python -m planner.cli``), capturing output."""
    env = dict(os.environ, MPLBACKEND="Agg")
    return subprocess.run(
        [sys.executable, "-m", "planner.cli", *args],
        cwd=cwd or ROOT,
        capture_output=True,
        text=True,
        timeout=timeout,
        env=env,
    )


@pytest.fixture
def cli():
    return run_cli
