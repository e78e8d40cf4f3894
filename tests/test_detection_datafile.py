"""planner.detection.read_trace_file: users' CSV/NPZ logs; every bad file -> one line each."""

import numpy as np
import pytest

from planner.detection import read_trace_file
from planner.errors import ScenarioError


def _csv(tmp_path, text, name="log.csv"):
    p = tmp_path / name
    p.write_text(text)
    return p


def _rows(n=30, cols="t,cx,cy", f=lambda i: f"{i * 0.01},{i * 1e-3},0.0"):
    return cols + "\n" + "\n".join(f(i) for i in range(n)) + "\n"


def test_csv_with_units_and_comments(tmp_path):
    text = "# a comment\n" + _rows(
        cols="t_ms,cx_mm,cy_mm,px_mm,py_mm,nx,ny",
        f=lambda i: f"{i * 10},{i * 1.0},10.0,{i * 1.0},0.0,0.0,1.0",
    )
    d = read_trace_file(_csv(tmp_path, text))
    assert d.t[1] == pytest.approx(0.01)
    assert d.centers.shape == (30, 2) and d.centers[1, 0] == pytest.approx(1e-3)
    assert d.contacts[3, 0] == pytest.approx(3e-3) and np.allclose(d.normals[:, 1], 1.0)
    assert d.tip_radius is None


def test_csv_three_d(tmp_path):
    d = read_trace_file(
        _csv(tmp_path, _rows(cols="t,cx,cy,cz", f=lambda i: f"{i},{i * 1e-3},0,0.01"))
    )
    assert d.centers.shape == (30, 3) and d.contacts is None and d.normals is None


def _issues(path):
    with pytest.raises(ScenarioError) as exc:
        read_trace_file(path)
    return exc.value.issues


def test_missing_file_and_wrong_extension(tmp_path):
    (iss,) = _issues(tmp_path / "nope.csv")
    assert "file not found" in iss.message
    (iss,) = _issues(_csv(tmp_path, "x", name="log.txt"))
    assert "expected .csv or .npz" in iss.message


def test_missing_and_unknown_columns_reported_at_once(tmp_path):
    issues = _issues(_csv(tmp_path, _rows(cols="t,cx,speed", f=lambda i: f"{i},{i},1")))
    text = "\n".join(str(i) for i in issues)
    assert "speed" in text and "unknown column" in text
    assert "cy: required column is missing" in text
    issues = _issues(_csv(tmp_path, _rows(cols="t,cx,cy,px", f=lambda i: f"{i},{i},1,2")))
    assert "missing ['py']" in issues[0].message
    issues = _issues(_csv(tmp_path, _rows(cols="t_h,cx,cy", f=lambda i: f"{i},{i},1")))
    assert "unknown unit 'h'" in issues[0].message


def test_bad_values_name_their_line(tmp_path):
    rows = _rows().splitlines()
    rows[5] = "0.04,abc,0"  # file line 6
    (iss,) = _issues(_csv(tmp_path, "\n".join(rows)))
    assert iss.line == 6 and iss.path == "cx" and "not a number" in iss.message
    rows = _rows().splitlines()
    rows[7] = "0.06,nan,0"
    (iss,) = _issues(_csv(tmp_path, "\n".join(rows)))
    assert iss.line == 8 and "NaN" in iss.message
    assert iss.path == "cx"  # regression: the real column, not "c*[7]"
    rows = _rows(cols="t_ms,cx_mm,cy_mm").splitlines()
    rows[7] = "0.065,1,inf"
    (iss,) = _issues(_csv(tmp_path, "\n".join(rows)))
    assert iss.path == "cy_mm" and iss.line == 8
    rows = _rows().splitlines()
    rows[10] = "0.0,0.009,0"  # time goes back
    (iss,) = _issues(_csv(tmp_path, "\n".join(rows)))
    assert iss.line == 11 and "not strictly increasing" in iss.message
    # regression: plain numbers, not np.float64(...)
    assert "np.float64" not in iss.message and "(t=0 after 0.08)" in iss.message
    rows = _rows().splitlines()
    rows[3] = "0.02,0.002"
    (iss,) = _issues(_csv(tmp_path, "\n".join(rows)))
    assert iss.line == 4 and "expected 3 values" in iss.message


def test_too_few_samples_and_millimetres(tmp_path):
    (iss,) = _issues(_csv(tmp_path, _rows(n=5)))
    assert "too few samples" in iss.message
    (iss,) = _issues(_csv(tmp_path, _rows(f=lambda i: f"{i},{i * 10.0},0")))
    assert "millimetres" in iss.message
    (iss,) = _issues(
        _csv(tmp_path, _rows(cols="t,cx,cy,nx,ny", f=lambda i: f"{i},{i * 1e-3},0,0,2"))
    )
    assert "unit vectors" in iss.message
    (iss,) = _issues(_csv(tmp_path, "# only comments\n"))
    assert "no header" in iss.message


def test_npz(tmp_path):
    t = np.linspace(0, 1, 40)
    c = np.column_stack([t * 0.05, np.zeros(40)])
    p = tmp_path / "log.npz"
    np.savez(p, t=t, centers=c, normals=np.tile([0.0, 1.0], (40, 1)), tip_radius=0.01)
    d = read_trace_file(p)
    assert d.tip_radius == 0.01 and d.normals.shape == (40, 2)
    np.savez(p, t=t, centers=c[:30], extra=t)
    text = "\n".join(str(i) for i in _issues(p))
    assert "extra: unknown array" in text
    np.savez(p, t=t, centers=c[:30])
    assert "expected 40 rows" in _issues(p)[0].message
    np.savez(p, t=t, centers=np.zeros((40, 4)))
    assert "(N, 2) or (N, 3)" in _issues(p)[0].message
    p.write_bytes(b"not a zip")
    assert "not a readable .npz" in _issues(p)[0].message
