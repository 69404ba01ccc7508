"""Response models trained on a run's training units and hundreds to thousands more simulated units,
on a GPU (research log entry 31).

Entry 25 trained the response model on a registry's 16 training units and 128 more simulated
units (`options.extra_units`) and took the 120 s ratio from 1.31x to 1.15x; its cost grows with the
units (35 min for 144 units on 2 CPU cores). This script trains, for each seed of finished
cross_sensor runs, response models with the run's recipe on the seed's training units and on the
first N units of a simulated fleet, for each N of `--extra`, and saves them in the layout
`scripts/transfer_bounds.py --response-model` reads (the registry's own training units keep
their codes, so a new unit's rows are transferred from them as in the run):

    OMP_NUM_THREADS=1 python scripts/response_many_units.py \\
        reports/cross_sensor_response_extra/fleet88_seed0 reports/cross_sensor_response_extra/fleet88_seed1 \\
        --registry-seed 40 --registry-protocols full,short,quick --extra-seed 8 --extra 128,1024 \\
        --workers 16 --device cuda --out build/many_units

`--extra-store DIR` keeps the extra units' registries in DIR, and a later call with the same extra
units and `--workers` reads them from there instead of simulating them again (research log entry
48: one simulation of 1,024 units for two registries' folds).

The extra units' rows are split and capped with the first run's seed, the same for every fold of
the call; `--extra-split-seed S` gives another, so that a later call for some folds builds the rows
an earlier call with more folds did (research log entry 51: other16 folds 2-3 after entry 48's call
for folds 0-3, whose first run had seed 0).

`--models 128:32768,1024:32768` names each model as extra units and rows per step instead (research
log entry 33). `--registry-fleet FILE` gives the fleet config the registry's units were simulated
with (`anytip data simulate --fleet FILE`; default: the default fleet), e.g. other16's
`configs/fleets/other_elastomer.yaml`.

`--extra-fleet FILE` draws the extra units from another fleet config, e.g. `configs/fleets/severe.yaml`
(twice the default spread; research log entry 80); the models' names end in the file's stem, and an
`--extra-store` records the config it was written with and refuses another.

Nothing is read from the run's registry: the script needs only the runs' specs and splits. The
registry's training units are simulated again from their fleet seed and protocols (their ids,
SIM<seed>-<index>, give the index; `--registry-fleet`), and the extra units are units 0..N-1 of the
default fleet of `--extra-seed` (the units `anytip data simulate --units N --seed S --protocols
full` writes; `--extra-protocols`). Each worker process simulates its units, writes them to a
registry of its own and reads them back through `load_arrays` (the checked read path), then builds
each unit's fitting and validation rows as the pipeline's `training_units` does. The SHA-256 of
each registry unit's rows goes to `log.json` beside the models, to compare with the run's registry
(on fleet88 they were equal bit for bit).

Extra units keep at most `--max-rows` fitting rows (random, default 120,000 of about 330,000; the
recipe's 20,000 steps draw 3-28 rows of each unit per step) and a tenth as many validation rows.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import asdict, dataclass, replace
from multiprocessing import get_context
from pathlib import Path
from typing import Any

import numpy as np
import torch

from anytip.config import load_spec
from anytip.data.arrays import OUTPUT_NAMES, load_arrays
from anytip.data.registry import Registry
from anytip.data.seeds import unit_seed
from anytip.data.simulated import as_run
from anytip.errors import AnytipError
from anytip.models.io import save_response
from anytip.pipelines.common import Context
from anytip.pipelines.cross_sensor import roles_of
from anytip.pipelines.cross_sensor_options import Options, parse_options
from anytip.rundir import read_json
from anytip.sensor import simulate as sim
from anytip.sensor.fleet import FleetConfig, load_fleet_config
from anytip.train.data import FleetBatchData, UnitTensors
from anytip.train.response import ResponseRecipe, train_response
from anytip.train.shared_split import Roles, training_units

Rows = tuple[str, np.ndarray, np.ndarray, np.ndarray, np.ndarray]  # unit, X_fit, Y_fit, X_val, Y_val
Key = tuple[int, int]  # (fold, position in its training list); fold -1: an extra unit, in every fold


@dataclass(frozen=True)
class Task:
    """One unit to simulate (`SIM<seed>-<index>` of `fleet`, these protocols) and the training-list
    slots it fills."""

    fleet: FleetConfig
    seed: int
    index: int
    protocols: str
    keys: tuple[Key, ...]


@dataclass(frozen=True)
class Fold:
    """A seed of a finished run: its training units, options and unit roles."""

    name: str
    seed: int
    train: list[str]
    opts: Options
    roles: Roles


def unit_index(unit: str, seed: int) -> int:
    """The index of a simulated unit `SIM<seed>-<index>`."""
    prefix = f"SIM{seed}-"
    if not unit.startswith(prefix) or not unit[len(prefix):].isdigit():
        raise AnytipError(f"unit {unit!r} is not a unit of simulated fleet seed {seed} (SIM{seed}-<index>)")
    return int(unit[len(prefix):])


def simulate_units(root: Path, tasks: list[Task]) -> Registry:
    """Each task's unit of its fleet simulated into a new registry at `root`, one unit per
    transaction, as `anytip data simulate` writes it."""
    registry = Registry(root)
    for t in tasks:
        runs = sim.fleet_unit_runs(t.fleet, t.seed, t.index, t.protocols.split(","))
        registry.add_runs([as_run(r) for r in runs])
    return registry


def stored_or_simulated(root: Path, tasks: list[Task]) -> Registry:
    """The registry at `root` if an earlier call left every task's unit there, else the tasks
    simulated into it (a partly written one is an error: delete it and run again)."""
    if not root.exists():
        return simulate_units(root, tasks)
    registry = Registry(root)
    have = {r.unit for r in registry.list_runs()}
    missing = [u for u in (sim.unit_sensor_id(t.seed, t.index) for t in tasks) if u not in have]
    if missing:
        raise AnytipError(f"{root}: the stored extra units lack {missing[:3]} ({len(missing)} in all); "
                          "give the --extra and --workers it was written with, or delete it")
    return registry


def shard(tasks: list[Task], roles: Roles, seed: int, max_rows: int | None,
          store: Path | None = None) -> list[tuple[Key, Rows]]:
    """A worker: its units simulated, written and read back (or read from `store`, kept by an
    earlier call), and each unit's rows for each of its slots (the position in a training list
    seeds its validation rows, as in the pipeline)."""
    torch.set_num_threads(1)
    out = []
    with tempfile.TemporaryDirectory() as tmp:
        registry = (stored_or_simulated(store, tasks) if store is not None
                    else simulate_units(Path(tmp) / "registry", tasks))
        arrays = load_arrays(registry, registry.list_runs())
        for t in tasks:
            unit = sim.unit_sensor_id(t.seed, t.index)
            for key in t.keys:
                members, _, _ = training_units(arrays, [unit], roles, None, False, seed, first_index=key[1])
                m = members[0]
                rows = [a.numpy() for a in (m.X_train, m.Y_train, m.X_val, m.Y_val)]
                if max_rows is not None:
                    rows = capped(rows, max_rows, unit_seed(seed, key[1], "many units rows"))
                out.append((key, (unit, *rows)))
    return out


def capped(rows: list[np.ndarray], max_rows: int, seed: int) -> list[np.ndarray]:
    """At most `max_rows` random fitting rows and a tenth as many validation rows."""
    g = np.random.default_rng(seed)
    fit = np.sort(g.permutation(len(rows[0]))[:max_rows])
    val = np.sort(g.permutation(len(rows[2]))[:max(1, max_rows // 10)])
    return [rows[0][fit], rows[1][fit], rows[2][val], rows[3][val]]


def checked_store(store: Path, fleet: FleetConfig) -> None:
    """Records `fleet` in `store` (a new one), or checks that an earlier call stored units of the
    same fleet config (the units' ids do not say which fleet they were drawn from)."""
    marker, wanted = store / "extra_fleet.json", fleet.model_dump_json(indent=1)
    if marker.exists():
        if marker.read_text() != wanted:
            raise AnytipError(f"{store}: its extra units were simulated with another fleet config "
                              f"({marker}); give that --extra-fleet, or another --extra-store")
        return
    if store.exists() and any(store.iterdir()):
        raise AnytipError(f"{store}: holds extra units that name no fleet config; delete it or give another")
    store.mkdir(parents=True, exist_ok=True)
    marker.write_text(wanted)


def rows_digest(rows: Rows) -> str:
    """SHA-256 (hex) of a unit's id and its four row arrays."""
    h = hashlib.sha256(rows[0].encode())
    for a in rows[1:]:
        h.update(np.ascontiguousarray(a).data)
    return h.hexdigest()


def gather(tasks: list[Task], roles: Roles, seed: int, workers: int, max_rows: int | None,
           store: Path | None = None) -> dict[Key, Rows]:
    """{slot: rows} of every task, simulated by `workers` processes (each part kept in a registry
    under `store`, or read from it, where one is given)."""
    parts = [tasks[k::workers] for k in range(workers) if tasks[k::workers]]
    roots = [store / f"part{k}of{len(parts)}" if store else None for k in range(len(parts))]
    with ProcessPoolExecutor(len(parts), mp_context=get_context("spawn")) as pool:
        done = pool.map(shard, parts, [roles] * len(parts), [seed] * len(parts), [max_rows] * len(parts),
                        roots)
        return {key: rows for part in done for key, rows in part}


def folds_of(runs: list[Path]) -> list[Fold]:
    """Each seed of each run, with its training units from the run's provenance."""
    folds = []
    with tempfile.TemporaryDirectory() as tmp:
        for run_dir in runs:
            spec = load_spec(run_dir / "config.yaml", ["options.adapters=[]"])
            ctx = Context(spec, Registry(Path(tmp) / "none"), run_dir, torch.device("cpu"), False,
                          {"spec_file": str(run_dir / "config.yaml")})
            opts = parse_options(ctx)
            if opts.response is None:
                raise AnytipError(f"{run_dir}: its spec has no options.response")
            units, roles = read_json(run_dir / "provenance.json")["cross_sensor"], roles_of(ctx, opts)
            folds += [Fold(run_dir.name, seed, units[f"seed{seed}"]["units"]["train"], opts, roles)
                      for seed in spec.all_seeds]
    return folds


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", type=Path, help="finished cross_sensor runs with options.response")
    parser.add_argument("--registry-seed", type=int, required=True, help="the runs' registry's fleet seed")
    parser.add_argument("--registry-protocols", default="full,short,quick")
    parser.add_argument("--registry-fleet", type=Path, default=None,
                        help="fleet config YAML of the registry's units (default: the default fleet)")
    parser.add_argument("--extra-seed", type=int, default=8)
    parser.add_argument("--extra", default="128,1024", help="comma-separated counts of extra units")
    parser.add_argument("--extra-protocols", default="full")
    parser.add_argument("--extra-fleet", type=Path, default=None,
                        help="fleet config YAML of the extra units (default: the default fleet); a model's "
                        "name then ends in _<the file's stem>")
    parser.add_argument("--rows-per-step", default="", help="comma-separated rows_per_step to train with "
                        "besides the run's, at the largest count")
    parser.add_argument("--models", default="", help="comma-separated EXTRA:ROWS_PER_STEP models to train "
                        "(instead of --extra and --rows-per-step)")
    parser.add_argument("--extra-store", type=Path, default=None,
                        help="keep the extra units' registries here, or read them from an earlier call's "
                        "(same --extra-seed, counts and --workers), instead of simulating them again")
    parser.add_argument("--extra-split-seed", type=int, default=None,
                        help="the seed that splits and caps the extra units' rows (default: the first run's)")
    parser.add_argument("--max-rows", type=int, default=120_000)
    parser.add_argument("--steps", type=int, default=None, help="response model steps (default: the run's)")
    parser.add_argument("--workers", type=int, default=16)
    parser.add_argument("--device", default="cuda" if torch.cuda.is_available() else "cpu")
    parser.add_argument("--out", type=Path, required=True)
    args = parser.parse_args(argv)
    try:
        run(args)
    except AnytipError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    return 0


def extra_ids(seed: int, n: int) -> list[str]:
    """Units 0..n-1 of the extra fleet, sorted as a registry lists them."""
    return sorted(sim.unit_sensor_id(seed, i) for i in range(n))


def models_of(args: argparse.Namespace, recipe_rows: int) -> dict[int, list[int]]:
    """{extra units: [rows per step, ...]} to train: `--models`, or the recipe's rows per step at
    each count of `--extra` and `--rows-per-step`'s at the largest."""
    if args.models:
        try:
            pairs = [tuple(int(v) for v in m.split(":")) for m in args.models.split(",")]
        except ValueError:
            pairs = [()]
        if any(len(p) != 2 or min(p) < 0 for p in pairs):
            raise AnytipError(f"--models {args.models!r}: want comma-separated EXTRA:ROWS_PER_STEP pairs")
        return {n: [r for m, r in pairs if m == n] for n in sorted({p[0] for p in pairs})}
    counts = sorted(int(n) for n in args.extra.split(","))
    more = [int(r) for r in args.rows_per_step.split(",") if r]
    return {n: [recipe_rows, *(more if n == counts[-1] else [])] for n in counts}


def registry_rows(folds: list[Fold], args: argparse.Namespace) -> dict[Key, Rows]:
    """Every fold's training units' rows, each unit simulated once (its rows for each fold's seed
    and position)."""
    slots: dict[str, list[Key]] = {}
    for k, fold in enumerate(folds):
        for position, unit in enumerate(fold.train):
            slots.setdefault(unit, []).append((k, position))
    fleet = load_fleet_config(args.registry_fleet) if args.registry_fleet else FleetConfig()
    tasks = [Task(fleet, args.registry_seed, unit_index(u, args.registry_seed), args.registry_protocols,
                  tuple(keys)) for u, keys in slots.items()]
    got: dict[Key, Rows] = {}
    for seed in sorted({f.seed for f in folds}):  # the validation rows depend on the fold's seed
        mine = [replace(t, keys=tuple(k for k in t.keys if folds[k[0]].seed == seed)) for t in tasks]
        got |= gather([t for t in mine if t.keys], folds[0].roles, seed, args.workers, None)
    return got


def run(args: argparse.Namespace) -> None:
    start = time.perf_counter()
    folds = folds_of(args.runs)
    wanted = models_of(args, folds[0].opts.response.recipe().rows_per_step)
    counts = sorted(wanted)
    tag = f"_{args.extra_fleet.stem}" if args.extra_fleet else ""
    own = registry_rows(folds, args)
    first = max(len(f.train) for f in folds)  # extra units follow the training units, the same in every fold
    ids = extra_ids(args.extra_seed, counts[-1])
    extra_fleet = load_fleet_config(args.extra_fleet) if args.extra_fleet else FleetConfig()
    if args.extra_store is not None:
        checked_store(args.extra_store, extra_fleet)
    tasks = [Task(extra_fleet, args.extra_seed, unit_index(u, args.extra_seed), args.extra_protocols,
                  ((-1, first + j),)) for j, u in enumerate(ids)]
    split_seed = folds[0].seed if args.extra_split_seed is None else args.extra_split_seed
    extra = {rows[0]: rows for rows in gather(tasks, folds[0].roles, split_seed, args.workers,
                                              args.max_rows, args.extra_store).values()}
    log: dict[str, Any] = {"simulate_s": time.perf_counter() - start, "torch": torch.__version__,
                           "device": args.device,
                           "gpu": torch.cuda.get_device_name() if torch.cuda.is_available() else None,
                           "registry_rows_sha256": {}, "models": []}
    print(f"simulated {len(own)} registry unit slots and {len(extra)} extra units in "
          f"{log['simulate_s']:.0f} s", flush=True)
    args.out.mkdir(parents=True, exist_ok=True)
    log_path = args.out / f"log_{'_'.join(f'{f.name}-seed{f.seed}' for f in folds)}.json"
    for k, fold in enumerate(folds):
        rows = [own[(k, p)] for p in range(len(fold.train))]
        log["registry_rows_sha256"][f"{fold.name}_seed{fold.seed}"] = {r[0]: rows_digest(r) for r in rows}
        recipe = fold.opts.response.recipe()
        for n in counts:
            members = [UnitTensors(*(torch.from_numpy(a) for a in r[1:]), unit_id=r[0])
                       for r in rows + [extra[u] for u in extra_ids(args.extra_seed, n)]]
            data = FleetBatchData.from_units(members, args.device, OUTPUT_NAMES)
            for rps in wanted[n]:
                asked = replace(recipe, rows_per_step=rps, steps=args.steps or recipe.steps)
                name = f"{fold.name}_seed{fold.seed}_extra{n}_rps{rps}{tag}"
                log["models"].append(train_one(data, fold, asked, args.out / name))
                log_path.write_text(json.dumps(log, indent=1))
            del data
    print(f"done in {time.perf_counter() - start:.0f} s", flush=True)


def train_one(data: FleetBatchData, fold: Fold, recipe: ResponseRecipe, path: Path) -> dict[str, Any]:
    """A response model trained on `data` and saved at `path` (.safetensors and .json), with the
    metadata `ResponseFit.from_loaded` and `transfer_bounds.py` read; its wall time."""
    assert fold.opts.response is not None
    t = time.perf_counter()
    fit = train_response(data, [0, 1, 2], fold.opts.response.config(), recipe, fold.seed, data.device)
    if data.device.type == "cuda":
        torch.cuda.synchronize()
    wall = time.perf_counter() - t
    meta = {"unit_ids": fit.unit_ids, "source_unit_ids": list(fold.train), "seed": fold.seed,
            "output_names": list(OUTPUT_NAMES), "recipe": asdict(recipe), "wall_s": wall,
            "training_digest": None, "device": str(data.device)}
    save_response(path.with_suffix(".safetensors"), fit.model.cpu(), fit.noise_var.cpu(), fit.code_var.cpu(),
                  meta)
    print(f"{path.name}: {data.n_units} units, {recipe.steps} steps of {recipe.rows_per_step} rows, "
          f"{wall:.0f} s", flush=True)
    return {"file": path.name, "units": data.n_units, "rows_per_step": recipe.rows_per_step, "wall_s": wall}


if __name__ == "__main__":
    sys.exit(main())
