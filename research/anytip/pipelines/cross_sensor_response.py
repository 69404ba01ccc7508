"""The cross_sensor method `response`: each validation and held-out unit calibrated by response
transfer (train/response.py) at every labeled budget, scored on its test patches like every other
method. The response model is trained once per seed on the training units and saved with the run
(`models/response_seed<s>.safetensors`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
import torch
from torch import Tensor

from anytip.data.arrays import FleetArrays
from anytip.data.plans import INFORMED, Budget, Plan
from anytip.errors import AnytipError
from anytip.models.io import LoadedResponse, ModelFileError, load_response, save_response
from anytip.models.scaler import Scaler
from anytip.pipelines.common import Context
from anytip.pipelines.cross_sensor_jobs import (
    FleetWidths,
    Job,
    UnitLosses,
    budget_fields,
    interval_fields,
    mean_loss,
    plan_of,
    plan_suffix,
    scaled_fields,
    validation_by_method,
    validation_factors,
    validation_losses,
)
from anytip.pipelines.cross_sensor_label_free import METHOD as LABEL_FREE
from anytip.pipelines.cross_sensor_label_free import (
    OrdinaryUse,
    label_free_rows,
    plan_use_codes,
    read_ordinary_use,
    use_fields,
    use_rows_for,
)
from anytip.pipelines.cross_sensor_options import Options, budget_list
from anytip.train.data import FleetBatchData
from anytip.train.fleet import FitResult
from anytip.train.label_free import WITH_USE, with_use_method
from anytip.train.metrics import scores
from anytip.train.response import (
    ResponseFit,
    ResponseRecipe,
    SourceRows,
    calibrate_by_response,
    grouped_networks,
    plan_residual,
    press_information,
    source_rows,
    start_network,
    start_network_path,
    train_response,
    training_digest,
    transferred,
)
from anytip.train.shared_split import SeedData, predict_rows
from anytip.uncertainty.fleet_margin import Learner

METHOD = "response"


class ResponseRows(NamedTuple):
    """Rows of the held-out units, and the validation units' mean standardised MSE per budget and
    of the zero-shot `response:label_free` (None where it did not run)."""

    rows: list[dict[str, Any]]
    val_units: dict[Budget, UnitLosses]
    label_free_units: UnitLosses | None = None
    use_val_units: dict[Budget, UnitLosses] = {}  # noqa: RUF012  (a NamedTuple's default, never mutated)
    use_method: str = WITH_USE  # the method of use_val_units's rows (`with_use_method`)

    @property
    def val_loss(self) -> dict[Budget, float]:
        """The validation units' mean loss per budget, plan alone."""
        return {b: mean_loss(v) for b, v in self.val_units.items()}

    @property
    def use_val_loss(self) -> dict[Budget, float]:
        """The same with ordinary use."""
        return {b: mean_loss(v) for b, v in self.use_val_units.items()}

    @property
    def label_free_loss(self) -> float | None:
        """The zero-shot row's validation units' mean loss."""
        return None if not self.label_free_units else mean_loss(self.label_free_units)


def response_rows(ctx: Context, arrays: FleetArrays, sd: SeedData, opts: Options, seed: int,
                  fit: ResponseFit | None = None, extra: FleetArrays | None = None) -> ResponseRows:
    """Every validation and held-out unit calibrated by response transfer on the plan each labeled
    budget grants it; rows of the held-out units (`response@<strategy>`), with the RMS of the
    plan's pressures about the unit's fitted response (`response_residual_pa`, its own check).
    `fit`: a response model trained before on `sd`'s training units (None: train it here); `extra`:
    the run's extra units (the label-free row's code encoder reads their ordinary use)."""
    assert opts.response is not None
    recipe = opts.response.recipe()
    digest = None  # a model handed in was trained elsewhere: its file records no digest
    if fit is None:
        fit, digest = trained_response(ctx, sd, arrays, opts, seed)
    check_trained_on(fit.unit_ids, sd.train.unit_ids, [*sd.split.val, *sd.split.test, *sd.split.factor], seed)
    fit = fit.with_code_prior(recipe.code_prior, registry_units(sd))
    jobs = labeled_jobs(sd, [*sd.split.val, *sd.split.test], opts, seed, fit, arrays)
    factor_jobs = (labeled_jobs(sd, list(sd.split.factor), opts, seed, fit, arrays)
                   if opts.intervals is not None else [])
    rows: list[dict[str, Any]] = []
    val_units: dict[Budget, UnitLosses] = {}
    residual: dict[Budget, list[float]] = {}
    free_units = None
    if jobs or opts.response.label_free is not None:
        source = source_rows(fit, source_units(sd, recipe), recipe.source_rows, seed)
        start = None
        if recipe.inverse_start == "pooled":
            start = start_network(source, ctx.spec.model, recipe, seed, arrays.output_names, ctx.progress)
            start.save(start_network_path(response_path(ctx, seed)))
    bands, factor = Bands({}, {}, {}), None
    if jobs:
        mine = calibrated(ctx, arrays, sd, fit, (source, start), recipe, jobs, seed)
        X, Y, codes, preds = mine.X, mine.Y, mine.codes, mine.preds
        val_units = budget_losses(preds, jobs, sd, arrays)
        if opts.intervals is not None:
            checks = None
            if opts.intervals.transfer_check:  # each unit's network again, on its transferred rows alone
                checks = grouped_networks(
                    lambda m: (transferred(fit, source, codes[m], X[m], Y[m], recipe), source.Y),
                    fleet_groups(jobs, sd.split.test), ctx.spec.model, recipe, seed,
                    [f"{u}@{b.label}" for u, b, _ in jobs], arrays.output_names, fit.device, ctx.progress,
                    start)
            if factor_jobs:
                factor = calibrated(ctx, arrays, sd, fit, (source, start), recipe, factor_jobs, seed)
            bands = plan_bands(mine.nets, arrays, sd, mine.at(), mine.plans(), opts.intervals.level, checks,
                               factor)
        for m, ((u, b, plan), pred) in enumerate(zip(jobs, preds, strict=True)):
            own = plan_residual(fit, X[m], Y[m], codes[m])
            if u in sd.split.val:
                residual.setdefault(b, []).append(own)
                continue
            rows.append({"method": METHOD + plan_suffix(b), "unit": u, **budget_fields(b, plan),
                         "response_residual_pa": own,
                         **scores(pred, arrays.targets[sd.evals[u].test_rows], arrays.layout),
                         **bands.fields.get(m, {})})
        ctx.say(f"seed {seed}: {len(jobs)} units and budgets calibrated by response transfer")
    use_units: dict[Budget, UnitLosses] = {}
    use_bands = Bands({}, {}, {})
    saved_use: dict[str, Any] = {}  # what calibrate reads a new unit's ordinary use with
    if opts.response.label_free is not None:
        assert start is not None  # the option needs inverse_start: pooled
        read = read_ordinary_use(arrays, sd, opts, seed, fit, source, start, extra)
        if opts.response.label_free.zero_shot:
            free_rows, free_units = label_free_rows(ctx, arrays, sd, opts, seed, fit, source, start, read)
            rows += free_rows
        saved_use["label_free"] = read.fleet.to_json()
        if opts.response.label_free.with_plans and jobs:
            use_rows, use_units, use_bands = with_use_rows(ctx, arrays, sd, opts, seed, fit, (source, start),
                                                          read, mine, factor)
            rows += use_rows
    free = opts.response.label_free
    got = ResponseRows(rows, val_units, free_units, use_units,
                       WITH_USE if free is None else with_use_method(free.recipe()))
    meta = {**response_meta(ctx, sd, arrays, recipe, seed, fit, digest),
            "val_loss_by_strategy": by_strategy(got.val_loss),
            "residual_by_strategy": by_strategy(residual), **saved_use}
    if opts.response.plan_strategy is not None:  # anytip calibrate takes it over the validation units' choice
        meta["decided_plan_strategy"] = opts.response.plan_strategy
    if got.label_free_loss is not None:
        meta["label_free_val_loss"] = got.label_free_loss
    if use_units:
        meta["use_val_loss_by_strategy"] = by_strategy(got.use_val_loss)
    if opts.intervals is not None and jobs:
        meta["intervals"] = intervals_meta(opts.intervals.level, arrays.output_names, bands, use_bands,
                                           len(sd.split.factor))
    save_response(response_path(ctx, seed), fit.model, fit.noise_var, fit.code_var, meta)
    return got


def with_use_rows(ctx: Context, arrays: FleetArrays, sd: SeedData, opts: Options, seed: int, fit: ResponseFit,
                  carry: tuple[SourceRows, FitResult], read: OrdinaryUse,
                  plans: Calibrated, factor: Calibrated | None = None
                  ) -> tuple[list[dict[str, Any]], dict[Budget, UnitLosses], Bands]:
    """Rows `response+use@<strategy>` of the held-out units, the validation units' loss per budget
    and, with `options.intervals`, their intervals (`plan_bands`; the factor units, `factor` as
    `response@` calibrated them, calibrated again the same way, learn its fleet factor too): every
    job (unit, budget, plan) calibrated again as
    `response@` is (`carry`: the source rows and the start network), its codes from one joint fit
    of its plan's rows and its unit's ordinary use `read`, started from the plan's own codes
    (`plans`: the jobs as `response@` calibrated them; entry 45). Each network keeps its job's id,
    so it starts as the job's `response@` network did and the two differ by their codes alone."""
    assert opts.response is not None
    recipe, jobs = opts.response.recipe(), plans.jobs
    joint, fitted = plan_use_codes(fit, opts, read, seed, [(u, p) for u, _, p in jobs], plans.X, plans.Y,
                                   plans.codes)
    extra = [use_rows_for(read, arrays, u, c) for (u, _, _), c in zip(jobs, fitted, strict=True)]
    mine = calibrated(ctx, arrays, sd, fit, carry, recipe, jobs, seed, joint, extra)
    ctx.say(f"seed {seed}: {len(jobs)} units and budgets calibrated with their ordinary use")
    bands = Bands({}, {}, {})
    if opts.intervals is not None:
        with_use = None
        if factor is not None:  # the factor units' joint fit from their plan codes, as the jobs' own
            pairs = [(u, p) for u, _, p in factor.jobs]
            both, found = plan_use_codes(fit, opts, read, seed, pairs, factor.X, factor.Y, factor.codes)
            more = [use_rows_for(read, arrays, u, c) for (u, _), c in zip(pairs, found, strict=True)]
            with_use = calibrated(ctx, arrays, sd, fit, carry, recipe, factor.jobs, seed, both, more)
        bands = plan_bands(mine.nets, arrays, sd, mine.at(), mine.plans(), opts.intervals.level,
                           factor=with_use)
    rows = [{"method": with_use_method(read.fleet.free) + plan_suffix(b), "unit": u, **budget_fields(b, plan),
             **use_fields(read.uses[u]), **scores(pred, arrays.targets[sd.evals[u].test_rows], arrays.layout),
             **bands.fields.get(m, {})}
            for m, ((u, b, plan), pred) in enumerate(zip(jobs, mine.preds, strict=True))
            if u in sd.split.test]
    return rows, budget_losses(mine.preds, jobs, sd, arrays), bands


def labeled_jobs(sd: SeedData, units: list[str], opts: Options, seed: int, fit: ResponseFit,
                 arrays: FleetArrays) -> list[tuple[str, Budget, Plan]]:
    """(unit, budget, plan) of `units` at every labeled budget whose plan holds rows; `informative`
    and `cover_informative` plans choose presses for what they tell `fit`'s codes."""
    assert opts.response is not None
    budgets = [b for b in budget_list(opts, response=True) if b.amount > 0]
    jobs = []
    for u in units:
        information = None
        if any(b.strategy in INFORMED for b in budgets):
            information = press_information(fit, arrays, sd.evals[u].presses, opts.rig.effective_hz,
                                            opts.response.recipe().plan_criterion)
        jobs += [(u, b, plan_of(sd, u, b, opts, seed, information)) for b in budgets]
    return [j for j in jobs if len(j[2].rows)]


class Calibrated(NamedTuple):
    """Jobs (unit, budget, plan) calibrated by response transfer in one batched fleet: each job's
    plan rows X[m] (n_m, C) Pa, Y[m] (n_m, D), codes (M, C, k), networks, test-row predictions."""

    jobs: list[tuple[str, Budget, Plan]]
    X: list[Tensor]
    Y: list[Tensor]
    codes: Tensor
    nets: FitResult
    preds: list[np.ndarray]

    def at(self) -> list[tuple[Job, np.ndarray]]:
        """((unit, budget, 0), test-row prediction) per job, as `plan_bands` takes them."""
        return [((u, b, 0.0), p) for (u, b, _), p in zip(self.jobs, self.preds, strict=True)]

    def plans(self) -> list[Plan]:
        return [p for _, _, p in self.jobs]


def fleet_groups(jobs: list[tuple[str, Budget, Plan]], held_out: Sequence[str]) -> list[tuple[Budget, bool]]:
    """Each job's batched fleet (`calibrate_by_response`'s `groups`): its budget, so a job trains for
    as many steps as `anytip calibrate` gives its plan whatever other budgets the run holds, and
    whether its unit is held out, so no held-out unit's rows reach a validation or factor unit's
    network (a fleet's epoch is its largest job's rows, and a job's draws are those of its index)
    and what those units choose (budgets, plans, the fleet factor and its margin) is the same
    whichever units are held out."""
    test = set(held_out)
    return [(b, u in test) for u, b, _ in jobs]


def calibrated(ctx: Context, arrays: FleetArrays, sd: SeedData, fit: ResponseFit,
               carry: tuple[SourceRows, FitResult | None], recipe: ResponseRecipe,
               jobs: list[tuple[str, Budget, Plan]], seed: int, codes: Tensor | None = None,
               extra: list[tuple[Tensor, Tensor] | None] | None = None) -> Calibrated:
    """`jobs` calibrated by response transfer with `recipe` (`carry`: the source rows and the start
    network), their codes fitted on their plans or given (`codes`, (M, C, k)), each network also
    trained on its job's `extra` rows where given (`calibrate_by_response`), one batched fleet per
    budget and role (`fleet_groups`), and scored on their units' test rows."""
    source, start = carry
    X = [torch.from_numpy(arrays.pressure[p.rows]) for _, _, p in jobs]
    Y = [torch.from_numpy(arrays.targets[p.rows]) for _, _, p in jobs]
    ids = [f"{u}@{b.label}" for u, b, _ in jobs]
    nets, got = calibrate_by_response(fit, source, X, Y, [p.n_effective for _, _, p in jobs], ctx.spec.model,
                                      recipe, seed, ids, arrays.output_names, ctx.progress, start, codes,
                                      extra, fleet_groups(jobs, sd.split.test))
    preds = predict_rows(nets.model, nets.in_scaler, nets.out_scaler, arrays,
                         [sd.evals[u].test_rows for u, _, _ in jobs])
    return Calibrated(jobs, X, Y, got, nets, preds)


def intervals_meta(level: float, names: tuple[str, ...], bands: Bands, use_bands: Bands,
                   n_factor_units: int) -> dict[str, Any]:
    """What a response model records of its benchmark's intervals for `anytip calibrate`: the fleet
    factors per strategy and budget (`use_`: codes fitted with ordinary use), the spread of
    log(needed / own half-width), the factors' leave-one-unit-out margins (`margin_by_strategy`:
    the margin, and per grid value the left-out unit-outputs below the floor and the share in the
    band), and each validation and factor unit's half-widths (`units_by_strategy`)."""
    def named(widths: dict[Budget, FleetWidths]) -> dict[str, dict[str, Any]]:
        return by_strategy({b: dict(zip(names, map(float, w.factor), strict=True))
                            for b, w in widths.items()})

    def learners(widths: dict[Budget, FleetWidths]) -> dict[str, dict[str, Any]]:
        return by_strategy({b: {u: {f: dict(zip(names, map(float, getattr(x, f)), strict=True))
                                    for f in Learner._fields} for u, x in w.learners.items()}
                            for b, w in widths.items()})

    def margins(widths: dict[Budget, FleetWidths]) -> dict[str, dict[str, Any]]:
        return by_strategy({b: {"margin": w.margin.margin,
                                "below_floor": {f"{m:g}": v for m, v in w.margin.below.items()},
                                "in_band": {f"{m:g}": v for m, v in w.margin.in_band.items()}}
                            for b, w in widths.items()})

    spreads = {kind: by_strategy({b: _finite_by_name(names, f) for b, f in spread.items()})
               for kind, spread in bands.spreads.items()}
    return {"level": level, "residuals": INTERVAL_RESIDUALS, "factor_units": n_factor_units,
            "fleet_factor_by_strategy": named(bands.widths),
            "use_fleet_factor_by_strategy": named(use_bands.widths),
            "margin_by_strategy": margins(bands.widths), "use_margin_by_strategy": margins(use_bands.widths),
            "log_ratio_spread_by_strategy": spreads,
            "units_by_strategy": learners(bands.widths), "use_units_by_strategy": learners(use_bands.widths)}


def budget_losses(preds: list[np.ndarray], jobs: list[tuple[str, Budget, Plan]], sd: SeedData,
                  arrays: FleetArrays) -> dict[Budget, UnitLosses]:
    """Each validation unit's standardised MSE per budget of the jobs' predictions."""
    loss = validation_losses([(u, b, 0.0) for u, b, _ in jobs], preds, sd, arrays, set(sd.split.val),
                             Scaler.pooled(sd.train.Y_train, sd.train.n_train))
    return {b: v for (b, _), v in loss.items()}


def val_by_method(got: ResponseRows, per_unit: bool = False) -> dict[str, dict[str, Any]]:
    """{row method: {budget: validation-unit loss}} of every method of response transfer's rows: the
    mean, or with `per_unit` each validation unit's (`UnitLosses`)."""
    plan, use, free = ((got.val_units, got.use_val_units, got.label_free_units) if per_unit
                       else (got.val_loss, got.use_val_loss, got.label_free_loss))
    out = validation_by_method(METHOD, plan) | validation_by_method(got.use_method, use)
    if free is not None:
        out[LABEL_FREE] = {"0": free}
    return out


def _finite_by_name(names: tuple[str, ...], values: np.ndarray) -> dict[str, float | None]:
    """{output name: value}, None where it is not finite (JSON has no NaN)."""
    return {n: float(v) if np.isfinite(v) else None for n, v in zip(names, values, strict=True)}


def trained_response(ctx: Context, sd: SeedData, arrays: FleetArrays, opts: Options,
                     seed: int) -> tuple[ResponseFit, str]:
    """The seed's response model and its `training_digest` (rows, shape, recipe, seed), saved in
    the run directory as soon as it is trained. A run resumed in place after an interruption
    reuses the model it saved there when that model's digest is this one's; any other file is
    trained over."""
    assert opts.response is not None
    recipe, config, force_cols = opts.response.recipe(), opts.response.config(), arrays.force_columns
    digest = training_digest(sd.train, force_cols, config, recipe, seed)
    path = response_path(ctx, seed)
    saved = saved_response(path)
    if saved is not None and saved.meta.get("training_digest") == digest:
        ctx.say(f"seed {seed}: response model reused from the interrupted run ({path})")
        return ResponseFit.from_loaded(saved), digest
    fit = train_response(sd.train, force_cols, config, recipe, seed, ctx.device, ctx.progress)
    ctx.say(f"seed {seed}: response model trained ({fit.wall_s:.0f} s)")
    save_response(path, fit.model, fit.noise_var, fit.code_var,
                  response_meta(ctx, sd, arrays, recipe, seed, fit, digest))
    return fit, digest


def check_trained_on(learnt: Sequence[str], train: Sequence[str], new: Sequence[str], seed: int) -> None:
    """A response model that learnt the units `learnt` can calibrate a split's units only if it
    learnt every training unit of the split (their codes carry the rows over) and none of its
    validation or held-out units (`new`). A model trained elsewhere may have learnt more units
    (many simulated ones, say) beside them."""
    known = set(learnt)
    missing = [u for u in train if u not in known]
    if missing:
        raise AnytipError(f"seed {seed}: the response model was not trained on the split's training units "
                          f"{', '.join(missing[:4])}{' ...' if len(missing) > 4 else ''}")
    seen = [u for u in new if u in known]
    if seen:
        raise AnytipError(f"seed {seed}: the response model was trained on validation or held-out units "
                          f"{', '.join(seen[:4])}{' ...' if len(seen) > 4 else ''}")


def response_path(ctx: Context, seed: int) -> Path:
    """Where the run keeps the seed's response model."""
    return ctx.run_dir / "models" / f"response_seed{seed}.safetensors"


def saved_response(path: Path) -> LoadedResponse | None:
    """The response model at `path`, or None where there is none or it cannot be read (a file an
    interruption cut short)."""
    if not path.exists():
        return None
    try:
        return load_response(path)
    except ModelFileError:
        return None


def response_meta(ctx: Context, sd: SeedData, arrays: FleetArrays, recipe: ResponseRecipe, seed: int,
                  fit: ResponseFit, digest: str | None) -> dict[str, Any]:
    """What a response model file records of its training (`training_digest`: None for a model
    trained elsewhere), of the rows `anytip calibrate` transfers (`source_unit_ids`) and of the
    registry's own training units (`registry_unit_ids`, what the `registry` code prior is centred on)."""
    return {"unit_ids": fit.unit_ids, "source_unit_ids": list(sd.train.unit_ids[:n_sources(sd, recipe)]),
            "registry_unit_ids": registry_units(sd),
            "seed": seed, "output_names": list(arrays.output_names), "recipe": asdict(recipe),
            "wall_s": fit.wall_s, "shape": ctx.spec.model.model_dump(mode="json"),
            "training_digest": digest}


def registry_units(sd: SeedData) -> list[str]:
    """The registry's own training units of a split (`sd.train` less its `extra_units`)."""
    return list(sd.train.unit_ids[: sd.train.n_units - sd.n_extra])


def n_sources(sd: SeedData, recipe: ResponseRecipe) -> int:
    """How many of `sd.train`'s units (its first ones) a new unit's network trains on: every
    training unit (`extra_units` included), or the registry's own (`recipe.transfer_from`)."""
    n = sd.train.n_units
    return n - sd.n_extra if recipe.transfer_from == "registry" else n


def source_units(sd: SeedData, recipe: ResponseRecipe) -> FleetBatchData:
    """Those units' rows (`n_sources`): `sd.train` itself, or a copy of the registry's own units."""
    n = n_sources(sd, recipe)
    return sd.train if n == sd.train.n_units else sd.train.subset(range(n))


class Bands(NamedTuple):
    """Intervals of response-transferred units: each held-out job's interval fields by job index,
    what the learning units say of the plan's residuals per budget (`cross_sensor_jobs.FleetWidths`:
    the fleet factor, its margin, ...), and per residual kind (`plan`, `transfer`) and budget their
    spread of log(needed / own half-width) (D,)."""

    fields: dict[int, dict[str, Any]]
    widths: dict[Budget, FleetWidths]
    spreads: dict[str, dict[Budget, np.ndarray]]


INTERVAL_RESIDUALS = "plan"  # what a response-transferred unit's intervals start from (plan_bands)


def plan_bands(nets: FitResult, arrays: FleetArrays, sd: SeedData,
               at: list[tuple[Job, np.ndarray]], plans: list[Plan], level: float,
               checks: FitResult | None = None, factor: Calibrated | None = None) -> Bands:
    """Intervals from each unit's own plan: the conformal half-width of its network's residuals
    on the plan's rows (D,), times the fleet factor the validation units learnt at its budget (how
    much wider their test rows needed it; `uncertainty.conformal.fleet_factor`).

    The plan's rows also trained the network, so its residuals there understate its error
    elsewhere; the fleet factor carries that back, as it carries the press-fold residuals of
    adapters (which would cost a response transfer a network per fold). `at`: ((unit, budget,
    prior), test-row prediction) per job, in the order of `nets`' models and `plans`. `checks`:
    each job's network trained on its transferred rows alone (`transfer_check`), whose residuals
    on the plan's rows, which it never saw, give the `transfer_` fields with their own factor.
    `factor`: the factor units' calibrations, whose plans and test rows learn the fleet factor with
    the validation units' (`options.intervals.factor_units`; not the `transfer_` one)."""
    residuals = _plan_residuals(nets, arrays, plans)
    learn_at, learn = list(at), dict(residuals)
    if factor is not None:
        more = _plan_residuals(factor.nets, arrays, factor.plans())
        learn |= {len(at) + m: r for m, r in more.items()}
        learn_at += factor.at()
    fleet = validation_factors(learn_at, learn, sd, arrays, level)
    names = arrays.output_names
    fields = {m: interval_fields(residuals[m], pred, arrays.targets[sd.evals[u].test_rows], names, level,
                                 fleet.get(b), arrays.patch[sd.evals[u].test_rows], m)
              for m, ((u, b, _), pred) in enumerate(at) if u in sd.split.test}
    spreads = {"plan": {b: f.spread for b, f in fleet.items()}}
    if checks is not None:
        unseen = _plan_residuals(checks, arrays, plans)
        other = validation_factors(at, unseen, sd, arrays, level)
        spreads["transfer"] = {b: f.spread for b, f in other.items()}
        for m, ((u, b, _), pred) in enumerate(at):
            if m in fields and fields[m] and b in other:
                target = arrays.targets[sd.evals[u].test_rows]
                fields[m] |= scaled_fields(unseen[m], pred, target, names, level, other[b], "transfer_")
    return Bands(fields, fleet, spreads)


def _plan_residuals(nets: FitResult, arrays: FleetArrays, plans: list[Plan]) -> dict[int, np.ndarray]:
    """Job m's network's residuals (n_m, D) on its plan's rows."""
    fitted = predict_rows(nets.model, nets.in_scaler, nets.out_scaler, arrays, [p.rows for p in plans])
    return {m: f - arrays.targets[p.rows] for m, (f, p) in enumerate(zip(fitted, plans, strict=True))}


def by_strategy(values: dict[Budget, Any]) -> dict[str, dict[str, Any]]:
    """{strategy: {robot seconds (or samples): value}}: what `anytip calibrate` reads for the plans
    it makes (the validation units' loss, their plans' residual about their response in Pa)."""
    out: dict[str, dict[str, Any]] = {}
    for b, v in sorted(values.items(), key=lambda kv: kv[0].amount):
        out.setdefault(b.strategy if b.unit == "seconds" else "samples", {})[f"{b.amount:g}"] = v
    return out
