"""`anytip run SPEC`: validate the spec, prepare the run directory, run its pipeline,
write metrics and provenance, print a summary.
"""

from __future__ import annotations

import importlib
import time
from collections import defaultdict
from pathlib import Path
from typing import Any

import numpy as np
import torch

from anytip import rundir
from anytip.config import ExperimentSpec, load_spec
from anytip.data.registry import Registry
from anytip.pipelines.common import Context, resolve_device


def fill_if_empty(spec: ExperimentSpec, registry: Registry, progress: bool) -> bool:
    """Simulate the spec's fleet into an empty registry when the spec asks for it."""
    if spec.simulate_if_empty is None or registry.list_runs():
        return False
    from anytip.data.simulated import simulate_into

    sim = spec.simulate_if_empty
    simulate_into(registry, spec.fleet, sim.units, sim.seed, sim.protocols, progress)
    print(f"simulated {sim.units} units into the empty registry {registry.root}")
    return True


def summarise(rows: list[dict[str, Any]]) -> str:
    """One screen: mean force and angle RMSE per (method, split, calib_samples) group."""
    groups: dict[tuple, list[dict[str, Any]]] = defaultdict(list)
    for r in rows:
        groups[(r["method"], r.get("split", "-"))].append(r)
    lines = [f"{'method':<24}{'split':<10}{'rows':>6}{'force RMSE [N]':>16}{'angle RMSE [rad]':>18}"]
    for (method, split), rs in sorted(groups.items()):
        f = np.mean([r["force_rmse_n"] for r in rs])
        a = np.mean([r["angle_rmse_rad"] for r in rs])
        lines.append(f"{method:<24}{split:<10}{len(rs):>6}{f:>16.3f}{a:>18.4f}")
    return "\n".join(lines)


def run_experiment(spec_path: str | Path, registry: Registry, out: str | Path | None = None,
                   overrides: list[str] | None = None, progress: bool = True) -> Path:
    """Run one spec against `registry`; returns the run directory."""
    spec = load_spec(spec_path, overrides)
    device = resolve_device(spec.device)
    if spec.threads is not None:
        torch.set_num_threads(spec.threads)
    module = importlib.import_module(f"anytip.pipelines.{spec.pipeline}")
    fill_if_empty(spec, registry, progress)
    run_dir = rundir.new_run_dir(spec.name, out)
    rundir.write_config(run_dir, spec.model_dump(mode="json"))
    ctx = Context(spec, registry, run_dir, device, progress)
    ctx.provenance.update(spec_file=str(spec_path), overrides=overrides or [], seeds=spec.all_seeds,
                          code=rundir.code_version(), machine=rundir.machine(), device=str(device))
    start = time.perf_counter()
    rows = module.run(ctx)
    ctx.provenance["wall_s"] = round(time.perf_counter() - start, 2)
    rundir.write_metrics(run_dir, rows, spec=spec.name, pipeline=spec.pipeline)
    rundir.write_json(run_dir / "provenance.json", ctx.provenance)
    print(getattr(module, "summarise", summarise)(rows))
    print(f"run directory: {run_dir}  (report: {run_dir / 'report.md'})")
    return run_dir
