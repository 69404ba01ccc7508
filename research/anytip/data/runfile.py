"""Calibration run files: the interchange format, versions 1 and 2 (docs/calibration_format.md).

One calibration run of one sensor unit is one HDF5 file. Version 1 is the fingertip's
(targets `force` and `angles` at the root); version 2 holds any named targets in a group
`targets`, each with its `unit` and `components`. A run keeps the version it was read or
made with, so a v1 run's content hash never changes; `as_version` converts. `read_run`
accepts exactly the format and refuses everything CALIBRATION_FORMAT.md lists with a
`RunFormatError` that names the file; `write_run` writes it (chunked, compressed,
fletcher32), and a read/write round trip changes no value.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any, TypeVar

import h5py
import numpy as np

from anytip.errors import AnytipError

T = TypeVar("T")
FORMAT = "calibration_run"
FORMAT_VERSIONS = (1, 2)
FORMAT_VERSION = 2  # what new runs are written as unless made as v1
SOURCES = ("rig", "simulated", "import")
SENSOR_ID_RE = re.compile(r"[A-Za-z0-9._-]{1,64}")
TARGET_NAME_RE = re.compile(r"[A-Za-z][A-Za-z0-9_]{0,63}")
REQUIRED_ATTRS = (
    "format", "format_version", "sensor_id", "sensor_model", "sample_rate_hz", "source", "created",
)
OPTIONAL_ATTRS = ("operator", "rig", "firmware", "notes", "simulator")
REQUIRED_DATASETS = ("time", "pressure")
V1_TARGET_DATASETS = ("force", "angles")
OPTIONAL_DATASETS = ("temperature", "in_contact")
TARGETS_GROUP = "targets"
DTYPES = {
    "time": np.float64, "pressure": np.float32, "force": np.float32, "angles": np.float32,
    "temperature": np.float32, "in_contact": np.bool_,
}
TARGET_DTYPE = np.float32
# Absolute pressure is positive. Above 2**24 Pa (about 168 bar, far past any barometer's range) float32's
# spacing exceeds 1 Pa, a barometer's resolution, so a tare could not recover the contact's change: a value
# there (3.4e38, float32's largest, is a common failed-read sentinel) is a logger's fault, not a reading.
PRESSURE_RANGE_PA = (0.0, float(2**24))
PRESSURE_PROBLEM = ("raw absolute readings lie between 0 and 2**24 Pa (about 168 bar); "
                    "a tared log, a unit other than Pa, or a failed read?")


@dataclass(frozen=True)
class TargetLayout:
    """What one target holds: its SI unit and the names of its k components."""

    unit: str
    components: tuple[str, ...]

    def to_json(self) -> dict[str, Any]:
        return {"unit": self.unit, "components": list(self.components)}


# The fingertip's targets, which version 1 implies.
V1_LAYOUT = {"force": TargetLayout("N", ("fx", "fy", "fz")), "angles": TargetLayout("rad", ("theta", "phi"))}


@dataclass
class Target:
    """One labelled quantity of a run: values (N, k) float32 in `unit`, columns `components`."""

    values: np.ndarray
    unit: str
    components: tuple[str, ...]

    @property
    def layout(self) -> TargetLayout:
        return TargetLayout(self.unit, tuple(self.components))


def fingertip_targets(force: np.ndarray, angles: np.ndarray) -> dict[str, Target]:
    """The targets of a fingertip run: force (N, 3) in N and angles (N, 2) in rad."""
    return {name: Target(values, V1_LAYOUT[name].unit, V1_LAYOUT[name].components)
            for name, values in (("force", force), ("angles", angles))}


def layout_json(channels: int, targets: dict[str, TargetLayout]) -> str:
    """A sensor model's layout as canonical JSON: channel count and targets (the registry's record)."""
    return json.dumps({"channels": int(channels), "targets": {k: v.to_json() for k, v in targets.items()}},
                      sort_keys=True)


def parse_created(created: object) -> datetime:
    """An ISO 8601 time as an aware UTC datetime; a time without a zone is UTC.

    Raises ValueError for text that is not a time, or one that leaves the range a
    datetime holds once moved to UTC (year 1 with a positive offset, for example).
    """
    if not isinstance(created, str):
        raise ValueError(f"'created' must be an ISO 8601 string, got {created!r}")
    try:
        t = datetime.fromisoformat(created)
        return t.replace(tzinfo=UTC) if t.tzinfo is None else t.astimezone(UTC)
    except (ValueError, OverflowError):
        raise ValueError(f"'created' {created!r} is not a valid ISO 8601 date and time") from None


class RunFormatError(AnytipError):
    """A calibration run file that does not follow the interchange format."""

    def __init__(self, path: str | Path, problem: str):
        self.path, self.problem = str(path), problem
        super().__init__(f"{path}: {problem}")


def check_sensor_id(sensor_id: str, where: str = "sensor_id") -> str:
    """Return `sensor_id` if it is a valid unit serial, else raise ValueError.

    The format's pattern admits '.' and '..', which would name directories; both are refused.
    """
    if not isinstance(sensor_id, str) or not SENSOR_ID_RE.fullmatch(sensor_id) or set(sensor_id) == {"."}:
        raise ValueError(f"{where} {sensor_id!r} must match [A-Za-z0-9._-]{{1,64}} and not be only dots")
    return sensor_id


@dataclass
class CalibrationRun:
    """One calibration run of one unit, in memory.

    Arrays have N rows: `time` (N,) float64 s; `pressure` (N, C) float32 Pa absolute;
    `targets` {name: Target (N, k) float32}, for the fingertip `force` (N, 3) N in the contact
    frame (Fz < 0 when pressing) and `angles` (N, 2) rad (theta, phi); optional `temperature`
    (N, C) float32 degC and `in_contact` (N,) bool. `extra` holds the optional attributes
    (operator, rig, firmware, notes, simulator), all strings. `format_version` is the
    version the run is written and hashed as (1 only for the fingertip's targets).
    """

    sensor_id: str
    sensor_model: str
    orientation_deg: float
    sample_rate_hz: float
    source: str
    created: str
    time: np.ndarray
    pressure: np.ndarray
    targets: dict[str, Target]
    temperature: np.ndarray | None = None
    in_contact: np.ndarray | None = None
    extra: dict[str, str] = field(default_factory=dict)
    format_version: int = FORMAT_VERSION

    @classmethod
    def fingertip(cls, *, force: np.ndarray, angles: np.ndarray, format_version: int = 1,
                  **fields: Any) -> CalibrationRun:
        """A run with the fingertip's targets (written as version 1 unless asked otherwise)."""
        return cls(targets=fingertip_targets(force, angles), format_version=format_version, **fields)

    @property
    def n_rows(self) -> int:
        return int(self.time.shape[0])

    @property
    def n_channels(self) -> int:
        return int(self.pressure.shape[1])

    @property
    def duration_s(self) -> float:
        """Robot time the run covers, in seconds (one sample period per row)."""
        return self.n_rows / float(self.sample_rate_hz)

    @property
    def target_layout(self) -> dict[str, TargetLayout]:
        return {name: t.layout for name, t in self.targets.items()}

    def layout(self) -> str:
        """The run's channel count and targets as canonical JSON (`layout_json`)."""
        return layout_json(self.n_channels, self.target_layout)

    def target(self, name: str) -> np.ndarray:
        """The values (N, k) of target `name`; an error names the run's targets if it has none."""
        if name not in self.targets:
            raise AnytipError(f"run of unit {self.sensor_id!r} (sensor model {self.sensor_model!r}) has no "
                              f"target {name!r}; its targets: {sorted(self.targets)}")
        return self.targets[name].values

    @property
    def force(self) -> np.ndarray:
        """The fingertip's contact force (N, 3) in N."""
        return self.target("force")

    @property
    def angles(self) -> np.ndarray:
        """The fingertip's contact angles (N, 2) in rad."""
        return self.target("angles")

    @property
    def simulator(self) -> dict[str, Any] | None:
        """The parsed `simulator` attribute, or None for measured runs."""
        text = self.extra.get("simulator")
        return None if text is None else json.loads(text)

    def attrs(self) -> dict[str, Any]:
        """Root attributes as written to the file."""
        out: dict[str, Any] = {
            "format": FORMAT, "format_version": int(self.format_version), "sensor_id": self.sensor_id,
            "sensor_model": self.sensor_model, "orientation_deg": float(self.orientation_deg),
            "sample_rate_hz": float(self.sample_rate_hz), "source": self.source,
            "created": self.created,
        }
        out.update({k: self.extra[k] for k in OPTIONAL_ATTRS if k in self.extra})
        return out

    def datasets(self) -> dict[str, np.ndarray]:
        """The datasets present, in format order, named by their path in the file (v2 targets
        as `targets/<name>`, sorted by name)."""
        out = {"time": self.time, "pressure": self.pressure}
        if self.format_version == 1:
            out |= {name: self.targets[name].values for name in V1_TARGET_DATASETS}
        else:  # by name, as HDF5 lists a group (the hash must not depend on the order given)
            out |= {f"{TARGETS_GROUP}/{name}": self.targets[name].values for name in sorted(self.targets)}
        return out | {n: getattr(self, n) for n in OPTIONAL_DATASETS if getattr(self, n) is not None}

    def as_version(self, version: int) -> CalibrationRun:
        """The same run written as `version`; version 1 holds only the fingertip's targets."""
        if version not in FORMAT_VERSIONS:
            raise AnytipError(f"format_version {version}: this code writes {list(FORMAT_VERSIONS)}")
        if version == 1 and self.target_layout != V1_LAYOUT:
            raise AnytipError(f"run of unit {self.sensor_id!r} cannot be written as format version 1: "
                              f"version 1 holds only {describe_targets(V1_LAYOUT)}; this run has "
                              f"{describe_targets(self.target_layout)}")
        return dataclasses.replace(self, format_version=version)

    def content_hash(self) -> str:
        """sha256 of the run's content: attributes and dataset values, not file bytes.

        Two files holding the same values hash the same whatever their chunking or
        compression, so re-importing a run is recognised as such. A v2 run's hash also covers
        its targets' units and components (a v1 run's are implied by the version).
        """
        h = hashlib.sha256()
        h.update(json.dumps(self.attrs(), sort_keys=True).encode())
        if self.format_version != 1:
            h.update(self.layout().encode())
        for name, arr in self.datasets().items():
            dtype = DTYPES.get(name, TARGET_DTYPE)
            arr = np.ascontiguousarray(arr, dtype=np.dtype(dtype).newbyteorder("<"))
            h.update(f"{name}:{arr.dtype.str}:{arr.shape}".encode())
            h.update(arr.tobytes())
        return h.hexdigest()

    def validate(self, path: str | Path = "<memory>") -> CalibrationRun:
        """Check the run against the format; raise RunFormatError naming `path`."""
        _validate(self, path)
        return self


def parse_layout(layout: str) -> tuple[int, dict[str, TargetLayout]]:
    """(channel count, targets) of a `layout_json` text."""
    data = json.loads(layout)
    return int(data["channels"]), {name: TargetLayout(t["unit"], tuple(t["components"]))
                                   for name, t in data["targets"].items()}


def describe_layout(layout: str) -> str:
    """'8 pressure channels and the targets force [N] (fx, fy, fz), ...' for a `layout_json` text."""
    channels, targets = parse_layout(layout)
    return f"{channels} pressure channels and the targets {describe_targets(targets)}"


def describe_targets(layout: dict[str, TargetLayout]) -> str:
    """'force [N] (fx, fy, fz), angles [rad] (theta, phi)'."""
    return ", ".join(f"{n} [{t.unit}] ({', '.join(t.components)})" for n, t in layout.items()) or "no targets"


def _problem(path: str | Path, msg: str) -> RunFormatError:
    return RunFormatError(path, msg)


def _validate(run: CalibrationRun, path: str | Path) -> None:
    if run.format_version not in FORMAT_VERSIONS or isinstance(run.format_version, bool):
        raise _problem(path, f"unknown format_version {run.format_version!r}; this reader knows "
                             f"{list(FORMAT_VERSIONS)}")
    try:
        check_sensor_id(run.sensor_id)
    except ValueError as e:
        raise _problem(path, str(e)) from None
    try:
        check_sensor_id(run.sensor_model, "sensor_model")
    except ValueError as e:
        raise _problem(path, str(e)) from None
    if run.source not in SOURCES:
        raise _problem(path, f"attribute 'source' is {run.source!r}; allowed: {', '.join(SOURCES)}")
    for name in ("orientation_deg", "sample_rate_hz"):
        value = getattr(run, name)
        number = isinstance(value, (int, float, np.floating, np.integer)) and not isinstance(value, bool)
        if not number or not math.isfinite(value):
            raise _problem(path, f"attribute {name!r} must be a finite number, got {value!r}")
    if not run.sample_rate_hz > 0 or not math.isfinite(run.n_rows / run.sample_rate_hz):
        raise _problem(path, f"attribute 'sample_rate_hz' must be > 0 and give a finite duration, "
                             f"got {run.sample_rate_hz}")
    try:
        parse_created(run.created)
    except ValueError as e:
        raise _problem(path, f"attribute {e}") from None
    for key, value in run.extra.items():
        if key not in OPTIONAL_ATTRS or not isinstance(value, str):
            raise _problem(
                path, f"optional attribute {key!r} must be one of {OPTIONAL_ATTRS} and a string"
            )
    for key, value in [("sensor_model", run.sensor_model), ("created", run.created), *run.extra.items()]:
        check_text(path, key, value)
    if "simulator" in run.extra:
        try:
            json.loads(run.extra["simulator"])
        except json.JSONDecodeError as e:
            raise _problem(path, f"attribute 'simulator' is not valid JSON ({e})") from None
    _validate_targets(run, path)
    _validate_arrays(run, path)


def _validate_targets(run: CalibrationRun, path: str | Path) -> None:
    """Names, units and components of the targets; version 1 holds exactly the fingertip's."""
    if run.format_version == 1:
        if run.target_layout != V1_LAYOUT:
            raise _problem(path, f"format version 1 holds the targets {describe_targets(V1_LAYOUT)}, got "
                                 f"{describe_targets(run.target_layout)}")
        return
    if not run.targets:
        raise _problem(path, f"group {TARGETS_GROUP!r} must hold at least one target dataset")
    for name, t in run.targets.items():
        where = f"target {TARGETS_GROUP}/{name}"
        if not isinstance(name, str) or not TARGET_NAME_RE.fullmatch(name):
            raise _problem(path, f"{where}: a target name must match [A-Za-z][A-Za-z0-9_]{{0,63}}")
        if not isinstance(t.unit, str) or not t.unit.strip():
            raise _problem(path, f"{where}: attribute 'unit' must be a non-empty string, got {t.unit!r}")
        check_text(path, f"{where} unit", t.unit)
        comps = t.components
        if not comps or not all(isinstance(c, str) and c.strip() for c in comps):
            raise _problem(path, f"{where}: attribute 'components' must be a list of non-empty strings, "
                                 f"got {list(comps) if isinstance(comps, tuple) else comps!r}")
        if len(set(comps)) != len(comps):
            raise _problem(path, f"{where}: attribute 'components' names a column twice: {list(comps)}")
        for c in comps:
            check_text(path, f"{where} components", c)


def check_text(path: str | Path, key: str, value: str) -> None:
    """HDF5 strings are UTF-8 without NUL characters; refuse text that cannot be stored."""
    try:
        value.encode("utf-8")
    except UnicodeEncodeError:
        raise _problem(path, f"attribute {key!r} is not valid UTF-8 text") from None
    if "\x00" in value:
        raise _problem(path, f"attribute {key!r} contains a NUL character")


def _validate_arrays(run: CalibrationRun, path: str | Path) -> None:
    n = run.time.shape[0] if run.time.ndim == 1 else -1
    if run.time.ndim != 1:
        raise _problem(path, f"dataset 'time' must have shape (N,), got {run.time.shape}")
    if run.pressure.ndim != 2 or run.pressure.shape[1] < 1:
        raise _problem(path, f"dataset 'pressure' must have shape (N, C), got {run.pressure.shape}")
    c = run.pressure.shape[1]
    expected = {"pressure": (n, c), "temperature": (n, c), "in_contact": (n,)}
    prefix = "" if run.format_version == 1 else f"{TARGETS_GROUP}/"
    expected |= {prefix + name: (n, len(t.components)) for name, t in run.targets.items()}
    for name, arr in run.datasets().items():
        if name == "time":
            continue
        want = expected[name]
        if not isinstance(arr, np.ndarray):
            raise _problem(path, f"dataset {name!r} must be an array, got {type(arr).__name__}")
        if arr.ndim != len(want):
            raise _problem(
                path, f"dataset {name!r} must have {len(want)} dimension(s), got shape {arr.shape}"
            )
        if arr.shape[0] != n:
            raise _problem(path, f"dataset {name!r} has {arr.shape[0]} rows but 'time' has {n}")
        if arr.shape != want:
            why = " (as its 'components' attribute names)" if prefix and name.startswith(prefix) else ""
            raise _problem(path, f"dataset {name!r} must have {want[1]} columns{why}, got {arr.shape[1]}")
    if n == 0:
        raise _problem(path, "the run has no rows")
    checked = {"pressure": run.pressure} | {prefix + k: t.values for k, t in run.targets.items()}
    check_values(path, run.time, run.pressure, checked)


def check_values(path: str | Path, time: np.ndarray, pressure: np.ndarray, checked: dict[str, np.ndarray]
                 ) -> None:
    """The format's checks of values (shapes already checked): every dataset of `checked` finite,
    `pressure` (N, C) Pa inside PRESSURE_RANGE_PA, `time` (N,) s finite and never decreasing;
    RunFormatError naming `path` and the first row at fault."""
    for name, values in checked.items():
        bad = ~np.isfinite(values)
        if bad.any():
            row = int(np.argwhere(bad)[0][0])
            raise _problem(path, f"dataset {name!r} holds NaN or infinite values (first at row {row})")
    outside = pressure_outside_range(pressure)
    if outside is not None:
        row, column, value = outside
        raise _problem(path, f"dataset 'pressure' holds {value:.6g} Pa at row {row}, column {column}: "
                             f"{PRESSURE_PROBLEM}")
    if not np.isfinite(time).all():
        raise _problem(path, "dataset 'time' holds NaN or infinite values")
    steps = np.diff(time)
    if (steps < 0).any():
        row = int(np.argmax(steps < 0)) + 1
        raise _problem(path, f"dataset 'time' decreases at row {row}")


def pressure_outside_range(pressure: np.ndarray) -> tuple[int, int, float] | None:
    """(row, column, value) of the first finite reading outside PRESSURE_RANGE_PA, or None.

    pressure: (N, C) Pa, absolute. Non-finite values are left to the finite check.
    """
    low, high = PRESSURE_RANGE_PA
    values = np.asarray(pressure)
    bad = np.isfinite(values) & ((values <= low) | (values >= high))
    if not bad.any():
        return None
    row, column = (int(i) for i in np.argwhere(bad)[0])
    return row, column, float(values[row, column])


def attr_value(value: Any) -> Any:
    """h5py returns numpy scalars and bytes; give plain Python values."""
    if isinstance(value, bytes):
        return value.decode("utf-8")
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray) and value.shape == ():
        return value.item()
    return value


def read_run(path: str | Path) -> CalibrationRun:
    """Read and validate one interchange file; raise RunFormatError naming it."""
    return read_hdf5(path, _read_open, "run")


def read_hdf5(path: str | Path, read_open: Callable[[h5py.File, Path], T], what: str) -> T:
    """`read_open` on the HDF5 file at `path` once it is known to be read from itself alone
    (`check_self_contained`); any failure a RunFormatError naming the file (`what`: the run, the log)."""
    path = Path(path)
    if not path.is_file():
        raise _problem(path, "no such file")
    try:
        with h5py.File(path, "r") as f:
            check_self_contained(f, path)
            return read_open(f, path)
    except RunFormatError:
        raise
    except MemoryError:
        raise _problem(path, f"the {what} does not fit in memory") from None
    except (OSError, KeyError, RuntimeError, ValueError) as e:
        # h5py reports damaged headers as KeyError or RuntimeError, not only OSError.
        raise _problem(path, f"not a readable HDF5 file (truncated or corrupt?): {e}") from None


def check_self_contained(f: h5py.File, path: str | Path) -> None:
    """Refuse a file any of whose objects lives outside it: soft or external links, datasets
    with external raw storage, virtual datasets. A run file is read from itself alone."""
    problems: list[str] = []

    def visit(name: str, link: h5py.HardLink | h5py.SoftLink | h5py.ExternalLink) -> None:
        if isinstance(link, h5py.ExternalLink):
            problems.append(f"{name!r} is an external link (to {link.filename!r}); data must be in the file")
        elif isinstance(link, h5py.SoftLink):
            problems.append(f"{name!r} is a soft link (to {link.path!r}); links are not allowed")
        elif not problems:
            node = f.get(name)
            if isinstance(node, h5py.Dataset) and node.external:
                problems.append(f"dataset {name!r} uses external raw storage; data must live in the file")
            elif isinstance(node, h5py.Dataset) and node.is_virtual:
                problems.append(f"dataset {name!r} is a virtual dataset; data must live in the file")

    f.visititems_links(visit)
    if problems:
        raise _problem(path, problems[0])


def _free_memory_bytes() -> int:
    """Memory the process could still take, in bytes: the kernel's MemAvailable (free pages plus
    the cache it can reclaim), else all physical memory, else no limit known (1 TiB)."""
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 2**40


def check_size(f: h5py.File, path: Path) -> None:
    """Refuse datasets that would not fit in memory before reading any (a crafted file can
    declare 10^11 rows in a few bytes)."""
    total = 0
    for name, node in _data_nodes(f).items():
        total += int(node.size) * np.dtype(DTYPES.get(name, TARGET_DTYPE)).itemsize
    free = _free_memory_bytes()
    if total > free:
        raise _problem(path, f"datasets declare {total / 1e9:.3g} GB, more than the "
                             f"{free / 1e9:.3g} GB of memory available")


def _data_nodes(f: h5py.File) -> dict[str, h5py.Dataset]:
    """The datasets a reader takes, by path: the root's known names and the v2 targets."""
    names = [*REQUIRED_DATASETS, *V1_TARGET_DATASETS, *OPTIONAL_DATASETS]
    nodes = {n: f[n] for n in names if isinstance(f.get(n), h5py.Dataset)}
    group = f.get(TARGETS_GROUP)
    if isinstance(group, h5py.Group):
        nodes |= {f"{TARGETS_GROUP}/{k}": v for k, v in group.items() if isinstance(v, h5py.Dataset)}
    return nodes


def root_attrs(f: h5py.File, path: Path, required: tuple[str, ...], fmt: str) -> dict[str, Any]:
    """The file's root attributes as plain values; RunFormatError naming `path` where one of `required`
    is missing or `format` is not `fmt`."""
    attrs = {k: attr_value(v) for k, v in f.attrs.items()}
    for key in required:
        if key not in attrs:
            raise _problem(path, f"missing root attribute {key!r}")
    if attrs["format"] != fmt:
        raise _problem(path, f"attribute 'format' is {attrs['format']!r}, expected {fmt!r}")
    return attrs


def _read_open(f: h5py.File, path: Path) -> CalibrationRun:
    attrs = root_attrs(f, path, REQUIRED_ATTRS, FORMAT)
    version = attrs["format_version"]
    if not isinstance(version, int) or isinstance(version, bool):
        raise _problem(path, f"attribute 'format_version' must be an integer, got {version!r}")
    if version not in FORMAT_VERSIONS:
        raise _problem(path, f"unknown format_version {version}; this reader knows {list(FORMAT_VERSIONS)}")
    if version == 1 and "orientation_deg" not in attrs:
        raise _problem(path, "missing root attribute 'orientation_deg' (required in format version 1)")
    for key in ("sensor_id", "sensor_model", "source", "created"):
        if not isinstance(attrs[key], str):
            raise _problem(path, f"attribute {key!r} must be a string, got {attrs[key]!r}")
    check_size(f, path)
    arrays = {name: read_dataset(f, name, path, required=name in REQUIRED_DATASETS)
              for name in REQUIRED_DATASETS + OPTIONAL_DATASETS}
    targets = _read_v1_targets(f, path) if version == 1 else _read_v2_targets(f, path)
    extra = {k: attrs[k] for k in OPTIONAL_ATTRS if k in attrs}
    for key, value in extra.items():
        if not isinstance(value, str):
            raise _problem(path, f"optional attribute {key!r} must be a string, got {value!r}")
    run = CalibrationRun(
        sensor_id=attrs["sensor_id"], sensor_model=attrs["sensor_model"],
        orientation_deg=attrs.get("orientation_deg", 0.0), sample_rate_hz=attrs["sample_rate_hz"],
        source=attrs["source"], created=attrs["created"], extra=extra, targets=targets,
        format_version=version, **arrays,
    )
    run.validate(path)
    run.orientation_deg, run.sample_rate_hz = float(run.orientation_deg), float(run.sample_rate_hz)
    return run


def _read_v1_targets(f: h5py.File, path: Path) -> dict[str, Target]:
    """`force` and `angles` at the root, with the fingertip's units and components."""
    values = {name: read_dataset(f, name, path, required=True) for name in V1_TARGET_DATASETS}
    return fingertip_targets(values["force"], values["angles"])


def _read_v2_targets(f: h5py.File, path: Path) -> dict[str, Target]:
    """The datasets of the `targets` group with their `unit` and `components` attributes."""
    for name in V1_TARGET_DATASETS:
        if name in f:
            raise _problem(path, f"format version 2 keeps targets in the group {TARGETS_GROUP!r}; "
                                 f"found {name!r} at the root")
    group = f.get(TARGETS_GROUP)
    if not isinstance(group, h5py.Group):
        raise _problem(path, f"missing group {TARGETS_GROUP!r} (format version 2)")
    targets = {}
    for name in group:
        where = f"{TARGETS_GROUP}/{name}"
        node = group[name]
        if not isinstance(node, h5py.Dataset):
            raise _problem(path, f"{where!r} is not a dataset")
        for key in ("unit", "components"):
            if key not in node.attrs:
                raise _problem(path, f"target {where}: missing attribute {key!r}")
        unit = attr_value(node.attrs["unit"])
        targets[name] = Target(read_dataset(f, where, path, required=True), unit,
                               _components(node.attrs["components"], where, path))
    return targets


def _components(value: Any, where: str, path: Path) -> tuple[str, ...]:
    """A `components` attribute as a tuple of strings (h5py gives str, bytes or an array)."""
    value = attr_value(value)
    items = [value] if isinstance(value, str) else value
    if not isinstance(items, (np.ndarray, list, tuple)) or np.ndim(items) != 1:
        raise _problem(path, f"target {where}: attribute 'components' must be a list of strings, "
                             f"got {value!r}")
    out = [attr_value(c) for c in items]
    if not all(isinstance(c, str) for c in out):
        raise _problem(path, f"target {where}: attribute 'components' must be a list of strings, got {out!r}")
    return tuple(out)


def read_dataset(f: h5py.File, name: str, path: Path, required: bool) -> np.ndarray | None:
    if name not in f:
        if required:
            raise _problem(path, f"missing dataset {name!r}")
        return None
    node = f[name]
    if not isinstance(node, h5py.Dataset):
        raise _problem(path, f"{name!r} is not a dataset")
    want = np.dtype(DTYPES.get(name, TARGET_DTYPE))
    kind = node.dtype.kind
    if name == "in_contact":
        if kind not in "bui":
            raise _problem(path, f"dataset 'in_contact' must be boolean, got dtype {node.dtype}")
    elif kind not in "fiu":
        raise _problem(path, f"dataset {name!r} must be numeric, got dtype {node.dtype}")
    try:
        data = node[()]
    except OSError as e:
        raise _problem(path, f"dataset {name!r} cannot be read (corrupt or truncated): {e}") from None
    if name == "in_contact" and kind != "b":
        if not np.isin(data, (0, 1)).all():
            raise _problem(path, "dataset 'in_contact' must hold only 0/1 or booleans")
    return np.asarray(data).astype(want, copy=False)


def write_run(run: CalibrationRun, path: str | Path, *, compression: str | None = "gzip") -> Path:
    """Write `run` as an interchange file at `path` (chunked, shuffled, gzip, fletcher32).

    Validates first; nothing is written for an invalid run, and a write that fails part
    way removes its file. Not atomic by itself: the registry writes to a temporary name
    and renames.
    """
    path = Path(path)
    run.validate(path)
    try:
        with h5py.File(path, "w", libver=("earliest", "v110")) as f:
            for key, value in run.attrs().items():
                f.attrs[key] = value
            for name, arr in run.datasets().items():
                dtype = DTYPES.get(name, TARGET_DTYPE)
                write_dataset(f, name, np.ascontiguousarray(arr, dtype=dtype), compression)
            if run.format_version != 1:
                for name, t in run.targets.items():
                    node = f[f"{TARGETS_GROUP}/{name}"]
                    node.attrs["unit"] = t.unit
                    node.attrs["components"] = list(t.components)
    except BaseException:
        path.unlink(missing_ok=True)  # never leave half a file behind
        raise
    return path


def write_dataset(f: h5py.File, name: str, arr: np.ndarray, compression: str | None = "gzip") -> None:
    """One dataset in chunks of about 256 KiB of rows, shuffled, compressed, fletcher32."""
    chunk_rows = int(min(arr.shape[0], max(1, 2**18 // max(1, arr[:1].nbytes))))
    f.create_dataset(
        name, data=arr, chunks=(chunk_rows, *arr.shape[1:]), compression=compression,
        compression_opts=1 if compression == "gzip" else None,
        shuffle=compression is not None, fletcher32=True,
    )
