"""``designer completion bash|zsh|fish``: the shell's completion script for every command and option, printed
to standard output (shtab writes it from the argument parser itself, so it never falls behind the options).
docs/commands.md shows where each shell reads it from."""

from __future__ import annotations

from designer.cli import build_parser

SHELLS = ("bash", "zsh", "fish")
"""The shells a completion script is written for (shtab's static scripts)."""


def register(sub) -> None:
    p = sub.add_parser(
        "completion",
        help="print the shell completion script (bash, zsh or fish)",
        description="Print a static completion script for every designer command and option, their choices "
        "included. For bash (new shells): mkdir -p ~/.local/share/bash-completion/completions && designer "
        "completion bash > ~/.local/share/bash-completion/completions/designer (zsh and fish: docs/commands.md).",
    )
    p.add_argument("shell", choices=SHELLS, help="the shell to complete in: " + ", ".join(SHELLS))
    p.set_defaults(func=run, fit=False)  # a script for the shell: its lines as shtab writes them


def run(args) -> int:
    """Print the completion script of ``args.shell`` for the whole ``designer`` parser; exit 0."""
    import shtab  # ~40 ms (it loads email.parser): only for this command, not at every start

    print(shtab.complete(with_choices(build_parser()), shell=args.shell), end="")
    return 0


def with_choices(parser):
    """``parser`` (a fresh one, used only to write the script) with the choices of every option that declares
    them for completion (``action.completion_choices``, e.g. ``--surface``: tile, carpet) set as argparse
    choices, which shtab completes; the parser that parses the command line checks them itself (one-line errors
    naming the choices)."""
    import argparse

    stack = [parser]
    while stack:
        for action in stack.pop()._actions:
            if isinstance(action, argparse._SubParsersAction):
                stack.extend(action.choices.values())
            elif getattr(action, "completion_choices", None) and not action.choices:
                action.choices = tuple(action.completion_choices)
    return parser
