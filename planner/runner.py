"""Run a validated scenario: pick the runner of its kind, time it, write the run directory."""

from __future__ import annotations

import time
from dataclasses import dataclass
from datetime import datetime
from pathlib import Path

from planner.results import Event, RunResult, write_run_directory
from planner.runctx import RunContext
from planner.scenario import ScenarioBase, kinds


@dataclass(frozen=True)
class RunOutcome:
    """A finished run: its result and where it was written (``None`` if not written)."""

    result: RunResult
    out_dir: Path | None


def run_config(
    config: ScenarioBase,
    *,
    plots: bool | None = None,
    quick: bool = False,
    base_dir: Path | None = None,
    verbose: bool = False,
    progress: bool = False,
) -> tuple[RunResult, dict]:
    """Run a validated scenario in memory.

    Args:
        config: a validated scenario (see :func:`planner.scenario.load_scenario`).
        plots: build figures (default: the scenario's ``output.plots``).
        quick: short smoke-test run (runners reduce horizons/resolutions).
        base_dir: folder against which relative data-file paths resolve.
        verbose: print progress messages (and show progress bars).
        progress: show progress bars of long loops on stderr.

    Returns:
        ``(result, timings_s)``. Library failures inside the runner that leave the task
        unable to go on become ``status="failed"`` with the reason; programming errors raise.
    """
    from planner.errors import HapexError, InvalidParameter, ScenarioError

    spec = kinds()[config.kind]
    ctx = RunContext.for_seed(
        config.seed,
        plots=config.output.plots if plots is None else (plots and config.output.plots),
        quick=quick,
        base_dir=base_dir or Path.cwd(),
        verbose=verbose,
        progress_bars=progress,
    )
    t0 = time.perf_counter()
    try:
        result = spec.run(config, ctx)
    except (ScenarioError, InvalidParameter):
        raise  # bad input found late is still bad input: exit 2, nothing written
    except HapexError as exc:
        result = RunResult(
            status="failed",
            reason=f"{type(exc).__name__}: {exc}",
            events=[Event("error", str(exc))],
        )
    timings = dict(ctx.timings_s)
    timings["total"] = time.perf_counter() - t0
    return result, timings


def default_out_dir(config: ScenarioBase) -> Path:
    """``runs/<name>-<YYYYmmdd-HHMMSS>`` in the current directory."""
    stamp = datetime.now().strftime("%Y%m%d-%H%M%S")
    return Path("runs") / f"{config.name}-{stamp}"


def execute(
    config: ScenarioBase,
    out_dir: Path | None = None,
    *,
    plots: bool | None = None,
    quick: bool = False,
    base_dir: Path | None = None,
    verbose: bool = False,
    progress: bool = False,
) -> RunOutcome:
    """Run a scenario and write its run directory (atomically).

    ``progress`` shows progress bars of long loops on stderr (``hapex run`` in a terminal).
    """
    result, timings = run_config(
        config, plots=plots, quick=quick, base_dir=base_dir, verbose=verbose, progress=progress
    )
    out = Path(out_dir) if out_dir is not None else default_out_dir(config)
    resolved = config.model_dump(mode="json")
    write_run_directory(
        out,
        result,
        name=config.name,
        kind=config.kind,
        seed=config.seed,
        resolved_scenario=resolved,
        timings_s=timings,
        plot_formats=tuple(config.output.formats),
        dpi=config.output.dpi,
    )
    return RunOutcome(result, out)


__all__ = ["RunOutcome", "default_out_dir", "execute", "run_config"]
