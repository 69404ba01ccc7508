"""Fixed linear input features that fold into the first layer of the deployed network.

A feature map is a matrix F (8, k): the network is trained on x @ F (B, k) for tared pressures
x (B, 8) Pa, standardised per feature. Because x -> x @ F is linear, the trained first layer
and its input scaler fold into an 8-input layer (`fold_features`), so the deployed network is
8 -> ... -> 5 with the MACs and flash of a raw-input network of the same hidden widths. A
feature map changes the optimisation (what the standardisation and initialisation see), not
the set of functions the network can compute.

- `raw`: F = I (8, 8).
- `neighbour_diffs`: F = [I | D] (8, 16); column e of D is p_i - p_j for the e-th pair of
  neighbouring barometers. Neighbours are each barometer's two nearest barometers on the
  dome (sensor/geometry.py positions), edges taken undirected: on the fingertip this is the
  ring 2-0-4-6-7-5-1-3-2 that runs along each board and across the corner where the top
  and side boards meet (the closest pairs, 3.5 mm apart, straddle that corner).
"""

from __future__ import annotations

from typing import Literal

import numpy as np
import torch
from torch import Tensor

from anytip.errors import AnytipError
from anytip.models.mlp import BatchedMLP, MLPConfig
from anytip.models.scaler import Scaler
from anytip.sensor.geometry import NOMINAL, SensorGeometry

Features = Literal["raw", "neighbour_diffs"]
FEATURES = ("raw", "neighbour_diffs")


def neighbour_pairs(geometry: SensorGeometry = NOMINAL, k: int = 2) -> list[tuple[int, int]]:
    """Undirected pairs (i < j) joining each barometer to its k nearest, sorted."""
    pos = np.asarray(geometry.baro_positions_m, float)
    dist = np.linalg.norm(pos[:, None] - pos[None], axis=-1)
    np.fill_diagonal(dist, np.inf)
    nearest = np.argsort(dist, axis=1, kind="stable")[:, :k]
    pairs = {tuple(sorted((i, int(j)))) for i in range(len(pos)) for j in nearest[i]}
    return sorted(pairs)


def feature_matrix(name: str, n_inputs: int = 8, geometry: SensorGeometry = NOMINAL) -> np.ndarray:
    """F (n_inputs, k) float64 of feature map `name`; unknown names list the known ones."""
    if name == "raw":
        return np.eye(n_inputs)
    if name == "neighbour_diffs":
        if geometry.n_channels != n_inputs:
            raise AnytipError(f"features 'neighbour_diffs': the geometry has {geometry.n_channels} "
                              f"barometers but the network {n_inputs} inputs")
        pairs = neighbour_pairs(geometry)
        D = np.zeros((n_inputs, len(pairs)))
        for e, (i, j) in enumerate(pairs):
            D[i, e], D[j, e] = 1.0, -1.0
        return np.concatenate([np.eye(n_inputs), D], axis=1)
    raise AnytipError(f"unknown input features {name!r}; known: {list(FEATURES)}")


def apply_features(x: Tensor, F: Tensor) -> Tensor:
    """(..., 8) pressures -> (..., k) features; zero rows (padding) stay zero."""
    return x @ F.to(x.dtype).to(x.device)


@torch.no_grad()
def fold_features(model: BatchedMLP, in_scaler: Scaler, F: Tensor,
                  raw_scaler: Scaler) -> tuple[BatchedMLP, Scaler]:
    """A network on raw pressures computing exactly what `model` computes on features.

    model: U networks (k -> ... -> out) on standardised features; in_scaler (U, 1, k) their
    feature statistics; F (8, k); raw_scaler (U, 1, 8): the scaler the folded network is given
    (any positive std works; the pressures' own statistics keep its weights well scaled).
    With z = (x - m8) / s8: ((x F - m) / s) W0 + b0 = z (s8 F / s W0) + b0 + ((m8 F - m) / s) W0.
    Computed in float64, returned in the model's dtype.
    """
    W0, b0 = model.weights[0].double(), model.biases[0].double()  # (U, k, h), (U, 1, h)
    Fd = F.double().to(W0.device)
    m, s = in_scaler.mean.double(), in_scaler.std.double()  # (U, 1, k)
    m8, s8 = raw_scaler.mean.double(), raw_scaler.std.double()  # (U, 1, 8)
    scaled = W0 / s.transpose(1, 2)  # (U, k, h): diag(1/s) W0
    W_new = s8.transpose(1, 2) * torch.matmul(Fd, scaled)  # (U, 8, h)
    b_new = b0 + torch.bmm(m8 @ Fd - m, scaled)
    dtype = model.weights[0].dtype
    plains = []
    for u in range(model.n_models):
        plain = model.to_plain(u)
        plain[0] = (W_new[u].to(dtype), b_new[u, 0].to(dtype))
        plains.append(plain)
    config = MLPConfig(sizes=(F.shape[0], *model.config.sizes[1:]), activation=model.config.activation,
                       output_activation=model.config.output_activation)
    folded = BatchedMLP.from_plain(plains, config)
    return folded, Scaler(raw_scaler.mean.to(in_scaler.mean.dtype).clone(),
                          raw_scaler.std.to(in_scaler.std.dtype).clone())
