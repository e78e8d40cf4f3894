"""The hapex exception hierarchy.

Every error hapex raises on purpose derives from :class:`HapexError`, so a caller can catch
the library's failures without catching programming errors.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any


class HapexError(Exception):
    """Base class of every error raised by hapex."""


@dataclass(frozen=True)
class InputIssue:
    """One problem found in user input.

    Attributes:
        source: file name (or ``--set:N`` for the N-th command-line override).
        line: 1-based line number in ``source`` (0 when unknown).
        path: dotted key path inside the document (``"(root)"`` for the whole document).
        message: what is wrong, what was expected, and the valid choices where they are few.
    """

    source: str
    line: int
    path: str
    message: str

    def __str__(self) -> str:
        return f"{self.source}:{self.line}: {self.path}: {self.message}"


class ScenarioError(HapexError):
    """Bad input: an unreadable or invalid scenario file, data file or command-line option.

    Carries every problem found (``issues``) so that all of them can be reported at once.
    """

    def __init__(self, issues: Sequence[InputIssue] | str):
        if isinstance(issues, str):
            issues = [InputIssue("(input)", 0, "(root)", issues)]
        self.issues: tuple[InputIssue, ...] = tuple(issues)
        super().__init__("\n".join(str(i) for i in self.issues))


class InvalidParameter(HapexError, ValueError):
    """A library function was called with an argument outside its documented domain."""


class InfeasibleProblem(HapexError):
    """An optimization problem (QP, LP, NLP) has no solution or the solver failed.

    Attributes:
        problem: the data needed to replay the solve: a :class:`planner.optim.QPProblem`
            (or any object with ``to_arrays()``), a dict of arrays, or ``None``.
        solver: name of the backend that failed.

    A QP failure is replayed with ``err.save("failed.npz")`` then
    ``planner.optim.replay("failed.npz")`` (or ``planner.optim.QPProblem.load``).
    """

    def __init__(self, message: str, problem: Any = None, solver: str | None = None):
        super().__init__(message)
        self.problem = problem
        self.solver = solver

    def save(self, path: str | Path) -> Path:
        """Write the problem, the solver's name and the message to ``path`` (``.npz``).

        Returns:
            The file written (``.npz`` is appended when ``path`` lacks it).

        Raises:
            InvalidParameter: the error carries no problem data to save.
        """
        if hasattr(self.problem, "to_arrays"):
            arrays = dict(self.problem.to_arrays())
        elif isinstance(self.problem, dict):
            arrays = {k: v for k, v in self.problem.items() if v is not None}
        else:
            raise InvalidParameter(
                f"problem: expected QP data to save, got {type(self.problem).__name__}"
            )
        import numpy as np

        path = Path(path)
        if path.suffix != ".npz":
            path = path.with_name(path.name + ".npz")
        np.savez(path, **arrays, solver=np.str_(self.solver or ""), message=np.str_(str(self)))
        return path


class SingularConfiguration(HapexError):
    """A robot configuration is singular or outside the domain of its closed-form kinematics.

    Attributes:
        value: the offending quantity (e.g. an arccos argument outside [-1, 1]).
    """

    def __init__(self, message: str, value: float | None = None):
        super().__init__(message)
        self.value = value


class ContactLost(HapexError):
    """A contact that a controller or integrator relies on was lost."""


class CoordinatePatchExit(HapexError):
    """An integrator left the domain of a surface's coordinate patch."""


__all__ = [
    "ContactLost",
    "CoordinatePatchExit",
    "HapexError",
    "InfeasibleProblem",
    "InputIssue",
    "InvalidParameter",
    "ScenarioError",
    "SingularConfiguration",
]
