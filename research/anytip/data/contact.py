"""Contact found from a unit's pressures alone, where no rig measures the force (its ordinary use).

A row is in contact where some barometer stands more than `threshold_pa` from a baseline that follows the
unit at rest, and at least `fraction` of the largest such deviation of the preceding `window_s` seconds. The
baseline: the run's rest reading (its first `rest_s` seconds, which the run format guarantees at rest),
the rows within the threshold of it taken as rest, their pressures interpolated over time and smoothed by a
running median of `median_s` seconds. The fraction lets the dome's recovery after each press go: the
pressures fall with a time constant near 0.5 s once the force is gone, and rows that bear no force but
hundreds of Pa bend a unit's codes (research log entries 176-179: on simulated sessions of ordinary use,
f = 0.1 keeps 99.2% of the rows at |F| >= 1 N with 7.8% of what it finds outside the force flag, and codes
fitted on its rows keep the gain of ordinary use, x1.009 [0.999, 1.020] against the flag).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view
from scipy.ndimage import median_filter

from anytip.data.arrays import REST_S


@dataclass(frozen=True)
class ContactDetector:
    """How contact is found from pressures: thresholds in Pa, durations in seconds (research log
    entry 179)."""

    threshold_pa: float = 200.0
    fraction: float = 0.1
    window_s: float = 2.0
    rest_s: float = REST_S  # the run format's rest before any contact
    median_s: float = 2.0
    grid_s: float = 0.05

    def rest_baseline(self, time: np.ndarray, pressure: np.ndarray) -> np.ndarray:
        """(n, C) Pa: the rest baseline of pressures (n, C) Pa at times (n,) s (module docstring)."""
        first = time - time[0] < self.rest_s
        reading = pressure[first].mean(0) if first.any() else pressure[0]
        still = ~(np.abs(pressure - reading) > self.threshold_pa).any(1)
        if not still.any():
            return np.broadcast_to(reading, pressure.shape).copy()
        grid = np.arange(time[0], time[-1] + self.grid_s, self.grid_s)
        width = max(1, int(round(self.median_s / self.grid_s)))
        out = np.empty_like(pressure)
        for c in range(pressure.shape[1]):
            rest = np.interp(grid, time[still], pressure[still, c])
            coarse = median_filter(rest, size=width, mode="nearest")
            out[:, c] = np.interp(time, grid, coarse)
        return out

    def contact(self, time: np.ndarray, pressure: np.ndarray, sample_rate_hz: float) -> np.ndarray:
        """(n,) bool: the rows of pressures (n, C) Pa at times (n,) s found in contact."""
        if not len(time):
            return np.zeros(0, bool)
        p = pressure.astype(np.float64)
        m = np.abs(p - self.rest_baseline(time, p)).max(1)
        width = max(1, int(round(self.window_s * sample_rate_hz)))
        recent = sliding_window_view(np.pad(m, (width - 1, 0)), width).max(1)
        return (m > self.threshold_pa) & (m >= self.fraction * recent)
