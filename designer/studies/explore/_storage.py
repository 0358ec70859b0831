"""Where a study lives: storage URLs, opening an optuna storage, journal repair, atomic writes of result files.

See :mod:`designer.studies.explore` for the storage forms.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import shutil
import sqlite3
import tempfile
import time
import warnings
from dataclasses import dataclass
from pathlib import Path


from designer.errors import SECRET_KEYS, InputError, OutputError, StorageError, mask_secrets
from designer.output import FileKind, check_file, output_folder
from designer.textfiles import not_a_file
import importlib.util


# --------------------------------------------------------------------------- storage


@dataclass(frozen=True)
class StorageSpec:
    """A parsed storage URL.

    Attributes
    ----------
    kind : "memory" | "journal" | "rdb"
    url : the URL as optuna takes it (journal: the file path)
    shown : the URL with any password replaced by ``***`` (safe for reports)
    """

    kind: str
    url: str | None
    shown: str

    @property
    def shared(self) -> bool:
        """True when several processes can work on one study."""
        return self.kind != "memory"

    @property
    def remote(self) -> bool:
        """A client–server database (heartbeat decides which RUNNING trials are stale)."""
        return self.kind == "rdb" and not self.url.startswith("sqlite")


RDB_SCHEMES = ("sqlite", "postgresql", "postgres", "mysql", "mariadb", "oracle", "mssql")


def parse_storage(storage: str | None) -> StorageSpec:
    """Parse a storage argument; :class:`StorageError` (exit 6) when it is not one of the forms.

    Forms: ``None``/``"memory"``; ``journal:///abs/path.log`` or any path ending
    ``.log``/``.journal``; ``sqlite:///path.db`` or a path ending ``.db``/``.sqlite``/``.sqlite3``;
    ``postgresql://user:password@host:port/database`` (also ``postgresql+psycopg2://``, ``mysql://``).
    """
    if storage is None or storage.strip() in ("", "memory", ":memory:", "inmemory"):
        return StorageSpec("memory", None, "memory")
    text = storage.strip()
    if text.startswith("journal://"):
        path = text[len("journal://") :]
        if not path:
            raise StorageError(f"storage {text!r}: journal URL without a file path; use journal:///abs/path/study.log")
        return StorageSpec("journal", path, f"journal://{path}")
    match = re.match(r"^([A-Za-z][A-Za-z0-9+.-]*)://", text)
    if match:
        scheme = match.group(1).lower().split("+")[0]
        if scheme not in RDB_SCHEMES:
            raise StorageError(
                f"storage {redact_url(text)!r}: unknown scheme {match.group(1)!r}; use sqlite:///file.db, "
                f"postgresql://user:password@host/db or journal:///path/file.log"
            )
        url = "postgresql" + text[len(match.group(1).split("+")[0]) :] if scheme == "postgres" else text
        find = importlib.util.find_spec  # SQLAlchemy 2.1 reads postgresql:// as psycopg (3), but the README (and
        # the `test` extra) install psycopg2-binary: the installed driver; an explicit postgresql+driver:// is kept
        if scheme == "postgres" or match.group(1).lower() == "postgresql":
            if find("psycopg") is None and find("psycopg2") is not None:
                url = "postgresql+psycopg2://" + url[len("postgresql://") :]
        path = url.split("://", 1)[1]  # an SQLite URL without a file: sqlite://, sqlite:///, :memory:, mode=memory
        if scheme == "sqlite" and (path.split("?", 1)[0] in ("", "/") or ":memory:" in path or "mode=memory" in path):
            raise StorageError(
                f"storage {redact_url(text)!r}: an in-memory SQLite database keeps nothing once the run ends and "
                f"lives inside one process (--workers cannot share it); use a file (sqlite:///study.db, "
                f"journal:///path/study.log), or leave --storage out for a study in memory"
            )
        return StorageSpec("rdb", url, redact_url(url))
    lower = text.lower()
    if lower.endswith((".log", ".journal")):
        return StorageSpec("journal", text, f"journal://{text}")
    if lower.endswith((".db", ".sqlite", ".sqlite3")):
        return StorageSpec("rdb", f"sqlite:///{text}", f"sqlite:///{text}")
    raise StorageError(
        f"storage {redact_url(text)!r}: not a storage URL; use sqlite:///file.db, postgresql://user:password@host/db, "
        f"journal:///path/file.log (or a path ending .db or .log)"
    )


SECRET_QUERY_KEYS = SECRET_KEYS
"""The query keys of a storage URL whose value is a secret (:data:`designer.errors.SECRET_KEYS`)."""

_SECRET_KEY = re.compile(f"^{SECRET_QUERY_KEYS}$", re.IGNORECASE)


def redact_url(url: str) -> str:
    """``url`` with every password replaced by ``***``: the one function for every place a storage URL is shown
    (explore.json, ``--json``, the terminal, error messages, logs).

    Every form SQLAlchemy's URL accepts (parsed by ``sqlalchemy.engine.make_url``,
    ``render_as_string(hide_password=True)``, its query's secret keys :data:`SECRET_QUERY_KEYS` masked), then
    :func:`designer.errors.mask_secrets` on the result: ``user:pw@`` with a raw ``@`` or ``:`` in it, an empty
    user, and the strings that merely look like a URL (``caster:S3cretPW@db.example.com/studies`` without a
    scheme, ``postgresql:/user:pw@...``, ``postgresql//user:pw@...``), libpq's ``host=... password=...`` and
    ODBC's ``PWD=...;``.  A URL without a secret is returned unchanged.
    """
    text = str(url)
    try:
        from sqlalchemy.engine import make_url

        parsed = make_url(text)
        hidden = {k for k in parsed.query if _SECRET_KEY.match(k)}
        if parsed.password is not None or hidden:
            parsed = parsed.update_query_dict({k: "***" for k in hidden}) if hidden else parsed
            text = parsed.render_as_string(hide_password=True)
    except Exception:  # noqa: BLE001 - not a URL SQLAlchemy reads: the masks below still apply
        pass
    return mask_secrets(text)


def scrub(text: str, url: str | None) -> str:
    """``text`` (a driver's error message) without the secrets of ``url``: each password that
    :func:`redact_url` hides is replaced by ``***`` wherever it appears, and any copy of the URL by its shown form."""
    if not url:
        return text
    shown = redact_url(url)
    text = text.replace(url, shown)
    try:
        from sqlalchemy.engine import make_url

        parsed = make_url(url)
        secrets = [parsed.password] if parsed.password else []
        secrets += [v for k, v in parsed.query.items() if isinstance(v, str) and _SECRET_KEY.match(k)]
    except Exception:  # noqa: BLE001
        secrets = []
    for value in list(secrets):  # a connection string's own password (ODBC's "...;PWD=secret;...")
        secrets += re.findall(r"(?i)(?:^|[;&])\s*(?:pwd|password|passwd)\s*=\s*([^;&]+)", str(value))
    for secret in secrets:
        if secret and len(str(secret)) >= 3:
            text = text.replace(str(secret), "***")
    return mask_secrets(text)


def _one_line(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()
    first = next((line.strip() for line in text if line.strip()), type(exc).__name__)
    return (first[:200] + "…") if len(first) > 200 else first


HEARTBEAT_SECONDS = 10
"""A worker on a remote (PostgreSQL/MySQL) study records a heartbeat this often (env DESIGNER_HEARTBEAT_SECONDS)."""
GRACE_SECONDS = 60
"""A RUNNING trial without a heartbeat for this long is failed and retried (env DESIGNER_GRACE_SECONDS)."""
STALE_RETRIES = 3
"""A candidate whose trial went stale is retried up to this many times (a retry can go stale too: its worker
killed or starved); each retry is evaluated once, and the stale trial's own late result never counts."""


def _heartbeat() -> tuple[int, int]:
    """Heartbeat interval and grace period [s] of remote studies: the defaults, or the environment's."""
    out = []
    for name, default in (("DESIGNER_HEARTBEAT_SECONDS", HEARTBEAT_SECONDS), ("DESIGNER_GRACE_SECONDS", GRACE_SECONDS)):
        text = os.environ.get(name, str(default))
        try:
            value = int(text)
        except ValueError:
            value = 0
        if not 1 <= value <= 86400:
            raise InputError(f"{name} = {text!r}: expected whole seconds from 1 to 86400")
        out.append(value)
    if out[1] <= out[0]:
        raise InputError(f"DESIGNER_GRACE_SECONDS = {out[1]}: must exceed DESIGNER_HEARTBEAT_SECONDS = {out[0]}")
    return out[0], out[1]


SCHEMA_ATTEMPTS = 3
"""Opens of a remote storage tried when another process is creating optuna's tables at the same moment."""


def _open_database(spec: StorageSpec, heartbeat: int | None, grace: int | None):
    """optuna's RDBStorage of ``spec`` (remote: with heartbeat and retry of stale trials).  Processes started
    together on a fresh database race to create optuna's tables: the loser's CREATE fails on a unique index
    (PostgreSQL's pg_type), and as the tables exist then, it opens again (:data:`SCHEMA_ATTEMPTS` in all)."""
    import optuna

    engine_kwargs = {}
    if spec.remote:
        engine_kwargs = {"connect_args": {"connect_timeout": 10}, "pool_pre_ping": True}
    for attempt in range(1, SCHEMA_ATTEMPTS + 1):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                if not spec.remote:  # SQLite: one machine; --resume fails every RUNNING trial, no heartbeat needed
                    return optuna.storages.RDBStorage(spec.url)
                return optuna.storages.RDBStorage(
                    spec.url,
                    engine_kwargs=engine_kwargs,
                    heartbeat_interval=heartbeat,
                    grace_period=grace,
                    failed_trial_callback=optuna.storages.RetryFailedTrialCallback(max_retry=STALE_RETRIES),
                )
        except Exception as exc:  # noqa: BLE001 - the caller makes any failure one line
            if not spec.remote or type(exc).__name__ != "IntegrityError" or attempt == SCHEMA_ATTEMPTS:
                raise
            time.sleep(0.5 * attempt)
    raise AssertionError("unreachable: the last attempt returns or raises")


def _optuna_journal(path: Path) -> bool:
    """True if ``path`` is optuna's journal: JSON lines, each an operation (``{"op_code": ...``)."""
    try:
        with open(path, "rb") as fh:
            first = fh.readline(1 << 20)
    except OSError:
        return False
    if not first.endswith(b"\n"):  # a first record cut short by a kill (repaired on open)
        return first.startswith(b'{"op_code":')
    try:
        record = json.loads(first)
    except ValueError:
        return False
    return isinstance(record, dict) and "op_code" in record


OPTUNA_TABLES = frozenset({"studies", "trials", "version_info"})
"""Tables every optuna RDB schema has: an SQLite file holding them (or no table at all) is a study's."""


def _optuna_sqlite(path: Path) -> bool:
    """True if ``path`` is an SQLite database of optuna's schema (or one without any table yet).

    Read without changing anything: read-only first.  A database left by a process killed in a write
    transaction (explore's worker under kill -9) has a hot ``-journal`` beside it that a read-only reader may
    not roll back ("attempt to write a readonly database"): it is copied with its journal into a temporary
    folder and read there, rolled back as SQLite itself will roll it back when the study is opened.
    """
    try:
        with open(path, "rb") as fh:
            if fh.read(16) != b"SQLite format 3\x00":
                return False
    except OSError:
        return False
    tables = _sqlite_tables(Path(os.path.abspath(path)).as_uri() + "?mode=ro")
    if tables is None and any(os.path.exists(f"{path}{s}") for s in ("-journal", "-wal")):
        with tempfile.TemporaryDirectory(prefix="designer-sqlite-") as tmp:
            copy = Path(tmp) / "study.db"
            try:
                shutil.copyfile(path, copy)
                for suffix in ("-journal", "-wal"):
                    if os.path.exists(f"{path}{suffix}"):
                        shutil.copyfile(f"{path}{suffix}", f"{copy}{suffix}")
            except OSError:
                return False
            tables = _sqlite_tables(str(copy))
    return tables is not None and (not tables or OPTUNA_TABLES <= tables)


def _sqlite_tables(uri: str) -> set[str] | None:
    """The table names of the SQLite database at ``uri`` (a ``file:`` URI or a path), None if it cannot be read."""
    try:
        con = sqlite3.connect(uri, uri=uri.startswith("file:"))
        try:
            return {row[0] for row in con.execute("select name from sqlite_master where type = 'table'")}
        finally:
            con.close()
    except sqlite3.Error:
        return None


JOURNAL = FileKind("an optuna journal (JSON lines written by designer explore)", _optuna_journal)
"""What ``--storage FILE.log`` may write into: a new or empty file, or optuna's journal; never a user's text."""

SQLITE = FileKind("an SQLite database of optuna's schema", _optuna_sqlite)
"""What ``--storage FILE.db`` may write into: a new or empty file, or an optuna SQLite database."""


def storage_file(spec: StorageSpec) -> Path | None:
    """The file of a journal or SQLite storage (None for memory and a database server)."""
    if spec.kind == "journal":
        return Path(spec.url)
    if spec.url is not None and spec.url.startswith("sqlite:///") and len(spec.url) > len("sqlite:///"):
        return Path(spec.url[len("sqlite:///") :].split("?", 1)[0])
    return None


@contextlib.contextmanager
def removed_if_failed(spec: StorageSpec):
    """Context manager: a storage file this run creates is removed again if the run fails while it is still
    empty (a full disk: optuna made the file and could not write a byte); nothing half-written stays behind.
    A file that existed before, or holds anything, is left as it is (a study to resume)."""
    path = storage_file(spec)
    new = path is not None and not os.path.lexists(path)
    try:
        yield
    except BaseException:
        if new and path is not None and path.is_file() and path.stat().st_size == 0:
            for leftover in (path, Path(f"{path}-journal"), Path(f"{path}.lock")):
                with contextlib.suppress(OSError):
                    leftover.unlink()
        raise


def open_storage(spec: StorageSpec, break_lock: bool = False):
    """Open (and check) an optuna storage; any failure is one :class:`StorageError` line.

    ``break_lock`` (resume of a journal file): remove a lock file left by a
    killed process instead of waiting out its grace period.
    """
    import optuna

    if spec.kind == "memory":
        return optuna.storages.InMemoryStorage()
    path = storage_file(spec)  # a journal or an SQLite file (None: a database server)
    if path is not None and not path.parent.is_dir():
        raise StorageError(f"storage {spec.shown}: folder {path.parent} does not exist")
    # StorageError (exit 6, every storage problem's code) unless the file can be written and is new, empty or
    # optuna's own (designer.output.check_file's rule and words): a user's notes.log or database is never
    # written into, a read-only folder, a loop of links or a name too long is named as such
    try:
        if path is not None:
            kind, example = (JOURNAL, "study.log") if spec.kind == "journal" else (SQLITE, "study.db")
            check_file(path, "--storage", example=example, kind=kind)
    except OutputError as exc:
        raise StorageError(str(exc)) from None
    other = None if path is None else not_a_file(path)  # the readers' rule: a device (/dev/stdout) or a FIFO
    if other is not None:
        expected = "a journal file" if spec.kind == "journal" else "an SQLite database file"
        raise StorageError(f"storage {spec.shown}: is {other}, expected {expected}")
    heartbeat, grace = _heartbeat() if spec.remote else (None, None)  # a bad setting is its own one line
    try:
        if spec.kind != "journal":
            return _open_database(spec, heartbeat, grace)
        from optuna.storages.journal import JournalFileBackend, JournalFileOpenLock, JournalStorage

        assert path is not None
        if break_lock:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(f"{path}.lock")
        if path.exists() and path.stat().st_size:  # drop a partial last line left by a process killed in
            with open(path, "rb+") as f:  # mid-write (it would corrupt the next append)
                f.seek(-1, os.SEEK_END)
                if f.read(1) != b"\n":
                    data = f.seek(0) or f.read()
                    f.truncate(data.rfind(b"\n") + 1)
        return JournalStorage(JournalFileBackend(str(path), lock_obj=JournalFileOpenLock(str(path), grace_period=10)))
    except Exception as exc:  # noqa: BLE001 - every failure becomes one line
        line = scrub(_one_line(exc), spec.url)
        if isinstance(exc, ImportError) and spec.kind != "journal":
            raise StorageError(
                f"storage {spec.shown}: the database driver is not installed ({line}); "
                f"PostgreSQL: pip install psycopg2-binary, MySQL: pip install pymysql"
            ) from None
        raise StorageError(f"storage {spec.shown}: cannot open it ({type(exc).__name__}: {line})") from None


# --------------------------------------------------------------------------- atomic writes


def _atomic_write_many(files: dict, option: str = "--out") -> None:
    """Write the files of ``files`` (path -> text, one folder) at once: into a temporary folder inside it,
    synced, then renamed over the previous ones (:func:`designer.output.output_folder`).  Nothing else in the
    folder is touched; a full disk or an unwritable folder is one OutputError line (exit 7), and no temporary
    file is left behind."""
    (folder,) = {Path(p).parent for p in files}
    names = {Path(p).name for p in files}
    with output_folder(folder, names, option=option, command="designer explore") as tmp:
        for path, text in files.items():
            with open(tmp / Path(path).name, "w", encoding="utf-8") as f:
                f.write(text)
                f.flush()
                os.fsync(f.fileno())
