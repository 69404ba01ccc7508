"""What every cross_sensor method shares about its calibration jobs: the plan a budget grants a
unit, what a row says of it, and the validation units' loss that chooses between methods."""

from __future__ import annotations

from typing import Any

import numpy as np

from anytip.data.arrays import FleetArrays
from anytip.data.plans import Budget, Plan, plan_for
from anytip.models.scaler import Scaler
from anytip.pipelines.cross_sensor_options import Options
from anytip.train.shared_split import SeedData


def plan_of(sd: SeedData, unit: str, budget: Budget, opts: Options, seed: int) -> Plan:
    """The labeled rows `budget` grants `unit` (a stream prefix or whole presses)."""
    ev = sd.evals[unit]
    return plan_for(budget, ev.stream, ev.presses, opts.rig.timing(), seed)


def budget_fields(budget: Budget, plan: Plan) -> dict[str, Any]:
    """What a row says of its calibration: labeled samples and robot seconds, and for a
    budget in seconds the budget, the press selection and the plan's presses."""
    out: dict[str, Any] = {"calib_samples": int(len(plan.rows)), "calib_seconds": plan.calib_seconds}
    if budget.unit == "seconds":
        out |= {"budget_s": budget.amount, "plan": budget.strategy, "presses": plan.presses,
                "n_effective": plan.n_effective, "orientations": len(plan.orientations)}
    return out


def plan_suffix(budget: Budget) -> str:
    """What a method name says of a budget in robot seconds: `@strategy` (nothing at 0 s)."""
    return f"@{budget.strategy}" if budget.unit == "seconds" and budget.amount > 0 else ""


def validation_by_method(method: str, val_loss: dict[Budget, float]) -> dict[str, dict[str, float]]:
    """{row method: {budget: validation-unit loss}} of one shared model and prior, keyed as the
    report keys rows (method with its plan suffix; budget in samples or seconds)."""
    out: dict[str, dict[str, float]] = {}
    for b, v in val_loss.items():
        out.setdefault(method + plan_suffix(b), {})[f"{b.amount:g}"] = v
    return out


def validation_losses(jobs: list[tuple[str, Budget, float]], preds: list[np.ndarray], sd: SeedData,
                      arrays: FleetArrays, val_units: set[str],
                      out_scaler: Scaler) -> dict[tuple[Budget, float], list[float]]:
    """(budget, prior) -> each validation unit's standardised MSE on its test patches."""
    std = out_scaler.std.reshape(-1).cpu().numpy()
    loss: dict[tuple[Budget, float], list[float]] = {}
    for (u, b, p), pred in zip(jobs, preds, strict=True):
        if u in val_units:
            err = (pred - arrays.targets[sd.evals[u].test_rows]) / std
            loss.setdefault((b, p), []).append(float((err**2).mean()))
    return loss
