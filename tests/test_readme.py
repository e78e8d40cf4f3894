"""Every Python example of the README runs as is; the README's main command runs."""

from __future__ import annotations

import json
import os
import re
import shlex
import subprocess
import sys

import pytest
from conftest import ROOT, run_cli

README = (ROOT / "README.md").read_text()
DOCS = {path.name: path.read_text() for path in sorted((ROOT / "docs").glob("*.md"))}
PY_BLOCKS = [
    code
    for text in (README, *DOCS.values())
    for code in re.findall(r"```python\n(.*?)```", text, flags=re.S)
]


def test_readme_has_two_setup_commands():
    setup = README.split("## Set-up", 1)[1].split("\n## ", 1)[0]
    bash = re.findall(r"```bash\n(.*?)```", setup, flags=re.S)
    assert len(bash) == 2
    assert "hapex run scenarios/" in bash[0] and "pytest" in bash[1]
    ci = (ROOT / ".ci" / "run").read_text()
    test_cmd = bash[1].strip().split("&& ", 2)[-1]  # pip install ... && python -m pytest ...
    assert test_cmd.split(" && ")[0] in ci and "python -m pytest -q -n 2" in ci


def test_readme_main_command_runs(tmp_path):
    setup = README.split("## Set-up", 1)[1]
    cmd = re.findall(r"hapex run (\S+)", setup)[0]
    out = tmp_path / "run"
    proc = run_cli("run", cmd, "--out", str(out), "--quick")
    assert proc.returncode == 0, proc.stderr
    assert json.loads((out / "result.json").read_text())["status"] == "ok"


def test_readme_documents_every_kind():
    from planner.scenario import kinds

    for name in kinds():
        assert f"kind `{name}`" in README, name


@pytest.mark.parametrize("code", PY_BLOCKS, ids=[f"example{i}" for i in range(len(PY_BLOCKS))])
def test_readme_python_example(code, tmp_path):
    script = tmp_path / "example.py"
    # examples that write run directories write them inside the temporary folder
    script.write_text(code.replace('"runs/', f'"{tmp_path}/runs/'))
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONPATH": str(ROOT)}  # test this checkout
    proc = subprocess.run(
        [sys.executable, str(script)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
        env=env,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.strip(), "an example prints what it shows"


def test_shlex_of_commands_is_valid():
    for text in (README, *DOCS.values()):
        for block in re.findall(r"```bash\n(.*?)```", text, flags=re.S):
            shlex.split(block)


@pytest.mark.parametrize("name", ["README.md", *(f"docs/{n}" for n in DOCS)])
def test_relative_links_resolve(name):
    """Every relative Markdown link of the README and of docs/ names a file of the repo."""
    path = ROOT / name
    links = re.findall(r"\]\(([^)#:\s]+)(?:#[^)]*)?\)", path.read_text())
    missing = [link for link in links if not (path.parent / link).exists()]
    assert not missing, missing


def test_readme_links_the_gait_log():
    assert "docs/gait.md" in README and "gait.md" in DOCS
