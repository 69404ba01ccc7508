"""Research log entry 159: the per-unit references of a finished run's fold for fresh held-out units.

The run's fold (its seed) keeps its training and validation units; its held-out units become the registry's
units whose ids start with PREFIX, the slice FROM:TO of them in sorted order, as entry 107's
`fresh_held_out.py` holds them out, so each unit's test rows are the same. Each is given its per-unit
reference as the run's pipeline trains one (`per_unit_rows`: the spec's model on the unit's full calibration
less its test patches, each of `reference_lrs`, the fit with the lowest loss on its own validation patches
kept), written to OUT/references.json with each unit's number of test rows. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry159/fresh_references.py RUN --registry REG \\
        --prefix SIM25- --units 0:32 --out OUT [--set KEY=VALUE ...]
"""

from __future__ import annotations

import argparse
import runpy
import time
from pathlib import Path

import anytip.train.shared_split as shared_split
from anytip.data.splits import UnitSplit
from anytip.pipelines.cross_sensor import per_unit_rows, prepare
from anytip.rundir import write_json

# entry 98's driver: a finished run's fold (its spec, one CPU thread, the registry's arrays, its unit roles)
FOLD_OF = runpy.run_path("reports/cross_sensor_response_gpu/entry98/more_val.py")["fold_of"]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path)
    parser.add_argument("--registry", type=Path, required=True)
    parser.add_argument("--prefix", required=True, help="the fresh held-out units' id prefix")
    parser.add_argument("--units", required=True, help="FROM:TO, the slice of those units (sorted) held out")
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--set", dest="overrides", action="append", default=[])
    args = parser.parse_args()
    start = time.perf_counter()
    ctx, opts, arrays, seed, was = FOLD_OF(args.run, args.registry, args.out, args.overrides)
    first, last = (int(v) for v in args.units.split(":"))
    fresh = sorted(u for u in arrays.units if u.startswith(args.prefix))[first:last]
    split = UnitSplit(tuple(was["train"]), tuple(was["val"]), tuple(fresh), tuple(was.get("factor", ())))
    shared_split.split_units = lambda *_, **__: split  # the run's learners, fresh held-out units
    sd = prepare(ctx, arrays, opts, seed)
    rows = [{**r, "seed": seed, "test_rows": int(len(sd.evals[r["unit"]].test_rows))}
            for r in per_unit_rows(ctx, arrays, sd, opts, seed)]
    write_json(args.out / "references.json", {"run": str(args.run), "seed": seed, "overrides": args.overrides,
                                               "units": split.to_json(), "rows": rows,
                                               "wall_s": round(time.perf_counter() - start, 1)})
    print(f"seed {seed}: {len(fresh)} fresh units' references in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
