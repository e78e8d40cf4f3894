"""Expansion of a sweep into runs: grid x zip groups x random points x seeds, each one
applied to the base scenario through the same key paths as ``hapex run --set`` and validated
by its kind's model before anything runs."""

from __future__ import annotations

import hashlib
import itertools
import json
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from planner.errors import InputIssue, ScenarioError
from planner.scenario import ScenarioBase, apply_overrides, validate
from planner.sweep.spec import Sweep, dotted, load_sweep, sweep_from_dict

#: most problems reported when many combinations are bad
MAX_ISSUES = 20
#: keys that do not change what a run computes (left out of the run id)
_NOT_HASHED = ("name", "description", "output")


@dataclass(frozen=True)
class PlannedRun:
    """One run of a sweep.

    Attributes:
        run_id: stable hash of the resolved scenario (seed included) and the quick flag.
        index: position in the expansion (grid order, then zip, random points, seeds).
        params: swept key path -> value (the seed is separate).
        seed: the scenario's seed.
        data: the scenario document (base + ``set`` + params + seed) a worker validates.
        config: the validated scenario.
        base_dir: folder against which relative data-file paths resolve.
        quick: run with ``quick=True`` (the ``--quick`` variant).
        plots: draw the run's own figures.
    """

    run_id: str
    index: int
    params: Mapping[str, Any]
    seed: int
    data: Mapping[str, Any]
    config: ScenarioBase
    base_dir: Path
    quick: bool = False
    plots: bool = False

    @property
    def label(self) -> str:
        """``mu=1, object.shape=ellipse, seed=0``: names the combination in messages."""
        parts = [f"{k}={_flow(v)}" for k, v in self.params.items()]
        return ", ".join([*parts, f"seed={self.seed}"])


def as_sweep(sweep: Sweep | str | Path | Mapping[str, Any], quick: bool = False) -> Sweep:
    """A :class:`Sweep` from a sweep, a sweep file path, or a mapping."""
    if isinstance(sweep, Sweep):
        return sweep
    if isinstance(sweep, Mapping):
        return sweep_from_dict(sweep, quick=quick)
    return load_sweep(sweep, quick=quick)


def run_id(config: ScenarioBase, quick: bool = False) -> str:
    """Stable id of a run: 12 hex digits of the SHA-256 of its resolved parameters (every key
    of the validated scenario but name/description/output, the seed included) and of the
    quick flag. The same scenario gives the same id on every machine and in every session."""
    resolved = config.model_dump(mode="json")
    key = {k: v for k, v in resolved.items() if k not in _NOT_HASHED}
    text = json.dumps({"scenario": key, "quick": bool(quick)}, sort_keys=True, allow_nan=True)
    return hashlib.sha256(text.encode()).hexdigest()[:12]


def _flow(value: Any) -> str:
    """A value as one line of YAML flow (what ``--set key=VALUE`` parses back to it)."""
    text = yaml.safe_dump(value, default_flow_style=True, width=1 << 30, allow_unicode=True)
    return text.removesuffix("\n...\n").strip()


def _origin(sweep: Sweep, where: tuple) -> tuple:
    """Key path in the sweep file of a block, under ``quick:`` when the variant replaced it."""
    q = sweep.model.quick
    if sweep.quick and q is not None and where[0] in q.model_fields_set:
        return ("quick", *where)
    return where


def _combinations(sweep: Sweep) -> list[tuple[dict[str, Any], dict[str, tuple]]]:
    """Parameter combinations (without seeds) and, for each key, where the file sets it."""
    m = sweep.model
    axes: list[list[tuple[dict, dict]]] = []
    for key, values in (m.grid or {}).items():
        where = _origin(sweep, ("grid", key))
        axes.append([({key: v}, {key: where}) for v in values])
    for i, group in enumerate(m.zip or []):
        n = len(next(iter(group.values())))
        origins = {k: _origin(sweep, ("zip", i, k)) for k in group}
        axes.append([({k: vals[j] for k, vals in group.items()}, origins) for j in range(n)])
    if m.random is not None:
        rng = np.random.default_rng(m.random.seed)
        draws = {k: d.sample(rng, m.random.samples) for k, d in m.random.params.items()}
        origins = {k: _origin(sweep, ("random", "params", k)) for k in draws}
        axes.append(
            [({k: v[j] for k, v in draws.items()}, origins) for j in range(m.random.samples)]
        )
    out = []
    for combo in itertools.product(*axes):
        params: dict[str, Any] = {}
        origins: dict[str, tuple] = {}
        for p, o in combo:
            params.update(p)
            origins.update(o)
        out.append((params, origins))
    return out


def _seeds(sweep: Sweep) -> list[int | None]:
    seeds = sweep.model.seeds
    if seeds is None:
        return [None]  # the base scenario's own seed
    return list(range(seeds)) if isinstance(seeds, int) else list(seeds)


def _relocate(
    sweep: Sweep, issues: tuple[InputIssue, ...], keys: list[tuple[str, tuple]], label: str
) -> list[InputIssue]:
    """Issues of one combination, at the sweep line that set the offending key."""
    out = []
    for issue in issues:
        if issue.source.startswith("--set:"):
            key, where = keys[int(issue.source.split(":")[1]) - 1]
            inner = "" if issue.path == key else f"{issue.path}: "
            out.append(
                InputIssue(
                    sweep.source,
                    sweep.line(*where),
                    dotted(where),
                    f"combination ({label}): {inner}{issue.message}",
                )
            )
        else:
            out.append(
                InputIssue(
                    issue.source, issue.line, issue.path, f"{issue.message} (combination {label})"
                )
            )
    return out


def plan(sweep: Sweep | str | Path | Mapping[str, Any]) -> list[PlannedRun]:
    """Every run of a sweep, validated; combinations that resolve to the same scenario are
    merged (one run).

    Raises:
        ScenarioError: one issue per problem of every bad combination (at most
            :data:`MAX_ISSUES`), each naming the combination; nothing has run.
    """
    sweep = as_sweep(sweep)
    m = sweep.model
    fixed = [(k, v, _origin(sweep, ("set", k))) for k, v in (m.set or {}).items()]
    base = sweep.base
    if isinstance(m.base, dict) and "name" not in base.data:
        base = type(base)({**base.data, "name": m.name}, base.source, base.lines, base.origins)
    runs: list[PlannedRun] = []
    seen: set[str] = set()
    issues: list[InputIssue] = []
    for params, origins in _combinations(sweep):
        for seed in _seeds(sweep):
            sets = fixed + [(k, v, origins[k]) for k, v in params.items()]
            if seed is not None:
                sets.append(("seed", seed, _origin(sweep, ("seeds",))))
            named = [*params.items()] + ([("seed", seed)] if seed is not None else [])
            label = ", ".join(f"{k}={_flow(v)}" for k, v in named) or "the base scenario"
            try:
                doc = apply_overrides(base, [f"{k}={_flow(v)}" for k, v, _ in sets])
                config = validate(doc)
            except ScenarioError as exc:
                keys = [(k, w) for k, _, w in sets]
                issues.extend(_relocate(sweep, exc.issues, keys, label))
                continue
            rid = run_id(config, sweep.quick)
            if rid in seen:
                continue
            seen.add(rid)
            runs.append(
                PlannedRun(
                    rid,
                    len(runs),
                    dict(params),
                    config.seed,
                    {**doc.data, "name": config.name},
                    config,
                    sweep.base_dir,
                    sweep.quick,
                    m.run_plots,
                )
            )
    if issues:
        shown = list(dict.fromkeys(issues))[:MAX_ISSUES]
        if len(issues) > len(shown):
            shown.append(
                InputIssue(
                    sweep.source, 0, "(root)", f"... {len(issues) - len(shown)} more problems"
                )
            )
        raise ScenarioError(shown)
    return runs


def expand(sweep: Sweep | str | Path | Mapping[str, Any]) -> list[ScenarioBase]:
    """The validated scenarios of a sweep, in expansion order (see :func:`plan`)."""
    return [r.config for r in plan(sweep)]


__all__ = ["PlannedRun", "as_sweep", "expand", "plan", "run_id"]
