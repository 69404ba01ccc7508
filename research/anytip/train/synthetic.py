"""A smooth, nonlinear stand-in for a fleet's calibration data, for tests and benchmarks.

A latent contact s ~ U(-1, 1)^5 maps to the targets by a fixed affine map (forces in N,
angles in rad) and to eight pressures (Pa) by a per-unit smooth map
p = A (M_u s + 0.3 sin(K s + c_u)) + noise. Eight channels of five latent dimensions make
the targets a smooth function of the pressures, which an 8-12-64-64-5 MLP can learn.
"""

from __future__ import annotations

import numpy as np
import torch

from anytip.data.seeds import TEST_PATCHES, stream_seed
from anytip.train.data import FleetBatchData, split_rows

PRESSURE_SCALE_PA = 2e4
TARGET_SCALE = np.array([3.0, 3.0, 7.0, 0.6, 1.5])  # half-ranges: N, N, N, rad, rad
TARGET_SHIFT = np.array([0.0, 0.0, 8.0, 0.6, 0.0])


def synthetic_fleet(n_units: int = 3, n_rows: int = 2000, seed: int = 0, val_fraction: float = 0.1,
                    noise_pa: float = 20.0, device: torch.device | str = "cpu") -> FleetBatchData:
    """n_units units of n_rows rows each, split at random into train and validation rows."""
    rng = np.random.default_rng(seed)
    M0, K = rng.normal(size=(8, 5)), rng.normal(scale=1.5, size=(8, 5))
    units = []
    for u in range(n_units):
        M = M0 + 0.2 * rng.normal(size=M0.shape)
        c = rng.uniform(0, 2 * np.pi, size=8)
        s = rng.uniform(-1, 1, size=(n_rows, 5))
        X = PRESSURE_SCALE_PA * (s @ M.T + 0.3 * np.sin(s @ K.T + c))
        X += noise_pa * rng.normal(size=X.shape)
        Y = s * TARGET_SCALE + TARGET_SHIFT
        units.append(split_rows(X, Y, val_fraction, seed=stream_seed(TEST_PATCHES, seed, u),
                                unit_id=f"syn{u:03d}"))
    return FleetBatchData.from_units(units, device)
