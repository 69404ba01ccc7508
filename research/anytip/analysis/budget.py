"""End-to-end latency of a simulated sensor stream, measured by cross-correlation, and its budget.

Chains, each a sequence of what happens to the model's 200 Hz estimate before a
consumer sees it (times s, all measured against the 1 kHz F/T truth of normal force):

- `sensor`: the estimate at its sample instants: what the sensor physics and the
  (memoryless) model add, nothing else;
- `device`: the estimate leaves the microcontroller an inference time after its sample
  and is held until the next one (zero-order hold): what an online consumer sees;
- `device + causal MA w`: a causal moving average of w samples before the hold;
- `zero-phase MA w (offline)`: the forward-backward moving average at the sample
  instants; it needs w - 1 future samples, so it is an offline tool.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from anytip.analysis.filters import causal_moving_average, zero_phase_moving_average
from anytip.analysis.latency import Hold, estimate_delay
from anytip.analysis.stream import Stream, estimate, sense
from anytip.sensor.protocols import Trajectory
from anytip.sensor.variation import UnitParams
from anytip.train.fleet import FitResult
from anytip.train.metrics import rmse

FZ = 2  # normal force column of the model's outputs
UPSAMPLE = 100  # compare on a 0.01 ms grid so the hold's mean age and the inference time are resolved
# the simulator's effects with memory, switched off one at a time
PHYSICS = {"memoryless": {"relax_fraction": 0.0, "hysteresis": 0.0},
           "hysteresis only": {"relax_fraction": 0.0}, "relaxation only": {"hysteresis": 0.0}}


@dataclass(frozen=True)
class Chain:
    """One measured chain: its name, delay (s), whether it can run online, and its
    moving-average window in samples (1: no filter)."""

    name: str
    latency_s: float
    online: bool
    window: int = 1


def _delay(stream: Stream, est: np.ndarray, max_delay_s: float, t0_s: float = 0.0,
           hold: Hold = "linear") -> float:
    return estimate_delay(stream.truth[:, FZ], stream.truth_rate_hz, est, stream.sensor_rate_hz,
                          max_delay_s, t0_s, hold, UPSAMPLE if hold == "zoh" else 1)


def measure_chains(stream: Stream, est: np.ndarray, inference_s: float, windows: list[int],
                   max_delay_s: float) -> list[Chain]:
    """Delays of every chain for the model's estimate est (M, 5) of `stream`."""
    fz = est[:, FZ]
    chains = [Chain("sensor", _delay(stream, fz, max_delay_s), True),
              Chain("device", _delay(stream, fz, max_delay_s, inference_s, "zoh"), True)]
    for w in windows:
        smooth = causal_moving_average(fz, w)
        chains.append(Chain(f"device + causal MA {w}", _delay(stream, smooth, max_delay_s, inference_s,
                                                              "zoh"), True, w))
    for w in windows:
        chains.append(Chain(f"zero-phase MA {w} (offline)",
                            _delay(stream, zero_phase_moving_average(fz, w), max_delay_s), False, w))
    return chains


def physics_delays(unit: UnitParams, traj: Trajectory, fit: FitResult, truth_rate_hz: float,
                   decimate: int, seed: int, max_delay_s: float) -> dict[str, float]:
    """Delay (s) of the `sensor` chain with the simulator's memory effects switched off in turn.

    The same trajectory and noise draw as the full stream; the same model.
    """
    out = {}
    for name, update in PHYSICS.items():
        stream = sense(unit.model_copy(update=update), traj, truth_rate_hz, decimate, seed)
        out[name] = _delay(stream, estimate(fit, stream.pressure)[:, FZ], max_delay_s)
    return out


def stream_errors(stream: Stream, est: np.ndarray, min_force_n: float = 2.0) -> tuple[float, float]:
    """(force RMSE N, angle RMSE rad) of est (M, 5) at the sample instants where |Fz| > min_force_n
    (elsewhere the contact angles are undefined)."""
    truth = stream.truth[:: stream.decimate]
    angles = stream.angles[:: stream.decimate]
    m = -truth[:, FZ] > min_force_n
    force, angle = rmse(est[m, :3], truth[m]), rmse(est[m, 3:], angles[m])
    return force, angle
