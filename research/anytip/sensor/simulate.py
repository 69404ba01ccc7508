"""Simulated calibration runs: a unit plays a protocol on the rig and its barometers are read.

Each run stores, in its `simulator` attribute, a JSON object with every input of
`simulate_run`; `regenerate` replays it bit-exactly. Randomness: a unit is drawn from
SeedSequence([seed, unit_index, 0]) and its run k from SeedSequence([seed, unit_index,
k + 1]), so units and runs are independent streams.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Iterator, Sequence
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta
from typing import Any

import numpy as np

from anytip.errors import AnytipError
from anytip.sensor.barometer import channel_temperature, read_out, temperature_trace
from anytip.sensor.fleet import FleetConfig, RunConditions
from anytip.sensor.geometry import contact_rotation
from anytip.sensor.physics import (
    coupling,
    elastic_pressure,
    hysteresis_factor,
    relax,
    shifted_points,
)
from anytip.sensor.protocols import Protocol, Trajectory, build_trajectory, get_protocol
from anytip.sensor.variation import UnitParams, draw_unit

SIMULATOR_VERSION = 1
EPOCH = datetime(2024, 1, 1, tzinfo=UTC)


def _entropy(seed: int | Sequence[int]) -> list[int]:
    return [int(seed)] if isinstance(seed, (int, np.integer)) else [int(s) for s in seed]


def _iso(t: datetime) -> str:
    return t.strftime("%Y-%m-%dT%H:%M:%SZ")


@dataclass
class SimulatedRun:
    """One simulated calibration run, as the format stores it (anytip.data.simulated writes it).

    time (N,) s; pressure (N, C) Pa absolute; force (N, 3) N (contact frame); angles (N, 2) rad;
    temperature (N, C) degC; in_contact (N,) bool; `record` every input of `simulate_run`, so
    `regenerate` can replay the run.
    """

    sensor_id: str
    sensor_model: str
    orientation_deg: float
    sample_rate_hz: float
    created: str
    time: np.ndarray
    pressure: np.ndarray
    force: np.ndarray
    angles: np.ndarray
    temperature: np.ndarray
    in_contact: np.ndarray
    record: dict[str, Any]
    notes: str


def unit_sensor_id(seed: int, unit_index: int) -> str:
    """Serial of a simulated unit, e.g. SIM7-000."""
    return f"SIM{seed}-{unit_index:03d}"


def unit_rng(seed: int, unit_index: int) -> np.random.Generator:
    """The stream a fleet draws unit `unit_index` from."""
    return np.random.default_rng(np.random.SeedSequence([seed, unit_index, 0]))


def elastomer_pressure(
    unit: UnitParams, traj: Trajectory, true_angles: np.ndarray, dt: float
) -> np.ndarray:
    """(N, C) Pa pressure the elastomer applies to each barometer over a trajectory.

    true_angles (N, 2) rad: where the rig really touched (labels plus positioning error).
    """
    rot = contact_rotation(true_angles[:, 0], true_angles[:, 1])
    points = shifted_points(
        unit.radius_m * rot[:, :, 2], rot, traj.force, unit.shift_compliance_m_per_n
    )
    force_base = np.einsum("nij,nj->ni", rot, traj.force)
    p = elastic_pressure(points, force_base, unit) * coupling(points, unit)
    p *= hysteresis_factor(-traj.force[:, 2], traj.press, unit.hysteresis)[:, None]
    return relax(p, dt, unit.relax_fraction, unit.relax_tau_s)


def simulate_run(
    unit: UnitParams,
    protocol: str | Protocol,
    orientation_deg: float,
    seed: int | Sequence[int],
    sensor_id: str,
    conditions: RunConditions | None = None,
    created: str | None = None,
) -> SimulatedRun:
    """One calibration run of `unit` at one rig orientation (deg), deterministic from `seed`.

    `seed` is SeedSequence entropy (an int or a list of ints). `created` defaults to a
    time derived from the seed. The run carries its `record`, the `simulator` JSON.
    """
    protocol, conditions = get_protocol(protocol), conditions or RunConditions()
    entropy = _entropy(seed)
    seq = np.random.SeedSequence(entropy)
    if created is None:
        created = _iso(EPOCH + timedelta(seconds=int(seq.generate_state(1)[0]) % (365 * 86400)))
    rng = np.random.default_rng(seq)
    traj = build_trajectory(protocol, orientation_deg, rng)
    n, dt = traj.force.shape[0], 1.0 / protocol.sample_rate_hz
    time = np.arange(n) * dt
    rig_error = conditions.angle_noise_rad * rng.standard_normal((int(traj.press.max()) + 1, 2))
    p = elastomer_pressure(unit, traj, traj.angles + rig_error[traj.press], dt)
    trace = temperature_trace(time, conditions, rng)
    atmosphere = conditions.atmosphere_pa + conditions.atmosphere_sigma_pa * rng.standard_normal()
    pressure = read_out(p, trace[:, None], atmosphere, unit, rng)
    temperature = channel_temperature(trace, unit, conditions, rng)
    bias = conditions.force_bias_n * rng.standard_normal(3)
    force = traj.force + bias + conditions.force_noise_n * rng.standard_normal(traj.force.shape)
    record = {
        "simulator": "anytip.sensor",
        "version": SIMULATOR_VERSION,
        "sensor_id": sensor_id,
        "created": created,
        "orientation_deg": float(orientation_deg),
        "seed": entropy,
        "protocol": protocol.to_json(),
        "conditions": conditions.model_dump(mode="json"),
        "unit": unit.model_dump(mode="json"),
    }
    return SimulatedRun(
        sensor_id=sensor_id, sensor_model=unit.sensor_model, orientation_deg=float(orientation_deg),
        sample_rate_hz=float(protocol.sample_rate_hz), created=created, time=time,
        pressure=pressure.astype(np.float32), force=force.astype(np.float32),
        angles=traj.angles.astype(np.float32), temperature=temperature.astype(np.float32),
        in_contact=traj.in_contact, record=record, notes=f"protocol {protocol.name}",
    )


def simulate_unit(
    unit: UnitParams,
    protocol: str | Protocol,
    seed: int,
    unit_index: int = 0,
    sensor_id: str | None = None,
    conditions: RunConditions | None = None,
    first_run: int = 0,
) -> list[SimulatedRun]:
    """One run per orientation of `protocol`; run k uses SeedSequence([seed, unit_index, k + 1])
    with k counting from `first_run`, and is created `unit_index` days plus 2 k hours after
    the epoch."""
    protocol = get_protocol(protocol)
    sensor_id = sensor_id or unit_sensor_id(seed, unit_index)
    runs = []
    for i, orientation in enumerate(protocol.orientations_deg):
        k = first_run + i
        created = _iso(EPOCH + timedelta(days=unit_index, hours=2 * k))
        runs.append(
            simulate_run(
                unit,
                protocol,
                orientation,
                [seed, unit_index, k + 1],
                sensor_id,
                conditions,
                created,
            )
        )
    return runs


def simulate_fleet(
    config: FleetConfig,
    n_units: int,
    seed: int,
    protocols: Iterable[str | Protocol] = ("full", "short"),
) -> Iterator[SimulatedRun]:
    """Every run of `n_units` units drawn from `config`: per unit, each protocol's orientations
    in turn. Unit ids are SIM{seed}-{index:03d}; deterministic from `seed`."""
    protocols = [get_protocol(p) for p in protocols]
    for index in range(n_units):
        yield from fleet_unit_runs(config, seed, index, protocols)


def fleet_unit_runs(config: FleetConfig, seed: int, index: int,
                    protocols: Iterable[str | Protocol]) -> list[SimulatedRun]:
    """Unit `index` of the fleet `simulate_fleet` draws from `config` and `seed`, with its runs of
    each protocol in turn: the same runs, bit for bit, whatever other units are simulated."""
    unit = draw_unit(config, unit_rng(seed, index))
    runs: list[SimulatedRun] = []
    for protocol in map(get_protocol, protocols):
        runs += simulate_unit(unit, protocol, seed, index, None, config.run, len(runs))
    return runs


def regenerate(simulator_json: dict[str, Any] | str) -> SimulatedRun:
    """Replay a simulated run from its `simulator` attribute, bit for bit."""
    record = json.loads(simulator_json) if isinstance(simulator_json, str) else simulator_json
    if record.get("simulator") != "anytip.sensor" or record.get("version") != SIMULATOR_VERSION:
        raise AnytipError(
            f"simulator record {record.get('simulator')!r} version {record.get('version')!r} "
            f"cannot be replayed exactly by anytip.sensor version {SIMULATOR_VERSION}"
        )
    return simulate_run(
        UnitParams.model_validate(record["unit"]),
        Protocol.model_validate(record["protocol"]),
        record["orientation_deg"],
        record["seed"],
        record["sensor_id"],
        RunConditions.model_validate(record["conditions"]),
        record["created"],
    )
