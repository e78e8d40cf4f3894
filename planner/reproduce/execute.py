"""Run claims: each check in isolation, a raising check becomes an ``error`` verdict.

Claims run serially or, with ``jobs > 1``, in worker processes through joblib (the same
machinery as ``hapex sweep``'s local backend). A check that raises never crashes the command:
its claim shows as ``error`` with the exception in the report.
"""

from __future__ import annotations

import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from planner.reproduce.claim import Claim, ClaimContext, Evidence, NotImplementedClaim, Verdict
from planner.reproduce.registry import select

__all__ = ["ClaimResult", "run_claim", "run_claims"]


@dataclass(frozen=True)
class ClaimResult:
    """A claim with its evidence, the wall time of its check [s] and any error text."""

    claim: Claim
    evidence: Evidence
    seconds: float
    error: str = ""


def run_claim(claim: Claim, ctx: ClaimContext) -> ClaimResult:
    """Run one claim's check; exceptions become ``not implemented`` or ``error`` verdicts."""
    t0 = time.perf_counter()
    try:
        evidence = claim.check(ctx)
        error = ""
    except NotImplementedClaim as exc:
        evidence = Evidence(Verdict.NOT_IMPLEMENTED, explanation=str(exc))
        error = ""
    except Exception as exc:  # a broken check is reported, never a crash of the command
        evidence = Evidence(Verdict.ERROR, explanation=f"{type(exc).__name__}: {exc}")
        error = traceback.format_exc()
    return ClaimResult(claim, evidence, time.perf_counter() - t0, error)


def _run_by_id(claim_id: str, ctx: ClaimContext) -> ClaimResult:
    import matplotlib

    matplotlib.use("Agg")
    (claim,) = select([claim_id])
    return run_claim(claim, ctx)


def run_claims(
    ids: list[str] | None = None,
    *,
    quick: bool = False,
    figures: Path | None = None,
    jobs: int = 1,
    seed: int = 0,
    progress: Callable[[ClaimResult], None] | None = None,
) -> list[ClaimResult]:
    """Run the selected claims (all when ``ids`` is empty) and return their results in order.

    Args:
        ids: claim ids (see ``hapex reproduce --only``).
        quick: short checks (the test suite's mode).
        figures: folder for the figures (``None``: no figures).
        jobs: worker processes (1: serial, in this process).
        seed: seed of every check's random generator.
        progress: called with each result as it completes.
    """
    claims = select(ids)
    ctx = ClaimContext(quick=quick, figures=figures, seed=seed)
    if jobs <= 1 or len(claims) <= 1:
        results = []
        for c in claims:
            r = run_claim(c, ctx)
            if progress:
                progress(r)
            results.append(r)
        return results
    from joblib import Parallel, delayed

    out = Parallel(n_jobs=jobs, return_as="generator")(
        delayed(_run_by_id)(c.id, ctx) for c in claims
    )
    results = []
    for r in out:
        if progress:
            progress(r)
        results.append(r)
    return results
