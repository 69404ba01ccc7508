"""Fit heteroscedastic per-unit MLPs, and deep ensembles of them, as one batched model.

An ensemble of K members for U units is one BatchedMLP of M = U * K models: model
m = u * K + k is member k of unit u, with its own initialisation seed and its own sampler
stream, trained on unit u's rows only. Every step draws a batch for every member and
takes one Adam step over the stacked weights; the loss is the sum over members of each
member's mean beta-NLL, so each member's gradient is its own. K = 1 is a single
heteroscedastic model per unit.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import torch
from torch import Tensor

from anytip.data.arrays import OUTPUT_NAMES
from anytip.models.heteroscedastic import (
    gaussian_nll,
    hetero_config,
    output_scaler_2d,
    split_heads,
    to_physical,
    unit_loss,
)
from anytip.models.io import save_models
from anytip.models.mlp import ACTIVATIONS, BatchedMLP, MLPConfig
from anytip.models.scaler import Scaler
from anytip.train.data import FleetBatchData, UnitSampler
from anytip.train.fleet import BestSnapshot
from anytip.train.recipe import FAST, TrainRecipe, eval_points, lr_at, make_optimizer, set_lr


@dataclass
class EnsembleFit:
    """A trained heteroscedastic fleet: model (U * K models, 2d outputs), per-unit scalers
    (U, 1, 8) and (U, 1, d), K members per unit, and the training curve."""

    model: BatchedMLP
    in_scaler: Scaler
    out_scaler: Scaler
    n_members: int
    unit_ids: list[str]
    beta: float
    recipe: TrainRecipe
    seed: int
    wall_s: float
    history: list[dict[str, Any]] = field(default_factory=list)

    def member_unit(self) -> Tensor:
        """(M,) int64: the unit of each model."""
        return torch.arange(len(self.unit_ids)).repeat_interleave(self.n_members)

    def save(self, path: str | Path) -> Path:
        """Save all members as plain MLPs; meta names which outputs are scales."""
        mu = self.member_unit()
        out2 = output_scaler_2d(self.out_scaler)
        meta = {"unit_ids": [self.unit_ids[u] for u in mu.tolist()],
                "member": [m % self.n_members for m in range(len(mu))],
                "n_members": self.n_members, **hetero_meta(self.out_scaler.mean.shape[-1], self.beta),
                "recipe": self.recipe.model_dump(mode="json"), "seed": self.seed}
        return save_models(path, self.model, self.in_scaler.take(mu), out2.take(mu), meta)


def hetero_meta(d: int, beta: float) -> dict[str, Any]:
    """Model-file meta of a heteroscedastic model with d means: which outputs are scales."""
    return {"output_names": list(OUTPUT_NAMES[:d]),
            "mean_outputs": list(range(d)), "scale_outputs": list(range(d, 2 * d)),
            "scale_kind": "log-variance in physical units (N^2, rad^2): sigma_k = exp(0.5 * output[d + k])",
            "loss": f"beta-NLL, beta={beta}"}



def train_hetero_fleet(data: FleetBatchData, config: MLPConfig | None = None,
                       recipe: TrainRecipe = FAST, n_members: int = 1, beta: float = 0.5,
                       seed: int = 0, device: torch.device | str | None = None) -> EnsembleFit:
    """Fit K heteroscedastic members per unit of `data`, all at once, with beta-NLL.

    Scalers are fit on each unit's training rows; each member keeps its weights at its
    lowest validation NLL (the unit's validation rows).
    """
    start = time.perf_counter()
    config = hetero_config(config or MLPConfig())
    device = torch.device(device) if device is not None else data.device
    data = data.to(device)
    U, K = data.n_units, n_members
    in_s, out_s = Scaler.fit(data.X_train, data.n_train), Scaler.fit(data.Y_train, data.n_train)
    X, Y = in_s.transform(data.X_train), out_s.transform(data.Y_train)
    Xv, Yv = in_s.transform(data.X_val), out_s.transform(data.Y_val)
    unit_of = torch.arange(U, device=device).repeat_interleave(K)[:, None]  # (M, 1)

    model = BatchedMLP(U * K, config, seed=seed).to(device)
    opt = make_optimizer(model.parameters(), recipe)
    sampler = UnitSampler(data.n_train.repeat_interleave(K), recipe.batch_size, seed, device)
    total = recipe.epochs * sampler.steps_per_epoch
    eval_at = eval_points(sampler.steps_per_epoch, recipe.evals_per_epoch)
    snapshot = BestSnapshot(model, recipe.patience)
    history: list[dict[str, Any]] = []
    for step, idx in sampler.steps(total):
        set_lr(opt, lr_at(step, total, recipe))
        loss_m = unit_loss(model(X[unit_of, idx]), Y[unit_of, idx], beta)  # (M,)
        opt.zero_grad(set_to_none=True)
        loss_m.sum().backward()
        opt.step()
        if step % sampler.steps_per_epoch + 1 in eval_at or step + 1 == total:
            val = val_nll(model, Xv[unit_of[:, 0]], Yv[unit_of[:, 0]], data.n_val[unit_of[:, 0]])
            history.append({"step": step + 1, "epoch": (step + 1) / sampler.steps_per_epoch,
                            "val_nll": val.tolist()})
            if snapshot.update(model, val):
                break
    if recipe.keep_best:
        snapshot.restore(model)
    return EnsembleFit(model, in_s, out_s, K, list(data.unit_ids), beta, recipe, seed,
                       time.perf_counter() - start, history)


@torch.no_grad()
def val_nll(model: BatchedMLP, X: Tensor, Y: Tensor, n: Tensor, chunk: int = 8192) -> Tensor:
    """Mean standardised Gaussian NLL of each model on its first n[m] rows: (M,) float64."""
    total = torch.zeros(X.shape[0], dtype=torch.float64, device=X.device)
    for i in range(0, X.shape[1], chunk):
        mu, log_var = split_heads(model(X[:, i:i + chunk]))
        nll = gaussian_nll(mu, log_var, Y[:, i:i + chunk]).mean(-1).double()
        mask = torch.arange(i, i + nll.shape[1], device=X.device) < n[:, None]
        total += (nll * mask).sum(1)
    return total / n.double()


@torch.no_grad()
def predict_members(fit: EnsembleFit, u: int, x: np.ndarray, members: int | None = None,
                    chunk: int = 65536) -> tuple[np.ndarray, np.ndarray]:
    """Unit u's first `members` (default all K) members on x (n, 8) Pa -> physical means
    and sigmas, each (K, n, d)."""
    K = fit.n_members
    k_use = K if members is None else members
    dev = fit.in_scaler.mean.device
    W = [(w[u * K:u * K + k_use], b[u * K:u * K + k_use]) for w, b in
         zip(fit.model.weights, fit.model.biases, strict=True)]
    mus, sigmas = [], []
    for i in range(0, max(len(x), 1), chunk):
        xt = torch.as_tensor(x[i:i + chunk], dtype=torch.float32, device=dev)
        z = fit.in_scaler.slice(u).transform(xt[None]).expand(k_use, -1, -1)
        for k, (w, b) in enumerate(W):
            z = torch.baddbmm(b, z, w)
            if k < len(W) - 1:
                z = ACTIVATIONS[fit.model.config.activation](z)
        mu_z, lv = split_heads(z)
        mu, sigma = to_physical(mu_z, lv, fit.out_scaler.slice(u))
        mus.append(mu.cpu().numpy().astype(np.float64))
        sigmas.append(sigma.cpu().numpy().astype(np.float64))
    return np.concatenate(mus, 1), np.concatenate(sigmas, 1)


def mixture(mu: np.ndarray, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Members' Gaussians (K, n, d) -> mixture mean, total sigma and disagreement (std of
    the members' means), each (n, d). K = 1 gives zero disagreement."""
    mean = mu.mean(0)
    spread = mu.std(0)
    total = np.sqrt((sigma ** 2).mean(0) + spread ** 2)
    return mean, total, spread
