"""The per-unit baseline's report: summary table per unit, both splits, and figures."""

from __future__ import annotations

from collections import defaultdict
from typing import Any

import numpy as np

from anytip.report import figures
from anytip.report.markdown import image, table
from anytip.report.writer import Report


def _by_unit(rows: list[dict[str, Any]]) -> dict[tuple[str, str], dict[str, float]]:
    """Mean over seeds of each (unit, split)."""
    acc: dict[tuple[str, str], list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        acc[(r["unit"], r["split"])].append(r)
    keys = ("fx_rmse", "fy_rmse", "fz_rmse", "force_rmse_n", "theta_rmse", "phi_rmse", "angle_rmse_rad")
    return {k: {m: float(np.mean([r[m] for r in v])) for m in keys} for k, v in acc.items()}


def summary_table(rows: list[dict[str, Any]]) -> str:
    means = _by_unit(rows)
    units = sorted({u for u, _ in means})
    header = ["unit", "Fx", "Fy", "Fz", "force", "theta", "phi", "angle",
              "force (random rows)", "angle (random rows)", "force gap"]
    body = []
    for unit in [*units, "mean"]:
        if unit == "mean":
            keys = means[(units[0], "patches")]
            p = {m: float(np.mean([means[(u, "patches")][m] for u in units])) for m in keys}
            r = {m: float(np.mean([means[(u, "random")][m] for u in units])) for m in p}
        else:
            p, r = means[(unit, "patches")], means[(unit, "random")]
        body.append([f"**{unit}**" if unit == "mean" else unit, p["fx_rmse"], p["fy_rmse"],
                     p["fz_rmse"], p["force_rmse_n"], p["theta_rmse"], p["phi_rmse"],
                     p["angle_rmse_rad"], r["force_rmse_n"], r["angle_rmse_rad"],
                     f"{p['force_rmse_n'] / r['force_rmse_n']:.2f}x"])
    return table(header, body)


def write_report(ctx, rows: list[dict[str, Any]], fig: dict[str, Any]) -> None:
    out = ctx.run_dir
    spec = ctx.spec
    pred_p, y_p = fig["patches"]
    figures.parity(pred_p, y_p, fig["patches_rmse"], out / "parity_patches.png",
                   "held-out patches, all units")
    for name, label in (("force", "force RMSE [N]"), ("angle", "angle RMSE [rad]")):
        figures.region_heatmap(*fig[f"region_{name}"], out / f"region_{name}.png",
                               f"{label} over the contact region (held-out patches)")
    for split, label, suffix in (("patches", "held-out patches", ""), ("random", "random rows", "_random")):
        centres, values = fig[f"force_by_fz_{split}"]
        figures.error_vs_force(centres, {label: values}, out / f"force_vs_fz{suffix}.png",
                               "force error against normal force" + (f" ({label})" if suffix else ""))
    names = fig["member_names"]
    curves = {names[u]: [(h["epoch"], h["val_force_rmse"][u]) for h in fig["history"]]
              for u in range(len(names)) if "(patches)" in names[u]}
    figures.training_curves(curves, out / "training_curves.png",
                            f"validation force RMSE, recipe {spec.training.name!r}")
    prov = ctx.provenance
    text = f"""# {spec.name}: per-unit baseline

{spec.description.strip()}

The paper's MLP {' -> '.join(map(str, spec.model.sizes))} ({spec.model.activation}) trained per unit
with recipe `{spec.training.name}` on {len(prov['units'])} units of `{prov['sensor_model']}`
(seeds {spec.all_seeds}). Scores are RMSE on test rows the model never trained on, in two
splits: **held-out patches** (whole 15-degree patches of the protocol,
{spec.splits.patch_test_fraction:.0%} of each unit's patches) and the paper's **random rows**
({spec.splits.random_test_fraction:.0%} of rows, beside training rows).
Force RMSE is over the three axes [N], angle RMSE over theta and phi [rad].

## Summary (held-out patches unless marked; mean over seeds)

{summary_table(rows)}

"force gap" is held-out-patch force RMSE over random-row force RMSE: how much the paper's
random split flatters a unit's model on contacts away from its calibration presses.

## Figures

{image('parity_patches.png', 'parity plots')}

{image('region_force.png', 'force error over the contact region')}
{image('region_angle.png', 'angle error over the contact region')}

{image('force_vs_fz.png', 'force error against normal force')}
{image('force_vs_fz_random.png', 'force error against normal force, random rows')}

{image('training_curves.png', 'training curves')}

## Provenance

Registry `{prov['registry']}`, content hash `{prov['registry_content_hash'][:16]}`; runs used:
{len(prov['runs'])}; code {prov.get('code', {}).get('git_commit') or prov.get('code', {}).get('anytip')}.
"""
    Report(out).add(text).write()
