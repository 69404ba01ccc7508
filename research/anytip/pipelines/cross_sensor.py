"""Sensor-agnostic models on units they never trained on, against per-unit baselines.

Per seed: units are dealt into training, validation and held-out roles. Each held-out
(and validation) unit loses a fraction of its patches to testing: no method sees rows of
those patches, in any run. Its calibration budget is the first N rows of its calibration
stream (data/calibration.py). Methods, all scored on the same held-out patches:

- per_unit: the reference, the paper's MLP fitted on the unit's full calibration;
- scratch: the same MLP fitted only on the budget;
- pooled: one MLP over the training units with one input scaling for all; tare only;
- adapted:input_stats: a shared MLP whose per-unit input scaling comes from the unit's
  unlabeled pressures (label-free, calib_samples 0);
- adapted:<kind>: a shared MLP trained with per-unit adapters of that kind; a new unit's
  adapter is fitted on the budget (the prior strength chosen on validation units), then
  folded into a plain MLP of the deployed shape, which is what gets scored.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from anytip.calibrate import OWN_CHECK_ALARM
from anytip.data.arrays import FleetArrays, has_patch_grid
from anytip.data.calibration import CalibrationStream
from anytip.data.plans import Budget, Plan, Strategy
from anytip.data.seeds import CALIBRATION_ROWS, REFERENCE_START, VALIDATION_PATCHES, stream_seed
from anytip.data.splits import held_out_patches
from anytip.models.io import SHARED_FORMAT, read_header, save_shared
from anytip.models.mlp import MLPConfig
from anytip.models.scaler import Scaler
from anytip.pipelines.common import Context, load, load_extra, recorded_metrics, report_metrics, unit_of
from anytip.pipelines.cross_sensor_jobs import (
    Job,
    UnitLosses,
    budget_fields,
    interval_fields,
    mean_loss,
    missing_designs,
    plan_of,
    plan_suffix,
    validation_by_method,
    validation_factors,
    validation_losses,
)
from anytip.pipelines.cross_sensor_options import (
    FitVariant,
    Options,
    Training,
    budget_list,
    parse_options,
    plan_strategies,
    training_tag,
)
from anytip.pipelines.cross_sensor_response import response_rows
from anytip.pipelines.cross_sensor_response import val_by_method as response_val_by_method
from anytip.report.cross_sensor import full_set_rows, summary, write_report
from anytip.train.adapt import (
    AdapterRecipe,
    SharedFit,
    train_shared,
)
from anytip.train.adapter_prior import AdapterPrior, PriorFamily, make_prior
from anytip.train.data import FleetBatchData, split_validation, unit_tensors
from anytip.train.fleet import train_fleet
from anytip.train.label_free import data_family
from anytip.train.metrics import scores
from anytip.train.shared_split import (
    OWN_CHECK_FOLDS,
    Roles,
    SeedData,
    calibrate_many,
    main_rows,
    own_check_loss,
    own_check_losses,
    plan_residuals,
    predict_rows,
    prepare_seed,
    unit_main_rows,
)

PLAIN_FIT = FitVariant()  # the shared model's own adapter kind, `adapter_steps` Adam steps


PlanResiduals = dict[tuple[str, Budget], np.ndarray | None]


class Adapted(NamedTuple):
    """What `adapted_rows` gives: rows, the prior chosen per budget, each validation unit's loss
    per budget at that prior, the intervals' fleet factor per budget (output order), and the
    out-of-fold residuals of the validation and held-out units' plans at that prior
    ((unit, budget) -> (n, D) or None; `PlanResiduals`), empty without intervals."""

    rows: list[dict[str, Any]]
    chosen: dict[Budget, float]
    val_units: dict[Budget, UnitLosses]
    interval_factors: dict[Budget, np.ndarray]
    residuals: PlanResiduals

    @property
    def val_loss(self) -> dict[Budget, float]:
        """The validation units' mean loss per budget at the chosen prior."""
        return {b: mean_loss(v) for b, v in self.val_units.items()}


def prepare(ctx: Context, arrays: FleetArrays, opts: Options, seed: int,
            extra: FleetArrays | None = None) -> SeedData:
    """The seed's unit roles and tensors (`anytip.train.shared_split`) for this spec; `extra`:
    training-only units of `options.extra_units`."""
    return prepare_seed(arrays, roles_of(ctx, opts), opts.calibration_protocol, opts.calibration_interleave,
                        seed, ctx.device, extra)


def roles_of(ctx: Context, opts: Options) -> Roles:
    """The spec's unit roles and row fractions, as `prepare_seed` takes them."""
    s = ctx.spec.splits
    return Roles(s.n_val_units, s.n_test_units, s.n_train_units, s.patch_test_fraction, s.val_fraction,
                 s.unit_folds, opts.unlabeled_s, opts.intervals.factor_units if opts.intervals else 0,
                 s.test_rows)


def shared_shape(ctx: Context, opts: Options) -> MLPConfig:
    """The shape the shared and pooled models train (and adapters fold into)."""
    return opts.shared_shape(ctx.spec.model, *_names(ctx))


def _names(ctx: Context) -> tuple[str, str]:
    """(the spec's source, the sensor model): what a shape's error names."""
    return str(ctx.provenance.get("spec_file", ctx.spec.name)), str(ctx.provenance.get("sensor_model"))


def min_units(ctx: Context) -> int:
    """Training, validation and held-out units, with at least a few to train on."""
    return 8


def run(ctx: Context) -> list[dict[str, Any]]:
    opts = parse_options(ctx)
    arrays = load(ctx, min_units=min_units(ctx))
    for name in missing_designs(arrays, opts):
        ctx.say(f"strategy designed: no run of {name} among the runs read (data.protocol), so its budget "
                "has no designed rows; `anytip data simulate --protocols ...` or a lab's own runs of that "
                "plan marked with `anytip data protocol` supply them")
    extra = None
    if opts.extra_units is not None:
        extra = load_extra(ctx, opts.extra_units.registry, opts.extra_units.data(), arrays)
    rows: list[dict[str, Any]] = []
    for k, seed in enumerate(ctx.spec.all_seeds):
        rows += run_seed(ctx, arrays, opts, seed, sweep=k < opts.sweep_seeds, extra=extra)
    write_report(ctx, rows, opts, report_metrics(unit_of(ctx.provenance["targets"])), data_family)
    return rows


def report(ctx: Context, rows: list[dict[str, Any]]) -> None:
    """Write the report of a finished run from its recorded rows (`anytip report RUN_DIR`). A run
    recorded before validation losses went into its provenance has them in its shared models'
    metadata (`val_loss_by_budget`), which is read instead."""
    opts = parse_options(ctx)
    for key, losses in recorded_val_losses(ctx).items():
        ctx.provenance["cross_sensor"][key]["val_loss"] = losses
    write_report(ctx, rows, opts, recorded_metrics(ctx.provenance.get("targets")), data_family)


def recorded_val_losses(ctx: Context) -> dict[str, dict[str, dict[str, float]]]:
    """{seed key: {method: {budget: loss}}} of a finished run (`ctx.run_dir`): as its provenance
    records them, or, for a run recorded before validation losses went there, from its shared models'
    metadata (`saved_val_losses`)."""
    opts = parse_options(ctx)
    models = ctx.run_dir / "models"
    return {key: record["val_loss"] if "val_loss" in record else saved_val_losses(models, key, opts)
            for key, record in ctx.provenance.get("cross_sensor", {}).items()}


def saved_val_losses(models: Path, seed_key: str, opts: Options) -> dict[str, dict[str, float]]:
    """{method: {budget: loss}} from the metadata of a seed's saved shared models."""
    out: dict[str, dict[str, float]] = {}
    for kind, training in shared_models(opts):
        path = models / f"shared_{_slug(kind)}{_file_tag(training)}_{seed_key}.json"
        if path.is_file():
            meta = read_header(path, SHARED_FORMAT).get("meta", {})
            meta = meta if isinstance(meta, dict) else {}
            suffix = f"@{meta.get('plan_strategy')}" if meta.get("budget_unit") == "seconds" else ""
            for b, v in meta.get("val_loss_by_budget", {}).items():
                method = adapted_method(kind) + training_tag(training) + (suffix if float(b) > 0 else "")
                out.setdefault(method, {})[str(b)] = float(v)
    return out


def summarise(rows: list[dict[str, Any]], targets: dict[str, Any] | None = None) -> str:
    """One screen: mean RMSE and ratio to per_unit per (method, budget), for each target."""
    metrics = recorded_metrics(targets)
    head = "".join(f"{m.label:>22}{'ratio':>8}" for m in metrics)
    lines = [f"{'method':<46}{'budget':>8}{head}"]
    for s in summary(full_set_rows(rows), metrics):
        budget = "full" if s["budget"] < 0 else f"{s['budget']:g}"
        cells = "".join(f"{s[m.name]:>22.4g}{s[f'{m.name}_ratio']:>7.2f}x" for m in metrics)
        lines.append(f"{s['method']:<46}{budget:>8}{cells}")
    return "\n".join(lines)


def run_seed(ctx: Context, arrays: FleetArrays, opts: Options, seed: int,
             sweep: bool, extra: FleetArrays | None = None) -> list[dict[str, Any]]:
    spec = ctx.spec
    sd = prepare(ctx, arrays, opts, seed, extra)
    ctx.say(f"seed {seed}: {len(sd.split.train)} training, {len(sd.split.val)} validation and "
            f"{len(sd.split.test)} held-out units")
    held = "patches" if has_patch_grid(arrays.layout) else "blocks"
    base = {"seed": seed, "split": held, "n_train_units": len(sd.split.train)}
    if sd.n_extra:
        base["n_extra_units"] = sd.n_extra
    rows = [dict(base, **r) for r in per_unit_rows(ctx, arrays, sd, opts, seed)]
    ctx.say(f"seed {seed}: per-unit references trained")
    rows += [dict(base, **r) for r in scratch_rows(ctx, arrays, sd, opts, seed)]
    shape = shared_shape(ctx, opts)
    pooled = train_shared(sd.train, Scaler.pooled(sd.train.X_train, sd.train.n_train), shape,
                          "none", spec.training, seed, ctx.device, ctx.progress)
    rows += [dict(base, **r) for r in pooled_rows(pooled, arrays, sd)]
    priors_chosen: dict[str, dict[Budget, float]] = {}
    val_by_method: dict[str, dict[str, float]] = {}
    val_units_by_method: dict[str, dict[str, UnitLosses]] = {}
    own_by_method: dict[str, dict[str, dict[str, float | None]]] = {}
    for kind, training in shared_models(opts):
        tag = training_tag(training)
        episodes = (opts.episodic.recipe(), sd.press_index()) if training == "episodic" else None
        shared = train_shared(sd.train, sd.train_stats, shape, kind, spec.training, seed,
                              ctx.device, ctx.progress, opts.adapter_decay,
                              adapter_dropout=opts.adapter_dropout, episodes=episodes)
        ctx.say(f"seed {seed}: shared model {kind}{tag} trained")
        first: tuple[Adapted, PriorFamily, FitVariant] | None = None
        for family, fit in fit_methods(kind, opts, training):
            fit_kind = fit.kind(kind)
            got = adapted_rows(ctx, arrays, sd, opts, shared, seed, budget_list(opts), family=family, fit=fit,
                               tag=tag, intervals=first is None)
            rows += [dict(base, **r) for r in got.rows]
            method = adapted_method(fit_kind, family) + tag + fit.suffix()
            priors_chosen[method.removeprefix("adapted:")] = got.chosen
            val_by_method.update(validation_by_method(method, got.val_loss))
            val_units_by_method.update(validation_by_method(method, got.val_units))
            first = first or (got, family, fit)
            ctx.say(f"seed {seed}: {method} calibrated on every budget and prior")
        got, family, fit = first
        chosen = got.chosen
        strategy = calibrate_strategy(opts, got.val_loss)
        meta = shared_meta(shared, opts, chosen, seed, ctx.provenance.get("sensor_model"),
                           arrays.output_names, fit, strategy)
        meta["val_loss_by_budget"] = by_budget(got.val_loss, strategy)
        if got.interval_factors and opts.intervals is not None:
            meta["intervals"] = {"level": opts.intervals.level, "folds": opts.intervals.folds,
                                 "fleet_factor_by_budget": by_budget(
                                     {b: dict(zip(arrays.output_names, map(float, f), strict=True))
                                      for b, f in got.interval_factors.items()}, strategy)}
        checks = own_checks(arrays, sd, opts, shared, seed, chosen, family, fit, got.residuals)
        if checks:
            val = {b: [v for u, v in c.items() if u in sd.split.val and v is not None]
                   for b, c in checks.items()}
            meta["own_check_by_budget"] = by_budget(val, strategy)
            meta["own_check_folds"] = OWN_CHECK_FOLDS
            own_by_method[_slug(kind) + tag] = {b.label: c for b, c in checks.items()}
        path = ctx.run_dir / "models" / f"shared_{_slug(kind)}{_file_tag(training)}_seed{seed}.safetensors"
        save_shared(path, shared.model, shared.in_scaler, shared.out_scaler, meta)
    if opts.response is not None:
        got = response_rows(ctx, arrays, sd, opts, seed, extra=extra)
        rows += [dict(base, **r) for r in got.rows]
        val_by_method.update(response_val_by_method(got))
        val_units_by_method.update(response_val_by_method(got, per_unit=True))
    ctx.provenance.setdefault("cross_sensor", {})[f"seed{seed}"] = {
        "units": sd.split.to_json(), "val_loss": val_by_method, "val_loss_units": val_units_by_method,
        "priors_chosen": {k: {b.label: p for b, p in v.items()} for k, v in priors_chosen.items()},
        "test_patches": {u: np.unique(arrays.patch[e.test_rows]).tolist() for u, e in sd.evals.items()},
        "calibration_runs": {u: list(e.stream.runs) for u, e in sd.evals.items()},
        "own_check": {"validation_units": list(sd.split.val), "alarm_above": OWN_CHECK_ALARM,
                      "folds": OWN_CHECK_FOLDS, "by_shared_model": own_by_method},
    }
    if sweep:
        rows += unit_count_rows(ctx, arrays, sd, opts, seed, priors_chosen.get(opts.sweep_adapter, {}))
    return rows


def shared_models(opts: Options) -> list[tuple[str, Training]]:
    """(adapter kind, training) of every shared model a seed trains: the bare model (`none`,
    joint only) and each adapter kind with each of `shared_training`."""
    return [("none", "joint"), *((kind, t) for kind in opts.adapters for t in opts.shared_training)]


def _file_tag(training: Training) -> str:
    return "" if training == "joint" else f"_{training}"


def fit_methods(kind: str, opts: Options,
                training: Training = "joint") -> list[tuple[PriorFamily, FitVariant]]:
    """The (prior family, fit) pairs a shared model of `kind` is calibrated with: every family
    with every fit, the empirical prior only where the fitted kind is the shared one, inner fits
    only on episodic models (with no prior family of their own); the bare shared model
    (`none`) only as it is (input statistics, nothing fitted)."""
    if kind == "none":
        return [("identity", FitVariant())]
    fits = [f for f in opts.fits if training == "episodic" or not f.inner]
    return [(family, fit) for family in opts.adapter_priors for fit in fits
            if family == "identity" or not (fit.add or fit.inner)]


def adapted_method(kind: str, family: PriorFamily = "identity") -> str:
    """The method name of a shared model's rows: its adapter kind, and its prior family unless
    the identity prior (`adapted:input_affine+film/empirical`); plans add `@strategy`."""
    if kind == "none":
        return "adapted:input_stats"
    return f"adapted:{kind}" + ("" if family == "identity" else f"/{family}")


def pooled_rows(pooled: SharedFit, arrays: FleetArrays, sd: SeedData) -> list[dict[str, Any]]:
    """One network and one input scaling for every unit: the held-out units get tare only."""
    units = list(sd.split.test)
    folded = pooled.model.fold([0] * len(units))
    preds = predict_rows(folded, pooled.in_scaler.take([0] * len(units)), pooled.out_scaler, arrays,
                         [sd.evals[u].test_rows for u in units])
    return [{"method": "pooled", "unit": u, "calib_samples": 0, "calib_seconds": 0.0,
             **scores(p, arrays.targets[sd.evals[u].test_rows], arrays.layout)}
            for u, p in zip(units, preds, strict=True)]


def _slug(kind: str) -> str:
    return kind.replace("+", "-")


def per_unit_rows(ctx: Context, arrays: FleetArrays, sd: SeedData, opts: Options,
                  seed: int) -> list[dict[str, Any]]:
    """The reference (`per_unit`, the spec's model), and the same recipe in each of
    `reference_shapes` (`per_unit:<sizes>`)."""
    rows = reference_rows(ctx, arrays, sd, opts, seed, ctx.spec.model, "per_unit")
    for shape in opts.reference_shapes_for(ctx.spec.model, *_names(ctx)):
        name = "-".join(map(str, shape.sizes))
        rows += reference_rows(ctx, arrays, sd, opts, seed, shape, f"per_unit:{name}", f"_{name}")
    return rows


def reference_rows(ctx: Context, arrays: FleetArrays, sd: SeedData, opts: Options, seed: int,
                   shape: MLPConfig, method: str, tag: str = "") -> list[dict[str, Any]]:
    """Each held-out unit's MLP of `shape` on its full calibration minus its test patches,
    fitted with each of `reference_lrs` (or the recipe's lr) from each of `reference_starts`
    starts; each unit keeps the fit with the lowest loss on its own validation rows (random rows
    or whole patches: `reference_val`)."""
    units, members = list(sd.split.test), []
    main = main_rows(arrays, opts.calibration_protocol)
    recipe = opts.reference or ctx.spec.training
    for u, unit in enumerate(units):
        mine = unit_main_rows(arrays, unit, main)
        train_rows = mine[~np.isin(arrays.patch[mine], sd.evals[unit].test_cells)]
        if opts.reference_val == "patches":
            val = held_out_patches(arrays.patch[train_rows], ctx.spec.splits.val_fraction,
                                   stream_seed(VALIDATION_PATCHES, seed, u))
            members.append(unit_tensors(arrays, train_rows[~val], train_rows[val], unit))
            continue
        rng = np.random.default_rng(stream_seed(CALIBRATION_ROWS, seed, u))
        members.append(unit_tensors(arrays, *split_validation(train_rows, ctx.spec.splits.val_fraction, rng),
                                    unit))
    data = FleetBatchData.from_units(members, ctx.device, arrays.output_names)
    recipes = [recipe.model_copy(update={"lr": lr}) for lr in opts.reference_lrs] or [recipe]
    trials = reference_trials(opts)
    fits = [train_fleet(data, shape, recipes[k], seed=stream_seed(REFERENCE_START, seed, 1000 * j),
                        device=ctx.device, progress=ctx.progress) for k, j in trials]
    best = np.argmin(np.stack([best_val_loss(f) for f in fits]), axis=0)  # (units,) the fit each keeps
    for (k, j), fit in zip(trials, fits, strict=True):
        fit.save(ctx.run_dir / "models" / f"per_unit{tag}_seed{seed}{reference_tag(len(recipes), k, j)}")
    preds = [predict_rows(f.model, f.in_scaler, f.out_scaler, arrays, [sd.evals[u].test_rows for u in units])
             for f in fits]
    rows = []
    for k, u in enumerate(units):
        row = {"method": method, "unit": u, "calib_samples": int(data.n_train[k] + data.n_val[k]),
               "calib_seconds": None, **scores(preds[best[k]][k], arrays.targets[sd.evals[u].test_rows],
                                                        arrays.layout)}
        lr, start = trials[best[k]]
        if opts.reference_lrs:
            row["reference_lr"] = opts.reference_lrs[lr]
        if opts.reference_starts > 1:
            row["reference_start"] = start
        rows.append(row)
    return rows


def reference_trials(opts: Options) -> list[tuple[int, int]]:
    """Every reference fit as (learning rate, start), in the order they are trained: the index into
    `reference_lrs` (0 for the recipe's own) and the start, 0 to `reference_starts` - 1."""
    return [(k, j) for j in range(opts.reference_starts) for k in range(max(len(opts.reference_lrs), 1))]


def reference_tag(n_lrs: int, lr: int, start: int) -> str:
    """A saved reference fit's suffix: `_lr<lr>` where several learning rates were tried, and
    `_start<start>` for a start after the first (`per_unit_seed<s><suffix>`)."""
    return ("" if n_lrs <= 1 else f"_lr{lr}") + (f"_start{start}" if start else "")


def best_val_loss(fit: Any) -> np.ndarray:
    """(units,) each unit's lowest validation loss over a fleet fit's history."""
    return np.min(np.array([h["val_loss"] for h in fit.history], float), axis=0)


def unlabeled_fields(stream: CalibrationStream, seconds: float | None) -> dict[str, Any]:
    """How much unlabeled data a row's input statistics read: rows, and seconds where capped."""
    rows = stream.unlabeled(seconds)
    out: dict[str, Any] = {"unlabeled_samples": len(rows)}
    if seconds is not None:
        out["unlabeled_seconds"] = float(stream.seconds[len(rows) - 1]) if len(rows) else 0.0
    return out


def scratch_rows(ctx: Context, arrays: FleetArrays, sd: SeedData, opts: Options,
                 seed: int) -> list[dict[str, Any]]:
    """The paper's MLP trained on the budget alone (no held-out rows; no model selection)."""
    amounts = opts.budgets if opts.scratch_budgets is None else opts.scratch_budgets
    jobs = [(u, b, plan_of(sd, u, b, opts, seed)) for u in sd.split.test for b in budget_list(opts, amounts)
            if b.amount > 0]
    jobs = [j for j in jobs if len(j[2].rows)]
    if not jobs:
        return []
    members = [unit_tensors(arrays, plan.rows, plan.rows, f"{u}@{b.label}") for u, b, plan in jobs]
    data = FleetBatchData.from_units(members, ctx.device, arrays.output_names)
    fit = train_fleet(data, ctx.spec.model, opts.scratch, seed=seed, device=ctx.device,
                      progress=ctx.progress)
    preds = predict_rows(fit.model, fit.in_scaler, fit.out_scaler, arrays,
                         [sd.evals[u].test_rows for u, _, _ in jobs])
    return [{"method": "scratch" + plan_suffix(b), "unit": u, **budget_fields(b, plan),
             **scores(preds[k], arrays.targets[sd.evals[u].test_rows], arrays.layout)}
            for k, (u, b, plan) in enumerate(jobs)]


def adapted_rows(ctx: Context, arrays: FleetArrays, sd: SeedData, opts: Options, shared: SharedFit,
                 seed: int, budgets: list[Budget], fixed_priors: dict[Budget, float] | None = None,
                 family: PriorFamily = "identity", fit: FitVariant = PLAIN_FIT,
                 tag: str = "", intervals: bool = False
                 ) -> Adapted:
    """Rows of one shared model on the held-out units at every budget, the prior chosen
    per budget on the validation units (given `fixed_priors`, those are used instead), and
    the validation units' mean standardised MSE per budget at that prior (empty when fixed).
    Adapters are fitted as `fit` says (`FitVariant`; an inner fit takes no prior); `tag` names
    the shared model's training in the method. With `intervals` (and `options.intervals`), each
    row with labels also holds its unit's interval coverage (`interval_fields`), and the
    result the fleet factor of the intervals per budget (`plan_bands`)."""
    fit_kind = fit.kind(shared.model.kind)
    kind = fit_kind
    method = adapted_method(kind, family) + tag + fit.suffix()
    fits = kind != "none"
    if fit.inner:
        priors_of = {b: [0.0] for b in budgets if b.amount > 0}
    elif fixed_priors is not None:
        priors_of = {b: [fixed_priors[b]] for b in budgets if b.amount > 0}
    else:
        priors_of = {b: list(opts.priors) for b in budgets if b.amount > 0}
    recipe = fit.recipe(opts, shared.inner_lr)
    prior = make_prior(family, shared.model, opts.prior_rank) if fits and kind == shared.model.kind else None
    plans: dict[tuple[str, Budget], Plan] = {}

    def fitted(units: Sequence[str]) -> list[tuple[Job, np.ndarray]]:
        jobs = planned_jobs(sd, opts, seed, units, budgets, priors_of, fits, plans)
        return fit_jobs(shared, arrays, sd, opts, seed, jobs, plans, recipe, fit_kind, prior)

    chosen, val_units = dict(fixed_priors or {}), {}
    validation: list[tuple[Job, np.ndarray]] = []
    if fixed_priors is None:
        # the prior is chosen on the validation units before any held-out unit is fitted
        validation = fitted(sd.split.val)
        loss = validation_losses([j for j, _ in validation], [p for _, p in validation], sd, arrays,
                                 set(sd.split.val), shared.out_scaler)
        chosen = choose_priors(loss)
        val_units = {b: v for (b, p), v in loss.items() if p == chosen.get(b, p)}
        priors_of = {b: [chosen.get(b, ps[0] if len(ps) == 1 else default_prior(opts))]
                     for b, ps in priors_of.items()}
    held_out = fitted(sd.split.test)
    at_chosen = [(job, pred) for job, pred in validation + held_out
                 if job[1].amount == 0 or job[2] == chosen.get(job[1], job[2])]
    kept = [(job, pred) for job, pred in at_chosen if job[0] in sd.split.test]
    bands: list[dict[str, Any]] = [{} for _ in kept]
    factors: dict[Budget, np.ndarray] = {}
    resid: PlanResiduals = {}
    if intervals and opts.intervals is not None:
        bands, factors, resid = plan_bands(shared, arrays, sd, opts, at_chosen, plans, recipe, seed, fit_kind,
                                           prior)
    rows = []
    for ((u, b, p), pred), band in zip(kept, bands, strict=True):
        rows.append({"method": method + plan_suffix(b), "unit": u, **budget_fields(b, plans[(u, b)]),
                     **unlabeled_fields(sd.evals[u].stream, opts.unlabeled_s),
                     "prior": p if b.amount > 0 else None,
                     **scores(pred, arrays.targets[sd.evals[u].test_rows], arrays.layout), **band})
    return Adapted(rows, chosen, val_units, factors, resid)




def planned_jobs(sd: SeedData, opts: Options, seed: int, units: Sequence[str], budgets: list[Budget],
                 priors_of: dict[Budget, list[float]], fits: bool,
                 plans: dict[tuple[str, Budget], Plan]) -> list[Job]:
    """Every (unit, budget, prior) of `units` whose plan buys at least one press (budget 0 at
    prior 0, and only budget 0 for a shared model without adapters); the plans are added to
    `plans`."""
    jobs = [(u, b, p) for u in units for b in budgets
            for p in (priors_of.get(b, [0.0]) if b.amount > 0 else [0.0]) if fits or b.amount == 0]
    for u, b, _ in jobs:
        if (u, b) not in plans:
            plans[(u, b)] = plan_of(sd, u, b, opts, seed)
    # a budget that buys no press (too short, or no designed run of the unit) has no row
    return [(u, b, p) for u, b, p in jobs if b.amount == 0 or len(plans[(u, b)].rows)]


def fit_jobs(shared: SharedFit, arrays: FleetArrays, sd: SeedData, opts: Options, seed: int,
             jobs: list[Job], plans: dict[tuple[str, Budget], Plan], recipe: AdapterRecipe,
             fit_kind: str, prior: AdapterPrior | None) -> list[tuple[Job, np.ndarray]]:
    """Each job's adapter fitted and folded on its plan (one batch), with its physical
    predictions (n_test, D) on its unit's test rows."""
    if not jobs:
        return []
    folded, stats = calibrate_many(shared, arrays, [sd.evals[u].stream.unlabeled(opts.unlabeled_s)
                                                    for u, _, _ in jobs],
                                   [plans[(u, b)] for u, b, _ in jobs], [p for _, _, p in jobs], recipe,
                                   seed, fit_kind, prior)
    preds = predict_rows(folded, stats, shared.out_scaler, arrays,
                         [sd.evals[u].test_rows for u, _, _ in jobs])
    return list(zip(jobs, preds, strict=True))


def plan_bands(shared: SharedFit, arrays: FleetArrays, sd: SeedData, opts: Options,
               at_chosen: list[tuple[Job, np.ndarray]], plans: dict[tuple[str, Budget], Plan],
               recipe: AdapterRecipe, seed: int, fit_kind: str, prior: AdapterPrior | None
               ) -> tuple[list[dict[str, Any]], dict[Budget, np.ndarray], PlanResiduals]:
    """Intervals of the held-out units among `at_chosen` ((unit, budget, prior), test-row
    prediction) from their own plans (`interval_fields`, one dict per held-out job in order),
    the fleet factor per budget (D,) learnt on the validation units among them (how much wider
    their test rows needed the interval than their plan's out-of-fold residuals said;
    `uncertainty.conformal.fleet_factor`), and every plan's out-of-fold residuals. All plans'
    fold fits run as one batch. A plan of fewer presses than folds is cross-fitted one press per
    fold (its residuals serve the own check) but gets no interval."""
    assert opts.intervals is not None
    level, names, folds = opts.intervals.level, arrays.output_names, opts.intervals.folds
    labeled = [k for k, ((_, b, _), _) in enumerate(at_chosen) if b.amount > 0]
    jobs = [at_chosen[k][0] for k in labeled]
    unlabeled = [sd.evals[u].stream.unlabeled(opts.unlabeled_s) for u, _, _ in jobs]
    resid = plan_residuals(shared, arrays, unlabeled, [plans[(u, b)] for u, b, _ in jobs],
                           [p for _, _, p in jobs], recipe, seed, fit_kind, prior, folds, fewer=True)
    by_job = {k: r if plans[(u, b)].presses >= folds else None
              for k, (u, b, _), r in zip(labeled, jobs, resid, strict=True)}
    fleet = validation_factors(at_chosen, by_job, sd, arrays, level)
    bands = []
    for k, ((u, b, _), pred) in enumerate(at_chosen):
        if u in sd.split.test:
            test = sd.evals[u].test_rows
            bands.append(interval_fields(by_job.get(k), pred, arrays.targets[test], names, level,
                                         fleet.get(b), arrays.patch[test], k))
    by_plan = {(u, b): r for (u, b, _), r in zip(jobs, resid, strict=True)}
    return bands, {b: f.factor for b, f in fleet.items()}, by_plan


def own_checks(arrays: FleetArrays, sd: SeedData, opts: Options, shared: SharedFit, seed: int,
               chosen: dict[Budget, float], family: PriorFamily, fit: FitVariant,
               known: PlanResiduals | None = None) -> dict[Budget, dict[str, float | None]]:
    """Budget -> validation or held-out unit -> its calibration's own check at the chosen
    prior (`train.shared_split.own_check_losses`: every press predicted by the adapter refitted
    without its fold). Budgets in robot seconds only (a stream prefix has no presses to hold out);
    empty for a shared model without adapters. `known`: out-of-fold residuals the intervals
    already cross-fitted at these priors, used as they are where their fold count is the check's."""
    kind = fit.kind(shared.model.kind)
    budgets = [b for b in chosen if b.amount > 0 and b.unit == "seconds"]
    if kind == "none" or not budgets:
        return {}
    if known is None or opts.intervals is None or opts.intervals.folds != OWN_CHECK_FOLDS:
        known = {}
    jobs = [(u, b) for b in budgets for u in [*sd.split.val, *sd.split.test]]
    todo = [job for job in jobs if job not in known]
    prior = make_prior(family, shared.model, opts.prior_rank) if kind == shared.model.kind else None
    unlabeled = [sd.evals[u].stream.unlabeled(opts.unlabeled_s) for u, _ in todo]
    recipe = fit.recipe(opts, shared.inner_lr)
    fresh = own_check_losses(shared, arrays, unlabeled, [plan_of(sd, u, b, opts, seed) for u, b in todo],
                             [chosen[b] for _, b in todo], recipe, seed, kind, prior) if todo else []
    losses = dict(zip(todo, fresh, strict=True))
    losses.update({job: own_check_loss(known[job], shared.out_scaler) for job in jobs if job in known})
    out: dict[Budget, dict[str, float | None]] = {}
    for u, b in jobs:
        out.setdefault(b, {})[u] = losses[(u, b)]
    return out


def choose_priors(loss: dict[tuple[Budget, float], UnitLosses]) -> dict[Budget, float]:
    """Per budget > 0, the prior with the lowest mean validation loss."""
    chosen: dict[Budget, float] = {}
    for (b, p), v in sorted(loss.items(), key=lambda kv: (kv[0][0].amount, kv[0][0].strategy, kv[0][1])):
        if b.amount == 0:
            continue
        if b not in chosen or mean_loss(v) < mean_loss(loss[(b, chosen[b])]):
            chosen[b] = p
    return chosen


def unit_count_rows(ctx: Context, arrays: FleetArrays, sd: SeedData, opts: Options, seed: int,
                    priors: dict[Budget, float]) -> list[dict[str, Any]]:
    """The sweep adapter's shared model trained on fewer units: zero-shot and one budget."""
    rows = []
    order = list(np.random.default_rng(seed).permutation(len(sd.split.train)))
    budgets = budget_list(opts, sorted({0, opts.sweep_budget}))
    for k in opts.train_unit_counts:
        if k >= len(sd.split.train):
            continue
        keep = sorted(order[:k])
        sub = sd.train.subset(keep)
        stats = sd.train_stats.take(keep)
        shared = train_shared(sub, stats, shared_shape(ctx, opts), opts.sweep_adapter, ctx.spec.training,
                              seed, ctx.device, ctx.progress, opts.adapter_decay)
        fixed = {b: priors.get(b, default_prior(opts)) for b in budgets if b.amount > 0}
        kind_rows = adapted_rows(ctx, arrays, sd, opts, shared, seed, budgets, fixed).rows
        rows += [dict(r, seed=seed, split="patches", n_train_units=k) for r in kind_rows]
    return rows


def default_prior(opts: Options) -> float:
    """The middle of the prior grid: used where no validation choice exists."""
    return sorted(opts.priors)[len(opts.priors) // 2]


def calibrate_strategy(opts: Options, val_loss: dict[Budget, float] | None = None) -> Strategy:
    """The press selection `anytip calibrate` uses for a budget in seconds: where the spec
    compared several and `val_loss` (budget -> validation units' loss at the chosen prior) has
    them all at the same labeled budgets, the one with the lowest mean loss over those budgets;
    else spread where the spec compared it, else the spec's first (plans chosen with a response
    model are the response method's alone; a spec of them alone gives its adapters `cover`)."""
    mine = plan_strategies(opts) or ["cover"]
    losses = {s: [v for b, v in (val_loss or {}).items() if b.unit == "seconds" and b.amount > 0
                  and b.strategy == s] for s in mine}
    if len(losses) > 1 and all(losses.values()) and len({len(v) for v in losses.values()}) == 1:
        return min(mine, key=lambda s: float(np.mean(losses[s])))
    return "spread" if "spread" in mine else mine[0]


def by_budget(values: dict[Budget, Any], strategy: Strategy) -> dict[str, Any]:
    """Per-budget values keyed by amount (samples, or seconds of `strategy`, calibrate's)."""
    keep = {b: v for b, v in values.items() if b.unit == "samples" or b.strategy == strategy}
    return {(str(int(b.amount)) if b.unit == "samples" else f"{b.amount:g}"): v
            for b, v in sorted(keep.items(), key=lambda kv: kv[0].amount)}


def shared_meta(shared: SharedFit, opts: Options, chosen: dict[Budget, float], seed: int,
                sensor_model: str | None, output_names: tuple[str, ...],
                fit: FitVariant = PLAIN_FIT, strategy: Strategy = "spread") -> dict[str, Any]:
    """What `anytip calibrate` needs to fit a new unit's adapter like the benchmark's `fit` did
    (its steps, or the inner fit's step sizes; an `add` fit is calibrated without the part),
    with the plans of `strategy`."""
    recipe = fit.recipe(opts, shared.inner_lr)
    return {"unit_ids": shared.unit_ids, "seed": seed, "sensor_model": sensor_model,
            "recipe": shared.recipe.model_dump(mode="json"),
            "priors_by_budget": by_budget(chosen, strategy), "budget_unit": opts.budget_unit,
            "plan_strategy": strategy, "rig": opts.rig.model_dump(),
            "adapter_prior": opts.adapter_priors[0], "prior_rank": opts.prior_rank,
            "unlabeled_s": opts.unlabeled_s,
            "default_prior": default_prior(opts),
            "adapter_recipe": {"steps": recipe.steps, "lr": recipe.lr,
                               **({} if recipe.rates is None else {"rates": recipe.rates})},
            "calibration_protocol": opts.calibration_protocol,
            "calibration_interleave": opts.calibration_interleave,
            "output_names": list(output_names),
            **({} if shared.inner_lr is None else {"inner_lr": shared.inner_lr})}
