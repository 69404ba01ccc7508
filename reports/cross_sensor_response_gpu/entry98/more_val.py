"""Research log entry 98: a finished run's response models scored on more validation units.

The run's fold (its seed) keeps its training units, so its response model and the start network
are the run's own; its validation units are the run's plus every unit of the registry whose id
starts with PREFIX (units simulated for this, never trained on, never held out), and no unit is held
out here: only the validation units' losses are computed, per unit and per plan strategy, as
`scripts/rescore_response.py` computes them, and written to OUT/val_loss_units.json. Usage, from the
repository root:

    python reports/cross_sensor_response_gpu/entry98/more_val.py RUN --registry REG --prefix SIM41- \\
        --out OUT [--response-model FILE] [--set KEY=VALUE ...]

Run in place of `scripts/rescore_response.py` by a wrapper that reads `RESCORE_SCRIPT` (entry 83's
`start_draw.py`), it scores the validation units with that wrapper's start network.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any

import torch

import anytip.train.shared_split as shared_split
from anytip.config import load_spec
from anytip.data.registry import Registry
from anytip.data.splits import UnitSplit
from anytip.models.io import load_response
from anytip.pipelines.common import Context, load
from anytip.pipelines.cross_sensor import min_units, prepare
from anytip.pipelines.cross_sensor_options import parse_options
from anytip.pipelines.cross_sensor_response import response_rows, val_by_method
from anytip.rundir import read_json, write_json
from anytip.train.response import ResponseFit


def fold_of(run: Path, registry: Path, out: Path,
            overrides: list[str]) -> tuple[Context, Any, Any, int, dict]:
    """A finished run's fold on one CPU thread, written to `out`: its context (the run's spec with
    `overrides`, no adapters), options, the registry's arrays, its seed and its recorded unit roles."""
    torch.set_num_threads(1)
    spec = load_spec(run / "config.yaml", [*overrides, "options.adapters=[]"])
    out.mkdir(parents=True, exist_ok=True)
    ctx = Context(spec, Registry(registry, create=False), out, torch.device("cpu"), False,
                  {"spec_file": str(run / "config.yaml")})
    (seed,) = spec.all_seeds
    was = read_json(run / "provenance.json")["cross_sensor"][f"seed{seed}"]["units"]
    return ctx, parse_options(ctx), load(ctx, min_units(ctx)), seed, was


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path)
    parser.add_argument("--registry", type=Path, required=True)
    parser.add_argument("--prefix", required=True, help="the added validation units' id prefix")
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--set", dest="overrides", action="append", default=[])
    parser.add_argument("--response-model",
                        help="the seed's response model from this file ({seed}: the seed), not the run's own")
    args = parser.parse_args()
    start = time.perf_counter()
    ctx, opts, arrays, seed, was = fold_of(args.run, args.registry, args.out,
                                           [*args.overrides, "options.extra_units=null"])
    added = sorted(u for u in arrays.units if u.startswith(args.prefix))
    clash = set(added) & {*was["train"], *was["val"], *was["test"]}
    if not added or clash:
        raise SystemExit(f"no units {args.prefix}* to add, or some are the run's own: {sorted(clash)}")
    split = UnitSplit(tuple(was["train"]), (*was["val"], *added), ())
    shared_split.split_units = lambda *_, **__: split  # the run's training units, more validation units
    sd = prepare(ctx, arrays, opts, seed)
    path = (Path(args.response_model.format(seed=seed)) if args.response_model
            else args.run / "models" / f"response_seed{seed}.safetensors")
    fit = ResponseFit.from_loaded(load_response(path))
    got = response_rows(ctx, arrays, sd, opts, seed, fit)
    write_json(args.out / "val_loss_units.json", {
        "run": str(args.run), "response_model": str(path), "seed": seed, "overrides": args.overrides,
        "units": split.to_json(),
        "val_loss": val_by_method(got), "val_loss_units": val_by_method(got, per_unit=True),
        "wall_s": round(time.perf_counter() - start, 1)})
    print(f"seed {seed}: {len(split.val)} validation units in {time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
