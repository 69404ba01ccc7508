"""Training arrays: a selection of registry runs as flat, tared, labelled rows.

Tare follows the firmware: each run's rest reading is subtracted, so inputs are pressure
changes in Pa. The rest reading is the mean of the contact-free rows before the first
contact (as the firmware's power-up mean); a run without `in_contact` finds its contacts
from its force where it has the fingertip's (`force_contact`), and otherwise labels every row
and tares from its first 0.5 s, which the format guarantees to be at rest. Only contact rows
carry labels.
Each row keeps the index of its unit, its run and its patch, so every split can be made
by unit and by patch: the fingertip's patches are cells of its contact angles; a sensor
model without that grid is cut into contiguous blocks of rows within each run.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from anytip.data.registry import Registry, RunRecord
from anytip.data.runfile import V1_LAYOUT, CalibrationRun, TargetLayout
from anytip.errors import AnytipError

PATCH_DEG = 15.0
THETA_MIN_DEG, PHI_MIN_DEG = -45.0, -135.0
PATCH_GRID = (6, 12)  # theta cells x phi cells of the sensing region
CONTACT_FORCE_N = 0.5  # |F| threshold that marks contact when a run with `force` has no in_contact
CONTACT_RELEASE_N = 0.25  # ... and the |F| below which such a contact ends (`force_contact`)
ONSET_SIGMAS, RELEASE_SIGMAS = 7.0, 3.5  # the same in units of the F/T noise at rest, where larger
MAD_TO_SIGMA = 1.4826  # a Gaussian's standard deviation over its median absolute deviation
REST_S = 0.5  # a run starts with at least this long at rest (the format's promise)
BLOCKS_PER_RUN = 16  # the blocked split's patches: contiguous blocks of each run's label rows
# the fingertip's columns, in the order of FleetArrays.targets: force in N, then angles in rad
OUTPUT_NAMES = ("fx", "fy", "fz", "theta", "phi")
TARGET_SLICES = {"force": slice(0, 3), "angles": slice(3, 5)}


def target_slices(layout: dict[str, TargetLayout]) -> dict[str, slice]:
    """Each target's columns in the label matrix, targets in layout order."""
    out, start = {}, 0
    for name, t in layout.items():
        out[name] = slice(start, start + len(t.components))
        start += len(t.components)
    return out


def output_names(layout: dict[str, TargetLayout]) -> tuple[str, ...]:
    """Every component name, targets in layout order (the fingertip's: fx, fy, fz, theta, phi)."""
    return tuple(c for t in layout.values() for c in t.components)


def has_patch_grid(layout: dict[str, TargetLayout]) -> bool:
    """Whether rows fall into the fingertip's patch grid: the layout holds the fingertip's
    targets (`force` in N, `angles` in rad), whatever else it holds."""
    return all(layout.get(name) == t for name, t in V1_LAYOUT.items())


@dataclass
class FleetArrays:
    """Rows of many runs, flattened. N rows, C channels, D label columns.

    pressure (N, C) float32 tared Pa; labels (N, D) float32, the targets of `layout` side by
    side in their units (the fingertip's: Fx, Fy, Fz in N, theta, phi in rad); unit, run (N,)
    int32 indices into `units` and `runs`; patch (N,) int16 cell index (`patch_index`) or
    block index (`block_index`); tare (R, C) float64 Pa, the rest reading of each run; time
    (N,) float64 s since the first sample of the row's run (robot-seconds into the protocol).
    Rows of a run keep their recorded order.
    """

    pressure: np.ndarray
    labels: np.ndarray
    unit: np.ndarray
    run: np.ndarray
    patch: np.ndarray
    tare: np.ndarray
    units: list[str]
    runs: list[RunRecord]
    time: np.ndarray | None = None
    layout: dict[str, TargetLayout] = field(default_factory=lambda: dict(V1_LAYOUT))

    @property
    def n_rows(self) -> int:
        return int(self.pressure.shape[0])

    @property
    def targets(self) -> np.ndarray:
        """(N, D) float32 labels (the fingertip's: Fx, Fy, Fz in N, then theta, phi in rad)."""
        return self.labels

    @property
    def slices(self) -> dict[str, slice]:
        """Each target's columns of `targets`."""
        return target_slices(self.layout)

    @property
    def output_names(self) -> tuple[str, ...]:
        return output_names(self.layout)

    @property
    def force_columns(self) -> list[int]:
        """The label columns of the sensor model's `force` target, or none."""
        if "force" not in self.layout:
            return []
        return list(range(len(self.output_names)))[self.slices["force"]]

    def target(self, name: str) -> np.ndarray:
        """(N, k) the columns of target `name`; an error names the targets there are."""
        if name not in self.layout:
            raise AnytipError(f"the rows have no target {name!r}; their targets: {list(self.layout)}")
        return self.labels[:, self.slices[name]]

    @property
    def force(self) -> np.ndarray:
        return self.target("force")

    @property
    def angles(self) -> np.ndarray:
        return self.target("angles")

    def select(self, mask: np.ndarray) -> FleetArrays:
        """Rows where `mask` (N,) bool holds; unit, run and patch indices keep their meaning."""
        return FleetArrays(
            self.pressure[mask], self.labels[mask], self.unit[mask], self.run[mask], self.patch[mask],
            self.tare, self.units, self.runs, None if self.time is None else self.time[mask], self.layout,
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


def block_index(n: int) -> np.ndarray:
    """(n,) int16: the contiguous block (0..BLOCKS_PER_RUN-1) each of a run's n label rows is in."""
    return (np.arange(n) * BLOCKS_PER_RUN // max(n, 1)).astype(np.int16)


def contact_mask(run: CalibrationRun, name: str = "run") -> np.ndarray:
    """(n,) bool label rows: the run's `in_contact` flag; without it, the contacts its force
    reading shows (`force_contact`) for a run with the fingertip's `force` target, else every
    row (as the format says). AnytipError naming the run (`name`) where its force cannot show them."""
    if run.in_contact is not None:
        return run.in_contact.astype(bool)
    if "force" in run.targets and run.targets["force"].layout == V1_LAYOUT["force"]:
        try:
            return force_contact(run.force, run.time)
        except ValueError as e:
            raise AnytipError(f"{name}: {e}") from None
    return np.ones(len(run.time), bool)


def force_contact(force: np.ndarray, time: np.ndarray) -> np.ndarray:
    """(n,) bool: the rows in contact by a force reading (n, 3) N at `time` (n,) s.

    The run's first REST_S seconds are at rest (the format's promise). Each component's median over
    them is the reading's zero, so an F/T sensor's offset is no contact; 1.4826 times each
    component's median absolute deviation there is its noise (Gaussian), s the largest. Both stand
    where a file breaks the promise for under half of those rows. A contact starts at a row where
    |F - zero| >= max(CONTACT_FORCE_N, 7 s) and lasts until it falls below max(CONTACT_RELEASE_N,
    3.5 s). At rest 3D Gaussian noise passes 7 s with a chance of 1.3e-10 a row (no contact out of
    noise) and stays over 3.5 s with 0.0066 (a press ends within a row or two of its force). The two
    thresholds keep the noise on a press's loading and unloading ramps from cutting one press into
    fragments, each counted as a press of its own by a plan; a row in between before any contact is
    rest. ValueError where s reaches CONTACT_FORCE_N: no threshold then tells a contact from the noise
    (or the first REST_S seconds were not at rest)."""
    if not len(force):
        return np.zeros(0, bool)
    zero, noise = force_rest(force, time)
    if noise >= CONTACT_FORCE_N:
        raise ValueError(f"it has no in_contact, and its force over its first {REST_S:g} s, which the format "
                         f"keeps at rest, spreads by {noise:.3g} N per axis, as much as a contact's "
                         f"{CONTACT_FORCE_N:g} N: its contacts cannot be told from its force (start the run "
                         f"with {REST_S:g} s at rest, or give it an in_contact dataset)")
    return hysteresis(np.linalg.norm(force - zero, axis=1), max(CONTACT_FORCE_N, ONSET_SIGMAS * noise),
                      max(CONTACT_RELEASE_N, RELEASE_SIGMAS * noise))


def force_rest(force: np.ndarray, time: np.ndarray) -> tuple[np.ndarray, float]:
    """A force reading's (n, 3) N zero (3,) N, each component's median over its first REST_S seconds
    of `time` (n,) s, and its noise there, N: the largest component's MAD_TO_SIGMA x median absolute
    deviation (`force_contact`)."""
    rest = force[time - time[0] < REST_S]
    zero = np.median(rest, axis=0)
    return zero, float((MAD_TO_SIGMA * np.median(np.abs(rest - zero), axis=0)).max())


def hysteresis(magnitude: np.ndarray, onset: float, release: float) -> np.ndarray:
    """(n,) bool: on from a row where `magnitude` (n,) >= `onset` until it falls below `release`; off
    before any onset."""
    event = np.full(len(magnitude), -1, np.int8)  # -1: in the band, keep the state before
    event[magnitude < release] = 0
    event[magnitude >= onset] = 1
    if len(event):
        event[0] = max(event[0], 0)
    last = np.maximum.accumulate(np.where(event >= 0, np.arange(len(event)), 0))
    return event[last] == 1


def rest_rows(contact: np.ndarray, time: np.ndarray | None = None) -> np.ndarray:
    """(n,) bool rows to tare from, given the label rows contact (n,) bool: the contact-free
    rows before the first contact (every contact-free row when the run starts in contact);
    when every row is a label (no `in_contact`, no force), the first REST_S seconds of
    `time` (n,) s, which the format guarantees to be at rest."""
    if contact.all() and time is not None:
        return time - time[0] < REST_S
    first = int(np.argmax(contact)) if contact.any() else len(contact)
    return np.arange(len(contact)) < first if first > 0 else ~contact


def rest_reading(pressure: np.ndarray, contact: np.ndarray, path: str,
                 time: np.ndarray | None = None) -> np.ndarray:
    """(C,) float64 Pa: mean pressure (n, C) of the run's `rest_rows(contact, time)`."""
    rest = rest_rows(contact, time)
    if not rest.any():
        raise AnytipError(f"{path}: no contact-free rows to tare from")
    return pressure[rest].astype(np.float64).mean(axis=0)


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
    parts: dict[str, list[np.ndarray]] = {k: [] for k in ("p", "y", "u", "r", "t", "b")}
    tares, layout = [], None
    for k, rec in enumerate(runs):
        run = registry.open_run(rec.run_id)  # validated, and hashed against the catalog
        if layout is None:
            layout = run.target_layout
        elif run.target_layout != layout:
            raise AnytipError(f"run {rec.run_id}: targets differ from the other runs of sensor model "
                              f"{rec.sensor_model!r}; a sensor model has one layout")
        contact = contact_mask(run, f"run {rec.run_id}")
        tare = rest_reading(run.pressure, contact, f"run {rec.run_id}", run.time)
        tares.append(tare)
        n = int(contact.sum())
        parts["p"].append((run.pressure[contact] - tare).astype(np.float32))
        parts["y"].append(np.concatenate([run.targets[name].values[contact] for name in layout], axis=1))
        parts["u"].append(np.full(n, units.index(rec.unit), np.int32))
        parts["r"].append(np.full(n, k, np.int32))
        parts["t"].append((run.time - run.time[0])[contact])
        parts["b"].append(block_index(n))
    assert layout is not None
    labels = np.concatenate(parts["y"]).astype(np.float32)
    sl = target_slices(layout)
    patch = patch_index(labels[:, sl["angles"]]) if has_patch_grid(layout) else np.concatenate(parts["b"])
    return FleetArrays(
        pressure=np.concatenate(parts["p"]), labels=labels, unit=np.concatenate(parts["u"]),
        run=np.concatenate(parts["r"]), patch=patch, tare=np.stack(tares), units=units,
        runs=list(runs), time=np.concatenate(parts["t"]), layout=layout,
    )
