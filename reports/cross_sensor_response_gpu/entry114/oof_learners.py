"""Research log entry 114: a response-transferred unit's own half-width from out-of-fold residuals.

Today a response-transferred unit's own half-width is the conformal half-width of its network's residuals on
its plan's rows, which trained that network and fitted its codes: in-sample (`plan_bands`). This driver takes
a finished rescoring's fold (its spec, registry and unit roles; entry 112's `fleet88r_apart`), calibrates its
learners (validation and factor units, each group as the run calibrated it) again to check that their
in-sample half-widths are the run's recorded `own`, then calibrates each learner once more per press fold
(press k in fold k mod FOLDS left out: codes and network fitted without it, as `shared_split.plan_residuals`
does for adapters) and writes each learner's out-of-fold half-widths beside the recorded ones to
OUT/learners.json. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry114/oof_learners.py RUN --registry REG --response-model M \\
        --out OUT
"""

from __future__ import annotations

import argparse
import runpy
import time
from pathlib import Path

import numpy as np

import anytip.train.shared_split as shared_split
from anytip.data.splits import UnitSplit
from anytip.models.io import load_response
from anytip.pipelines.cross_sensor import prepare
from anytip.pipelines.cross_sensor_response import calibrated, labeled_jobs, registry_units, source_units
from anytip.rundir import read_json, write_json
from anytip.train.response import ResponseFit, source_rows, start_network
from anytip.train.shared_split import predict_rows
from anytip.uncertainty.conformal import residual_halfwidth

FOLD_OF = runpy.run_path("reports/cross_sensor_response_gpu/entry98/more_val.py")["fold_of"]
FOLDS = 5  # as the adapters' press folds (`options.intervals.folds`)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path)
    parser.add_argument("--registry", type=Path, required=True)
    parser.add_argument("--response-model", type=Path, required=True)
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--folds", type=int, default=FOLDS, help="press folds; 0: the in-sample check alone")
    args = parser.parse_args()
    start_s = time.perf_counter()
    ctx, opts, arrays, seed, was = FOLD_OF(args.run, args.registry, args.out, [])
    split = UnitSplit(tuple(was["train"]), tuple(was["val"]), tuple(was["test"]), tuple(was["factor"]))
    shared_split.split_units = lambda *_, **__: split  # the run's recorded roles
    sd = prepare(ctx, arrays, opts, seed)
    recipe = opts.response.recipe()
    fit = ResponseFit.from_loaded(load_response(args.response_model)).with_code_prior(
        recipe.code_prior, registry_units(sd))
    source = source_rows(fit, source_units(sd, recipe), recipe.source_rows, seed)
    start = start_network(source, ctx.spec.model, recipe, seed, arrays.output_names, ctx.progress)
    header = read_json(args.run / f"models/response_seed{seed}.json")
    recorded = header.get("meta", header)["intervals"]["units_by_strategy"]["cover_informative"]["120"]
    names, level = arrays.output_names, opts.intervals.level
    out = {}
    for group in (list(split.val), list(split.factor)):  # as the run calibrated them: apart
        jobs = labeled_jobs(sd, group, opts, seed, fit, arrays)
        whole = calibrated(ctx, arrays, sd, fit, (source, start), recipe, jobs, seed)
        fold_jobs, left_out = [], []
        for u, b, plan in jobs:
            for f in range(args.folds):
                smaller, check = plan.without_presses(args.folds, f)
                fold_jobs.append((u, b, smaller))
                left_out.append(check)
        checks = []
        if fold_jobs:
            folds = calibrated(ctx, arrays, sd, fit, (source, start), recipe, fold_jobs, seed)
            nets = folds.nets
            checks = predict_rows(nets.model, nets.in_scaler, nets.out_scaler, arrays, left_out)
        fitted = predict_rows(whole.nets.model, whole.nets.in_scaler, whole.nets.out_scaler, arrays,
                              [plan.rows for _, _, plan in jobs])  # network m on job m's plan
        for m, (u, _, plan) in enumerate(jobs):
            in_sample = residual_halfwidth(fitted[m] - arrays.targets[plan.rows], level)
            out[u] = {"in_sample": dict(zip(names, map(float, in_sample), strict=True)),
                      "recorded": recorded[u], "presses": int(plan.presses)}
            if args.folds:
                k = args.folds
                oof = np.concatenate([checks[m * k + f] - arrays.targets[left_out[m * k + f]]
                                      for f in range(k)])
                out[u]["oof"] = dict(zip(names, map(float, residual_halfwidth(oof, level)), strict=True))
        ctx.say(f"seed {seed}: {len(jobs)} learners, {len(fold_jobs)} fold calibrations")
    write_json(args.out / "learners.json", {"run": str(args.run), "seed": seed, "folds": args.folds,
                                            "units": out, "wall_s": round(time.perf_counter() - start_s, 1)})
    print(f"seed {seed}: {len(out)} learners in {time.perf_counter() - start_s:.0f} s")


if __name__ == "__main__":
    main()
