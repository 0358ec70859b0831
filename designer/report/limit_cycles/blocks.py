"""The limit-cycle report's text blocks as Markdown and as HTML (one list of blocks, two renderings).

A block is a tuple: ``("h1", text)``, ``("h2", text)``, ``("p", text)``, ``("img", file, alt)``,
``("ul", [lines])`` or ``("table", [header], [[cells]])``.  Text may hold Markdown's bold (two stars) and
code (backquotes), which :func:`to_html` turns into tags after escaping.
"""

from __future__ import annotations

import html
import re


def to_markdown(blocks) -> str:
    """limit_cycles.md from the blocks."""
    out = []
    for b in blocks:
        kind = b[0]
        if kind in ("h1", "h2"):
            out.append("#" * int(kind[1]) + f" {b[1]}\n")
        elif kind == "p":
            out.append(b[1] + "\n")
        elif kind == "img":
            out.append(f"![{b[2]}]({b[1]})\n")
        elif kind == "ul":
            out.append("\n".join(f"- {line}" for line in b[1]) + "\n")
        elif kind == "table":
            lines = ["| " + " | ".join(b[1]) + " |", "|" + "---|" * len(b[1])]
            out.append("\n".join(lines + ["| " + " | ".join(r) + " |" for r in b[2]]) + "\n")
    return "\n".join(out)


def _inline(text: str) -> str:
    t = html.escape(text)
    t = re.sub(r"\*\*(.+?)\*\*", r"<strong>\1</strong>", t)
    t = re.sub(r"(?<![\w*])\*(\w[^*]*?)\*(?![\w*])", r"<em>\1</em>", t)  # *word*, not N*m
    return re.sub(r"`(.+?)`", r"<code>\1</code>", t)


def to_html(blocks) -> str:
    """limit_cycles.html (one self-contained page) from the blocks."""
    out = [
        "<!doctype html><html><head><meta charset='utf-8'>"
        "<meta name='viewport' content='width=device-width, initial-scale=1'><title>Shimmy beyond onset</title>"
        "<style>body{font-family:sans-serif;max-width:70em;margin:2em auto;padding:0 1em;line-height:1.45;"
        "overflow-wrap:break-word}"
        ".wide{overflow-x:auto}table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:2px 8px}"
        "img{max-width:100%;height:auto}code{overflow-wrap:anywhere}"
        "@media (max-width:600px){body{margin:1em auto;padding:0 .5em}td,th{padding:2px 4px}}</style></head><body>"
    ]
    for b in blocks:
        kind = b[0]
        if kind in ("h1", "h2"):
            out.append(f"<{kind}>{_inline(b[1])}</{kind}>")
        elif kind == "p":
            out.append(f"<p>{_inline(b[1])}</p>")
        elif kind == "img":
            out.append(f"<p><img src='{html.escape(b[1])}' alt='{html.escape(b[2])}'></p>")
        elif kind == "ul":
            out.append("<ul>" + "".join(f"<li>{_inline(x)}</li>" for x in b[1]) + "</ul>")
        elif kind == "table":
            out.append(  # a wide table scrolls in its own box on a phone, never the page
                "<div class='wide'><table><tr>"
                + "".join(f"<th>{_inline(h)}</th>" for h in b[1])
                + "</tr>"
                + "".join("<tr>" + "".join(f"<td>{_inline(c)}</td>" for c in r) + "</tr>" for r in b[2])
                + "</table></div>"
            )
    out.append("</body></html>")
    return "\n".join(out)
