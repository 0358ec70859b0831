"""Issue 12.6: the docs ship with the package's source; every problem-file key the loader accepts is
documented, and code and report templates cite docs/, not an internal spec."""

from __future__ import annotations

import re

from designer.problem import SCHEMA

from conftest import ROOT


def test_every_loader_key_is_in_the_problem_file_reference():
    """Each key of designer.problem.SCHEMA appears in docs/problem-file.md as `section.key`
    (top-level keys as `key`); a key added to the loader without its documentation fails here."""
    text = (ROOT / "docs" / "problem-file.md").read_text(encoding="utf-8")
    missing = [
        f"{section}.{key}" if section else key
        for section, keys in SCHEMA.items()
        for key in keys
        if f"`{section + '.' if section else ''}{key}`" not in text
    ]
    assert not missing, f"undocumented problem-file keys: {missing}"
    for section in SCHEMA:
        if section:
            assert f"## [{section}]" in text, section


def test_no_internal_spec_citations():
    """No "DESIGN §" citation in the package or its report templates: they point to docs/ instead, and
    every docs/ file they cite exists."""
    offenders, cited = [], set()
    for path in (ROOT / "designer").rglob("*"):
        if path.suffix in (".py", ".j2", ".md", ".toml") and path.is_file():
            text = path.read_text(encoding="utf-8")
            if re.search(r"DESIGN(\.md)?`? ?§", text):
                offenders.append(str(path.relative_to(ROOT)))
            cited.update(re.findall(r"docs/([a-z0-9_-]+\.md)", text))
    assert not offenders
    assert cited and all((ROOT / "docs" / name).is_file() for name in cited), cited


def test_docs_cover_the_model_equations_and_checks():
    """docs/model.md names every equation the physics modules cite; docs/checks.md every check of validate."""
    model = (ROOT / "docs" / "model.md").read_text(encoding="utf-8")
    cited = set()
    for path in (ROOT / "designer" / "physics").glob("*.py"):
        cited.update(re.findall(r"Eq\. (\d+[A-C]?)", path.read_text(encoding="utf-8")))
    missing = sorted(e for e in cited if not re.search(rf"Eq\. {e}\b", model))
    assert not missing, f"equations cited in designer/physics but not in docs/model.md: {missing}"
    from designer.analysis.checks import paper_checks

    checks = (ROOT / "docs" / "checks.md").read_text(encoding="utf-8")
    for c in paper_checks():
        assert f"### {c.name}" in checks, c.name
