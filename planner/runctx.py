"""What a scenario runner gets besides its validated configuration."""

from __future__ import annotations

import sys
import time
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import TypeVar

import numpy as np

T = TypeVar("T")


@dataclass
class RunContext:
    """Services offered to a runner.

    Attributes:
        rng: the only source of randomness, seeded from the scenario's ``seed``.
        plots: whether the runner should build figures (``--no-plots`` / ``output.plots``).
        quick: a short smoke-test run (``--quick``): runners reduce horizons and resolutions.
        base_dir: folder of the scenario file; relative data-file paths resolve against it.
        verbose: ``-v`` was given.
        progress_bars: show progress bars on stderr (``hapex run`` in a terminal, or ``-v``);
            off in sweeps, the reproduce report and library calls unless asked for.
        timings_s: wall-clock time per named stage [s], filled by :meth:`timer`.
    """

    rng: np.random.Generator
    plots: bool = True
    quick: bool = False
    base_dir: Path = field(default_factory=Path.cwd)
    verbose: bool = False
    progress_bars: bool = False
    timings_s: dict[str, float] = field(default_factory=dict)

    @classmethod
    def for_seed(cls, seed: int, **kwargs) -> RunContext:
        """A context whose generator is ``numpy.random.default_rng(seed)``."""
        return cls(rng=np.random.default_rng(seed), **kwargs)

    @contextmanager
    def timer(self, stage: str) -> Iterator[None]:
        """Measure the wall-clock time of a ``with`` block into ``timings_s[stage]`` [s]."""
        t0 = time.perf_counter()
        try:
            yield
        finally:
            self.timings_s[stage] = self.timings_s.get(stage, 0.0) + time.perf_counter() - t0

    def progress(
        self, iterable: Iterable[T] | None = None, desc: str = "", total: int | None = None
    ):
        """A tqdm progress bar on stderr for a long loop, shown with ``-v`` or ``progress_bars``.

        Use it around an iterable (``for x in ctx.progress(xs, "tracing"):``) or, for a loop
        you advance yourself, with ``total`` and no iterable::

            with ctx.progress(total=n_steps, desc="simulating") as bar:
                while ...:
                    bar.update(1)

        Args:
            iterable: what the loop iterates over (``None``: a manual bar of ``total`` steps).
            desc: the bar's label.
            total: the number of items (default: ``len(iterable)`` when it has one).

        Returns:
            A ``tqdm`` object: iterate over it, or call ``update(n)``; disabled (silent, no
            cost beyond the loop) unless ``verbose`` or ``progress_bars``.
        """
        from tqdm.auto import tqdm

        return tqdm(
            iterable,
            desc=desc,
            total=total,
            leave=False,
            disable=not (self.verbose or self.progress_bars),
            file=sys.stderr,
        )

    def log(self, message: str) -> None:
        """Print a progress message on stderr when ``-v`` was given."""
        if self.verbose:
            print(message, file=sys.stderr)


__all__ = ["RunContext"]
