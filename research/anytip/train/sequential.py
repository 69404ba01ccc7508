"""The reference: fit the units one at a time, each a plain nn.Sequential, as the paper did.

A standard PyTorch loop per unit: shuffle the unit's rows each epoch, step through them
in mini-batches. Each unit starts from the same initial weights and uses the same scalers
as `train_fleet` with the same seed would, so the two differ only in how they train.
"""

from __future__ import annotations

import math
import time
from typing import Any

import torch
from torch import nn

from anytip.data.seeds import unit_seed
from anytip.models.mlp import BatchedMLP, MLPConfig, sequential_to_plain
from anytip.models.scaler import Scaler
from anytip.train.data import FleetBatchData
from anytip.train.fleet import FitResult, ProgressBar, _lap
from anytip.train.metrics import evaluate, history_fields, progress_text
from anytip.train.recipe import PAPER, EarlyStopping, TrainRecipe, eval_points, lr_at, make_optimizer, set_lr


def train_sequential(data: FleetBatchData, config: MLPConfig | None = None,
                     recipe: TrainRecipe = PAPER, seed: int = 0,
                     device: torch.device | str | None = None, progress: bool = False,
                     evals_per_epoch: int = 10) -> FitResult:
    """Fit each unit of `data` alone; validation every 1/evals_per_epoch epoch.

    History rows are per unit (`unit` key) with `elapsed_s` counted from that unit's start,
    evaluation excluded; `unit_train_s` holds each unit's total training seconds.
    """
    start = time.perf_counter()
    config = config or MLPConfig()
    device = torch.device(device) if device is not None else data.device
    data = data.to(device)
    in_scaler = Scaler.fit(data.X_train, data.n_train)
    out_scaler = Scaler.fit(data.Y_train, data.n_train)
    history: list[dict[str, Any]] = []
    plains, unit_train_s = [], []
    for u in range(data.n_units):
        net, rows, train_s = _fit_unit(data, u, config, recipe, seed, in_scaler.slice(u),
                                       out_scaler.slice(u), evals_per_epoch, progress)
        plains.append(sequential_to_plain(net))
        history += rows
        unit_train_s.append(train_s)
    model = BatchedMLP.from_plain(plains, config)
    return FitResult(model, in_scaler, out_scaler, history, list(data.unit_ids), recipe, seed,
                     time.perf_counter() - start, unit_train_s, data.output_names)


def _fit_unit(data: FleetBatchData, u: int, config: MLPConfig, recipe: TrainRecipe, seed: int,
              in_scaler: Scaler, out_scaler: Scaler, evals_per_epoch: int, progress: bool
              ) -> tuple[nn.Sequential, list[dict[str, Any]], float]:
    """One unit's loop; returns the selected net, its curve and its training seconds."""
    device = data.device
    unit = data.unit(u)
    X, Y = in_scaler.transform(unit.X_train)[0], out_scaler.transform(unit.Y_train)[0]  # (n, d)
    Xv, Yv = unit.X_val[None], unit.Y_val[None]  # (1, m, d), physical
    net = BatchedMLP(1, config, seed=[unit_seed(seed, u)]).to_sequential(0).to(device)
    opt = make_optimizer(net.parameters(), recipe)
    g = torch.Generator(device).manual_seed(unit_seed(seed, u, "sample"))
    n, B = len(X), recipe.batch_size
    steps_per_epoch = math.ceil(n / B)
    total = recipe.epochs * steps_per_epoch
    eval_at = eval_points(steps_per_epoch, evals_per_epoch)
    stopping, best_state = EarlyStopping(1, recipe.patience), _copy_state(net)

    rows: list[dict[str, Any]] = []
    train_s, loss_sum, n_loss = 0.0, torch.zeros((), device=device), 0
    bar = ProgressBar(progress, total, f"unit {unit.unit_id} ({recipe.name})")
    tick = time.perf_counter()
    for step in range(total):
        if step % steps_per_epoch == 0:
            perm = torch.randperm(n, generator=g, device=device)
        lr = lr_at(step, total, recipe)
        set_lr(opt, lr)
        idx = perm[(step % steps_per_epoch) * B : (step % steps_per_epoch + 1) * B]
        loss = ((net(X[idx]) - Y[idx]) ** 2).mean()
        opt.zero_grad(set_to_none=True)
        loss.backward()
        opt.step()
        loss_sum += loss.detach()
        n_loss += 1

        if step % steps_per_epoch + 1 not in eval_at and step + 1 < total:
            continue
        train_s += _lap(tick, device)
        val = evaluate(net, in_scaler, out_scaler, Xv, Yv)
        val_loss = float(val["loss"][0])
        rows.append({"unit": u, "epoch": (step + 1) / steps_per_epoch, "step": step + 1,
                     "elapsed_s": train_s, "lr": lr, "train_loss": float(loss_sum) / n_loss,
                     "val_loss": val_loss, **history_fields(val, 0)})
        loss_sum.zero_()
        n_loss = 0
        if stopping.update(torch.tensor([val_loss], dtype=torch.float64))[0]:
            best_state = _copy_state(net)
        bar.update(step + 1, f"unit {unit.unit_id}: {progress_text(val)}")
        if stopping.all_stopped:
            break
        tick = time.perf_counter()
    bar.close()
    if recipe.keep_best:
        net.load_state_dict(best_state)
    return net, rows, train_s


def _copy_state(net: nn.Module) -> dict[str, torch.Tensor]:
    return {k: v.detach().clone() for k, v in net.state_dict().items()}
