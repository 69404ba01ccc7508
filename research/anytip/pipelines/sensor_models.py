"""Every sensor model of a registry side by side: the per-unit baseline and the cross-sensor
benchmark run on each model in turn, with the same spec (model hidden widths, recipe, seeds,
unit roles), and one table a reader compares across designs.

Each model's own runs go to `<run dir>/<sensor model>/baseline` and `.../cross_sensor`, each
with its full report. Widths come from each sensor model (the spec's model block names
hidden widths). The cross-sensor method shown per budget is the one chosen on validation
units, as in the cross-sensor report.
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np
from pydantic import BaseModel, ConfigDict, Field

from anytip.data.runfile import parse_layout
from anytip.errors import AnytipError
from anytip.pipelines import baseline, cross_sensor
from anytip.pipelines.common import Context, report_metrics, unit_of, validate_options
from anytip.report.cross_sensor import chosen_methods, full_set_rows, ratio_text, summary
from anytip.report.markdown import table
from anytip.report.writer import Report


class Options(BaseModel):
    """`models`: which sensor models of the registry (default: every model with at least
    `cross_sensor`'s unit count); `cross_sensor`: that pipeline's options."""

    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)
    models: list[str] | None = Field(default=None, min_length=1)
    cross_sensor: dict[str, Any] = Field(default_factory=dict)


def parse_options(ctx: Context) -> Options:
    opts = validate_options(ctx, Options)
    sub = Context(replace_spec(ctx, None, opts), ctx.registry, ctx.run_dir, ctx.device, False,
                  {"spec_file": f"{ctx.provenance.get('spec_file', ctx.spec.name)} (options.cross_sensor)"})
    cross_sensor.parse_options(sub)
    return opts


def min_units(ctx: Context) -> int:
    return cross_sensor.min_units(ctx)


def replace_spec(ctx: Context, sensor_model: str | None, opts: Options, options: dict | None = None):
    """The spec one sub-run reads: this spec on one sensor model, its widths set from the model,
    with `options` (the cross-sensor options, or none for the baseline)."""
    spec = ctx.spec
    data = spec.data.model_copy(update={"sensor_model": sensor_model})
    model = spec.model
    if sensor_model is not None:
        channels, targets = parse_layout(ctx.registry.sensor_models()[sensor_model])
        widths = sum(len(t.components) for t in targets.values())
        source = str(ctx.provenance.get("spec_file", spec.name))
        model = model.for_sensor(channels, widths, source, sensor_model)
    return spec.model_copy(update={"data": data, "model": model,
                                   "options": opts.cross_sensor if options is None else options})


def models_to_run(ctx: Context, opts: Options) -> list[str]:
    """The sensor models named by `options.models` (each must be in the registry), else every
    model of the registry with enough units for the cross-sensor benchmark."""
    units = Counter(model for model, _ in {(r.sensor_model, r.unit) for r in ctx.registry.list_runs()})
    need = min_units(ctx)
    if opts.models is None:
        chosen = sorted(m for m, n in units.items() if n >= need)
        if not chosen:
            raise AnytipError(f"registry {ctx.registry.root}: no sensor model has {need} units "
                              f"(units per model: {dict(units)})")
        return chosen
    short = [f"{m} ({units.get(m, 0)} units)" for m in opts.models if units.get(m, 0) < need]
    if short:
        raise AnytipError(f"{ctx.provenance.get('spec_file', ctx.spec.name)}: key 'options.models': the "
                          f"cross-sensor benchmark needs {need} units of each model; the registry "
                          f"{ctx.registry.root} holds {', '.join(short)}")
    return list(opts.models)


def run_model(ctx: Context, model: str, opts: Options) -> tuple[list[dict[str, Any]], dict[str, Any]]:
    """Baseline and cross-sensor on one sensor model: their rows (tagged with the model and the
    stage) and their provenance."""
    rows, prov = [], {}
    for stage, module, options in (("baseline", baseline, {}), ("cross_sensor", cross_sensor, None)):
        run_dir = ctx.run_dir / model / stage
        run_dir.mkdir(parents=True, exist_ok=True)
        sub = Context(replace_spec(ctx, model, opts, options), ctx.registry, run_dir, ctx.device,
                      ctx.progress, {"spec_file": ctx.provenance.get("spec_file")})
        rows += [{**r, "sensor_model": model, "stage": stage} for r in module.run(sub)]
        prov[stage] = sub.provenance | {"model_sizes": list(sub.spec.model.sizes)}
    return rows, prov


def run(ctx: Context) -> list[dict[str, Any]]:
    opts = parse_options(ctx)
    rows: list[dict[str, Any]] = []
    ctx.provenance["targets"] = {}  # the models' targets differ; each row carries its own
    for model in models_to_run(ctx, opts):
        model_rows, prov = run_model(ctx, model, opts)
        rows += model_rows
        ctx.provenance.setdefault("sensor_models", {})[model] = {
            "targets": prov["baseline"]["targets"], "units": prov["baseline"]["units"],
            "selection_content_hash": prov["baseline"]["selection_content_hash"],
            "val_loss": {k: v.get("val_loss", {})
                         for k, v in prov["cross_sensor"].get("cross_sensor", {}).items()},
            "cross_sensor_provenance": prov["cross_sensor"],
        }
    write_report(ctx, rows)
    return rows


def report(ctx: Context, rows: list[dict[str, Any]]) -> None:
    """Write this run's report and each model's cross-sensor report again from the recorded rows
    (`anytip report RUN_DIR`)."""
    opts = parse_options(ctx)
    for model, info in ctx.provenance.get("sensor_models", {}).items():
        if "cross_sensor_provenance" not in info:
            continue  # recorded before the sub-runs' provenance was kept
        prov = info["cross_sensor_provenance"]
        spec = replace_spec(ctx, None, opts)
        sized = spec.model.model_copy(update={"sizes": tuple(prov["model_sizes"])})
        spec = spec.model_copy(update={"model": sized})
        sub = Context(spec, ctx.registry, ctx.run_dir / model / "cross_sensor", ctx.device, False, prov)
        mine = [r for r in rows if r["sensor_model"] == model and r["stage"] == "cross_sensor"]
        cross_sensor.report(sub, mine)
    write_report(ctx, rows)


def baseline_lines(rows: list[dict[str, Any]], targets: dict[str, Any]) -> list[list[Any]]:
    """Per target: the per-unit models' held-out RMSE (mean over units and seeds) and that over
    the target's spread in the registry's label rows (as the baseline report gives it)."""
    held = [r for r in rows if r["stage"] == "baseline" and r["split"] != "random"]
    out = []
    for name, t in targets.items():
        key = report_metrics({name: t['unit']})[0].key
        out.append([name, f"{np.mean([r[key] for r in held]):.4g} {t['unit']}"])
    return out


def chosen_lines(rows: list[dict[str, Any]], targets: dict[str, Any], val_loss: dict[str, Any]
                 ) -> dict[float, tuple[str, str, int]]:
    """Per budget: (the method chosen on validation units, its held-out ratio to per_unit for each
    target as 'name mean [95% interval over units]', the number of held-out units)."""
    metrics = report_metrics(unit_of(targets))
    lines = summary(full_set_rows([r for r in rows if r["stage"] == "cross_sensor"]), metrics)
    by_key = {(s["method"], s["budget"]): s for s in lines}
    out = {}
    for (budget, _strategy), method in sorted(chosen_methods(val_loss).items(), key=lambda kv: kv[0][0]):
        s = by_key.get((method, budget))
        if s is not None:
            ratios = "; ".join(f"{m.name} {ratio_text(s[f'{m.name}_unit'])}" for m in metrics)
            out[budget] = (method, ratios, s["units"])
    return out


def side_by_side(rows: list[dict[str, Any]], models: dict[str, Any]) -> str:
    """One table: a row per budget, a column per sensor model, each cell the chosen method's
    ratios to per_unit (mean over held-out units)."""
    chosen = {m: chosen_lines([r for r in rows if r["sensor_model"] == m], info["targets"], info["val_loss"])
              for m, info in models.items()}
    budgets = sorted({b for c in chosen.values() for b in c})
    body = [[f"{b:g}", *(chosen[m][b][1] if b in chosen[m] else "" for m in models)] for b in budgets]
    return table(["budget", *models], body)


def write_report(ctx: Context, rows: list[dict[str, Any]]) -> Path:
    models = ctx.provenance.get("sensor_models", {})
    links = ", ".join(f"[{m}/{stage}]({m}/{stage}/report.md)"
                      for m in models for stage in ("baseline", "cross_sensor"))
    blocks = [f"""# {ctx.spec.name}: sensor models side by side

{ctx.spec.description.strip()}

Each sensor model ran the per-unit baseline and the cross-sensor benchmark with the same spec
(hidden widths {list(ctx.spec.model.sizes[1:-1])}, recipe `{ctx.spec.training.name}`, seeds
{ctx.spec.all_seeds}); input and output widths are each model's. Full reports: {links}.

## Side by side

A held-out unit's RMSE over its own per-unit model's, per target (mean over held-out units [95%
bootstrap interval over units]), for the cross-sensor method chosen on validation units at
each budget (labeled calibration samples; 0: label-free).

{side_by_side(rows, models)}
"""]
    for model, info in models.items():
        mine = [r for r in rows if r["sensor_model"] == model]
        targets = info["targets"]
        chosen = [[f"{b:g}", f"`{m}`", ratios, n]
                  for b, (m, ratios, n) in chosen_lines(mine, targets, info["val_loss"]).items()]
        blocks.append(f"""## `{model}` ({len(info['units'])} units; targets {', '.join(
            f"{n} [{t['unit']}]" for n, t in targets.items())})

Per-unit models, held-out RMSE (mean over units and seeds):

{table(['target', 'RMSE'], baseline_lines(mine, targets))}

Cross-sensor, the method chosen on validation units at each budget; ratio to each held-out
unit's own per-unit model, mean over units [95% bootstrap interval]:

{table(['budget', 'method', 'ratio to per_unit', 'held-out units'], chosen)}
""")
    return Report(ctx.run_dir).add("\n".join(blocks)).write()


def summarise(rows: list[dict[str, Any]]) -> str:
    """One line per (sensor model, stage): rows and the held-out units."""
    groups = Counter((r["sensor_model"], r["stage"]) for r in rows)
    units = {m: len({r["unit"] for r in rows if r["sensor_model"] == m}) for m, _ in groups}
    return "\n".join(f"{m:<24}{stage:<14}{n:>6} rows, {units[m]} units"
                     for (m, stage), n in sorted(groups.items()))

