"""Calibration by response transfer: a new unit's own network trained on the training units' rows,
carried over to the new unit through a fleet response model (models/response.py).

1. `train_response`: the response network and every training unit's codes, jointly, every
   unit's rows in every step (pressure MSE, a small decay on the codes).
2. `fit_codes`: a new unit's codes from its calibration rows, the network frozen: the MAP
   estimate under a Gaussian prior learnt from the training units' codes (`train.code_prior`), with the
   training units' residual variance as the noise and the plan's effective sample count as
   the number of independent rows. Each barometer's pressure depends on its own code alone,
   so the estimate is C small least-squares problems of k numbers, solved by Gauss-Newton
   with Levenberg-Marquardt damping (`code_fit: gauss_newton`) or by Adam (`adam`, the
   first recipe, which response models saved before the choice existed were run with).
3. `transfer`: each source row of training unit t, (x, y), becomes a row of the new unit u:
   (x + G(y; z_u) - G(y; z_t), y). The training unit's own deviations from its response
   (rig positioning error, relaxation, hysteresis, drift, noise) are kept; only the
   difference between the two units' responses is added.
4. `calibrate_by_response`: each new unit's network of the deployed shape, trained on its
   transferred rows and its own calibration rows (every unit one model of a batched fleet,
   `train.fleet.train_fleet`). What is deployed is that plain network: nothing to fold.

The response network is learnt from the registry's training units alone; nothing here
assumes the project's simulator.
Shapes: U training units, M new-unit jobs, C barometers, D label columns, k code_dim.
"""

from __future__ import annotations

import hashlib
import json
import time
from collections.abc import Callable, Hashable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
import torch
from torch import Tensor

from anytip.data.arrays import OUTPUT_NAMES, FleetArrays
from anytip.data.plans import CRITERIA, CodeInformation, Presses
from anytip.data.seeds import unit_seed
from anytip.models.io import LoadedModels, LoadedResponse
from anytip.models.mlp import MLPConfig
from anytip.models.response import ResponseConfig, ResponseModel
from anytip.train.code_prior import CODE_PRIORS, CodePrior, code_prior
from anytip.train.data import FleetBatchData, UnitSampler, UnitTensors, pad_rows
from anytip.train.fleet import FitResult, ProgressBar, joined_fits, train_fleet
from anytip.train.recipe import FAST, TrainRecipe, lr_at, set_lr

CODE_FITS = ("gauss_newton", "adam")  # how a new unit's codes are fitted (fit_codes)
# whose rows a new unit's network is trained on: every unit the response model was trained on, or
# the registry's own training units only (not the `extra_units` that helped train the response model)
TRANSFER_FROM = ("all", "registry")
# where a new unit's network starts: random weights, or the network of the source rows pooled
INVERSE_STARTS = ("scratch", "pooled")
# what the plan's residual correction does with each barometer's mean residual over the plan where the unit's
# codes were not fitted on the plan alone (given: the joint fit with ordinary use): keeps it (entry 101), or
# takes it out, so that the plan session's own offset against those codes reaches no transferred row
# (`centred`; research log entries 130-131)
RESIDUAL_LEVELS = ("kept", "centred")
RESPONSE_VAL_FRACTION = 0.1  # of a new unit's transferred rows: its network's early stopping


@dataclass(frozen=True)
class ResponseRecipe:
    """How the response model is trained (`steps` Adam steps of `rows_per_step` rows over all
    training units, one-cycle at peak `lr`, `code_decay` on the training codes), how a new
    unit's codes are fitted (`code_fit`: `gauss_newton`, at most `code_iterations` damped
    Gauss-Newton steps on `code_rows` rows evenly spaced over the plan, each barometer's problem
    stopping once a step moves its loss by less than `code_tolerance` of it (0: never; research log
    entry 99); or `adam`, `code_steps` Adam steps of
    `code_rows` random rows at `code_lr`), how many rows of each training unit are transferred
    (`source_rows`) and from which units (`transfer_from`: every unit that trained the response
    model, or the registry's own training units), and how the new unit's network trains on them
    (`inverse_epochs` of the fast recipe in batches of `inverse_batch` rows at peak `inverse_lr`,
    from random weights, `inverse_start: scratch`, or from one network trained on the source rows
    as they were measured, `pooled`: `start_network`). `code_prior`: the prior a new unit's codes are
    fitted under (`train.code_prior`; a model saved before the choice existed ran `diagonal`).
    `plan_criterion`: what an `informative` plan maximises (`data.plans.CodeInformation`).
    `code_draw_scale`: where a unit's codes are fitted on its plan alone, each transferred row's codes
    are drawn from their Laplace posterior with its covariance times this (`code_covariance`,
    `drawn_codes`; 0, the default: every row the MAP codes; research log entry 94).
    `residual_length` > 0: each transferred row also carries the unit's own misfit at its contact, as
    a Gaussian process learns it from the plan's residuals (`plan_correction`: kernel length
    `residual_length` in standard deviations of the contact, noise-to-signal `residual_ratio`, at most
    `residual_rows` plan rows; 0, the default: none; research log entry 101). `residual_level`: where
    the unit's codes are given (fitted with its ordinary use), the correction learns from the plan's residuals
    as they are (`kept`) or less each barometer's mean (`centred`, `RESIDUAL_LEVELS`)."""

    steps: int = 5000
    rows_per_step: int = 4096
    lr: float = 3e-3
    warmup_frac: float = 0.1
    code_decay: float = 1e-3
    code_fit: str = "gauss_newton"
    code_prior: str = "diagonal"
    plan_criterion: str = "v"
    code_draw_scale: float = 0.0
    code_iterations: int = 10
    code_tolerance: float = 0.0
    code_steps: int = 300
    code_rows: int = 2048
    code_lr: float = 3e-2
    residual_length: float = 0.0
    residual_ratio: float = 1.0
    residual_rows: int = 1024
    residual_level: str = "centred"
    source_rows: int = 8000
    transfer_from: str = "all"
    inverse_epochs: int = 40
    inverse_batch: int = 256
    inverse_lr: float = FAST.lr
    inverse_start: str = "scratch"

    @classmethod
    def from_saved(cls, saved: dict[str, Any]) -> ResponseRecipe:
        """The recipe a saved response model records (unknown keys ignored). A model saved before a
        choice existed ran its first value: Adam codes (`code_fit`), batches of 256 rows, the plan's
        mean residual kept in its correction (`residual_level`)."""
        known = {k: v for k, v in saved.items() if k in cls.__dataclass_fields__}
        recipe = cls(**({"code_fit": "adam", "inverse_batch": 256, "residual_level": "kept"} | known))
        for key, default in asdict(cls()).items():
            value = getattr(recipe, key)
            kind = float if isinstance(default, float) else type(default)
            typed = isinstance(value, kind) or (kind is float and isinstance(value, int))
            ok = typed and not isinstance(value, bool)
            if not ok or (kind is int and value < 1) or (kind is float and not value >= 0):
                raise ValueError(f"recipe.{key}: {value!r} is not a {'positive ' if kind is int else ''}"
                                 f"{kind.__name__}")
        if recipe.residual_ratio <= 0:
            raise ValueError(f"recipe.residual_ratio: {recipe.residual_ratio!r} is not a positive float")
        choices = {"code_fit": CODE_FITS, "code_prior": CODE_PRIORS, "plan_criterion": CRITERIA,
                   "inverse_start": INVERSE_STARTS, "residual_level": RESIDUAL_LEVELS,
                   "transfer_from": TRANSFER_FROM}
        for key, allowed in choices.items():
            if (value := getattr(recipe, key)) not in allowed:
                raise ValueError(f"recipe.{key}: {value!r} is not one of {', '.join(allowed)}")
        return recipe


@dataclass
class ResponseFit:
    """A trained response model with what a new unit's code fit needs: noise_var (C,) Pa^2, the
    training units' residual variance per barometer on their validation rows; code_var (k,), the
    spread of their codes per code dimension."""

    model: ResponseModel
    noise_var: Tensor
    code_var: Tensor
    unit_ids: list[str]
    wall_s: float = 0.0
    prior: CodePrior | None = None  # a new unit's code prior; None: the diagonal prior of code_var

    @property
    def device(self) -> torch.device:
        return self.model.codes.device

    @property
    def code_prior(self) -> CodePrior:
        """The prior a new unit's codes are fitted under (`with_code_prior`), on the model's device."""
        prior = self.prior or code_prior("diagonal", self.model.codes, self.code_var)
        return prior.to(self.device)

    def with_code_prior(self, kind: str, registry_units: Sequence[str] = ()) -> ResponseFit:
        """This model with the code prior `kind` (`train.code_prior.CODE_PRIORS`) learnt from its
        training units' codes; `registry_units`: the registry's own units among them (the
        `registry` prior's)."""
        mine = set(registry_units)
        registry = [i for i, u in enumerate(self.unit_ids) if u in mine]
        prior = code_prior(kind, self.model.codes.detach(), self.code_var, registry)
        return replace(self, prior=prior)

    @classmethod
    def from_loaded(cls, loaded: LoadedResponse) -> ResponseFit:
        """A saved response model (`models.io.load_response`), its training units and training time
        from its metadata."""
        units = [str(u) for u in loaded.meta.get("unit_ids", [])]
        wall = loaded.meta.get("wall_s", 0.0)
        wall_s = float(wall) if isinstance(wall, int | float) and not isinstance(wall, bool) else 0.0
        return cls(loaded.model, loaded.noise_var, loaded.code_var, units, wall_s)


TRAINING_FIELDS = ("steps", "rows_per_step", "lr", "warmup_frac", "code_decay")  # what train_response reads


def training_digest(data: FleetBatchData, force_cols: list[int], config: ResponseConfig,
                    recipe: ResponseRecipe, seed: int) -> str:
    """SHA-256 (hex) of everything `train_response` depends on: the units' rows and their ids,
    the force columns, the network's shape, the recipe's training fields and the seed. Two
    trainings with the same digest give the same model on the same device, so a model saved
    under it can stand in for training it again."""
    h = hashlib.sha256()
    settings = {"units": list(data.unit_ids), "force_cols": [int(c) for c in force_cols],
                "config": config.to_json(), "seed": seed,
                "recipe": {k: getattr(recipe, k) for k in TRAINING_FIELDS}}
    h.update(json.dumps(settings, sort_keys=True).encode())
    for t in (data.X_train, data.Y_train, data.n_train, data.X_val, data.Y_val, data.n_val):
        h.update(str((tuple(t.shape), t.dtype)).encode())
        h.update(np.ascontiguousarray(t.detach().cpu().numpy()).data)  # no copy on the CPU
    return h.hexdigest()


def train_response(data: FleetBatchData, force_cols: list[int], config: ResponseConfig | None = None,
                   recipe: ResponseRecipe = ResponseRecipe(), seed: int = 0,
                   device: torch.device | str | None = None, progress: bool = False) -> ResponseFit:
    """The response network and the training units' codes from their fitting rows (physical
    units), scored on their validation rows for the noise variance."""
    start = time.perf_counter()
    config = config or ResponseConfig()
    device = torch.device(device) if device is not None else data.device
    data = data.to(device)
    U, C, D = data.n_units, data.X_train.shape[2], data.Y_train.shape[2]
    model = ResponseModel(U, C, D, force_cols, config, seed).to(device)
    rows = [data.unit(u) for u in range(U)]
    model.set_scales(torch.cat([r.Y_train for r in rows]), torch.cat([r.X_train for r in rows]))
    scale = model.pressure_scale
    opt = torch.optim.Adam(model.parameters(), lr=recipe.lr)
    schedule = TrainRecipe(name="response", lr=recipe.lr, schedule="onecycle", warmup_frac=recipe.warmup_frac,
                           final_lr_frac=0.01)
    sampler = UnitSampler(data.n_train, max(1, recipe.rows_per_step // U), seed, device)
    rows_of = torch.arange(U, device=device)[:, None]
    bar = ProgressBar(progress, recipe.steps, f"response model over {U} units")
    for step, idx in sampler.steps(recipe.steps):
        set_lr(opt, lr_at(step, recipe.steps, schedule))
        pred = model(data.Y_train[rows_of, idx], model.codes[:, None])
        loss = (((pred - data.X_train[rows_of, idx]) / scale) ** 2).mean()
        loss = loss + recipe.code_decay * model.codes.pow(2).mean()
        opt.zero_grad(set_to_none=True)
        loss.backward()
        opt.step()
        bar.update(step + 1)
    bar.close()
    model.eval()
    with torch.no_grad():
        resid = [(model(r.Y_val, model.codes[u]) - r.X_val).pow(2) for u, r in enumerate(rows)]
        noise_var = torch.cat(resid).mean(0).clamp_min(1e-12)
        code_var = model.codes.var(0).mean(0).clamp_min(1e-8) if U > 1 else torch.ones(config.code_dim,
                                                                                       device=device)
    return ResponseFit(model, noise_var, code_var, list(data.unit_ids), time.perf_counter() - start)


@contextmanager
def frozen(model: torch.nn.Module) -> Iterator[None]:
    """The model's weights without grad while the block runs (only its inputs' derivatives are
    taken, as a code fit needs), given it back after."""
    for p in model.parameters():
        p.requires_grad_(False)
    try:
        yield
    finally:
        for p in model.parameters():
            p.requires_grad_(True)


CODE_JOBS_PER_PASS = 16  # new units whose Gauss-Newton step runs in one pass (bounds memory)


def fit_codes(fit: ResponseFit, X: list[Tensor], Y: list[Tensor], n_effective: list[float],
              recipe: ResponseRecipe = ResponseRecipe(), seed: int = 0) -> Tensor:
    """(M, C, k) MAP codes of M jobs, each its calibration rows X (n_m, C) Pa, Y (n_m, D), worth
    n_effective[m] independent rows. The loss of job m is n_eff / 2 times the mean over rows of
    sum_c (x_c - G_c)^2 / noise_var_c, plus the code prior's penalty (`fit.code_prior`; the
    diagonal prior's is sum (z^2 / code_var) / 2). A job without rows keeps the prior's mean (the
    fleet's typical unit). `recipe.code_fit` picks the solver."""
    if recipe.code_fit not in CODE_FITS:
        raise ValueError(f"code_fit {recipe.code_fit!r}: expected one of {', '.join(CODE_FITS)}")
    M = len(X)
    has_rows = torch.tensor([len(x) > 0 for x in X], device=fit.device)
    typical = fit.code_prior.mean.expand(M, -1, -1)
    codes = typical.clone()
    if not bool(has_rows.any()):
        return codes
    with frozen(fit.model):
        if recipe.code_fit == "adam":
            codes = _codes_by_adam(fit, X, Y, n_effective, recipe, seed)
        else:
            for a in range(0, M, CODE_JOBS_PER_PASS):
                part = slice(a, a + CODE_JOBS_PER_PASS)
                codes[part] = _codes_by_gauss_newton(fit, X[part], Y[part], n_effective[part], recipe)
    return torch.where(has_rows[:, None, None], codes, typical)


def evenly_spaced(n: int, at_most: int) -> Tensor:
    """Indices of at most `at_most` of n rows, evenly spaced (all of them when n <= at_most)."""
    if n <= at_most:
        return torch.arange(n)
    return torch.linspace(0, n - 1, at_most).round().long()


class _PlanProblem(NamedTuple):
    """M jobs' code-fit problem on at most `code_rows` evenly spaced rows each: pressures Xp
    (M, B, C) Pa, labels Yp (M, B, D), each job's row weight per barometer row_w (M, 1, C) 1/Pa^2,
    and each job's number of rows n (M ints; 1 for a job without rows, its one zero row, weighed 0).

    Each job's sums over its rows run on its own rows alone, one job at a time: a sum over a batch
    padded to another job's rows, or a contraction batched over another number of jobs, may take
    another kernel and round otherwise (seen on AVX-512 cores), and a job's codes must not depend
    on the jobs fitted beside it."""

    Xp: Tensor
    Yp: Tensor
    row_w: Tensor
    n: list[int]

    def loss(self, fit: ResponseFit, codes: Tensor) -> Tensor:
        """(M, C): each (job, barometer) problem's loss at codes (M, C, k)."""
        with torch.no_grad():
            err = self.row_w * (self.Xp - fit.model(self.Yp, codes[:, None])) ** 2
            own = torch.stack([err[m, :n].sum(0) for m, n in enumerate(self.n)])
            return own / 2 + fit.code_prior.penalty(codes)

    def system(self, fit: ResponseFit, codes: Tensor) -> tuple[Tensor, Tensor]:
        """The Gauss-Newton Hessian (M, C, k, k) of the loss at codes (M, C, k), and minus its
        gradient (M, C, k)."""
        pred, J = code_jacobian(fit.model, self.Yp, codes[:, None])  # J (M, B, C, k)
        JW, r = J * self.row_w[..., None], self.Xp - pred
        H = torch.stack([torch.einsum("bck,bcj->ckj", JW[m, :n], J[m, :n]) for m, n in enumerate(self.n)])
        g = torch.stack([torch.einsum("bck,bc->ck", JW[m, :n], r[m, :n]) for m, n in enumerate(self.n)])
        return H + fit.code_prior.precision, g + fit.code_prior.pull(codes)


def _plan_problem(fit: ResponseFit, X: list[Tensor], Y: list[Tensor], n_effective: list[float],
                  recipe: ResponseRecipe) -> _PlanProblem:
    """The code-fit problem of jobs X[m] (n_m, C) Pa, Y[m] (n_m, D), worth n_effective[m] rows:
    n_eff / n of each taken row's squared error over the barometer's noise variance."""
    model, device = fit.model, fit.device
    take = [evenly_spaced(len(x), recipe.code_rows) for x in X]
    Xp, n = pad_rows([x[t] if len(x) else x.new_zeros(1, model.n_channels)
                      for x, t in zip(X, take, strict=True)], device)
    Yp, _ = pad_rows([y[t] if len(y) else y.new_zeros(1, Y[0].shape[-1])
                      for y, t in zip(Y, take, strict=True)], device)
    has = torch.tensor([len(x) > 0 for x in X], device=device)
    weight = torch.tensor(n_effective, dtype=torch.float32, device=device) * has / n  # per row
    row_w = weight[:, None, None] / fit.noise_var.to(device)  # (M, 1, C): padded rows are never summed
    return _PlanProblem(Xp, Yp, row_w, n.tolist())


def _codes_by_gauss_newton(fit: ResponseFit, X: list[Tensor], Y: list[Tensor], n_effective: list[float],
                           recipe: ResponseRecipe) -> Tensor:
    """(M, C, k) MAP codes by damped Gauss-Newton on `code_rows` evenly spaced rows of each job.

    Pressure c depends on code c alone, so every row's Jacobian (M, n, C, k) comes from one
    backward pass (`code_jacobian`); each (job, barometer) then takes a Levenberg-Marquardt step of
    k numbers, kept where it lowers that problem's loss (the damping shrinks after a kept step and
    grows after a refused one). A problem whose step, kept or refused, moved its loss by less than
    `recipe.code_tolerance` of it stops there (its codes do not depend on the other jobs of the
    pass); the fit ends when every problem has, or after `recipe.code_iterations` steps."""
    problem = _plan_problem(fit, X, Y, n_effective, recipe)
    M, C, k = len(X), fit.model.n_channels, fit.model.config.code_dim
    codes = fit.code_prior.mean.expand(M, C, k).clone()
    damping = torch.full((M, C), 1e-2, device=fit.device)
    done = torch.zeros((M, C), dtype=torch.bool, device=fit.device)
    loss = problem.loss(fit, codes)
    for _ in range(recipe.code_iterations):
        H, g = problem.system(fit, codes)
        diag = torch.diagonal(H, dim1=-2, dim2=-1)
        damped = H + torch.diag_embed(damping[..., None] * diag)
        step = torch.linalg.solve(damped, g.unsqueeze(-1)).squeeze(-1)
        trial = problem.loss(fit, codes + step)
        kept = (trial < loss) & ~done
        codes = torch.where(kept[..., None], codes + step, codes)
        done |= (trial - loss).abs() < recipe.code_tolerance * loss  # a refused step at the optimum too
        loss = torch.where(kept, trial, loss)
        damping = torch.where(kept, damping / 3, damping * 4).clamp(1e-6, 1e6)
        if bool(done.all()):
            break
    return codes


def code_covariance(fit: ResponseFit, X: list[Tensor], Y: list[Tensor], n_effective: list[float],
                    codes: Tensor, recipe: ResponseRecipe = ResponseRecipe()) -> Tensor:
    """(M, C, k, k): the Laplace covariance of M jobs' codes (M, C, k) fitted on their plans (X[m]
    (n_m, C) Pa, Y[m] (n_m, D), worth n_effective[m] rows; `fit_codes`): the inverse of the
    Gauss-Newton Hessian of that fit's loss at the codes, on the same rows. A job without rows gets
    the prior's covariance."""
    M = len(X)
    out = torch.linalg.inv(fit.code_prior.precision).expand(M, -1, -1, -1).clone()
    with frozen(fit.model):
        for a in range(0, M, CODE_JOBS_PER_PASS):
            part = slice(a, a + CODE_JOBS_PER_PASS)
            H, _ = _plan_problem(fit, X[part], Y[part], n_effective[part], recipe).system(
                fit, codes[part].to(fit.device))
            has = torch.tensor([len(x) > 0 for x in X[part]], device=fit.device)
            out[part] = torch.where(has[:, None, None, None], torch.linalg.inv(H), out[part])
    return out


def drawn_codes(codes: Tensor, covariance: Tensor, scale: float, n: int, seed: int) -> Tensor:
    """(n, C, k): n draws of one job's codes from N(codes (C, k), scale * covariance (C, k, k)), one
    per transferred row (`ResponseRecipe.code_draw_scale`)."""
    g = torch.Generator(device=codes.device).manual_seed(seed)
    L = torch.linalg.cholesky(covariance * scale)
    eps = torch.randn((n, *codes.shape), generator=g, device=codes.device, dtype=codes.dtype)
    return codes + torch.einsum("ckj,ncj->nck", L, eps)


def code_jacobian(model: ResponseModel, labels: Tensor, codes: Tensor) -> tuple[Tensor, Tensor]:
    """At labels (*, D) and codes broadcastable to (*, C, k): the pressures (*, C) Pa and each one's
    derivative in its own barometer's code, d pressure_c / d code_c (*, C, k), detached
    (`ResponseModel.jacobians`)."""
    pressure, _, d_code = model.jacobians(labels, codes)
    return pressure, d_code


def _codes_by_adam(fit: ResponseFit, X: list[Tensor], Y: list[Tensor], n_effective: list[float],
                   recipe: ResponseRecipe, seed: int) -> Tensor:
    """(M, C, k) MAP codes by `code_steps` Adam steps of `code_rows` random rows of each job."""
    device, model = fit.device, fit.model
    M, C, k = len(X), model.n_channels, model.config.code_dim
    prior = fit.code_prior
    codes = prior.mean.expand(M, C, k).clone().requires_grad_(True)
    n = torch.tensor([len(x) for x in X], device=device)
    Xp, _ = pad_rows([x if len(x) else x.new_zeros(1, C) for x in X], device)
    Yp, _ = pad_rows([y if len(y) else y.new_zeros(1, Y[0].shape[-1]) for y in Y], device)
    weight = torch.tensor(n_effective, dtype=torch.float32, device=device) * (n > 0)
    sampler = UnitSampler(n.clamp_min(1), min(recipe.code_rows, int(n.max())), seed, device)
    rows_of = torch.arange(M, device=device)[:, None]
    opt = torch.optim.Adam([codes], lr=recipe.code_lr)
    schedule = TrainRecipe(name="codes", lr=recipe.code_lr, schedule="cosine", final_lr_frac=0.05)
    noise = fit.noise_var.to(device)
    for step, idx in sampler.steps(recipe.code_steps):
        set_lr(opt, lr_at(step, recipe.code_steps, schedule))
        err = (model(Yp[rows_of, idx], codes[:, None]) - Xp[rows_of, idx]).pow(2) / noise  # (M, B, C)
        loss = (weight * err.mean(1).sum(-1)).sum() / 2 + prior.penalty(codes).sum()
        opt.zero_grad(set_to_none=True)
        loss.backward()
        opt.step()
    return codes.detach()


@dataclass
class SourceRows:
    """Rows of the training units to transfer: X (S, C) Pa, Y (S, D), unit (S,) index into the
    response model's training units, fitted (S, C) Pa the unit's own response G(y; z_unit)."""

    X: Tensor
    Y: Tensor
    unit: Tensor
    fitted: Tensor


def source_rows(fit: ResponseFit, data: FleetBatchData, per_unit: int, seed: int = 0) -> SourceRows:
    """`per_unit` random fitting rows of each unit of `data` (`draw_source_rows`), with their own
    response (`own_response`)."""
    src = draw_source_rows(fit, data, per_unit, seed)
    src.fitted = own_response(fit, src)
    return src


def draw_source_rows(fit: ResponseFit, data: FleetBatchData, per_unit: int, seed: int = 0) -> SourceRows:
    """`per_unit` random fitting rows of each unit of `data` (units the response model was trained
    on, found by id; in the model's order, all of them or some), their own response not yet
    computed (`fitted` empty)."""
    device = fit.device
    missing = [u for u in data.unit_ids if u not in fit.unit_ids]
    if missing:
        raise ValueError(f"units {', '.join(missing[:4])} did not train the response model: no codes to "
                         "transfer their rows with")
    X, Y, unit = [], [], []
    for k in range(data.n_units):
        r, u = data.unit(k), fit.unit_ids.index(data.unit_ids[k])
        g = torch.Generator().manual_seed(unit_seed(seed, u, "response source rows"))
        take = torch.randperm(len(r.X_train), generator=g)[:per_unit].to(r.X_train.device)
        X.append(r.X_train[take].to(device))
        Y.append(r.Y_train[take].to(device))
        unit.append(torch.full((len(take),), u, dtype=torch.int64, device=device))
    return SourceRows(torch.cat(X), torch.cat(Y), torch.cat(unit), torch.empty(0, fit.model.n_channels))


def own_response(fit: ResponseFit, source: SourceRows) -> Tensor:
    """(S, C) Pa: each source row's response under its own unit's code, G(y; z_unit)."""
    return respond(fit.model, source.Y, fit.model.codes.detach()[source.unit])


def source_digest(fit: ResponseFit, source: SourceRows) -> str:
    """SHA-256 (hex) of what `own_response` computes from: the response model's weights, buffers and
    codes, and the source rows (X, Y, unit). Equal digests give equal responses on the same
    device, so responses saved under one can stand in for computing them again."""
    h = hashlib.sha256()
    rows = [("X", source.X), ("Y", source.Y), ("unit", source.unit)]
    tensors = sorted(fit.model.state_dict().items()) + rows
    for name, t in tensors:
        h.update(f"{name}{tuple(t.shape)}{t.dtype}".encode())
        h.update(np.ascontiguousarray(t.detach().cpu().numpy()).data)
    return h.hexdigest()


def source_response_path(response_path: Path) -> Path:
    """Where `anytip calibrate` keeps a response model's own responses to the source rows it last
    drew: beside it, `<stem>_source.safetensors`."""
    return response_path.with_name(response_path.name.removesuffix(".safetensors") + "_source.safetensors")


@torch.no_grad()
def respond(model: ResponseModel, labels: Tensor, codes: Tensor, chunk: int = 256) -> Tensor:
    """(n, C) Pa: the response to labels (n, D) with codes (n, C, k) or (C, k), in chunks (256 rows:
    the hidden layers' activations of a chunk then stay in a CPU core's cache, 10-15% faster than
    1024 rows; every row's result is the same either way)."""
    model.eval()
    out = []
    for a in range(0, len(labels), chunk):
        z = codes if codes.dim() == 2 else codes[a:a + chunk]
        out.append(model(labels[a:a + chunk], z))
    return torch.cat(out) if out else labels.new_zeros(0, model.n_channels)


def transfer(fit: ResponseFit, source: SourceRows, codes: Tensor) -> Tensor:
    """(S, C) Pa: the source rows as the unit of `codes` (C, k), or each row's codes (S, C, k), would
    have read them."""
    return source.X + respond(fit.model, source.Y, codes.to(fit.device)) - source.fitted


RESIDUAL_CHUNK = 8192  # query rows per kernel block in `plan_correction` (bounds memory)


class PlanMisfit(NamedTuple):
    """The plan's misfit as `plan_correction` learns it: its contacts standardised (n, D) and the Gaussian
    process's weights (n, C) through them, float64, and the standardisation's mean and std (D,)."""

    points: Tensor
    weights: Tensor
    mean: Tensor
    std: Tensor


def plan_misfit(fit: ResponseFit, X: Tensor, Y: Tensor, codes: Tensor, scale: tuple[Tensor, Tensor],
                recipe: ResponseRecipe, centred: bool = False) -> PlanMisfit:
    """What `plan_correction` learns from a unit's plan: a zero-mean Gaussian process per barometer
    through the plan's residuals about the unit's response with `codes` (C, k) at its rows X (n, C) Pa,
    Y (n, D), on at most `recipe.residual_rows` of them evenly spaced (less each barometer's mean over
    them where `centred`), solved in float64."""
    take = evenly_spaced(len(Y), recipe.residual_rows).to(Y.device)
    mean, std = (t.to(fit.device, torch.float64) for t in scale)
    points = (Y[take].to(fit.device, torch.float64) - mean) / std
    fitted = respond(fit.model, Y[take].to(fit.device), codes.to(fit.device))
    resid = (X[take].to(fit.device) - fitted).double()
    if centred:
        resid = resid - resid.mean(0)
    noise = recipe.residual_ratio * torch.eye(len(points), dtype=torch.float64, device=fit.device)
    gram = _kernel(points, points, recipe.residual_length) + noise
    return PlanMisfit(points, torch.cholesky_solve(resid, torch.linalg.cholesky(gram)), mean, std)


def _kernel(a: Tensor, p: Tensor, length: float) -> Tensor:
    """(m, n): exp(-|a_i - p_j|^2 / (2 length^2)) of rows a (m, D), p (n, D), in their dtype."""
    # the squared distances as |a|^2 + |p|^2 - 2 a.p, as cdist's own product path computes them,
    # without its root and a square after it; in place: the (chunk, n) block is the correction's
    # whole cost, and each pass allocating another block doubles it
    d2 = torch.addmm(p.pow(2).sum(1), a, p.T, alpha=-2).add_(a.pow(2).sum(1, keepdim=True)).clamp_min_(0)
    return d2.div_(-2 * length**2).exp_()


def plan_correction(fit: ResponseFit, X: Tensor, Y: Tensor, codes: Tensor, queries: Tensor,
                    scale: tuple[Tensor, Tensor], recipe: ResponseRecipe,
                    query_dtype: torch.dtype = torch.float32, centred: bool = False) -> Tensor:
    """(q, C) Pa: a unit's misfit at contacts `queries` (q, D) as its plan tells it: the posterior mean
    of the Gaussian process `plan_misfit` fits to the plan's residuals. Kernel: squared exponential
    of length `recipe.residual_length` over contacts standardised by `scale` (mean, std, each (D,));
    noise variance `recipe.residual_ratio` times the kernel's. Far from every press the correction
    falls to zero (research log entry 101). The query rows' kernel and its product with the weights
    are evaluated in `query_dtype`: float32 takes half of float64's time over the source rows, the
    correction's whole cost (research log entry 109); `tests/test_response.py` bounds the difference.
    `centred`: the process learns the residuals less each barometer's mean (`plan_misfit`)."""
    misfit = plan_misfit(fit, X, Y, codes, scale, recipe, centred)
    near, weights = misfit.points.to(query_dtype), misfit.weights.to(query_dtype)
    out = [_kernel(((queries[a:a + RESIDUAL_CHUNK].to(fit.device, torch.float64) - misfit.mean) / misfit.std)
                   .to(query_dtype), near, recipe.residual_length) @ weights
           for a in range(0, len(queries), RESIDUAL_CHUNK)]
    return torch.cat(out).to(X.dtype) if out else X.new_zeros(0, X.shape[1])


def transferred(fit: ResponseFit, source: SourceRows, codes: Tensor, X: Tensor, Y: Tensor,
                recipe: ResponseRecipe, drawn: Tensor | None = None, centred: bool = False) -> Tensor:
    """(S, C) Pa: the source rows as the unit of `codes` (C, k) would have read them (`transfer`; with
    each row's codes `drawn` (S, C, k) where given), plus the misfit its plan's rows X (n, C) Pa,
    Y (n, D) show about its response with `codes` (`plan_correction`, contacts standardised over the
    source rows, the residuals `centred` or not) where the recipe asks for it."""
    rows = transfer(fit, source, codes if drawn is None else drawn)
    if recipe.residual_length <= 0 or not len(Y):
        return rows
    scale = (source.Y.double().mean(0), source.Y.double().std(0).clamp_min(1e-12))
    return rows + plan_correction(fit, X, Y, codes, source.Y, scale, recipe, centred=centred)


def calibrate_by_response(fit: ResponseFit, source: SourceRows, X: list[Tensor], Y: list[Tensor],
                          n_effective: list[float], shape: MLPConfig,
                          recipe: ResponseRecipe = ResponseRecipe(), seed: int = 0,
                          ids: list[str] | None = None, output_names: tuple[str, ...] = OUTPUT_NAMES,
                          progress: bool = False, start: FitResult | LoadedModels | None = None,
                          codes: Tensor | None = None,
                          extra: Sequence[tuple[Tensor, Tensor] | None] | None = None,
                          groups: Sequence[Hashable] | None = None) -> tuple[FitResult, Tensor]:
    """M new units' plain networks of `shape` and their codes (M, C, k).

    Job m: codes fitted on its calibration rows X[m] (n_m, C) Pa, Y[m] (n_m, D), worth
    n_effective[m] rows (or given as `codes`); its network trained on the transferred source rows
    (each row's codes drawn from their posterior where `recipe.code_draw_scale` > 0 and they are
    fitted here; the plan's correction centred where they are given and `recipe.residual_level` says so),
    its own calibration rows and its `extra[m]` rows (pressures (e, C) Pa, contacts (e, D)) where
    given (`unit_networks`), from `start` (`start_network`) where the recipe's `inverse_start` is
    `pooled`. The jobs of one key of `groups` (one per job; None: one group) train as one batched
    fleet, each group apart, in the order of its first job: a fleet's epoch is as long as its largest
    job's rows (`UnitSampler`), so a job trained beside much larger ones (a 10 s plan beside a 600 s
    plan) would take more steps than `anytip calibrate` gives it alone, and its draws are those of
    its index within its group."""
    if (start is None) != (recipe.inverse_start == "scratch"):
        raise ValueError(f"inverse_start {recipe.inverse_start!r} with{'out' if start is None else ''} "
                         "a start network")
    covariance = None
    centred = codes is not None and recipe.residual_level == "centred"  # codes not the plan's own
    if codes is None:
        codes = fit_codes(fit, X, Y, n_effective, recipe, seed)
        if recipe.code_draw_scale > 0:
            covariance = code_covariance(fit, X, Y, n_effective, codes, recipe)
    more = list(extra) if extra is not None else [None] * len(X)

    def drawn(m: int) -> Tensor | None:
        if covariance is None:
            return None
        return drawn_codes(codes[m].to(fit.device), covariance[m].to(fit.device), recipe.code_draw_scale,
                           len(source.Y), unit_seed(seed, m, "response code draws"))

    def job_rows(m: int) -> tuple[Tensor, Tensor]:
        carried = transferred(fit, source, codes[m], X[m], Y[m], recipe, drawn(m), centred)
        xs, ys = [carried, X[m].to(fit.device)], [source.Y, Y[m].to(fit.device)]
        if more[m] is not None:
            xs.append(more[m][0].to(fit.device))
            ys.append(more[m][1].to(fit.device))
        return torch.cat(xs), torch.cat(ys)

    nets = grouped_networks(job_rows, [None] * len(X) if groups is None else groups, shape, recipe, seed, ids,
                            output_names, fit.device, progress, start)
    return nets, codes


def grouped_networks(job_rows: Callable[[int], tuple[Tensor, Tensor]], groups: Sequence[Hashable],
                     shape: MLPConfig, recipe: ResponseRecipe = ResponseRecipe(), seed: int = 0,
                     ids: list[str] | None = None, output_names: tuple[str, ...] = OUTPUT_NAMES,
                     device: torch.device | str = "cpu", progress: bool = False,
                     start: FitResult | LoadedModels | None = None) -> FitResult:
    """M jobs' plain networks (`unit_networks`), job m on `job_rows(m)` (X (n_m, C) Pa, Y (n_m, D)):
    the jobs of one key of `groups` (one per job) train as one batched fleet, each group apart, in
    the order of its first job, and the result holds job m's network at index m."""
    keys = list(groups)
    parts = []
    for key in dict.fromkeys(keys):
        ms = [m for m, k in enumerate(keys) if k == key]
        mine = None if ids is None else [ids[m] for m in ms]
        nets = unit_networks((job_rows(m) for m in ms), shape, recipe, seed, mine, output_names, device,
                             progress, start)
        parts.append((ms, nets))
    return parts[0][1] if len(parts) == 1 else joined_fits(parts)


def start_network_path(response_path: Path) -> Path:
    """Where a response model's start network is saved: beside it, `<stem>_start.safetensors`."""
    return response_path.with_name(response_path.name.removesuffix(".safetensors") + "_start.safetensors")


def start_network(source: SourceRows, shape: MLPConfig, recipe: ResponseRecipe = ResponseRecipe(),
                  seed: int = 0, output_names: tuple[str, ...] = OUTPUT_NAMES,
                  progress: bool = False) -> FitResult:
    """One plain network of `shape` on every source row as it was measured (the training units
    pooled), trained from random weights as a unit's network is (`unit_networks`, peak lr FAST's):
    where each new unit's network starts under `inverse_start: pooled`. It depends on the
    response model's source rows alone, so a benchmark trains it once per seed and saves it."""
    return unit_networks([(source.X, source.Y)], shape, replace(recipe, inverse_lr=FAST.lr), seed, ["pooled"],
                         output_names, source.X.device, progress)


def unit_networks(rows: Iterable[tuple[Tensor, Tensor]], shape: MLPConfig,
                  recipe: ResponseRecipe = ResponseRecipe(), seed: int = 0, ids: list[str] | None = None,
                  output_names: tuple[str, ...] = OUTPUT_NAMES, device: torch.device | str = "cpu",
                  progress: bool = False, start: FitResult | LoadedModels | None = None) -> FitResult:
    """M plain networks of `shape`, one batched fleet, job m trained on its rows (X (n_m, C) Pa,
    Y (n_m, D)) for `recipe.inverse_epochs` of the fast recipe at peak `recipe.inverse_lr`, from
    random weights or from `start`'s network and scalers; a random RESPONSE_VAL_FRACTION of
    each job's rows validating (keep-best). `rows` may be a generator: each job's rows are then
    made only when its turn comes, and held once, in the padded fleet."""
    members = []
    for m, (xs, ys) in enumerate(rows):
        g = torch.Generator().manual_seed(unit_seed(seed, m, "response validation rows"))
        perm = torch.randperm(len(xs), generator=g)
        n_val = max(1, int(round(RESPONSE_VAL_FRACTION * len(xs))))
        val, train = perm[:n_val], perm[n_val:]
        xs, ys = xs.cpu(), ys.cpu()
        members.append(UnitTensors(xs[train], ys[train], xs[val], ys[val], ids[m] if ids else str(m)))
    data = FleetBatchData.from_units(members, device, output_names)
    del members  # the padded copy is all training needs; a large fleet's rows are held once
    inverse = FAST.model_copy(update={"epochs": recipe.inverse_epochs, "batch_size": recipe.inverse_batch,
                                      "lr": recipe.inverse_lr})
    return train_fleet(data, shape, inverse, seed=seed, device=device, progress=progress, init=start)


def residual_rms(fit: ResponseFit, X: Tensor, Y: Tensor, codes: Tensor) -> np.ndarray:
    """(C,) Pa: RMS of a unit's pressures X (n, C) about its response with `codes` (C, k)."""
    resid = X.to(fit.device) - respond(fit.model, Y.to(fit.device), codes.to(fit.device))
    return resid.pow(2).mean(0).sqrt().cpu().numpy()


def plan_residual(fit: ResponseFit, X: Tensor, Y: Tensor, codes: Tensor) -> float:
    """Pa: RMS over rows and barometers of a unit's pressures X (n, C) about its response with
    `codes` (C, k); the calibration's own check and the benchmark rows' `response_residual_pa`."""
    return float((residual_rms(fit, X, Y, codes) ** 2).mean() ** 0.5)


INFORMATION_ROWS = 8  # rows of a press whose Jacobians stand for it in `press_information`
INFORMATION_CHUNK = 8192  # rows per Jacobian pass (bounds memory)


def press_information(fit: ResponseFit, arrays: FleetArrays, presses: Presses, effective_hz: float,
                      criterion: str = "v") -> CodeInformation:
    """What each of a unit's candidate presses tells its codes under `fit` (an `informative` plan's
    information, `data.plans.CodeInformation`), linearised at the code prior's mean: from the
    press's labels alone (what the rig commands), never its pressures. A press stands by at most
    INFORMATION_ROWS evenly spaced rows and is worth min(rows, contact seconds x `effective_hz`)
    independent rows, as a plan's rows are in `fit_codes`."""
    model, device = fit.model, fit.device
    prior = fit.code_prior
    C, k = model.n_channels, model.config.code_dim
    counts = np.diff(presses.start)
    take = [evenly_spaced(int(n), INFORMATION_ROWS).numpy() for n in counts]
    taken = np.array([len(t) for t in take], np.int64)
    rows = (presses.rows[np.concatenate([presses.start[p] + t for p, t in enumerate(take)])]
            if len(presses) else np.zeros(0, np.int64))
    press_of = torch.from_numpy(np.repeat(np.arange(len(presses)), taken))
    labels = torch.from_numpy(arrays.targets[rows]).to(device)
    noise = fit.noise_var.to(device)
    total = torch.zeros(len(presses), C, k, k, dtype=torch.float64)
    for a in range(0, len(rows), INFORMATION_CHUNK):
        _, J = code_jacobian(model, labels[a:a + INFORMATION_CHUNK], prior.mean)
        outer = torch.einsum("rck,rcj->rckj", J, J) / noise[:, None, None]
        total.index_add_(0, press_of[a:a + INFORMATION_CHUNK], outer.double().cpu())
    mean = total.numpy() / np.maximum(taken, 1)[:, None, None, None]
    n_eff = np.minimum(counts, presses.duration_s * effective_hz)
    region = (mean * counts[:, None, None, None]).sum(0) / max(int(counts.sum()), 1)
    return CodeInformation(mean * n_eff[:, None, None, None], prior.precision.double().cpu().numpy(), region,
                           criterion)
