"""griffe extension for the API reference: read this package's docstrings as they are written.

The docstrings use NumPy sections, but an entry is often ``name : prose with units`` (``trail : T [m]``)
where NumPy puts a type after the colon.  This extension moves such prose (text with a space in it) to the
entry's description, so it renders as text, not as a type (in Returns, ``Front with ...`` becomes the type
``Front`` and its description); and it turns Sphinx roles
(``:class:`~designer.problem.Problem```) into code spans (``Problem``), which Markdown would print raw.
mkdocs.yml loads it (handlers.python.options.extensions).
"""

from __future__ import annotations

import re

import griffe

SECTIONS = {"parameters", "attributes", "other parameters", "keyword arguments", "args", "arguments"}
RETURNS = {"returns", "yields"}
ARTICLES = {"The", "A", "An", "One", "Each", "Every", "It", "This", "Its"}
RETURN_PROSE = re.compile(r"^([A-Za-z_][\w.\[\]]*)\s+(\S.*)$")
ENTRY = re.compile(r"^(\*{0,2}[A-Za-z_][\w]*(?:\s*,\s*\*{0,2}[A-Za-z_]\w*)*)\s+:\s+(.+)$")
TYPE_LIKE = re.compile(r"^[\w.\[\]]+(?:\s*(?:\||or|,)\s*[\w.\[\]]+)*(?:,\s*optional)?$")
ROLE = re.compile(r":(?:class|func|meth|attr|data|mod|obj|exc|ref):`(~?)([^`]+)`")


def _role(match: re.Match) -> str:
    target = match.group(2)
    return f"`{target.rsplit('.', 1)[-1] if match.group(1) else target}`"


def _is_prose(text: str) -> bool:
    return " " in text.strip() and not TYPE_LIKE.match(text.strip())


def rewrite(text: str) -> str:
    """The docstring with prose after ``name :`` moved to the description and Sphinx roles as code spans."""
    lines = ROLE.sub(_role, text).splitlines()
    out: list[str] = []
    section = None
    for i, line in enumerate(lines):
        following = lines[i + 1] if i + 1 < len(lines) else ""
        if line.strip() and set(following.strip()) == {"-"} and not line.startswith(" "):
            section = line.strip().lower()
            out.append(line)
            continue
        match = ENTRY.match(line) if section in SECTIONS else None
        returned = RETURN_PROSE.match(line) if section in RETURNS and " : " not in line else None
        if returned and returned.group(1) in ARTICLES:
            returned = None
        if match and _is_prose(match.group(2)):
            out.extend([match.group(1), "    " + match.group(2)])
        elif returned:  # "Front with ..." -> type Front, the rest its description
            out.extend([returned.group(1), "    " + returned.group(2)])
        else:
            out.append(line)
    return "\n".join(out)


class ProseEntries(griffe.Extension):
    """Rewrite every docstring once, when its object is loaded."""

    def on_instance(self, *, obj: griffe.Object, **kwargs) -> None:
        if obj.docstring is not None:
            obj.docstring.value = rewrite(obj.docstring.value)
