"""Calibration by the shared model's adapter: fitted on the plan as the benchmark fitted adapters, folded
into a plain MLP of the deployed shape, with the plan's out-of-fold own check and intervals."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import torch

from anytip.calibrate.intervals import fleet_factor_for, interval_folds, plan_intervals
from anytip.calibrate.records import own_check_table, prior_for, val_loss_table
from anytip.calibrate.result import OWN_CHECK_ALARM, Calibrated, check_on_other_runs
from anytip.data.arrays import FleetArrays
from anytip.data.calibration import CalibrationStream
from anytip.data.plans import Plan
from anytip.models.io import LoadedShared, save_models
from anytip.models.mlp import BatchedMLP
from anytip.models.scaler import Scaler
from anytip.train.adapt import AdapterRecipe, calibrate_and_fold
from anytip.train.adapter_prior import make_prior
from anytip.train.shared_split import OWN_CHECK_FOLDS, own_check_loss, plan_residuals

Fit = Callable[[np.ndarray, float], tuple[BatchedMLP, Scaler]]


@dataclass
class Fitter:
    """How a new unit's adapter is fitted, as the shared model's benchmark fitted adapters.

    fit(rows, n_effective) -> (folded MLP, input scaler): fitted on `rows`; residuals(plan,
    folds): the plan's out-of-fold residuals (n, D) over that many press folds (one per press
    for a shorter plan; `train.shared_split.plan_residuals`), which give the calibration's own
    check over OWN_CHECK_FOLDS folds, as the benchmark measured it on its validation units, and
    the unit's intervals over the folds its benchmark used for them."""

    fit: Fit
    residuals: Callable[[Plan, int], np.ndarray | None]


def _fitter(shared: LoadedShared, meta: dict[str, Any], arrays: FleetArrays, unlabeled_rows: np.ndarray,
            prior: float) -> Fitter:
    """The unit's `Fitter`: the benchmark's recipe, prior family and strength."""
    recipe = AdapterRecipe(**meta.get("adapter_recipe", {}))
    seed = int(meta.get("seed", 0))
    family = None
    if shared.model.adapter_parameters():
        family = make_prior(meta.get("adapter_prior", "identity"), shared.model,
                            int(meta.get("prior_rank", 4)))
    unlabeled = [torch.from_numpy(arrays.pressure[unlabeled_rows])]

    def fit(rows: np.ndarray, n_effective: float) -> tuple[BatchedMLP, Scaler]:
        X, Y = [torch.from_numpy(arrays.pressure[rows])], [torch.from_numpy(arrays.targets[rows])]
        return calibrate_and_fold(shared, unlabeled, X, Y, [len(rows)], [prior], recipe,
                                  seed=seed, n_effective=[n_effective], adapter_prior=family)

    def residuals(plan: Plan, folds: int) -> np.ndarray | None:
        return plan_residuals(shared, arrays, [unlabeled_rows], [plan], [prior], recipe, seed,
                              adapter_prior=family, folds=folds, fewer=True)[0]
    return Fitter(fit, residuals)


def own_check(loss: float | None, plan: Plan, fleet_loss: float | None,
              validation: list[float] | None) -> dict[str, Any] | None:
    """The calibration's own check (the plan's presses in OWN_CHECK_FOLDS folds, each predicted
    by the adapter refitted without it, standardised MSE over all of them) beside what the
    shared model's benchmark measured:
    the same statistic on its validation units at this budget (`validation`; `over_validation`
    is the ratio to the worst of them, and `alarm` is set above OWN_CHECK_ALARM), and the
    validation units' loss on their test patches (`over_fleet`: other rows, a guide only).
    None for a plan of fewer than 2 presses."""
    if loss is None:
        return None
    out: dict[str, Any] = {"presses": plan.presses, "folds": min(OWN_CHECK_FOLDS, plan.presses),
                           "rows": int(len(plan.rows)), "standardised_mse": loss}
    if fleet_loss is not None:
        out |= {"fleet_validation_mse": fleet_loss, "over_fleet": loss / fleet_loss}
    if validation:
        over = loss / max(validation)
        out |= {"validation_units_mse": validation, "over_validation": over, "alarm": over > OWN_CHECK_ALARM}
    return out


def calibrate_by_adapter_unit(model: tuple[LoadedShared, Path], arrays: FleetArrays,
                              stream: CalibrationStream, plan: Plan, budget: float, out: Path,
                              notes: list[str], interval_level: float | None = 0.9) -> Calibrated:
    """A new unit's adapter fitted on its plan and folded into a plain MLP of the deployed shape, saved in
    the per-unit format with its own check (the plan's presses in OWN_CHECK_FOLDS folds, beside the
    benchmark's validation units) and its intervals from the plan's out-of-fold residuals times the fleet
    factor. `model`: the shared model and its file; `budget`: the key of the benchmark's per-budget
    records (labeled samples or robot seconds, as it budgeted)."""
    shared, shared_path = model
    meta = shared.meta
    n = len(plan.rows)
    prior = prior_for(meta, budget)
    unlabeled_rows = stream.unlabeled(meta.get("unlabeled_s"))
    tick = time.perf_counter()
    fitter = _fitter(shared, meta, arrays, unlabeled_rows, prior)
    folded, stats = fitter.fit(plan.rows, plan.n_effective)
    wall_s = time.perf_counter() - tick
    tick = time.perf_counter()
    resid = fitter.residuals(plan, OWN_CHECK_FOLDS) if n else None
    own = own_check(own_check_loss(resid, shared.out_scaler), plan, val_loss_table(meta, budget),
                    own_check_table(meta, budget))
    check_s = time.perf_counter() - tick
    if own is not None and "validation_units_mse" in own and "own_check_folds" not in meta:
        notes.append("the shared model's validation units were checked on one held-out fold of every 5th "
                     "press (a benchmark from before the press-fold check): the same expected value, "
                     "noisier, so the comparison below is rougher")
    if own is not None and own.get("alarm"):
        notes.append(f"warning: the calibration's own check is {own['over_validation']:.1f}x the worst of "
                     "the shared model's validation units checked the same way (alarm above "
                     f"{OWN_CHECK_ALARM:g}x): check the unit's barometers, mounting and labels before "
                     "deploying it")
    out_scaler = Scaler(shared.out_scaler.mean.clone(), shared.out_scaler.std.clone())
    check, on_other = check_on_other_runs((folded, stats, out_scaler), arrays, stream)
    bands = None
    folds = interval_folds(meta)
    if interval_level is not None and plan.presses >= folds:
        factor, why = fleet_factor_for(meta, budget, interval_level, arrays.output_names)
        notes += [why] if why else []
        tick = time.perf_counter()
        band_resid = resid if folds == OWN_CHECK_FOLDS else fitter.residuals(plan, folds)
        check_s += time.perf_counter() - tick
        bands = plan_intervals(band_resid, interval_level, arrays.output_names, on_other, factor, folds)
    result = Calibrated(out, stream.unit, n, plan.calib_seconds, len(unlabeled_rows), prior, check, notes,
                        own, wall_s, bands, check_s)
    save_models(out / "model.safetensors", folded, stats, out_scaler, {
        "unit_ids": [stream.unit], "output_names": meta.get("output_names"), "shared_model": str(shared_path),
        "adapter": shared.model.kind, "calib_samples": n, "calib_seconds": result.calib_seconds,
        "calib_presses": plan.presses, "n_effective": plan.n_effective,
        "unlabeled_samples": result.unlabeled_samples, "prior": prior,
        "calibration_runs": list(stream.runs), "check_on_other_runs": check, "own_check": own,
        "intervals": bands,
    })
    return result
