"""The registry's SQLite catalog: one row per run, the run id rule, and the registry hash.

The catalog is the registry's source of truth: a payload file counts only once its row
is committed. Connections use WAL (readers never block the one writer) and a busy
timeout (a second writer waits instead of failing). See docs/registry.md.
"""

from __future__ import annotations

import hashlib
import re
import sqlite3
import time
from collections.abc import Iterable
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

from anytip.data.runfile import SENSOR_ID_RE, CalibrationRun, check_sensor_id, parse_created
from anytip.errors import AnytipError

SCHEMA_VERSION = 3
BUSY_TIMEOUT_S = 120.0
RUN_ID_RE = re.compile(r"[A-Za-z0-9._-]{1,160}")

# One row per sensor model: its channel count and targets (runfile.layout_json), which
# every run of the model must share.
SENSOR_MODELS_TABLE = """
CREATE TABLE IF NOT EXISTS sensor_models (
    sensor_model    TEXT PRIMARY KEY,
    layout          TEXT NOT NULL
)"""

SCHEMA = """
CREATE TABLE IF NOT EXISTS runs (
    run_id          TEXT PRIMARY KEY,
    unit            TEXT NOT NULL,
    sensor_model    TEXT NOT NULL,
    orientation_deg REAL NOT NULL,
    source          TEXT NOT NULL,
    rows            INTEGER NOT NULL,
    channels        INTEGER NOT NULL,
    duration_s      REAL NOT NULL,
    protocol        TEXT,
    sha256          TEXT NOT NULL,
    created         TEXT NOT NULL,
    path            TEXT NOT NULL,
    imported_at     TEXT NOT NULL,
    protocol_set    INTEGER NOT NULL DEFAULT 0
);
CREATE INDEX IF NOT EXISTS runs_unit ON runs (unit);
CREATE INDEX IF NOT EXISTS runs_sensor_model ON runs (sensor_model);
""" + SENSOR_MODELS_TABLE

# A run's protocol set in the registry (`Registry.set_protocol`), not named by its file: 1.
PROTOCOL_SET_COLUMN = "protocol_set INTEGER NOT NULL DEFAULT 0"
# What a catalog of each older schema version lacks, applied in order when it is opened.
MIGRATIONS = {1: SENSOR_MODELS_TABLE, 2: f"ALTER TABLE runs ADD COLUMN {PROTOCOL_SET_COLUMN}"}


@dataclass(frozen=True)
class RunRecord:
    """One catalog row. `path` is relative to the registry root; times are ISO 8601 UTC.
    `protocol`: the protocol the run file names (a simulated run's `simulator` attribute) or, with
    `protocol_set`, the one the registry was told (`Registry.set_protocol`, `import_paths`)."""

    run_id: str
    unit: str
    sensor_model: str
    orientation_deg: float
    source: str
    rows: int
    channels: int
    duration_s: float
    protocol: str | None
    sha256: str
    created: str
    path: str
    imported_at: str
    protocol_set: bool = False

    def to_json(self) -> dict[str, Any]:
        """The record as a JSON-ready dict (column name -> value)."""
        return asdict(self)


COLUMNS = tuple(f.name for f in fields(RunRecord))


def check_run_id(run_id: str) -> str:
    """Return `run_id` if it is a safe file name ([A-Za-z0-9._-], not only dots), else raise."""
    if not isinstance(run_id, str) or not RUN_ID_RE.fullmatch(run_id) or set(run_id) == {"."}:
        raise AnytipError(f"run id {run_id!r} must match [A-Za-z0-9._-]{{1,160}} and not be only dots")
    return run_id


def compact_time(created: str) -> str:
    """ISO 8601 time -> 'YYYYMMDDTHHMMSSZ' in UTC (with '.ffffff' before 'Z' if sub-second).

    A time without a zone is taken as UTC, as the format prescribes.
    """
    try:
        t = parse_created(created)
    except ValueError as e:
        raise AnytipError(str(e)) from None
    frac = f".{t.microsecond:06d}" if t.microsecond else ""
    return t.strftime("%Y%m%dT%H%M%S") + frac + "Z"


def compact_number(x: float) -> str:
    """-45.0 -> '-45', 22.5 -> '22.5': the shortest text that round-trips the float."""
    x = float(x)
    return str(int(x)) if x.is_integer() else repr(x)


def make_run_id(run: CalibrationRun) -> str:
    """`<sensor_id>_o<orientation_deg>_<created as YYYYMMDDTHHMMSSZ>`, e.g. FT-0007_o-45_20240501T120000Z.

    Built from the run's identity (unit, rig orientation, recording time), never its
    values, so a re-import of the same recording finds the same id.
    """
    check_sensor_id(run.sensor_id)
    return check_run_id(f"{run.sensor_id}_o{compact_number(run.orientation_deg)}_{compact_time(run.created)}")


def payload_relpath(unit: str, run_id: str) -> str:
    """Where a run's payload lives, relative to the registry root (POSIX separators)."""
    return f"runs/{check_sensor_id(unit, 'unit')}/{check_run_id(run_id)}.h5"


def check_protocol(name: str) -> str:
    """Return `name` if it may name a protocol (the sensor id pattern, [A-Za-z0-9._-]{1,64}), else raise."""
    if not isinstance(name, str) or not SENSOR_ID_RE.fullmatch(name):
        raise AnytipError(f"protocol {name!r} must match [A-Za-z0-9._-]{{1,64}}")
    return name


def protocol_name(run: CalibrationRun) -> str | None:
    """`name` of the `protocol` object in the `simulator` JSON attribute, if any."""
    try:
        sim = run.simulator
    except ValueError:
        return None
    protocol = sim.get("protocol") if isinstance(sim, dict) else None
    name = protocol.get("name") if isinstance(protocol, dict) else None
    return name if isinstance(name, str) else None


def record_for(run: CalibrationRun, run_id: str, sha256: str, imported_at: str) -> RunRecord:
    """The catalog row describing `run` stored under `run_id`."""
    return RunRecord(
        run_id=run_id, unit=run.sensor_id, sensor_model=run.sensor_model,
        orientation_deg=float(run.orientation_deg), source=run.source, rows=run.n_rows,
        channels=run.n_channels, duration_s=run.duration_s, protocol=protocol_name(run),
        sha256=sha256, created=run.created, path=payload_relpath(run.sensor_id, run_id),
        imported_at=imported_at,
    )


def _enable_wal(conn: sqlite3.Connection, db_path: Path) -> None:
    """Switch the catalog to WAL, retrying while another connection holds the file.

    SQLite returns SQLITE_BUSY for a journal-mode change without calling the busy
    handler when a second process is creating the same file, so the timeout set on
    the connection does not cover it.
    """
    deadline = time.monotonic() + BUSY_TIMEOUT_S
    delay = 0.005
    while True:
        try:
            conn.execute("PRAGMA journal_mode = WAL")
            return
        except sqlite3.OperationalError as err:
            if "locked" not in str(err) and "busy" not in str(err):
                raise
            if time.monotonic() > deadline:
                raise AnytipError(f"{db_path}: catalog locked for {BUSY_TIMEOUT_S:.0f} s") from err
            time.sleep(delay)
            delay = min(delay * 2, 0.2)


def connect(db_path: Path) -> sqlite3.Connection:
    """Open (creating if needed) the catalog in autocommit mode; transactions are explicit.

    A file that is not an SQLite database, or one without the runs table, is refused
    with an AnytipError naming it.
    """
    conn = sqlite3.connect(db_path, timeout=BUSY_TIMEOUT_S, isolation_level=None)
    try:
        _prepare(conn, db_path)
    except sqlite3.DatabaseError as e:
        conn.close()
        raise AnytipError(f"{db_path}: not a registry catalog ({e})") from None
    except BaseException:
        conn.close()
        raise
    return conn


def _prepare(conn: sqlite3.Connection, db_path: Path) -> None:
    conn.execute(f"PRAGMA busy_timeout = {int(BUSY_TIMEOUT_S * 1000)}")
    _enable_wal(conn, db_path)
    conn.execute("PRAGMA synchronous = FULL")
    version = conn.execute("PRAGMA user_version").fetchone()[0]
    if version == 0:
        conn.execute("BEGIN IMMEDIATE")
        version = conn.execute("PRAGMA user_version").fetchone()[0]  # another process may have won
        if version == 0:
            for statement in SCHEMA.split(";"):
                conn.execute(statement)
            conn.execute(f"PRAGMA user_version = {SCHEMA_VERSION}")
            version = SCHEMA_VERSION
        conn.execute("COMMIT")
    elif version in MIGRATIONS:
        _migrate(conn, db_path)
    elif version != SCHEMA_VERSION:
        raise AnytipError(f"{db_path}: catalog schema version {version}; this code knows {SCHEMA_VERSION}")
    columns = [row[1] for row in conn.execute("PRAGMA table_info(runs)")]
    if columns != list(COLUMNS):
        raise AnytipError(f"{db_path}: table 'runs' has columns {columns}, expected {list(COLUMNS)}")


def _migrate(conn: sqlite3.Connection, db_path: Path) -> None:
    """Bring an older catalog to SCHEMA_VERSION in one transaction (another process may do it first).

    A migrated catalog has no sensor_models rows yet; the registry fills them from the
    runs on the next import of each model.
    """
    conn.execute("BEGIN IMMEDIATE")
    version = conn.execute("PRAGMA user_version").fetchone()[0]
    while version in MIGRATIONS:
        conn.execute(MIGRATIONS[version])
        version += 1
    conn.execute(f"PRAGMA user_version = {version}")
    conn.execute("COMMIT")
    if version != SCHEMA_VERSION:
        raise AnytipError(f"{db_path}: catalog schema version {version}; this code knows {SCHEMA_VERSION}")


def model_layouts(conn: sqlite3.Connection) -> dict[str, str]:
    """Each recorded sensor model's layout (`runfile.layout_json`: channel count and targets)."""
    return dict(conn.execute("SELECT sensor_model, layout FROM sensor_models"))


def record_model(conn: sqlite3.Connection, sensor_model: str, layout: str) -> None:
    """Record `sensor_model`'s layout unless one is recorded (the registry checked they agree)."""
    conn.execute("INSERT OR IGNORE INTO sensor_models (sensor_model, layout) VALUES (?, ?)",
                 (sensor_model, layout))


def forget_unused_models(conn: sqlite3.Connection) -> None:
    """Drop the layout of every sensor model with no runs left (a later import may set a new one)."""
    conn.execute("DELETE FROM sensor_models WHERE sensor_model NOT IN "
                 "(SELECT DISTINCT sensor_model FROM runs)")


def _record(row: tuple) -> RunRecord:
    return RunRecord(*row[:-1], protocol_set=bool(row[-1]))


def get(conn: sqlite3.Connection, run_id: str) -> RunRecord | None:
    row = conn.execute(f"SELECT {', '.join(COLUMNS)} FROM runs WHERE run_id = ?", (run_id,)).fetchone()
    return None if row is None else _record(row)


def query(conn: sqlite3.Connection, **equal: str | None) -> list[RunRecord]:
    """Rows whose columns equal the given non-None values, ordered by unit then run id."""
    keys = [k for k, v in equal.items() if v is not None]
    for k in keys:
        assert k in COLUMNS, k
    where = " AND ".join(f"{k} = ?" for k in keys) or "1"
    sql = f"SELECT {', '.join(COLUMNS)} FROM runs WHERE {where} ORDER BY unit, run_id"
    return [_record(r) for r in conn.execute(sql, [equal[k] for k in keys])]


def set_protocol(conn: sqlite3.Connection, run_id: str, protocol: str | None) -> None:
    """Set a run's protocol as the registry's (None: clear it). The caller checks the run's file
    names none."""
    conn.execute("UPDATE runs SET protocol = ?, protocol_set = ? WHERE run_id = ?",
                 (protocol, int(protocol is not None), run_id))


def hash_entry(sha256: str, protocol: str | None, protocol_set: bool) -> str:
    """What a run adds to the registry hash: its content hash, and a protocol set in the registry
    (which changes what a benchmark reads of the run). Runs without one hash as before it existed."""
    return f"{sha256}\tprotocol={protocol}" if protocol_set else sha256


def insert(conn: sqlite3.Connection, record: RunRecord) -> None:
    marks = ", ".join("?" for _ in COLUMNS)
    conn.execute(f"INSERT INTO runs ({', '.join(COLUMNS)}) VALUES ({marks})", astuple(record))


def delete(conn: sqlite3.Connection, run_ids: Iterable[str]) -> None:
    conn.executemany("DELETE FROM runs WHERE run_id = ?", [(r,) for r in run_ids])


def astuple(record: RunRecord) -> tuple:
    return tuple(int(v) if isinstance(v, bool) else v for v in (getattr(record, c) for c in COLUMNS))


def hash_pairs(pairs: Iterable[tuple[str, str]]) -> str:
    """sha256 over sorted (run_id, sha256) pairs: independent of insertion order."""
    h = hashlib.sha256()
    for run_id, sha in sorted(pairs):
        h.update(f"{run_id}\t{sha}\n".encode())
    return h.hexdigest()
