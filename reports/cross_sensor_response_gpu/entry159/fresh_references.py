"""Research log entry 159: the per-unit references of a finished run's fold for fresh held-out units.

The run's fold (its seed) keeps its training and validation units; its held-out units become the registry's
units whose ids start with PREFIX, the slice FROM:TO of them in sorted order, as entry 107's
`fresh_held_out.py` holds them out (its `fresh_fold`), so each unit's test rows are the same. Each is given
its per-unit reference as the run's pipeline trains one (`per_unit_rows`: the spec's model on the unit's full
calibration less its test patches, each of `reference_lrs`, the fit with the lowest loss on its own validation
patches kept), written to OUT/references.json with each unit's number of test rows. Usage, from the repository
root:

    python reports/cross_sensor_response_gpu/entry159/fresh_references.py RUN --registry REG \\
        --prefix SIM25- --units 0:32 --out OUT [--set KEY=VALUE ...]
"""

from __future__ import annotations

import runpy
import time

from anytip.pipelines.cross_sensor import per_unit_rows
from anytip.rundir import write_json

# entry 107's fold with fresh held-out units, named by the same command line
FRESH = runpy.run_path("reports/cross_sensor_response_gpu/entry107/fresh_held_out.py")


def main() -> None:
    args = FRESH["arguments"](__doc__.splitlines()[0])
    start = time.perf_counter()
    ctx, opts, arrays, seed, split, sd = FRESH["fresh_fold"](args)
    rows = [{**r, "seed": seed, "test_rows": int(len(sd.evals[r["unit"]].test_rows))}
            for r in per_unit_rows(ctx, arrays, sd, opts, seed)]
    write_json(args.out / "references.json", {"run": str(args.run), "seed": seed, "overrides": args.overrides,
                                               "units": split.to_json(), "rows": rows,
                                               "wall_s": round(time.perf_counter() - start, 1)})
    print(f"seed {seed}: {len(split.test)} fresh units' references in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
