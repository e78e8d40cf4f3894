"""Parameter studies: sweep files expanded into many runs, executed locally (joblib) or on a
Dask cluster, resumable, with a tidy results table and a report.

::

    from planner.sweep import load_sweep, expand, run_sweep

    sweep = load_sweep("scenarios/sweeps/detection_noise.yaml", quick=True)
    scenarios = expand(sweep)                 # validated scenarios, nothing run
    table = run_sweep(sweep, "sweeps/detection_noise", jobs=2)   # pandas.DataFrame

This package sits at the top of hapex (beside ``planner.cli``): it uses
:mod:`planner.scenario`, :mod:`planner.runner` and :mod:`planner.results`; library packages
never import it. ``dask.distributed`` is imported only when a Dask backend is used.
"""

from importlib import import_module

_HOMES = {
    "PlannedRun": "expansion",
    "expand": "expansion",
    "plan": "expansion",
    "run_id": "expansion",
    "SweepInterrupted": "run",
    "pending": "run",
    "run_sweep": "run",
    "Sweep": "spec",
    "SweepModel": "spec",
    "load_sweep": "spec",
    "sweep_from_dict": "spec",
    "results_table": "table",
    "SweepBackendError": "backends",
    "SchedulerUnreachable": "backends",
}


def __getattr__(name: str):
    """Import on first use, so ``hapex --help`` does not pay for pydantic/pandas here."""
    if name in _HOMES:
        return getattr(import_module(f"planner.sweep.{_HOMES[name]}"), name)
    raise AttributeError(f"module 'planner.sweep' has no attribute {name!r}")


__all__ = [
    "PlannedRun",
    "SchedulerUnreachable",
    "Sweep",
    "SweepBackendError",
    "SweepInterrupted",
    "SweepModel",
    "expand",
    "load_sweep",
    "pending",
    "plan",
    "results_table",
    "run_id",
    "run_sweep",
    "sweep_from_dict",
]
