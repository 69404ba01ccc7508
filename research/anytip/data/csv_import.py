"""Rig CSV logs -> CalibrationRun, through a column map (configs/csv/*.yaml) and a sidecar.

The column map says which CSV columns hold time, pressure (C), the labels (the fingertip's
force (3) and angles (2), or any named targets with their units and components: a
format-version-2 run) and optionally temperature (C) and in_contact, how to convert them
to the format's units, and metadata defaults. Columns it does not name are ignored. Per-log metadata
(sensor_id, created, and overrides of the defaults) comes from a sidecar next to the
log: `<log>.json`, `<log>.yaml` or `<log>.yml` (also `<log>.csv.json` etc.).

Bad input raises `CsvFormatError` (an AnytipError) naming the file, line and column.
Numbers are parsed by `np.loadtxt` with a fixed dtype (100k x 34 in about 0.2 s); only
a failing file is re-scanned cell by cell to find the offending line.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from datetime import datetime
from pathlib import Path
from typing import Any, Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from anytip.data.runfile import (
    PRESSURE_PROBLEM,
    CalibrationRun,
    Target,
    parse_created,
    pressure_outside_range,
)
from anytip.errors import AnytipError
from anytip.rundir import builtin
from anytip.validation import describe_error, format_validation_error, load_yaml

DEFAULT_COLUMN_MAP = builtin("configs") / "csv" / "rig34.yaml"
SIDECAR_SUFFIXES = (".json", ".yaml", ".yml")

ColumnRef = int | str  # 0-based column index, or a header name


class CsvFormatError(AnytipError):
    """A CSV log (or its sidecar) that cannot become a calibration run."""

    def __init__(self, path: str | Path, problem: str, line: int | None = None, column: str | None = None):
        self.path, self.problem, self.line, self.column = str(path), problem, line, column
        where = "".join([f", line {line}" if line else "", f", column {column}" if column else ""])
        super().__init__(f"{path}{where}: {problem}")


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class NamedTarget(_Strict):
    """A labelled quantity of a format-version-2 run: its columns, SI unit, component names
    (default: the column references) and the factor from logged values to that unit."""

    columns: list[ColumnRef] = Field(min_length=1)
    unit: str = Field(min_length=1)
    components: list[str] | None = None
    scale: float = Field(1.0, allow_inf_nan=False)

    @model_validator(mode="after")
    def _one_name_per_column(self) -> NamedTarget:
        if self.components is not None and len(self.components) != len(self.columns):
            raise ValueError(f"components names {len(self.components)} columns, "
                             f"columns has {len(self.columns)}")
        if self.scale == 0:
            raise ValueError("scale must not be 0")
        return self

    def component_names(self) -> tuple[str, ...]:
        return tuple(self.components or [str(c) for c in self.columns])


class Columns(_Strict):
    """Where each quantity lives in the log: column indices (from 0) or header names. Labels
    are the fingertip's `force` and `angles` (a version-1 run) or named `targets` (version 2)."""

    time: ColumnRef
    force: tuple[ColumnRef, ColumnRef, ColumnRef] | None = None
    pressure: list[ColumnRef] = Field(min_length=1)
    angles: tuple[ColumnRef, ColumnRef] | None = None
    targets: dict[str, NamedTarget] | None = Field(default=None, min_length=1)
    temperature: list[ColumnRef] | None = None
    in_contact: ColumnRef | None = None

    @model_validator(mode="after")
    def _temperature_per_barometer(self) -> Columns:
        if self.temperature is not None and len(self.temperature) != len(self.pressure):
            raise ValueError("temperature must name one column per pressure column")
        fingertip = (self.force is not None, self.angles is not None)
        if self.targets is None and fingertip != (True, True):
            raise ValueError("name the labels: force and angles (the fingertip), or targets")
        if self.targets is not None and any(fingertip):
            raise ValueError("name either force and angles or targets, not both")
        return self

    def refs(self) -> dict[str, list[ColumnRef]]:
        """Quantity -> its column references, for the quantities present (targets as
        `targets.<name>`)."""
        out = {"time": [self.time], "pressure": list(self.pressure)}
        if self.force is not None and self.angles is not None:
            out |= {"force": list(self.force), "angles": list(self.angles)}
        for name, t in (self.targets or {}).items():
            out[f"targets.{name}"] = list(t.columns)
        if self.temperature is not None:
            out["temperature"] = list(self.temperature)
        if self.in_contact is not None:
            out["in_contact"] = [self.in_contact]
        return out


class Units(_Strict):
    """Multipliers that turn logged values into the format's units (s, N, Pa, rad)."""

    time_scale: float = Field(1.0, gt=0)
    force_scale: float = Field(1.0, gt=0)
    force_sign: tuple[Literal[1, -1], Literal[1, -1], Literal[1, -1]] = (1, 1, 1)
    pressure_scale: float = Field(1.0, gt=0)
    angles: Literal["deg", "rad"] = "rad"


class Defaults(_Strict):
    """Run metadata used when the sidecar does not give it."""

    sensor_model: str | None = None
    sample_rate_hz: float | None = Field(None, gt=0)
    orientation_deg: float | None = None
    source: Literal["rig", "simulated", "import"] = "rig"


class ColumnMap(_Strict):
    """How to read one kind of rig CSV log (see configs/csv/rig34.yaml)."""

    name: str
    header: bool = True
    delimiter: str = Field(",", min_length=1, max_length=1)
    n_columns: int | None = Field(None, ge=1)
    columns: Columns
    units: Units = Units()
    defaults: Defaults = Defaults()

    @model_validator(mode="after")
    def _names_need_header(self) -> ColumnMap:
        names = [r for refs in self.columns.refs().values() for r in refs if isinstance(r, str)]
        if names and not self.header:
            raise ValueError(f"columns name header fields {names[:3]} but header is false")
        return self


class Sidecar(_Strict):
    """Per-log metadata next to the CSV; overrides the map's defaults."""

    sensor_id: str
    created: str
    sensor_model: str | None = None
    orientation_deg: float | None = None
    sample_rate_hz: float | None = Field(None, gt=0)
    source: Literal["rig", "simulated", "import"] | None = None
    operator: str | None = None
    rig: str | None = None
    firmware: str | None = None
    notes: str | None = None

    @field_validator("created", mode="before")
    @classmethod
    def _utc_iso(cls, value: Any) -> str:
        """Any ISO 8601 time (or a YAML timestamp) -> ISO 8601 UTC with 'Z'; naive means UTC."""
        t = parse_created(value.isoformat() if isinstance(value, datetime) else str(value))
        return t.isoformat().replace("+00:00", "Z")


def _load_mapping(path: Path) -> dict[str, Any]:
    try:
        text = path.read_text(encoding="utf-8")
        data = json.loads(text) if path.suffix == ".json" else load_yaml(text, str(path))
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise AnytipError(f"{path}: cannot read ({e})") from None
    if not isinstance(data, dict):
        raise AnytipError(f"{path}: expected a mapping of keys to values")
    return data


def load_column_map(source: str | Path | ColumnMap | None = None) -> ColumnMap:
    """Load and check a column map YAML (default configs/csv/rig34.yaml)."""
    if isinstance(source, ColumnMap):
        return source
    path = Path(source) if source is not None else DEFAULT_COLUMN_MAP
    try:
        return ColumnMap.model_validate(_load_mapping(path))
    except ValidationError as e:
        raise AnytipError(format_validation_error(e, str(path), ColumnMap, "bad column map")) from None


def find_sidecar(csv_path: Path) -> Path | None:
    """The one sidecar file of `csv_path`, None if there is none; refuse two."""
    found = [p for suffix in SIDECAR_SUFFIXES
             for p in (csv_path.with_suffix(suffix), csv_path.with_name(csv_path.name + suffix))
             if p.is_file()]
    if len(found) > 1:
        raise CsvFormatError(csv_path, f"more than one sidecar: {', '.join(map(str, found))}")
    return found[0] if found else None


def read_sidecar(csv_path: Path, overrides: Mapping[str, Any] | None = None) -> Sidecar:
    """Metadata for `csv_path`: its sidecar file, updated with `overrides`."""
    sidecar = find_sidecar(csv_path)
    data = _load_mapping(sidecar) if sidecar is not None else {}
    data.update(overrides or {})
    where = sidecar or f"{csv_path} (no sidecar {csv_path.stem}.json/.yaml found)"
    try:
        return Sidecar.model_validate(data)
    except ValidationError as e:
        problems = "; ".join(describe_error(x, Sidecar) for x in e.errors())
        raise CsvFormatError(where, f"bad run metadata: {problems}") from None


def read_csv_run(
    path: str | Path, column_map: str | Path | ColumnMap | None = None,
    metadata: Mapping[str, Any] | None = None,
) -> CalibrationRun:
    """Read one rig CSV log into a validated CalibrationRun.

    `column_map` defaults to configs/csv/rig34.yaml; `metadata` overrides the sidecar's keys.
    """
    path = Path(path)
    cmap = load_column_map(column_map)
    meta = read_sidecar(path, metadata)
    table = _Table.read(path, cmap)
    run = table.to_run(cmap, _run_metadata(path, cmap, meta))
    return run.validate(path)


def _run_metadata(path: Path, cmap: ColumnMap, meta: Sidecar) -> dict[str, Any]:
    defaults = cmap.defaults
    out = {
        "sensor_id": meta.sensor_id, "created": meta.created,
        "sensor_model": meta.sensor_model or defaults.sensor_model,
        "orientation_deg": _orientation(cmap, meta),
        "sample_rate_hz": meta.sample_rate_hz or defaults.sample_rate_hz,
        "source": meta.source or defaults.source,
    }
    missing = [k for k, v in out.items() if v is None]
    if missing:
        raise CsvFormatError(path, f"no {', '.join(missing)} in the sidecar or the column map's defaults")
    extra = {k: getattr(meta, k) for k in ("operator", "rig", "firmware", "notes") if getattr(meta, k)}
    return out | {"extra": extra}


def _orientation(cmap: ColumnMap, meta: Sidecar) -> float | None:
    """The sidecar's orientation, else the map's; a v2 run (named targets) defaults to 0."""
    if meta.orientation_deg is not None:
        return meta.orientation_deg
    if cmap.defaults.orientation_deg is None and cmap.columns.targets is not None:
        return 0.0
    return cmap.defaults.orientation_deg


class _Table:
    """The mapped columns of one CSV log as float64, with file line numbers for messages."""

    def __init__(self, path: Path, lines: list[str], first: int, index: dict[str, list[int]],
                 names: list[str], data: np.ndarray):
        self.path, self.lines, self.first, self.index, self.names = path, lines, first, index, names
        self.data = data  # (N, K): column j holds file column used[j]
        self.used = _used(index)

    @classmethod
    def read(cls, path: Path, cmap: ColumnMap) -> _Table:
        try:
            lines = path.read_text(encoding="utf-8-sig").splitlines()
        except (OSError, UnicodeDecodeError) as e:
            raise CsvFormatError(path, f"cannot read ({e})") from None
        first = next((i for i, line in enumerate(lines) if line.strip()), None)
        if first is None:
            raise CsvFormatError(path, "the file is empty")
        d = cmap.delimiter
        header = [c.strip() for c in lines[first].split(d)] if cmap.header else None
        start = first + 1 if header is not None else first
        n_cols = cmap.n_columns or len(lines[first].split(d))
        if header is not None and len(header) != n_cols:
            raise CsvFormatError(path, f"header has {len(header)} columns, expected {n_cols}", first + 1)
        _check_column_counts(path, lines, start, d, n_cols)
        names = header or [str(i) for i in range(n_cols)]
        index = _resolve_columns(path, cmap, header, n_cols)
        used = _used(index)
        body = lines[start:]
        if not any(line.strip() for line in body):
            raise CsvFormatError(path, "no data rows")
        try:
            data = np.loadtxt(body, delimiter=d, usecols=used, dtype=np.float64, ndmin=2, comments=None)
        except ValueError as e:
            _find_bad_cell(path, lines, start, d, used, names)
            raise CsvFormatError(path, f"cannot parse numbers ({e})") from None
        return cls(path, lines, start, index, names, data)

    def column(self, quantity: str) -> np.ndarray:
        """The columns of one quantity, (N, k) float64."""
        return self.data[:, [self.used.index(i) for i in self.index[quantity]]]

    def line_of(self, row: int) -> int:
        """File line number (from 1) of data row `row` (blank lines are skipped by the parser)."""
        rows = [i for i in range(self.first, len(self.lines)) if self.lines[i].strip()]
        return rows[row] + 1

    def fail(self, quantity: str, row: int, k: int, problem: str) -> CsvFormatError:
        return CsvFormatError(self.path, problem, self.line_of(row), self._colname(quantity, k))

    def _colname(self, quantity: str, k: int) -> str:
        i = self.index[quantity][k]
        return f"{i} ({self.names[i]})"

    def pressure(self, scale: float) -> np.ndarray:
        """(N, C) float32 Pa: the logged pressures times `scale`, each checked to be an absolute reading."""
        pressure = (self.column("pressure") * scale).astype(np.float32)
        outside = pressure_outside_range(pressure)
        if outside is not None:
            row, k, value = outside
            raise self.fail("pressure", row, k, f"pressure {value:.6g} Pa (after pressure_scale {scale:g}): "
                                                f"{PRESSURE_PROBLEM}")
        return pressure

    def to_run(self, cmap: ColumnMap, meta: dict[str, Any]) -> CalibrationRun:
        u = cmap.units
        for quantity in [q for q in self.index if q not in ("temperature", "in_contact")]:
            bad = np.argwhere(~np.isfinite(self.column(quantity)))
            if len(bad):
                raise self.fail(quantity, int(bad[0, 0]), int(bad[0, 1]), f"{quantity} is NaN or infinite")
        time = self.column("time")[:, 0] * u.time_scale
        back = np.flatnonzero(np.diff(time) < 0)
        if len(back):
            raise self.fail("time", int(back[0]) + 1, 0, "time decreases")
        in_contact = None
        if "in_contact" in self.index:
            flag = self.column("in_contact")[:, 0]
            bad = np.flatnonzero((flag != 0) & (flag != 1))
            if len(bad):
                problem = f"in_contact must be 0 or 1, got {flag[bad[0]]}"
                raise self.fail("in_contact", int(bad[0]), 0, problem)
            in_contact = flag == 1
        common = dict(
            time=time, pressure=self.pressure(u.pressure_scale),
            temperature=(self.column("temperature").astype(np.float32)
                         if "temperature" in self.index else None),
            in_contact=in_contact, **meta,
        )
        if cmap.columns.targets is not None:
            targets = {name: Target((self.column(f"targets.{name}") * t.scale).astype(np.float32), t.unit,
                                    t.component_names())
                       for name, t in cmap.columns.targets.items()}
            return CalibrationRun(targets=targets, format_version=2, **common)
        angles = self.column("angles")
        return CalibrationRun.fingertip(
            force=(self.column("force") * (u.force_scale * np.asarray(u.force_sign))).astype(np.float32),
            angles=(np.deg2rad(angles) if u.angles == "deg" else angles).astype(np.float32), **common,
        )


def _used(index: dict[str, list[int]]) -> list[int]:
    """Sorted file columns that some quantity reads."""
    return sorted({i for cols in index.values() for i in cols})


def _check_column_counts(path: Path, lines: list[str], start: int, d: str, n_cols: int) -> None:
    bad = next((i for i in range(start, len(lines))
                if lines[i].count(d) != n_cols - 1 and lines[i].strip()), None)
    if bad is not None:
        found = lines[bad].count(d) + 1
        raise CsvFormatError(path, f"row has {found} columns, expected {n_cols}", bad + 1)


def _resolve_columns(
    path: Path, cmap: ColumnMap, header: list[str] | None, n_cols: int
) -> dict[str, list[int]]:
    """Quantity -> column indices, checking every reference exists in this log."""
    out = {}
    for quantity, refs in cmap.columns.refs().items():
        cols = []
        for ref in refs:
            if isinstance(ref, str):
                if ref not in (header or []):
                    raise CsvFormatError(path, f"column map {cmap.name!r} key columns.{quantity}: "
                                               f"no header column named {ref!r}")
                cols.append(header.index(ref))
            elif not 0 <= ref < n_cols:
                raise CsvFormatError(path, f"column map {cmap.name!r} key columns.{quantity}: "
                                           f"column {ref} out of range (the log has {n_cols})")
            else:
                cols.append(ref)
        out[quantity] = cols
    return out


def _find_bad_cell(
    path: Path, lines: list[str], start: int, d: str, used: list[int], names: list[str]
) -> None:
    """Raise naming the first cell in a used column that is not a number."""
    for i in range(start, len(lines)):
        if not lines[i].strip():
            continue
        cells = lines[i].split(d)
        for j in used:
            text = cells[j].strip()
            if not _is_number(text):
                shown = repr(text) if text else "an empty cell"
                raise CsvFormatError(path, f"{shown} is not a number", i + 1, f"{j} ({names[j]})")


def _is_number(text: str) -> bool:
    # Python's float() accepts '1_000'; np.loadtxt does not.
    try:
        float(text)
    except ValueError:
        return False
    return "_" not in text
