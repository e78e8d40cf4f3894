"""Whether NumPy's float64 ufuncs round as the C library does, and a re-run where they do.

The compiled kernels (numba) call the C library's ``exp``, ``atan2``, ``hypot``, ... The
NumPy reference paths call NumPy's ufuncs, which on CPUs with AVX-512 dispatch to SIMD
implementations that differ from the C library in the last bit (measured on an AMD EPYC
with AVX-512: ``exp`` on 930, ``arctan2`` on 1686 and ``tanh`` on 4950 of 20001 points of
[-10, 10]; ``sin``/``cos``/``sqrt`` agree). A test that claims "the compiled path computes
what the reference computes, to the bit" is then checked in a child process whose NumPy is
pinned to its baseline code (``NPY_DISABLE_CPU_FEATURES``: its dispatch targets off), where
both round alike. Nothing is loosened: the comparison stays exact.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from planner.results import numpy_dispatch_targets

#: set in the child process of :func:`rerun_with_baseline_numpy` (no second re-run)
RERUN_FLAG = "HAPEX_BASELINE_NUMPY_RERUN"

_UNARY = ((np.exp, math.exp), (np.log, math.log), (np.tanh, math.tanh), (np.tan, math.tan),
          (np.arctan, math.atan), (np.sin, math.sin), (np.cos, math.cos))  # fmt: skip
_BINARY = ((np.arctan2, math.atan2), (np.hypot, math.hypot))


def numpy_matches_libm(n: int = 4001) -> bool:
    """Whether NumPy's float64 ``exp, log, tanh, tan, arctan, sin, cos, arctan2, hypot``
    equal Python's ``math`` (the C library) to the bit on ``n`` points of [-10, 10]."""
    x = np.linspace(-10.0, 10.0, n)
    y = x[::-1] + 0.3
    pos = np.abs(x) + 1e-3
    for f, g in _UNARY:
        arg = pos if f is np.log else x
        if not np.array_equal(f(arg), np.array([g(v) for v in arg])):
            return False
    return all(
        np.array_equal(f(x, y), np.array([g(u, v) for u, v in zip(x, y, strict=True)]))
        for f, g in _BINARY
    )


def rerun_with_baseline_numpy(nodeid: str) -> subprocess.CompletedProcess:
    """Run the pytest test ``nodeid`` in a child process with NumPy's dispatch targets
    disabled; its output in ``stdout``."""
    env = dict(os.environ, NPY_DISABLE_CPU_FEATURES=" ".join(numpy_dispatch_targets()))
    env[RERUN_FLAG] = "1"
    root = Path(__file__).resolve().parents[1]
    cmd = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "no:xdist",
           "-p", "no:randomly", nodeid]  # fmt: skip
    return subprocess.run(cmd, cwd=root, env=env, capture_output=True, text=True, timeout=900)


def needs_baseline_rerun() -> bool:
    """Whether an exact comparison with NumPy reference paths must run in a child process:
    NumPy here rounds unlike the C library, and this is not that child already."""
    return not numpy_matches_libm() and not os.environ.get(RERUN_FLAG)
