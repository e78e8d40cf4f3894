"""Sweep files: the YAML that describes a parameter study, and its validation.

A sweep file (see the README section "Parameter studies")::

    name: gait_feasibility            # default: the file's stem
    description: "..."
    base: ../ellipse_grasp_map.yaml   # a scenario file (relative to this file) or a mapping
    set: {resolution: 180}            # fixed overrides of the base (key.path: value)
    grid:                             # key.path -> values: the cartesian product
      mu: [0.5, 1.0, 2.0]
    zip:                              # groups of key paths whose values vary together
      - {object.a: [0.04, 0.05], object.width: [0.08, 0.10]}
    random:                           # `samples` points, each key drawn independently
      samples: 8
      seed: 0                         # of the sampler (the expansion is reproducible)
      params:
        simulation.center_sigma: {loguniform: [1.0e-5, 1.0e-3]}
        hand.tip_radius: {uniform: [0.01, 0.03]}
        hand.left_tip: {choice: [flat, round]}
    seeds: 3                          # scenario seeds 0, 1, 2 (or a list: [0, 7, 9])
    run_plots: false                  # per-run figures (the report has the study's plots)
    report: {metrics: [gait_feasible, "alg*_f1"]}   # metrics (fnmatch patterns) to plot
    quick: {grid: {mu: [1.0]}, seeds: 1}   # replaces those keys for --quick

Key paths are those of ``hapex run --set`` (``features.0.spacing`` indexes a list).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from pydantic import Field, ValidationError, field_validator, model_validator

from planner.errors import InputIssue, ScenarioError
from planner.scenario import (
    SourceDoc,
    StrictModel,
    read_yaml,
    validation_issues,
)

KEY_PATH = re.compile(r"^[A-Za-z0-9_-]+(\.[A-Za-z0-9_-]+)*$")
#: keys a sweep may not vary: the seed has ``seeds:``, the name identifies the study
RESERVED = ("seed", "name", "kind")


def dotted(path: tuple) -> str:
    """``("zip", 0, "object.a")`` -> ``zip[0].object.a`` (the key paths of error messages)."""
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out or "(root)"


class Distribution(StrictModel):
    """One random parameter: exactly one of ``uniform``, ``loguniform``, ``choice``."""

    uniform: tuple[float, float] | None = Field(None, description="[low, high)")
    loguniform: tuple[float, float] | None = Field(
        None, description="[low, high), 0 < low: log-uniform"
    )
    choice: list[Any] | None = Field(None, min_length=1, description="equally likely values")

    @model_validator(mode="after")
    def _one(self) -> Distribution:
        given = [k for k in ("uniform", "loguniform", "choice") if getattr(self, k) is not None]
        if len(given) != 1:
            raise ValueError(
                f"give exactly one of uniform: [low, high], loguniform: [low, high], "
                f"choice: [values]; got {given or 'none'}"
            )
        for key in ("uniform", "loguniform"):
            bounds = getattr(self, key)
            if bounds is None:
                continue
            lo, hi = bounds
            if not (math.isfinite(lo) and math.isfinite(hi) and lo < hi):
                raise ValueError(
                    f"{key}: bounds must be finite with low < high, got {list(bounds)}"
                )
            if key == "loguniform" and lo <= 0:
                raise ValueError(f"loguniform: low must be > 0, got {lo}")
        return self

    def sample(self, rng, n: int) -> list[Any]:
        """``n`` independent draws from ``rng`` (a ``numpy.random.Generator``)."""
        if self.choice is not None:
            return [self.choice[int(i)] for i in rng.integers(0, len(self.choice), size=n)]
        if self.uniform is not None:
            return [float(v) for v in rng.uniform(*self.uniform, size=n)]
        lo, hi = self.loguniform
        return [float(math.exp(v)) for v in rng.uniform(math.log(lo), math.log(hi), size=n)]


class RandomSpec(StrictModel):
    """``samples`` random points; each parameter drawn independently of the others."""

    samples: int = Field(..., ge=1, le=100_000, description="number of random points")
    seed: int = Field(0, ge=0, description="seed of the sampler (not of the runs)")
    params: dict[str, Distribution] = Field(..., min_length=1, description="key.path -> law")


def _zip_groups(value: Any) -> Any:
    """``zip:`` takes one group (a mapping) or a list of groups."""
    return [value] if isinstance(value, Mapping) else value


class Variant(StrictModel):
    """The parts of a study that ``--quick`` may replace (a smaller study, same base)."""

    set: dict[str, Any] | None = Field(None, description="fixed overrides of the base")
    grid: dict[str, list[Any]] | None = Field(None, description="key.path -> values")
    zip: list[dict[str, list[Any]]] | None = Field(None, description="groups varying together")
    random: RandomSpec | None = Field(None, description="random points")
    seeds: int | list[int] | None = Field(None, description="count, or list of seeds")

    _groups = field_validator("zip", mode="before")(_zip_groups)

    @field_validator("seeds")
    @classmethod
    def _seeds(cls, v):
        if isinstance(v, int) and not 1 <= v <= 100_000:
            raise ValueError(f"a seed count must be between 1 and 100000, got {v}")
        if isinstance(v, list):
            if not v:
                raise ValueError("the list of seeds is empty")
            if any(s < 0 for s in v) or len(set(v)) != len(v):
                raise ValueError(f"seeds must be distinct and >= 0, got {v}")
        return v

    @field_validator("grid")
    @classmethod
    def _grid(cls, v):
        empty = [k for k, vals in (v or {}).items() if not vals]
        if empty:
            raise ValueError(f"grid key(s) {empty} have no values")
        return v


class ReportSpec(StrictModel):
    """What ``report.md`` plots."""

    metrics: list[str] = Field(
        default_factory=list,
        description="metric names or fnmatch patterns (default: every numeric metric)",
    )


class SweepModel(Variant):
    """A sweep file."""

    name: str = Field(..., pattern=r"^[A-Za-z0-9_.-]+$", max_length=100)
    description: str = Field("", description="one line")
    base: str | dict[str, Any] = Field(..., description="scenario file or inline scenario")
    run_plots: bool = Field(False, description="draw each run's own figures")
    report: ReportSpec = Field(default_factory=ReportSpec)
    quick: Variant | None = Field(None, description="replacements for --quick")


@dataclass(frozen=True)
class Sweep:
    """A validated sweep file, ready to expand.

    Attributes:
        model: the validated file; with ``quick``, its ``quick:`` block already applied.
        source: the sweep file's path (``"(dict)"`` for a mapping).
        lines: key path -> line in ``source``.
        base: the base scenario as a parsed document (lines of its own file, or of the
            sweep's ``base:`` block when inline).
        base_dir: where the runs resolve relative data-file paths (the base file's folder).
        quick: the ``--quick`` variant (smaller study, runs with ``quick=True``).
    """

    model: SweepModel
    source: str
    lines: Mapping[tuple, int]
    base: SourceDoc
    base_dir: Path
    quick: bool = False

    @property
    def name(self) -> str:
        return self.model.name

    def line(self, *path: Any) -> int:
        """Line of the deepest known prefix of ``path`` in the sweep file (0: unknown)."""
        for k in range(len(path), -1, -1):
            if tuple(path[:k]) in self.lines:
                return self.lines[tuple(path[:k])]
        return 0


def _blocks(variant: Mapping[str, Any]) -> list[tuple[tuple, Mapping[str, Any]]]:
    """``(where, {key.path: ...})`` of every block of a (sweep or quick:) mapping that varies
    or sets key paths, read from the raw file: blocks of the wrong type are skipped (their
    own errors are pydantic's), so these checks run whether or not the file validates."""
    out = []
    for key in ("set", "grid"):
        if isinstance(variant.get(key), Mapping):
            out.append(((key,), variant[key]))
    groups = _zip_groups(variant.get("zip"))
    for i, g in enumerate(groups if isinstance(groups, list) else []):
        if isinstance(g, Mapping):
            out.append((("zip", i), g))
    random = variant.get("random")
    if isinstance(random, Mapping) and isinstance(random.get("params"), Mapping):
        out.append((("random", "params"), random["params"]))
    return out


def _semantic_issues(data: Mapping[str, Any], doc: SourceDoc) -> list[InputIssue]:
    """Key-path syntax, reserved keys, keys varied twice, zip groups of unequal length.

    Works on the raw document, so the command reports these together with the schema's
    errors (an unknown key and a reserved one in the same file: both, at once)."""
    issues = []

    def bad(path: tuple, message: str) -> None:
        line = next(
            (doc.lines[path[:k]] for k in range(len(path), -1, -1) if path[:k] in doc.lines), 0
        )
        issues.append(InputIssue(doc.source, line, dotted(path), message))

    for prefix, variant in (((), data), (("quick",), data.get("quick"))):
        if not isinstance(variant, Mapping):
            continue
        owners: dict[str, tuple] = {}
        blocks = _blocks(variant)
        for where, block in blocks:
            for key in block:
                path = prefix + where + (key,)
                if not isinstance(key, str) or not KEY_PATH.match(key):
                    bad(path, f"{key!r} is not a key path like 'object.radius' or 'features.0.x'")
                elif key.split(".")[0] in RESERVED:
                    bad(
                        path,
                        f"'{key.split('.')[0]}' cannot be varied by a sweep (seeds: sets seeds)",
                    )
                elif key in owners:
                    bad(path, f"already set by {dotted(prefix + owners[key])}")
                else:
                    owners[key] = where
        for where, group in blocks:
            if where[0] != "zip":
                continue
            sizes = {k: len(v) for k, v in group.items() if isinstance(v, list)}
            if len(set(sizes.values())) > 1:
                bad(
                    prefix + where, f"the lists of a zip group must have equal lengths, got {sizes}"
                )
            if not group or 0 in sizes.values():
                bad(prefix + where, "a zip group needs at least one key with values")
    return issues


#: what a sweep file's unknown key is told (the scenario loader's text speaks of kinds)
UNKNOWN_KEY = (
    "unknown key (check the spelling; the keys of a sweep file are in the README section "
    "'Parameter studies')"
)


def _base_doc(model: SweepModel, doc: SourceDoc, here: Path) -> tuple[SourceDoc, Path]:
    """The base scenario document and the folder its relative paths resolve against."""
    if isinstance(model.base, dict):
        lines = {p[1:]: n for p, n in doc.lines.items() if p[:1] == ("base",)}
        return SourceDoc(dict(model.base), doc.source, lines, {}), here
    path = Path(model.base)
    path = path if path.is_absolute() else here / path
    try:
        base = read_yaml(path)
    except ScenarioError as exc:
        line = doc.lines.get(("base",), 0)
        raise ScenarioError(
            [InputIssue(doc.source, line, "base", f"{path}: {i.message}") for i in exc.issues]
        ) from None
    return base, path.parent


def sweep_from_doc(doc: SourceDoc, *, quick: bool = False, base_dir: Path | None = None) -> Sweep:
    """Validate a parsed sweep document (see :func:`load_sweep`)."""
    data = dict(doc.data)
    if "name" not in data and doc.source not in ("", "(dict)", "(input)"):
        data["name"] = Path(doc.source).stem
    doc = SourceDoc(data, doc.source, doc.lines, doc.origins)
    issues = _semantic_issues(data, doc)
    try:
        model = SweepModel.model_validate(data)
    except ValidationError as exc:
        # every problem of the file, at once
        issues = validation_issues(doc, exc, UNKNOWN_KEY) + issues
    if issues:
        unique = list({str(i): i for i in issues}.values())
        raise ScenarioError(sorted(unique, key=lambda i: (i.source != doc.source, i.line)))
    if quick and model.quick is not None:
        replace = {k: getattr(model.quick, k) for k in model.quick.model_fields_set}
        model = model.model_copy(update=replace)
    here = base_dir if base_dir is not None else Path(doc.source).resolve().parent
    base, bdir = _base_doc(model, doc, here)
    return Sweep(model, doc.source, doc.lines, base, bdir, quick)


def load_sweep(path: str | Path, *, quick: bool = False) -> Sweep:
    """Read and validate a sweep file.

    Args:
        path: the sweep YAML file.
        quick: use its ``quick:`` variant (a smaller study whose runs use ``--quick``).

    Raises:
        ScenarioError: every problem found, each as ``FILE:LINE: key.path: message``.
    """
    return sweep_from_doc(read_yaml(path), quick=quick)


def sweep_from_dict(
    data: Mapping[str, Any], *, quick: bool = False, base_dir: str | Path | None = None
) -> Sweep:
    """Validate a sweep given as a Python mapping (library use); a ``base`` path resolves
    against ``base_dir`` (default: the current directory)."""
    here = Path(base_dir) if base_dir is not None else Path.cwd()
    return sweep_from_doc(SourceDoc(dict(data), "(dict)", {}, {}), quick=quick, base_dir=here)


__all__ = ["Distribution", "RandomSpec", "Sweep", "SweepModel", "load_sweep", "sweep_from_dict"]
