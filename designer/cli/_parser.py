"""The argument parser of every ``designer`` command: one-line errors, and "did you mean" for a misspelled
option or sub-command (``--trial`` -> ``--trail``, ``--piont`` -> ``--points``, ``evalute`` -> ``evaluate``)."""

from __future__ import annotations

import argparse
import difflib
import re
import textwrap

CUTOFF = 0.6
"""Least similarity (difflib's ratio, 0 to 1) of a suggestion to the word typed: 0.6 is difflib's own default,
which takes one or two letters swapped, missing or doubled in a word of four or more (``--trial``/``--trail``
0.86, ``--piont``/``--points`` 0.80) and leaves unrelated words alone (``--speed``/``--seed`` 0.92 is a
suggestion, ``--foo``/``--json`` 0.55 is not)."""


def suggestion(word: str, choices) -> str:
    """``"; did you mean '--trail'?"`` for the choice closest to ``word`` (difflib, :data:`CUTOFF`), else ``""``."""
    close = difflib.get_close_matches(word, list(choices), n=1, cutoff=CUTOFF)
    return f"; did you mean {close[0]!r}?" if close else ""


class Formatter(argparse.HelpFormatter):
    """argparse's help layout, wrapped at spaces only: a path (``~/.local/share/bash-completion/...``), an
    option or a hyphenated word is never split across two lines."""

    def _split_lines(self, text: str, width: int) -> list[str]:
        return textwrap.wrap(re.sub(r"\s+", " ", text).strip(), width, break_on_hyphens=False, break_long_words=False)

    def _fill_text(self, text: str, width: int, indent: str) -> str:
        return "\n".join(indent + line for line in self._split_lines(text, width - len(indent)))


class Parser(argparse.ArgumentParser):
    """argparse with the project's error line (``designer: error: ...``, exit 2) that names a misspelled option
    or sub-command with the closest valid one.

    The options are checked before argparse parses them, so ``designer evaluate --trial 2in ...`` is told about
    ``--trial`` (did you mean ``--trail``?) and not that ``--trail`` is missing.  A sub-command's parser checks
    its own options; the top parser checks those before the sub-command and the sub-command's name.
    """

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("formatter_class", Formatter)
        super().__init__(*args, **kwargs)
        # a minus and a digit start a value (--weights -1,1, --trail -1in), which the option's own check names;
        # argparse's own rule takes only plain negative numbers, and would say that --weights lacks its value
        self._negative_number_matcher = re.compile(r"^-[0-9.]")  # noqa: V101 - argparse reads it

    def error(self, message):  # one line, exit 2, like every input error
        self.exit(2, f"designer: error: {message}\n")

    def parse_known_args(self, args=None, namespace=None):
        """argparse's, after :meth:`check_spelling` of ``args``."""
        if args is not None:
            self.check_spelling(list(args))
        return super().parse_known_args(args, namespace)

    def check_spelling(self, args: list[str]) -> None:
        """Exit 2 naming the first unknown option (``--x`` or ``--x=v``) with its closest match, or an unknown
        sub-command with its closest name.  Only what this parser would parse itself is looked at: at the top,
        the words up to the sub-command; a value after ``--`` or after an option that takes one is left alone."""
        known = {s for a in self._actions for s in a.option_strings}
        takes_value = {s for a in self._actions if a.nargs != 0 for s in a.option_strings}
        commands = self._commands()
        i = 0
        while i < len(args):
            word = args[i]
            if word == "--":
                return
            if word.startswith("--"):
                name = word.split("=", 1)[0]
                if name not in known and not self._abbreviates(name, known):
                    self.error(f"unrecognized option {name}{suggestion(name, sorted(known))}")
                i += 2 if name in takes_value and "=" not in word else 1
                continue
            if commands and not word.startswith("-"):
                if word not in commands:
                    self.error(f"unknown command {word!r}{suggestion(word, commands)} (designer --help lists them)")
                return  # the sub-command's parser checks the rest
            i += 1

    def _commands(self) -> list[str]:
        """The names of this parser's sub-commands (none for a sub-command's parser without its own)."""
        for action in self._actions:
            if isinstance(action, argparse._SubParsersAction):
                return list(action.choices)
        return []

    def _abbreviates(self, name: str, known: set[str]) -> bool:
        """True if ``name`` is a unique prefix of a known option (argparse accepts ``--tri`` for ``--trials``)."""
        return self.allow_abbrev and len([k for k in known if k.startswith(name)]) == 1


__all__ = ["CUTOFF", "Formatter", "Parser", "suggestion"]
