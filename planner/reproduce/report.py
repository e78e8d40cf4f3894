"""The reproduction report: ``report.md`` (summary table, one section per claim, peer
comparisons) and ``claims.json`` (the same evidence, machine-readable)."""

from __future__ import annotations

import json
import platform
from collections import Counter
from datetime import datetime, timezone
from pathlib import Path

from planner.exit_codes import EXIT_FAILED, EXIT_OK
from planner.reproduce.claim import Verdict
from planner.reproduce.execute import ClaimResult

__all__ = ["exit_code", "peer_reports", "write_claims_json", "write_report"]

#: Benchmark reports whose peer comparisons the report carries: a glob over the file names the
#: ``benchmarks/bench_*.py`` scripts write into ``benchmarks/results/`` -> what they compare.
#: ``bench_sim.py`` writes ``sim.md`` (and ``sim_breakdown.md``, hapex alone: not a peer).
PEER_REPORTS = {
    "bench_grasp*.md": "grasp map vs per-cell LP; QP backends",
    "bench_control*.md": "control step: code-generated vs plain numpy/qpsolvers",
    "sim.md": "simulator vs MuJoCo on the same scenes",
    "bench_explore*.md": "3GM explorer: control step and accuracy",
    "bench_gait*.md": "gait NLP and the §2.3.1 batch",
}


def exit_code(results: list[ClaimResult]) -> int:
    """0 when every claim is reproduced, explained or not implemented; 1 when any errored
    or differs without an explanation."""
    for r in results:
        v = r.evidence.verdict
        if v is Verdict.ERROR:
            return EXIT_FAILED
        if v in (Verdict.PARTLY, Verdict.DIFFERS) and not r.evidence.explanation.strip():
            return EXIT_FAILED
    return EXIT_OK


def _versions() -> dict[str, str]:
    from importlib.metadata import PackageNotFoundError, version

    out = {}
    for pkg in ("hapex", "numpy", "scipy", "pin", "casadi", "shapely", "daqp", "osqp", "mujoco"):
        try:
            out[pkg] = version(pkg)
        except PackageNotFoundError:
            out[pkg] = "not installed"
    return out


def write_claims_json(results: list[ClaimResult], path: Path, *, quick: bool) -> None:
    """Write the evidence of every claim to ``path`` (JSON)."""
    doc = {
        "schema": 1,
        "created": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "quick": quick,
        "versions": _versions(),
        "summary": dict(Counter(r.evidence.verdict.value for r in results)),
        "claims": [
            {
                "id": r.claim.id,
                "reference": r.claim.reference,
                "statement": r.claim.statement,
                "tested_by": list(r.claim.tested_by),
                "verdict": r.evidence.verdict.value,
                "explanation": r.evidence.explanation,
                "numbers": [n.as_dict() for n in r.evidence.numbers],
                "figure": r.evidence.figure,
                "thesis_figure": r.claim.thesis_figure,
                "seconds": round(r.seconds, 3),
                "error": r.error,
            }
            for r in results
        ],
    }
    path.write_text(json.dumps(doc, indent=2) + "\n")


def peer_reports(root: Path | None = None) -> list[tuple[str, str, str]]:
    """``(stem, what, markdown)`` of each committed benchmark report found under
    ``root/benchmarks/results`` (the source tree; empty when hapex runs from a wheel)."""
    if root is None:
        root = Path(__file__).resolve().parents[2]
    folder = root / "benchmarks" / "results"
    found = []
    for pattern, what in PEER_REPORTS.items():
        for f in sorted(folder.glob(pattern)):
            found.append((f.stem, what, f.read_text()))
    return found


def _cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def _section(r: ClaimResult) -> list[str]:
    c, e = r.claim, r.evidence
    lines = [f"### {c.id} — {c.reference}", "", f"**Claim.** {c.statement}", ""]
    lines += [f"**Verdict: {e.verdict.value}.** {e.explanation}".rstrip(), ""]
    if e.numbers:
        lines += ["| quantity | hapex | thesis | rule | ok |", "|---|---|---|---|---|"]
        for n in e.numbers:
            d = n.as_dict()
            lines.append(
                f"| {_cell(n.name)} | {d['hapex']} | {'-' if d['thesis'] is None else d['thesis']}"
                f" | {_cell(n.tolerance)} | {'yes' if n.ok else 'no'} |"
            )
        lines.append("")
    if e.figure:
        lines += [f"![{c.id}]({e.figure})", ""]
    if c.thesis_figure:
        lines += [f"*The thesis' figure:* {c.thesis_figure}", ""]
    lines += [f"Tested by: {', '.join(f'`{t}`' for t in c.tested_by)}.", ""]
    if r.error:
        lines += ["```", r.error.strip()[-2000:], "```", ""]
    return lines


def write_report(results: list[ClaimResult], path: Path, *, quick: bool) -> None:
    """Write ``report.md``: summary table, one section per claim, peer comparisons."""
    counts = Counter(r.evidence.verdict.value for r in results)
    versions = _versions()
    lines = [
        "# hapex reproduction of *Haptic Exploration of Unknown Objects*",
        "",
        f"Created {datetime.now(timezone.utc):%Y-%m-%d %H:%M} UTC on {platform.node()} "
        f"({platform.processor() or platform.machine()}), Python {platform.python_version()}; "
        + ", ".join(f"{k} {v}" for k, v in versions.items())
        + (". **Quick mode** (short checks)." if quick else "."),
        "",
        "Summary: " + ", ".join(f"{n} {v}" for v, n in sorted(counts.items())) + ".",
        "",
        "| claim | thesis reference | verdict | key number (hapex vs thesis) |",
        "|---|---|---|---|",
    ]
    for r in results:
        lines.append(
            f"| [{r.claim.id}](#{_anchor(r)}) | {_cell(r.claim.reference)} | "
            f"{r.evidence.verdict.value} | {_cell(r.evidence.key_number)} |"
        )
    lines += ["", "## Claims", ""]
    for r in results:
        lines += _section(r)
    lines += ["## Peer comparisons (from `benchmarks/results/`)", ""]
    peers = peer_reports()
    if not peers:
        lines += ["No committed benchmark report found (run hapex from its source tree).", ""]
    for stem, what, text in peers:
        body = "\n".join(("###" + ln[1:] if ln.startswith("#") else ln) for ln in text.splitlines())
        lines += [f"### {stem}: {what}", "", body, ""]
    path.write_text("\n".join(lines) + "\n")


def _anchor(r: ClaimResult) -> str:
    text = f"{r.claim.id} — {r.claim.reference}".lower()
    keep = [ch if ch.isalnum() or ch in "-_ " else "" for ch in text]
    return "".join(keep).replace(" ", "-")
