"""Output at the terminal's width: at COLUMNS=80 no line any command prints (each with its shipped example) is
wider than 80 or ends in a space, tables stay whole; the one wrap rule (designer/cli/_terminal.py)."""

from __future__ import annotations

import io
from pathlib import Path

import pytest

from designer.cli import COMMANDS, main
from designer.cli._terminal import Fitted, fit, fit_line, width

from conftest import ROOT

_CURRENT = "T=1.5in,d=7.75in,B=0.5625in,c=1.3"


def _examples() -> dict[str, list[list[str]]]:
    """Each command's shipped example (README, docs/commands.md), made quick where it has a size option, its
    files named relative to the folder it runs in (a path longer than the width is one word); the studio (a
    server) and the completion script (read by the shell) by their help."""
    return {
        "init": [["init", "new.toml"]],
        "evaluate": [
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
        ],
        "validate": [["validate"]],
        "run": [["run", "indoor-manual"]],
        "pareto": [["pareto", "indoor-manual", "--points", "5", "--out", "p"]],
        "explore": [["explore", "indoor-manual", "--trials", "12", "--out", "e"]],
        "robust": [["robust", "indoor-manual-robust", "--points", "3", "--out", "r"]],
        "simulate": [["simulate", "--trail", "2in", "--speed", "2m/s"]],
        "calibrate": [["calibrate", "damping", str(ROOT / "designer/data/examples/damping.csv")]],
        "fleet": [
            ["fleet", "--example", "6", "--out", "fleet.csv"],
            ["fleet", "fleet.csv", "--no-skus", "--out", "f"],
        ],
        "studio": [["studio", "--help"]],
        "spec": [["spec", "indoor-manual", "--out", "spec.html"]],
        "inspect": [
            ["inspect", "indoor-manual", "--template", "measured.csv"],
            ["inspect", "indoor-manual", str(ROOT / "docs/examples/measured-casters.csv")],
        ],
        "fix": [
            ["fix", "indoor-manual", "--current", _CURRENT, "--inertia", "0.00127"],
            ["fix", "indoor-manual", "--current", _CURRENT],
        ],
        "completion": [["completion", "--help"]],
    }


def _run(argv: list[str], capsys) -> list[str]:
    """The lines ``designer ARGV`` prints on standard output and standard error (``--help`` exits 0)."""
    try:
        code = main(argv)
    except SystemExit as exc:  # --help
        code = exc.code
    out, err = capsys.readouterr()
    assert code in (0, 1), (argv, code, err)  # validate exits 1 only when a check fails
    return (out + err).splitlines()


def _a_path(line: str) -> bool:
    """True for a line that is one file's absolute path alone (``open:`` on the line above it): one word,
    left whole so that it can be copied or clicked, however deep the folder."""
    word = line.strip()
    return " " not in word and word.startswith("/") and Path(word).exists()


def test_every_command_has_an_example():
    """The width test below covers every sub-command (a new one needs its example here)."""
    assert sorted(_examples()) == sorted(COMMANDS)


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_output_fits_80_columns(command, tmp_path, monkeypatch, capsys):
    """At COLUMNS=80 every line printed is at most 80 characters (but an absolute path alone on its line) and
    none ends in a space; a box-drawn table's lines all have its border's width (a table is never wrapped);
    ``designer --help`` too."""
    monkeypatch.setenv("COLUMNS", "80")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr("sys.stdin", io.StringIO(""))
    runs = _examples()[command] + ([["--help"]] if command == "init" else [])
    for argv in runs:
        lines = _run(argv, capsys)
        assert lines, argv
        wide = [ln for ln in lines if len(ln) > 80 and not _a_path(ln)]
        assert wide == [], (argv, wide[:3])
        assert [ln for ln in lines if ln != ln.rstrip()] == [], argv
        border = None
        for ln in lines:
            if ln.startswith(("┏", "┌")):
                border = len(ln)
            elif border is not None and ln.startswith(("┃", "│", "┡", "├", "└")):
                assert len(ln) == border, (argv, ln)


def test_fit_wraps_at_words():
    """The wrap rule, planted: a 120-character line becomes lines of at most 80 at word boundaries, continued
    two columns in; a comment stays a comment; trailing spaces go; a long word is left whole."""
    words = " ".join(f"word{i:02d}" for i in range(20))  # 20 words of 6 + 19 spaces = 139
    lines = fit(f"  {words}   ", 80).split("\n")
    assert len(lines) == 2 and all(len(ln) <= 80 for ln in lines)
    assert lines[0].startswith("  word00") and lines[1].startswith("    word")
    assert " ".join(" ".join(lines).split()) == words
    assert all(ln.startswith("# ") for ln in fit("# " + words, 80).split("\n"))
    assert fit_line("x" * 100, 80) == "x" * 100
    assert fit_line("table row   \x1b[0m", 80) == "table row\x1b[0m"


def test_a_number_keeps_its_unit():
    """A wrapped line never ends in a number whose unit starts the next line ("4.9" / "% ..."): each number
    and unit break together, and the text is unchanged apart from the breaks."""
    for unit in ("%", "m/s", "N", "in", "N·m/rad", "kg·m²", "mm", "°"):
        for pad in range(60, 80):
            line = "x" * pad + f" 12.5 {unit} and then some more words to wrap"
            lines = fit_line(line, 80).split("\n")
            assert all(len(ln) <= 80 for ln in lines)
            assert f"12.5 {unit}" in "\n".join(lines), (pad, unit, lines)
            assert " ".join(" ".join(lines).split()) == " ".join(line.split())


def test_the_console_keeps_a_number_with_its_unit(monkeypatch, capsys):
    """Prose printed by the commands' rich console wraps at the width without parting a number from its unit or
    'Eq.' from its number, and the character that joins them while rich wraps never reaches the output."""
    from designer.cli._terminal import console

    monkeypatch.setenv("COLUMNS", "80")
    for pad in range(60, 80):
        console().print("x" * pad + " by 16.4 % (predicted lower), see Eq. 7 and more words to wrap")
        out = capsys.readouterr().out
        assert "16.4 %" in out and "Eq. 7" in out and "\ue000" not in out, (pad, out)
        assert all(len(line) <= 80 for line in out.splitlines())


def test_fitted_stream(monkeypatch):
    """The stream holds a partial line (a prompt) until flush and fits each whole line; COLUMNS sets the
    width, at least 40."""
    sink = io.StringIO()
    stream = Fitted(sink, 40)
    stream.write("a " * 30)
    assert sink.getvalue() == ""
    stream.write("\nprompt: ")
    stream.flush()
    assert sink.getvalue().split("\n")[:2] == [("a " * 20).strip(), ("  " + "a " * 10).rstrip()]
    assert sink.getvalue().endswith("prompt: ")
    monkeypatch.setenv("COLUMNS", "120")
    assert width() == 120 and width(wide=True) == 150
    monkeypatch.setenv("COLUMNS", "10")
    assert width() == 40
