"""Scenario kind ``detect``: curvature and macro features from a fingertip trace, simulated
over a profile (with ground truth and scoring) or read from a user's CSV/NPZ log (thesis
§3.3-3.4). Keys are documented on :class:`Config` (:mod:`planner.kinds.detect.config`); the
run is :func:`planner.kinds.detect.pipeline.run` (the submodule is not named ``run``:
importing it would rebind this package's :func:`run` to the module).
"""

from planner.kinds.detect.config import Config, Simulation


def run(config: Config, ctx):
    """Run the ``detect`` scenario (see :mod:`planner.kinds.detect.pipeline`)."""
    from planner.kinds.detect.pipeline import run as run_detect

    return run_detect(config, ctx)


__all__ = ["Config", "Simulation", "run"]
