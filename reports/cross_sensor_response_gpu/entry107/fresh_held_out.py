"""Research log entry 107: a finished run's fold scored on fresh held-out units, its learners as they were.

The run's fold (its seed) keeps its training, validation and factor units, its spec and its response
model (the run's own, `models/response_seed<seed>.safetensors`); its held-out units become the registry's
units whose ids start with PREFIX, the slice FROM:TO of them in sorted order (units simulated for this,
never trained on, never scored). Every held-out unit is calibrated as `scripts/rescore_response.py`
calibrates one, with the intervals the spec asks for (the learners' fleet factor and margin), and the
held-out rows (no per-unit references: only their intervals are read) and the learners' record are written
to OUT/rows.json and OUT/models/. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry107/fresh_held_out.py RUN --registry REG --prefix SIM42- \\
        --units 0:32 --out OUT [--set KEY=VALUE ...]
"""

from __future__ import annotations

import argparse
import runpy
import time
from pathlib import Path
from typing import Any

import anytip.train.shared_split as shared_split
from anytip.data.splits import UnitSplit
from anytip.models.io import load_response
from anytip.pipelines.cross_sensor import prepare
from anytip.pipelines.cross_sensor_response import response_rows
from anytip.rundir import write_json
from anytip.train.response import ResponseFit

# entry 98's driver: a finished run's fold (its spec, one CPU thread, the registry's arrays, its unit roles)
FOLD_OF = runpy.run_path("reports/cross_sensor_response_gpu/entry98/more_val.py")["fold_of"]


def arguments(description: str) -> argparse.Namespace:
    """The command line a fresh held-out fold is named by (entry 159's references read the same)."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("run", type=Path)
    parser.add_argument("--registry", type=Path, required=True)
    parser.add_argument("--prefix", required=True, help="the fresh held-out units' id prefix")
    parser.add_argument("--units", required=True, help="FROM:TO, the slice of those units (sorted) held out")
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--set", dest="overrides", action="append", default=[],
                        help="KEY=VALUE on the run's spec, e.g. splits.test_rows=all_sessions")
    return parser.parse_args()


def fresh_fold(args: argparse.Namespace) -> tuple[Any, Any, Any, int, UnitSplit, Any]:
    """The run's fold with the fresh units held out: its context, options, the registry's arrays, its seed,
    the split (the run's learners, the fresh held-out units) and the seed's prepared data."""
    ctx, opts, arrays, seed, was = FOLD_OF(args.run, args.registry, args.out, args.overrides)
    first, last = (int(v) for v in args.units.split(":"))
    fresh = sorted(u for u in arrays.units if u.startswith(args.prefix))[first:last]
    clash = set(fresh) & {u for role in was.values() for u in role}
    if not fresh or clash:
        raise SystemExit(f"no units {args.prefix}* in {args.units}, or some are the run's own: "
                         f"{sorted(clash)}")
    split = UnitSplit(tuple(was["train"]), tuple(was["val"]), tuple(fresh), tuple(was.get("factor", ())))
    shared_split.split_units = lambda *_, **__: split  # the run's learners, fresh held-out units
    return ctx, opts, arrays, seed, split, prepare(ctx, arrays, opts, seed)


def main() -> None:
    args = arguments(__doc__.splitlines()[0])
    start = time.perf_counter()
    ctx, opts, arrays, seed, split, sd = fresh_fold(args)
    path = args.run / "models" / f"response_seed{seed}.safetensors"
    got = response_rows(ctx, arrays, sd, opts, seed, ResponseFit.from_loaded(load_response(path)))
    write_json(args.out / "rows.json", {"run": str(args.run), "seed": seed, "overrides": args.overrides,
                                         "units": split.to_json(),
                                         "rows": got.rows, "wall_s": round(time.perf_counter() - start, 1)})
    print(f"seed {seed}: {len(split.test)} fresh held-out units in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
