"""Architecture search under the microcontroller's budget (`pipeline: search`).

Units are dealt into search units (the study's objective: their held-out patches) and test
units (never seen by the study). The study (search/study.py) runs in a storage URL; then the
paper's MLP and the feasible Pareto front are retrained on the test units and scored on
their held-out patches, which is what the report's comparison uses.
"""

from __future__ import annotations

import multiprocessing as mp
import time
import warnings
from typing import Any

import optuna

from anytip.data.splits import split_units
from anytip.errors import AnytipError
from anytip.models.mlp import MLPConfig
from anytip.pipelines.common import (
    Context,
    load,
    patch_test_mask,
    per_unit_split,
    predict_units,
    scores,
    validate_options,
)
from anytip.report.search import write_report
from anytip.search.budget import load_budget
from anytip.search.study import (
    SearchOptions,
    front_table,
    make_objective,
    mean_scores,
    open_study,
    paper_params,
    remaining,
)
from anytip.train.fleet import train_fleet
from anytip.train.recipe import TrainRecipe

PAPER_SIZES = (8, 12, 64, 64, 5)
MAX_FRONT = 6  # front members retrained on the test units: the most accurate on the search units


def parse_options(ctx: Context) -> SearchOptions:
    opts = validate_options(ctx, SearchOptions)
    if opts.min_hidden > opts.max_hidden:
        raise AnytipError(f"options: min_hidden {opts.min_hidden} > max_hidden {opts.max_hidden}")
    return opts


def unit_scorer(ctx: Context, arrays, units: list[str], seed: int):
    """fit_and_score(config, recipe) -> mean held-out (force, angle) RMSE over `units`."""
    split = per_unit_split(arrays, units, patch_test_mask(ctx.spec.splits.patch_test_fraction, seed),
                           ctx.spec.splits.val_fraction, seed, ctx.device)

    def fit_and_score(config: MLPConfig, recipe: TrainRecipe, per_unit: bool = False):
        fit = train_fleet(split.data, config, recipe, seed=seed, device=ctx.device)
        preds = predict_units(fit, split.X_test)
        s = [scores(p, y) | {"calib_samples": int(n)}
             for p, y, n in zip(preds, split.Y_test, split.data.n_train, strict=True)]
        return s if per_unit else mean_scores(s)

    return fit_and_score


def _worker(url: str, name: str, opts: SearchOptions, objective, n: int, worker: int = 0) -> None:
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    open_study(url, name, opts, worker).optimize(objective, n_trials=n, catch=(RuntimeError,))


def run_trials(url: str, opts: SearchOptions, objective, workers: int) -> float:
    """Run the study's remaining trials in `workers` processes; returns wall seconds."""
    study = open_study(url, opts.study_name, opts)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
        optuna.storages.fail_stale_trials(study)  # a killed run's trials: failed, then retried
    n = remaining(study, opts.n_trials)
    start = time.perf_counter()
    if workers <= 1 or n <= 1:
        _worker(url, opts.study_name, opts, objective, n)
    else:
        ctx = mp.get_context("fork")
        shares = [n // workers + (k < n % workers) for k in range(workers)]
        procs = [ctx.Process(target=_worker, args=(url, opts.study_name, opts, objective, s, k))
                 for k, s in enumerate(shares) if s]
        for p in procs:
            p.start()
        for p in procs:
            p.join()
        # a worker that died (killed, or a storage error) leaves trials undone: finish them here
        left = remaining(open_study(url, opts.study_name, opts), opts.n_trials)
        if left:
            _worker(url, opts.study_name, opts, objective, left, workers)
    return time.perf_counter() - start


def run(ctx: Context) -> list[dict[str, Any]]:
    opts, spec = parse_options(ctx), ctx.spec
    workers = opts.workers
    budget = load_budget(opts.budget)
    arrays = load(ctx, min_units=opts.n_search_units + opts.n_test_units + 1)
    split = split_units(arrays.units, spec.seed, opts.n_search_units, opts.n_test_units)
    search_units, test_units = list(split.val), list(split.test)
    url = opts.storage or f"sqlite:///{ctx.run_dir / 'study.db'}"
    study = open_study(url, opts.study_name, opts)
    paper = paper_params(opts, spec.training)
    if not study.trials and paper is not None:
        study.enqueue_trial(paper)
    objective = make_objective(unit_scorer(ctx, arrays, search_units, spec.seed), opts, budget,
                               spec.training)
    run_trials(url, opts, objective, workers)
    study = open_study(url, opts.study_name, opts)
    wall = study_seconds(study)
    table = front_table(study)
    rows = test_rows(ctx, arrays, test_units, table, spec.training)
    done = sum(t.state == optuna.trial.TrialState.COMPLETE for t in study.trials)
    ctx.provenance["search"] = {
        "storage": url, "study_name": opts.study_name, "workers": workers, "budget": budget.model_dump(),
        "search_units": search_units, "test_units": test_units, "wall_s": wall,
        "trials": len(study.trials), "complete": done,
        "trials_per_hour": 3600 * len(study.trials) / wall if wall > 0 else None, "table": table}
    write_report(ctx, rows, table, budget)
    return rows


def study_seconds(study: optuna.Study) -> float:
    """Wall seconds from the first trial's start to the last trial's end (across resumes)."""
    starts = [t.datetime_start for t in study.trials if t.datetime_start]
    ends = [t.datetime_complete for t in study.trials if t.datetime_complete]
    return (max(ends) - min(starts)).total_seconds() if starts and ends else 0.0


def test_rows(ctx: Context, arrays, units: list[str], table: list[dict[str, Any]],
              recipe: TrainRecipe) -> list[dict[str, Any]]:
    """The paper's MLP and up to MAX_FRONT front members retrained on the test units."""
    paper = [r for r in table if tuple(r["sizes"]) == PAPER_SIZES][:1]
    front = sorted((r for r in table if r["pareto"] and tuple(r["sizes"]) != PAPER_SIZES),
                   key=lambda r: r["force_rmse_n"])[:MAX_FRONT]
    score = unit_scorer(ctx, arrays, units, ctx.spec.seed + 1)
    rows = []
    for r in paper + front:
        rec = recipe.model_copy(update={"lr": r["lr"], "batch_size": r["batch_size"]})
        method = "paper_mlp" if tuple(r["sizes"]) == PAPER_SIZES else "search"
        for unit, s in zip(units, score(MLPConfig(sizes=tuple(r["sizes"])), rec, per_unit=True), strict=True):
            rows.append({"method": method, "unit": unit, "calib_samples": s["calib_samples"],
                         "seed": ctx.spec.seed,
                         "force_rmse_n": s["force_rmse_n"], "angle_rmse_rad": s["angle_rmse_rad"],
                         "sizes": list(r["sizes"]), "trial": r["number"], "pareto": r["pareto"],
                         **{k: r[k] for k in ("params", "macs", "flash_bytes", "ram_bytes", "cycles",
                                              "measured")}})
    return rows
