"""The README and docs/ are tested as documentation.

- Each printed output they show (a ``text`` block after an ``<!-- output: COMMAND -->`` marker) is what the
  program prints now: the command runs as docs/outputs.py runs it (which rewrites the blocks), and the block
  must equal its output.  A ``text`` block of program output without a marker fails.
- A Markdown page with ``>>>`` prompts is a self-contained doctest: its prompts (imports included) run in
  order in one fresh namespace, from the repository root, and each output must match (doctest's ELLIPSIS and
  NORMALIZE_WHITESPACE).  docs/examples/index.md, the notebook guide, is one.
"""

from __future__ import annotations

import doctest
import importlib.util
import os
import re
from pathlib import Path

import pytest

from conftest import ROOT

spec = importlib.util.spec_from_file_location("docs_outputs", ROOT / "docs" / "outputs.py")
outputs = importlib.util.module_from_spec(spec)
spec.loader.exec_module(outputs)

PAGES = outputs.pages()
MARKED = [(page, command, body) for page in PAGES for command, body in outputs.blocks(page.read_text("utf-8"))]
FENCE = re.compile(r"^```(\w*)\n(.*?)^```", re.S | re.M)
DOCTESTS = [page for page in PAGES if ">>>" in page.read_text("utf-8")]


@pytest.mark.parametrize("page, command, body", MARKED, ids=[f"{p.relative_to(ROOT)}:{c[:40]}" for p, c, _ in MARKED])
def test_printed_output_is_the_programs(page, command, body):
    """The block shows exactly what its command prints now (regenerate: python docs/outputs.py)."""
    assert outputs.printed(command) == body, f"{page.relative_to(ROOT)}: stale output of {command!r}"


def test_every_output_block_is_marked():
    """Every ``text`` block in README.md and docs/ is either a doctest (``>>>``) or marked with the command
    that prints it; there is at least one marked block (so the test above tests something)."""
    unmarked = []
    for page in PAGES:
        text = page.read_text("utf-8")
        for m in FENCE.finditer(text):
            if m[1] == "text" and ">>>" not in m[2] and not text[: m.start()].rstrip().endswith("-->"):
                unmarked.append(f"{page.relative_to(ROOT)}:{text[: m.start()].count(chr(10)) + 1}")
    assert not unmarked, f"text blocks without an <!-- output: ... --> marker: {unmarked}"
    assert len(MARKED) >= 3


def test_a_stale_block_is_caught():
    """Planted: a block whose command prints something else is found (and docs/outputs.py rewrites it)."""
    page = '<!-- output: echo "P 107.0 N" -->\n```text\nP 101.0 N\n```\n'
    ((command, body),) = outputs.blocks(page)
    assert outputs.printed(command) != body
    assert outputs.rewrite(page) == '<!-- output: echo "P 107.0 N" -->\n```text\nP 107.0 N\n```\n'


def doctest_text(page: Path) -> str:
    """The fenced blocks of ``page`` that hold ``>>>`` prompts, in order, as one doctest text."""
    return "\n\n".join(m[2] for m in FENCE.finditer(page.read_text("utf-8")) if ">>>" in m[2])


@pytest.mark.parametrize("page", DOCTESTS, ids=[p.relative_to(ROOT).as_posix() for p in DOCTESTS])
def test_markdown_prompts_run(page, monkeypatch):
    """Every ``>>>`` prompt of the page runs, in a fresh namespace from the repository root, and prints what
    the page shows."""
    monkeypatch.chdir(ROOT)
    monkeypatch.setitem(os.environ, "COLUMNS", "80")
    name = page.relative_to(ROOT).as_posix()
    test = doctest.DocTestParser().get_doctest(doctest_text(page), {}, name, str(page), 0)
    assert test.examples, f"{name}: no prompts"
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    report = []
    runner.run(test, out=report.append)
    assert runner.failures == 0, "".join(report)


def test_the_notebook_guide_is_a_doctest():
    """docs/examples/index.md shows the Python API with prompts (and imports designer in its own prompts)."""
    assert ROOT / "docs" / "examples" / "index.md" in DOCTESTS
    text = doctest_text(ROOT / "docs" / "examples" / "index.md")
    assert text.lstrip().startswith(">>> import designer")


def test_a_failing_prompt_is_caught():
    """Planted: a prompt whose output differs fails the doctest (the runner above is not blind)."""
    test = doctest.DocTestParser().get_doctest(">>> 1 + 1\n3\n", {}, "planted", "planted", 0)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    runner.run(test, out=lambda _: None)
    assert runner.failures == 1
