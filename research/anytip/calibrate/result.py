"""What a calibration of one new unit produced (`Calibrated`, written as `calibration.json`), and
what both calibration methods share: the check of its network on its runs outside the calibration
stream, and the own-check alarm."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import torch
from torch import Tensor

from anytip.data.arrays import FleetArrays
from anytip.data.calibration import CalibrationStream
from anytip.models.scaler import Scaler
from anytip.rundir import write_json
from anytip.train.metrics import predict, scores, target_key

# A new unit whose own check exceeds the worst validation unit's by more than this is flagged.
# Every cross_sensor report shows how often it fires on held-out units, which are ordinary units
# (section "The calibration's own check on ordinary units").
OWN_CHECK_ALARM = 2.0


@dataclass
class Calibrated:
    """What `calibrate_unit` wrote and measured."""

    path: Path
    unit: str
    calib_samples: int
    calib_seconds: float
    unlabeled_samples: int
    prior: float
    check: dict[str, float] | None  # RMSE on the unit's other runs, when it has any
    notes: list[str]  # which shared model and why, clipped budgets, warnings
    own_check: dict[str, float] | None = None  # the plan's held-out presses against the fleet's
    wall_s: float = 0.0  # fitting and folding the adapter on the whole plan
    intervals: dict[str, Any] | None = None  # from the plan's residuals (`plan_intervals`)
    check_s: float = 0.0  # the fold fits behind the own check and the intervals
    response_check: dict[str, Any] | None = None  # response transfer: the plan about its fitted response
    unlabeled_seconds: float = 0.0  # contact seconds of ordinary use read (response transfer)
    core_gflops: float | None = None  # this core's reference product rate after the fit (`train.core_speed`)


def write_calibration(result: Calibrated) -> Calibrated:
    """`calibration.json` in the result's directory: every field of `result`, paths as text."""
    write_json(Path(result.path) / "calibration.json",
               {k: (str(v) if isinstance(v, Path) else v) for k, v in result.__dict__.items()})
    return result


def check_on_other_runs(net: tuple[Callable[[Tensor], Tensor], Scaler, Scaler], arrays: FleetArrays,
                        stream: CalibrationStream, read: np.ndarray | None = None
                        ) -> tuple[dict[str, Any] | None, tuple[np.ndarray, np.ndarray] | None]:
    """A unit's network (with its input and output scalers) scored on its runs outside the
    calibration stream but the rows `read` (indices: ordinary use drawn from those runs, its pressures
    read), None where none are left, and its predictions and targets there (n, D)."""
    other = stream.outside(arrays)
    if read is not None:
        other[read] = False
    if not other.any():
        return None, None
    pred = predict(*net, torch.from_numpy(arrays.pressure[other])[None])[0].numpy()
    on_other = (pred, arrays.targets[other])
    return {"rows": int(other.sum()), **scores(*on_other, arrays.layout),
            "units": {target_key(n): t.unit for n, t in arrays.layout.items()}}, on_other
