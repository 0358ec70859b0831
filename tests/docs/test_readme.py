"""The README works as written: it fits a screen or two, keeps the two commands, and every shell command in it
runs in a fresh shell and passes.

How the shell commands run: each line of its ``bash`` blocks in ``bash -c``, with a PATH that holds no
virtual environment (a fresh shell: nothing activated), from a temporary folder holding ``problems/`` and
``.venv`` (a link to the interpreter this suite runs in: after the README's install that is what
``.venv/bin/...`` names).  The ``pip install`` and ``python3 -m venv`` steps of a line are not run: creating a
venv and installing every extra again would take minutes of the CI's 30 (the extras are installed in the test
venv: ``.[test]`` holds dash, pandas and mkdocs); the rest of the line runs as written.  The test line's
``pytest`` is this suite itself and is checked as text.  ``designer studio`` is a server: it must print its
URL, answer it, and stop cleanly on Ctrl-C (exit 0).
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import signal
import subprocess
import sys
import urllib.request
from pathlib import Path

import pytest

from conftest import ROOT

README = (ROOT / "README.md").read_text(encoding="utf-8")
MAIN_JOB = (
    "python3 -m venv .venv && .venv/bin/pip install -e . && .venv/bin/designer pareto problems/indoor-manual.toml"
)
TESTS = (
    'python3 -m venv .venv && .venv/bin/pip install -e ".[test]" -c constraints.txt && '
    ".venv/bin/python -m pytest -n auto --dist loadscope"
)
SETUP = re.compile(r"^(python3 -m venv \S+|\S*pip install .*)$")
"""A step of a line that sets the environment up (not run here; see the module's docstring)."""


def shell_lines() -> list[str]:
    """Every command line of the README's ``bash`` blocks, comments removed."""
    lines = []
    for block in re.findall(r"^```bash\n(.*?)^```", README, flags=re.S | re.M):
        for line in block.splitlines():
            command = re.sub(r"\s+#.*$", "", line).strip()
            if command and not command.startswith("#"):
                lines.append(command)
    return lines


LINES = shell_lines()


def test_readme_fits_a_screen_or_two():
    """At most 150 lines, with the two commands exactly as the project promises them."""
    assert len(README.splitlines()) <= 150
    assert MAIN_JOB in LINES and TESTS in LINES


def test_every_command_names_the_venv():
    """No line relies on an activated venv: ``designer``, ``python`` and ``pip`` are written ``.venv/bin/...``."""
    bare = [
        line
        for line in LINES
        for step in line.split("&&")
        if re.match(r"\s*(designer|python|pip|mkdocs|pytest)\b", step)
    ]
    assert bare == []


@pytest.fixture
def fresh(tmp_path):
    """(folder, environment) of a fresh shell in a folder holding problems/ and .venv."""
    (tmp_path / "problems").symlink_to(ROOT / "problems")
    (tmp_path / ".venv").symlink_to(Path(sys.executable).parent.parent)
    venv = str(Path(sys.executable).parent)
    path = os.pathsep.join(p for p in os.environ.get("PATH", "").split(os.pathsep) if p and p != venv)
    env = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "PYTHONPATH")}
    return tmp_path, env | {"PATH": path, "COLUMNS": "80"}


def runnable(line: str) -> str:
    """``line`` without its set-up steps."""
    return " && ".join(s.strip() for s in line.split("&&") if not SETUP.match(s.strip()))


@pytest.mark.parametrize("line", LINES, ids=[line[:60] for line in LINES])
def test_shell_command_runs_in_a_fresh_shell(line, fresh):
    """The line (its set-up steps aside) exits 0 in a fresh shell."""
    folder, env = fresh
    command = runnable(line)
    if command == ".venv/bin/python -m pytest -n auto --dist loadscope":
        return  # the suite running this test
    if command.endswith("designer studio"):
        proc = subprocess.Popen(
            ["bash", "-c", f"exec {command} --port 0 --no-browser"],
            cwd=folder,
            env=env,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        try:
            url = re.search(r"http://127\.0\.0\.1:\d+/", proc.stdout.readline())
            assert url
            with urllib.request.urlopen(url.group(0), timeout=60) as page:  # serving
                assert page.status == 200
        finally:
            proc.send_signal(signal.SIGINT)
        assert proc.wait(60) == 0, proc.stderr.read()
        return
    done = subprocess.run(["bash", "-c", command], cwd=folder, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, f"{command}: exit {done.returncode}\n{done.stderr[-2000:]}"
    assert done.stdout.strip()


def test_a_bare_command_fails_in_a_fresh_shell(fresh):
    """Planted: ``designer --version`` without ``.venv/bin/`` is not found in such a shell (exit 127), so the
    runs above do test the paths as written."""
    folder, env = fresh
    done = subprocess.run(["bash", "-c", "designer --version"], cwd=folder, env=env, capture_output=True, text=True)
    assert done.returncode == 127


def test_readme_python_example_runs():
    """Every ```python block of the README executes and prints V_c = 2.91 m/s (Eq. 8's wheel) first."""
    blocks = re.findall(r"```python\n(.*?)```", README, flags=re.S)
    assert blocks, "README has no python example"
    out = io.StringIO()
    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        with contextlib.redirect_stdout(out):
            for block in blocks:
                exec(compile(block, "README.md", "exec"), {})
    finally:
        os.chdir(cwd)
    assert out.getvalue().splitlines()[0] == "2.91"


def test_public_api_names():
    """docs/commands.md#python-api: the loader, the design dataclass, optimise, pareto_front, explore and
    write_report come from ``import designer`` (the last two imported lazily)."""
    import designer

    for name in (
        "load_problem",
        "Design",
        "Conditions",
        "evaluate",
        "performance",
        "optimise",
        "pareto_front",
        "explore",
        "write_report",
        "report_data",
        "Uncertainty",
    ):
        assert callable(getattr(designer, name)), name
    assert designer.write_report.__module__.startswith("designer.report")
    assert designer.report_data.__module__ == "designer.pipeline"
    assert designer.explore.__module__.startswith("designer.studies.explore")
