"""Code habits: ruff and mypy pass (when installed: .ci/run runs them anyway), and long functions say why."""

from __future__ import annotations

import ast
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "designer"

MAX_FUNCTION_LINES = 80
"""A function longer than this says why on its ``def`` line.  Modules have no line cap: a module is as long as
its one purpose needs, and tests/test_architecture.py keeps the rooms cohesive (no prefix clusters, no private
name across rooms)."""


def _tool(name: str) -> str:
    path = Path(sys.executable).with_name(name)
    found = str(path) if path.exists() else shutil.which(name)
    if not found:
        pytest.skip(f"{name} is not installed (pip install -e '.[test]'); .ci/run runs it")
    return found


def test_ruff_check_passes():
    """``ruff check .`` finds nothing with the rules of pyproject.toml."""
    result = subprocess.run([_tool("ruff"), "check", "--quiet", "."], cwd=ROOT, capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr


def test_ruff_format_passes():
    """``ruff format --check .`` would change nothing: the code is in the formatter's layout (tables excepted
    with ``# fmt: off``)."""
    result = subprocess.run([_tool("ruff"), "format", "--check", "."], cwd=ROOT, capture_output=True, text=True)
    assert result.returncode == 0, result.stdout + result.stderr


def test_mypy_passes():
    """``mypy`` (files and strictness from pyproject.toml) finds no error."""
    result = subprocess.run([_tool("mypy")], cwd=ROOT, capture_output=True, text=True)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr


def _modules():
    return sorted(PACKAGE.rglob("*.py"))


def test_long_functions_say_why():
    """A function over 80 lines has a comment on its ``def`` line (or the line above) saying why."""
    unexplained = []
    for path in _modules():
        lines = path.read_text(encoding="utf-8").splitlines()
        for node in ast.walk(ast.parse("\n".join(lines))):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                if node.end_lineno - node.lineno + 1 > MAX_FUNCTION_LINES:
                    first = node.decorator_list[0].lineno if node.decorator_list else node.lineno
                    window = " ".join(lines[first - 2 : node.lineno])
                    if "#" not in window:
                        unexplained.append(f"{path.relative_to(PACKAGE)}:{node.lineno} {node.name}")
    assert unexplained == []
