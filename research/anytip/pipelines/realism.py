"""How different are the units? Per-unit models against one model pooled over other units.

Held-out units each get their own per-unit model (trained on their calibration, held-out
patches excluded). One pooled model is trained on every row of the training units (tare
only: no unit-specific calibration) and applied to the held-out units. Both are scored
on the same held-out patches of the held-out units; the ratio pooled / per-unit says how
much a unit's own calibration is worth, the simulator's realism target.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import torch

from anytip.data.splits import patch_test_mask, split_units
from anytip.pipelines.common import Context, load, per_unit_split, predict_units
from anytip.report import figures
from anytip.report.markdown import table
from anytip.report.writer import Report
from anytip.train.data import FleetBatchData, UnitTensors
from anytip.train.fleet import train_fleet
from anytip.train.metrics import scores

FINGERTIP_ONLY = True  # its figures and objectives are the fingertip's force and angles (runner)


def _pooled_data(split, device: torch.device) -> FleetBatchData:
    """All training units' train and validation rows as one member."""
    members = [split.data.unit(u) for u in range(split.data.n_units)]
    cat = lambda k: torch.cat([getattr(m, k) for m in members])  # noqa: E731
    return FleetBatchData.from_units([UnitTensors(cat("X_train"), cat("Y_train"), cat("X_val"),
                                                  cat("Y_val"), "pooled")], device)


def min_units(ctx: Context) -> int:
    """Held-out units and at least two to pool over."""
    return (ctx.spec.splits.n_test_units or 4) + 2


def run(ctx: Context) -> list[dict[str, Any]]:
    spec = ctx.spec
    n_test = spec.splits.n_test_units or 4
    arrays = load(ctx, min_units=min_units(ctx))
    rows: list[dict[str, Any]] = []
    for seed in spec.all_seeds:
        roles = split_units(arrays.units, seed, n_val=0, n_test=n_test, n_train=spec.splits.n_train_units)
        ctx.provenance.setdefault("unit_split", {})[str(seed)] = roles.to_json()
        mask = patch_test_mask(spec.splits.patch_test_fraction, seed)
        test = per_unit_split(arrays, roles.test, mask, spec.splits.val_fraction, seed, ctx.device)
        train = per_unit_split(arrays, roles.train, mask, spec.splits.val_fraction, seed, ctx.device)
        per_unit = train_fleet(test.data, spec.model, spec.training, seed=seed, device=ctx.device,
                               progress=ctx.progress)
        pooled_recipe = spec.training.model_copy(
            update={"batch_size": spec.training.batch_size * len(roles.train)})
        pooled = train_fleet(_pooled_data(train, ctx.device), spec.model, pooled_recipe, seed=seed,
                             device=ctx.device, progress=ctx.progress)
        own = predict_units(per_unit, test.X_test)
        shared = [predict_units(pooled, [x])[0] for x in test.X_test]
        for u, unit in enumerate(roles.test):
            base = {"unit": unit, "seed": seed, "split": "patches", "recipe": spec.training.name}
            rows.append({"method": "per_unit", "calib_samples": int(test.data.n_train[u]), **base,
                         **scores(own[u], test.Y_test[u])})
            rows.append({"method": "pooled", "calib_samples": 0, "train_units": len(roles.train),
                         **base, **scores(shared[u], test.Y_test[u])})
    Report(ctx.run_dir).add(_report(ctx, rows)).write()
    return rows


def ratios(rows: list[dict[str, Any]]) -> dict[str, float]:
    """Mean pooled RMSE over mean per-unit RMSE, force and angle."""
    def mean(method: str, key: str) -> float:
        return float(np.mean([r[key] for r in rows if r["method"] == method]))

    return {k: mean("pooled", k) / mean("per_unit", k) for k in ("force_rmse_n", "angle_rmse_rad")}


def _report(ctx: Context, rows: list[dict[str, Any]]) -> str:
    units = sorted({r["unit"] for r in rows})
    get = lambda m, u, k: float(np.mean([r[k] for r in rows if r["method"] == m and r["unit"] == u]))  # noqa: E731
    body = [[u, get("per_unit", u, "force_rmse_n"), get("pooled", u, "force_rmse_n"),
             get("per_unit", u, "angle_rmse_rad"), get("pooled", u, "angle_rmse_rad")] for u in units]
    r = ratios(rows)
    figures.bars(units, {m: [get(m, u, "force_rmse_n") for u in units] for m in ("per_unit", "pooled")},
                 ctx.run_dir / "pooled_vs_per_unit.png", "held-out patches of held-out units",
                 "force RMSE [N]")
    n_train = next(r["train_units"] for r in rows if r["method"] == "pooled")
    return f"""# {ctx.spec.name}: per-unit models against a model pooled over {n_train} other units

Registry `{ctx.provenance['registry']}` (content hash `{ctx.provenance['registry_content_hash'][:16]}`),
seeds {ctx.spec.all_seeds}, recipe `{ctx.spec.training.name}`. Pooled: trained on {n_train} training units,
tare only on the held-out units.

{table(['held-out unit', 'per-unit force [N]', 'pooled force [N]', 'per-unit angle [rad]',
        'pooled angle [rad]'], body)}

Ratio pooled / per-unit (means over held-out units and seeds): force **{r['force_rmse_n']:.2f}x**,
angle **{r['angle_rmse_rad']:.2f}x**.

![pooled against per-unit](pooled_vs_per_unit.png)
"""
