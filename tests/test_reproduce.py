"""hapex reproduce: the claims registry, verdicts from numbers, the report and the command."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from planner.errors import InvalidParameter
from planner.reproduce import (
    Claim,
    ClaimContext,
    Evidence,
    NotImplementedClaim,
    Number,
    Verdict,
    all_claims,
    exit_code,
    run_claim,
    select,
    write_report,
)
from planner.reproduce.claim import verdict_from
from planner.reproduce.report import PEER_REPORTS, peer_reports

#: The thesis results the issue names; each must have a claim.
REQUIRED = {
    "appA.sphere",
    "appA.bump",
    "appA.montana",
    "fig3.1",
    "fig3.3-3.4",
    "fig3.7",
    "table3.1",
    "fig3.9",
    "sec3.4.2",
    "tableB.1",
    "appB.3",
    "fig2.4",
    "sec2.3.1",
    "fig2.10",
    "fig2.12",
    "fig2.14",
    "appC.3gm",
    "appC.owts",
    "fig4.7",
    "fig4.8",
    "fig4.11",
    "fig4.12",
    "fig4.13",
    "fig4.14-4.15",
}


def test_registry_covers_the_thesis():
    claims = all_claims()
    ids = [c.id for c in claims]
    assert len(ids) == len(set(ids))
    assert REQUIRED <= set(ids)
    for c in claims:
        assert c.reference and c.statement.endswith(".") and c.tested_by


def test_select_rejects_unknown_ids():
    assert [c.id for c in select(["fig3.7"])] == ["fig3.7"]
    with pytest.raises(InvalidParameter, match="unknown claim id.*nope"):
        select(["nope"])


def test_verdict_is_computed_from_numbers():
    ok, bad = Number("a", 1.0, 1.0, True), Number("b", 2.0, 1.0, False)
    assert verdict_from([ok, ok])[0] is Verdict.REPRODUCED
    assert verdict_from([ok, bad])[0] is Verdict.PARTLY
    assert verdict_from([bad])[0] is Verdict.DIFFERS
    assert verdict_from([])[0] is Verdict.DIFFERS


def _claim(check) -> Claim:
    return Claim("test.claim", "nowhere", "A test claim.", ("tests",), check)


def test_broken_check_is_an_error_not_a_crash(tmp_path):
    def broken(ctx):
        raise ZeroDivisionError("boom")

    r = run_claim(_claim(broken), ClaimContext(quick=True))
    assert r.evidence.verdict is Verdict.ERROR
    assert "ZeroDivisionError: boom" in r.evidence.explanation and "Traceback" in r.error
    assert exit_code([r]) == 1
    write_report([r], tmp_path / "report.md", quick=True)
    assert "boom" in (tmp_path / "report.md").read_text()


def test_peer_reports_find_the_files_the_benchmarks_write(tmp_path):
    results = tmp_path / "benchmarks" / "results"
    results.mkdir(parents=True)
    (results / "sim.md").write_text("# hapex vs MuJoCo\n")
    (results / "sim_breakdown.md").write_text("# hapex alone\n")
    (results / "bench_grasp.md").write_text("# grasp\n")
    found = {stem: what for stem, what, _ in peer_reports(tmp_path)}
    assert set(found) == {"sim", "bench_grasp"}
    assert "MuJoCo" in found["sim"]


def test_every_peer_report_is_committed():
    """Each entry of PEER_REPORTS names a file some benchmark script writes (``bench_sim.py``
    writes ``sim.md``, not ``bench_sim*.md``): none silently missing from the report."""
    results = Path(__file__).resolve().parents[1] / "benchmarks" / "results"
    if not results.is_dir():
        pytest.skip("not a source tree")
    for pattern in PEER_REPORTS:
        assert list(results.glob(pattern)), f"no benchmarks/results/{pattern}"


def test_report_carries_the_simulator_vs_mujoco_comparison(tmp_path):
    if not peer_reports():
        pytest.skip("not a source tree")
    r = run_claim(_claim(lambda ctx: Evidence(Verdict.REPRODUCED, [], "")), ClaimContext())
    write_report([r], tmp_path / "report.md", quick=True)
    peers = (tmp_path / "report.md").read_text().split("## Peer comparisons")[1]
    assert "### sim: simulator vs MuJoCo on the same scenes" in peers
    assert "Contact simulator: hapex vs MuJoCo" in peers


def test_missing_capability_is_not_implemented():
    def missing(ctx):
        raise NotImplementedClaim("planner.x.y is not implemented yet")

    r = run_claim(_claim(missing), ClaimContext())
    assert r.evidence.verdict is Verdict.NOT_IMPLEMENTED
    assert exit_code([r]) == 0


def test_unexplained_difference_fails_the_command():
    def differs(ctx):
        v, nums = verdict_from([Number("x", 2.0, 1.0, False)])
        return Evidence(v, nums, "")

    def explained(ctx):
        v, nums = verdict_from([Number("x", 2.0, 1.0, False)])
        return Evidence(v, nums, "the thesis' eq. 9.9 is an OCR error: derived value 2")

    assert exit_code([run_claim(_claim(differs), ClaimContext())]) == 1
    assert exit_code([run_claim(_claim(explained), ClaimContext())]) == 0


def test_reproduce_command_quick(cli, tmp_path):
    out = tmp_path / "repro"
    proc = cli("reproduce", "--quick", "--jobs", "2", "--out", str(out))
    assert proc.returncode == 0, proc.stderr + proc.stdout
    doc = json.loads((out / "claims.json").read_text())
    verdicts = {c["id"]: c["verdict"] for c in doc["claims"]}
    assert REQUIRED <= set(verdicts)
    assert "error" not in verdicts.values(), verdicts
    # the static half of the thesis is reproduced, each claim with its numbers
    for cid in ("fig3.7", "table3.1", "appA.sphere", "fig2.4", "fig4.14-4.15"):
        assert verdicts[cid] == "reproduced", cid
    # the thesis figure's description travels with the evidence, as in report.md
    by_id = {c["id"]: c for c in doc["claims"]}
    assert by_id["fig4.12"]["thesis_figure"] and by_id["fig3.7"]["figure"]
    report = (out / "report.md").read_text()
    assert "| claim | thesis reference | verdict |" in report
    assert (out / "figures" / "fig3.7.png").is_file()
    assert not list(tmp_path.glob(".repro.tmp-*"))


def test_reproduce_bad_options(cli, tmp_path):
    proc = cli("reproduce", "--only", "nope", "--out", str(tmp_path / "r"))
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "unknown claim id" in proc.stderr
    assert not (tmp_path / "r").exists()
    foreign = tmp_path / "foreign"
    foreign.mkdir()
    (foreign / "keep.txt").write_text("mine")
    proc = cli("reproduce", "--quick", "--only", "fig3.7", "--out", str(foreign))
    assert proc.returncode == 2 and "not a hapex reproduce folder" in proc.stderr
    assert (foreign / "keep.txt").read_text() == "mine"


@pytest.mark.parametrize("below", ["r", "r/deeper"])
def test_reproduce_out_below_a_regular_file_exits_2_before_running(cli, tmp_path, below):
    (tmp_path / "afile").write_text("keep me")
    out = tmp_path / "afile" / below
    proc = cli("reproduce", "--quick", "--only", "fig3.7", "--out", str(out))
    assert proc.returncode == 2 and "Traceback" not in proc.stderr, proc.stderr
    (line,) = proc.stderr.strip().splitlines()
    assert line == f"--out: {out}: {tmp_path / 'afile'} is a file, not a directory"
    assert proc.stdout == ""  # no claim ran
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile"]
