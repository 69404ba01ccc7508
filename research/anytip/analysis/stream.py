"""A simulated sensor stream for latency analysis: a force/torque sensor at 1 kHz as ground
truth, the unit's barometers sampled at 200 Hz, and a per-unit model on the samples.

This uses the simulator directly rather than the registry: a latency measurement needs
one continuous stream at two rates from the same contact, which calibration runs (one
rate, presses on a grid) do not hold. The pressure goes through the simulator's whole
forward model at the truth's rate (contact mechanics, hysteresis, viscoelastic
relaxation), then is sampled at the sensor's rate and read out (gain, offset, noise,
quantisation). Forces N, pressures Pa, angles rad, times s.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import torch

from anytip.data.arrays import rest_reading
from anytip.models.mlp import MLPConfig
from anytip.sensor.barometer import read_out
from anytip.sensor.fleet import RunConditions
from anytip.sensor.protocols import Trajectory
from anytip.sensor.simulate import elastomer_pressure, simulate_unit
from anytip.sensor.variation import UnitParams
from anytip.train.data import FleetBatchData, split_rows
from anytip.train.fleet import FitResult, train_fleet
from anytip.train.metrics import predict
from anytip.train.recipe import TrainRecipe

THETA_DEG, PHI_DEG = (-40.0, 40.0), (-130.0, 40.0)  # inside the sensing region, off its edges


@dataclass
class Stream:
    """truth (N, 3) N contact-frame force from the F/T sensor at truth_rate_hz; pressure
    (M, C) Pa tared barometer samples at sensor_rate_hz, sample m taken at truth row
    m * decimate; angles (N, 2) rad true contact angles."""

    truth: np.ndarray
    angles: np.ndarray
    pressure: np.ndarray
    truth_rate_hz: float
    decimate: int

    @property
    def sensor_rate_hz(self) -> float:
        return self.truth_rate_hz / self.decimate


def press_trajectory(n_presses: int, rate_hz: float, rng: np.random.Generator, rest_s: float = 0.5,
                     press_s: tuple[float, float] = (0.3, 1.2), gap_s: float = 0.1,
                     peak_n: tuple[float, float] = (5.0, 25.0), shear_ratio: float = 0.4) -> Trajectory:
    """Random presses at random contact points, one after another, sampled at rate_hz.

    Each press is a raised-cosine bump of normal force (duration and peak uniform in the
    given ranges) with shear along a random direction, up to shear_ratio times the normal
    force, followed by gap_s without contact; rest_s without contact first (for the tare).
    """
    parts, press, angles = [np.zeros((round(rest_s * rate_hz), 3))], [], []
    press.append(np.zeros(len(parts[0]), int))
    for i in range(n_presses):
        n = max(2, round(rng.uniform(*press_s) * rate_hz))
        shape = 0.5 * (1.0 - np.cos(2.0 * np.pi * np.arange(n) / n))
        peak, direction = rng.uniform(*peak_n), rng.uniform(0.0, 2.0 * np.pi)
        shear = rng.uniform(0.0, shear_ratio) * np.array([np.cos(direction), np.sin(direction)])
        force = peak * shape[:, None] * np.array([*shear, -1.0])
        parts += [force, np.zeros((round(gap_s * rate_hz), 3))]
        press.append(np.full(len(force) + len(parts[-1]), i))
        angles.append(np.deg2rad([rng.uniform(*THETA_DEG), rng.uniform(*PHI_DEG)]))
    force, press_id = np.concatenate(parts), np.concatenate(press)
    return Trajectory(force=force, angles=np.asarray(angles)[press_id], in_contact=force[:, 2] < 0.0,
                      press=press_id, patch=press_id, cells=np.zeros((0, 2), int))


def sense(unit: UnitParams, traj: Trajectory, truth_rate_hz: float, decimate: int, seed: int,
          conditions: RunConditions | None = None) -> Stream:
    """The unit's stream for a trajectory sampled at truth_rate_hz; deterministic from `seed`.

    The F/T truth carries the conditions' force noise; barometers are read every
    `decimate` truth rows at the ambient temperature and tared on the rest before contact.
    """
    conditions = conditions or RunConditions()
    rng = np.random.default_rng(seed)
    p = elastomer_pressure(unit, traj, traj.angles, 1.0 / truth_rate_hz)[::decimate]
    temp = np.full_like(p, conditions.ambient_c)
    reading = read_out(p, temp, conditions.atmosphere_pa, unit, rng)
    tared = reading - rest_reading(reading, traj.in_contact[::decimate], "stream")
    truth = traj.force + conditions.force_noise_n * rng.standard_normal(traj.force.shape)
    return Stream(truth, traj.angles, tared, truth_rate_hz, decimate)


def calibration_rows(unit: UnitParams, protocols: list[str], seed: int) -> tuple[np.ndarray, np.ndarray]:
    """The unit's calibration: X (n, C) tared Pa and Y (n, 5) labels of its contact rows."""
    xs, ys, first = [], [], 0
    for protocol in protocols:
        runs = simulate_unit(unit, protocol, seed, first_run=first)
        first += len(runs)
        for run in runs:
            c = run.in_contact
            tare = rest_reading(run.pressure, c, f"{run.sensor_id} {protocol}")
            xs.append(run.pressure[c] - tare)
            ys.append(np.concatenate([run.force[c], run.angles[c]], axis=1))
    return np.concatenate(xs), np.concatenate(ys)


def train_unit_model(unit: UnitParams, protocols: list[str], recipe: TrainRecipe, seed: int,
                     model: MLPConfig | None = None, unit_id: str = "unit") -> tuple[FitResult, int]:
    """A per-unit model (the paper's MLP by default) on the unit's calibration rows.

    Returns the fit and the number of calibration rows it was trained on (training plus
    validation rows).
    """
    X, Y = calibration_rows(unit, protocols, seed)
    data = FleetBatchData.from_units([split_rows(X, Y, 0.1, seed, unit_id)])
    return train_fleet(data, model, recipe, seed=seed), len(X)


def estimate(fit: FitResult, pressure: np.ndarray) -> np.ndarray:
    """(M, 5) model outputs (Fx, Fy, Fz N, theta, phi rad) for tared pressures (M, C) Pa."""
    x = torch.as_tensor(pressure, dtype=torch.float32, device=fit.in_scaler.mean.device)[None]
    return predict(fit.model, fit.in_scaler, fit.out_scaler, x)[0].double().cpu().numpy()
