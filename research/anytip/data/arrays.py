"""Training arrays: a selection of registry runs as flat, tared, labelled rows.

Tare follows the firmware: each run's rest reading (mean of its contact-free rows
before the first contact, as the firmware's power-up mean) is subtracted, so inputs are
pressure changes in Pa. Only contact rows carry labels; contact-free rows are dropped.
Each row keeps the index of its unit, its run and its patch, so every split can be
made by unit and by patch.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from anytip.data.registry import Registry, RunRecord
from anytip.data.runfile import CalibrationRun
from anytip.errors import AnytipError

PATCH_DEG = 15.0
THETA_MIN_DEG, PHI_MIN_DEG = -45.0, -135.0
PATCH_GRID = (6, 12)  # theta cells x phi cells of the sensing region
CONTACT_FORCE_N = 0.5  # |F| threshold that marks contact when a run has no in_contact
# the targets' columns, in the order of FleetArrays.targets: force in N, then angles in rad
OUTPUT_NAMES = ("fx", "fy", "fz", "theta", "phi")
# each target's columns in FleetArrays.targets: force (N) and contact angles (rad)
TARGET_SLICES = {"force": slice(0, 3), "angles": slice(3, 5)}


@dataclass
class FleetArrays:
    """Rows of many runs, flattened. N rows, C channels.

    pressure (N, C) float32 tared Pa; force (N, 3) float32 N; angles (N, 2) float32 rad;
    unit, run (N,) int32 indices into `units` and `runs`; patch (N,) int16 cell index
    (see `patch_index`); tare (R, C) float64 Pa, the rest reading of each run; time (N,)
    float64 s since the first sample of the row's run (robot-seconds into the protocol).
    Rows of a run keep their recorded order.
    """

    pressure: np.ndarray
    force: np.ndarray
    angles: np.ndarray
    unit: np.ndarray
    run: np.ndarray
    patch: np.ndarray
    tare: np.ndarray
    units: list[str]
    runs: list[RunRecord]
    time: np.ndarray | None = None

    @property
    def n_rows(self) -> int:
        return int(self.pressure.shape[0])

    @property
    def targets(self) -> np.ndarray:
        """(N, 5) float32: Fx, Fy, Fz in N, then theta, phi in rad."""
        return np.concatenate([self.force, self.angles], axis=1)

    def select(self, mask: np.ndarray) -> FleetArrays:
        """Rows where `mask` (N,) bool holds; unit, run and patch indices keep their meaning."""
        return FleetArrays(
            self.pressure[mask], self.force[mask], self.angles[mask], self.unit[mask],
            self.run[mask], self.patch[mask], self.tare, self.units, self.runs,
            None if self.time is None else self.time[mask],
        )



def patch_index(angles: np.ndarray) -> np.ndarray:
    """Patch cell of each row from its label angles (N, 2) rad -> (N,) int16.

    Cells are 15 deg squares of (theta, phi) with edges at theta = -45 + 15k and
    phi = -135 + 15k deg, the grid the calibration protocol presses on; rows outside
    the sensing region fall into the nearest edge cell.
    """
    deg = np.degrees(angles.astype(np.float64))
    i = np.clip(np.floor((deg[:, 0] - THETA_MIN_DEG) / PATCH_DEG), 0, PATCH_GRID[0] - 1)
    j = np.clip(np.floor((deg[:, 1] - PHI_MIN_DEG) / PATCH_DEG), 0, PATCH_GRID[1] - 1)
    return (i * PATCH_GRID[1] + j).astype(np.int16)


def contact_mask(run: CalibrationRun) -> np.ndarray:
    """(n,) bool: the run's recorded `in_contact` flag, else |F| >= CONTACT_FORCE_N."""
    if run.in_contact is not None:
        return run.in_contact.astype(bool)
    return np.linalg.norm(run.force, axis=1) >= CONTACT_FORCE_N


def rest_reading(pressure: np.ndarray, contact: np.ndarray, path: str) -> np.ndarray:
    """(C,) float64 Pa: mean of the contact-free rows before the first contact.

    Falls back to every contact-free row when the run starts in contact.
    """
    first = int(np.argmax(contact)) if contact.any() else len(contact)
    rest = pressure[:first] if first > 0 else pressure[~contact]
    if len(rest) == 0:
        raise AnytipError(f"{path}: no contact-free rows to tare from")
    return rest.astype(np.float64).mean(axis=0)


def load_arrays(registry: Registry, runs: Sequence[RunRecord]) -> FleetArrays:
    """Load `runs` (catalog records of one sensor model) into flat tared rows."""
    if not runs:
        raise AnytipError(f"{registry.root}: no runs selected to load")
    models = {r.sensor_model for r in runs}
    if len(models) > 1:
        raise AnytipError(f"runs mix sensor models {sorted(models)}; load one model at a time")
    channels = {r.channels for r in runs}
    if len(channels) > 1:
        raise AnytipError(f"{registry.root}: runs of sensor model {runs[0].sensor_model!r} have "
                          f"{sorted(channels)} pressure channels; a sensor model has one layout")
    units = sorted({r.unit for r in runs})
    parts: dict[str, list[np.ndarray]] = {k: [] for k in ("p", "f", "a", "u", "r", "t")}
    tares = []
    for k, rec in enumerate(runs):
        run = registry.open_run(rec.run_id)  # validated, and hashed against the catalog
        pressure, force, angles, contact = run.pressure, run.force, run.angles, contact_mask(run)
        time = run.time - run.time[0]
        tare = rest_reading(pressure, contact, f"run {rec.run_id}")
        tares.append(tare)
        n = int(contact.sum())
        parts["p"].append((pressure[contact] - tare).astype(np.float32))
        parts["f"].append(force[contact])
        parts["a"].append(angles[contact])
        parts["u"].append(np.full(n, units.index(rec.unit), np.int32))
        parts["r"].append(np.full(n, k, np.int32))
        parts["t"].append(time[contact])
    angles = np.concatenate(parts["a"])
    return FleetArrays(
        pressure=np.concatenate(parts["p"]), force=np.concatenate(parts["f"]), angles=angles,
        unit=np.concatenate(parts["u"]), run=np.concatenate(parts["r"]),
        patch=patch_index(angles), tare=np.stack(tares), units=units, runs=list(runs),
        time=np.concatenate(parts["t"]),
    )
