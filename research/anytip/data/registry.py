"""The dataset registry: calibration runs stored as HDF5 payloads and listed in a SQLite catalog.

Layout under the root (docs/registry.md):

    catalog.sqlite              one row per run (anytip.data.catalog)
    runs/<unit>/<run_id>.h5     payloads: interchange files written by `write_run`
    tmp/                        scratch space of writes in progress (anytip.data.staging)

A write stages payloads in tmp/ (outside any lock), then, inside one `BEGIN IMMEDIATE`
transaction, checks the catalog, renames the payloads into runs/ and inserts their
rows. A failure removes what it placed and rolls back, so readers and other writers
only ever see whole imports.
"""

from __future__ import annotations

import logging
import os
import sqlite3
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import closing, contextmanager
from dataclasses import dataclass, field, replace
from datetime import UTC, datetime
from pathlib import Path

from anytip.data import catalog, csv_import
from anytip.data.catalog import RunRecord
from anytip.data.runfile import (
    CalibrationRun,
    RunFormatError,
    TargetLayout,
    describe_layout,
    layout_json,
    read_run,
    write_run,
)
from anytip.data.staging import Staging, clean_stale
from anytip.errors import AnytipError

ENV_VAR = "ANYTIP_REGISTRY"
DEFAULT_ROOT = Path("data/registry")
RUN_SUFFIXES = (".h5", ".hdf5")
CSV_SUFFIXES = (".csv",)
log = logging.getLogger(__name__)


def default_registry_path() -> Path:
    """`$ANYTIP_REGISTRY` if set, else ./data/registry (relative to the working directory)."""
    env = os.environ.get(ENV_VAR)
    return Path(env) if env else DEFAULT_ROOT


@dataclass(frozen=True)
class ImportReport:
    """What an import did: runs newly added, and runs already present with the same content."""

    added: list[RunRecord]
    unchanged: list[RunRecord]

    @property
    def records(self) -> list[RunRecord]:
        return self.added + self.unchanged

    def summary(self) -> str:
        return f"{len(self.added)} run(s) added, {len(self.unchanged)} unchanged"


@dataclass(frozen=True)
class VerifyReport:
    """Result of `Registry.verify()`; `ok` when every list is empty.

    missing: run ids whose payload file is absent. corrupt: (run id, problem) for
    payloads that fail to read, fail validation or no longer match their catalog hash.
    orphans: files under runs/ that no catalog row names (paths relative to the root).
    bad_rows: (run id, problem) for rows whose ids or path are unsafe or inconsistent.
    """

    checked: int
    missing: list[str] = field(default_factory=list)
    corrupt: list[tuple[str, str]] = field(default_factory=list)
    orphans: list[str] = field(default_factory=list)
    bad_rows: list[tuple[str, str]] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not (self.missing or self.corrupt or self.orphans or self.bad_rows)

    def problems(self) -> list[str]:
        return (
            [f"{r}: payload missing" for r in self.missing]
            + [f"{r}: {p}" for r, p in self.corrupt + self.bad_rows]
            + [f"{p}: payload file not in the catalog" for p in self.orphans]
        )


@dataclass
class _Staged:
    record: RunRecord  # imported_at is filled in at commit
    temp: Path
    source: str
    targets: dict[str, TargetLayout]


class Registry:
    """A directory of calibration runs with a SQLite catalog; safe for concurrent processes."""

    def __init__(self, root: str | Path | None = None, *, create: bool = True):
        """Open the registry at `root`; with `create`, make it if it does not exist yet.

        Without `create`, a directory that holds no catalog is refused (a mistyped path
        must not become an empty registry).
        """
        self.root = Path(root) if root is not None else default_registry_path()
        self.db_path = self.root / "catalog.sqlite"
        if not create and not self.db_path.is_file():
            raise AnytipError(f"{self.root}: not a registry (no catalog.sqlite); create one with "
                              "`anytip data import` or `anytip data simulate`")
        if self.root.exists() and not self.root.is_dir():
            raise AnytipError(f"{self.root}: not a directory")
        self.root.mkdir(parents=True, exist_ok=True)
        (self.root / "runs").mkdir(exist_ok=True)
        with closing(self._connect()):
            pass

    def __repr__(self) -> str:
        return f"Registry({str(self.root)!r})"

    # ---- writing -------------------------------------------------------------------------

    def add_runs(
        self, runs: Sequence[CalibrationRun], source_paths: Sequence[str | Path] | None = None
    ) -> list[RunRecord]:
        """Add runs all-or-nothing; return one record per input run, in input order.

        A run already stored with the same content is left as it is. A run whose id is
        taken by different content, or any invalid run, refuses the whole call.
        """
        if source_paths is not None and len(source_paths) != len(runs):
            raise AnytipError(f"add_runs: {len(runs)} runs but {len(source_paths)} source paths")
        sources = [str(p) for p in source_paths] if source_paths else [f"<run {i}>" for i in range(len(runs))]
        clean_stale(self.root / "tmp")
        with Staging(self.root / "tmp") as staging:
            staged, refused = [], []
            for i, (run, source) in enumerate(zip(runs, sources, strict=True)):
                try:
                    staged.append(_stage(run, staging.dir / f"{i}.h5", source))
                except AnytipError as e:
                    refused.append(_named(e, source))
            self._raise_if_refused(staged, refused, len(runs))
            added, existing = self._commit(staged)
        by_id = existing | added
        return [by_id[s.record.run_id] for s in staged]

    def import_paths(
        self, paths: str | Path | Iterable[str | Path],
        column_map: str | Path | csv_import.ColumnMap | None = None, protocol: str | None = None,
    ) -> ImportReport:
        """Import interchange files (.h5, .hdf5) and rig CSV logs (.csv), recursing into directories.

        Every input is read and validated before anything is written; if any is refused,
        nothing is imported and the AnytipError lists every refused file with its problem.
        CSV logs are read with `column_map` (default configs/csv/rig34.yaml) and their
        sidecar metadata (see anytip.data.csv_import). With `protocol`, every imported run is
        marked as run by that protocol (`set_protocol`), in the same transaction.
        """
        if protocol is not None:
            catalog.check_protocol(protocol)
        files, refused = _collect_inputs([paths] if isinstance(paths, (str, Path)) else paths)
        n_inputs, cmap = len(files) + len(refused), None
        clean_stale(self.root / "tmp")
        with Staging(self.root / "tmp") as staging:
            staged = []
            for i, path in enumerate(files):
                try:
                    if path.suffix.lower() in CSV_SUFFIXES:
                        cmap = cmap or csv_import.load_column_map(column_map)
                        run = csv_import.read_csv_run(path, cmap)
                    else:
                        run = read_run(path)
                    staged.append(_stage(run, staging.dir / f"{i}.h5", str(path)))
                except AnytipError as e:
                    refused.append(_named(e, path))
            self._raise_if_refused(staged, refused, n_inputs)
            added, existing = self._commit(staged, protocol)
        # A second input with the content of an earlier one counts as unchanged.
        unchanged, seen = [], set()
        for s in staged:
            run_id = s.record.run_id
            if run_id not in added or run_id in seen:
                unchanged.append(existing.get(run_id) or added[run_id])
            seen.add(run_id)
        return ImportReport(added=list(added.values()), unchanged=unchanged)

    def set_protocol(self, unit_or_run_id: str, protocol: str | None) -> list[RunRecord]:
        """Mark one run (by run id) or every run of a unit as run by `protocol` (None: clear the
        mark), all or nothing; return the runs' records after. The catalog holds the mark, the run
        files stay as they are: a run whose file names its protocol (a simulated run) keeps it, one
        that names another refuses the call, and clearing leaves it alone. What a benchmark reads of a
        protocol: a unit's test session (`retest`), a designed calibration (`plan<seconds>`), the
        spec's `data.protocol`."""
        if protocol is not None:
            catalog.check_protocol(protocol)
        with self._write() as conn:
            records = self._resolve(conn, unit_or_run_id)
            _refuse_protocol_clashes(records, protocol, self.root)
            marked = _mark(conn, records, protocol)
        return [marked.get(rec.run_id, rec) for rec in records]

    def remove(self, unit_or_run_id: str) -> list[RunRecord]:
        """Remove one run (by run id) or every run of a unit; return the removed records."""
        with self._write() as conn:
            records = self._resolve(conn, unit_or_run_id)
            catalog.delete(conn, [r.run_id for r in records])
            catalog.forget_unused_models(conn)
        # The payloads are now orphans; delete them under a fresh write lock, so a
        # concurrent re-import of the same run id is never harmed.
        with self._write() as conn:
            self._sweep_orphans(conn)
        return records

    # ---- reading -------------------------------------------------------------------------

    def list_runs(
        self, unit: str | None = None, sensor_model: str | None = None, protocol: str | None = None
    ) -> list[RunRecord]:
        """Catalog rows matching every filter given, ordered by unit then run id."""
        with closing(self._connect()) as conn:
            return catalog.query(conn, unit=unit, sensor_model=sensor_model, protocol=protocol)

    def sensor_models(self) -> dict[str, str]:
        """Each sensor model's layout (`runfile.layout_json`: channel count and targets), by name.

        A catalog written before layouts were recorded learns a model's from its first readable run.
        """
        with closing(self._connect()) as conn:
            layouts = catalog.model_layouts(conn)
            for (model,) in conn.execute("SELECT DISTINCT sensor_model FROM runs"):
                if model not in layouts:
                    found = _layout_from_runs(conn, model, self.open_run)
                    if found is not None:
                        layouts[model] = found[0]
        return dict(sorted(layouts.items()))

    def units(self, sensor_model: str | None = None) -> list[str]:
        """Sorted unit serials (sensor ids), optionally of one sensor model."""
        return sorted({r.unit for r in self.list_runs(sensor_model=sensor_model)})

    def record(self, run_id: str) -> RunRecord:
        """The catalog row of `run_id`; AnytipError if there is none."""
        with closing(self._connect()) as conn:
            rec = catalog.get(conn, run_id)
        if rec is None:
            raise AnytipError(f"{self.root}: no run {run_id!r} in the registry")
        return rec

    def payload_path(self, run_id: str) -> Path:
        """Absolute path of a run's payload, checked to lie inside the registry."""
        return self._checked_path(self.record(run_id))

    def open_run(self, run_id: str) -> CalibrationRun:
        """Read a stored run, checking it still has the content hash it was imported with."""
        rec = self.record(run_id)
        path = self._checked_path(rec)
        if not path.is_file():
            raise AnytipError(f"{path}: payload of run {run_id!r} is missing; run verify")
        run = read_run(path)
        if run.content_hash() != rec.sha256:
            raise AnytipError(f"{path}: payload of run {run_id!r} changed since import (hash differs)")
        return run

    def export(self, unit_or_run_id: str, out_dir: str | Path, overwrite: bool = False,
               format_version: int | None = None) -> list[Path]:
        """Write interchange files `<out_dir>/<run_id>.h5` for a run or a whole unit.

        Each file holds the same values as the import (same `content_hash()`), in the run's
        own format version unless `format_version` converts it (1 only for the fingertip's
        targets). Files already there, and runs that cannot be converted, are refused before
        anything is written.
        """
        with closing(self._connect()) as conn:
            records = self._resolve(conn, unit_or_run_id)
        runs = [self.open_run(r.run_id) for r in records]  # checks the row's ids are safe file names
        if format_version is not None:
            runs = [run.as_version(format_version) for run in runs]
        out_dir = Path(out_dir)
        if out_dir.exists() and not out_dir.is_dir():
            raise AnytipError(f"{out_dir}: exists and is not a directory")
        taken = [str(out_dir / f"{r.run_id}.h5") for r in records if (out_dir / f"{r.run_id}.h5").exists()]
        if taken and not overwrite:
            raise AnytipError(f"{taken[0]}: already exists ({len(taken)} of {len(records)} files); "
                              "pass --force to overwrite")
        out_dir.mkdir(parents=True, exist_ok=True)
        written = []
        for rec, run in zip(records, runs, strict=True):
            dest = out_dir / f"{rec.run_id}.h5"
            temp = out_dir / f".{rec.run_id}.{os.getpid()}.tmp"
            try:
                write_run(run, temp)
                os.replace(temp, dest)
            finally:
                temp.unlink(missing_ok=True)
            written.append(dest)
        return written

    def content_hash(self, run_ids: Iterable[str] | None = None) -> str:
        """Order-independent sha256 over (run_id, sha256) of all runs, or of `run_ids` only; a protocol
        set in the registry is part of its run's entry (`catalog.hash_entry`)."""
        with closing(self._connect()) as conn:
            rows = conn.execute("SELECT run_id, sha256, protocol, protocol_set FROM runs").fetchall()
        pairs = {run_id: catalog.hash_entry(sha, protocol, bool(marked))
                 for run_id, sha, protocol, marked in rows}
        if run_ids is not None:
            wanted = set(run_ids)
            unknown = sorted(wanted - pairs.keys())
            if unknown:
                raise AnytipError(f"{self.root}: no such run(s): {', '.join(unknown)}")
            pairs = {r: pairs[r] for r in wanted}
        return catalog.hash_pairs(pairs.items())

    def verify(self) -> VerifyReport:
        """Re-read and re-hash every payload; find missing, corrupt and orphaned files."""
        # Under the write lock, the catalog and runs/ agree (writers place files only
        # inside their transaction); the slow re-hashing happens after releasing it.
        with self._write() as conn:
            records = catalog.query(conn)
            named = self._named_paths(records)
            orphans = [p for p in self._payload_files() if p not in named]
        report = VerifyReport(checked=len(records), orphans=orphans)
        for rec in records:
            self._verify_one(rec, report)
        return report

    # ---- internals -----------------------------------------------------------------------

    def _connect(self) -> sqlite3.Connection:
        return catalog.connect(self.db_path)

    @contextmanager
    def _write(self, placed: list[Path] | None = None) -> Iterator[sqlite3.Connection]:
        """One BEGIN IMMEDIATE transaction: committed on success, rolled back on any error.

        On error, files listed in `placed` are unlinked first, while the write lock is
        still held: once it is released another writer may legitimately put a file there.
        """
        with closing(self._connect()) as conn:
            conn.execute("BEGIN IMMEDIATE")
            try:
                yield conn
                conn.execute("COMMIT")
            except BaseException:
                for path in placed or ():
                    path.unlink(missing_ok=True)
                if conn.in_transaction:
                    conn.execute("ROLLBACK")
                raise

    def _commit(self, staged: list[_Staged], protocol: str | None = None
                ) -> tuple[dict[str, RunRecord], dict[str, RunRecord]]:
        """Move staged payloads into place and insert their rows, all or nothing, each marked as run
        by `protocol` where given (`set_protocol`).

        Returns (added, already present with the same content), both keyed by run id.
        """
        placed: list[Path] = []
        added: dict[str, RunRecord] = {}
        now = datetime.now(UTC).isoformat(timespec="microseconds").replace("+00:00", "Z")
        with self._write(placed) as conn:
            self._sweep_orphans(conn)
            existing, new = self._split_existing(conn, staged)
            if protocol is not None:
                records = [s.record for s in new] + list(existing.values())
                _refuse_protocol_clashes(records, protocol, self.root, marks_change=False)
                existing |= _mark(conn, existing.values(), protocol)
                for s in new:  # not in the catalog yet: their rows are inserted marked
                    s.record = _marked(s.record, protocol) or s.record
            _check_layouts(conn, new, self.db_path, self.open_run)
            for s in new:
                dest = self.root / s.record.path
                dest.parent.mkdir(parents=True, exist_ok=True)
                os.replace(s.temp, dest)
                placed.append(dest)
            _fsync_dirs({p.parent for p in placed})
            for s in new:
                added[s.record.run_id] = replace(s.record, imported_at=now)
                catalog.insert(conn, added[s.record.run_id])
        return added, existing

    def _split_existing(
        self, conn: sqlite3.Connection, staged: list[_Staged]
    ) -> tuple[dict[str, RunRecord], list[_Staged]]:
        """Rows already present (same content) and the staged runs still to add; refuse clashes."""
        existing: dict[str, RunRecord] = {}
        new: dict[str, _Staged] = {}
        clashes = []
        for s in staged:
            rec = catalog.get(conn, s.record.run_id)
            if rec is not None and rec.sha256 != s.record.sha256:
                clashes.append(_clash(s, str(self.root / rec.path), rec.sha256))
            elif rec is not None:
                existing[rec.run_id] = rec
            else:
                new.setdefault(s.record.run_id, s)
        if clashes:
            raise AnytipError(f"{self.root}: nothing imported:\n  " + "\n  ".join(clashes))
        return existing, list(new.values())

    def _raise_if_refused(self, staged: list[_Staged], refused: list[str], n_inputs: int) -> None:
        """Add within-batch and catalog clashes to `refused`; raise listing all if any."""
        seen: dict[str, _Staged] = {}
        for s in staged:
            first = seen.setdefault(s.record.run_id, s)
            if first.record.sha256 != s.record.sha256:
                refused.append(_clash(s, first.source, first.record.sha256))
        with closing(self._connect()) as conn:
            for s in seen.values():
                rec = catalog.get(conn, s.record.run_id)
                if rec is not None and rec.sha256 != s.record.sha256:
                    refused.append(_clash(s, str(self.root / rec.path), rec.sha256))
        if len(refused) == 1:
            raise AnytipError(f"nothing imported into {self.root}: {refused[0]}")
        if refused:
            head = f"{self.root}: refused {len(refused)} problem(s) in {n_inputs} input(s); nothing imported:"
            raise AnytipError(head + "\n  " + "\n  ".join(refused))

    def _resolve(self, conn: sqlite3.Connection, unit_or_run_id: str) -> list[RunRecord]:
        rec = catalog.get(conn, unit_or_run_id)
        records = [rec] if rec is not None else catalog.query(conn, unit=unit_or_run_id)
        if not records:
            raise AnytipError(f"{self.root}: no run or unit {unit_or_run_id!r} in the registry")
        return records

    def _checked_path(self, rec: RunRecord) -> Path:
        """The payload path rebuilt from the row's validated ids; refuse a row that disagrees."""
        try:
            rel = catalog.payload_relpath(rec.unit, rec.run_id)
        except (ValueError, AnytipError) as e:
            raise AnytipError(f"{self.db_path}: unsafe catalog row {rec.run_id!r}: {e}") from None
        if rec.path != rel:
            raise AnytipError(
                f"{self.db_path}: catalog row {rec.run_id!r} has path {rec.path!r}, expected {rel!r}"
            )
        return self.root / rel

    def _payload_files(self) -> list[str]:
        """Every entry two levels under runs/, as root-relative POSIX paths."""
        runs = self.root / "runs"
        out = []
        for unit_dir in sorted(runs.iterdir()) if runs.is_dir() else []:
            if unit_dir.is_dir() and not unit_dir.is_symlink():
                out += [p.relative_to(self.root).as_posix() for p in sorted(unit_dir.iterdir())]
            else:
                out.append(unit_dir.relative_to(self.root).as_posix())
        return out

    def _named_paths(self, records: Iterable[RunRecord]) -> set[str]:
        """Every payload path a row names: its `path` column and the path its ids give."""
        named = set()
        for rec in records:
            named.add(rec.path)
            try:
                named.add(catalog.payload_relpath(rec.unit, rec.run_id))
            except (ValueError, AnytipError):
                pass
        return named

    def _sweep_orphans(self, conn: sqlite3.Connection) -> list[str]:
        """Delete payload files under runs/ that no row names, logging each; return them.

        Only regular files inside the registry's own runs/ and links there (the link, never
        its target) are ever removed; a file that any row names, by its path column or by
        the path its ids give, is kept. Call only inside a write transaction.
        """
        named = self._named_paths(catalog.query(conn))
        runs = (self.root / "runs").resolve()
        removed = []
        for rel in self._payload_files():
            path = self.root / rel
            # a link is removed itself, never followed; a file only if it really lies in runs/
            inside = path.is_file() and runs in path.resolve().parents
            if rel in named or not (path.is_symlink() or inside):
                continue
            path.unlink(missing_ok=True)
            removed.append(rel)
            log.warning("%s: removed %s, a payload no catalog row names", self.root, rel)
        for unit_dir in runs.iterdir():
            if unit_dir.is_dir() and not unit_dir.is_symlink() and not any(unit_dir.iterdir()):
                unit_dir.rmdir()
        return removed

    def _verify_one(self, rec: RunRecord, report: VerifyReport) -> None:
        try:
            path = self._checked_path(rec)
        except AnytipError as e:
            report.bad_rows.append((rec.run_id, str(e)))
            return
        if not path.is_file():
            report.missing.append(rec.run_id)
            return
        try:
            run = read_run(path)
            expected_id = catalog.make_run_id(run)
        except (RunFormatError, AnytipError) as e:
            report.corrupt.append((rec.run_id, str(e)))
            return
        if run.content_hash() != rec.sha256:
            report.corrupt.append((rec.run_id, f"{path}: content hash differs from the catalog"))
        elif expected_id != rec.run_id or run.sensor_id != rec.unit:
            problem = f"{path}: holds run {expected_id!r} of unit {run.sensor_id!r}"
            report.corrupt.append((rec.run_id, problem))


def _check_layouts(conn: sqlite3.Connection, staged: Sequence[_Staged], db_path: Path,
                   open_run: Callable[[str], CalibrationRun]) -> None:
    """Refuse runs whose channel count or targets (names, units, components) disagree with the
    layout the catalog records for their sensor model, or, for a model new to the catalog,
    with the other runs of the same import; then record the layouts of new models."""
    recorded = catalog.model_layouts(conn)
    layout = {model: (text, f"recorded in {db_path}") for model, text in recorded.items()}
    for model in {s.record.sensor_model for s in staged} - layout.keys():
        found = _layout_from_runs(conn, model, open_run)
        if found is not None:
            layout[model] = found
    problems = []
    for s in staged:
        mine = layout_json(s.record.channels, s.targets)
        theirs, where = layout.setdefault(s.record.sensor_model, (mine, s.source))
        if theirs != mine:
            problems.append(f"{s.source}: sensor model {s.record.sensor_model!r} has "
                            f"{describe_layout(theirs)} ({where}), this run has {describe_layout(mine)}")
    if problems:
        raise AnytipError(f"nothing imported into {db_path.parent}: " + "; ".join(problems))
    for model, (text, _) in layout.items():
        if model not in recorded:
            catalog.record_model(conn, model, text)


def _layout_from_runs(conn: sqlite3.Connection, model: str,
                      open_run: Callable[[str], CalibrationRun]) -> tuple[str, str] | None:
    """The layout of `model` read from its first readable run, for a catalog written before
    layouts were recorded; None when the catalog has no run of it."""
    run_ids = [r for (r,) in conn.execute(
        "SELECT run_id FROM runs WHERE sensor_model = ? ORDER BY run_id", (model,))]
    problems = []
    for run_id in run_ids:
        try:
            return open_run(run_id).layout(), f"run {run_id}"
        except AnytipError as e:
            problems.append(str(e))
    if problems:
        raise AnytipError(f"sensor model {model!r}: no run of it in the catalog can be read to learn its "
                          f"layout (run `anytip data verify`): {problems[0]}")
    return None


def _stage(run: CalibrationRun, temp: Path, source: str) -> _Staged:
    """Validate `run`, write it to `temp` (fsynced) and describe its catalog row."""
    run.validate(source)
    try:
        run_id = catalog.make_run_id(run)
    except ValueError as e:
        raise AnytipError(str(e)) from None
    record = catalog.record_for(run, run_id, run.content_hash(), imported_at="")
    write_run(run, temp)
    fd = os.open(temp, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
    return _Staged(record=record, temp=temp, source=source, targets=run.target_layout)


def _collect_inputs(paths: Iterable[str | Path]) -> tuple[list[Path], list[str]]:
    """Input files in a stable order, and problems with paths that cannot be inputs."""
    files, refused = [], []
    suffixes = RUN_SUFFIXES + CSV_SUFFIXES
    for p in map(Path, paths):
        if p.is_dir():
            files += sorted(f for f in p.rglob("*") if f.is_file() and f.suffix.lower() in suffixes)
        elif not p.exists():
            refused.append(f"{p}: no such file or directory")
        elif p.suffix.lower() not in suffixes:
            refused.append(f"{p}: not a run file ({', '.join(suffixes)})")
        else:
            files.append(p)
    return files, refused


def _named(error: Exception, source: str | Path) -> str:
    """The error message, prefixed with the input's name unless it already starts with it."""
    msg = str(error)
    return msg if msg.startswith(str(source)) else f"{source}: {msg}"


def _marked(rec: RunRecord, protocol: str | None) -> RunRecord | None:
    """`rec` marked as run by `protocol` (None: its mark cleared), or None where its file names its
    protocol (a mark never replaces that)."""
    if rec.protocol is not None and not rec.protocol_set:
        return None
    return replace(rec, protocol=protocol, protocol_set=protocol is not None)


def _mark(conn: sqlite3.Connection, records: Iterable[RunRecord], protocol: str | None
          ) -> dict[str, RunRecord]:
    """Mark the catalog rows of `records` as `_marked` says, inside the caller's transaction; the
    changed records by run id."""
    changed = {}
    for rec in records:
        new = _marked(rec, protocol)
        if new is not None:
            catalog.set_protocol(conn, rec.run_id, protocol)
            changed[rec.run_id] = new
    return changed


def _refuse_protocol_clashes(records: Sequence[RunRecord], protocol: str | None, root: Path,
                             marks_change: bool = True) -> None:
    """Raise, naming every run, where marking `records` as run by `protocol` (None: clearing the
    mark) would contradict the protocol a run's file names, or (unless `marks_change`) another
    mark the registry holds."""
    problems = []
    for rec in records:
        if rec.protocol is None or rec.protocol == protocol or (rec.protocol_set and marks_change):
            continue
        if protocol is None and not rec.protocol_set:  # nothing to clear: the file names it
            continue
        whose = "the registry marks it" if rec.protocol_set else "its file names"
        hint = " (change a mark with `anytip data protocol`)" if rec.protocol_set else ""
        problems.append(f"run {rec.run_id}: {whose} protocol {rec.protocol!r}{hint}")
    if problems:
        wanted = f"marked as run by protocol {protocol!r}" if protocol else "have its protocol cleared"
        raise AnytipError(f"{root}: nothing changed; a run cannot be {wanted} where:\n  "
                          + "\n  ".join(problems))


def _clash(s: _Staged, other: str, other_sha: str) -> str:
    return (f"{s.source}: run id {s.record.run_id!r} (sha256 {s.record.sha256[:12]}) is already "
            f"taken by {other} with different content (sha256 {other_sha[:12]})")


def _fsync_dirs(dirs: Iterable[Path]) -> None:
    for d in dirs:
        fd = os.open(d, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
