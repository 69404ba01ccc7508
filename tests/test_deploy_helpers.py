"""Helpers for the deploy tests (no tests here): tiny random per-unit and folded cross-sensor models."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import torch

from anytip.models.adapted import AdaptedMLP
from anytip.models.io import save_models
from anytip.models.mlp import BatchedMLP, MLPConfig
from anytip.models.scaler import Scaler

PAPER = MLPConfig(sizes=(8, 12, 64, 64, 5))
NAMES = ["fx", "fy", "fz", "theta", "phi"]


def scalers(n: int, seed: int = 0) -> tuple[Scaler, Scaler]:
    g = torch.Generator().manual_seed(seed)
    in_s = Scaler(15000 + 5000 * torch.rand(n, 1, 8, generator=g),
                  8000 + 8000 * torch.rand(n, 1, 8, generator=g))
    out_s = Scaler(torch.tensor([0.1, -0.2, -6.0, 0.2, 0.0]).repeat(n, 1, 1),
                   torch.tensor([3.0, 3.5, 7.0, 0.45, 0.8]).repeat(n, 1, 1))
    return in_s, out_s


def save_baseline(path: Path, n: int = 2, config: MLPConfig = PAPER, seed: int = 0) -> Path:
    """A per-unit model file with `n` random units U0, U1, ..."""
    model = BatchedMLP(n, config, seed=seed)
    in_s, out_s = scalers(n, seed)
    return save_models(path / "model.safetensors", model, in_s, out_s,
                       {"unit_ids": [f"U{i}" for i in range(n)], "output_names": NAMES})


def save_folded(path: Path, kind: str = "input_affine+embedding+film", n: int = 3) -> Path:
    """A cross-sensor model with random adapters, folded into a per-unit model file."""
    model = AdaptedMLP(n, PAPER, kind, seed=1)
    g = torch.Generator().manual_seed(2)
    with torch.no_grad():
        for p in model.adapter.values():
            p.add_(0.3 * torch.randn(p.shape, generator=g))
    in_s, out_s = scalers(n, 1)
    return save_models(path / "folded" / "model.safetensors", model.fold(), in_s, out_s,
                       {"unit_ids": [f"N{i}" for i in range(n)], "output_names": NAMES, "adapter": kind})


def synthetic_x(rows: int = 500, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return 17000 + 12000 * rng.standard_normal((rows, 8))
