"""Compiled kernels: numba's ``njit`` with an on-disk cache keyed by EVERY kernel's source.

numba caches a ``cache=True`` function under a stamp of its own source file only (numba
0.68: the sha256 of the file that defines it). A kernel that calls a kernel of another file
keeps the machine code it was compiled with, callee included, after that other file
changes. Found on 2026-11-25: after ``geometry_kernel.closest`` got its corner-sign fix,
``step_kernel.full_step`` (which calls it) went on running the old sign rule in every
checkout that had run the simulator before, so the compiled step and the Python step
disagreed on the same state (a random polygon thrown against another gained 2.8 J in one
step) until ``__pycache__`` was removed. A fresh clone never showed it; a ``git pull`` or an
edit did, silently.

:func:`njit` is numba's decorator, but a ``cache=True`` function is cached in
``<root>/<fingerprint>/``, the fingerprint hashing numba's version and the content of every
file of :data:`KERNEL_FILES` (the modules that define compiled functions): any change to any
kernel recompiles all of them once (about a minute on the reference machine), and an
unchanged checkout keeps its cache. ``root`` is ``$NUMBA_CACHE_DIR/hapex`` when that is set,
else ``planner/__pycache__/numba`` when writable (older fingerprints there, idle for an hour,
are removed when a new one is created), else ``~/.cache/hapex/numba``.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import time
from functools import lru_cache
from pathlib import Path

import numba
from numba import njit as _numba_njit

__all__ = ["KERNEL_FILES", "cache_dir", "fingerprint", "njit"]

#: Every module that defines a compiled function, relative to the directory holding the
#: ``planner`` and ``robots`` packages (tests/test_jit.py checks the list is complete).
KERNEL_FILES = (
    "planner/control/grasp_stability.py",
    "planner/control/hybrid_kernel.py",
    "planner/exploration/planar/controller_kernel.py",
    "planner/exploration/planar/gait_loop_kernel.py",
    "planner/exploration/planar/outline_pose_kernel.py",
    "planner/exploration/planar/pivot_reach_kernel.py",
    "planner/exploration/planar/sensing.py",
    "planner/exploration/surface/runtime.py",
    "planner/jit.py",
    "planner/sim/lcp.py",
    "planner/sim/planar/geometry_kernel.py",
    "planner/sim/planar/presets.py",
    "planner/sim/planar/run_kernel.py",
    "planner/sim/planar/sensing.py",
    "planner/sim/planar/step_kernel.py",
    "planner/sim/spatial/cone_kernel.py",
    "planner/sim/spatial/kernel.py",
    "planner/sim/spatial/recording.py",
    "planner/sim/spatial/step_kernel.py",
    "planner/sim/spatial/tip_controller.py",
    "robots/sensors/tactile_kernel.py",
)

#: the directory holding the ``planner`` and ``robots`` packages
SOURCE_ROOT = Path(__file__).resolve().parent.parent


def fingerprint(files=KERNEL_FILES, root: Path = SOURCE_ROOT) -> str:
    """16 hex digits of the sha256 of numba's version and the content of ``files`` (paths
    relative to ``root``; a missing file counts as empty)."""
    h = hashlib.sha256(numba.__version__.encode())
    for name in files:
        h.update(name.encode() + b"\0")
        path = root / name
        h.update(path.read_bytes() if path.is_file() else b"")
        h.update(b"\0")
    return h.hexdigest()[:16]


def _writable(path: Path) -> bool:
    try:
        path.mkdir(parents=True, exist_ok=True)
        probe = path / f".probe-{os.getpid()}"
        probe.touch()
        probe.unlink()
        return True
    except OSError:
        return False


def _prune(local: Path, keep: str, idle: float = 3600.0) -> None:
    """Remove this checkout's earlier fingerprints, those untouched for ``idle`` [s] (a
    process still running an older checkout may yet write to its own)."""
    now = time.time()
    for old in local.iterdir():
        try:
            stale = old.is_dir() and old.name != keep and now - old.stat().st_mtime > idle
        except OSError:
            continue
        if stale:
            shutil.rmtree(old, ignore_errors=True)


@lru_cache(maxsize=1)
def cache_dir() -> Path:
    """The directory this checkout's compiled kernels are cached in (see the module doc)."""
    fp = fingerprint()
    user = os.environ.get("NUMBA_CACHE_DIR")
    if user:
        return Path(user) / "hapex" / fp
    local = SOURCE_ROOT / "planner" / "__pycache__" / "numba"
    if _writable(local):
        target = local / fp
        if not target.exists():
            _prune(local, keep=fp)
        return target
    return Path.home() / ".cache" / "hapex" / "numba" / fp


def _compile(fn, options: dict):
    if not options.get("cache"):
        return _numba_njit(**options)(fn)
    saved = numba.config.CACHE_DIR
    numba.config.CACHE_DIR = str(cache_dir())  # read when the cache locator is made
    try:
        return _numba_njit(**options)(fn)
    finally:
        numba.config.CACHE_DIR = saved


def njit(*args, **options):
    """``numba.njit`` (same arguments); with ``cache=True`` cached under :func:`cache_dir`."""
    if len(args) == 1 and callable(args[0]):
        return _compile(args[0], options)
    if args:
        raise TypeError("njit: give options as keywords (signatures are not used here)")
    return lambda fn: _compile(fn, options)
