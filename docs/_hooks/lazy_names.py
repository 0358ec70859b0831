"""mkdocs hook: ``::: designer.NAME`` in a page documents the object ``import designer`` gives for NAME.

``designer`` resolves most public names lazily (``designer._LAZY``: name -> defining module), which static
analysis cannot follow; this hook rewrites such a line to the defining module, read from the same table, so
the API pages follow a module when it moves and a name that disappears fails the strict build.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

_INIT = Path(__file__).resolve().parents[2] / "designer" / "__init__.py"
_LINE = re.compile(r"^(:::\s+)designer\.([A-Za-z_][A-Za-z0-9_]*)\s*$", flags=re.M)


def lazy_names() -> dict[str, str]:
    """``designer._LAZY`` read from the source (name -> module), without importing the package."""
    tree = ast.parse(_INIT.read_text(encoding="utf-8"))
    table: dict[str, str] = {}
    for node in tree.body:
        if isinstance(node, ast.AnnAssign | ast.Assign) and isinstance(node.value, ast.Dict):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            if any(isinstance(t, ast.Name) and t.id == "_LAZY" for t in targets):
                table.update({k.value: v.value for k, v in zip(node.value.keys, node.value.values)})
        elif isinstance(node, ast.Assign) and isinstance(node.targets[0], ast.Subscript):
            target = node.targets[0]
            if isinstance(target.value, ast.Name) and target.value.id == "_LAZY":
                table[target.slice.value] = node.value.value
    return table


def on_page_markdown(markdown: str, **kwargs) -> str:
    """Point ``::: designer.NAME`` at NAME's defining module when NAME is a lazy name."""
    table = lazy_names()

    def point(match: re.Match) -> str:
        name = match.group(2)
        module = table.get(name)
        return f"{match.group(1)}{module}.{name}" if module else match.group(0)

    return _LINE.sub(point, markdown)
