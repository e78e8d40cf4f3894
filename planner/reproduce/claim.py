"""One claim of the thesis, the evidence hapex produces for it, and the verdict.

A :class:`Claim` names a result of the thesis (its reference, a one-sentence statement) and
holds a ``check`` that computes hapex's :class:`Evidence` for it from numbers: the quantities
compared (hapex's value beside the thesis' value), the verdict, and a figure. Verdicts are
never hard-coded: a check compares numbers and :func:`verdict_from` turns the comparison into
a :class:`Verdict`.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path

import numpy as np

__all__ = [
    "Claim",
    "ClaimContext",
    "Evidence",
    "Number",
    "NotImplementedClaim",
    "Verdict",
    "verdict_from",
]


class Verdict(str, Enum):
    """How hapex's result stands against the thesis' claim."""

    REPRODUCED = "reproduced"
    PARTLY = "partly"
    DIFFERS = "differs"
    NOT_IMPLEMENTED = "not implemented"
    ERROR = "error"

    @property
    def acceptable(self) -> bool:
        """Reproduced, or explained (partly/differs with evidence), or not yet implemented."""
        return self is not Verdict.ERROR


class NotImplementedClaim(Exception):
    """Raised by a check whose capability is not (yet) in hapex; the reason is the message."""


@dataclass(frozen=True)
class Number:
    """One quantity compared: hapex's value beside the thesis' value.

    Attributes:
        name: what is compared (with its unit in brackets, e.g. ``"chi2 of x [-]"``).
        hapex: hapex's value.
        thesis: the thesis' value, or ``None`` where the thesis states only a qualitative result.
        ok: whether hapex's value satisfies the claim (within the stated tolerance).
        tolerance: the tolerance or rule applied, in words (``"|d| <= 1e-9"``, ``"> 0.5"``).
    """

    name: str
    hapex: float | str | bool
    thesis: float | str | bool | None
    ok: bool
    tolerance: str = ""

    def as_dict(self) -> dict:
        return {
            "name": self.name,
            "hapex": _plain(self.hapex),
            "thesis": _plain(self.thesis),
            "ok": bool(self.ok),
            "tolerance": self.tolerance,
        }


def _plain(v):
    if isinstance(v, (np.floating, np.integer)):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    if isinstance(v, np.bool_):
        return bool(v)
    return v


@dataclass(frozen=True)
class Evidence:
    """What a check found.

    Attributes:
        verdict: the verdict (computed from ``numbers`` by :func:`verdict_from` in most checks).
        numbers: the quantities compared.
        explanation: for ``partly``/``differs``: what differs and why (where the thesis is
            believed wrong, e.g. an OCR error, say so); for ``reproduced``: how it was shown.
        figure: path of the figure that shows it (relative to the report folder), or ``None``.
    """

    verdict: Verdict
    numbers: tuple[Number, ...] = ()
    explanation: str = ""
    figure: str | None = None

    @property
    def key_number(self) -> str:
        """The first compared quantity as ``name: hapex vs thesis``."""
        if not self.numbers:
            return ""
        n = self.numbers[0]
        thesis = "-" if n.thesis is None else _fmt(n.thesis)
        return f"{n.name}: {_fmt(n.hapex)} vs {thesis}"


def _fmt(v) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "yes" if v else "no"
    if isinstance(v, (float, np.floating)):
        return f"{float(v):.4g}"
    return str(v)


def verdict_from(
    numbers: list[Number] | tuple[Number, ...], *, explained: str = ""
) -> tuple[Verdict, tuple[Number, ...]]:
    """Return ``REPRODUCED`` when every number is ok, ``PARTLY`` when some are, else ``DIFFERS``.

    ``explained`` is ignored here but documents, at the call site, why a partial or
    differing result is expected; :class:`Evidence` carries it.
    """
    numbers = tuple(numbers)
    oks = [n.ok for n in numbers]
    if not oks:
        return Verdict.DIFFERS, numbers
    if all(oks):
        return Verdict.REPRODUCED, numbers
    return (Verdict.PARTLY if any(oks) else Verdict.DIFFERS), numbers


@dataclass(frozen=True)
class ClaimContext:
    """What a check may use.

    Attributes:
        quick: a short run (coarser resolutions, fewer repeats) for the test suite.
        figures: folder where the check writes its figure (``None``: no figures).
        seed: seed of the check's ``numpy.random.Generator``.
    """

    quick: bool = False
    figures: Path | None = None
    seed: int = 0

    def rng(self) -> np.random.Generator:
        return np.random.default_rng(self.seed)

    def figure_path(self, claim_id: str) -> Path | None:
        if self.figures is None:
            return None
        self.figures.mkdir(parents=True, exist_ok=True)
        return self.figures / f"{claim_id.replace('/', '_')}.png"


@dataclass(frozen=True)
class Claim:
    """A claim of the thesis and the check that tests it.

    Attributes:
        id: stable identifier (``"fig3.7"``, ``"tableB.1"``, ``"sec2.3.1"``).
        reference: the thesis reference (section, figure, table or equation).
        statement: the claim in one sentence.
        tested_by: the scenarios or library calls that test it.
        thesis_figure: a description of the thesis figure (shown beside hapex's figure).
        check: ``check(ctx) -> Evidence``; raises :class:`NotImplementedClaim` when the
            capability is missing.
    """

    id: str
    reference: str
    statement: str
    tested_by: tuple[str, ...]
    check: Callable[[ClaimContext], Evidence] = field(repr=False)
    thesis_figure: str = ""
