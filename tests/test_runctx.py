"""RunContext (planner.runctx): seeded generator, timers, the -v progress bar."""

from __future__ import annotations

import numpy as np

from planner.runctx import RunContext


def test_progress_is_silent_unless_verbose(capsys):
    quiet = RunContext.for_seed(0)
    assert list(quiet.progress(range(5), "loop")) == [0, 1, 2, 3, 4]
    assert capsys.readouterr().err == ""
    loud = RunContext.for_seed(0, verbose=True)
    assert list(loud.progress(range(5), "loop")) == [0, 1, 2, 3, 4]
    assert "loop" in capsys.readouterr().err
    bars = RunContext.for_seed(0, progress_bars=True)  # hapex run in a terminal, without -v
    assert list(bars.progress(range(3), "terminal")) == [0, 1, 2]
    assert "terminal" in capsys.readouterr().err


def test_progress_manual_bar_counts_updates(capsys):
    ctx = RunContext.for_seed(0, verbose=True)
    with ctx.progress(total=4, desc="steps") as bar:
        for _ in range(4):
            bar.update(1)
        assert bar.n == 4
    assert "steps" in capsys.readouterr().err


def test_seeded_generator_and_timer():
    a, b = RunContext.for_seed(7), RunContext.for_seed(7)
    assert np.array_equal(a.rng.normal(size=3), b.rng.normal(size=3))
    with a.timer("stage"):
        pass
    with a.timer("stage"):
        pass
    assert a.timings_s["stage"] >= 0.0
