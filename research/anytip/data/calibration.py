"""What a lab records first on a new unit: its calibration stream, and budgets cut from it.

A unit's stream is its runs of the calibration protocol (e.g. `short`) in recorded order,
contact rows only; a unit with no such run falls back to all its runs, in order, so a
registry of measured full calibrations still works. A budget of N samples is the first
N rows of the stream (never a random subset), and its cost in robot-seconds is the
protocol time until the N-th row.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import zip_longest

import numpy as np

from anytip.data.arrays import FleetArrays
from anytip.errors import AnytipError
from anytip.sensor.protocols import is_designed, is_test_session


@dataclass(frozen=True)
class CalibrationStream:
    """rows (k,) indices into the FleetArrays, in time order; seconds (k,) robot-seconds
    from the start of the stream to each row; runs: the run ids it reads."""

    unit: str
    rows: np.ndarray
    seconds: np.ndarray
    runs: tuple[str, ...]
    protocol: str | None

    def first(self, n: int) -> np.ndarray:
        """Row indices of a budget of n labeled samples (all rows when n exceeds the stream)."""
        return self.rows[:n]

    def outside(self, arrays: FleetArrays) -> np.ndarray:
        """(N,) bool: rows of runs the stream does not read (the unit's other runs, other units)."""
        return ~np.isin(arrays.run, [k for k, r in enumerate(arrays.runs) if r.run_id in self.runs])

    def unlabeled(self, seconds: float | None) -> np.ndarray:
        """Row indices of the stream's first `seconds` of robot time (all rows for None): the
        pressures a unit records in ordinary use after mounting, read without labels."""
        return self.rows if seconds is None else self.rows[self.seconds <= seconds]

    def seconds_for(self, n: int) -> float:
        """Robot-seconds a budget of n samples costs (0 for n == 0)."""
        if n <= 0 or len(self.rows) == 0:
            return 0.0
        return float(self.seconds[min(n, len(self.rows)) - 1])


def calibration_stream(arrays: FleetArrays, unit: str, protocol: str | None,
                       exclude: np.ndarray | None = None, interleave: bool = False) -> CalibrationStream:
    """The unit's calibration stream, without rows where `exclude` (N,) bool is True.

    Excluded rows (a held-out unit's test patches) still take robot time: they are
    dropped, not skipped over in the clock. The runs follow each other in recorded order,
    or with `interleave` their patch visits take turns (visit 1 of every run, then visit 2,
    ...), as a robot that presses the unit from every orientation in turn would play them;
    each visit keeps its own robot time (from the end of the run's previous visit). Runs of a
    designed calibration (`plan<seconds>`) are left out where the unit has other runs: they are
    a plan of their own (`data.plans.plan_for`, strategy `designed`); so are those of a test
    session (`retest`), which hold the unit's test rows alone.
    """
    if arrays.time is None:
        raise AnytipError("calibration streams need row times; load the runs with load_arrays")
    if unit not in arrays.units:
        raise AnytipError(f"unit {unit!r} is not among the loaded units {arrays.units}")
    mine = [k for k, r in enumerate(arrays.runs) if r.unit == unit]
    if not is_designed(protocol):  # a designed plan's runs are that plan, unless they are all the unit has
        mine = [k for k in mine if not is_designed(arrays.runs[k].protocol)] or mine
    mine = [k for k in mine if not is_test_session(arrays.runs[k].protocol)] or mine  # so is a test session
    chosen = [k for k in mine if arrays.runs[k].protocol == protocol] or mine
    chosen.sort(key=lambda k: (arrays.runs[k].created, arrays.runs[k].run_id))
    pieces = [_visits(arrays, k) for k in chosen]  # per run: [(rows, seconds into the visit)]
    if interleave:
        order = [v for turn in zip_longest(*pieces) for v in turn if v is not None]
    else:
        order = [v for run in pieces for v in run]
    rows, seconds, offset = [], [], 0.0
    for r, t, duration in order:
        keep = np.ones(len(r), bool) if exclude is None else ~exclude[r]
        rows.append(r[keep])
        seconds.append(offset + t[keep])
        offset += duration
    used = protocol if any(arrays.runs[k].protocol == protocol for k in chosen) else None
    return CalibrationStream(unit, np.concatenate(rows) if rows else np.zeros(0, np.int64),
                             np.concatenate(seconds) if seconds else np.zeros(0),
                             tuple(arrays.runs[k].run_id for k in chosen), used)


def _visits(arrays: FleetArrays, run: int) -> list[tuple[np.ndarray, np.ndarray, float]]:
    """A run's rows cut where its patch changes, in time order: (rows, seconds from the end of
    the previous visit, the visit's robot seconds) per visit."""
    r = np.flatnonzero(arrays.run == run)
    if len(r) == 0:
        return []
    r = r[np.argsort(arrays.time[r], kind="stable")]
    t, patch = arrays.time[r], arrays.patch[r]
    cuts = np.flatnonzero(np.diff(patch) != 0) + 1
    out, start_t = [], 0.0
    for idx in np.split(np.arange(len(r)), cuts):
        end_t = float(t[idx[-1]])
        out.append((r[idx], t[idx] - start_t, end_t - start_t))
        start_t = end_t
    return out
