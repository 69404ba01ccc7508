"""Research log entry 165: a finished run's own per-unit references trained again from several starts.

The run's fold (its seed, its spec on one CPU thread, its recorded units: entry 98's `fold_of`) with the
spec's options changed by `--set` (here `options.reference_starts=3`). Its held-out units are given their
references as the pipeline trains them (`per_unit_rows`: every learning rate of `reference_lrs` from every
start, each unit keeping the fit with the lowest loss on its own validation patches). OUT/references.json
holds the kept rows (`per_unit`, as a run writes them) and, per fit, every unit's test RMSEs and lowest
validation loss (`trials`), so that the fits of start 0 alone give the run's own reference back. The networks
are not kept. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry165/references.py RUN --registry REG --out OUT \\
        --set options.reference_starts=3
"""

from __future__ import annotations

import argparse
import runpy
import shutil
import time
from pathlib import Path
from typing import Any

import anytip.pipelines.cross_sensor as pipeline
from anytip.rundir import write_json
from anytip.train.metrics import scores
from anytip.train.shared_split import predict_rows

FOLD_OF = runpy.run_path("reports/cross_sensor_response_gpu/entry98/more_val.py")["fold_of"]
# entry 164's hook on the pipeline's reference fits; from its start 0 it keeps each fit, its seed unmoved
KEEP_FITS = runpy.run_path("reports/cross_sensor_response_gpu/entry164/starts.py")["from_start"]


def trial_rows(fits: list[Any], opts: Any, arrays: Any, sd: Any) -> list[dict[str, Any]]:
    """Per fit and held-out unit: its learning rate, start, lowest validation loss and test scores."""
    units = list(sd.split.test)
    tests = [sd.evals[u].test_rows for u in units]
    rows = []
    for (k, j), fit in zip(pipeline.reference_trials(opts), fits, strict=True):
        val = pipeline.best_val_loss(fit)
        preds = predict_rows(fit.model, fit.in_scaler, fit.out_scaler, arrays, tests)
        rows += [{"unit": u, "lr": opts.reference_lrs[k] if opts.reference_lrs else None, "start": j,
                  "val_loss": float(val[i]), **scores(preds[i], arrays.targets[tests[i]], arrays.layout)}
                 for i, u in enumerate(units)]
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path)
    parser.add_argument("--registry", type=Path, required=True)
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--set", dest="overrides", action="append", default=[])
    args = parser.parse_args()
    begin = time.perf_counter()
    ctx, opts, arrays, seed, was = FOLD_OF(args.run, args.registry, args.out, args.overrides)
    sd = pipeline.prepare(ctx, arrays, opts, seed)
    if list(sd.split.test) != list(was["test"]):
        raise SystemExit(f"the fold's held-out units {list(sd.split.test)} are not the run's {was['test']}")
    fits: list[Any] = []
    KEEP_FITS(0, fits)
    rows = [{**r, "seed": seed, "test_rows": int(len(sd.evals[r["unit"]].test_rows))}
            for r in pipeline.per_unit_rows(ctx, arrays, sd, opts, seed)]
    shutil.rmtree(args.out / "models", ignore_errors=True)
    write_json(args.out / "references.json", {
        "run": str(args.run), "seed": seed, "overrides": args.overrides, "units": was, "rows": rows,
        "trials": trial_rows(fits, opts, arrays, sd), "wall_s": round(time.perf_counter() - begin, 1)})
    print(f"seed {seed}: {len(rows)} references from {len(fits)} fits in {time.perf_counter() - begin:.0f} s",
          flush=True)


if __name__ == "__main__":
    main()
