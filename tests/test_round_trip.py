"""What the tool writes it reads back (issue 33, "Must show"): every file a command writes for another command
(a problem saved by the studio, a calibration's TOML snippet, an example fleet, fleet.csv and fleet.json, a
report's front.csv and front.json) is read back by the command that consumes it, with hostile strings in every
free-text field (chair names, [stock] wheel names, problem titles and descriptions): control characters, formulas,
quotes, backslashes, non-ASCII, commas and newlines, and very long text."""

from __future__ import annotations

import csv
import dataclasses
import io
import json
import re
from pathlib import Path

import pytest

from designer.output import MANIFEST, MANIFEST_SCHEMA, RUN_MANIFEST

from designer.cli import main
from designer.problem import load_problem
from designer.studio import state
from designer.studies.fleet import example_fleet, read_fleet, write_fleet_csv
from designer.studies.front import Front
from designer.textfiles import FORMULA_STARTS, csv_table

ROOT = Path(__file__).resolve().parents[1]

HOSTILE = [
    '=HYPERLINK("http://evil.example","x")',
    "-2+3+cmd|' /C calc'!A0",
    "+SUM(A1:A9)",
    "@risk",
    "\ttab first",
    "\rreturn first",
    "quote \" apostrophe ' backslash \\ brace } bracket ]",
    "naïve – µ ² 中文 🙂 ‮rtl",
    "ctrl \x01 \x1b[31m \x1f \x7f end",
    "comma, and\nnewline",
    "x" * 2000,
]
"""Free text a user may type; each round trip below carries all of them."""


def test_a_studio_saved_problem_reads_back_with_hostile_text(tmp_path, capsys):
    """ "Save problem" (state.to_toml) of a problem whose title, description and [stock] wheel names are hostile:
    `designer run`'s loader reads the same text back (wheel names without their outer blanks, as the loader
    keeps them), control characters escaped, never written raw; `designer run --json` on it exits 0."""
    data, _ = state.read_problem_data(ROOT / "problems" / "indoor-manual.toml")
    data["title"] = HOSTILE[0]
    data["description"] = "\n".join(HOSTILE)
    stock = dict(data["stock"])
    stock.pop("diameters", None)
    stock["wheels"] = [{"name": text, "diameter": f"{4 + k * 0.25} in"} for k, text in enumerate(HOSTILE)]
    data["stock"] = stock
    text = state.to_toml(data)
    assert not any(ord(ch) < 0x20 and ch not in "\n" or ord(ch) == 0x7F for ch in text)
    path = tmp_path / "saved.toml"
    path.write_text(text, encoding="utf-8")
    problem = load_problem(path)
    assert problem.title == HOSTILE[0] and problem.description == "\n".join(HOSTILE)
    assert problem.stock is not None and problem.stock.wheels is not None
    assert [w.name for w in problem.stock.wheels] == [t.strip() for t in HOSTILE]
    assert main(["run", str(path), "--json", "--no-cross-check"]) == 0
    assert json.loads(capsys.readouterr().out)["problem"] == problem.name


def test_a_saved_problem_with_item_costs_opens_in_the_studio_and_saves_unchanged():
    """A problem whose [stock] items carry their own costs (`{ value = "7 in", cost = 6 }`, which `designer run`
    reads) opens in the studio (it was an internal error, exit 70), shows them as `7 in (cost 6)`, and an
    untouched control writes the items back as they were; an edited one keeps the costs it shows."""
    data, _ = state.read_problem_data(ROOT / "problems" / "indoor-manual.toml")
    data["stock"]["diameters"] = ["5 in", {"value": "7 in", "cost": 6}]
    values = state.control_values(data)
    assert values["stock_diameters"] == "5 in, 7 in (cost 6)"
    problem, merged = state.build_problem(data, values)
    assert merged["stock"]["diameters"] == ["5 in", {"value": "7 in", "cost": 6}]
    edited = state.apply(data, {**values, "stock_diameters": "6 in, 7 in (cost 6.5)"})
    assert edited["stock"]["diameters"] == ["6 in", {"value": "7 in", "cost": 6.5}]
    assert problem.stock is not None and problem.stock.cost("wheel", 7 * 0.0254) == 6


def test_a_calibration_snippet_reads_back_in_a_problem(tmp_path, capsys):
    """`designer calibrate turning --snippet` writes TOML that a problem file (with a hostile title) includes and
    `designer run`'s loader reads: the fitted k_tile is the problem's, to the snippet's 6 digits."""
    data = tmp_path / "d.csv"
    data.write_text("load_N,moment_Nm\n" + "".join(f"{100 + 20 * i},{0.005 * (100 + 20 * i):.6g}\n" for i in range(8)))
    snippet = tmp_path / "k.toml"
    assert main(["calibrate", "turning", str(data), "--snippet", str(snippet)]) == 0
    capsys.readouterr()
    head = f'name = "p"\ntitle = {state.toml_string(HOSTILE[-3])}\n[shimmy]\ntarget_speed = "2.5 m/s"\n'
    path = tmp_path / "p.toml"
    path.write_text(head + snippet.read_text(encoding="utf-8"), encoding="utf-8")
    problem = load_problem(path)
    assert problem.title == HOSTILE[-3]
    assert problem.conditions.turning.tile_moment_per_load == pytest.approx(0.005, rel=1e-5)


def test_a_fleet_with_hostile_names_round_trips_through_every_file(tmp_path, capsys):
    """An example fleet renamed with hostile names: write_fleet_csv (what `fleet --example` writes) is read back
    by read_fleet (what `designer fleet` reads) with the same names; `designer fleet` on it writes fleet.csv (names
    protected from spreadsheets, read back as they were) and fleet.json (the same names)."""
    fleet = example_fleet(len(HOSTILE), seed=3)
    fleet = dataclasses.replace(fleet, names=[f"{text} #{k}" for k, text in enumerate(HOSTILE)])
    path = write_fleet_csv(fleet, tmp_path / "fleet-in.csv")
    expected = [name.strip() for name in fleet.names]
    assert list(read_fleet(path).names) == expected
    out = tmp_path / "report"
    assert main(["fleet", str(path), "--problem", "indoor-manual", "--no-skus", "--out", str(out)]) == 0
    capsys.readouterr()
    _, body, _ = csv_table((out / "fleet.csv").read_text(encoding="utf-8"), "fleet.csv")
    assert sorted(row[0] for row in body) == sorted(expected)
    rows = json.loads((out / "fleet.json").read_text(encoding="utf-8"))["rows"]
    assert sorted(r["name"] for r in rows) == sorted(expected)


def test_a_report_front_with_hostile_wheel_names_reads_back(tmp_path, capsys):
    """`designer pareto` on a problem whose [stock] wheels have hostile names writes front.csv (the buildable
    front's wheels by name) and front.json; Front.from_csv reads the CSV back with the same wheel names and
    numbers as front.json."""
    data, _ = state.read_problem_data(ROOT / "problems" / "indoor-manual.toml")
    stock = dict(data["stock"])
    stock.pop("diameters", None)
    names = HOSTILE[:6] + HOSTILE[7:10]
    stock["wheels"] = [{"name": text, "diameter": f"{4 + k * 0.5} in"} for k, text in enumerate(names)]
    data["stock"] = stock
    data["pareto"] = {"points": 5}
    problem_path = tmp_path / "hostile.toml"
    problem_path.write_text(state.to_toml(data), encoding="utf-8")
    out = tmp_path / "report"
    assert main(["pareto", str(problem_path), "--out", str(out)]) in (0, 1)  # 1: a check of the front failed
    capsys.readouterr()
    problem = load_problem(problem_path)
    front_json = json.loads((out / "front.json").read_text(encoding="utf-8"))
    buildable = Front.from_csv(out / "front.csv", problem, buildable=True)
    wheels = {p.wheel for p in buildable.points if p.wheel}
    assert wheels and wheels <= {n.strip() for n in names}
    assert json.dumps(front_json)  # plain JSON
    front = Front.from_csv(out / "front.csv", problem)
    assert [round(p.turning_effort, 6) for p in front.points] == [
        round(p["turning_effort"], 6) for p in front_json["points"]
    ]


RESULT_FILES = sorted(
    p for p in (ROOT / "results").rglob("*") if p.suffix in (".csv", ".json") and p.name != "run.json"
)
"""Every data file the tool committed to results/ (run.json is git-ignored: each run's dates and seconds)."""


@pytest.mark.parametrize("path", RESULT_FILES, ids=lambda p: p.relative_to(ROOT / "results").as_posix())
def test_every_result_file_reads_back_by_the_shared_readers(path):
    """Every CSV and JSON file in results/ reads back by the readers the commands use: a CSV by
    designer.textfiles.csv_table (one header, rows as wide as it, no text cell a spreadsheet would run as a
    formula, LF line ends), a JSON by json with its schema stamp ``caster-designer/<file>/<version>`` first
    (in each record of a list); a folder's manifest (designer.output.MANIFEST, the proof of what the tool wrote)
    carries the one stamp of every manifest, :data:`designer.output.MANIFEST_SCHEMA`."""
    text = path.read_text(encoding="utf-8")
    if path.suffix == ".csv":
        assert "\r" not in text, f"{path.name}: CR line ends"
        header, rows, _ = csv_table(text, path.name)
        assert rows and len(set(header)) == len(header) and all(len(row) == len(header) for row in rows)
        raw = [cell for line in csv.reader(io.StringIO(text)) if line and not line[0].startswith("#") for cell in line]
        # as written (csv_table gives a protected '=x back as =x): no cell a spreadsheet would run as a formula
        assert not [c for c in raw if c.startswith(FORMULA_STARTS) and not _number(c)], path.name
        return
    data = json.loads(text)
    records = data if isinstance(data, list) else [data]
    for record in records:
        assert next(iter(record)) == "schema", f"{path.name}: no schema key first"
        if path.name in (MANIFEST, RUN_MANIFEST):
            assert record["schema"] == MANIFEST_SCHEMA and isinstance(record["files"], dict), path
            continue
        assert record["schema"].startswith(f"caster-designer/{path.name}/"), record["schema"]


def _number(cell: str) -> bool:
    try:
        float(cell)
    except ValueError:
        return False
    return True


@pytest.mark.parametrize(
    "edit, message",
    [
        (lambda h, r: (h.replace("damping_N_m_per_rad", "dampx"), r), "line 2: no column 'damping'"),
        (lambda h, r: (h, [",".join([""] + r[0].split(",")[1:]), *r[1:]]), "line 2: column trail_in = '': not a"),
        (lambda h, r: (h, [",".join(["two"] + r[0].split(",")[1:]), *r[1:]]), "column trail_in = 'two': not a"),
        (lambda h, r: (h.replace("trail_in", "trail"), r), "line 2: trail = 2.5 m: outside the model's range"),
    ],
    ids=["missing column", "empty cell", "text cell", "inches in a bare SI column"],
)
def test_a_broken_front_csv_is_one_line_naming_file_line_and_column(edit, message, tmp_path):
    """Front.from_csv, the reader of a report's front.csv: every kind of broken file (a column missing, a cell
    empty or not a number, an old bare-SI header over inch values: a 2.5 m trail) is an InputError naming the
    file, the line and the column, never a raw KeyError or ValueError, and never a caster 40 times too large."""
    from designer.errors import InputError

    header, *rows = (ROOT / "results" / "indoor-manual" / "front.csv").read_text(encoding="utf-8").splitlines()
    header, rows = edit(header, rows)
    path = tmp_path / "front.csv"
    path.write_text("\n".join([header, *rows]) + "\n", encoding="utf-8")
    with pytest.raises(InputError, match=re.escape(message)) as error:
        Front.from_csv(path, "indoor-manual")
    assert str(path) in str(error.value) and "\n" not in str(error.value)
