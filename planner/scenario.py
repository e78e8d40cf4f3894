"""Scenario files: YAML with line numbers, validated by pydantic models, one per ``kind``.

A scenario file is a YAML mapping. Keys common to every kind (:class:`ScenarioBase`)::

    name: step_trace          # identifier, letters/digits/_/- (default: the file's stem)
    kind: trace               # selects the model and the runner (see ``hapex list``)
    description: "..."        # one line, shown by ``hapex list``
    seed: 0                   # seeds numpy.random.default_rng; the only randomness source
    output: {plots: true, formats: [png], dpi: 120}

Every other key belongs to the kind's own model, defined in ``planner/kinds/<kind>.py`` as
``Config`` (a :class:`ScenarioBase` subclass with ``kind: Literal["<kind>"]``) together with
``run(config, ctx) -> RunResult``. Kinds are discovered from that package, so adding a kind
touches one file. Models forbid unknown keys; every problem is reported at once with its
file, line and key path.
"""

from __future__ import annotations

import importlib
import pkgutil
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any, Literal

import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from planner.errors import InputIssue, ScenarioError

ROOT = "(root)"


class StrictModel(BaseModel):
    """Base of every scenario model: unknown keys are errors; models are immutable; no
    number may be infinite or NaN (``.inf`` / ``.nan`` in YAML, ``inf`` on ``--set``)."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)


class OutputSettings(StrictModel):
    """What the run directory gets besides result.json."""

    plots: bool = Field(True, description="write figures to plots/")
    formats: tuple[Literal["png", "svg", "pdf"], ...] = Field(
        ("png",), min_length=1, description="figure file formats"
    )
    dpi: int = Field(120, ge=30, le=600, description="raster figure resolution [dpi]")


class ScenarioBase(StrictModel):
    """Keys common to every scenario kind."""

    name: str = Field(
        ...,
        pattern=r"^[A-Za-z0-9_.-]+$",
        max_length=100,
        description="identifier of the scenario (default: the file name stem)",
    )
    kind: str
    description: str = Field("", description="one-line description")
    seed: int = Field(0, ge=0, description="seed of numpy.random.default_rng")
    output: OutputSettings = Field(default_factory=OutputSettings)


@dataclass(frozen=True)
class KindSpec:
    """A registered scenario kind: its model and its runner."""

    name: str
    config: type[ScenarioBase]
    run: Callable[..., Any]
    module: str


@cache
def kinds() -> dict[str, KindSpec]:
    """All scenario kinds found in ``planner.kinds`` (name -> spec), sorted by name."""
    import planner.kinds as pkg

    found: dict[str, KindSpec] = {}
    for info in pkgutil.iter_modules(pkg.__path__):
        if info.name.startswith("_"):
            continue
        mod = importlib.import_module(f"planner.kinds.{info.name}")
        config = getattr(mod, "Config", None)
        run = getattr(mod, "run", None)
        if config is None or run is None:
            continue
        ann = config.model_fields["kind"].annotation
        name = ann.__args__[0]
        found[name] = KindSpec(name, config, run, mod.__name__)
    return dict(sorted(found.items()))


# --------------------------------------------------------------------------- YAML + lines
def _line_map(node: yaml.Node, path: tuple = (), out: dict | None = None) -> dict:
    """Map every key path of a composed YAML node tree to its 1-based line."""
    if out is None:
        out = {}
    out.setdefault(path, node.start_mark.line + 1)
    if isinstance(node, yaml.MappingNode):
        for knode, vnode in node.value:
            key = knode.value
            out[path + (key,)] = knode.start_mark.line + 1
            _line_map(vnode, path + (key,), out)
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            out[path + (i,)] = item.start_mark.line + 1
            _line_map(item, path + (i,), out)
    return out


@dataclass(frozen=True)
class SourceDoc:
    """A parsed YAML document and where each key came from."""

    data: Any
    source: str
    lines: Mapping[tuple, int]
    origins: Mapping[tuple, str]  # key path -> "--set:N" for overridden keys


def read_yaml(path: str | Path) -> SourceDoc:
    """Read a YAML file, keeping the line of every key.

    Raises:
        ScenarioError: the file is missing, unreadable, empty, not YAML, or not a mapping.
    """
    src = str(path)
    try:
        text = Path(path).read_text()
    except FileNotFoundError:
        raise ScenarioError([InputIssue(src, 0, ROOT, "file not found")]) from None
    except IsADirectoryError:
        raise ScenarioError([InputIssue(src, 0, ROOT, "is a directory, not a file")]) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ScenarioError([InputIssue(src, 0, ROOT, f"cannot read: {exc}")]) from None
    try:
        node = yaml.compose(text, Loader=yaml.SafeLoader)
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
        line = mark.line + 1 if mark is not None else 0
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise ScenarioError([InputIssue(src, line, ROOT, f"not valid YAML: {problem}")]) from None
    if node is None:
        raise ScenarioError(
            [InputIssue(src, 1, ROOT, "file is empty; expected a mapping with at least 'kind'")]
        )
    if not isinstance(data, dict):
        raise ScenarioError(
            [
                InputIssue(
                    src,
                    node.start_mark.line + 1,
                    ROOT,
                    f"expected a mapping of keys, got {type(data).__name__}",
                )
            ]
        )
    return SourceDoc(data, src, _line_map(node), {})


def _parse_override(text: str, index: int) -> tuple[tuple[str, ...], Any]:
    where = f"--set:{index}"
    if "=" not in text:
        raise ScenarioError([InputIssue(where, 0, text, "expected key.path=value")])
    key, _, raw = text.partition("=")
    parts = tuple(p.strip() for p in key.strip().split("."))
    if not key.strip() or any(not p for p in parts):
        raise ScenarioError([InputIssue(where, 0, key or ROOT, "empty key in key.path=value")])
    try:
        value = yaml.safe_load(raw) if raw.strip() else None
    except yaml.YAMLError:
        value = raw
    return parts, value


def apply_overrides(doc: SourceDoc, overrides: Sequence[str]) -> SourceDoc:
    """Apply ``--set key.path=value`` overrides (values parsed as YAML scalars/flow).

    Path parts index mappings by key and lists by position (``features.0.spacing``).
    """
    import copy

    data = copy.deepcopy(doc.data)
    origins = dict(doc.origins)
    issues = []
    for i, text in enumerate(overrides, start=1):
        try:
            parts, value = _parse_override(text, i)
        except ScenarioError as exc:
            issues.extend(exc.issues)
            continue
        cur = data
        keys: list[Any] = []
        problem = None
        for depth, p in enumerate(parts):
            where = ".".join(parts[: depth + 1])
            if isinstance(cur, list):
                if not p.lstrip("-").isdigit() or not -len(cur) <= int(p) < len(cur):
                    problem = (where, f"is not an index of a list of {len(cur)} items")
                    break
                key: Any = int(p) % len(cur)
            elif isinstance(cur, dict):
                key = p
            else:
                problem = (
                    ".".join(parts[:depth]),
                    "is not a mapping or a list; cannot set a key inside it",
                )
                break
            keys.append(key)
            if depth == len(parts) - 1:
                cur[key] = value
            else:
                if isinstance(cur, dict) and cur.get(key) is None:
                    cur[key] = {}
                cur = cur[key]
        if problem is not None:
            issues.append(InputIssue(f"--set:{i}", 0, problem[0], problem[1]))
        else:
            origins[tuple(keys)] = f"--set:{i}"
    if issues:
        raise ScenarioError(issues)
    return SourceDoc(data, doc.source, doc.lines, origins)


def _locate(doc: SourceDoc, loc: Sequence[Any]) -> tuple[str, int, str]:
    """Turn a pydantic error location into (source, line, dotted path).

    Discriminator tags that pydantic inserts into ``loc`` are skipped by walking the data.
    """
    path: list[Any] = []
    cur = doc.data
    for item in loc:
        if isinstance(cur, dict) and item in cur:
            path.append(item)
            cur = cur[item]
        elif isinstance(cur, list) and isinstance(item, int) and 0 <= item < len(cur):
            path.append(item)
            cur = cur[item]
        elif isinstance(cur, dict) and item in {v for v in cur.values() if isinstance(v, str)}:
            continue  # the tag of a discriminated union (e.g. ``type: step``)
        elif isinstance(item, str) and not (isinstance(cur, dict) and item in cur):
            # a union/discriminator tag or a missing key: a missing key is the last item
            if item == loc[-1]:
                path.append(item)
            cur = None if not isinstance(cur, (dict, list)) else cur
    tpath = tuple(path)
    for k in range(len(tpath), -1, -1):
        if tpath[:k] in doc.origins:
            return doc.origins[tpath[:k]], 0, _dotted(tpath)
    if tpath:  # a rule over a block (``sampling``) that an override inside it changed
        inner = [o for o in doc.origins if o[: len(tpath)] == tpath]
        if inner:
            return doc.origins[inner[-1]], 0, _dotted(tpath)
    line = 0
    for k in range(len(tpath), -1, -1):
        if tpath[:k] in doc.lines:
            line = doc.lines[tpath[:k]]
            break
    return doc.source, line, _dotted(tpath)


def _dotted(path: Sequence[Any]) -> str:
    if not path:
        return ROOT
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


def _discriminator(err: Mapping[str, Any]) -> str | None:
    """The key that selects a union member (``type`` of ``profile: {type: ...}``), if any."""
    if err.get("type") not in ("union_tag_invalid", "union_tag_not_found"):
        return None
    return str(err.get("ctx", {}).get("discriminator", "")).strip("'\"") or None


def _error_loc(err: Mapping[str, Any], data: Any) -> tuple:
    """The location of a pydantic error, down to the offending key.

    pydantic reports a bad union tag at the union's key (``profile``); the value at fault is
    the tag itself (``profile.type``), which may come from ``--set`` rather than the file.
    A model-level validator (a rule across keys) has no location; when its message starts
    with a key path of the document (``sampling: ...``), that key is the location, so the
    line (or the ``--set``) that gave the value is blamed.
    """
    loc = tuple(err["loc"])
    key = _discriminator(err)
    if key and err.get("type") == "union_tag_invalid":
        return loc + (key,)
    if err.get("type") == "value_error":
        head = _message(err).split(": ", 1)[0]
        parts = tuple(head.split("."))
        cur = data
        for p in loc:  # the validator's model inside the document (list items too)
            if isinstance(cur, dict):
                cur = cur.get(p)
            elif isinstance(cur, list) and isinstance(p, int) and 0 <= p < len(cur):
                cur = cur[p]
            else:
                cur = None
        if head and " " not in head and isinstance(cur, dict) and parts[0] in cur:
            return loc + parts
    return loc


def _items_missing(errors: Sequence[Mapping[str, Any]]) -> list[Mapping[str, Any]]:
    """``errors`` with pydantic's ``missing`` errors of a fixed-length tuple's items (one per
    absent item, located at the item's index: ``pose[2]: Field required`` for a 2-item pose
    of 3) merged into one ``too_few_items`` error at the tuple, with the counts: the tuple
    was reported as a missing key."""
    need: dict[tuple, int] = {}
    for err in errors:
        loc = tuple(err["loc"])
        if err.get("type") == "missing" and loc and isinstance(loc[-1], int):
            need[loc[:-1]] = max(need.get(loc[:-1], 0), loc[-1] + 1)
    if not need:
        return list(errors)
    out: list[Mapping[str, Any]] = []
    for err in errors:
        loc = tuple(err["loc"])
        if loc[:-1] in need and err.get("type") == "missing" and isinstance(loc[-1], int):
            got = err.get("input")
            ctx = {
                "expected": need[loc[:-1]],
                "actual": len(got) if isinstance(got, list) else None,
            }
            err = {"type": "too_few_items", "loc": loc[:-1], "msg": "", "ctx": ctx}
        out.append(err)
    return out


def _message(err: Mapping[str, Any]) -> str:
    kind = err.get("type")
    if kind == "too_few_items":
        ctx = err["ctx"]
        got = "" if ctx["actual"] is None else f", got {ctx['actual']}"
        return f"expected {ctx['expected']} items{got}"
    if kind == "extra_forbidden":
        return "unknown key (check the spelling; see the README for the keys of this kind)"
    if kind == "missing":
        return "required key is missing"
    if kind == "union_tag_invalid":
        ctx = err.get("ctx", {})
        key = _discriminator(err) or "kind"
        return f"unknown {key} {ctx.get('tag')!r}; expected one of {ctx.get('expected_tags')}"
    if kind == "union_tag_not_found":
        return f"missing key {err.get('ctx', {}).get('discriminator', 'kind')}"
    msg = str(err.get("msg", "invalid value"))
    for prefix in ("Value error, ", "Assertion failed, "):
        if msg.startswith(prefix):
            msg = msg[len(prefix) :]
    return msg


def validation_issues(
    doc: SourceDoc, exc: ValidationError, unknown_key: str | None = None
) -> list[InputIssue]:
    """The problems of a pydantic ``ValidationError`` raised on ``doc.data``, each located at
    its file, line and key path (file errors in line order, then override errors).

    For any model validated from a :class:`SourceDoc` (scenario kinds, sweep files);
    ``unknown_key``: the message of an unknown key (default: the scenario kinds' hint).
    """
    issues = []
    seen = set()
    for err in _items_missing(exc.errors()):
        src, line, path = _locate(doc, err["loc"])
        unknown = unknown_key is not None and err.get("type") == "extra_forbidden"
        issue = InputIssue(src, line, path, unknown_key if unknown else _message(err))
        if str(issue) not in seen:
            seen.add(str(issue))
            issues.append(issue)
    return sorted(issues, key=lambda i: (i.source != doc.source, i.line))


def validate(doc: SourceDoc) -> ScenarioBase:
    """Validate a parsed document against the model of its kind.

    Raises:
        ScenarioError: with one issue per problem, all at once.
    """
    data = dict(doc.data)
    if "name" not in data and doc.source not in ("", "(input)"):
        data["name"] = Path(doc.source).stem
    if "kind" not in data:
        raise ScenarioError(
            [
                InputIssue(
                    doc.source,
                    1,
                    "kind",
                    f"required key is missing; expected one of {sorted(kinds())}",
                )
            ]
        )
    if not isinstance(data["kind"], str) or data["kind"] not in kinds():
        src, line, path = _locate(doc, ("kind",))
        raise ScenarioError(
            [
                InputIssue(
                    src,
                    line,
                    "kind",
                    f"unknown kind {data['kind']!r}; expected one of {sorted(kinds())}",
                )
            ]
        )
    doc = SourceDoc(data, doc.source, doc.lines, doc.origins)
    model = kinds()[data["kind"]].config
    try:
        return model.model_validate(data)
    except ValidationError as exc:
        issues = []
        seen = set()
        for err in _items_missing(exc.errors()):
            loc = _error_loc(err, doc.data)
            msg = _message(err)
            # the key the line is reported at: the path a rule's message named, or the
            # validated field itself; a message that starts with it does not repeat it
            head = ".".join(str(k) for k in loc[len(err["loc"]) :]) or (str(loc[-1]) if loc else "")
            if head and msg.startswith(f"{head}: "):
                msg = msg.split(": ", 1)[1]
            src, line, path = _locate(doc, loc)
            issue = InputIssue(src, line, path, msg)
            if str(issue) not in seen:
                seen.add(str(issue))
                issues.append(issue)
        # file errors in line order, then override errors
        raise ScenarioError(
            sorted(issues, key=lambda i: (i.source != doc.source, i.line))
        ) from None


def load_scenario(
    path: str | Path, overrides: Sequence[str] = (), seed: int | None = None
) -> ScenarioBase:
    """Read, override and validate a scenario file.

    Args:
        path: the YAML file.
        overrides: ``key.path=value`` strings (as given to ``--set``).
        seed: replaces the file's ``seed`` when given.

    Returns:
        The validated scenario (an instance of its kind's ``Config``).

    Raises:
        ScenarioError: every problem found, each with file, line and key path.
    """
    doc = read_yaml(path)
    if seed is not None:
        overrides = [*overrides, f"seed={seed}"]
    doc = apply_overrides(doc, overrides)
    return validate(doc)


def late_issue(
    path: str | Path,
    overrides: Sequence[str],
    message: str,
    seed: int | None = None,
    resolved: Mapping[str, Any] | None = None,
) -> InputIssue:
    """Where bad input found during a run belongs: the library's ``name: message`` (an
    :class:`~planner.errors.InvalidParameter`) put at the one scenario key named ``name``.

    The key is looked up in the file and its overrides (with its line, or its ``--set``),
    else in the ``resolved`` scenario (a key left at its default: line 0); a name that
    matches no key, or several, stays at ``(root)`` with the whole message.
    """
    head, sep, rest = message.partition(": ")
    name = head.split("[")[0].strip()
    if not sep or not name.isidentifier():
        return InputIssue(str(path), 0, ROOT, message)
    seeded = [*overrides, f"seed={seed}"] if seed is not None else list(overrides)
    doc = apply_overrides(read_yaml(path), seeded)
    for data, lines in ((doc.data, True), (resolved, False)):
        hits = [p for p in _key_paths(data) if p[-1] == name] if data is not None else []
        if len(hits) == 1:
            if lines:
                source, line, dotted = _locate(doc, hits[0])
            else:
                source, line, dotted = str(path), 0, _dotted(hits[0])
            return InputIssue(source, line, dotted, f"{rest} ({head})" if head != name else rest)
    return InputIssue(str(path), 0, ROOT, message)


def _key_paths(data: Any, prefix: tuple = ()) -> list[tuple]:
    """Every key path of the mappings nested in ``data`` (through lists too)."""
    out: list[tuple] = []
    items = (
        data.items()
        if isinstance(data, Mapping)
        else (enumerate(data) if isinstance(data, list) else ())
    )
    for k, v in items:
        out.append((*prefix, k))
        out.extend(_key_paths(v, (*prefix, k)))
    return [p for p in out if isinstance(p[-1], str)]


def scenario_from_dict(data: Mapping[str, Any]) -> ScenarioBase:
    """Validate a scenario given as a Python mapping (library use)."""
    return validate(SourceDoc(dict(data), "(dict)", {}, {}))


__all__ = [
    "KindSpec",
    "OutputSettings",
    "ScenarioBase",
    "SourceDoc",
    "StrictModel",
    "apply_overrides",
    "kinds",
    "late_issue",
    "load_scenario",
    "read_yaml",
    "scenario_from_dict",
    "validate",
    "validation_issues",
]
