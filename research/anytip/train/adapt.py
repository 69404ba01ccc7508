"""Fit a shared network across units, and fit new units' adapters from a few samples.

`train_shared`: shared weights and the training units' adapters, jointly, every unit's
rows in every step (loss = mean over units of each unit's MSE on standardised outputs).
`fit_adapters`: the shared weights frozen, one adapter per (unit, budget, prior) model,
all fitted at once; a prior pulls each adapter toward the identity with a weight that
shrinks as the unit's calibration grows (lambda * |adapter - identity|^2 / n).

With `hetero_beta` set, the shared network has heteroscedastic heads (2d outputs: d means,
d log-variances, models/heteroscedastic.py) and both steps minimise beta-NLL instead of
MSE, so a new unit's adapter also sets its predicted scale; it folds like any adapter.
"""

from __future__ import annotations

import copy
import time
from dataclasses import dataclass, field
from typing import Any

import torch
from torch import Tensor

from anytip.data.seeds import unit_seed
from anytip.errors import AnytipError
from anytip.models.adapted import AdaptedMLP
from anytip.models.heteroscedastic import hetero_config, unit_loss
from anytip.models.io import LoadedShared
from anytip.models.mlp import BatchedMLP, MLPConfig
from anytip.models.scaler import Scaler
from anytip.train.adapter_prior import AdapterPrior
from anytip.train.data import FleetBatchData, UnitSampler, pad_rows
from anytip.train.episodic import EpisodeRecipe, PressIndex, episode_loss, inner_fit, inner_rates
from anytip.train.fleet import ProgressBar, _lap
from anytip.train.metrics import evaluate, history_fields, progress_text
from anytip.train.recipe import FAST, TrainRecipe, eval_points, lr_at, make_optimizer, set_lr


@dataclass
class SharedFit:
    """A shared network with the training units' adapters and scalers.

    in_scaler (U, 1, d_in): each training unit's input statistics (label-free);
    out_scaler (1, 1, d_out): one output standardisation for every unit.
    """

    model: AdaptedMLP
    in_scaler: Scaler
    out_scaler: Scaler
    unit_ids: list[str]
    recipe: TrainRecipe
    seed: int
    history: list[dict[str, Any]] = field(default_factory=list)
    wall_s: float = 0.0
    hetero_beta: float | None = None  # heteroscedastic heads trained with this beta-NLL
    inner_lr: dict[str, float] | None = None  # episodic training's learnt step sizes (kept model's)


def mean_head(model: AdaptedMLP, d_out: int):
    """The model's first d_out outputs (the means), for accuracy evaluation."""
    return lambda x: model(x)[..., :d_out]


def input_stats(pressures: list[Tensor], device: torch.device | str = "cpu") -> Scaler:
    """Per-unit input scaler (U, 1, d) from each unit's unlabeled pressures [(n_u, d), ...]."""
    return Scaler(torch.stack([p.double().mean(0, keepdim=True) for p in pressures]).float().to(device),
                  torch.stack([_std_floor(p) for p in pressures]).float().to(device))


def _std_floor(p: Tensor) -> Tensor:
    std = p.double().std(0, unbiased=False, keepdim=True)
    return torch.maximum(std, (1e-6 * std.max()).clamp_min(1e-12))


def train_shared(data: FleetBatchData, in_scaler: Scaler, config: MLPConfig | None = None,
                 kind: str = "none", recipe: TrainRecipe = FAST, seed: int = 0,
                 device: torch.device | str | None = None, progress: bool = False,
                 adapter_decay: float = 0.0, hetero_beta: float | None = None,
                 adapter_dropout: float = 0.0,
                 episodes: tuple[EpisodeRecipe, PressIndex] | None = None) -> SharedFit:
    """Fit the shared weights and each training unit's adapter together.

    data: the training units' rows (physical units); in_scaler: their input statistics,
    (U, 1, d_in) per unit or (1, 1, d_in) pooled. `adapter_decay` adds
    adapter_decay * mean over units of |adapter - identity|^2 to the loss, so the identity
    adapter stays a typical unit (the zero-shot starting point of a new unit). Model
    selection (recipe.keep_best) uses the mean validation loss over units (MSE of the
    means, also for heteroscedastic heads). `hetero_beta` trains heteroscedastic heads
    with that beta-NLL (module docstring). `adapter_dropout` is the chance that a unit's
    adapter is left out (the identity used) in a step, so the shared weights also serve a
    unit whose adapter is not known yet (zero-shot) or poorly fitted. `episodes` adds each
    step's episodic loss (train/episodic.py: an adapter fitted on a few of each unit's presses,
    scored on its other rows of the batch), with the press of every fitting row.
    """
    start = time.perf_counter()
    device = torch.device(device) if device is not None else data.device
    data, in_scaler = data.to(device), in_scaler.to(device)
    U = data.n_units
    out_scaler = Scaler.pooled(data.Y_train, data.n_train)
    X, Y = in_scaler.transform(data.X_train), out_scaler.transform(data.Y_train)
    rows_of = torch.arange(U, device=device)[:, None]
    config = config or MLPConfig()
    d_out = config.sizes[-1]
    model = AdaptedMLP(U, config if hetero_beta is None else hetero_config(config), kind, seed).to(device)
    opt = make_optimizer(model.parameters(), recipe)
    sampler = UnitSampler(data.n_train, recipe.batch_size, seed, device)
    total = recipe.epochs * sampler.steps_per_epoch
    eval_at = eval_points(sampler.steps_per_epoch, recipe.evals_per_epoch)
    drop = None
    if adapter_dropout > 0:
        drop = torch.Generator(device).manual_seed(unit_seed(seed, 0, "adapter dropout"))
    episodic = _episodic(model, episodes, recipe, seed, hetero_beta, device)
    best, best_loss, history, train_s, best_rates = None, float("inf"), [], 0.0, None
    bar = ProgressBar(progress, total, f"shared over {U} units ({kind})")
    tick = time.perf_counter()
    for step, idx in sampler.steps(total):
        set_lr(opt, lr_at(step, total, recipe))
        keep = None if drop is None else torch.rand(U, generator=drop, device=device) >= adapter_dropout
        loss = unit_loss(model(X[rows_of, idx], keep), Y[rows_of, idx], hetero_beta).mean()
        if adapter_decay > 0:
            loss = loss + adapter_decay * model.deviation().mean()
        if episodic is not None:
            set_lr(episodic.opt, lr_at(step, total, recipe))
            loss = loss + episodic.recipe.weight * episode_loss(
                model, X, Y, episodic.index, idx, episodic.log_lr, episodic.recipe, episodic.generator)
            episodic.opt.zero_grad(set_to_none=True)
        opt.zero_grad(set_to_none=True)
        loss.backward()
        opt.step()
        if episodic is not None:
            episodic.opt.step()
        bar.update(step + 1)
        if step % sampler.steps_per_epoch + 1 not in eval_at and step + 1 < total:
            continue
        train_s += _lap(tick, device)
        val = evaluate(mean_head(model.eval(), d_out), in_scaler, out_scaler, data.X_val, data.Y_val,
                       data.n_val)
        model.train()
        history.append({"epoch": (step + 1) / sampler.steps_per_epoch, "step": step + 1,
                        "elapsed_s": train_s, "val_loss": val["loss"].tolist(), **history_fields(val),
                        **({} if episodic is None else {"inner_lr": episodic.rates()})})
        bar.update(step + 1, f"shared ({kind}): {progress_text(val)}")
        if float(val["loss"].mean()) < best_loss:
            best_loss, best = float(val["loss"].mean()), copy.deepcopy(model.state_dict())
            best_rates = None if episodic is None else episodic.rates()
        tick = time.perf_counter()
    bar.close()
    rates = None if episodic is None else episodic.rates()
    if recipe.keep_best and best is not None:
        model.load_state_dict(best)
        rates = best_rates
    return SharedFit(model, in_scaler, out_scaler, list(data.unit_ids), recipe, seed, history,
                     time.perf_counter() - start, hetero_beta, rates)


@dataclass
class _Episodic:
    """Episodic training's state in `train_shared`: the drawn episodes and the learnt step sizes."""

    recipe: EpisodeRecipe
    index: PressIndex
    log_lr: dict[str, Tensor]
    opt: torch.optim.Optimizer
    generator: torch.Generator

    def rates(self) -> dict[str, float]:
        return {k: float(v.detach().exp()) for k, v in self.log_lr.items()}


def _episodic(model: AdaptedMLP, episodes: tuple[EpisodeRecipe, PressIndex] | None, recipe: TrainRecipe,
              seed: int, hetero_beta: float | None, device: torch.device) -> _Episodic | None:
    if episodes is None:
        return None
    if hetero_beta is not None or not model.adapter_parameters():
        raise AnytipError("episodic training needs a shared model with adapters and plain (not "
                          "heteroscedastic) outputs")
    rates = inner_rates(model, episodes[0])
    opt = torch.optim.Adam(rates.values(), lr=recipe.lr)
    return _Episodic(episodes[0], episodes[1].to(device), rates, opt,
                     torch.Generator(device).manual_seed(unit_seed(seed, 0, "episodes")))


# Pull of the training units' adapters toward the identity in `train_shared` (adapter_decay):
# the default of every pipeline that trains a shared model.
ADAPTER_DECAY = 0.01


@dataclass(frozen=True)
class AdapterRecipe:
    """How a new unit's adapter is fitted: Adam steps on its calibration rows; or, with `rates`
    (adapter tensor -> step size, learnt by episodic training), `steps` full-batch gradient
    steps with those step sizes: the inner fit the shared model was trained for."""

    steps: int = 400
    lr: float = 1e-2
    batch_size: int = 256
    rates: dict[str, float] | None = None


def fit_adapters(shared: SharedFit | LoadedShared, X: Tensor, Y: Tensor, n: Tensor, in_scaler: Scaler,
                 prior: Tensor, recipe: AdapterRecipe = AdapterRecipe(), seed: int = 0,
                 kind: str | None = None, n_effective: Tensor | None = None,
                 adapter_prior: AdapterPrior | None = None) -> AdaptedMLP:
    """Adapters for M new models, the shared weights frozen.

    X (M, N, d_in), Y (M, N, d_out) physical calibration rows, the first n[m] real;
    in_scaler (M, 1, d_in) each model's label-free input statistics; prior (M,) lambda.
    `kind` fits another adapter kind than the shared model was trained with (e.g. with
    `+delta` added); new units start at the identity either way. Returns a model with the
    shared weights and the M fitted adapters. n[m] == 0 leaves model m at the identity.
    The prior's weight is lambda / n[m], or lambda / n_effective[m] (M,) where given: the
    calibration's effective sample count (data/plans.py), for rows that are autocorrelated.
    `adapter_prior` (train/adapter_prior.py) sets where the adapters start and what the prior
    measures; None is the identity prior (start at the identity, |adapter - identity|^2).
    A heteroscedastic shared model's adapters are fitted by its beta-NLL.
    """
    device = shared.model.weights[0].device
    hetero_beta = getattr(shared, "hetero_beta", None)
    model = copy.deepcopy(shared.model)
    if kind is not None and kind != model.kind:
        fresh = AdaptedMLP(1, model.config, kind)
        fresh.weights, fresh.biases = model.weights, model.biases
        model = fresh
    model.reset_adapter(X.shape[0])
    model.to(device)
    if adapter_prior is not None:
        if kind is not None and kind != shared.model.kind:
            raise AnytipError(f"an adapter prior learnt for {shared.model.kind!r} adapters cannot "
                              f"fit {kind!r} adapters")
        adapter_prior = adapter_prior.to(device)
        adapter_prior.start(model)
    penalty = model.deviation if adapter_prior is None else (lambda: adapter_prior.penalty(model))
    for p in model.shared_parameters():
        p.requires_grad_(False)
    fit = n > 0
    if not model.adapter_parameters() or not bool(fit.any()):
        return _thaw(model)
    Xs, Ys = in_scaler.to(device).transform(X.to(device)), shared.out_scaler.transform(Y.to(device))
    if recipe.rates is not None:
        count = n.clamp_min(1).to(device).float() if n_effective is None else n_effective.to(device).float()
        weight = prior.to(device).float() / count.clamp_min(1.0)
        inner_fit(model, Xs, Ys, n.to(device), recipe.rates, recipe.steps, lambda: weight * penalty())
        return _thaw(model)
    n_safe = n.clamp_min(1).to(device)
    sampler = UnitSampler(n_safe, min(recipe.batch_size, int(n.max())), seed, device)
    rows_of = torch.arange(X.shape[0], device=device)[:, None]
    weight = fit.to(device).float()
    count = n_safe.float() if n_effective is None else n_effective.to(device).float().clamp_min(1.0)
    prior = prior.to(device).float() / count
    opt = torch.optim.Adam(model.adapter_parameters(), lr=recipe.lr)
    constant = TrainRecipe(name="adapter", lr=recipe.lr, schedule="cosine", final_lr_frac=0.05)
    for step, idx in sampler.steps(recipe.steps):
        set_lr(opt, lr_at(step, recipe.steps, constant))
        fit_loss = unit_loss(model(Xs[rows_of, idx]), Ys[rows_of, idx], hetero_beta)
        loss = (weight * (fit_loss + prior * penalty())).sum()
        opt.zero_grad(set_to_none=True)
        loss.backward()
        opt.step()
    return _thaw(model)


def _thaw(model: AdaptedMLP) -> AdaptedMLP:
    for p in model.shared_parameters():
        p.requires_grad_(True)
    return model


def calibrate_and_fold(shared: SharedFit | LoadedShared, unlabeled: list[Tensor], X: list[Tensor],
                       Y: list[Tensor], n: list[int], priors: list[float],
                       recipe: AdapterRecipe = AdapterRecipe(), seed: int = 0,
                       kind: str | None = None, n_effective: list[float] | None = None,
                       adapter_prior: AdapterPrior | None = None) -> tuple[BatchedMLP, Scaler]:
    """New units' deployable models: M jobs, each a unit's unlabeled pressures (n_u, d_in),
    its labeled rows X (k, d_in), Y (k, d_out) of which the first n[m] are used (0: label-free),
    and a prior (scaled by n_effective[m] instead of n[m] where given). Returns the M folded
    MLPs and their input scalers (M, 1, d_in)."""
    device = shared.model.weights[0].device
    stats = input_stats(unlabeled, device)
    Xp, _ = pad_rows([x if len(x) else x.new_zeros(1, x.shape[1]) for x in X], device)
    Yp, _ = pad_rows([y if len(y) else y.new_zeros(1, y.shape[1]) for y in Y], device)
    counts = torch.tensor(n, device=device)
    effective = None if n_effective is None else torch.tensor(n_effective, dtype=torch.float64)
    adapted = fit_adapters(shared, Xp, Yp, counts, stats, torch.tensor(priors), recipe, seed, kind, effective,
                           adapter_prior)
    return adapted.fold(), stats
