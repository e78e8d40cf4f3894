"""``hapex reproduce``: every claim of the thesis beside hapex's result, with the evidence.

A claims registry (:func:`all_claims`), each claim with its thesis reference, a statement, the
scenarios or library calls that test it and a check computing the verdict from numbers
(``reproduced``, ``partly``, ``differs``, ``not implemented``, or ``error`` for a broken
check); :func:`run_claims` runs them (in parallel with ``jobs > 1``) and :func:`write_report`
writes ``report.md`` and :func:`write_claims_json` ``claims.json``.

This is a spine-level package (like ``planner.sweep``): it may run scenarios; no library
package imports it.
"""

from planner.reproduce.claim import (
    Claim,
    ClaimContext,
    Evidence,
    NotImplementedClaim,
    Number,
    Verdict,
)
from planner.reproduce.execute import ClaimResult, run_claim, run_claims
from planner.reproduce.registry import all_claims, select
from planner.reproduce.report import exit_code, write_claims_json, write_report

__all__ = [
    "Claim",
    "ClaimContext",
    "ClaimResult",
    "Evidence",
    "NotImplementedClaim",
    "Number",
    "Verdict",
    "all_claims",
    "exit_code",
    "run_claim",
    "run_claims",
    "select",
    "write_claims_json",
    "write_report",
]
