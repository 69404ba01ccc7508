"""The cross_sensor zero-shot method `response:label_free` (`options.response.label_free`): each
validation and held-out unit's response-transfer codes from its pressures in ordinary use alone
(train/label_free.py), its own network trained on the training units' rows carried over by them,
scored on its test patches like every other method (research log entries 37, 38, 40 and 44). The
search and the fit are held to the force scale of the registry's training units' own ordinary use
(`force_scale`, on by default), and the search starts from the codes an encoder learnt across the
response model's units predicts from the unit's pressure statistics (`start: encoder`, the default)."""

from __future__ import annotations

from typing import Any

import torch

from anytip.data.arrays import FleetArrays
from anytip.data.plans import Budget, Plan, ordinary_use, ordinary_use_seed
from anytip.errors import AnytipError
from anytip.pipelines.common import Context
from anytip.pipelines.cross_sensor_jobs import budget_fields, validation_losses
from anytip.pipelines.cross_sensor_options import Options
from anytip.train.adapt import pooled_scaler
from anytip.train.code_encoder import CodeEncoder, stream_features
from anytip.train.fleet import FitResult
from anytip.train.label_free import (
    ForceScale,
    LabelFreeRecipe,
    fleet_code_encoder,
    fleet_force_scale,
    label_free_codes,
    search_candidates,
)
from anytip.train.metrics import scores
from anytip.train.response import ResponseFit, SourceRows, evenly_spaced, transfer, unit_networks
from anytip.train.shared_split import SeedData, predict_rows

METHOD = "response:label_free"


def label_free_rows(ctx: Context, arrays: FleetArrays, sd: SeedData, opts: Options, seed: int,
                    fit: ResponseFit, source: SourceRows, start: FitResult, extra: FleetArrays | None = None
                    ) -> tuple[list[dict[str, Any]], float | None]:
    """Rows of the held-out units, and the validation units' mean standardised MSE (None without
    validation units). `source`: the rows a unit's network trains on once carried over; `start`: the
    pooled network it starts from, whose contacts the fit pulls each unlabeled row towards; `extra`:
    the run's extra units, whose ordinary use teaches the code encoder with the registry's."""
    assert opts.response is not None and opts.response.label_free is not None
    free, recipe = opts.response.label_free.recipe(), opts.response.recipe()
    units = [*sd.split.val, *sd.split.test]
    candidates = search_candidates(source.Y, free.candidates, seed)
    n_eff = free.seconds * opts.rig.effective_hz
    scale = force_scale(arrays, sd, opts, free, seed)
    coder = code_encoder(arrays, extra, opts, free, seed, fit)
    uses: list[Plan] = []
    codes = []
    for u in units:
        use = ordinary_use(sd.evals[u].presses, free.seconds, ordinary_use_seed(seed, u))
        rows = use.rows[evenly_spaced(len(use.rows), free.rows).numpy()]
        X = torch.from_numpy(arrays.pressure[rows]).to(fit.device)
        Y0 = torch.from_numpy(predict_rows(start.model, start.in_scaler, start.out_scaler, arrays, [rows])[0])
        first = None
        if coder is not None and len(use.rows) > 1:
            first = coder(stream_features(arrays.pressure[use.rows])).to(fit.device)
        z, _, _ = label_free_codes(fit, recipe, free, X, Y0.to(fit.device), n_eff, candidates, seed, scale,
                                   first)
        uses.append(use)
        codes.append(z)
    carried = ((transfer(fit, source, z), source.Y) for z in codes)
    nets = unit_networks(carried, ctx.spec.model, recipe, seed, [f"{u}@label_free" for u in units],
                         arrays.output_names, fit.device, ctx.progress, start)
    preds = predict_rows(nets.model, nets.in_scaler, nets.out_scaler, arrays,
                         [sd.evals[u].test_rows for u in units])
    zero = Budget(0.0, opts.budget_unit, opts.plan_strategies[0])
    loss = validation_losses([(u, zero, 0.0) for u in units], preds, sd, arrays, set(sd.split.val),
                             pooled_scaler(sd.train.Y_train, sd.train.n_train)).get((zero, 0.0))
    said = "codes zero" if coder is None else f"an encoder's codes (left-out units' R^2 {coder.loo_r2:.2f})"
    ctx.say(f"seed {seed}: {len(units)} units' codes fitted from {free.seconds:g} s of unlabeled use, "
            f"searched from {said}")
    out = [{"method": METHOD, "unit": u, **budget_fields(zero, Plan.empty()),
            "unlabeled_samples": int(len(use.rows)), "unlabeled_seconds": use.contact_seconds,
            **scores(pred, arrays.targets[sd.evals[u].test_rows], arrays.layout)}
           for u, use, pred in zip(units, uses, preds, strict=True) if u in sd.split.test]
    return out, None if loss is None else float(sum(loss) / len(loss))


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
