"""Simulated runs as calibration run files, and filling a registry from the fleet simulator
(one unit, all of its runs, per transaction). The simulator (`anytip.sensor.simulate`) knows
nothing of files; this module gives its runs the interchange format's shape."""

from __future__ import annotations

import json
from collections.abc import Iterable, Iterator, Sequence
from itertools import groupby
from typing import Any

from rich.progress import track

from anytip.data.registry import Registry
from anytip.data.runfile import CalibrationRun
from anytip.sensor import simulate as sim
from anytip.sensor.fleet import FleetConfig
from anytip.sensor.protocols import Protocol


def as_run(run: sim.SimulatedRun) -> CalibrationRun:
    """The run file of a simulated run (validated), with its `simulator` JSON attribute."""
    return CalibrationRun.fingertip(
        sensor_id=run.sensor_id, sensor_model=run.sensor_model, orientation_deg=run.orientation_deg,
        sample_rate_hz=run.sample_rate_hz, source="simulated", created=run.created, time=run.time,
        pressure=run.pressure, force=run.force, angles=run.angles, temperature=run.temperature,
        in_contact=run.in_contact,
        extra={"simulator": json.dumps(run.record, sort_keys=True), "notes": run.notes},
    ).validate()


def simulate_run(*args: Any, **kwargs: Any) -> CalibrationRun:
    """`anytip.sensor.simulate.simulate_run` as a run file."""
    return as_run(sim.simulate_run(*args, **kwargs))


def simulate_fleet(config: FleetConfig, n_units: int, seed: int,
                   protocols: Iterable[str | Protocol] = ("full", "short")) -> Iterator[CalibrationRun]:
    """`anytip.sensor.simulate.simulate_fleet`, run by run, as run files."""
    return (as_run(r) for r in sim.simulate_fleet(config, n_units, seed, protocols))


def regenerate(simulator_json: dict[str, Any] | str) -> CalibrationRun:
    """Replay a simulated run from its `simulator` attribute; equal `content_hash()`."""
    return as_run(sim.regenerate(simulator_json))


def simulate_into(registry: Registry, config: FleetConfig, n_units: int, seed: int,
                  protocols: Sequence[str] = ("full", "short"), progress: bool = False
                  ) -> tuple[int, int]:
    """Simulate `n_units` units and add their runs; returns (runs added, runs already there).

    Re-running with the same arguments adds nothing: simulated runs are deterministic.
    """
    before = {r.run_id for r in registry.list_runs()}
    runs = simulate_fleet(config, n_units=n_units, seed=seed, protocols=tuple(protocols))
    added = unchanged = 0
    for _, unit_runs in track(groupby(runs, key=lambda r: r.sensor_id), total=n_units,
                              description="simulating units", disable=not progress):
        records = registry.add_runs(list(unit_runs))
        new = sum(r.run_id not in before for r in records)
        added, unchanged = added + new, unchanged + len(records) - new
    return added, unchanged
