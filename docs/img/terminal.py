"""Render a command's output at a terminal width to a PNG in docs/img/ (headless Chromium), as a user sees it.

Run from the repository root::

    python docs/img/terminal.py fix-80-columns.png -- designer fix problems/indoor-manual.toml \\
        --current "T=1.25in,d=8in,B=0,c=1.3"

The command runs with ``COLUMNS=80`` (``--columns`` to change it), its standard output goes into an HTML
``<pre>`` of exactly that many character cells (a dashed line marks the right edge), and Chromium takes the
screenshot.  The command is shown above the output as a prompt (wrapped at the same width).  Needs the Debian ``chromium`` package.
``designer`` is run as ``python -m designer`` with this interpreter, so the checkout's package is the one shown.
"""

from __future__ import annotations

import argparse
import html
import os
import shlex
import subprocess
import sys
import tempfile
from pathlib import Path

OUT = Path(__file__).resolve().parent
FONT_PX = 14
LINE_PX = 17
CELL_PX = 8.43
"""Advance width of one character of DejaVu Sans Mono at 14 px [px] (0.602 em): sizes the window."""

PAGE = (
    '<!doctype html><html><head><meta charset="utf-8"><title>{title}</title><style>'
    "body{{margin:12px;background:#fff}}"
    "pre{{font:{font}px/{line}px 'DejaVu Sans Mono',monospace;margin:0;width:{columns}ch;"
    "border-right:1px dashed #aaa;white-space:pre;overflow:hidden}}"
    ".prompt{{font:{font}px/{line}px 'DejaVu Sans Mono',monospace;color:#555;width:{columns}ch;margin:0 0 4px}}"
    "</style></head><body><div class=prompt>{prompt}</div><pre>{text}</pre></body></html>"
)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("png", help="file name in docs/img/, e.g. fix-80-columns.png")
    parser.add_argument("--columns", type=int, default=80, help="terminal width (COLUMNS) [characters]")
    parser.add_argument("command", nargs=argparse.REMAINDER, help="-- then the command, e.g. designer fix ...")
    args = parser.parse_args(argv)
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    if not command:
        parser.error("no command given (after --)")
    run = [sys.executable, "-m", "designer", *command[1:]] if command[0] == "designer" else command
    env = os.environ | {"COLUMNS": str(args.columns), "LINES": "200", "TERM": "dumb"}
    text = subprocess.run(run, env=env, capture_output=True, text=True, check=True).stdout
    lines = text.rstrip("\n").splitlines()
    widest = max(len(line.rstrip()) for line in lines)
    prompt = f"$ COLUMNS={args.columns} " + shlex.join(command)
    page = PAGE.format(
        title=html.escape(args.png),
        font=FONT_PX,
        line=LINE_PX,
        columns=args.columns,
        prompt=html.escape(prompt),
        text=html.escape("\n".join(line.rstrip() for line in lines)),
    )
    width = int(args.columns * CELL_PX) + 40
    height = (len(lines) + 1 + len(prompt) // args.columns) * LINE_PX + 34
    with tempfile.TemporaryDirectory() as tmp:
        file = Path(tmp) / "terminal.html"
        file.write_text(page, encoding="utf-8")
        subprocess.run(
            [
                "chromium",
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--hide-scrollbars",
                f"--screenshot={OUT / args.png}",
                f"--window-size={width},{height}",
                file.as_uri(),
            ],
            check=True,
            capture_output=True,
        )
    print(f"{OUT / args.png}: {len(lines)} lines, the widest {widest} characters (COLUMNS={args.columns})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
