"""`anytip run SPEC`: validate the spec, prepare the run directory, run its pipeline,
write metrics and provenance, print a summary.
"""

from __future__ import annotations

import importlib
import inspect
import time
from collections import defaultdict
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import torch

from anytip import rundir
from anytip.config import ExperimentSpec, load_spec, public_config
from anytip.data.registry import Registry
from anytip.data.runfile import V1_LAYOUT
from anytip.errors import AnytipError
from anytip.pipelines.common import Context, check_options, check_registry, resolve_device
from anytip.train.metrics import target_key
from anytip.validation import mask_secrets


def fill_if_empty(spec: ExperimentSpec, registry: Registry, progress: bool) -> bool:
    """Simulate the spec's fleet into an empty registry when the spec asks for it."""
    if spec.simulate_if_empty is None or registry.list_runs():
        return False
    from anytip.data.simulated import simulate_into

    sim = spec.simulate_if_empty
    simulate_into(registry, spec.fleet, sim.units, sim.seed, sim.protocols, progress)
    print(f"simulated {sim.units} units into the empty registry {registry.root}")
    return True


def summarise(rows: list[dict[str, Any]], keys: Sequence[str] = ("force_rmse_n", "angle_rmse_rad")) -> str:
    """One screen: the mean of each target's RMSE (`keys`) per (method, split) group."""
    groups: dict[tuple, list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        groups[(r["method"], r.get("split", "-"))].append(r)
    keys = [k for k in keys if any(k in r for r in rows)]
    lines = [f"{'method':<24}{'split':<10}{'rows':>6}" + "".join(f"{k:>18}" for k in keys)]
    for (method, split), rs in sorted(groups.items()):
        means = [np.mean([r[k] for r in rs if k in r]) for k in keys]
        lines.append(f"{method:<24}{split:<10}{len(rs):>6}" + "".join(f"{m:>18.4g}" for m in means))
    return "\n".join(lines)


def run_experiment(spec_path: str | Path, registry: Registry | str | Path, out: str | Path | None = None,
                   overrides: list[str] | None = None, progress: bool = True, force: bool = False) -> Path:
    """Run one spec against `registry` (a Registry, or its directory: created only for a spec
    that simulates into an empty registry or a pipeline that reads none); returns the run
    directory.

    Everything a user can get wrong is checked before the run directory is made: the spec
    and its options, and whether the registry holds enough units. `out` must not hold a
    run already unless `force`.
    """
    spec = load_spec(spec_path, overrides)
    device = resolve_device(spec.device)
    module = importlib.import_module(f"anytip.pipelines.{spec.pipeline}")
    use = getattr(module, "REGISTRY", "required")  # "required", "optional" (any units) or "unused"
    if not isinstance(registry, Registry):
        registry = Registry(registry, create=spec.simulate_if_empty is not None or use == "unused")
    ctx = Context(spec, registry, Path(), device, progress)
    ctx.provenance["spec_file"] = str(spec_path)
    check_options(ctx, module)
    if out is not None:
        rundir.check_run_dir(Path(out), force)
    if spec.threads is not None:
        torch.set_num_threads(spec.threads)
    fill_if_empty(spec, registry, progress)
    if use == "required":
        need = module.min_units(ctx) if hasattr(module, "min_units") else 1
        fingertip_only = getattr(module, "FINGERTIP_ONLY", False)
        spec = ctx.spec = check_registry(spec, registry, need, str(spec_path), fingertip_only)
    run_dir = rundir.new_run_dir(spec.name, out, force=force)
    ctx.run_dir = run_dir
    rundir.write_config(run_dir, public_config(spec))
    ctx.provenance.update(overrides=[mask_secrets(o) for o in overrides or []], seeds=spec.all_seeds,
                          code=rundir.code_version(), machine=rundir.machine(), device=str(device))
    start = time.perf_counter()
    rows = module.run(ctx)
    ctx.provenance["wall_s"] = round(time.perf_counter() - start, 2)
    keys = [target_key(name) for name in ctx.provenance.get("targets", V1_LAYOUT)]
    rundir.write_metrics(run_dir, rows, keys, spec=spec.name, pipeline=spec.pipeline)
    rundir.write_json(run_dir / "provenance.json", ctx.provenance)
    if hasattr(module, "summarise"):  # a pipeline's own screen, given the targets where it takes them
        takes = "targets" in inspect.signature(module.summarise).parameters
        print(module.summarise(rows, ctx.provenance.get("targets")) if takes else module.summarise(rows))
    else:
        print(summarise(rows, keys))
    print(f"run directory: {run_dir}  (report: {run_dir / 'report.md'})")
    return run_dir


def rewrite_report(run_dir: str | Path) -> Path:
    """Write a finished run's report again from what the run recorded (its config.yaml,
    metrics.json and provenance.json), with this version's report writer: no training, no
    registry. For pipelines that provide `report(ctx, rows)`; others are refused by name."""
    run_dir = Path(run_dir)
    for name in ("config.yaml", "metrics.json", "provenance.json"):
        if not (run_dir / name).is_file():
            raise AnytipError(f"{run_dir}: not a finished run directory (no {name})")
    spec = load_spec(run_dir / "config.yaml")
    module = importlib.import_module(f"anytip.pipelines.{spec.pipeline}")
    if not hasattr(module, "report"):
        raise AnytipError(f"{run_dir}: pipeline {spec.pipeline!r} cannot rewrite its report from "
                          "recorded results; run the spec again")
    provenance = rundir.read_json(run_dir / "provenance.json")
    ctx = Context(spec, None, run_dir, torch.device("cpu"), False, provenance)  # type: ignore[arg-type]
    rows = rundir.read_json(run_dir / "metrics.json").get("results")
    if not isinstance(rows, list):
        raise AnytipError(f"{run_dir / 'metrics.json'}: no 'results' list")
    module.report(ctx, rows)
    return run_dir / "report.md"
