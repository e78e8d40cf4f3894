"""Extra files of a run directory (planner.results): text, bytes and writer callbacks,
written atomically (nothing half-written when a writer fails)."""

from __future__ import annotations

import json

import pytest

from planner.errors import HapexError
from planner.results import RunResult, write_run_directory

GIF = b"GIF89a\x01\x00\x01\x00\x00\x00\x00;\x00\xff\xfe"  # arbitrary bytes, not UTF-8


def _write(out, result):
    return write_run_directory(out, result, name="t", kind="k", seed=0,
                               resolved_scenario={"kind": "k"}, timings_s={})  # fmt: skip


def test_text_bytes_and_writer_files_are_written_and_listed(tmp_path):
    def writer(path):
        path.write_bytes(b"\x00\x01\x02")

    res = RunResult(files={"a.json": '{"x": 1}', "plots/animation.gif": GIF,
                           "data/big.bin": writer})  # fmt: skip
    out = _write(tmp_path / "run", res)
    assert (out / "a.json").read_text() == '{"x": 1}'
    assert (out / "plots" / "animation.gif").read_bytes() == GIF
    assert (out / "data" / "big.bin").read_bytes() == b"\x00\x01\x02"
    files = json.loads((out / "result.json").read_text())["files"]
    assert files["plots/animation.gif"] == "plots/animation.gif"
    assert files["data/big.bin"] == "data/big.bin"


def test_failing_writer_leaves_nothing_and_keeps_the_previous_run(tmp_path):
    out = tmp_path / "run"
    _write(out, RunResult(files={"keep.txt": "previous"}))

    def broken(path):
        path.write_bytes(b"half")
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError, match="disk full"):
        _write(out, RunResult(files={"a.gif": GIF, "b.bin": broken}))
    assert (out / "keep.txt").read_text() == "previous"
    assert not (out / "a.gif").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run"]  # no temporary left


def test_writer_that_creates_nothing_is_an_error(tmp_path):
    with pytest.raises(HapexError, match="did not create"):
        _write(tmp_path / "run", RunResult(files={"x.bin": lambda path: None}))
    assert not (tmp_path / "run").exists()


@pytest.mark.parametrize("name", ["../escape.txt", "/abs.txt", "result.json", ""])
def test_bad_file_names_are_refused(tmp_path, name):
    with pytest.raises(HapexError, match="not a valid extra file name"):
        _write(tmp_path / "run", RunResult(files={name: "x"}))
    assert not (tmp_path / "run").exists()
    assert not (tmp_path.parent / "escape.txt").exists()


def test_unknown_content_type_is_refused(tmp_path):
    with pytest.raises(HapexError, match="expected str, bytes or a writer"):
        _write(tmp_path / "run", RunResult(files={"x.bin": 3.5}))
    assert list(tmp_path.iterdir()) == []


def test_numpy_simd_names_the_dispatch_targets_in_use():
    """``versions.numpy_simd``: NumPy's SIMD targets this CPU runs ("baseline" with all
    of them disabled, which NumPy reads at import: a child process)."""
    import os
    import subprocess
    import sys

    from planner.results import numpy_dispatch_targets, numpy_simd

    here = numpy_simd()
    assert here == "baseline" or set(here.split()) <= set(numpy_dispatch_targets())
    env = dict(os.environ, NPY_DISABLE_CPU_FEATURES=" ".join(numpy_dispatch_targets()))
    code = "from planner.results import numpy_simd; print(numpy_simd())"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, check=True)  # fmt: skip
    assert out.stdout.strip() == "baseline"
