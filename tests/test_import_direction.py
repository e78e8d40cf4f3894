"""Imports point down the layers of DESIGN.md, and library packages form no cycle.

Layers (lower never imports higher)::

    errors, checks  <-  geometry, contact, optim, robots  <-  grasp, detection, skeleton, sim
        <-  control, trajectory  <-  exploration  <-  kinds  <-  scenario, cli, runner, sweep

Every ``import`` statement of every library module is read from its AST, function-local and
``TYPE_CHECKING`` imports included, relative imports resolved.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: The always-allowed leaves of the whole code base.
BASE = {"planner", "planner.errors", "planner.checks", "planner.jit"}
#: The spine: what only kinds and the command line may use.
SPINE = {
    "planner.kinds",
    "planner.results",
    "planner.scenario",
    "planner.cli",
    "planner.runner",
    "planner.runctx",
    "planner.sweep",
}
#: Library packages and their layer: a package may import its own or lower layers only.
RANK = {
    "planner.geometry": 1,
    "planner.contact": 1,
    "planner.optim": 1,
    "robots": 1,
    "planner.grasp": 2,
    "planner.detection": 2,
    "planner.skeleton": 2,
    "planner.sim": 2,
    "planner.control": 3,
    "planner.trajectory": 3,
    "planner.exploration": 4,
}


def package_of(module: str) -> str:
    """``planner.grasp.maps`` -> ``planner.grasp``; ``robots.three_gm.gm`` -> ``robots``."""
    parts = module.split(".")
    if parts[0] == "robots":
        return "robots"
    return ".".join(parts[:2])


def module_name(path: Path) -> str:
    rel = path.relative_to(ROOT).with_suffix("")
    parts = rel.parts[:-1] if rel.name == "__init__" else rel.parts
    return ".".join(parts)


def imports_of(source: str, module: str, is_package: bool = False) -> list[tuple[int, str]]:
    """``(line, imported module)`` of every import in ``source`` (anywhere in the tree)."""
    out = []
    here = module.split(".") if is_package else module.split(".")[:-1]
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = here[: len(here) - node.level + 1]
                base = ".".join(anchor + ([base] if base else []))
            # ``from planner import checks`` imports the module planner.checks
            out += [
                (node.lineno, f"{base}.{a.name}" if base in ("planner", "robots") else base)
                for a in node.names
            ]
    return [(line, m) for line, m in out if m.split(".")[0] in ("planner", "robots")]


def library_modules() -> list[Path]:
    files = []
    for pkg in RANK:
        folder = ROOT.joinpath(*pkg.split("."))
        files += sorted(folder.rglob("*.py")) if folder.is_dir() else []
    return files


def edges() -> list[tuple[str, str, str, int]]:
    """``(source package, target module, file, line)`` of every cross-package import."""
    out = []
    for f in library_modules():
        mod = module_name(f)
        for line, target in imports_of(f.read_text(), mod, f.name == "__init__.py"):
            if package_of(target) != package_of(mod):
                out.append((package_of(mod), target, f.relative_to(ROOT).as_posix(), line))
    return out


def test_no_library_module_imports_the_spine():
    bad = [
        f"{file}:{line}: imports {target} (spine: only kinds and the CLI may)"
        for _, target, file, line in edges()
        if package_of(target) in SPINE or target in SPINE
    ]
    assert not bad, "\n".join(bad)


def test_imports_point_down_the_layers():
    bad = []
    for src, target, file, line in edges():
        dst = package_of(target)
        if target in BASE or dst in SPINE:
            continue  # the spine is the test above
        if dst not in RANK:
            bad.append(f"{file}:{line}: imports {target}, a package of no known layer")
        elif RANK[dst] > RANK[src]:
            bad.append(
                f"{file}:{line}: {src} (layer {RANK[src]}) imports {target} (layer {RANK[dst]})"
            )
    assert not bad, "\n".join(bad)


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One cycle of ``graph`` as a list of nodes (first == last), or None."""
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                return stack[stack.index(nxt) :] + [nxt]
            if nxt not in state and (found := visit(nxt)):
                return found
        state[node] = 2
        stack.pop()
        return None

    for node in sorted(graph):
        if node not in state and (found := visit(node)):
            return found
    return None


def test_library_packages_form_no_cycle():
    graph: dict[str, set[str]] = {}
    for src, target, _, _ in edges():
        if package_of(target) in RANK:
            graph.setdefault(src, set()).add(package_of(target))
    cycle = find_cycle(graph)
    assert cycle is None, "package import cycle: " + " -> ".join(cycle)


def test_optim_is_a_leaf():
    bad = [
        f"{file}:{line}: imports {target}"
        for src, target, file, line in edges()
        if src == "planner.optim" and target not in BASE
    ]
    assert not bad, "planner.optim may import only planner.errors/checks:\n" + "\n".join(bad)


# ------------------------------------------------------------- the checker itself
def test_checker_sees_function_local_relative_and_from_package_imports():
    src = (
        "import numpy as np\n"
        "from planner import checks\n"
        "def f():\n"
        "    from planner.kinds.trace import run\n"
        "    from ..results import RunResult\n"
        "    from . import cones\n"
    )
    got = imports_of(src, "planner.contact.friction")
    assert got == [
        (2, "planner.checks"),
        (4, "planner.kinds.trace"),
        (5, "planner.results"),
        (6, "planner.contact"),
    ]
    assert package_of("robots.three_gm.gm") == "robots"


def test_cycle_finder():
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert find_cycle({"a": {"b"}, "b": {"c"}}) is None
