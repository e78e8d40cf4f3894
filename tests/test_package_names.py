"""A package's public name stays what it is when its same-named submodule is imported.

Importing ``pkg.name`` binds the module to the attribute ``pkg.name``. If ``pkg`` exports a
function or class under that name, from its own ``__init__`` or lazily through
``__getattr__``, whatever imports the submodule later (a user, a test, a lazy import in the
library) silently replaces the function with the module. ``planner.kinds.detect.run`` did
this: the kind's run function became its module ``run.py`` once something imported that.
Each clash (an exported name that is also a submodule) is checked in a fresh interpreter:
the attribute before and after the submodule's import must be the same object.
"""

from __future__ import annotations

import ast
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _exported(init: Path) -> set[str]:
    """The names ``__init__.py`` exports: its literal ``__all__`` and the keys of a literal
    ``_HOMES`` dict (the lazy exports its ``__getattr__`` resolves)."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(init.read_text())):
        if isinstance(node, ast.Assign | ast.AnnAssign):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            ids = {t.id for t in targets if isinstance(t, ast.Name)}
            if not ids & {"__all__", "_HOMES"} or node.value is None:
                continue
            try:
                value = ast.literal_eval(node.value)
            except ValueError:
                continue
            names |= set(value)
    return names


def _clashes() -> list[tuple[str, str]]:
    """Every ``(package, name)`` of ``planner`` and ``robots`` whose export ``name`` is
    also a submodule or subpackage of ``package``."""
    found = []
    for init in sorted([*ROOT.glob("planner/**/__init__.py"), *ROOT.glob("robots/**/__init__.py")]):
        folder = init.parent
        if "__pycache__" in folder.parts:
            continue
        package = ".".join(folder.relative_to(ROOT).parts)
        subs = {p.stem for p in folder.glob("*.py") if p.stem != "__init__"}
        subs |= {p.parent.name for p in folder.glob("*/__init__.py")}
        found += [(package, name) for name in sorted(_exported(init) & subs)]
    return found


_PROBE = """
import importlib, json, sys
package, name = sys.argv[1], sys.argv[2]
pkg = importlib.import_module(package)
before = getattr(pkg, name)
importlib.import_module(package + "." + name)
after = getattr(pkg, name)
print(json.dumps([type(before).__name__, type(after).__name__, before is after]))
"""


def test_the_clash_finder_sees_the_intended_module_exports():
    # robots exports its submodules planar_hand, sensors and three_gm on purpose; the
    # finder must list them (else the check below would have nothing to look at)
    assert {("robots", "planar_hand"), ("robots", "three_gm")} <= set(_clashes())


@pytest.mark.parametrize(("package", "name"), _clashes())
def test_importing_a_submodule_does_not_rebind_the_package_export(package, name):
    done = subprocess.run(
        [sys.executable, "-c", _PROBE, package, name],
        capture_output=True, text=True, timeout=120, cwd=ROOT,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    before, after, same = json.loads(done.stdout.strip().splitlines()[-1])
    assert same, f"{package}.{name} was a {before}, after importing the submodule a {after}"
