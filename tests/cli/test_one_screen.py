"""One screen by default: each command of the README's tour and of docs/commands.md, with its shipped example at
COLUMNS=80, answers ``run``, ``fix``, ``fleet`` and ``evaluate`` in at most 24 lines and ``validate`` in at most
45 (standard output and standard error together, warnings included), no line wider than 80 columns; and no
first screen speaks the tool's own jargon."""

from __future__ import annotations

import io
import re
import shlex
import shutil

import pytest

from designer.cli import main

from conftest import ROOT

SCREEN = 24
"""Lines of one terminal screen: the most ``run``, ``fix``, ``fleet`` and ``evaluate`` print by default."""
VALIDATE_LINES = 45
"""The most ``validate`` prints by default (about 40: eleven checks, two lines each, and their headings)."""
LIMITS = {"run": SCREEN, "fix": SCREEN, "fleet": SCREEN, "evaluate": SCREEN, "validate": VALIDATE_LINES}

JARGON = re.compile(r"\bJ =|\bknee\b|risk-bounded|\bIPOPT\b|\bSLSQP\b|\bduals?\b|multiplier|\bNLP\b|margin \+")
"""Words of the solver and the workshop that a first screen never uses (the plain sentence says what they mean)."""


def tour_commands() -> list[list[str]]:
    """The ``designer`` commands of the README's tour, in order, as argument lists (the installs, the studio
    (a server) and the Python line left out)."""
    text = (ROOT / "README.md").read_text()
    block = text.split("## A ten-line tour", 1)[1].split("```bash", 1)[1].split("```", 1)[0]
    out = []
    for line in block.strip().splitlines():
        lexer = shlex.shlex(line, posix=True, punctuation_chars=True)
        lexer.whitespace_split = True
        lexer.commenters = "#"
        words: list[str] = []
        for token in [*lexer, ";"]:
            if token not in ("&&", "||", ";", "[", "]"):
                words.append(token)
                continue
            if words and words[0].endswith("bin/designer") and words[1:2] != ["studio"]:
                out.append(words[1:])
            words = []
    return out


def commands_examples() -> list[list[str]]:
    """The shipped example of each command docs/commands.md lists for the first screen's commands (its table's
    first column, PROBLEM as the shipped indoor-manual problem)."""
    return [
        ["run", "problems/indoor-manual.toml"],
        ["evaluate", "--trail", "2in", "--diameter", "8in", "--groove", "0", "--damping", "1.3"],
        [
            "evaluate",
            "--trail",
            "2in",
            "--diameter",
            "8in",
            "--groove",
            "0",
            "--damping",
            "1.3",
            "--target-speed",
            "3m/s",
        ],
        ["validate"],
        ["fix", "problems/indoor-manual.toml", "--current", "T=1.5in,d=7.75in,B=0.5625in,c=1.3"],
        ["fix", "problems/indoor-manual.toml", "--current", "T=2.5in,d=7in,B=0.75in,c=1.3"],
        ["fleet", "--example", "200"],
        ["fleet", "fleet-example-200.csv"],
    ]


def _lines(argv: list[str], capsys) -> list[str]:
    """What ``designer ARGV`` prints on standard output and standard error together, line by line."""
    try:
        code = main(argv)
    except SystemExit as exc:  # --help
        code = exc.code
    out, err = capsys.readouterr()
    assert code == 0, (argv, err)
    return (out + err).splitlines()


@pytest.fixture
def checkout(tmp_path, monkeypatch):
    """A folder holding the shipped problems, as the checkout the tour is pasted in, at 80 columns."""
    shutil.copytree(ROOT / "problems", tmp_path / "problems")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("COLUMNS", "80")
    monkeypatch.setattr("sys.stdin", io.StringIO(""))
    return tmp_path


def test_the_tour_is_parsed():
    """The README's tour yields the commands the one-screen test runs (a changed tour keeps them covered)."""
    verbs = [argv[0] for argv in tour_commands()]
    for verb in ("run", "init", "evaluate", "fix", "fleet", "validate", "pareto", "--help"):
        assert verb in verbs, verbs


def test_the_tour_and_the_commands_fit_one_screen(checkout, capsys):
    """Every command of the README's tour, then each docs/commands.md example of run, fix, fleet, evaluate and
    validate: at most 24 lines (validate 45), every line at most 80 columns (an absolute path alone excepted),
    and the first screen of run, fix, fleet and evaluate free of J, knee, risk-bounded and solver words."""
    seen = set()
    for argv in tour_commands() + commands_examples():
        lines = _lines(argv, capsys)
        verb = argv[0]
        wide = [ln for ln in lines if len(ln) > 80 and not ln.strip().startswith("/")]
        assert wide == [], (argv, wide)
        if verb in LIMITS:
            seen.add(verb)
            assert len(lines) <= LIMITS[verb], (argv, len(lines), lines)
        if verb in ("run", "fix", "fleet", "evaluate"):
            jargon = [ln for ln in lines if JARGON.search(ln)]
            assert jargon == [], (argv, jargon)
    assert seen == set(LIMITS)


def test_run_answers_first_in_the_problems_units(checkout, capsys):
    """``designer run`` names the caster to build first, says why in plain words, what it costs and what to do
    next; on a problem written in millimetres by ``designer init --units mm`` it prints no inch value."""
    lines = _lines(["run", "problems/indoor-manual.toml"], capsys)
    assert lines[1].startswith("The caster to build: a 7 in wheel with a 3/4 in groove")
    text = " ".join(" ".join(lines).split())
    for head in ("Why: ", "Cost: turning effort F_turn 7.942 N, sill force P 106.96 N", "Next: "):
        assert head in text
    assert "easiest to turn: 5 in wheel" in text
    _lines(["init", "mm.toml", "--units", "mm", "--defaults"], capsys)
    lines = _lines(["run", "mm.toml"], capsys)
    text = " ".join(lines)
    assert not re.search(r"\d in\b|\binch", text), lines
    assert "T 63.50 mm, d 177.80 mm, B 19.05 mm" in text and "a 12.7 mm sill" in text


def test_fix_on_a_caster_that_needs_nothing_says_so_briefly(checkout, capsys):
    """``designer fix`` on the caster ``run`` recommends: one or two lines, its risk against the bound, and
    neither "Next: fit the parts" nor the count of other fixes."""
    lines = _lines(["fix", "indoor-manual", "--current", "T=2.5in,d=7in,B=0.75in,c=1.3"], capsys)
    assert 1 <= len(lines) <= 2
    text = " ".join(lines)
    assert text.startswith("No fix needed: ") and "2.98 % (allowed 5 %)" in text
    assert "Next:" not in text and "0 more" not in text
