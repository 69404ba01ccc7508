"""Episodic shared training: prepare the shared weights for a new unit's short calibration.

A new unit's adapter is fitted on a plan of a few whole presses and scored on patches the plan
never touched. Joint training (train/adapt.py) fits each training unit's adapter on all of its
rows, so nothing asks the shared weights to make a good adapter findable from a few presses.
An episode asks exactly that, for every training unit at once (CAVIA / Meta-SGD style):

1. support: `presses` whole presses of the unit drawn at random, `rows_per_press` rows of each;
2. inner fit: starting at the identity adapter, `inner_steps` gradient steps on the support
   loss, each adapter tensor with its own step size, learnt (Meta-SGD, one rate per tensor);
3. query: the unit's rows of the same training batch outside the support presses, scored with
   the fitted adapter; that loss is added to the joint loss (times `weight`) and its gradient
   reaches the shared weights through the inner fit (second order).

The inner fit is truncated (a few plain gradient steps); a new unit's calibration still runs
`fit_adapters` to convergence under its prior. The training units' own adapters stay (the
empirical prior and model selection use them).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import torch
from torch import Tensor

from anytip.errors import AnytipError
from anytip.models.adapted import AdaptedMLP


@dataclass(frozen=True)
class EpisodeRecipe:
    """How an episode is drawn and fitted. The defaults mimic a 120 s plan of the fingertip's
    3.8 s presses (10 presses over the three orientations)."""

    presses: int = 10
    rows_per_press: int = 32
    inner_steps: int = 5
    inner_lr: float = 0.1  # every tensor's step size at the start; learnt from there
    weight: float = 1.0  # of the query loss beside the joint loss
    units_per_step: int | None = None  # episodes of this many training units per step (None: all)

    def __post_init__(self) -> None:
        for name in ("presses", "rows_per_press", "inner_steps", "units_per_step"):
            if getattr(self, name) is not None and getattr(self, name) < 1:
                raise AnytipError(f"episodic training: {name} must be >= 1, got {getattr(self, name)}")
        for name in ("inner_lr", "weight"):
            value = getattr(self, name)
            if not math.isfinite(value) or value <= 0:
                raise AnytipError(f"episodic training: {name} must be a finite number > 0, got {value}")


@dataclass
class PressIndex:
    """Training units' fitting rows grouped by press.

    press (U, N) int64: the press of each padded fitting row (-1 for padding; ids 0..P_u-1);
    order (U, N) int64: row positions sorted by press; start (U, P_max) and count (U, P_max):
    where each press's rows begin in `order` and how many; n_presses (U,).
    """

    press: Tensor
    order: Tensor
    start: Tensor
    count: Tensor
    n_presses: Tensor

    @classmethod
    def from_ids(cls, ids: list[np.ndarray], n_rows: int, device: torch.device | str) -> PressIndex:
        """ids[u] (n_u,) any integer press label of unit u's fitting rows, in row order; padded to
        n_rows. Labels are renumbered 0..P_u-1 per unit."""
        U = len(ids)
        press = torch.full((U, n_rows), -1, dtype=torch.int64)
        dense = [np.unique(i, return_inverse=True)[1].reshape(-1) for i in ids]
        P = max(int(d.max()) + 1 if len(d) else 0 for d in dense)
        start = torch.zeros(U, max(P, 1), dtype=torch.int64)
        count = torch.zeros(U, max(P, 1), dtype=torch.int64)
        order = torch.zeros(U, n_rows, dtype=torch.int64)
        for u, d in enumerate(dense):
            press[u, : len(d)] = torch.from_numpy(d)
            order[u, : len(d)] = torch.from_numpy(np.argsort(d, kind="stable"))
            c = np.bincount(d, minlength=P)
            count[u, :P] = torch.from_numpy(c)
            start[u, :P] = torch.from_numpy(np.concatenate([[0], np.cumsum(c)[:-1]]))
        n_presses = torch.tensor([int(d.max()) + 1 if len(d) else 0 for d in dense])
        if int(n_presses.min()) < 2:
            raise AnytipError("episodic training needs at least 2 presses in every training unit's rows "
                              f"(support and query); the fewest is {int(n_presses.min())}")
        return cls(*(t.to(device) for t in (press, order, start, count, n_presses)))

    def to(self, device: torch.device | str) -> PressIndex:
        return PressIndex(*(t.to(device) for t in (self.press, self.order, self.start, self.count,
                                                  self.n_presses)))

    def draw(self, recipe: EpisodeRecipe, generator: torch.Generator) -> tuple[Tensor, Tensor]:
        """One episode's support for every unit: (rows (U, K * r) positions into the padded
        fitting rows, presses (U, K) the chosen press ids); K = min(presses, fewest presses - 1),
        so every unit keeps presses for its query."""
        device = self.press.device
        U, P = self.count.shape
        K = min(recipe.presses, int(self.n_presses.min()) - 1)
        score = torch.rand(U, P, generator=generator, device=device)
        score = score.masked_fill(torch.arange(P, device=device)[None] >= self.n_presses[:, None], 2.0)
        chosen = score.argsort(dim=1)[:, :K]
        pick = torch.rand(U, K, recipe.rows_per_press, generator=generator, device=device)
        count = self.count.gather(1, chosen)[:, :, None]
        where = self.start.gather(1, chosen)[:, :, None] + (pick * count).long().clamp_max(count - 1)
        return self.order.gather(1, where.reshape(U, -1)), chosen

    def outside(self, rows: Tensor, chosen: Tensor, units: Tensor | None = None) -> Tensor:
        """(U', B) float: 1 where row position rows[i, b] of unit units[i] (default: every unit in
        order) is not in one of its chosen presses chosen[i]."""
        press = self.press if units is None else self.press[units]
        of = press.gather(1, rows)
        return (of[:, :, None] != chosen[:, None, :]).all(-1).float()


def inner_rates(model: AdaptedMLP, recipe: EpisodeRecipe) -> dict[str, Tensor]:
    """log step size per adapter tensor, learnable, starting at log(inner_lr)."""
    device = model.weights[0].device
    return {k: torch.tensor(math.log(recipe.inner_lr), device=device, requires_grad=True)
            for k in model.adapter.keys()}


def episode_loss(model: AdaptedMLP, X: Tensor, Y: Tensor, index: PressIndex, batch: Tensor,
                 log_lr: dict[str, Tensor], recipe: EpisodeRecipe, generator: torch.Generator) -> Tensor:
    """The mean over units of the query loss after an inner fit on a drawn support (module
    docstring). X (U, N, d_in), Y (U, N, d_out) standardised fitting rows; batch (U, B) row
    positions of this step's joint batch (the query, outside the support presses). With
    `units_per_step`, only that many units, drawn at random, have an episode this step."""
    support, chosen = index.draw(recipe, generator)
    who = torch.arange(X.shape[0], device=X.device)
    if recipe.units_per_step is not None and recipe.units_per_step < X.shape[0]:
        who = torch.randperm(X.shape[0], generator=generator, device=X.device)[: recipe.units_per_step]
    rows_of, support, chosen, batch = who[:, None], support[who], chosen[who], batch[who]
    Xs, Ys = X[rows_of, support], Y[rows_of, support]
    adapter = {k: v.requires_grad_(True) for k, v in model.identity_like(len(who)).items()}
    for _ in range(recipe.inner_steps):
        loss = ((model.forward_with(Xs, adapter) - Ys) ** 2).mean(dim=(1, 2)).sum()
        grads = torch.autograd.grad(loss, list(adapter.values()), create_graph=True)
        adapter = {k: v - log_lr[k].exp() * g for (k, v), g in zip(adapter.items(), grads, strict=True)}
    keep = index.outside(batch, chosen, who)
    err = ((model.forward_with(X[rows_of, batch], adapter) - Y[rows_of, batch]) ** 2).mean(-1)
    return ((err * keep).sum(1) / keep.sum(1).clamp_min(1.0)).mean()


def inner_fit(model: AdaptedMLP, X: Tensor, Y: Tensor, n: Tensor, rates: dict[str, float], steps: int,
              penalty: Callable[[], Tensor] | None = None) -> None:
    """Fit model's M adapters in place by the inner loop episodic training learnt: `steps`
    full-batch gradient steps on each model's first n[m] rows of X (M, N, d_in), Y (M, N, d_out)
    (standardised), each adapter tensor with its step size in `rates`; `penalty()` (M,) is
    added to each model's loss where given. Models with n[m] == 0 keep their adapter."""
    missing = sorted(set(model.adapter.keys()) - set(rates))
    if missing:
        raise AnytipError(f"the inner fit has no step size for adapter tensor(s) {missing}; it fits the "
                          "adapter kind the shared model was trained with")
    mask = (torch.arange(X.shape[1], device=X.device)[None] < n[:, None]).float()
    count = mask.sum(1).clamp_min(1.0)
    params = model.adapter_parameters()
    for _ in range(steps):
        loss = (((model(X) - Y) ** 2).mean(-1) * mask).sum(1) / count
        if penalty is not None:
            loss = loss + penalty()
        grads = torch.autograd.grad((loss * (n > 0).float()).sum(), params)
        with torch.no_grad():
            for (k, p), g in zip(model.adapter.items(), grads, strict=True):
                p.sub_(rates[k] * g)
