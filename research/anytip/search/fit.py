"""Per-unit candidates: train every unit's network at once on its input features, then fold
the features into the first layer so what is scored is the deployable 8-input network."""

from __future__ import annotations

import torch

from anytip.models.features import apply_features, feature_matrix, fold_features
from anytip.models.mlp import MLPConfig
from anytip.models.scaler import Scaler
from anytip.search.study import Candidate
from anytip.train.data import FleetBatchData
from anytip.train.fleet import FitResult, train_fleet
from anytip.train.recipe import TrainRecipe


def feature_tensor(features: str, n_inputs: int = 8) -> torch.Tensor:
    """F (n_inputs, k) float32 of a feature map (models/features.py)."""
    return torch.from_numpy(feature_matrix(features, n_inputs)).float()


def map_fleet(data: FleetBatchData, F: torch.Tensor) -> FleetBatchData:
    """The fleet with inputs X (U, N, 8) replaced by features X @ F (U, N, k)."""
    return FleetBatchData(apply_features(data.X_train, F), data.Y_train, data.n_train,
                          apply_features(data.X_val, F), data.Y_val, data.n_val, list(data.unit_ids),
                          data.output_names)


def train_candidate(data: FleetBatchData, cand: Candidate, recipe: TrainRecipe, seed: int,
                    device: torch.device | str | None = None) -> FitResult:
    """One network of `cand` per unit of `data` (raw pressures), returned folded: model
    8 -> ... -> 5 with an 8-input scaler fitted on the units' training rows."""
    config = MLPConfig(sizes=cand.sizes, activation=cand.activation)
    if cand.features == "raw":
        return train_fleet(data, config, recipe, seed=seed, device=device)
    F = feature_tensor(cand.features, cand.sizes[0])
    config = config.model_copy(update={"sizes": (F.shape[1], *cand.sizes[1:])})
    fit = train_fleet(map_fleet(data, F), config, recipe, seed=seed, device=device)
    raw = Scaler.fit(data.X_train, data.n_train).to(fit.in_scaler.mean.device)
    fit.model, fit.in_scaler = fold_features(fit.model, fit.in_scaler, F, raw)
    return fit
