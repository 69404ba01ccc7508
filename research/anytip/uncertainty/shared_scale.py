"""A scale network for the adapted shared model: where its errors are large.

The shared model with per-unit adapters predicts the mean. A second plain MLP of the
deployed shape maps the same standardised input to d log-variances, fitted by Gaussian NLL
(the mean held at the shared model's prediction) on the residuals of the shared model's
training units on their validation rows. It is trained once for the fleet, is not adapted
per unit, and only needs the right shape of the error over the contact region and force:
a normalised conformal quantile calibrated on validation units sets its level for new units.
"""

from __future__ import annotations

import numpy as np
import torch
from torch import Tensor

from anytip.models.heteroscedastic import LOG_VAR_MAX, LOG_VAR_MIN
from anytip.models.mlp import BatchedMLP, MLPConfig
from anytip.models.scaler import Scaler
from anytip.train.adapt import SharedFit
from anytip.train.data import FleetBatchData


@torch.no_grad()
def validation_rows(shared: SharedFit, data: FleetBatchData) -> tuple[Tensor, Tensor, Tensor]:
    """The training units' validation rows, concatenated over units on the model's device:
    standardised inputs (m, d_in), the shared model's standardised predictions (m, d_out)
    (each unit through its own adapter) and the physical targets (m, d_out)."""
    device = shared.model.weights[0].device
    X = shared.in_scaler.transform(data.X_val.to(device))  # (U, N, d_in)
    was_training = shared.model.training
    pred = shared.model.eval()(X)
    shared.model.train(was_training)
    keep = [slice(0, int(n)) for n in data.n_val]

    def cat(t: Tensor) -> Tensor:
        return torch.cat([t[u, k] for u, k in enumerate(keep)])

    return cat(X), cat(pred), cat(data.Y_val.to(device))


@torch.no_grad()
def shared_residuals(shared: SharedFit, data: FleetBatchData) -> tuple[Tensor, Tensor]:
    """Standardised inputs (m, d_in) and standardised residuals (m, d_out) of the shared
    model (with each training unit's own adapter) on the training units' validation rows."""
    X, pred, Y = validation_rows(shared, data)
    return X.cpu(), (shared.out_scaler.transform(Y[None])[0] - pred).cpu()


def fit_scale_network(x: Tensor, resid: Tensor, config: MLPConfig, epochs: int = 10, batch_size: int = 512,
                      lr: float = 3e-3, seed: int = 0) -> BatchedMLP:
    """One MLP (d_in -> ... -> d_out) of log-variances of `resid` (m, d_out) given x (m, d_in),
    both standardised, by Gaussian NLL with zero mean."""
    model = BatchedMLP(1, config, seed=seed)
    opt = torch.optim.Adam(model.parameters(), lr=lr)
    g = torch.Generator().manual_seed(seed)
    steps = max(1, len(x) // batch_size)
    for _ in range(epochs):
        order = torch.randperm(len(x), generator=g)
        for s in range(steps):
            idx = order[s * batch_size:(s + 1) * batch_size]
            lv = model(x[idx][None])[0].clamp(LOG_VAR_MIN, LOG_VAR_MAX)
            loss = 0.5 * (lv + resid[idx] ** 2 / lv.exp()).mean()
            opt.zero_grad(set_to_none=True)
            loss.backward()
            opt.step()
    return model


@torch.no_grad()
def predict_scale(model: BatchedMLP, in_scaler: Scaler, out_scaler: Scaler, x: np.ndarray) -> np.ndarray:
    """Physical sigma (n, d_out) on pressures x (n, d_in) Pa, standardised by one unit's
    in_scaler (1, 1, d_in); out_scaler (1, 1, d_out) is the shared model's."""
    z = in_scaler.transform(torch.as_tensor(x, dtype=torch.float32, device=in_scaler.mean.device)[None])
    lv = model(z)[0].clamp(LOG_VAR_MIN, LOG_VAR_MAX)
    return (out_scaler.std[0, 0] * (0.5 * lv).exp()).cpu().numpy().astype(np.float64)


@torch.no_grad()
def fit_force_scale(shared: SharedFit, data: FleetBatchData) -> np.ndarray:
    """Least-squares fit of |residual_k| ~ a_k + b_k |F_hat| (physical units) on the training
    units' validation rows: (2, d_out), a above b, both clipped at >= 0 and a > 0. A gain
    error of a new unit's adapter grows with the force, which this scale follows."""
    _, pred, Y = validation_rows(shared, data)
    p = shared.out_scaler.inverse(pred[None])[0].cpu().double().numpy()
    y = Y.cpu().double().numpy()
    A = np.stack([np.ones(len(p)), np.linalg.norm(p[:, :3], axis=1)], 1)
    coef = np.linalg.lstsq(A, np.abs(y - p), rcond=None)[0]  # (2, d)
    coef = np.maximum(coef, 0.0)
    coef[0] = np.maximum(coef[0], 1e-3 * np.abs(y - p).mean(0))
    return coef


def force_scale(pred: np.ndarray, coef: np.ndarray) -> np.ndarray:
    """sigma (n, d) = a + b |F_hat| from predictions (n, d) (force in the first 3 columns)."""
    return coef[0] + np.linalg.norm(pred[:, :3], axis=1, keepdims=True) * coef[1]
