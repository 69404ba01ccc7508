"""The paper's per-unit baseline: one MLP per unit, trained on that unit's calibration,
scored on two test splits: the paper's random 10% of rows, and whole held-out patches.

All units and both splits train at once as one batched model (2U members).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from anytip.data.arrays import BLOCKS_PER_RUN, FleetArrays, has_patch_grid
from anytip.data.splits import patch_test_mask, random_test_mask
from anytip.pipelines.common import Context, load, per_unit_split, predict_units
from anytip.report.baseline import TargetInfo, write_report, write_targets_report
from anytip.train.data import FleetBatchData
from anytip.train.fleet import train_fleet
from anytip.train.metrics import region_rmse, rmse_by_level, scores, target_key


def split_names(arrays: FleetArrays) -> tuple[str, str]:
    """The held-out split's name, `patches` (the fingertip's grid) or `blocks` (contiguous
    blocks of rows of each run, for any other sensor model), then `random`."""
    return ("patches" if has_patch_grid(arrays.layout) else "blocks", "random")


def run(ctx: Context) -> list[dict[str, Any]]:
    spec = ctx.spec
    arrays = load(ctx)
    units = arrays.units
    rows: list[dict[str, Any]] = []
    figures_input: dict[str, Any] = {}
    order = split_names(arrays)
    for seed in spec.all_seeds:
        masks = {order[0]: patch_test_mask(spec.splits.patch_test_fraction, seed),
                 "random": random_test_mask(spec.splits.random_test_fraction, seed)}
        splits = {name: per_unit_split(arrays, units, masks[name], spec.splits.val_fraction, seed,
                                       ctx.device) for name in order}
        members = [splits[s].data.unit(u) for s in order for u in range(len(units))]
        data = FleetBatchData.from_units(members, ctx.device, arrays.output_names)
        fit = train_fleet(data, spec.model, spec.training, seed=seed, device=ctx.device,
                          progress=ctx.progress)
        fit.save(ctx.run_dir / "models" / f"per_unit_seed{seed}")
        for k, split in enumerate(order):
            s = splits[split]
            preds = predict_units(fit, s.X_test, first_model=k * len(units))
            for u, unit in enumerate(units):
                rows.append({
                    "method": "per_unit", "unit": unit, "calib_samples": int(s.data.n_train[u]),
                    "seed": seed, "split": split, "recipe": spec.training.name,
                    **scores(preds[u], s.Y_test[u], arrays.layout), "test_rows": len(s.Y_test[u]),
                })
            if seed == spec.all_seeds[0]:
                figures_input[split] = (np.concatenate(preds), np.concatenate(s.Y_test))
                pooled = scores(*figures_input[split], arrays.layout)
                figures_input[f"{split}_rmse"] = [pooled[f"{name}_rmse"] for name in arrays.output_names]
                if has_patch_grid(arrays.layout):
                    figures_input |= binned_errors(split, *figures_input[split])
        if seed == spec.all_seeds[0]:
            figures_input["history"] = fit.history
            figures_input["member_names"] = [f"{u} ({s})" for s in order for u in units]
    if order[0] == "patches":
        write_report(ctx, rows, figures_input)
    else:
        figures_input["target_std"] = target_spread(arrays)
        targets = {n: TargetInfo(t.unit, t.components, target_key(n)) for n, t in arrays.layout.items()}
        write_targets_report(ctx, rows, figures_input, targets, BLOCKS_PER_RUN)
    return rows


def target_spread(arrays: FleetArrays) -> dict[str, float]:
    """Each target's spread in its unit: the RMS over its components of their standard
    deviations over every label row (the scale a held-out RMSE is judged against)."""
    y = arrays.targets.astype(np.float64)
    return {name: float(np.sqrt((y[:, cols].std(0) ** 2).mean())) for name, cols in arrays.slices.items()}


def binned_errors(split: str, pred: np.ndarray, y: np.ndarray) -> dict[str, Any]:
    """The report's binned RMSEs of one split's pooled rows pred, y (N, 5): force RMSE by |Fz|
    bin, and (held-out patches only) force and angle RMSE over the contact region."""
    err2_force = ((pred[:, :3] - y[:, :3]) ** 2).mean(axis=1)
    out: dict[str, Any] = {f"force_by_fz_{split}": rmse_by_level(y[:, 2], err2_force)}
    if split == "patches":
        out["region_force"] = region_rmse(y[:, 3:], err2_force)
        out["region_angle"] = region_rmse(y[:, 3:], ((pred[:, 3:] - y[:, 3:]) ** 2).mean(axis=1))
    return out
