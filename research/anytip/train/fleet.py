"""Fit a whole fleet of per-unit MLPs as one batched model.

Every step draws `batch_size` rows for every unit, runs one batched forward pass, and
takes one Adam step over the stacked weights. The loss is the sum over units of each
unit's mean loss, so each unit's gradient is exactly its own; with Adam's per-weight
update and per-unit samplers, unit u's trained weights do not depend on any other unit.
"""

from __future__ import annotations

import contextlib
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import torch
from rich.progress import Progress
from torch import Tensor

from anytip.data.arrays import OUTPUT_NAMES
from anytip.models.io import LoadedModels, save_models
from anytip.models.mlp import BatchedMLP, MLPConfig
from anytip.models.scaler import Scaler
from anytip.train.compiled_steps import CompiledSteps, compiled_serves, one_blas_thread
from anytip.train.data import FleetBatchData, UnitSampler
from anytip.train.metrics import evaluate, history_fields, progress_text
from anytip.train.recipe import (
    FAST,
    EarlyStopping,
    Optimizer,
    TrainRecipe,
    eval_points,
    lr_at,
    make_optimizer,
    set_lr,
)


@dataclass
class FitResult:
    """A trained fleet, its scalers and its training curve.

    history rows carry `elapsed_s`: training seconds, evaluation time excluded. Fleet rows
    hold per-unit lists (val_loss, val_force_rmse N, val_angle_rmse rad, train_loss);
    sequential rows hold one unit's numbers and its index under `unit`.
    """

    model: BatchedMLP
    in_scaler: Scaler
    out_scaler: Scaler
    history: list[dict[str, Any]]
    unit_ids: list[str]
    recipe: TrainRecipe
    seed: int
    wall_s: float  # whole call, evaluation included
    unit_train_s: list[float] | None = None  # sequential only: training seconds per unit
    output_names: tuple[str, ...] = OUTPUT_NAMES
    extra: dict[str, Any] = field(default_factory=dict)

    def unit_history(self, u: int) -> list[dict[str, Any]]:
        """Unit u's curve as rows of plain numbers."""
        if self.history and "unit" in self.history[0]:
            return [r for r in self.history if r["unit"] == u]
        return [{k: (v[u] if isinstance(v, list) else v) for k, v in r.items()} | {"unit": u}
                for r in self.history]

    def save(self, path: str | Path) -> Path:
        """Write model and scalers with the unit ids, output names, recipe and seed."""
        meta = {"unit_ids": self.unit_ids, "output_names": list(self.output_names),
                "recipe": self.recipe.model_dump(mode="json"), "seed": self.seed}
        return save_models(path, self.model, self.in_scaler, self.out_scaler, meta)


class BestSnapshot:
    """Per-unit model selection and early stopping on validation loss.

    Unit u keeps the weights of its lowest val loss so far; after `patience` evaluations
    without a gain it stops: later weights of that unit are never kept. Training goes on
    until every unit has stopped (stopped units still step, their results are ignored).
    """

    def __init__(self, model: BatchedMLP, patience: int | None):
        self.params = [p.detach().clone() for p in model.parameters()]
        self.stopping = EarlyStopping(model.n_models, patience, self.params[0].device)

    @torch.no_grad()
    def update(self, model: BatchedMLP, val_loss: Tensor) -> bool:
        """Record one evaluation; returns True when every unit has stopped."""
        better = self.stopping.update(val_loss)
        for kept, p in zip(self.params, model.parameters(), strict=True):
            kept[better] = p[better]
        return self.stopping.all_stopped

    @torch.no_grad()
    def restore(self, model: BatchedMLP) -> None:
        for kept, p in zip(self.params, model.parameters(), strict=True):
            p.copy_(kept)


def train_fleet(data: FleetBatchData, config: MLPConfig | None = None, recipe: TrainRecipe = FAST,
                seed: int = 0, device: torch.device | str | None = None,
                progress: bool = False, init: FitResult | LoadedModels | None = None) -> FitResult:
    """Fit one MLP per unit of `data`, all at once. Scalers are fit on training rows only.

    `init`: a trained network (model 0 of a FitResult or a saved per-unit file, of the same shape)
    every unit starts from, with its scalers, instead of random weights and scalers fitted on its
    own rows."""
    start = time.perf_counter()
    config = config or MLPConfig()
    device = torch.device(device) if device is not None else data.device
    data = data.to(device)
    U = data.n_units

    if init is None:
        in_scaler = Scaler.fit(data.X_train, data.n_train)
        out_scaler = Scaler.fit(data.Y_train, data.n_train)
        model = BatchedMLP(U, config, seed=seed).to(device)
    else:
        problem = start_mismatch(init, config)
        if problem:
            raise ValueError(f"the start network: {problem}")
        in_scaler, out_scaler = (s.take([0] * U).to(device) for s in (init.in_scaler, init.out_scaler))
        model = BatchedMLP.from_plain([init.model.to_plain(0)] * U, config).to(device)
    X, Y = in_scaler.transform(data.X_train), out_scaler.transform(data.Y_train)  # once, up front

    stepper = CompiledSteps(model, recipe) if compiled_serves(model, device) else None
    opt = make_optimizer(model.parameters(), recipe) if stepper is None else None
    sampler = UnitSampler(data.n_train, recipe.batch_size, seed, device)
    steps_per_epoch = sampler.steps_per_epoch
    total = recipe.epochs * steps_per_epoch
    eval_at = eval_points(steps_per_epoch, recipe.evals_per_epoch)
    snapshot = BestSnapshot(model, recipe.patience)

    history: list[dict[str, Any]] = []
    train_s, loss_sum, n_loss = 0.0, torch.zeros(U, device=device), 0
    bar = ProgressBar(progress, total, f"fleet of {U} ({recipe.name})")
    tick = time.perf_counter()
    # one network steps compiled (train/compiled_steps.py): BLAS would spread each product over every core
    with one_blas_thread() if stepper is not None else contextlib.nullcontext():
        # every stretch ends at an evaluation (each epoch's last step is one) or the last step
        for start, stop, (xs, ys) in sampler.stretches(total, eval_at, X, Y):
            lrs = [lr_at(step, total, recipe) for step in range(start, stop)]
            if stepper is not None:
                loss_sum += stepper.run(xs, ys, lrs)
            else:
                _torch_steps(model, opt, xs, ys, lrs, loss_sum)
            n_loss += stop - start
            step, lr = stop - 1, lrs[-1]
            bar.update(stop)

            train_s += _lap(tick, device)
            model.eval()
            val = evaluate(model, in_scaler, out_scaler, data.X_val, data.Y_val, data.n_val)
            model.train()
            history.append({"epoch": (step + 1) / steps_per_epoch, "step": step + 1,
                            "elapsed_s": train_s, "lr": lr, "train_loss": (loss_sum / n_loss).tolist(),
                            "val_loss": val["loss"].tolist(), **history_fields(val)})
            loss_sum.zero_()
            n_loss = 0
            all_stopped = snapshot.update(model, val["loss"])
            bar.update(step + 1, f"fleet of {U}: {progress_text(val)}")
            if all_stopped:
                break
            tick = time.perf_counter()
    bar.close()
    if recipe.keep_best:
        snapshot.restore(model)
    return FitResult(model, in_scaler, out_scaler, history, list(data.unit_ids), recipe, seed,
                     time.perf_counter() - start, output_names=data.output_names,
                     extra={"steps": step + 1, "steps_per_epoch": steps_per_epoch})


def _torch_steps(model: BatchedMLP, opt: Optimizer, xs: Tensor, ys: Tensor, lrs: list[float],
                 loss_sum: Tensor) -> None:
    """Steps on rows xs (k, U, B, in), ys (k, U, B, out), step i at learning rate lrs[i], by the
    model's gradients (`mse_grads`) and `opt`; each step's loss (U,) added into `loss_sum`."""
    for x, y, lr in zip(xs.unbind(0), ys.unbind(0), lrs, strict=True):
        set_lr(opt, lr)
        loss_sum += model.mse_grads(x, y)  # (U,), each unit's gradient in its weights' .grad
        opt.step()


def joined_fits(parts: Sequence[tuple[Sequence[int], FitResult]]) -> FitResult:
    """One fleet of fleets trained apart: part (jobs, fit) puts fit's model i at index jobs[i] (the
    parts' jobs together are 0..M-1 once each), with its scalers and unit id. Their training curves
    do not share evaluation points, so they stay apart, each with its jobs, under extra["parts"];
    the joined history is empty. Wall time is the parts' sum."""
    order = [(m, fit, i) for jobs, fit in parts for i, m in enumerate(jobs)]
    order.sort(key=lambda t: t[0])
    if [m for m, _, _ in order] != list(range(len(order))):
        raise ValueError(f"the parts' jobs are not 0..{len(order) - 1} once each")
    first = parts[0][1]
    model = BatchedMLP.from_plain([fit.model.to_plain(i) for _, fit, i in order], first.model.config)

    def scaler(which: str) -> Scaler:
        taken = [getattr(fit, which).take([i]) for _, fit, i in order]
        return Scaler(torch.cat([t.mean for t in taken]), torch.cat([t.std for t in taken]))

    ids = [fit.unit_ids[i] for _, fit, i in order]
    return FitResult(model, scaler("in_scaler"), scaler("out_scaler"), [], ids, first.recipe,
                     first.seed, sum(fit.wall_s for _, fit in parts), output_names=first.output_names,
                     extra={"parts": [{"jobs": list(jobs), "history": fit.history, **fit.extra}
                                      for jobs, fit in parts]})


def start_mismatch(init: FitResult | LoadedModels, config: MLPConfig) -> str | None:
    """Why `init`'s networks cannot start networks of `config` (another shape or activation), or None."""
    got = init.model.config
    if (got.sizes, got.activation) == (config.sizes, config.activation):
        return None
    return (f"{init.model.n_models} network(s) of {got.sizes} ({got.activation}), where one "
            f"{config.sizes} ({config.activation}) is asked for")


def _lap(tick: float, device: torch.device) -> float:
    """Seconds since `tick`, after the device has finished its queued work."""
    if device.type == "cuda":
        torch.cuda.synchronize(device)
    return time.perf_counter() - tick


class ProgressBar:
    """A rich progress bar over training steps, or nothing when disabled."""

    def __init__(self, enabled: bool, total: int, description: str):
        self.bar = Progress() if enabled else None
        if self.bar is not None:
            self.task = self.bar.add_task(description, total=total)
            self.bar.start()

    def update(self, step: int, description: str | None = None) -> None:
        if self.bar is not None and (description is not None or step % 100 == 0):
            self.bar.update(self.task, completed=step, description=description)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()
