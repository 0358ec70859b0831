"""Every JSON file the tool writes, and every --json output, carries a schema version (issue 34.5): the committed
reports' files, a fresh report's, and ``designer run --json``."""

from __future__ import annotations

import json
import re

import pytest

from designer.jsonsafe import SCHEMA_VERSION, stamped

from conftest import ROOT

SCHEMA = re.compile(r"^caster-designer/[\w.\- ]+/(\d+)$")
REPORTS = sorted(p.parent for p in (ROOT / "results").glob("*/front.json"))


def _records(path):
    """The JSON objects of a file that carry the schema: the file's object, or each record of a list."""
    data = json.loads(path.read_text(encoding="utf-8"))
    return data if isinstance(data, list) else [data]


@pytest.mark.parametrize("folder", REPORTS, ids=lambda p: p.name)
def test_committed_report_files_carry_the_schema(folder):
    """front.json and every record of checks.json of each committed report start with the current schema."""
    for name in ("front.json", "checks.json"):
        for record in _records(folder / name):
            match = SCHEMA.match(record.get("schema", ""))
            assert match and int(match.group(1)) == SCHEMA_VERSION, (name, record.get("schema"))
            assert next(iter(record)) == "schema"


def test_stamped_puts_the_schema_first():
    """stamped() adds the schema key first and keeps every other key and value (a planted dict)."""
    out = stamped("front.json", {"problem": "x", "points": [1]})
    assert (
        list(out) == ["schema", "problem", "points"] and out["schema"] == f"caster-designer/front.json/{SCHEMA_VERSION}"
    )
    assert not SCHEMA.match("caster-designer/front.json")  # a stamp without a version does not pass the check


def test_run_json_carries_the_schema(capsys):
    """designer run --json: the command's schema first, the keys users rely on kept."""
    from designer.cli import main

    assert main(["run", str(ROOT / "problems" / "paper-invacare.toml"), "--json", "--no-cross-check"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["schema"] == f"caster-designer/run --json/{SCHEMA_VERSION}" and next(iter(out)) == "schema"
    assert {"design", "objectives", "recommendation", "alternatives", "weights"} <= set(out)
