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
from anytip.data.runfile import CalibrationRun, Target
from anytip.sensor import flat
from anytip.sensor import simulate as sim
from anytip.sensor.fleet import FleetConfig
from anytip.sensor.protocols import PLAN_MOVE_S, Protocol


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


def as_flat_run(run: flat.FlatRun) -> CalibrationRun:
    """The run file (format version 2, validated) of a simulated flat-sensor run."""
    targets = {name: Target(run.targets[name], unit, components)
               for name, unit, components in run.design.targets}
    notes = f"protocol {run.record['protocol']['name']}"
    return CalibrationRun(
        sensor_id=run.sensor_id, sensor_model=run.design.name, orientation_deg=0.0,
        sample_rate_hz=flat.RATE_HZ, source="simulated", created=run.created, time=run.time,
        pressure=run.pressure, targets=targets, in_contact=run.in_contact, format_version=2,
        extra={"simulator": json.dumps(run.record, sort_keys=True), "notes": notes},
    ).validate()


def regenerate(simulator_json: dict[str, Any] | str) -> CalibrationRun:
    """Replay a simulated run from its `simulator` attribute; equal `content_hash()`."""
    record = json.loads(simulator_json) if isinstance(simulator_json, str) else simulator_json
    if record.get("simulator") == flat.SIMULATOR:
        return as_flat_run(flat.regenerate(record))
    return as_run(sim.regenerate(record))


def simulate_flat_into(registry: Registry, sensor_model: str, n_units: int, seed: int,
                       protocols: Sequence[str] = ("full",), severity: float = 1.0,
                       move_s: float = PLAN_MOVE_S, points: str = flat.DEFAULT_PLAN_POINTS
                       ) -> tuple[int, int]:
    """Simulate `n_units` units of a flat sensor model (`anytip.sensor.flat.DESIGNS`) and add
    their runs, one unit per transaction; returns (runs added, runs already there). The rig moves
    `move_s` before each press of a designed plan (plan<seconds>) of `points` (`flat.design_plan`)."""
    before = {r.run_id for r in registry.list_runs()}
    runs = flat.simulate_fleet(sensor_model, n_units, seed, tuple(protocols), severity, move_s, points)
    added = unchanged = 0
    for _, unit_runs in groupby(runs, key=lambda r: r.sensor_id):
        records = registry.add_runs([as_flat_run(r) for r in unit_runs])
        new = sum(r.run_id not in before for r in records)
        added, unchanged = added + new, unchanged + len(records) - new
    return added, unchanged


def simulate_into(registry: Registry, config: FleetConfig, n_units: int, seed: int,
                  protocols: Sequence[str | Protocol] = ("full", "short"), progress: bool = False
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
