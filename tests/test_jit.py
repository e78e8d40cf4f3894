"""planner.jit: every compiled kernel goes through it, and its cache follows every kernel."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from planner import jit

ROOT = Path(jit.__file__).resolve().parent.parent
USES_NJIT = re.compile(r"^\s*@njit\b|\bnjit\(", re.MULTILINE)


def _kernel_sources() -> set[str]:
    found = set()
    for package in ("planner", "robots"):
        for path in (ROOT / package).rglob("*.py"):
            if path != ROOT / "planner/jit.py" and USES_NJIT.search(path.read_text()):
                found.add(path.relative_to(ROOT).as_posix())
    return found


def test_kernel_files_are_every_module_with_a_compiled_function():
    """A kernel missing from KERNEL_FILES would not invalidate its callers' cache."""
    listed = set(jit.KERNEL_FILES) - {"planner/jit.py"}
    assert listed == _kernel_sources()
    assert all((ROOT / f).is_file() for f in jit.KERNEL_FILES)


def test_no_module_compiles_with_numba_directly():
    direct = [
        path.relative_to(ROOT).as_posix()
        for package in ("planner", "robots")
        for path in (ROOT / package).rglob("*.py")
        if re.search(r"from numba import .*\bnjit\b|numba\.njit\(", path.read_text())
        and path.name != "jit.py"
    ]
    assert direct == []


def test_the_fingerprint_follows_every_file(tmp_path):
    files = ("a.py", "sub/b.py")
    (tmp_path / "sub").mkdir()
    (tmp_path / "a.py").write_text("x = 1\n")
    (tmp_path / "sub/b.py").write_text("y = 2\n")
    first = jit.fingerprint(files, tmp_path)
    assert re.fullmatch(r"[0-9a-f]{16}", first)
    assert jit.fingerprint(files, tmp_path) == first  # stable
    (tmp_path / "sub/b.py").write_text("y = 3\n")  # a callee's file changes
    second = jit.fingerprint(files, tmp_path)
    assert second != first
    (tmp_path / "sub/b.py").write_text("y = 2\n")
    assert jit.fingerprint(files, tmp_path) == first
    assert jit.fingerprint(files[:1], tmp_path) != first  # the list itself counts


def test_a_cached_kernel_lives_under_the_fingerprint():
    from planner.sim.planar import step_kernel

    where = Path(step_kernel.full_step._cache._cache_path)  # numba's cache of the dispatcher
    assert jit.cache_dir() in where.parents
    assert jit.cache_dir().name == jit.fingerprint()


def test_njit_keeps_numba_semantics():
    @jit.njit
    def plain(x):
        return 2 * x

    @jit.njit(cache=False, fastmath=False)
    def with_options(x):
        return x + 1

    assert plain(3) == 6 and with_options(3) == 4
    with pytest.raises(TypeError, match="keywords"):
        jit.njit("float64(float64)")


def test_prune_keeps_the_current_and_recently_used_fingerprints(tmp_path):
    import os
    import time

    for name in ("current", "recent", "old"):
        (tmp_path / name).mkdir()
        (tmp_path / name / "k.nbi").write_text("")
    hours_ago = time.time() - 7200
    os.utime(tmp_path / "old", (hours_ago, hours_ago))
    os.utime(tmp_path / "current", (hours_ago, hours_ago))
    jit._prune(tmp_path, keep="current")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["current", "recent"]
