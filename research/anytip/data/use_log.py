"""A log of a unit's ordinary use: its pressures while mounted on its robot, with no rig measuring the
contacts, in a file of its own (`docs/calibration_format.md`, "Ordinary-use logs").

The file is the run format's HDF5 without targets: root attributes `format` (`ordinary_use_log`),
`format_version` (1), `sensor_id`, `sensor_model`, `sample_rate_hz` and `created` as a run's; datasets
`time` (N,) s and `pressure` (N, C) Pa, absolute, starting with at least 0.5 s at rest; optional
`temperature` (N, C) degC. It is read from itself alone, with the run format's checks on every value.
`use_rows` finds its contacts from the pressures (`data.contact.ContactDetector`) and tares them from its
rest reading, as a calibration's ordinary use reads them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np

from anytip.data.arrays import rest_reading
from anytip.data.contact import ContactDetector
from anytip.data.runfile import (
    DTYPES,
    CalibrationRun,
    RunFormatError,
    check_sensor_id,
    check_size,
    check_text,
    check_values,
    parse_created,
    read_dataset,
    read_hdf5,
    root_attrs,
    write_dataset,
)

USE_LOG_FORMAT, USE_LOG_VERSION = "ordinary_use_log", 1
USE_LOG_ATTRS = ("format", "format_version", "sensor_id", "sensor_model", "sample_rate_hz", "created")


@dataclass(frozen=True)
class UseLog:
    """A unit's ordinary use: time (N,) s, pressure (N, C) float32 Pa absolute, temperature (N, C) degC or
    None."""

    sensor_id: str
    sensor_model: str
    sample_rate_hz: float
    created: str
    time: np.ndarray
    pressure: np.ndarray
    temperature: np.ndarray | None = None

    @classmethod
    def of_run(cls, run: CalibrationRun) -> UseLog:
        """What `run`'s unit logged during it, its targets and contact flag left out: its pressures and
        temperature as an ordinary-use log (a simulated session read as a deployed unit would log it)."""
        return cls(run.sensor_id, run.sensor_model, run.sample_rate_hz, run.created, run.time, run.pressure,
                   run.temperature)


def read_use_log(path: str | Path) -> UseLog:
    """Read and check one ordinary-use log; RunFormatError naming the file and what is wrong."""
    return read_hdf5(path, _read_open, "log")


def write_use_log(log: UseLog, path: str | Path) -> Path:
    """Write `log` (checked first; nothing is left of a failed write) as an ordinary-use log at `path`."""
    path = Path(path)
    _check(log, path)
    datasets = {"time": log.time, "pressure": log.pressure, "temperature": log.temperature}
    try:
        with h5py.File(path, "w", libver=("earliest", "v110")) as f:
            for key, value in (("format", USE_LOG_FORMAT), ("format_version", USE_LOG_VERSION),
                               ("sensor_id", log.sensor_id), ("sensor_model", log.sensor_model),
                               ("sample_rate_hz", float(log.sample_rate_hz)), ("created", log.created)):
                f.attrs[key] = value
            for name, values in datasets.items():
                if values is not None:  # as a run's: chunked, shuffled, gzip, fletcher32
                    write_dataset(f, name, np.ascontiguousarray(values, dtype=DTYPES[name]))
    except BaseException:
        path.unlink(missing_ok=True)
        raise
    return path


DETECTOR = ContactDetector()


def use_rows(log: UseLog, seconds: float, detector: ContactDetector = DETECTOR) -> tuple[np.ndarray, float]:
    """The log's ordinary use as a calibration reads it: the pressures (n, C) float32 Pa of the rows
    `detector` finds in contact, tared as a run's rows are (`arrays.rest_reading`: the mean of the rows
    before its first contact), in recorded order up to `seconds` of contact; and their contact seconds
    (rows over the sample rate). None found: (0, C) and 0."""
    contact = detector.contact(log.time, log.pressure, log.sample_rate_hz)
    if not contact.any():
        return np.zeros((0, log.pressure.shape[1]), np.float32), 0.0
    rest = rest_reading(log.pressure, contact, f"ordinary-use log of {log.sensor_id}", log.time)
    rows = np.flatnonzero(contact)[: max(1, int(math.floor(seconds * log.sample_rate_hz)))]
    return (log.pressure[rows].astype(np.float64) - rest).astype(np.float32), len(rows) / log.sample_rate_hz


def _read_open(f: h5py.File, path: Path) -> UseLog:
    attrs = root_attrs(f, path, USE_LOG_ATTRS, USE_LOG_FORMAT)
    if attrs["format_version"] != USE_LOG_VERSION or isinstance(attrs["format_version"], bool):
        raise RunFormatError(path, f"unknown format_version {attrs['format_version']!r}; this reader knows "
                                   f"[{USE_LOG_VERSION}]")
    for key in ("sensor_id", "sensor_model", "created"):
        if not isinstance(attrs[key], str):
            raise RunFormatError(path, f"attribute {key!r} must be a string, got {attrs[key]!r}")
    check_size(f, path)
    arrays = {name: read_dataset(f, name, path, required=name != "temperature")
              for name in ("time", "pressure", "temperature")}
    rate = attrs["sample_rate_hz"]
    if not isinstance(rate, (int, float)) or isinstance(rate, bool):
        raise RunFormatError(path, f"attribute 'sample_rate_hz' must be a finite number, got {rate!r}")
    log = UseLog(attrs["sensor_id"], attrs["sensor_model"], float(rate), attrs["created"], **arrays)
    _check(log, path)
    return log


def _check(log: UseLog, path: Path) -> None:
    """The run format's checks on a log's attributes and arrays; RunFormatError naming `path`."""
    try:
        check_sensor_id(log.sensor_id)
        check_sensor_id(log.sensor_model, "sensor_model")
        parse_created(log.created)
    except ValueError as e:
        raise RunFormatError(path, str(e)) from None
    for key in ("sensor_model", "created"):
        check_text(path, key, getattr(log, key))
    if not math.isfinite(log.sample_rate_hz) or log.sample_rate_hz <= 0:
        raise RunFormatError(path, f"attribute 'sample_rate_hz' must be > 0 and finite, "
                                   f"got {log.sample_rate_hz}")
    time, pressure = np.asarray(log.time), np.asarray(log.pressure)
    if time.ndim != 1 or not len(time):
        raise RunFormatError(path, f"dataset 'time' must have shape (N,) with N > 0, got {time.shape}")
    if pressure.ndim != 2 or pressure.shape[0] != len(time) or pressure.shape[1] < 1:
        raise RunFormatError(path, f"dataset 'pressure' must have shape ({len(time)}, C), "
                                   f"got {pressure.shape}")
    if log.temperature is not None and np.shape(log.temperature) != pressure.shape:
        raise RunFormatError(path, f"dataset 'temperature' must have shape {pressure.shape}, "
                                   f"got {np.shape(log.temperature)}")
    temperature = {} if log.temperature is None else {"temperature": np.asarray(log.temperature)}
    check_values(path, time, pressure, {"pressure": pressure} | temperature)
