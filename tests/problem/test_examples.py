"""designer.example_problem: the repository's problems/*.toml shipped as package data (issue 17)."""

from __future__ import annotations

import dataclasses
import fnmatch
import tomllib
from pathlib import Path

import pytest

import designer
from designer.errors import ProblemError

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = ROOT / "designer" / "data" / "problems"


def test_example_problem_equals_the_repository_file():
    """example_problem("indoor-manual") is the problem problems/indoor-manual.toml gives (source aside)."""
    shipped = designer.example_problem("indoor-manual")
    from_file = designer.load_problem(ROOT / "problems" / "indoor-manual.toml")
    assert shipped.source is None
    assert shipped == dataclasses.replace(from_file, source=None)
    assert shipped.name == "indoor-manual" and shipped.target_speed == 2.5


def test_every_problem_file_is_shipped_byte_equal():
    """designer/data/problems/ holds exactly the files of problems/, byte for byte (copy them after an edit)."""
    repo = {p.name: p.read_bytes() for p in (ROOT / "problems").glob("*.toml")}
    shipped = {p.name: p.read_bytes() for p in SHIPPED.glob("*.toml")}
    assert sorted(shipped) == sorted(repo), "copy problems/*.toml to designer/data/problems/"
    stale = [name for name in repo if repo[name] != shipped[name]]
    assert stale == [], f"designer/data/problems/ is stale, copy problems/{stale[0]} there"
    assert designer.example_names() == sorted(name[:-5] for name in repo)


@pytest.mark.parametrize("name", sorted(p.stem for p in SHIPPED.glob("*.toml")))
def test_each_example_loads(name):
    """Every shipped example is a valid problem named after its file."""
    problem = designer.example_problem(name)
    assert problem.name == name
    assert problem.target_speed > 0


def test_unknown_name_is_a_one_line_error_listing_the_names():
    """An unknown name raises ProblemError on one line that names the value and lists every shipped name."""
    with pytest.raises(ProblemError) as info:
        designer.example_problem("indoor-manul")
    message = str(info.value)
    assert "\n" not in message
    assert "'indoor-manul'" in message
    for name in designer.example_names():
        assert name in message


def test_package_data_ships_the_problem_files():
    """pyproject's package-data globs cover every shipped TOML, so a non-editable install (a wheel) has them."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    patterns = config["tool"]["setuptools"]["package-data"]["designer"]
    files = [p.relative_to(ROOT / "designer").as_posix() for p in SHIPPED.glob("*.toml")]
    assert files
    uncovered = [f for f in files if not any(fnmatch.fnmatch(f, pattern) for pattern in patterns)]
    assert uncovered == []
