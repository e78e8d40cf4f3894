"""Running sweeps: run directories, the tidy table, the report, resuming (deleted run
directory, Ctrl-C, a worker killed mid-run on a LocalCluster), and joblib == Dask."""

from __future__ import annotations

import json
import os
import shutil
import signal

import pandas as pd
import pytest

from planner.errors import HapexError
from planner.sweep import SweepInterrupted, plan, run_sweep, sweep_from_dict

DETECT = {
    "kind": "detect",
    "tip_radius": 0.01,
    "algorithms": [3],
    "simulation": {
        "profile": {"type": "wire", "diameter": 0.00065, "length": 0.005},
        "spacing": 1.0e-4,
    },
}
GRASP = {
    "kind": "grasp_map",
    "object": {"type": "circle", "radius": 0.03},
    "resolution": 60,
    "gait_resolution": 24,
}
VOLATILE = ["wall_s", "host"]  # the only columns that may differ between two executions


def detect_study(**keys):
    return sweep_from_dict(
        {"name": "d", "base": DETECT, "grid": {"tip_radius": [0.005, 0.01]}, "seeds": 2, **keys}
    )


def grasp_study(**keys):
    grid = {"mu": [0.3, 1.0], "object.radius": [0.03, 0.05]}
    return sweep_from_dict({"name": "g", "base": GRASP, "grid": grid, **keys})


def stable(df: pd.DataFrame) -> pd.DataFrame:
    return df.drop(columns=VOLATILE).reset_index(drop=True)


def test_run_directories_table_and_report(tmp_path):
    study = detect_study()
    df = run_sweep(study, tmp_path, jobs=1)
    runs = plan(study)
    assert list(df["run_id"]) == [r.run_id for r in runs]  # expansion order, one row each
    assert list(df.columns[:4]) == ["run_id", "tip_radius", "seed", "status"]
    assert df.columns[-2:].tolist() == VOLATILE
    assert (df["status"] == "ok").all() and (df["wall_s"] > 0).all()
    for r, (_, row) in zip(runs, df.iterrows(), strict=True):
        rd = tmp_path / "runs" / r.run_id
        doc = json.loads((rd / "result.json").read_text())
        assert all((rd / rel).is_file() for rel in doc["files"].values())
        assert json.loads((rd / "sweep.json").read_text())["params"] == {
            "tip_radius": r.params["tip_radius"]
        }
        assert doc["seed"] == row["seed"] == r.seed
        assert row["alg3_f1"] == doc["metrics"]["alg3_f1"]
        assert row["metric.tip_radius"] == row["tip_radius"]  # a metric named like a parameter
    assert "alg3_macro" not in df.columns  # list-valued metrics stay in result.json
    back = pd.read_parquet(tmp_path / "results.parquet")
    pd.testing.assert_frame_equal(back, df)
    csv = pd.read_csv(tmp_path / "results.csv")
    assert list(csv["run_id"]) == list(df["run_id"]) and list(csv.columns) == list(df.columns)
    report = (tmp_path / "report.md").read_text()
    assert "![metrics vs tip_radius](report/metrics_vs_tip_radius.png)" in report
    assert (tmp_path / "report" / "metrics_vs_tip_radius.png").stat().st_size > 1000
    assert "No run failed." in report
    assert not [p for p in (tmp_path / "runs").iterdir() if p.name.startswith(".")]


def test_resume_reruns_only_missing_runs(tmp_path):
    study = detect_study()
    first = run_sweep(study, tmp_path, jobs=1, report=False)
    gone, broken = first["run_id"][1], first["run_id"][2]
    shutil.rmtree(tmp_path / "runs" / gone)
    (tmp_path / "runs" / broken / "result.json").unlink()  # an incomplete run directory
    rerun = []
    second = run_sweep(
        study, tmp_path, jobs=1, report=False, on_result=lambda f: rerun.append(f.run_id)
    )
    assert sorted(rerun) == sorted([gone, broken])
    pd.testing.assert_frame_equal(stable(second), stable(first))
    assert second["run_id"].is_unique
    rerun.clear()
    run_sweep(study, tmp_path, jobs=1, report=False, on_result=lambda f: rerun.append(f.run_id))
    assert rerun == []


def test_failed_runs_are_results_and_retried_on_request(tmp_path):
    study = grasp_study()
    df = run_sweep(study, tmp_path, jobs=1)
    failed = df[df["status"] == "failed"]
    assert set(failed["mu"]) == {0.3} and set(df[df["status"] == "ok"]["mu"]) == {1.0}
    assert failed["reason"].str.startswith("no grasp gait").all()
    report = (tmp_path / "report.md").read_text()
    assert "## Success maps" in report and "success_mu__object_radius.png" in report
    assert all(f"`{rid}`" in report for rid in failed["run_id"])
    rerun = []
    run_sweep(study, tmp_path, jobs=1, report=False, on_result=lambda f: rerun.append(f.run_id))
    assert rerun == []
    run_sweep(
        study,
        tmp_path,
        jobs=1,
        report=False,
        retry_failed=True,
        on_result=lambda f: rerun.append(f.run_id),
    )
    assert sorted(rerun) == sorted(failed["run_id"])


def test_a_run_that_crashes_is_a_failed_run(tmp_path, monkeypatch):
    import planner.runner

    real = planner.runner.run_config

    def flaky(config, **kw):
        if config.tip_radius == 0.005:
            raise RuntimeError("boom")
        return real(config, **kw)

    monkeypatch.setattr(planner.runner, "run_config", flaky)
    df = run_sweep(detect_study(), tmp_path, jobs=1, report=False)  # jobs=1 runs in this process
    bad = df[df["tip_radius"] == 0.005]
    assert (bad["status"] == "failed").all() and (bad["reason"] == "RuntimeError: boom").all()
    assert (df[df["tip_radius"] == 0.01]["status"] == "ok").all()
    events = json.loads((tmp_path / "runs" / bad["run_id"].iloc[0] / "result.json").read_text())
    assert "Traceback" in events["events"][0]["message"]


def test_ctrl_c_keeps_complete_runs_and_resumes(tmp_path):
    study = detect_study()
    seen = []

    def stop_after_two(fin):
        seen.append(fin.run_id)
        if len(seen) == 2:
            raise KeyboardInterrupt

    with pytest.raises(SweepInterrupted) as exc:
        run_sweep(study, tmp_path, jobs=1, report=False, on_result=stop_after_two)
    assert (exc.value.done, exc.value.total) == (2, 4)
    partial = pd.read_parquet(tmp_path / "results.parquet")
    assert sorted(partial["run_id"]) == sorted(seen)
    more = []
    df = run_sweep(study, tmp_path, jobs=1, report=False, on_result=lambda f: more.append(f.run_id))
    assert len(more) == 2 and not set(more) & set(seen)
    assert len(df) == 4 and df["run_id"].is_unique


def test_output_folder_of_something_else_is_refused(tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(HapexError, match="not a hapex sweep"):
        run_sweep(detect_study(), tmp_path, jobs=1)
    run_sweep(detect_study(seeds=1), tmp_path / "s", jobs=1, report=False)
    with pytest.raises(HapexError, match="holds the sweep 'd', not 'g'"):
        run_sweep(grasp_study(), tmp_path / "s", jobs=1)


def test_joblib_and_dask_give_the_same_results(tmp_path):
    pytest.importorskip("distributed")
    study = detect_study()
    a = run_sweep(study, tmp_path / "joblib", backend="joblib", jobs=2, report=False)
    b = run_sweep(
        study, tmp_path / "dask", backend="dask", dask_workers=2, processes=False, report=False
    )
    pd.testing.assert_frame_equal(stable(a), stable(b))
    for rid in a["run_id"]:
        ra = json.loads((tmp_path / "joblib" / "runs" / rid / "result.json").read_text())
        rb = json.loads((tmp_path / "dask" / "runs" / rid / "result.json").read_text())
        assert ra["metrics"] == rb["metrics"]


def test_worker_killed_mid_run_on_a_local_cluster(tmp_path):
    pytest.importorskip("distributed")
    from planner.sweep.backends import dask_client

    base = {**GRASP, "resolution": 180, "gait_resolution": 48}
    study = sweep_from_dict(
        {"name": "k", "base": base, "grid": {"mu": [0.8, 1.0, 1.2, 1.5]}, "seeds": [0, 1]}
    )
    killed = []
    with dask_client(workers=2, processes=True) as client:

        def kill_a_busy_worker(fin):
            if killed:
                return
            busy = [w for w, tasks in client.processing().items() if tasks]
            if busy:
                pid = client.run(os.getpid, workers=busy[:1])[busy[0]]
                os.kill(pid, signal.SIGKILL)
                killed.append(busy[0])

        df = run_sweep(study, tmp_path, backend="dask", client=client, on_result=kill_a_busy_worker)
    assert killed, "no worker was busy when the first run came back"
    runs = plan(study)
    assert sorted(df["run_id"]) == sorted(r.run_id for r in runs)  # complete, no duplicates
    assert (df["status"] == "ok").all(), df["reason"].tolist()
    assert len(list((tmp_path / "runs").iterdir())) == len(runs)
