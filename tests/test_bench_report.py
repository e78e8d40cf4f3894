"""benchmarks/_common.py: the report's stamp is taken before the report is written (so a
rewritten tracked report never marks the commit dirty), and both files carry the rows."""

from __future__ import annotations

import csv

from conftest import benchmark_module


def test_the_stamp_is_taken_before_any_file_is_written(tmp_path, monkeypatch):
    common = benchmark_module("_common")
    seen = []

    def stamp():
        seen.append(sorted(p.name for p in tmp_path.iterdir()))
        return {"hapex_commit": "abc123"}

    monkeypatch.setattr(common, "environment", stamp)
    md = common.write_report("demo", [{"a": 1, "b": 2.5}], title="Demo", out=tmp_path,
                             notes=["a note"])  # fmt: skip
    assert seen == [[]]
    assert list(csv.DictReader(open(tmp_path / "demo.csv"))) == [{"a": "1", "b": "2.5"}]
    text = md.read_text()
    assert "| hapex_commit | abc123 |" in text and "| 1 | 2.5 |" in text
    assert text.rstrip().endswith("- a note")


def test_comma_list_options_convert_check_and_refuse_in_one_line():
    import argparse

    import pytest

    common = benchmark_module("_common")
    assert common.comma_list(float)("0, 45,90,") == [0.0, 45.0, 90.0]
    assert common.comma_list(int)("3") == [3]
    assert common.comma_list(choices=("a", "b"))("b,a") == ["b", "a"]
    with pytest.raises(argparse.ArgumentTypeError, match="comma-separated int values"):
        common.comma_list(int)("1,x")
    with pytest.raises(argparse.ArgumentTypeError, match=r"unknown \['c'\]; known: a, b"):
        common.comma_list(choices=("a", "b"))("a,c")
