"""Write the printed outputs shown in README.md and docs/ from the program itself.

An output block is a fenced ``text`` block right after a marker line naming the shell command that prints it::

    <!-- output: designer fix problems/indoor-manual.toml --current "T=1.25in,d=8in,B=0,c=1.3" | head -3 -->

Run from the repository root::

    python docs/outputs.py            # rewrite every marked block with what its command prints now

The command runs in bash from the repository root with ``COLUMNS=80`` and the interpreter's own ``bin``
folder first on ``PATH`` (so ``designer`` is this checkout's, as ``.venv/bin/designer`` after the README's
install); its standard output, trailing spaces removed, becomes the block.  tests/docs/test_outputs.py runs
the same commands and fails when a block differs from what the program prints, or when a ``text`` block
showing a command's output has no marker.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
MARKER = re.compile(r"<!-- output: (?P<command>.+?) -->\n```text\n(?P<body>.*?)```", re.S)
"""A marker line and the ``text`` block after it."""


def pages() -> list[Path]:
    """README.md and every Markdown page of docs/."""
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def printed(command: str) -> str:
    """What ``command`` prints (bash, repository root, ``COLUMNS=80``, this interpreter's ``bin`` first on PATH),
    each line without trailing spaces, ending in one newline."""
    env = os.environ | {
        "COLUMNS": "80",
        "LINES": "200",
        "TERM": "dumb",
        "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}",
    }
    done = subprocess.run(["bash", "-c", command], cwd=ROOT, env=env, capture_output=True, text=True)
    if done.returncode not in (0, 141):  # 141: SIGPIPE when `| head` stops reading
        raise RuntimeError(f"{command}: exit {done.returncode}: {done.stderr.strip()[-500:]}")
    return "\n".join(line.rstrip() for line in done.stdout.rstrip("\n").splitlines()) + "\n"


def blocks(text: str) -> list[tuple[str, str]]:
    """(command, block text) of every marked block of a page's ``text``."""
    return [(m["command"], m["body"]) for m in MARKER.finditer(text)]


def rewrite(text: str) -> str:
    """``text`` with every marked block replaced by what its command prints now."""
    return MARKER.sub(lambda m: f"<!-- output: {m['command']} -->\n```text\n{printed(m['command'])}```", text)


def main() -> int:
    for page in pages():
        text = page.read_text(encoding="utf-8")
        new = rewrite(text)
        if new != text:
            page.write_text(new, encoding="utf-8")
            print(f"{page.relative_to(ROOT)}: {len(blocks(text))} block(s) rewritten")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
