"""Every bundled scenario validates, and runs (``--quick``) through the CLI."""

from __future__ import annotations

import json

import pytest
from conftest import ROOT, run_cli

SCENARIOS = sorted((ROOT / "scenarios").glob("*.yaml"))


def test_there_are_bundled_scenarios():
    assert len(SCENARIOS) >= 4


def test_all_validate():
    proc = run_cli("validate", *map(str, SCENARIOS))
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.count(": ok (") == len(SCENARIOS)


@pytest.mark.parametrize("path", SCENARIOS, ids=[p.stem for p in SCENARIOS])
def test_runs_quick(path, tmp_path):
    out = tmp_path / "run"
    proc = run_cli("run", str(path), "--quick", "--out", str(out))
    doc = json.loads((out / "result.json").read_text())
    expected = 1 if doc["status"] == "failed" else 0
    assert proc.returncode == expected, proc.stderr
    assert "Traceback" not in proc.stderr
    if doc["status"] == "failed":
        # only scenarios that say so may fail (e.g. an object with no grasp gait)
        assert doc["reason"], doc
        text = path.read_text().lower()
        assert "fail" in text or "no gait" in text or "exit status 1" in text, path
    for rel in doc["files"].values():
        assert (out / rel).is_file(), rel
    assert doc["metrics"], "a run reports metrics"
