"""Rows of each unit for per-unit uncertainty: training, conformal calibration and test rows,
split by whole patches so calibration and test rows never sit beside training rows."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import torch

from anytip.data.arrays import FleetArrays
from anytip.data.seeds import CALIBRATION_PATCHES, VALIDATION_ROWS, stream_seed
from anytip.data.splits import held_out_patches, patch_test_mask
from anytip.train.data import FleetBatchData, split_validation, unit_tensors


@dataclass
class UQSplit:
    """Per-unit training tensors, conformal calibration rows and test rows (numpy, Pa / N, rad)."""

    data: FleetBatchData
    X_cal: list[np.ndarray]
    Y_cal: list[np.ndarray]
    X_test: list[np.ndarray]
    Y_test: list[np.ndarray]
    X_fit: list[np.ndarray]  # training rows (for input novelty statistics)
    test_idx: list[np.ndarray] = field(default_factory=list)  # test rows' indices into the arrays
    cal_idx: list[np.ndarray] = field(default_factory=list)  # calibration rows' indices
    rest_idx: list[np.ndarray] = field(default_factory=list)  # every non-test row's index


def capped(rows: np.ndarray, max_rows: int | None, rng: np.random.Generator) -> np.ndarray:
    """At most `max_rows` of `rows` (row indices), a sorted random subset; all when None or fewer."""
    if max_rows is None or len(rows) <= max_rows:
        return rows
    return np.sort(rng.choice(rows, max_rows, replace=False))


def uq_split(arrays: FleetArrays, max_train_rows: int | None, calib_patch_fraction: float,
             test_fraction: float, val_fraction: float, seed: int, device: torch.device) -> UQSplit:
    """Per unit: test patches, then calibration patches (`calib_patch_fraction` of the rest),
    then training rows (at most `max_train_rows`) and validation rows."""
    targets, test_mask = arrays.targets, patch_test_mask(test_fraction, seed)
    members, parts = [], {k: [] for k in ("X_cal", "Y_cal", "X_test", "Y_test", "X_fit", "test_idx",
                                                     "cal_idx", "rest_idx")}
    for u, unit in enumerate(arrays.units):
        rows = np.flatnonzero(arrays.unit == u)
        test = test_mask(arrays.patch[rows], u)
        rest = rows[~test]
        cal = held_out_patches(arrays.patch[rest], calib_patch_fraction,
                               stream_seed(CALIBRATION_PATCHES, seed, u))
        train = rest[~cal]
        rng = np.random.default_rng(stream_seed(VALIDATION_ROWS, seed, u))
        fit, val = split_validation(capped(train, max_train_rows, rng), val_fraction, rng)
        members.append(unit_tensors(arrays, fit, val, unit))
        for key, idx in (("cal", rest[cal]), ("test", rows[test])):
            parts[f"X_{key}"].append(arrays.pressure[idx])
            parts[f"Y_{key}"].append(targets[idx].astype(np.float64))
        parts["X_fit"].append(arrays.pressure[fit])
        parts["test_idx"].append(rows[test])
        parts["cal_idx"].append(rest[cal])
        parts["rest_idx"].append(rest)
    return UQSplit(FleetBatchData.from_units(members, device), **parts)
