"""`anytip calibrate`: a new unit's per-unit model from a shared model and minutes of data.

Takes the unit's calibration stream from the registry (its runs of the shared model's
calibration protocol, in recorded order), sets its input statistics from the stream's
pressures (no labels), fits its adapter on the first N labeled rows, folds it into a plain
MLP of the deployed shape and saves it in the per-unit model format (models/io.py), which
is what export reads. Rows of the unit's other runs, which calibration never touched,
score the result when there are any.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import torch
import yaml

from anytip.data.arrays import load_arrays
from anytip.data.calibration import CalibrationStream, calibration_stream
from anytip.data.registry import Registry
from anytip.errors import AnytipError
from anytip.models.io import load_shared, save_models
from anytip.models.scaler import Scaler
from anytip.pipelines.common import scores
from anytip.train.adapt import AdapterRecipe, calibrate_and_fold
from anytip.train.metrics import predict


@dataclass
class Calibrated:
    """What `calibrate_unit` wrote and measured."""

    path: Path
    unit: str
    calib_samples: int
    calib_seconds: float
    unlabeled_samples: int
    prior: float
    check: dict[str, float] | None  # RMSE on the unit's other runs, when it has any


def find_shared(model: str | Path, adapter: str | None = None, seed: int | None = None) -> Path:
    """A shared model file: `model` itself, or the one a cross_sensor run directory holds for
    `adapter` (default: the run's sweep adapter) and `seed` (default: its first seed)."""
    model = Path(model)
    if model.suffix in (".safetensors", ".json"):
        return model.with_suffix(".safetensors")
    config_path = model / "config.yaml"
    if not config_path.is_file():
        raise AnytipError(f"{model}: neither a shared model file nor a cross_sensor run directory "
                          "(no config.yaml)")
    config = yaml.safe_load(config_path.read_text()) or {}
    if config.get("pipeline") != "cross_sensor":
        raise AnytipError(f"{config_path}: pipeline {config.get('pipeline')!r} holds no shared model; "
                          "calibrate needs a cross_sensor run")
    adapter = adapter or config.get("options", {}).get("sweep_adapter", "input_affine+film")
    seeds = config.get("seeds") or [config.get("seed", 0)]
    seed = seeds[0] if seed is None else seed
    path = model / "models" / f"shared_{adapter.replace('+', '-')}_seed{seed}.safetensors"
    if not path.is_file():
        have = sorted(p.stem for p in (model / "models").glob("shared_*.safetensors"))
        raise AnytipError(f"{path}: no shared model for adapter {adapter!r}, seed {seed}; "
                          f"the run holds: {', '.join(have) or 'none'}")
    return path


def budget_rows(stream: CalibrationStream, samples: int | None, seconds: float | None) -> int:
    """Labeled rows a budget grants: a sample count, or all rows within `seconds` of robot time
    (the caller makes sure at most one is given)."""
    if seconds is not None:
        return int(np.searchsorted(stream.seconds, seconds, side="right"))
    n = 1000 if samples is None else samples
    if n < 0:
        raise AnytipError(f"--budget-samples must be >= 0, got {n}")
    return min(n, len(stream.rows))


def prior_for(meta: dict[str, Any], n: int) -> float:
    """The validation-chosen prior of the largest benchmarked budget <= n (else the default)."""
    table = {int(b): float(p) for b, p in meta.get("priors_by_budget", {}).items()}
    below = [b for b in table if b <= n]
    return table[max(below)] if below else float(meta.get("default_prior", 10.0))


def calibrate_unit(model: str | Path, unit: str, registry: Registry, out: str | Path,
                   budget_samples: int | None = None, budget_seconds: float | None = None,
                   adapter: str | None = None, seed: int | None = None) -> Calibrated:
    """Fit, fold and save one unit's model; see the module docstring."""
    if budget_samples is not None and budget_seconds is not None:
        raise AnytipError("give --budget-samples or --budget-seconds, not both")
    shared_path = find_shared(model, adapter, seed)
    shared = load_shared(shared_path)
    meta = shared.meta
    records = registry.list_runs(unit=unit)
    if not records:
        raise AnytipError(f"registry {registry.root} holds no runs of unit {unit!r}")
    want = meta.get("sensor_model")
    if want and any(r.sensor_model != want for r in records):
        models = sorted({r.sensor_model for r in records})
        raise AnytipError(f"unit {unit} is a {models} sensor; the shared model {shared_path} was "
                          f"trained on {want!r}")
    arrays = load_arrays(registry, records)
    stream = calibration_stream(arrays, unit, meta.get("calibration_protocol"),
                                interleave=bool(meta.get("calibration_interleave", False)))
    n = budget_rows(stream, budget_samples, budget_seconds)
    prior = prior_for(meta, n)
    labeled = stream.first(n)
    unlabeled = [torch.from_numpy(arrays.pressure[stream.rows])]
    X, Y = [torch.from_numpy(arrays.pressure[labeled])], [torch.from_numpy(arrays.targets[labeled])]
    recipe = AdapterRecipe(**meta.get("adapter_recipe", {}))
    folded, stats = calibrate_and_fold(shared, unlabeled, X, Y, [n], [prior], recipe,
                                       seed=int(meta.get("seed", 0)))
    out_scaler = Scaler(shared.out_scaler.mean.clone(), shared.out_scaler.std.clone())
    other = ~np.isin(arrays.run, [k for k, r in enumerate(arrays.runs) if r.run_id in stream.runs])
    check = None
    if other.any():
        pred = predict(folded, stats, out_scaler, torch.from_numpy(arrays.pressure[other])[None])[0]
        check = {"rows": int(other.sum()), **scores(pred.numpy(), arrays.targets[other])}
    result = Calibrated(Path(out), unit, n, stream.seconds_for(n), len(stream.rows), prior, check)
    save_models(Path(out) / "model.safetensors", folded, stats, out_scaler, {
        "unit_ids": [unit], "output_names": meta.get("output_names"), "shared_model": str(shared_path),
        "adapter": shared.model.kind, "calib_samples": n, "calib_seconds": result.calib_seconds,
        "unlabeled_samples": result.unlabeled_samples, "prior": prior,
        "calibration_runs": list(stream.runs), "check_on_other_runs": check,
    })
    (Path(out) / "calibration.json").write_text(json.dumps(
        {k: (str(v) if isinstance(v, Path) else v) for k, v in result.__dict__.items()}, indent=2) + "\n")
    return result
