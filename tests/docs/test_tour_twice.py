"""The README's tour pasted twice: in a copy of the checkout made a git repository of its own, every line of the
tour exits 0 the first time and the second (``designer init`` never replaces a file, so the tour's line keeps
the one written the first time), and ``git status --porcelain`` is empty after both (every file the tour writes
is ignored)."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import ROOT

GIT = shutil.which("git")
SETUP = re.compile(r"^(python3 -m venv \S+|\S*pip install .*)$")
"""A step that sets the environment up: not run (the test's interpreter stands for the README's install)."""


def tour_lines() -> list[str]:
    """The lines of the README's tour, comments removed, each without its set-up steps; the studio (a server,
    tested by tests/docs/test_readme.py) left out."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    block = readme.split("## A ten-line tour", 1)[1].split("```bash", 1)[1].split("```", 1)[0]
    out = []
    for line in block.strip().splitlines():
        command = re.sub(r"\s+#.*$", "", line).strip()
        steps = [s.strip() for s in command.split("&&") if not SETUP.match(s.strip())]
        command = " && ".join(steps)
        if command and not command.endswith("designer studio"):
            out.append(command)
    return out


def _git(folder: Path, *args: str) -> str:
    done = subprocess.run([GIT, *args], cwd=folder, capture_output=True, text=True, check=True)
    return done.stdout


@pytest.fixture
def clone(tmp_path):
    """The checkout's tracked files (as they are in the work tree) in a new git repository, committed, with
    ``.venv`` naming this suite's interpreter and this checkout's package first on the path."""
    if GIT is None:
        pytest.fail("git is needed to check that the tour leaves the checkout clean")
    names = _git(ROOT, "ls-files", "-z").split("\0")
    folder = tmp_path / "checkout"
    for name in filter(None, names):
        source = ROOT / name
        if source.is_file():
            (folder / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(source, folder / name)
    _git(folder, "init", "-q")
    _git(folder, "add", "-A")
    _git(folder, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", "checkout")
    (folder / ".venv").symlink_to(Path(sys.executable).parent.parent)
    env = {k: v for k, v in os.environ.items() if k != "VIRTUAL_ENV"}
    return folder, env | {"PYTHONPATH": str(folder), "COLUMNS": "80"}


def test_the_tour_twice_in_a_fresh_checkout_leaves_it_clean(clone):
    """Each tour line exits 0 both times, and the checkout's git status is empty after each pass."""
    folder, env = clone
    lines = tour_lines()
    assert any("init my-chair.toml" in line for line in lines) and len(lines) >= 8
    for attempt in (1, 2):
        for line in lines:
            done = subprocess.run(["bash", "-c", line], cwd=folder, env=env, capture_output=True, text=True)
            assert done.returncode == 0, f"pass {attempt}: {line}: exit {done.returncode}\n{done.stderr[-2000:]}"
        assert _git(folder, "status", "--porcelain") == "", f"pass {attempt} changed the checkout"
    assert (folder / "my-chair.toml").is_file()


def test_spec_leaves_the_checkout_clean(clone):
    """``designer spec problems/indoor-manual.toml`` writes its sheet beside the problem's report, and git
    ignores it: the checkout stays clean."""
    folder, env = clone
    command = ".venv/bin/designer spec problems/indoor-manual.toml"
    done = subprocess.run(["bash", "-c", command], cwd=folder, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert (folder / "results" / "indoor-manual" / "spec.html").is_file()
    assert _git(folder, "status", "--porcelain") == ""
