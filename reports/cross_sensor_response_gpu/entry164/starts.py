"""Research log entry 164: the per-unit references of a fold's fresh held-out units trained from several
starts.

Entry 159's references (`per_unit_rows` under entry 107's `fresh_fold`), each from START_COUNT starts of its
network: start 0 is the run's own (the fold's seed, as entry 159 trains it) and start j the seed plus 1000
j, everything else the same (data, validation patches, learning rates). Each start's rows carry every unit's
test RMSEs and its lowest validation loss, written to OUT/references.json; the networks are not kept. Usage,
from the repository root:

    python reports/cross_sensor_response_gpu/entry164/starts.py RUN --registry REG --prefix SIM25- \\
        --units 0:32 --out OUT [--set KEY=VALUE ...]
"""

from __future__ import annotations

import runpy
import shutil
import time
from typing import Any

import anytip.pipelines.cross_sensor as pipeline
from anytip.rundir import write_json

FRESH = runpy.run_path("reports/cross_sensor_response_gpu/entry107/fresh_held_out.py")
START_COUNT, START_STEP = 3, 1000
TRAIN_FLEET = pipeline.train_fleet


def from_start(j: int, fits: list[Any]) -> None:
    """Make the pipeline's reference fits start from start j, and keep each fit in `fits`."""
    def train(*args: Any, seed: int, **kwargs: Any) -> Any:
        fits.append(TRAIN_FLEET(*args, seed=seed + START_STEP * j, **kwargs))
        return fits[-1]
    pipeline.train_fleet = train


def main(starts: range = range(START_COUNT)) -> None:
    """Every start of `starts` (entry 167 runs starts 3 and 4 alone)."""
    args = FRESH["arguments"](__doc__.splitlines()[0])
    begin = time.perf_counter()
    ctx, opts, arrays, seed, split, sd = FRESH["fresh_fold"](args)
    rows = []
    for j in starts:
        fits: list[Any] = []
        from_start(j, fits)
        got = pipeline.per_unit_rows(ctx, arrays, sd, opts, seed)
        val = pipeline.best_val_loss(fits[0]) if len(fits) == 1 else None
        if val is None:
            raise SystemExit("one learning rate per start: set options.reference_lrs=[0.01]")
        rows += [{**r, "seed": seed, "start": j, "val_loss": float(val[k]),
                  "test_rows": int(len(sd.evals[r["unit"]].test_rows))} for k, r in enumerate(got)]
        print(f"seed {seed}, start {j}: {len(got)} references, {time.perf_counter() - begin:.0f} s",
              flush=True)
    shutil.rmtree(args.out / "models", ignore_errors=True)
    write_json(args.out / "references.json", {"run": str(args.run), "seed": seed, "overrides": args.overrides,
                                               "units": split.to_json(), "rows": rows,
                                               "wall_s": round(time.perf_counter() - begin, 1)})


if __name__ == "__main__":
    main()
