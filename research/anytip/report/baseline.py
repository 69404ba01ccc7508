"""The per-unit baseline's report: summary table per unit, both splits, and figures."""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass
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
    """The fingertip's report: held-out patches, the contact region, force bins."""
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


@dataclass(frozen=True)
class TargetInfo:
    """One target as the report shows it: its unit, its component names and its result key."""

    unit: str
    components: tuple[str, ...]
    key: str  # e.g. position_rmse


def targets_table(rows: list[dict[str, Any]], targets: dict[str, TargetInfo],
                  spread: dict[str, float]) -> str:
    """Per unit (mean over seeds): each component's (of targets with several) and each target's
    RMSE on held-out blocks, each
    target's RMSE on random rows, and each target's held-out RMSE over its spread."""
    multi = [c for t in targets.values() if len(t.components) > 1 for c in t.components]
    comps = [f"{c}_rmse" for c in multi]
    keys = [t.key for t in targets.values()]
    units = sorted({r["unit"] for r in rows})

    def mean(unit: str | None, split: str, key: str) -> float:
        return float(np.mean([r[key] for r in rows if r["split"] == split and unit in (None, r["unit"])]))

    body = []
    for unit in [*units, None]:
        cells = [mean(unit, "blocks", k) for k in comps + keys] + [mean(unit, "random", k) for k in keys]
        cells += [f"{mean(unit, 'blocks', t.key) / spread[n]:.3f}" for n, t in targets.items()]
        body.append(["**mean**" if unit is None else unit, *cells])
    header = ["unit", *multi, *targets,
              *(f"{n} (random rows)" for n in targets), *(f"{n} / spread" for n in targets)]
    return table(header, body, floatfmt=".4g")


def write_targets_report(ctx, rows: list[dict[str, Any]], fig: dict[str, Any],
                         targets: dict[str, TargetInfo], blocks_per_run: int) -> None:
    """The baseline's report for a sensor model without the fingertip's patch grid: held-out
    contiguous blocks of each run, RMSE per component and target in the target's unit."""
    out, spec, prov = ctx.run_dir, ctx.spec, ctx.provenance
    labels = [f"{c} [{t.unit}]" for t in targets.values() for c in t.components]
    figures.parity(*fig["blocks"], fig["blocks_rmse"], out / "parity_blocks.png",
                   "held-out blocks, all units", labels=labels)
    names = fig["member_names"]
    curves = {names[u]: [(h["epoch"], h["val_loss"][u]) for h in fig["history"]]
              for u in range(len(names)) if "(blocks)" in names[u]}
    figures.training_curves(curves, out / "training_curves.png", f"validation loss, recipe "
                            f"{spec.training.name!r}", ylabel="validation loss (standardised MSE)")
    spread = fig["target_std"]
    spreads = ", ".join(f"{n} {v:.4g} {targets[n].unit}" for n, v in spread.items())
    described = ", ".join(f"{n} [{t.unit}] ({', '.join(t.components)})" for n, t in targets.items())
    text = f"""# {spec.name}: per-unit baseline

{spec.description.strip()}

The MLP {' -> '.join(map(str, spec.model.sizes))} ({spec.model.activation}) trained per unit with
recipe `{spec.training.name}` on {len(prov['units'])} units of `{prov['sensor_model']}` (targets
{described}; seeds {spec.all_seeds}). Scores are RMSE on test rows the model never trained on, in
two splits: **held-out blocks** (each run's label rows cut into {blocks_per_run} contiguous blocks;
{spec.splits.patch_test_fraction:.0%} of the block indices held out, the same blocks of every run
of a unit) and **random rows** ({spec.splits.random_test_fraction:.0%} of rows, beside training
rows). A target's RMSE is over its components, in its unit.

## Summary (held-out blocks unless marked; mean over seeds)

{targets_table(rows, targets, spread)}

"spread" is each target's spread over every label row of the registry's units (the RMS of
its components' standard deviations: {spreads}); "/ spread" is the held-out RMSE in those units.

## Figures

{image('parity_blocks.png', 'parity plots')}

{image('training_curves.png', 'training curves')}

## Provenance

Registry `{prov['registry']}`, content hash `{prov['registry_content_hash'][:16]}`; runs used:
{len(prov['runs'])}; code {prov.get('code', {}).get('git_commit') or prov.get('code', {}).get('anytip')}.
"""
    Report(out).add(text).write()
