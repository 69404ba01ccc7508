"""Fleet trainer against the paper's way, in one run: time to the same held-out accuracy.

Reference: each unit's MLP fitted alone with the `paper` recipe (batch 10, 10 epochs),
one unit after another. Fleet, paper recipe: every unit's MLP fitted at once as one batched
model with the same `paper` recipe (the speed-up from batching alone). Fleet: the same with
the spec's recipe (batching and the faster recipe together). All see the same rows
(held-out patches excluded, validation rows for curves), start from the same weights and
scalers. The target is the reference's final validation force RMSE per unit; each method's
time is the training time until the unit-mean validation RMSE first comes within
`tolerance` of it. Held-out-patch RMSE of every final model is reported beside it.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from anytip.data.splits import patch_test_mask
from anytip.pipelines.common import Context, load, per_unit_split, predict_units, validate_options
from anytip.report import figures
from anytip.report.markdown import table
from anytip.report.writer import Report
from anytip.train.fleet import FitResult, train_fleet
from anytip.train.metrics import scores
from anytip.train.recipe import PAPER
from anytip.train.sequential import train_sequential

FINGERTIP_ONLY = True  # its figures and objectives are the fingertip's force and angles (runner)


class Options(BaseModel):
    """`options:` of a fleet_speed spec."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    tolerance: float = Field(0.05, ge=0)  # within this fraction of the reference's final RMSE
    reference_evals_per_epoch: int = Field(10, ge=1, le=1000)
    fleet_paper: bool = Field(True, description="also the fleet trainer with the paper recipe, which "
                                                "separates the gain of batching from the recipe's")


def _curve_sequential(fit: FitResult, n_units: int) -> list[tuple[float, float]]:
    """Unit-mean validation force RMSE against cumulative training seconds, units in turn.

    While unit u trains, units before it count at their final value and units after it
    at their first recorded value (they have not started).
    """
    per_unit = [fit.unit_history(u) for u in range(n_units)]
    current = [h[0]["val_force_rmse"] for h in per_unit]
    offset, points = 0.0, []
    for u, hist in enumerate(per_unit):
        for row in hist:
            current[u] = row["val_force_rmse"]
            points.append((offset + row["elapsed_s"], float(np.mean(current))))
        offset += fit.unit_train_s[u]
    return points


def _first_within(points: list[tuple[float, float]], target: float, tol: float) -> float | None:
    return next((t for t, v in points if v <= target * (1 + tol)), None)


def run(ctx: Context) -> list[dict[str, Any]]:
    spec, opts = ctx.spec, validate_options(ctx, Options)
    arrays = load(ctx)
    units, seed = arrays.units, spec.seed
    split = per_unit_split(arrays, units, patch_test_mask(spec.splits.patch_test_fraction, seed),
                           spec.splits.val_fraction, seed, ctx.device)
    ref = train_sequential(split.data, spec.model, PAPER, seed=seed, device=ctx.device,
                           progress=ctx.progress, evals_per_epoch=opts.reference_evals_per_epoch)
    fleet = train_fleet(split.data, spec.model, spec.training, seed=seed, device=ctx.device,
                        progress=ctx.progress)
    paper = (train_fleet(split.data, spec.model, PAPER, seed=seed, device=ctx.device, progress=ctx.progress)
             if opts.fleet_paper else None)
    ref_curve = _curve_sequential(ref, len(units))
    fleet_curve, paper_curve = (None if f is None else
                                [(h["elapsed_s"], float(np.mean(h["val_force_rmse"]))) for h in f.history]
                                for f in (fleet, paper))
    target = ref_curve[-1][1]
    t_ref = _first_within(ref_curve, target, opts.tolerance)
    t_fleet = _first_within(fleet_curve, target, opts.tolerance)
    t_paper = _first_within(paper_curve, target, opts.tolerance) if paper_curve else None
    rows = []
    fits = [("per_unit_sequential", ref, PAPER), ("per_unit_fleet", fleet, spec.training)]
    fits += [("per_unit_fleet_paper", paper, PAPER)] if paper is not None else []
    for name, fit, recipe in fits:
        preds = predict_units(fit, split.X_test)
        for u, unit in enumerate(units):
            rows.append({"method": name, "unit": unit, "calib_samples": int(split.data.n_train[u]),
                         "seed": seed, "split": "patches", "recipe": recipe.name,
                         **scores(preds[u], split.Y_test[u])})
    summary = {
        "units": len(units), "target_val_force_rmse_n": target, "tolerance": opts.tolerance,
        "reference_time_to_target_s": t_ref, "fleet_time_to_target_s": t_fleet,
        "reference_total_train_s": float(sum(ref.unit_train_s)),
        "fleet_total_train_s": fleet_curve[-1][0],
        "speedup_time_to_target": _ratio(t_ref, t_fleet),
        "fleet_paper_time_to_target_s": t_paper,
        "fleet_paper_total_train_s": paper_curve[-1][0] if paper_curve else None,
        "speedup_batching": _ratio(t_ref, t_paper), "speedup_recipe": _ratio(t_paper, t_fleet),
        "device": str(ctx.device), "fleet_recipe": spec.training.model_dump(mode="json"),
    }
    ctx.provenance["fleet_speed"] = summary
    curves = {"one by one, paper recipe": ref_curve, f"fleet, {spec.training.name} recipe": fleet_curve}
    if paper_curve:
        curves["fleet, paper recipe"] = paper_curve
    figures.training_curves(curves,
                            ctx.run_dir / "time_to_accuracy.png", "unit-mean validation force RMSE",
                            xlabel="training time [s]")
    Report(ctx.run_dir).add(_report(ctx, rows, summary)).write()
    return rows


def _ratio(a: float | None, b: float | None) -> float | None:
    """a / b, or None where either time was not reached."""
    return a / b if a and b else None


def _report(ctx: Context, rows: list[dict[str, Any]], s: dict[str, Any]) -> str:
    def mean(method: str, key: str) -> float:
        return float(np.mean([r[key] for r in rows if r["method"] == method]))

    fmt = lambda v: "not reached" if v is None else f"{v:.1f}"  # noqa: E731
    speed = "n/a" if s["speedup_time_to_target"] is None else f"**{s['speedup_time_to_target']:.1f}x**"
    body = [
        ["one unit at a time, `paper` recipe", fmt(s["reference_time_to_target_s"]),
         f"{s['reference_total_train_s']:.1f}", mean("per_unit_sequential", "force_rmse_n"),
         mean("per_unit_sequential", "angle_rmse_rad")],
        [f"all units at once, `{ctx.spec.training.name}` recipe", fmt(s["fleet_time_to_target_s"]),
         f"{s['fleet_total_train_s']:.1f}", mean("per_unit_fleet", "force_rmse_n"),
         mean("per_unit_fleet", "angle_rmse_rad")],
    ]
    if s["fleet_paper_total_train_s"] is not None:
        body.insert(1, ["all units at once, `paper` recipe", fmt(s["fleet_paper_time_to_target_s"]),
                        f"{s['fleet_paper_total_train_s']:.1f}", mean("per_unit_fleet_paper", "force_rmse_n"),
                        mean("per_unit_fleet_paper", "angle_rmse_rad")])
    ratio = lambda v: "n/a (a target not reached)" if v is None else f"{v:.1f}x"  # noqa: E731
    parts = (f"Of it, batching alone (paper recipe, all units at once against one by one): "
             f"{ratio(s['speedup_batching'])}; the recipe on top (fleet `{ctx.spec.training.name}` "
             f"against fleet `paper`): {ratio(s['speedup_recipe'])}."
             if s["fleet_paper_total_train_s"] is not None else "")
    machine = ctx.provenance.get("machine", {})
    return f"""# {ctx.spec.name}: fleet trainer against one-by-one training

{s['units']} units of `{ctx.provenance['sensor_model']}`, device `{s['device']}`
({machine.get('cpus')} CPUs, torch {machine.get('torch')}, {machine.get('torch_threads')} threads,
GPU: {machine.get('cuda')}).
Target: the reference's final unit-mean validation force RMSE, {s['target_val_force_rmse_n']:.3f} N,
within {s['tolerance']:.0%}. Times are training seconds (evaluation excluded).

{table(['method', 'time to target [s]', 'total training [s]', 'held-out force RMSE [N]',
        'held-out angle RMSE [rad]'], body)}

Speed-up in time to the same accuracy: {speed}. {parts}

![time to accuracy](time_to_accuracy.png)
"""
