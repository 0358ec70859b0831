"""Secrets and spreadsheets (issue class 4): a storage URL's password never reaches a screen or a file, every CSV
the tool writes is safe to open in a spreadsheet (and reads back as written), and the studio's origin check
compares scheme, host and port."""

from __future__ import annotations

import ast
import csv
import io
from pathlib import Path

import pytest

from designer.cli import main
from designer.studies.explore import parse_storage, redact_url
from designer.studies.explore._storage import scrub
from designer.textfiles import csv_table, csv_text, restore_cell, safe_cell

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "designer"

# (URL, the secrets it holds): every password form SQLAlchemy's URL accepts
SECRET_URLS = [
    ("postgresql://user:pw1secret@host/db", ["pw1secret"]),  # user:pw@
    ("postgresql://:pw2secret@host/db", ["pw2secret"]),  # empty user (the issue)
    ("postgresql://user@host/db?password=pw3secret", ["pw3secret"]),  # ?password= (the issue)
    ("postgresql://user:p%40ss%3Apw4@host:5432/db", ["p%40ss%3Apw4", "p@ss:pw4"]),  # percent-encoded
    ("postgresql://user:raw@pw5@host/db", ["raw@pw5"]),  # a raw '@' in the password
    ("mysql+pymysql://u:pw6secret@h/db?passwd=pw7secret&charset=utf8", ["pw6secret", "pw7secret"]),
    ("postgresql://h/db?sslpassword=pw8secret&PASSWORD=pw9secret", ["pw8secret", "pw9secret"]),
    ("postgres://u:pw10secret@[::1]:5432/db", ["pw10secret"]),  # the postgres:// alias, an IPv6 host
    ("mssql+pyodbc://?odbc_connect=DRIVER%3Dx%3BPWD%3Dpw11secret", ["pw11secret"]),
    ("weird://u:pw12secret@host/db", ["pw12secret"]),  # a scheme the tool refuses: the message is redacted too
]


@pytest.mark.parametrize("url, secrets", SECRET_URLS, ids=[u for u, _ in SECRET_URLS])
def test_no_password_form_survives_the_one_redaction(url, secrets):
    """redact_url (SQLAlchemy's make_url plus the query's secret keys) leaves no secret of any form, keeps the
    user and host; the storage's shown form (explore.json, --json, the terminal) and its error messages are made
    by it, and a driver's message quoting the URL or the password is scrubbed."""
    shown = redact_url(url)
    assert "***" in shown
    try:
        spec_text = parse_storage(url).shown
    except Exception as exc:  # noqa: BLE001 - the refusal's message is shown too
        spec_text = str(exc)
    driver = scrub(f"connection to {url} failed for password {secrets[-1]}", url)
    for secret in secrets:
        for text in (shown, spec_text, driver):
            assert secret not in text
    assert "host" in shown or "h/" in shown or "::1" in shown or "odbc" in shown


def test_urls_without_a_secret_are_shown_as_written():
    """A URL without a password is unchanged (paths, users and hosts as the user wrote them)."""
    for url in ("sqlite:///results/my study.db", "postgresql://user@host:5432/db?sslmode=require", "journal.log"):
        assert redact_url(url) == url


def test_a_refused_postgres_storage_prints_no_password(capsys, tmp_path):
    """`designer explore --storage postgresql://:pw@127.0.0.1:1/db` (nothing listens on port 1): exit 6, one
    line, and neither the password nor the query's password on stderr or stdout."""
    url = "postgresql://:hunter2secret@127.0.0.1:1/db?password=swordfish99"
    code = main(["explore", "paper-invacare", "--storage", url, "--trials", "4", "--out", str(tmp_path / "e")])
    out, err = capsys.readouterr()
    assert code == 6 and err.count("\n") == 1
    assert "hunter2secret" not in out + err and "swordfish99" not in out + err
    assert "127.0.0.1:1" in err


# (cell as the tool has it, cell as written)
CELLS = [
    ('=HYPERLINK("http://x")', '\'=HYPERLINK("http://x")'),
    ("+cmd|' /C calc'!A0", "'+cmd|' /C calc'!A0"),
    ("-2+3+cmd|' /C calc'!A0", "'-2+3+cmd|' /C calc'!A0"),
    ("@SUM(A1:A2)", "'@SUM(A1:A2)"),
    ("\tchair", "'\tchair"),
    ("\rchair", "'\rchair"),
    ("-3.25", "-3.25"),  # a negative number stays a number
    ("+1e-3", "+1e-3"),
    (-3.25, -3.25),
    (0, 0),
    ("chair = 1", "chair = 1"),  # '=' inside is harmless
    ("'quoted", "'quoted"),  # the user's own apostrophe
    ('naïve, "quoted"', 'naïve, "quoted"'),
    (None, ""),
    (True, "true"),
]


@pytest.mark.parametrize("value, written", CELLS, ids=[repr(v) for v, _ in CELLS])
def test_formula_cells_are_neutralised_and_read_back(value, written):
    """OWASP: a text cell starting with =, +, -, @, tab or CR gets a leading ' (a spreadsheet shows text instead
    of running a formula); numbers, negative ones included, stay numbers; the readers' restore_cell gives the
    text back, so a CSV the tool wrote reads back as it was."""
    assert safe_cell(value) == written
    text = csv_text([["name", "n"], [value, 1]])
    header, body, _ = csv_table(text, "t.csv")
    assert header == ["name", "n"]
    expected = "" if value is None else ("true" if value is True else str(value))
    assert body == [[expected, "1"]]
    assert restore_cell(str(written)) == expected


def test_every_csv_the_tool_writes_goes_through_the_one_writer():
    """No module but designer/textfiles.py calls csv.writer or csv.DictWriter, nor joins cells with ',' into a
    .csv (AST of every module): fleet.csv, front.csv, explore.csv, the calibration's, the simulations' and an
    example fleet are all written by designer.textfiles.csv_text."""
    offenders = []
    for path in PACKAGE.rglob("*.py"):
        if path.name == "textfiles.py":
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.Attribute) and node.attr in ("writer", "DictWriter"):
                if isinstance(node.value, ast.Name) and node.value.id == "csv":
                    offenders.append(f"{path.relative_to(ROOT)}:{node.lineno}")
    assert offenders == []


def test_a_fleet_csv_with_formula_names_is_safe_and_reads_back(tmp_path, capsys):
    """Chair names beginning with =, -, @ or a tab are written to fleet.csv with a leading ' (no formula runs in
    a spreadsheet), the numbers of the same rows stay numbers, and the names read back as the user wrote them."""
    names = ["=1+1", "-chair", "@risk", "\tchair", "plain"]
    rows = [
        ["name", "load_N", "threshold_height_in", "target_speed_m/s", "swept_radius_max_in", "surface", "turning_mode"]
    ]
    rows += [[n, 178, 0.5, 2.5, 5.0, "tile", "chair"] for n in names]
    fleet_csv = tmp_path / "f.csv"
    fleet_csv.write_text(csv_text(rows), encoding="utf-8")
    out = tmp_path / "report"
    assert main(["fleet", str(fleet_csv), "--problem", "indoor-manual", "--out", str(out)]) == 0
    capsys.readouterr()
    raw = list(csv.reader(io.StringIO((out / "fleet.csv").read_text(encoding="utf-8"))))
    written = [r[0] for r in raw[1:]]
    assert sorted(written) == sorted(["'=1+1", "'-chair", "'@risk", "chair", "plain"])  # the reader strips cells
    header = raw[0]  # each quantity names its unit; a part number carries its sizes ("1: T 2 in, d 6 in, ...")
    assert {"trail_in", "turning_effort_N", "sku"} <= set(header) and "trail" not in header
    numbers = [
        float(c) for r in raw[1:] for h, c in zip(header[1:], r[1:]) if h != "sku" and c and c[0] in "-0123456789"
    ]
    assert len(numbers) >= 2 * len(names)
    assert all(r[header.index("sku")].split(":")[1].startswith(" T ") for r in raw[1:] if r[header.index("sku")])
    _, body, _ = csv_table((out / "fleet.csv").read_text(encoding="utf-8"), "fleet.csv")
    assert sorted(r[0] for r in body) == sorted(n.strip() for n in names)


# (Origin header, status) for a studio on 127.0.0.1:8050
ORIGINS = [
    ("http://localhost:8050", 200),
    ("http://127.0.0.1:8050/", 200),
    ("http://[::1]:8050", 200),
    ("http://localhost", 403),  # port 80: another origin (the issue)
    ("http://127.0.0.1:80", 403),
    ("https://localhost:8050", 403),  # another scheme
    ("http://localhost:9999", 403),
    ("http://attacker.example:8050", 403),
    ("null", 403),
]


@pytest.mark.parametrize("origin, status", ORIGINS, ids=[o for o, _ in ORIGINS])
def test_the_studio_origin_is_scheme_host_and_port(tmp_path, origin, status):
    """The studio on port 8050 answers a page whose Origin is its own scheme, host and port, and refuses any other
    (http://localhost is port 80, not the studio's)."""
    from designer.studio import state
    from designer.studio.app import create_app
    from designer.studio.server import allowed_hosts, guard

    data, name = state.read_problem_data(ROOT / "problems" / "indoor-manual.toml")
    app = create_app(data, name, tmp_path)
    guard(app.server, allowed_hosts("127.0.0.1", 8050))
    client = app.server.test_client()
    assert client.get("/", headers={"Host": "127.0.0.1:8050", "Origin": origin}).status_code == status
