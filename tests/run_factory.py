"""Small calibration runs built from numpy for tests (no simulator needed)."""

from __future__ import annotations

import json

import numpy as np

from anytip.data.runfile import CalibrationRun


def make_run(
    sensor_id: str = "FT-0001",
    orientation_deg: float = 0.0,
    created: str = "2024-05-01T12:00:00Z",
    *,
    n: int = 64,
    channels: int = 8,
    seed: int = 0,
    source: str = "simulated",
    sensor_model: str = "fingertip-8baro-r10",
    protocol: str | None = None,
    optional: bool = True,
) -> CalibrationRun:
    """A valid run with N = `n` rows of random but plausible values (seeded)."""
    g = np.random.default_rng(seed)
    extra = {"operator": "test"}
    if protocol is not None:
        extra["simulator"] = json.dumps({"seed": seed, "protocol": {"name": protocol}})
    return CalibrationRun.fingertip(
        sensor_id=sensor_id, sensor_model=sensor_model, orientation_deg=orientation_deg,
        sample_rate_hz=200.0, source=source, created=created,
        time=np.arange(n) / 200.0,
        pressure=(1e5 + 50 * g.standard_normal((n, channels))).astype(np.float32),
        force=(g.standard_normal((n, 3)) * [3, 3, 8]).astype(np.float32),
        angles=g.uniform(-0.7, 0.7, (n, 2)).astype(np.float32),
        temperature=(25 + g.standard_normal((n, channels))).astype(np.float32) if optional else None,
        in_contact=(g.random(n) < 0.7) if optional else None,
        extra=extra,
    )
