"""MLP family: the batched per-unit MLP, per-unit scalers, and their safetensors files."""

from anytip.models.io import LoadedModels, ModelFileError, load_models, save_models
from anytip.models.mlp import (
    BatchedMLP,
    MLPConfig,
    plain_to_sequential,
    sequential_to_plain,
    unit_seed,
)
from anytip.models.scaler import Scaler

__all__ = [
    "BatchedMLP", "LoadedModels", "MLPConfig", "ModelFileError", "Scaler", "load_models",
    "plain_to_sequential", "save_models", "sequential_to_plain", "unit_seed",
]
