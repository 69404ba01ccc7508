"""The cross_sensor zero-shot method `response:label_free` (`options.response.label_free`): each
validation and held-out unit's response-transfer codes from its pressures in ordinary use alone
(train/label_free.py), its own network trained on the training units' rows carried over by them,
scored on its test patches like every other method (research log entries 37, 38, 40 and 44). The
search and the fit are held to the force scale of the registry's training units' own ordinary use
(`force_scale`, on by default), and the search starts from the codes an encoder learnt across the
response model's units predicts from the unit's pressure statistics (`start: encoder`, the default).
With `with_plans`, every labeled budget is also calibrated with the unit's ordinary use: its codes
from one joint fit of the plan's labeled rows and the ordinary use's unlabeled ones (`response+use`,
entry 45)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import torch
from torch import Tensor

from anytip.data.arrays import FleetArrays
from anytip.data.plans import Budget, Plan, ordinary_use, ordinary_use_seed
from anytip.errors import AnytipError
from anytip.models.scaler import Scaler
from anytip.pipelines.common import Context
from anytip.pipelines.cross_sensor_jobs import UnitLosses, budget_fields, validation_losses
from anytip.pipelines.cross_sensor_options import Options
from anytip.train.code_encoder import CodeEncoder
from anytip.train.fleet import FitResult
from anytip.train.label_free import (
    FleetUse,
    ForceScale,
    Labeled,
    LabelFreeRecipe,
    distilled_rows,
    fleet_code_encoder,
    fleet_force_scale,
    plan_and_use_codes,
    search_draws,
    started_codes,
    use_inputs,
)
from anytip.train.metrics import scores
from anytip.train.response import ResponseFit, SourceRows, transfer, unit_networks
from anytip.train.shared_split import SeedData, predict_rows

METHOD = "response:label_free"


@dataclass(frozen=True)
class OrdinaryUse:
    """What the label-free fits read of the validation and held-out units: per unit the whole presses
    of its ordinary use (`uses`), the fitted rows' pressures X (n, C) Pa and the pooled start
    network's contacts Y0 (n, D) there, and the code encoder's first codes (C, k) or None (`first`);
    the fleet's candidates (S, D) of each of the search's draws (`draws`), and what it learnt for
    reading ordinary use (`fleet`: the recipe, force-scale prior and encoder, saved with the response
    model for `anytip calibrate`)."""

    fleet: FleetUse
    uses: dict[str, Plan]
    X: dict[str, Tensor]
    Y0: dict[str, Tensor]
    first: dict[str, Tensor | None]
    draws: list[Tensor]


def read_ordinary_use(arrays: FleetArrays, sd: SeedData, opts: Options, seed: int, fit: ResponseFit,
                      source: SourceRows, start: FitResult, extra: FleetArrays | None = None) -> OrdinaryUse:
    """Each validation, held-out and factor unit's ordinary use (`options.response.label_free`) and what the
    fleet adds to it. `source`: the rows whose contacts the search draws; `start`: the pooled network
    whose contacts the fits pull each unlabeled row towards; `extra`: the run's extra units, whose
    ordinary use teaches the code encoder with the registry's."""
    assert opts.response is not None and opts.response.label_free is not None
    free = opts.response.label_free.recipe()
    coder = code_encoder(arrays, extra, opts, free, seed, fit)
    uses, X, Y0, first = {}, {}, {}, {}
    for u in [*sd.split.val, *sd.split.test, *sd.split.factor]:
        use = uses[u] = ordinary_use(sd.evals[u].presses, free.seconds, ordinary_use_seed(seed, u))
        X[u], Y0[u], first[u] = use_inputs(arrays.pressure[use.rows], free, start, coder, fit.device)
    fleet = FleetUse(free, opts.rig.effective_hz, force_scale(arrays, sd, opts, free, seed), coder)
    return OrdinaryUse(fleet, uses, X, Y0, first, search_draws(source.Y, free, seed))


def label_free_rows(ctx: Context, arrays: FleetArrays, sd: SeedData, opts: Options, seed: int,
                    fit: ResponseFit, source: SourceRows, start: FitResult, read: OrdinaryUse
                    ) -> tuple[list[dict[str, Any]], UnitLosses | None]:
    """Rows of the held-out units, and each validation unit's standardised MSE (None without
    validation units). `source`: the rows a unit's network trains on once carried over; `start`: the
    pooled network it starts from; `read`: the units' ordinary use (`read_ordinary_use`)."""
    assert opts.response is not None
    recipe, units = opts.response.recipe(), [*sd.split.val, *sd.split.test]
    fleet = read.fleet
    fits = [started_codes(fit, recipe, fleet.free, read.X[u], read.Y0[u], fleet.n_effective(), read.draws,
                          seed, fleet.scale, read.first[u]) for u in units]
    codes = [z for z, _, _ in fits]
    objective = {u: finals for u, (_, _, finals) in zip(units, fits, strict=True)}
    carried = ((transfer(fit, source, z), source.Y) for z in codes)
    nets = unit_networks(carried, ctx.spec.model, recipe, seed, [f"{u}@label_free" for u in units],
                         arrays.output_names, fit.device, ctx.progress, start)
    preds = predict_rows(nets.model, nets.in_scaler, nets.out_scaler, arrays,
                         [sd.evals[u].test_rows for u in units])
    zero = Budget(0.0, opts.budget_unit, opts.plan_strategies[0])
    loss = validation_losses([(u, zero, 0.0) for u in units], preds, sd, arrays, set(sd.split.val),
                             Scaler.pooled(sd.train.Y_train, sd.train.n_train)).get((zero, 0.0))
    said = "codes zero"
    if read.fleet.coder is not None:
        said = f"an encoder's codes (left-out units' R^2 {read.fleet.coder.loo_r2:.2f})"
    ctx.say(f"seed {seed}: {len(units)} units' codes fitted from {read.fleet.free.seconds:g} s of unlabeled "
            f"use, searched from {said}; the fit's objective per draw: "
            + ", ".join(f"{u} {' '.join(f'{v:.6g}' for v in finals)}" for u, finals in objective.items()))
    out = [{"method": METHOD, "unit": u, **budget_fields(zero, Plan.empty()), **use_fields(read.uses[u]),
            "label_free_objectives": objective[u],
            **scores(pred, arrays.targets[sd.evals[u].test_rows], arrays.layout)}
           for u, pred in zip(units, preds, strict=True) if u in sd.split.test]
    return out, loss


def plan_use_codes(fit: ResponseFit, opts: Options, read: OrdinaryUse, seed: int,
                   jobs: list[tuple[str, Plan]], X: list[Tensor], Y: list[Tensor], codes: Tensor
                   ) -> tuple[Tensor, list[Tensor]]:
    """(M, C, k) codes of M labeled jobs (unit, plan) with rows X[m] (n_m, C) Pa, Y[m] (n_m, D), each
    from one joint fit of its plan's rows and its unit's ordinary use (`plan_and_use_codes`, entry 45),
    started from the plan's own codes `codes` (M, C, k); and each job's fitted contacts of its unit's
    unlabeled rows (n_u, D) physical."""
    assert opts.response is not None
    recipe, fleet = opts.response.recipe(), read.fleet
    fits = [plan_and_use_codes(fit, recipe, fleet.free, read.X[u], read.Y0[u], fleet.n_effective(),
                               read.draws[0], seed,
                               Labeled(x.to(fit.device), y.to(fit.device), plan.n_effective), z, fleet.scale)
            for (u, plan), x, y, z in zip(jobs, X, Y, codes, strict=True)]
    return torch.stack([z for z, _ in fits]), [c for _, c in fits]


def use_rows_for(read: OrdinaryUse, arrays: FleetArrays, unit: str, fitted: Tensor
                 ) -> tuple[Tensor, Tensor] | None:
    """The rows `unit`'s ordinary use adds to its network (`distilled_rows`): its fitted rows'
    pressures with their fitted contacts `fitted` (n, D), or their true contacts for `oracle`."""
    free = read.fleet.free
    truth = None
    if free.distil == "oracle":
        rows = read.uses[unit].rows
        truth = torch.from_numpy(arrays.targets[rows[free.read_rows(len(rows))]])
    return distilled_rows(free, read.X[unit], fitted, None if truth is None else truth.to(fitted.device))


def use_fields(use: Plan) -> dict[str, Any]:
    """What a row says of the ordinary use it read: rows and contact seconds (no rig time)."""
    return {"unlabeled_samples": int(len(use.rows)), "unlabeled_seconds": use.contact_seconds}


def code_encoder(arrays: FleetArrays, extra: FleetArrays | None, opts: Options, free: LabelFreeRecipe,
                 seed: int, fit: ResponseFit) -> CodeEncoder | None:
    """The search's code encoder (`fleet_code_encoder`), or None where the recipe `free` starts from
    codes zero or the encoder explains nothing."""
    if free.start != "encoder":
        return None
    sources = [arrays] if extra is None else [arrays, extra]
    return fleet_code_encoder(fit, sources, opts.calibration_protocol, opts.calibration_interleave,
                              free.seconds, seed)


def force_scale(arrays: FleetArrays, sd: SeedData, opts: Options, free: LabelFreeRecipe,
                seed: int) -> ForceScale | None:
    """The fit's force-scale prior from the registry's training units' ordinary use, or None where
    the recipe `free` turns it off or the sensor model has no force target."""
    if not free.force_scale:
        return None
    try:
        return fleet_force_scale(arrays, list(sd.split.train), opts.calibration_protocol,
                                 opts.calibration_interleave, free, seed)
    except ValueError as e:
        raise AnytipError(f"options.response.label_free.force_scale: {e} (false fits without it)") from e
