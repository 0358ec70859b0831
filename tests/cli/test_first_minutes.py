"""The first minutes with the command line: "did you mean" for misspelled options and commands, shell
completion, and ``designer init`` (a commented problem file that ``designer run`` accepts)."""

from __future__ import annotations

import io
import re
import shutil
import subprocess
import tomllib

import pytest

from designer.cli import COMMANDS, build_parser, main
from designer.cli._parser import suggestion
from designer.problem import load_problem
from designer.units import INCH


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (
            ["evaluate", "--trial", "2in", "--diameter", "8in", "--groove", "0", "--damping", "1.3"],
            "unrecognized option --trial; did you mean '--trail'?",
        ),
        (["pareto", "indoor-manual", "--piont", "21"], "unrecognized option --piont; did you mean '--points'?"),
        (["pareto", "indoor-manual", "--piont=21"], "unrecognized option --piont; did you mean '--points'?"),
        (["evalute", "--trail", "2in"], "unknown command 'evalute'; did you mean 'evaluate'?"),
        (["--verison"], "unrecognized option --verison; did you mean '--version'?"),
        (["run", "indoor-manual", "--jsno"], "unrecognized option --jsno; did you mean '--json'?"),
    ],
)
def test_misspelled_option_is_named(argv, fragment, capsys):
    """A misspelled option or sub-command exits 2 with one line naming it and the closest valid one (the
    required option it was meant to be is not reported missing instead)."""
    with pytest.raises(SystemExit) as info:
        main(argv)
    assert info.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and fragment in err, err
    assert "required" not in err


def test_no_suggestion_for_an_unrelated_word(capsys):
    """An option like no valid one gets no guess; argparse's own abbreviations still work (``--tri`` is
    ``--trials``)."""
    with pytest.raises(SystemExit):
        main(["run", "indoor-manual", "--zzz"])
    err = capsys.readouterr().err
    assert "unrecognized option --zzz" in err and "did you mean" not in err
    assert suggestion("--zzz", ["--json", "--weights"]) == ""
    args = build_parser().parse_args(["explore", "indoor-manual", "--tri", "3"])
    assert args.trials == 3


@pytest.mark.parametrize("shell", ["bash", "zsh", "fish"])
def test_completion_script(shell, capsys):
    """``designer completion SHELL`` prints a script naming every sub-command and their options (one from
    each command checked: evaluate's --trail, pareto's --points, init's --front-fraction)."""
    assert main(["completion", shell]) == 0
    script = capsys.readouterr().out
    for name in COMMANDS:
        assert name in script, name
    for option in ("--trail", "--points", "--front-fraction"):
        assert option.lstrip("-") in script, option


@pytest.mark.skipif(shutil.which("bash") is None, reason="needs bash")
def test_bash_completion_loads(tmp_path, capsys):
    """The bash script is valid bash: sourcing it registers the completion of ``designer``."""
    main(["completion", "bash"])
    script = tmp_path / "designer.bash"
    script.write_text(capsys.readouterr().out)
    done = subprocess.run(["bash", "-c", f"source {script} && complete -p designer"], capture_output=True, text=True)
    assert done.returncode == 0 and "designer" in done.stdout, done.stderr


def _keys_with_comments(text: str) -> tuple[set[str], set[str]]:
    """(every key the TOML ``text`` sets, the keys whose line has ``# key:`` directly above it)."""
    data = tomllib.loads(text)
    keys = {k for k, v in data.items() if not isinstance(v, dict)}
    keys |= {k for v in data.values() if isinstance(v, dict) for k in v}
    lines = text.splitlines()
    commented = set()
    for i, line in enumerate(lines):
        m = re.match(r"^(\w+) = ", line)
        if m and i > 0 and lines[i - 1].startswith(f"# {m.group(1)}:"):
            commented.add(m.group(1))
    return keys, commented


def test_init_then_run(tmp_path, monkeypatch, capsys):
    """``designer init`` without a terminal writes the defaults (the shipped indoor-manual problem's load,
    sill, floor, speed and the parts on offer), every key under a comment that explains it; ``designer run`` on
    it exits 0 and recommends a caster built from those parts."""
    monkeypatch.setattr("sys.stdin", io.StringIO(""))
    path = tmp_path / "my-chair.toml"
    assert main(["init", str(path)]) == 0
    text = path.read_text()
    keys, commented = _keys_with_comments(text)
    assert len(keys) >= 12 and keys == commented, keys - commented
    base, mine = load_problem("indoor-manual"), load_problem(path)
    assert mine.conditions.load == base.conditions.load and mine.target_speed == base.target_speed
    assert mine.conditions.threshold_height == pytest.approx(base.conditions.threshold_height, rel=1e-12)
    assert mine.bounds == base.bounds
    assert mine.stock.diameters == base.stock.diameters and mine.stock.dampings == base.stock.dampings
    assert mine.stock.trails == base.stock.trails and mine.stock.grooves == base.stock.grooves
    capsys.readouterr()
    assert main(["run", str(path), "--no-cross-check"]) == 0
    out = capsys.readouterr().out
    assert "The caster to build: a 7 in wheel with a 3/4 in groove" in out
    # a caster the shop can fit: the shipped stock's 7 in wheel and 3/4 in groove, as for indoor-manual
    assert "  T 2.500 in, d 7.000 in, B 0.750 in, c_f 1.30 N·m/rad" in out.splitlines()


def test_init_options_mass_and_mm(tmp_path, capsys):
    """Options answer the questions: 95 kg with f = 0.3 is L = 95 x 9.80665 x 0.3 / 2 = 139.7 N per caster;
    a 3/4 in sill written in mm (19.05 mm) loads back to 0.01905 m; the front fraction's comment gives its
    typical range."""
    path = tmp_path / "p.toml"
    argv = ["init", str(path), "--mass", "95kg", "--front-fraction", "0.3", "--sill", "3/4in", "--units", "mm"]
    assert main([*argv, "--floor", "carpet", "--target-speed", "2m/s", "--defaults"]) == 0
    text = path.read_text()
    assert 'threshold_height = "19.05 mm"' in text and "typically 0.2 to 0.4" in text
    p = load_problem(path)
    assert p.conditions.load == pytest.approx(95 * 9.80665 * 0.3 / 2, rel=1e-12)
    assert p.conditions.threshold_height == pytest.approx(0.75 * INCH, rel=1e-9)
    assert p.conditions.surface == "carpet" and p.target_speed == 2.0 and p.units == "mm"
    assert p.stock.diameters == pytest.approx(load_problem("indoor-manual").stock.diameters, rel=1e-9)
    out = capsys.readouterr().out
    assert "139.7 N per front caster" in out and "front fraction f = 0.3" in out and "is the default" not in out


def test_init_says_when_the_front_fraction_is_its_default(tmp_path, monkeypatch, capsys):
    """--mass without --front-fraction takes f = 0.4, and the answer says so with its typical range (the load
    depends on it as much as on the mass), in lines of at most 80 characters."""
    monkeypatch.chdir(tmp_path)  # a short path: the lines' width is the answer's, not the temporary folder's
    assert main(["init", "m.toml", "--mass", "110kg", "--defaults"]) == 0
    out = capsys.readouterr().out
    assert f"{110 * 9.80665 * 0.4 / 2:.1f} N per front caster" in out
    assert "f = 0.4 is the default (typically 0.2 to 0.4); weigh yours: --front-fraction" in out
    assert all(len(line) <= 80 for line in out.splitlines())


def test_init_interactive(tmp_path, monkeypatch, capsys):
    """At a terminal the questions are asked; an empty reply takes the default, a bad one is named and asked
    again (here the speed 'fast', then 3 m/s)."""
    replies = iter(["", "250 N", "", "carpet", "fast", "3 m/s", ""])
    monkeypatch.setattr("sys.stdin.isatty", lambda: True, raising=False)
    monkeypatch.setattr("builtins.input", lambda _prompt="": next(replies))
    path = tmp_path / "q.toml"
    assert main(["init", str(path)]) == 0
    assert "  'fast': not a number; e.g. 2.5 m/s" in capsys.readouterr().err.splitlines()
    p = load_problem(path)
    assert p.conditions.load == 250.0 and p.conditions.surface == "carpet" and p.target_speed == 3.0


@pytest.mark.parametrize(
    "extra, code, fragment",
    [
        (["--front-fraction", "0.3"], 2, "--front-fraction 0.3: needs --mass"),
        (["--mass", "95kg", "--front-fraction", "1.5"], 2, "--front-fraction 1.5: out of range 0–1 (above 0)"),
        (["--mass", "95kg", "--load", "200N"], 2, "--load and --mass"),
        (["--floor", "grass"], 2, "--floor grass: not a floor this tool knows: tile or carpet"),
        (["--sill", "5in"], 2, "--sill 5in: out of range 0.1–2 in"),
        (["--sill", "20in"], 2, "--sill 20in: out of range 0.1–2 in"),
        (["--sill", "60mm", "--units", "mm"], 2, "--sill 60mm: out of range 2.54–50.8 mm"),
    ],
)
def test_init_bad_answers(extra, code, fragment, tmp_path, capsys):
    """A bad option is one line naming it, exit 2, and no file is written."""
    path = tmp_path / "bad.toml"
    assert main(["init", str(path), "--defaults", *extra]) == code
    assert fragment in capsys.readouterr().err
    assert not path.exists()


def test_init_never_replaces(tmp_path, capsys):
    """An existing file is left as it is: exit 7 naming it."""
    path = tmp_path / "mine.toml"
    path.write_text("my notes\n")
    assert main(["init", str(path), "--defaults"]) == 7
    assert "exists" in capsys.readouterr().err and path.read_text() == "my notes\n"
    assert [p.name for p in tmp_path.iterdir()] == ["mine.toml"]


@pytest.mark.parametrize(
    "key, reply, reason",
    [
        ("front_fraction", "abc", "not a number; e.g. 0.3"),
        ("front_fraction", "1.5", "out of range 0–1 (above 0)"),
        ("sill", "grass", "not a number; e.g. 1/2 in or 13 mm"),
        ("sill", "cm", "not a number; e.g. 1/2 in or 13 mm"),
        ("sill", "mm", "not a number; e.g. 1/2 in or 13 mm"),
        ("sill", "20 in", "out of range 0.1–2 in"),
        ("sill", "5 kg", "not a length; e.g. 1/2 in or 13 mm"),
        ("mass", "5000 kg", "out of range 1–2e+03 kg"),
        ("floor", "grass", "not a floor this tool knows: tile or carpet"),
        ("units", "cm", "not a unit system it writes: in or mm"),
        ("sill", "3/4 in", None),
        ("front_fraction", "0.3", None),
    ],
)
def test_init_says_the_true_reason_of_a_bad_answer(key, reply, reason):
    """Each bad answer at the terminal is refused for what is wrong with it: a word for a number is "not a
    number" (not "a unit without a number"), a 20 in sill is "out of range" (not "inches written as metres")."""
    from designer.cli.init import reply_reason

    assert reply_reason(key, reply) == reason


def test_init_prompts_fit_and_name_no_option(tmp_path, monkeypatch, capsys):
    """Every question at the terminal, with its default, fits 80 columns and names no option (no "--"); bad
    replies are refused with their reason and asked again, then the file is written."""
    prompts = []
    replies = iter(["95 kg", "abc", "0.3", "20 in", "3/4 in", "grass", "tile", "", "cm", "mm"])

    def answer(prompt=""):
        prompts.append(prompt)
        return next(replies)

    monkeypatch.setattr("sys.stdin.isatty", lambda: True, raising=False)
    monkeypatch.setattr("builtins.input", answer)
    assert main(["init", str(tmp_path / "p.toml")]) == 0
    err = capsys.readouterr().err
    assert "'abc': not a number" in err and "'20 in': out of range 0.1–2 in" in err and "'cm': not a unit" in err
    assert len(prompts) == 10 and all(len(p) <= 80 and "--" not in p for p in prompts), prompts
    p = load_problem(tmp_path / "p.toml")
    assert p.units == "mm" and p.conditions.threshold_height == pytest.approx(0.75 * INCH, rel=1e-9)


def _options_with_choices() -> list[tuple[str, str, tuple[str, ...]]]:
    """(command, option, choices) of every option whose help lists its choices as "a | b"."""
    import argparse

    out = []
    for action in build_parser()._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                for option in sub._actions:
                    words = re.findall(r"\w+", (option.help or "").split("(")[0].split(":")[-1])
                    if option.option_strings and " | " in (option.help or "") and words:
                        choices = option.choices or getattr(option, "completion_choices", ())
                        out.append((name, option.option_strings[-1], tuple(choices)))
    return out


def test_every_option_with_choices_completes_them():
    """Each option whose help lists choices ("tile | carpet") declares them for completion (evaluate's --surface
    and --turning-mode, init's --floor and --units, calibrate's --surface): none is left to complete nothing."""
    found = _options_with_choices()
    assert {(c, o) for c, o, _ in found} >= {("evaluate", "--surface"), ("init", "--units"), ("init", "--floor")}
    assert [(c, o) for c, o, choices in found if not choices] == []


@pytest.mark.skipif(shutil.which("bash") is None, reason="needs bash")
@pytest.mark.parametrize(
    "words, expected",
    [
        (["evaluate", "--surface"], "tile carpet"),
        (["evaluate", "--turning-mode"], "chair pivot"),
        (["init", "x.toml", "--units"], "in mm"),
        (["init", "x.toml", "--floor"], "tile carpet"),
    ],
)
def test_bash_completes_an_options_choices(words, expected, tmp_path, capsys):
    """``designer evaluate --surface <TAB>`` offers tile and carpet (bash, the script as printed)."""
    main(["completion", "bash"])
    script = tmp_path / "designer.bash"
    script.write_text(capsys.readouterr().out)
    line = " ".join(["designer", *words, ""])
    call = (
        f"source {script}; COMP_WORDS=(designer {' '.join(words)} ''); COMP_CWORD={len(words) + 1}; "
        f"COMP_LINE='{line}'; COMP_POINT={len(line)}; _shtab_designer designer '' {words[-1]}; echo \"${{COMPREPLY[*]}}\""
    )
    done = subprocess.run(["bash", "-c", call], capture_output=True, text=True)
    assert done.stdout.strip() == expected, done.stderr


@pytest.mark.skipif(shutil.which("bash") is None, reason="needs bash")
def test_the_documented_completion_install_works_on_a_fresh_home(tmp_path, monkeypatch, capsys):
    """docs/commands.md's bash line, in a home with no such folder yet, writes the script (the designer of this
    checkout standing for the installed one); ``completion --help`` at 80 columns keeps that path whole."""
    import sys

    from conftest import ROOT

    text = (ROOT / "docs" / "commands.md").read_text()
    line = next(ln for ln in text.splitlines() if ln.startswith("mkdir -p ~/.local/share/bash-completion"))
    command = line.split("  #")[0].replace("designer completion", f"{sys.executable} -m designer completion")
    home = tmp_path / "home"
    home.mkdir()
    env = {"HOME": str(home), "PATH": "/usr/bin:/bin", "PYTHONPATH": str(ROOT)}
    done = subprocess.run(["bash", "-c", command], env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "complete" in (home / ".local/share/bash-completion/completions/designer").read_text()
    monkeypatch.setenv("COLUMNS", "80")
    with pytest.raises(SystemExit):
        main(["completion", "--help"])
    lines = capsys.readouterr().out.splitlines()
    assert any("~/.local/share/bash-completion/completions/designer" in ln for ln in lines), lines
    assert all(len(ln) <= 80 for ln in lines)
