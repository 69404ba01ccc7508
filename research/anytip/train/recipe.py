"""Training recipes: optimiser, batch, epochs, learning-rate schedule, early stopping."""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Literal

import torch
from pydantic import BaseModel, ConfigDict, Field

from anytip.errors import AnytipError
from anytip.train.fused_adam import FusedAdam, fused_kernel_serves

# what make_optimizer gives: both have `param_groups`, `step()` and `zero_grad()`
Optimizer = torch.optim.Optimizer | FusedAdam


class TrainRecipe(BaseModel):
    """How to fit each unit's MLP. `batch_size` is rows per unit per step; an epoch is each
    unit's training rows seen once on average. The loss is MSE on standardised outputs."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    name: str
    optimizer: Literal["adam", "adamw"] = "adam"
    lr: float = Field(1e-3, gt=0, le=10)
    weight_decay: float = Field(0.0, ge=0, le=10)
    batch_size: int = Field(10, ge=1, le=2**20)
    epochs: int = Field(10, ge=1, le=100_000)
    schedule: Literal["constant", "onecycle", "cosine"] = "constant"
    warmup_frac: float = Field(0.0, ge=0, lt=1)  # of all steps; onecycle starts at lr / 25
    final_lr_frac: float = Field(0.0, ge=0, le=1)  # lr at the last step, as a fraction of lr
    # evaluations without val-loss gain before a unit stops
    patience: int | None = Field(None, ge=1, le=1_000_000)
    evals_per_epoch: int = Field(1, ge=1, le=1000)
    keep_best: bool = True  # each unit ends with its weights at its lowest val loss
    loss: Literal["mse"] = "mse"


PAPER = TrainRecipe(name="paper", optimizer="adam", lr=1e-3, batch_size=10, epochs=10)
# Large batches and a one-cycle schedule. Tuned on simulated fleets (short and full
# protocols): batch 256 at peak lr 1e-2 reached the paper recipe's validation RMSE soonest
# and the lowest held-out-patch RMSE; batch 1024 at 6e-2 was as fast but less accurate.
# configs/training/fast.yaml holds the same values (a test keeps them equal).
FAST = TrainRecipe(name="fast", optimizer="adam", lr=1e-2, batch_size=256, epochs=40,
                   schedule="onecycle", warmup_frac=0.15, final_lr_frac=1e-3, evals_per_epoch=2)
RECIPES = {r.name: r for r in (PAPER, FAST)}


class EarlyStopping:
    """Early stopping on validation loss, for n models at once (the one home of the rule).

    A model improves when its loss falls below its best so far; after `patience` evaluations
    without improving it stops, and later evaluations of it never count as improving.
    """

    def __init__(self, n: int, patience: int | None, device: torch.device | str = "cpu"):
        self.patience = patience
        self.best = torch.full((n,), float("inf"), dtype=torch.float64, device=device)
        self.bad = torch.zeros(n, dtype=torch.int64, device=device)
        self.stopped = torch.zeros(n, dtype=torch.bool, device=device)

    def update(self, val_loss: torch.Tensor) -> torch.Tensor:
        """Record one evaluation of every model (n,); returns (n,) bool, the models that improved."""
        better = (val_loss.to(self.best) < self.best) & ~self.stopped
        self.best = torch.where(better, val_loss.to(self.best), self.best)
        self.bad = torch.where(better, 0, self.bad + 1)
        if self.patience is not None:
            self.stopped |= self.bad >= self.patience
        return better

    @property
    def all_stopped(self) -> bool:
        return bool(self.stopped.all())


def get_recipe(name: str) -> TrainRecipe:
    """A named default recipe; unknown names list the known ones."""
    if name not in RECIPES:
        raise AnytipError(f"unknown training recipe {name!r}; known: {sorted(RECIPES)}")
    return RECIPES[name]


def lr_at(step: int, total: int, recipe: TrainRecipe) -> float:
    """Learning rate for step (0-based) of `total` steps.

    constant: lr. cosine: linear warmup from 0, then cosine to final_lr_frac * lr.
    onecycle: cosine warmup from lr / 25, then cosine to final_lr_frac * lr.
    """
    lr, final = recipe.lr, recipe.lr * recipe.final_lr_frac
    if recipe.schedule == "constant":
        return lr
    warmup = int(recipe.warmup_frac * total)
    if step < warmup:
        t = (step + 1) / warmup
        if recipe.schedule == "cosine":
            return lr * t
        start = lr / 25
        return start + (lr - start) * 0.5 * (1 - math.cos(math.pi * t))
    t = (step - warmup) / max(1, total - warmup - 1)
    return final + (lr - final) * 0.5 * (1 + math.cos(math.pi * min(t, 1.0)))


def eval_points(steps_per_epoch: int, evals_per_epoch: int) -> set[int]:
    """In-epoch step counts (1..steps_per_epoch) after which to evaluate, evenly spaced."""
    return {max(1, round(k * steps_per_epoch / evals_per_epoch)) for k in range(1, evals_per_epoch + 1)}


def make_optimizer(params: Iterable[torch.nn.Parameter], recipe: TrainRecipe) -> Optimizer:
    """Adam or AdamW; both update each weight from its own gradient history only. torch's fused
    kernel (one pass over all weights), called directly (`FusedAdam`), where every weight lives on
    a device that has one: a tiny network's step is otherwise a third optimizer overhead on a CPU
    core; torch.optim's own Adam elsewhere."""
    params = list(params)
    if fused_kernel_serves(params):
        return FusedAdam(params, recipe.lr, recipe.weight_decay, decoupled=recipe.optimizer == "adamw")
    cls = torch.optim.AdamW if recipe.optimizer == "adamw" else torch.optim.Adam
    return cls(params, lr=recipe.lr, weight_decay=recipe.weight_decay)


def set_lr(opt: Optimizer, lr: float) -> None:
    for group in opt.param_groups:
        group["lr"] = lr
