"""Calibration run files: the interchange format, version 1 (docs/calibration_format.md).

One calibration run of one sensor unit is one HDF5 file. `read_run` accepts exactly
the format and refuses everything CALIBRATION_FORMAT.md lists with a `RunFormatError`
that names the file; `write_run` writes it (chunked, compressed, fletcher32), and a
read/write round trip changes no value.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import re
from dataclasses import dataclass, field
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import h5py
import numpy as np

from anytip.errors import AnytipError

FORMAT = "calibration_run"
FORMAT_VERSION = 1
SOURCES = ("rig", "simulated", "import")
SENSOR_ID_RE = re.compile(r"[A-Za-z0-9._-]{1,64}")
REQUIRED_ATTRS = (
    "format", "format_version", "sensor_id", "sensor_model", "orientation_deg",
    "sample_rate_hz", "source", "created",
)
OPTIONAL_ATTRS = ("operator", "rig", "firmware", "notes", "simulator")
REQUIRED_DATASETS = ("time", "pressure", "force", "angles")
OPTIONAL_DATASETS = ("temperature", "in_contact")
DTYPES = {
    "time": np.float64, "pressure": np.float32, "force": np.float32, "angles": np.float32,
    "temperature": np.float32, "in_contact": np.bool_,
}


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
    `force` (N, 3) float32 N in the contact frame (Fz < 0 when pressing); `angles` (N, 2)
    float32 rad (theta, phi); optional `temperature` (N, C) float32 degC and
    `in_contact` (N,) bool. `extra` holds the optional attributes (operator, rig,
    firmware, notes, simulator), all strings.
    """

    sensor_id: str
    sensor_model: str
    orientation_deg: float
    sample_rate_hz: float
    source: str
    created: str
    time: np.ndarray
    pressure: np.ndarray
    force: np.ndarray
    angles: np.ndarray
    temperature: np.ndarray | None = None
    in_contact: np.ndarray | None = None
    extra: dict[str, str] = field(default_factory=dict)

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
    def simulator(self) -> dict[str, Any] | None:
        """The parsed `simulator` attribute, or None for measured runs."""
        text = self.extra.get("simulator")
        return None if text is None else json.loads(text)

    def attrs(self) -> dict[str, Any]:
        """Root attributes as written to the file."""
        out: dict[str, Any] = {
            "format": FORMAT, "format_version": FORMAT_VERSION, "sensor_id": self.sensor_id,
            "sensor_model": self.sensor_model, "orientation_deg": float(self.orientation_deg),
            "sample_rate_hz": float(self.sample_rate_hz), "source": self.source,
            "created": self.created,
        }
        out.update({k: self.extra[k] for k in OPTIONAL_ATTRS if k in self.extra})
        return out

    def datasets(self) -> dict[str, np.ndarray]:
        """The datasets present, in format order."""
        names = REQUIRED_DATASETS + OPTIONAL_DATASETS
        return {n: getattr(self, n) for n in names if getattr(self, n) is not None}

    def content_hash(self) -> str:
        """sha256 of the run's content: attributes and dataset values, not file bytes.

        Two files holding the same values hash the same whatever their chunking or
        compression, so re-importing a run is recognised as such.
        """
        h = hashlib.sha256()
        h.update(json.dumps(self.attrs(), sort_keys=True).encode())
        for name, arr in self.datasets().items():
            arr = np.ascontiguousarray(arr, dtype=np.dtype(DTYPES[name]).newbyteorder("<"))
            h.update(f"{name}:{arr.dtype.str}:{arr.shape}".encode())
            h.update(arr.tobytes())
        return h.hexdigest()

    def validate(self, path: str | Path = "<memory>") -> CalibrationRun:
        """Check the run against the format; raise RunFormatError naming `path`."""
        _validate(self, path)
        return self


def _problem(path: str | Path, msg: str) -> RunFormatError:
    return RunFormatError(path, msg)


def _validate(run: CalibrationRun, path: str | Path) -> None:
    try:
        check_sensor_id(run.sensor_id)
    except ValueError as e:
        raise _problem(path, str(e)) from None
    if not isinstance(run.sensor_model, str) or not run.sensor_model:
        raise _problem(path, "attribute 'sensor_model' must be a non-empty string")
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
        _check_text(path, key, value)
    if "simulator" in run.extra:
        try:
            json.loads(run.extra["simulator"])
        except json.JSONDecodeError as e:
            raise _problem(path, f"attribute 'simulator' is not valid JSON ({e})") from None
    _validate_arrays(run, path)


def _check_text(path: str | Path, key: str, value: str) -> None:
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
    expected = {
        "pressure": (n, c), "force": (n, 3), "angles": (n, 2), "temperature": (n, c), "in_contact": (n,),
    }
    for name, arr in run.datasets().items():
        if name == "time":
            continue
        want = expected[name]
        if arr.ndim != len(want):
            raise _problem(
                path, f"dataset {name!r} must have {len(want)} dimension(s), got shape {arr.shape}"
            )
        if arr.shape[0] != n:
            raise _problem(path, f"dataset {name!r} has {arr.shape[0]} rows but 'time' has {n}")
        if arr.shape != want:
            raise _problem(path, f"dataset {name!r} must have {want[1]} columns, got {arr.shape[1]}")
    if n == 0:
        raise _problem(path, "the run has no rows")
    for name in ("pressure", "force", "angles"):
        bad = ~np.isfinite(getattr(run, name))
        if bad.any():
            row = int(np.argwhere(bad)[0][0])
            raise _problem(path, f"dataset {name!r} holds NaN or infinite values (first at row {row})")
    if not np.isfinite(run.time).all():
        raise _problem(path, "dataset 'time' holds NaN or infinite values")
    steps = np.diff(run.time)
    if (steps < 0).any():
        row = int(np.argmax(steps < 0)) + 1
        raise _problem(path, f"dataset 'time' decreases at row {row}")


def _attr_value(value: Any) -> Any:
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
    path = Path(path)
    if not path.is_file():
        raise _problem(path, "no such file")
    try:
        with h5py.File(path, "r") as f:
            check_self_contained(f, path)
            return _read_open(f, path)
    except RunFormatError:
        raise
    except MemoryError:
        raise _problem(path, "the run does not fit in memory") from None
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


def _check_size(f: h5py.File, path: Path) -> None:
    """Refuse datasets that would not fit in memory before reading any (a crafted file can
    declare 10^11 rows in a few bytes)."""
    total = 0
    for name in REQUIRED_DATASETS + OPTIONAL_DATASETS:
        node = f.get(name)
        if isinstance(node, h5py.Dataset):
            total += int(node.size) * np.dtype(DTYPES[name]).itemsize
    free = _free_memory_bytes()
    if total > free:
        raise _problem(path, f"datasets declare {total / 1e9:.3g} GB, more than the "
                             f"{free / 1e9:.3g} GB of memory available")


def _read_open(f: h5py.File, path: Path) -> CalibrationRun:
    attrs = {k: _attr_value(v) for k, v in f.attrs.items()}
    for key in REQUIRED_ATTRS:
        if key not in attrs:
            raise _problem(path, f"missing root attribute {key!r}")
    if attrs["format"] != FORMAT:
        raise _problem(path, f"attribute 'format' is {attrs['format']!r}, expected {FORMAT!r}")
    if not isinstance(attrs["format_version"], int) or isinstance(attrs["format_version"], bool):
        raise _problem(
            path, f"attribute 'format_version' must be an integer, got {attrs['format_version']!r}"
        )
    if attrs["format_version"] != FORMAT_VERSION:
        raise _problem(
            path, f"unknown format_version {attrs['format_version']}; this reader knows {FORMAT_VERSION}"
        )
    for key in ("sensor_id", "sensor_model", "source", "created"):
        if not isinstance(attrs[key], str):
            raise _problem(path, f"attribute {key!r} must be a string, got {attrs[key]!r}")
    _check_size(f, path)
    arrays: dict[str, np.ndarray | None] = {}
    for name in REQUIRED_DATASETS + OPTIONAL_DATASETS:
        if name not in f:
            if name in REQUIRED_DATASETS:
                raise _problem(path, f"missing dataset {name!r}")
            arrays[name] = None
            continue
        node = f[name]
        if not isinstance(node, h5py.Dataset):
            raise _problem(path, f"{name!r} is not a dataset")
        arrays[name] = _read_dataset(node, name, path)
    extra = {k: attrs[k] for k in OPTIONAL_ATTRS if k in attrs}
    for key, value in extra.items():
        if not isinstance(value, str):
            raise _problem(path, f"optional attribute {key!r} must be a string, got {value!r}")
    run = CalibrationRun(
        sensor_id=attrs["sensor_id"], sensor_model=attrs["sensor_model"],
        orientation_deg=attrs["orientation_deg"], sample_rate_hz=attrs["sample_rate_hz"],
        source=attrs["source"], created=attrs["created"], extra=extra, **arrays,
    )
    run.validate(path)
    run.orientation_deg, run.sample_rate_hz = float(run.orientation_deg), float(run.sample_rate_hz)
    return run


def _read_dataset(node: h5py.Dataset, name: str, path: Path) -> np.ndarray:
    want = np.dtype(DTYPES[name])
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
                _write_dataset(f, name, np.ascontiguousarray(arr, dtype=DTYPES[name]), compression)
    except BaseException:
        path.unlink(missing_ok=True)  # never leave half a file behind
        raise
    return path


def _write_dataset(f: h5py.File, name: str, arr: np.ndarray, compression: str | None) -> None:
    """One dataset in chunks of about 256 KiB of rows, shuffled, compressed, fletcher32."""
    chunk_rows = int(min(arr.shape[0], max(1, 2**18 // max(1, arr[:1].nbytes))))
    f.create_dataset(
        name, data=arr, chunks=(chunk_rows, *arr.shape[1:]), compression=compression,
        compression_opts=1 if compression == "gzip" else None,
        shuffle=compression is not None, fletcher32=True,
    )
