"""The claims registry: every claim of the thesis hapex checks, in report order.

Claims are declared in the ``claims_*`` modules with the :func:`claim` decorator; importing
:func:`all_claims` loads them. Identifiers are unique.
"""

from __future__ import annotations

from collections.abc import Callable
from importlib import import_module

from planner.errors import InvalidParameter
from planner.reproduce.claim import Claim, ClaimContext, Evidence

__all__ = ["all_claims", "claim", "select"]

#: Modules holding claims, in the order of the thesis.
CLAIM_MODULES = (
    "planner.reproduce.claims_ch2",
    "planner.reproduce.claims_ch3",
    "planner.reproduce.claims_appendix",
    "planner.reproduce.claims_ch4",
)

_REGISTRY: dict[str, Claim] = {}


def claim(
    id: str,
    reference: str,
    statement: str,
    tested_by: tuple[str, ...] | list[str],
    thesis_figure: str = "",
) -> Callable[[Callable[[ClaimContext], Evidence]], Callable[[ClaimContext], Evidence]]:
    """Register the decorated ``check(ctx) -> Evidence`` as the check of a claim."""

    def register(check: Callable[[ClaimContext], Evidence]):
        if id in _REGISTRY and _REGISTRY[id].check is not check:
            raise RuntimeError(f"claim id {id!r} registered twice")
        _REGISTRY[id] = Claim(id, reference, statement, tuple(tested_by), check, thesis_figure)
        return check

    return register


def all_claims() -> tuple[Claim, ...]:
    """Every registered claim, in the order of :data:`CLAIM_MODULES` and declaration."""
    for name in CLAIM_MODULES:
        import_module(name)
    return tuple(_REGISTRY.values())


def select(ids: list[str] | tuple[str, ...] | None = None) -> tuple[Claim, ...]:
    """The claims named in ``ids`` (all when empty), in registry order.

    Raises:
        InvalidParameter: an unknown id (the message lists the valid ones).
    """
    claims = all_claims()
    if not ids:
        return claims
    known = {c.id for c in claims}
    unknown = [i for i in ids if i not in known]
    if unknown:
        raise InvalidParameter(
            f"only: unknown claim id(s) {unknown}; expected any of {sorted(known)}"
        )
    wanted = set(ids)
    return tuple(c for c in claims if c.id in wanted)
