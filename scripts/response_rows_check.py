"""Check that `scripts/response_many_units.py` trained on a registry's own rows: each training unit's
fitting and validation rows, rebuilt by the pipeline from the registry, against the SHA-256 the
script logged for the rows it simulated again.

    python scripts/response_rows_check.py reports/cross_sensor_response_extra/fleet88_seed1 \\
        --registry data/fleet88 --log reports/cross_sensor_response_gpu/entry33/log_call2_fleet88_seed1.json

Prints, for each seed of the run the log holds, how many training units' rows are equal; exits 1 if
any differs or the log holds none of the run's seeds.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import torch
from response_many_units import rows_digest

from anytip.config import load_spec
from anytip.data.registry import Registry
from anytip.errors import AnytipError
from anytip.pipelines.common import Context, load
from anytip.pipelines.cross_sensor import min_units, prepare
from anytip.pipelines.cross_sensor_options import parse_options
from anytip.rundir import read_json
from anytip.train.data import UnitTensors


def digest(unit: UnitTensors) -> str:
    """`rows_digest` of a training unit's fitting and validation rows."""
    rows = (unit.X_train, unit.Y_train, unit.X_val, unit.Y_val)
    return rows_digest((unit.unit_id, *(t.numpy() for t in rows)))


def check(run: Path, registry: Path, log: Path) -> bool:
    """True if the log holds a seed of the run and every training unit of every such seed has the
    logged rows."""
    logged = read_json(log)["registry_rows_sha256"]
    spec = load_spec(run / "config.yaml", ["options.adapters=[]"])
    same, checked = True, 0
    with tempfile.TemporaryDirectory() as tmp:
        ctx = Context(spec, Registry(registry, create=False), Path(tmp), torch.device("cpu"), False, {})
        opts, arrays = parse_options(ctx), load(ctx, min_units(ctx))
        for seed in spec.all_seeds:
            want = logged.get(f"{run.name}_seed{seed}")
            if want is None:
                print(f"{run.name} seed {seed}: not in {log}")
                continue
            train = prepare(ctx, arrays, opts, seed).train
            rows = [train.unit(k) for k in range(train.n_units)]
            equal = sum(digest(r) == want.get(r.unit_id) for r in rows)
            print(f"{run.name} seed {seed}: {equal} of {len(rows)} training units' rows equal")
            same &= equal == len(rows)
            checked += 1
    return same and checked > 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="the finished cross_sensor run the models were trained for")
    parser.add_argument("--registry", type=Path, required=True)
    parser.add_argument("--log", type=Path, required=True, help="a log_*.json of response_many_units.py")
    args = parser.parse_args(argv)
    try:
        return 0 if check(args.run, args.registry, args.log) else 1
    except AnytipError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
