"""Issue 42, classes 4 (secrets) and 5-6 (input paths, output streams, one exit code per refusal).

Each test is a table through one code path:

- :func:`designer.errors.mask_secrets` and :func:`designer.studies.explore._storage.redact_url`: every URL form
  optuna and SQLAlchemy accept, and strings that merely look like one, shown without their password, in every
  message of the command line;
- :func:`designer.textfiles.read_input_text`: a pipe (``<(cat f)``) is read once under the size limit, a flood
  is refused with that reason, a character device as what it is, a name too long as too long;
- :func:`designer.output.write_file` onto a stream: ``/dev/stdout`` and a pipe are written in place (exit 0),
  ``init`` never writes over anything (exit 7); a device as a report folder says it is a device;
- :func:`designer.output.check_file` / ``check_folder``: a loop of links is named as a loop;
- one exit code per kind of refusal, whatever the command (docs/commands.md, "Errors and exit codes").
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from designer.cli import main
from designer.errors import mask_secrets
from designer.studies.explore._storage import redact_url

ROOT = Path(__file__).resolve().parents[2]
INDOOR = str(ROOT / "problems" / "indoor-manual.toml")
INVACARE = str(ROOT / "problems" / "paper-invacare.toml")
SLIP = str(ROOT / "designer" / "data" / "examples" / "slip.csv")
ENV = dict(os.environ, PYTHONPATH=str(ROOT), PYTHONWARNINGS="ignore")
SECRET = "S3cretPW"

# --------------------------------------------------------------------------- secrets

SECRET_FORMS = {
    # form: the storage string as a user types it (each holds SECRET once or more)
    "URL": f"postgresql://caster:{SECRET}@db.example.com:5432/studies",
    "URL with a driver": f"postgresql+psycopg2://caster:{SECRET}@db.example.com/studies",
    "URL, MySQL with a query": f"mysql+pymysql://caster:{SECRET}@db/studies?charset=utf8mb4",
    "URL, empty user": f"postgresql://:{SECRET}@db/studies",
    "URL, raw @ and : in the password": f"postgresql://caster:{SECRET}@x:y@db/studies",
    "URL, percent-encoded password": f"postgresql://caster:{SECRET}%40x@db/studies",
    "URL, IPv6 host": f"postgresql://caster:{SECRET}@[::1]:5432/studies",
    "URL, several hosts": f"postgresql://caster:{SECRET}@h1:5432,h2:5432/studies",
    "URL, ?password=": f"postgresql://caster@db/studies?password={SECRET}&sslmode=require",
    "URL, ?sslpassword=": f"postgresql://caster@db/studies?sslpassword={SECRET}",
    "URL, ODBC connect string": f"mssql+pyodbc:///?odbc_connect=DRIVER%3D%7Bx%7D%3BUID%3Du%3BPWD%3D{SECRET}",
    "no scheme": f"caster:{SECRET}@db.example.com/studies",
    "no scheme, no path": f"caster:{SECRET}@db.example.com",
    "one slash": f"postgresql:/caster:{SECRET}@db.example.com/studies",
    "no colon": f"postgresql//caster:{SECRET}@db.example.com/studies",
    "three slashes": f"postgresql:///caster:{SECRET}@db/studies",
    "libpq key=value": f"host=db.example.com port=5432 user=caster password={SECRET} dbname=studies",
    "libpq quoted": f"host=db user=caster password='{SECRET} x' dbname=studies",
    "ODBC": f"Driver={{ODBC}};Server=db;UID=caster;PWD={SECRET};",
    "token in a query": f"postgresql://db/studies?auth_token={SECRET}",
}
UNCHANGED = ["sqlite:///study.db", "journal:///tmp/study.log", "postgresql://caster@db/studies", "study.log", "memory"]


@pytest.mark.parametrize("form", list(SECRET_FORMS))
def test_every_form_of_a_secret_is_masked(form):
    """redact_url (every place a storage is shown) and mask_secrets (every message the command line prints)
    leave no trace of the password in any URL form SQLAlchemy accepts, nor in strings that merely look like one;
    the user, the host and the database stay readable."""
    text = SECRET_FORMS[form]
    for masked in (redact_url(text), mask_secrets(text), mask_secrets(f"storage {text!r}: cannot open it")):
        assert SECRET not in masked, masked
        assert "***" in masked
    assert "db" in redact_url(text) or "h1" in redact_url(text) or "::1" in redact_url(text) or "pyodbc" in text


@pytest.mark.parametrize("text", UNCHANGED)
def test_a_string_without_a_secret_is_unchanged(text):
    """A storage without a password, and a user name alone, are shown as they are."""
    assert redact_url(text) == text and mask_secrets(text) == text


@pytest.mark.parametrize(
    "form", ["no scheme", "one slash", "no colon", "libpq key=value", "URL, raw @ and : in the password"]
)
def test_the_command_line_never_prints_the_password(form, tmp_path, capsys):
    """`designer explore --storage <form>` (the issue's forms: a URL without a scheme exited 6 printing the
    password in full): one line, exit 6, no password in stdout or stderr."""
    code = main(["explore", INVACARE, "--trials", "2", "--storage", SECRET_FORMS[form], "--out", str(tmp_path)])
    out, err = capsys.readouterr()
    assert code == 6, err
    assert err.count("\n") == 1 and SECRET not in out + err, err


def test_the_mask_catches_a_message_that_leaked(capsys):
    """Planted fault: a command whose message carries a password (as the storage errors did) is caught by the
    one place that prints errors (designer.cli._error masks every message)."""
    from designer.cli import _error
    from designer.errors import StorageError

    assert _error(StorageError(f"storage caster:{SECRET}@db/studies: unreachable"), debug=False) == 6
    err = capsys.readouterr().err
    assert SECRET not in err and "caster:***@db/studies" in err


# --------------------------------------------------------------------------- input paths


def _bash(script: str, tmp: Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        ["bash", "-c", script], env={**ENV, "PY": sys.executable}, cwd=tmp, capture_output=True, text=True, timeout=300
    )


def test_pipes_are_read_once_under_the_size_limit(tmp_path):
    """`designer run <(cat problem.toml)` (process substitution, how scripts pass files) reads the pipe once
    and runs (it was exit 3, "is a pipe (FIFO)"); a 1.1 MB flood through a pipe is refused with the size limit
    as its reason (exit 3); `designer fleet <(...)` reads a fleet through a pipe too."""
    ok = _bash(f'"$PY" -m designer run <(cat {INDOOR}) --json', tmp_path)
    assert ok.returncode == 0, ok.stderr
    assert '"design"' in ok.stdout
    flood = _bash('"$PY" -m designer run <(head -c 1100000 /dev/zero | tr "\\0" "a")', tmp_path)
    assert flood.returncode == 3 and "larger than the 1 MB a problem file may have" in flood.stderr, flood.stderr
    assert "from a pipe" in flood.stderr and flood.stderr.count("\n") == 1
    fleet = _bash(
        '"$PY" -m designer fleet <("$PY" -m designer fleet --example 2 --out /dev/stdout) --json'
        f" --problem {INVACARE} --no-monte-carlo --out out",
        tmp_path,
    )
    assert fleet.returncode == 0, fleet.stderr


INPUTS = {
    # row: (argv, exit code, the reason in the one line); NAME: a 300-character file name
    "character device as a problem": (["run", "/dev/zero"], 3, "/dev/zero: is a character device"),
    "character device as a fleet": (["fleet", "/dev/zero"], 3, "/dev/zero: is a character device"),
    "300-character name to fix": (
        ["fix", "NAME.toml", "--current", "T=1.5in,d=7.75in,B=0.5625in,c=1.3"],
        3,
        "a name longer than the file system allows",
    ),
    "300-character name as fleet's table": (["fleet", "NAME.csv"], 3, "a name longer than the file system allows"),
    "300-character name to fleet --example --out": (
        ["fleet", "--example", "3", "--out", "NAME.csv"],
        7,
        "a name longer than the file system allows",
    ),
}


@pytest.mark.parametrize("row", list(INPUTS))
def test_inputs_name_their_true_reason(row, tmp_path, capsys, monkeypatch):
    """A device, a name too long: one line with the true reason ("no such problem file" and "the output cannot
    be written" were said of a 300-character name), the code of its kind (3 a problem or fleet file, 7 an
    output)."""
    monkeypatch.chdir(tmp_path)
    argv, code, reason = INPUTS[row]
    argv = [a.replace("NAME", "a" * 300) for a in argv]
    assert main(argv) == code, capsys.readouterr().err
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and reason in err, err


# --------------------------------------------------------------------------- output streams and loops


def test_a_single_file_out_onto_a_stream_is_written_in_place(tmp_path):
    """`spec --out /dev/stdout | cat` and `fleet --example 5 --out /dev/stdout | cat` write the sheet or the
    fleet into the pipe (exit 0; it was "no such file or directory"), the notes going to stderr so the stream
    holds the file alone; a FIFO with a reader is written likewise."""
    spec = _bash(f'"$PY" -m designer spec {INVACARE} --out /dev/stdout | cat; exit ${{PIPESTATUS[0]}}', tmp_path)
    assert spec.returncode == 0, spec.stderr
    assert spec.stdout.startswith("<!DOCTYPE html>") and spec.stdout.rstrip().endswith("</html>")
    fleet = _bash('"$PY" -m designer fleet --example 5 --out /dev/stdout | cat; exit ${PIPESTATUS[0]}', tmp_path)
    assert fleet.returncode == 0, fleet.stderr
    lines = fleet.stdout.splitlines()
    assert lines[0].startswith("# Example fleet") and len(lines) == 2 + 5 and "wrote" in fleet.stderr
    fifo = _bash(
        'mkfifo p; cat p > got & "$PY" -m designer fleet --example 2 --out p; code=$?; wait; exit $code', tmp_path
    )
    assert fifo.returncode == 0 and (tmp_path / "got").read_text().startswith("# Example fleet"), fifo.stderr


STREAMS = {
    # row: (argv, exit code, the reason in the one line)
    "pareto --out /dev/null": (["pareto", INVACARE, "--out", "/dev/null"], 7, "is a character device, not a folder"),
    "init over /dev/null": (["init", "/dev/null", "--defaults"], 7, "already exists"),
    "init over an empty file": (["init", "EMPTY", "--defaults"], 7, "already exists"),
    "a FIFO nothing reads": (["fleet", "--example", "2", "--out", "FIFO"], 7, "a pipe (FIFO) that nothing reads"),
    "robust --out a loop of links": (
        ["robust", INVACARE, "--out", "L1"],
        7,
        "is a loop of symbolic links (L1 -> l2 -> L1)",
    ),
    "simulate --plot a loop of links": (
        ["simulate", "--trail", "2in", "--speed", "1m/s", "--plot", "L1.png"],
        7,
        "is a loop of symbolic links",
    ),
    "explore --storage a loop of links": (
        ["explore", INVACARE, "--trials", "2", "--storage", "L1.db", "--out", "E"],
        6,
        "is a loop of symbolic links",
    ),
}


@pytest.mark.parametrize("row", list(STREAMS))
def test_devices_pipes_and_loops_say_what_they_are(row, tmp_path, capsys, monkeypatch):
    """Each refusal says what the path is: a device as a report folder, init over anything (a device, an empty
    file), a FIFO that nothing reads, a loop of links (it was "a link to l2, which does not exist"); the
    refusal's code is the output's (7) or the storage's (6)."""
    monkeypatch.chdir(tmp_path)
    argv, code, reason = STREAMS[row]
    (tmp_path / "EMPTY").write_bytes(b"")
    os.mkfifo(tmp_path / "FIFO")
    for name in ("L1", "L1.png", "L1.db"):
        (tmp_path / name).symlink_to("l2" + name[2:])
        (tmp_path / ("l2" + name[2:])).symlink_to(name)
    assert main([a.replace("E", str(tmp_path / "e")) if a == "E" else a for a in argv]) == code
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and reason in err, err
    assert (tmp_path / "EMPTY").read_bytes() == b""


# --------------------------------------------------------------------------- one exit code per refusal

REFUSALS = {
    # kind of refusal: {command: (argv with OUT, how OUT is made)}; every command of a kind has the same code
    7: {
        "pareto --out": ["pareto", INVACARE, "--points", "3", "--out", "OUT"],
        "robust --out": ["robust", INVACARE, "--points", "3", "--out", "OUT"],
        "simulate --report": ["simulate", "--report", "OUT"],
        "calibrate --report": ["calibrate", "slip", SLIP, "--report", "OUT"],
        "explore --out": ["explore", INVACARE, "--trials", "2", "--out", "OUT"],
        "fleet --out": ["fleet", "FLEET", "--problem", INVACARE, "--no-monte-carlo", "--out", "OUT"],
    },
    6: {
        "explore --storage FILE.db": ["explore", INVACARE, "--trials", "2", "--storage", "OUT/study.db"],
        "explore --storage FILE.log": ["explore", INVACARE, "--trials", "2", "--storage", "OUT/study.log"],
    },
}


@pytest.mark.parametrize("code", list(REFUSALS))
def test_one_exit_code_per_kind_of_refusal(code, tmp_path, capsys):
    """The same refusal has one code whatever the command (docs/commands.md): a folder holding the user's own
    files of the names a command writes is 7 for every command (pareto said 2); a storage file of the user's
    (not optuna's) is 6, the code of every storage problem (it was 7)."""
    fleet = tmp_path / "fleet.csv"
    assert main(["fleet", "--example", "2", "--out", str(fleet)]) == 0
    wrong = {}
    for command, argv in REFUSALS[code].items():
        out = tmp_path / command.replace(" ", "_")
        out.mkdir()
        for name in ("index.html", "report.md", "explore.csv", "fleet.csv", "onset.csv", "study.db", "study.log"):
            (out / name).write_text(f"the user's {name}\n")
        before = {p.name: p.read_bytes() for p in out.iterdir()}
        got = main([str(fleet) if a == "FLEET" else a.replace("OUT", str(out)) for a in argv])
        err = capsys.readouterr().err
        if got != code or err.count("\n") != 1 or {p.name: p.read_bytes() for p in out.iterdir()} != before:
            wrong[command] = (got, err.strip()[:160])
    assert wrong == {}
