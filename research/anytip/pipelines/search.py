"""Architecture search under the microcontroller's budget (`pipeline: search`).

`options.family: per_unit` (default): units are dealt into search units (the study's
objective: their held-out patches) and test units; a candidate is trained per unit.
`options.family: shared`: units are dealt into training, search and test units; a candidate is a
shared network trained on the training units, scored on the search units after fitting their
adapters on a calibration budget (search/shared.py). Either way the test units are never seen by
the study (search/study.py, run in a storage URL); then the paper's MLP and the feasible Pareto
front are retrained and scored on the test units, which is what the report's comparison uses.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import time
import warnings
from typing import Any

import optuna

from anytip.data.arrays import has_patch_grid
from anytip.data.seeds import SEARCH_TEST_SCORER, stream_seed
from anytip.data.splits import patch_test_mask, split_units
from anytip.errors import AnytipError
from anytip.pipelines.common import (
    Context,
    load,
    per_unit_split,
    predict_units,
    report_metrics,
    validate_options,
)
from anytip.report.search import write_report
from anytip.search.budget import cost, load_budget
from anytip.search.fit import train_candidate
from anytip.search.shared import prepare_shared, shared_scorer
from anytip.search.study import (
    Candidate,
    SearchOptions,
    Shape,
    candidate_of,
    front_table,
    is_paper,
    make_objective,
    open_study,
    paper_params,
    remaining,
)
from anytip.train.metrics import scores, target_keys
from anytip.train.recipe import TrainRecipe
from anytip.validation import mask_secrets

# a storage URL from the environment keeps credentials out of specs, command lines and run files
STORAGE_ENV = "ANYTIP_SEARCH_STORAGE"
MAX_FRONT = 6  # front members retrained on the test units: the most accurate on the search units


def parse_options(ctx: Context) -> SearchOptions:
    opts = validate_options(ctx, SearchOptions)
    if opts.min_hidden > opts.max_hidden:
        raise AnytipError(f"options: min_hidden {opts.min_hidden} > max_hidden {opts.max_hidden}")
    return opts


def min_units(ctx: Context) -> int:
    """Units the study needs: search and test units, and training units for the shared family."""
    opts = parse_options(ctx)
    extra = 1 if opts.family == "per_unit" else (opts.n_train_units or 1)
    return opts.n_search_units + opts.n_test_units + extra


def unit_scorer(ctx: Context, arrays, units: list[str], seed: int):
    """fit_and_score(candidate, recipe) -> one held-out-patch score row per unit of `units`, of
    each unit's own network (features folded into its first layer)."""
    split = per_unit_split(arrays, units, patch_test_mask(ctx.spec.splits.patch_test_fraction, seed),
                           ctx.spec.splits.val_fraction, seed, ctx.device)

    def fit_and_score(cand: Candidate, recipe: TrainRecipe) -> list[dict[str, Any]]:
        fit = train_candidate(split.data, cand, recipe, seed, ctx.device)
        preds = predict_units(fit, split.X_test)
        return [{"unit": u, "calib_samples": int(n), **scores(p, y, arrays.layout)}
                for u, p, y, n in zip(units, preds, split.Y_test, split.data.n_train, strict=True)]

    return fit_and_score


def _worker(url: str, name: str, opts: SearchOptions, objective, n: int, worker: int = 0,
            n_objectives: int = 3) -> None:
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    open_study(url, name, opts, worker, n_objectives).optimize(objective, n_trials=n, catch=(RuntimeError,))


def run_trials(url: str, opts: SearchOptions, objective, workers: int, n_objectives: int = 3) -> float:
    """Run the study's remaining trials in `workers` processes; returns wall seconds."""
    study = open_study(url, opts.study_name, opts, n_objectives=n_objectives)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
        optuna.storages.fail_stale_trials(study)  # a killed run's trials: failed, then retried
    n = remaining(study, opts.n_trials)
    start = time.perf_counter()
    if workers <= 1 or n <= 1:
        _worker(url, opts.study_name, opts, objective, n, n_objectives=n_objectives)
    else:
        ctx = mp.get_context("fork")
        shares = [n // workers + (k < n % workers) for k in range(workers)]
        procs = [ctx.Process(target=_worker, args=(url, opts.study_name, opts, objective, s, k, n_objectives))
                 for k, s in enumerate(shares) if s]
        for p in procs:
            p.start()
        for p in procs:
            p.join()
        # a worker that died (killed, or a storage error) leaves trials undone: finish them here
        left = remaining(open_study(url, opts.study_name, opts, n_objectives=n_objectives), opts.n_trials)
        if left:
            _worker(url, opts.study_name, opts, objective, left, workers, n_objectives)
    return time.perf_counter() - start


def scorers(ctx: Context, arrays, opts: SearchOptions) -> tuple[Any, Any, dict[str, list[str]]]:
    """(search-unit scorer, test-unit scorer, unit roles) of the options' family."""
    seed = ctx.spec.seed
    if opts.family == "shared":
        data = prepare_shared(arrays, opts, ctx.spec.splits, seed, ctx.device)
        roles = {"train_units": data.train_units, "search_units": data.search_units,
                 "test_units": data.test_units}
        return (shared_scorer(arrays, data, opts, data.search_units, seed, ctx.device),
                shared_scorer(arrays, data, opts, data.test_units, seed, ctx.device), roles)
    split = split_units(arrays.units, seed, opts.n_search_units, opts.n_test_units)
    roles = {"search_units": list(split.val), "test_units": list(split.test)}
    return (unit_scorer(ctx, arrays, roles["search_units"], seed),
            unit_scorer(ctx, arrays, roles["test_units"], stream_seed(SEARCH_TEST_SCORER, seed)), roles)


def run(ctx: Context) -> list[dict[str, Any]]:
    opts, spec = parse_options(ctx), ctx.spec
    workers = opts.workers
    budget = load_budget(opts.budget)
    arrays = load(ctx, min_units=min_units(ctx))
    shape = Shape(arrays.pressure.shape[1], len(arrays.output_names), tuple(target_keys(arrays.layout)))
    opts = features_for(ctx, opts, arrays)
    search_scorer, test_scorer, roles = scorers(ctx, arrays, opts)
    url = opts.storage or os.environ.get(STORAGE_ENV) or f"sqlite:///{ctx.run_dir / 'study.db'}"
    n_obj = len(shape.keys) + 1
    study = open_study(url, opts.study_name, opts, n_objectives=n_obj)
    paper = paper_params(opts, spec.training)
    if not study.trials and paper is not None:
        study.enqueue_trial(paper)
    objective = make_objective(search_scorer, opts, budget, spec.training, shape)
    run_trials(url, opts, objective, workers, n_obj)
    study = open_study(url, opts.study_name, opts, n_objectives=n_obj)
    wall = study_seconds(study)
    table = [r | {"paper": is_paper(candidate_of(r), opts, shape)} for r in front_table(study, shape.keys)]
    front = test_candidates(table, shape.keys[0])
    front += ablations(front, budget, opts.measure)
    rows = test_rows(ctx, test_scorer, front, spec.training, opts.family, shape.keys)
    done = sum(t.state == optuna.trial.TrialState.COMPLETE for t in study.trials)
    ctx.provenance["search"] = {
        "storage": mask_secrets(url), "study_name": opts.study_name, "workers": workers,
        "budget": budget.model_dump(),
        "family": opts.family, **roles, "wall_s": wall, "trials": len(study.trials), "complete": done,
        "trials_per_hour": 3600 * len(study.trials) / wall if wall > 0 else None,
        "trial_seconds": trial_seconds(study), "table": table}
    write_report(ctx, rows, table, budget, report_metrics({n: t.unit for n, t in arrays.layout.items()}))
    return rows


def features_for(ctx: Context, opts: SearchOptions, arrays) -> SearchOptions:
    """The options' input features this sensor model can take: `neighbour_diffs` is built from the
    fingertip's barometer geometry, so another design searches raw pressures only (noted)."""
    if has_patch_grid(arrays.layout) or opts.features == ["raw"]:
        return opts
    ctx.provenance.setdefault("skipped", []).append(
        f"input features {[f for f in opts.features if f != 'raw']} left out: they are built from the "
        f"fingertip's barometer geometry, not {ctx.provenance.get('sensor_model')!r}'s")
    return opts.model_copy(update={"features": ["raw"]})


def trial_seconds(study: optuna.Study) -> dict[str, float | None]:
    """Median wall seconds of a complete trial and of a pruned (over-budget) one."""
    import statistics

    out: dict[str, float | None] = {}
    for state in (optuna.trial.TrialState.COMPLETE, optuna.trial.TrialState.PRUNED):
        d = [t.duration.total_seconds() for t in study.trials if t.state == state and t.duration]
        out[state.name.lower()] = statistics.median(d) if d else None
    return out


def study_seconds(study: optuna.Study) -> float:
    """Wall seconds from the first trial's start to the last trial's end (across resumes)."""
    starts = [t.datetime_start for t in study.trials if t.datetime_start]
    ends = [t.datetime_complete for t in study.trials if t.datetime_complete]
    return (max(ends) - min(starts)).total_seconds() if starts and ends else 0.0


def test_candidates(table: list[dict[str, Any]], key: str = "force_rmse_n") -> list[dict[str, Any]]:
    """The paper's MLP and the MAX_FRONT front members most accurate (`key`, the first target's
    RMSE) on the search units."""
    paper = [r | {"method": "paper_mlp"} for r in table if r["paper"]][:1]
    front = sorted((r for r in table if r["pareto"] and not r["paper"]), key=lambda r: r[key])[:MAX_FRONT]
    return paper + [r | {"method": "search"} for r in front]


def ablations(candidates: list[dict[str, Any]], budget, measure: bool) -> list[dict[str, Any]]:
    """The most accurate front member with raw pressures instead of its features, and with ReLU
    instead of its activation (method `ablation`, not front members), costed again."""
    best = next((r for r in candidates if r["method"] == "search"), None)
    if best is None:
        return []
    out = []
    for key, plain in (("features", "raw"), ("activation", "relu")):
        if best[key] == plain:
            continue
        c = cost(best["sizes"], budget, measure_if_possible=measure,
                 activation=plain if key == "activation" else best["activation"])
        out.append(best | {key: plain, "method": "ablation", "pareto": False, "params": c.params,
                           "macs": c.macs, "flash_bytes": c.flash_bytes, "ram_bytes": c.ram_bytes,
                           "cycles": c.cycles, "measured": c.measured_sizes})
    return out


def test_rows(ctx: Context, score, candidates: list[dict[str, Any]], recipe: TrainRecipe, family: str,
              keys: tuple[str, ...] = ("force_rmse_n", "angle_rmse_rad")) -> list[dict[str, Any]]:
    """`candidates` (front_table rows with a `method`) retrained and scored on the test units."""
    rows = []
    for r in candidates:
        rec = recipe.model_copy(update={"lr": r["lr"], "batch_size": r["batch_size"]})
        method = r["method"]
        for s in score(candidate_of(r), rec):
            rows.append({"method": method, "unit": s["unit"], "calib_samples": s["calib_samples"],
                         "seed": ctx.spec.seed, "family": family,
                         **{k: s[k] for k in keys},
                         "sizes": list(r["sizes"]), "trial": r["number"], "pareto": r["pareto"],
                         **{k: r[k] for k in ("params", "macs", "flash_bytes", "ram_bytes", "cycles",
                                              "measured", "activation", "features", "adapter")}})
    return rows
