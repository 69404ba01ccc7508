"""Simulated faults of a deployed unit, injected into its tared pressure rows.

All functions take x (n, C) tared pressures in Pa (rows in recorded order) and return a
faulty copy; the clean rows are left untouched. A tared reading is the change from the
power-up rest reading, so a barometer that stops responding reads 0 Pa after tare.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from anytip.data.arrays import contact_mask, rest_reading
from anytip.data.registry import Registry, RunRecord
from anytip.errors import AnytipError


class MissingData(AnytipError):
    """A run lacks an optional dataset that one analysis needs; the analysis is skipped."""


def dead_channel(x: np.ndarray, channel: int) -> np.ndarray:
    """Barometer `channel` stops responding: it reads its rest value (0 Pa tared)."""
    out = x.copy()
    out[:, channel] = 0.0
    return out


def stuck_channel(x: np.ndarray, channel: int, value_pa: float) -> np.ndarray:
    """Barometer `channel` freezes at `value_pa` (tared Pa), e.g. a reading it held once."""
    out = x.copy()
    out[:, channel] = value_pa
    return out


def baseline_drift(x: np.ndarray, amplitude_pa: float, channels: np.ndarray | None = None,
                   ramp: bool = False) -> np.ndarray:
    """The rest reading of `channels` (default: all) has drifted by `amplitude_pa` since
    tare; `ramp` grows the offset linearly from 0 over the rows instead of a constant."""
    out = x.copy()
    cols = np.arange(x.shape[1]) if channels is None else np.asarray(channels)
    offset = amplitude_pa * (np.linspace(0, 1, len(x)) if ramp else np.ones(len(x)))
    out[:, cols] += offset[:, None]
    return out


def saturation(x: np.ndarray, limit_pa: np.ndarray | float) -> np.ndarray:
    """Every channel clips at `limit_pa` (scalar or (C,)) tared Pa: lost headroom."""
    return np.minimum(x, limit_pa)


def fault_suite(x: np.ndarray, x_train: np.ndarray, rng: np.random.Generator,
                drift_pa: list[float], channel: int | None = None) -> dict[str, np.ndarray]:
    """The simulated faults of one unit's clean rows x (n, C), by name.

    Dead and stuck channels pick a random channel; the stuck value is the channel's
    reading in a random training row. Drift: every channel, or one random channel, offset
    by each amplitude. Saturation: every channel clips at half of its largest training
    reading (rows below the limit stay clean; score only the rows it changes). `channel`
    fixes the faulty channel (default: drawn from rng).
    """
    ch = int(rng.integers(x.shape[1])) if channel is None else channel
    stuck_value = float(x_train[rng.integers(len(x_train)), ch])
    out = {"dead_channel": dead_channel(x, ch), "stuck_channel": stuck_channel(x, ch, stuck_value)}
    for a in drift_pa:
        out[f"drift_all_{a / 1000:g}kPa"] = baseline_drift(x, a)
        out[f"drift_one_{a / 1000:g}kPa"] = baseline_drift(x, a, np.array([ch]))
    out["saturation"] = saturation(x, 0.5 * x_train.max(0))
    return out


def rest_rows(registry: Registry, runs: Sequence[RunRecord]) -> np.ndarray:
    """Contact-free rows after each run's first contact, tared like contact rows:
    (n, C) float32 Pa in recorded order. These are what a deployed unit reads between
    touches; the rows before the first contact (the tare itself) are left out."""
    parts = []
    for rec in runs:
        run = registry.open_run(rec.run_id)
        pressure, contact = run.pressure, contact_mask(run, f"run {rec.run_id}")
        tare = rest_reading(pressure, contact, rec.run_id, run.time)
        after = np.arange(len(contact)) > np.argmax(contact)
        parts.append((pressure[after & ~contact] - tare).astype(np.float32))
    return np.concatenate(parts) if parts else np.zeros((0, runs[0].channels if runs else 0), np.float32)


@dataclass
class RunStream:
    """One run as the unit reads it, every row in recorded order (n rows, C channels).

    pressure (n, C) float64 tared Pa; temperature (n, C) float64 degC change since tare (each
    barometer's own die temperature); contact (n,) bool, the recorded contact flag (used only
    to place the dataset's labelled rows in the stream and to find the tare rows); run the
    run's index in the loaded FleetArrays.
    """

    pressure: np.ndarray
    temperature: np.ndarray
    contact: np.ndarray
    run: int

    @property
    def after_tare(self) -> np.ndarray:
        """(n,) bool: rows after the first contact (the rows before it are the tare)."""
        return np.arange(len(self.contact)) > np.argmax(self.contact)

    def drifted(self, amplitude_pa: float, channels: np.ndarray | None = None, onset: int = 0) -> RunStream:
        """The same stream with the baseline of `channels` drifted by `amplitude_pa` from row
        `onset` on (and never before the tare is over): the level a slow drift has reached."""
        p = self.pressure.copy()
        rows = self.after_tare & (np.arange(len(p)) >= onset)
        p[rows] = baseline_drift(p[rows], amplitude_pa, channels)
        return RunStream(p, self.temperature, self.contact, self.run)


def run_streams(registry: Registry, runs: Sequence[RunRecord], indices: Sequence[int]) -> list[RunStream]:
    """Full recorded streams of `runs` (contact and contact-free rows), tared like the
    training rows; `indices` are the runs' positions in the loaded FleetArrays."""
    out = []
    for rec, k in zip(runs, indices, strict=True):
        run = registry.open_run(rec.run_id)
        if run.temperature is None:
            raise MissingData(f"run {rec.run_id} has no 'temperature' dataset")
        pressure, temp = run.pressure.astype(np.float64), run.temperature.astype(np.float64)
        contact = contact_mask(run, f"run {rec.run_id}")
        first = int(np.argmax(contact)) if contact.any() else len(contact)
        temp = temp.reshape(len(temp), -1)
        if temp.shape[1] != pressure.shape[1]:  # one sensor for the board: every channel reads it
            temp = np.repeat(temp[:, :1], pressure.shape[1], 1)
        t0 = temp[:max(first, 1)].mean(0)
        tare = rest_reading(pressure, contact, rec.run_id, run.time)
        out.append(RunStream(pressure - tare, temp - t0, contact, k))
    return out
