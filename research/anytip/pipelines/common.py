"""What every pipeline does first: pick runs from the registry, load them, build per-unit
tensors for a row split, and score per-unit models on their test rows.
"""

from __future__ import annotations

import sys
import time
from collections import Counter
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
import torch
from pydantic import BaseModel

from anytip.config import DataConfig, ExperimentSpec
from anytip.data.arrays import FleetArrays, has_patch_grid, load_arrays, output_names
from anytip.data.registry import Registry, RunRecord
from anytip.data.runfile import V1_LAYOUT, describe_layout, describe_targets, parse_layout
from anytip.data.seeds import VALIDATION_ROWS, stream_seed
from anytip.data.splits import TestMask
from anytip.errors import AnytipError
from anytip.report.metric import FINGERTIP_METRICS, Metric
from anytip.train.data import FleetBatchData, split_validation, unit_tensors
from anytip.train.fleet import FitResult
from anytip.train.metrics import predict, target_key
from anytip.validation import validate_strict


@dataclass
class Context:
    """What a pipeline gets: the spec, the registry, where to write, the device."""

    spec: ExperimentSpec
    registry: Registry
    run_dir: Path
    device: torch.device
    progress: bool = True
    provenance: dict[str, Any] = field(default_factory=dict)
    started: float = field(default_factory=time.perf_counter)
    narrate: bool = True  # `say` writes; progress bars show only on a terminal, these lines anywhere

    def say(self, text: str) -> None:
        """One line on stderr, with the seconds since the run began: what a long run has done so
        far, also where no progress bar renders (a log file). Nothing unless `narrate`."""
        if self.narrate:
            print(f"[{self.spec.name} +{time.perf_counter() - self.started:.0f} s] {text}", file=sys.stderr,
                  flush=True)


M = TypeVar("M", bound=BaseModel)


def validate_options(ctx: Context, model: type[M], raw: dict[str, Any] | None = None) -> M:
    """The spec's `options:` (or `raw`) as the pipeline's options model; a bad key or value
    stops the run with the spec file, the key and what is allowed."""
    source = str(ctx.provenance.get("spec_file", ctx.spec.name))
    return validate_strict(model, dict(ctx.spec.options) if raw is None else raw, source, "options")


def check_options(ctx: Context, module: Any) -> None:
    """Validate the spec's options the way `module` (a pipeline) will, before any work: its
    `parse_options(ctx)`, else its `Options` model, else it takes none."""
    if hasattr(module, "parse_options"):
        module.parse_options(ctx)
    elif hasattr(module, "Options"):
        validate_options(ctx, module.Options)
    elif ctx.spec.options:
        raise AnytipError(f"{ctx.provenance.get('spec_file', ctx.spec.name)}: pipeline "
                          f"{ctx.spec.pipeline!r} takes no options; got {sorted(ctx.spec.options)}")


def resolve_device(name: str) -> torch.device:
    if name == "auto":
        return torch.device("cuda" if torch.cuda.is_available() else "cpu")
    if name == "cuda" and not torch.cuda.is_available():
        raise AnytipError("device 'cuda' was asked for but torch sees no CUDA device; use 'cpu' or 'auto'")
    return torch.device(name)


def select_runs(registry: Registry, cfg: DataConfig, seed: int,
                min_units: int = 1) -> tuple[str, list[RunRecord]]:
    """Runs of one sensor model (the named one, else the one with most units).

    `protocol` keeps runs of that protocol and measured runs (no protocol recorded);
    `max_units` keeps that many units, chosen by `seed`.
    """
    records = registry.list_runs()
    if not records:
        raise AnytipError(f"registry {registry.root} is empty; add runs with "
                          "`anytip data simulate` or `anytip data import`")
    if cfg.protocols is not None:
        records = [r for r in records if r.protocol is None or r.protocol in cfg.protocols]
    units_per_model = Counter()
    for model, _unit in {(r.sensor_model, r.unit) for r in records}:
        units_per_model[model] += 1
    if cfg.sensor_model is None:
        if not units_per_model:
            raise AnytipError(f"registry {registry.root} holds no runs of protocol {cfg.protocol!r}")
        model = max(sorted(units_per_model), key=lambda m: units_per_model[m])
    else:
        model = cfg.sensor_model
    records = [r for r in records if r.sensor_model == model]
    units = sorted({r.unit for r in records})
    if len(units) < min_units:
        have = ", ".join(f"{m}: {n}" for m, n in sorted(units_per_model.items())) or "none"
        raise AnytipError(
            f"registry {registry.root} holds {len(units)} units of sensor model {model!r} "
            f"(protocol {cfg.protocol!r}); this experiment needs at least {min_units} "
            f"(units per model: {have})"
        )
    if cfg.max_units is not None and len(units) > cfg.max_units:
        keep = set(np.random.default_rng(seed).choice(units, cfg.max_units, replace=False))
        records = [r for r in records if r.unit in keep]
    return model, records


ANY_SENSOR_PIPELINES = ("baseline", "cross_sensor", "sensor_models", "uncertainty", "search", "deploy")


def check_registry(spec: ExperimentSpec, registry: Registry, min_units: int = 1,
                   source: str = "spec", fingertip_only: bool = False) -> ExperimentSpec:
    """Stop before any work when the registry cannot serve the spec: fewer units than the
    spec's unit roles (validation + held-out + training) or the pipeline's `min_units`, a
    model whose explicit input or output width disagrees with the sensor model's channels
    and label columns, or a pipeline written for the fingertip (`fingertip_only`) on another
    sensor model. Returns the spec with the model's widths set from the sensor model."""
    s = spec.splits
    roles = 1
    if s.n_val_units or s.n_test_units:
        roles = s.n_val_units + s.n_test_units + (s.n_train_units or 1)
    model, _ = select_runs(registry, spec.data, spec.seed, 1)  # the design first: more units would not help
    channels, targets = parse_layout(registry.sensor_models()[model])
    if fingertip_only and not has_patch_grid(targets):
        raise AnytipError(f"{source}: pipeline {spec.pipeline!r} is written for the fingertip's targets "
                          f"({describe_targets(V1_LAYOUT)}); sensor model {model!r} has "
                          f"{describe_targets(targets)}. Pipelines for any sensor model: "
                          f"{', '.join(ANY_SENSOR_PIPELINES)}")
    select_runs(registry, spec.data, spec.seed, max(min_units, roles))
    outputs = len(output_names(targets))
    return spec.model_copy(update={"model": spec.model.for_sensor(channels, outputs, source, model)})


def load(ctx: Context, min_units: int = 1) -> FleetArrays:
    model, records = select_runs(ctx.registry, ctx.spec.data, ctx.spec.seed, min_units)
    arrays = load_arrays(ctx.registry, records)
    ctx.provenance.update(
        sensor_model=model, runs=[r.run_id for r in records], units=arrays.units,
        registry=str(ctx.registry.root), registry_content_hash=ctx.registry.content_hash(),
        selection_content_hash=ctx.registry.content_hash([r.run_id for r in records]),
        targets={name: t.to_json() for name, t in arrays.layout.items()},
    )
    return arrays


def load_extra(ctx: Context, root: str, data: DataConfig, like: FleetArrays,
               source: str = "options.extra_units") -> FleetArrays:
    """Training-only units from another registry (`root`, relative to the working directory):
    runs of the sensor model `ctx` loaded, which must have the same channels and targets, and
    no unit that `like` (the experiment's own units) holds. Recorded in the provenance under
    `extra_units`."""
    registry = Registry(Path(root), create=False)
    model = ctx.provenance["sensor_model"]
    mine, theirs = ctx.registry.sensor_models().get(model), registry.sensor_models().get(model)
    if theirs is None or parse_layout(theirs) != parse_layout(mine):
        found = describe_layout(theirs) if theirs else "no runs of it"
        raise AnytipError(f"{source}: registry {root} must hold sensor model {model!r} with "
                          f"{describe_layout(mine)}; it has {found}")
    _, records = select_runs(registry, data.model_copy(update={"sensor_model": model}), ctx.spec.seed, 1)
    both = sorted({r.unit for r in records} & set(like.units))
    if both:
        raise AnytipError(f"{source}: registry {root} holds {len(both)} units that the experiment's "
                          f"registry holds too ({', '.join(both[:4])}); a validation or held-out unit "
                          f"must never train the shared model")
    arrays = load_arrays(registry, records)
    ctx.provenance["extra_units"] = {
        "registry": str(registry.root), "registry_content_hash": registry.content_hash(),
        "selection_content_hash": registry.content_hash([r.run_id for r in records]),
        "units": arrays.units, "runs": len(records),
    }
    return arrays


@dataclass
class UnitSplitRows:
    """Per-unit models' data for one split: training tensors and test rows (numpy)."""

    data: FleetBatchData
    X_test: list[np.ndarray]
    Y_test: list[np.ndarray]
    test_rows: list[np.ndarray]  # indices into the FleetArrays rows


def per_unit_split(arrays: FleetArrays, units: Sequence[str], test_mask: TestMask,
                   val_fraction: float, seed: int, device: torch.device) -> UnitSplitRows:
    """For each unit: test rows from `test_mask`, the rest split into train and validation."""
    targets = arrays.targets
    members, X_test, Y_test, test_rows = [], [], [], []
    for u, unit in enumerate(units):
        rows = np.flatnonzero(arrays.unit == arrays.units.index(unit))
        test = test_mask(arrays.patch[rows], u)
        train_rows, held = rows[~test], rows[test]
        rng = np.random.default_rng(stream_seed(VALIDATION_ROWS, seed, u))
        fit_rows, val_rows = split_validation(train_rows, val_fraction, rng)
        members.append(unit_tensors(arrays, fit_rows, val_rows, unit))
        X_test.append(arrays.pressure[held])
        Y_test.append(targets[held])
        test_rows.append(held)
    data = FleetBatchData.from_units(members, device, arrays.output_names)
    return UnitSplitRows(data, X_test, Y_test, test_rows)


def predict_units(fit: FitResult, X: Sequence[np.ndarray], first_model: int = 0) -> list[np.ndarray]:
    """Physical predictions of models first_model.. on their own rows: [(n_u, 5), ...]."""
    out = []
    for k, x in enumerate(X):
        m = first_model + k
        model = fit.model.model_slice(m)
        xt = torch.from_numpy(x).to(fit.in_scaler.mean.device)[None]
        pred = predict(model, fit.in_scaler.slice(m), fit.out_scaler.slice(m), xt)[0]
        out.append(pred.cpu().numpy())
    return out


def report_metrics(units: dict[str, str]) -> list[Metric]:
    """The report columns of a sensor model's targets, given {target: unit}; the fingertip's are
    `force` [N] and `angle` [rad] under its historical keys."""
    names = {"angles": "angle"}
    return [Metric(target_key(n), names.get(n, n), f"{names.get(n, n)} RMSE [{unit}]")
            for n, unit in units.items()]


def recorded_metrics(targets: dict[str, Any] | None) -> list[Metric]:
    """The report columns of the targets a run recorded (`provenance["targets"]`), or the fingertip's
    force and angle for a run that recorded none."""
    return report_metrics(unit_of(targets)) if targets else list(FINGERTIP_METRICS)


def unit_of(targets: dict[str, Any]) -> dict[str, str]:
    """{target: unit} of recorded targets ({target: {"unit": ..., "components": [...]}})."""
    return {name: t["unit"] for name, t in targets.items()}
