"""Scenario kind ``explore``: bad input is reported at the key it concerns, once (exit 2)."""

from __future__ import annotations

import re

import pytest
from conftest import run_cli

HEAD = "name: x\nkind: explore\nplate:\n  features: []\n"
LINE = re.compile(r"^(?P<file>[^:]+):(?P<line>\d+): (?P<key>[A-Za-z0-9_.\[\]()]+): (?P<msg>.+)$")


def _the_one_error(f):
    """``validate`` of ``f``: exit 2 and one stderr line ``FILE:LINE: key: message``, matched."""
    proc = run_cli("validate", str(f))
    assert proc.returncode == 2, proc.stderr
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert len(lines) == 1, proc.stderr
    m = LINE.match(lines[0])
    assert m, lines[0]
    return m, lines


@pytest.mark.parametrize(
    ("extra", "key", "start"),
    [
        # cross-key rules (model validator) are located at a key present in the file
        ("strategy: bug2\n", "strategy", "bug2 needs a goal"),
        ("strategy: random_walk\nidentify: raster\n", "identify", "raster pattern-matches"),
        # field rules do not repeat their key
        ("region: [[-0.25, 0.25], [-0.02, 0.02]]\n", "region", "the point (-250.0, -20.0) mm"),
        ("strategy: bug2\ngoal: [0.45, 0.0]\n", "goal", "the point (450.0, 0.0) mm"),
        # audit finding 7: these ran into a numpy MemoryError traceback (exit 1)
        ("line_spacing: 1.0e-12\n", "line_spacing", "expected >= 0.05 r_f = 0.40 mm"),
        (
            "tip_radius: 0.012\nline_spacing: 5.0e-4\n",
            "line_spacing",
            "expected >= 0.05 r_f = 0.60",
        ),
        ("duration: 1.0e7\n", "duration", "expected at most 600 s (the recorder"),
    ],
)
def test_error_is_one_line_at_its_key(tmp_path, extra, key, start):
    f = tmp_path / "x.yaml"
    f.write_text(HEAD + extra)
    m, lines = _the_one_error(f)
    assert m["file"].endswith("x.yaml") and m["key"] == key, lines[0]
    assert m["msg"].startswith(start), lines[0]
    assert not m["msg"].startswith(f"{key}:"), lines[0]
    line = int(m["line"])
    assert f.read_text().splitlines()[line - 1].startswith(f"{key}:")


@pytest.mark.parametrize(
    ("feature", "key", "start"),
    [
        # audit finding 8: these were reported at region's line as "region: path: ..."
        (
            "    - kind: ridge\n      height: 0.002\n      path:\n        - [0.0, 0.0]\n"
            "        - [0.0, 0.0]\n",
            "path",
            "consecutive points must differ",
        ),
        (
            "    - kind: wire\n      height: 0.002\n      rounding: 0.0001\n",
            "rounding",
            "expected >= the wire radius 0.001 m",
        ),
    ],
)
def test_plate_feature_error_is_at_its_key(tmp_path, feature, key, start):
    f = tmp_path / "x.yaml"
    text = (
        "name: x\nkind: explore\nplate:\n  features:\n    - kind: bump\n      height: 0.002\n"
        + feature
        + "region: [[-0.02, 0.02], [-0.02, 0.02]]\n"
    )
    f.write_text(text)
    m, lines = _the_one_error(f)
    assert m["key"] == f"plate.features[1].{key}", lines[0]
    assert m["msg"].startswith(start), lines[0]
    assert text.splitlines()[int(m["line"]) - 1].strip().startswith(f"{key}:")
