"""What a benchmark recorded, read for a new unit: the cross_sensor run directory and its shared and
response models, their validation-unit losses, priors and per-budget and per-strategy tables."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from anytip.errors import AnytipError
from anytip.models.io import RESPONSE_FORMAT, SHARED_FORMAT, model_paths, read_header
from anytip.validation import read_yaml


def run_config(run_dir: Path) -> dict[str, Any]:
    """The resolved spec of a cross_sensor run directory, checked enough to be used here."""
    config_path = run_dir / "config.yaml"
    if not config_path.is_file():
        raise AnytipError(f"{run_dir}: neither a shared model file nor a cross_sensor run directory "
                          "(no config.yaml)")
    config = read_yaml(config_path)
    if config.get("pipeline") != "cross_sensor":
        raise AnytipError(f"{config_path}: pipeline {config.get('pipeline')!r} holds no shared model; "
                          "calibrate needs a cross_sensor run")
    if not isinstance(config.get("options", {}), dict):
        raise AnytipError(f"{config_path}: key 'options' must be a mapping, got {config['options']!r}")
    seeds = config.get("seeds")
    if seeds is not None and not (isinstance(seeds, list) and all(type(x) is int for x in seeds)):
        raise AnytipError(f"{config_path}: key 'seeds' must be a list of integers, got {seeds!r}")
    if type(config.get("seed", 0)) is not int:
        raise AnytipError(f"{config_path}: key 'seed' must be an integer, got {config['seed']!r}")
    return config


def find_shared(model: str | Path, adapter: str | None = None, seed: int | None = None,
                budget: float | None = None) -> tuple[Path, str]:
    """A shared model file and why it was picked: `model` itself, or the one a cross_sensor run
    directory holds for `adapter` and `seed` (default: the run's first seed).

    Without `adapter`, the run's shared model with the lowest validation-unit loss recorded in
    its metadata is taken: at the largest benchmarked budget <= `budget` (labeled samples or
    robot-seconds, as the run budgeted; so a label-free calibration compares zero-shot
    losses), or the mean over budgets without one.
    A run that recorded none falls back to its `sweep_adapter`.
    """
    model = Path(model)
    if model.suffix in (".safetensors", ".json"):
        return model.with_suffix(".safetensors"), "the model file given"
    config = run_config(model)
    seeds = config.get("seeds") or [config.get("seed", 0)]
    seed = seeds[0] if seed is None else seed
    have = {p.stem: p for p in sorted((model / "models").glob(f"shared_*_seed{seed}.safetensors"))}
    if adapter is not None:
        path = model / "models" / f"shared_{adapter.replace('+', '-')}_seed{seed}.safetensors"
        if not path.is_file():
            raise AnytipError(f"{path}: no shared model for adapter {adapter!r}, seed {seed}; "
                              f"the run holds: {', '.join(have) or 'none'}")
        return path, f"adapter {adapter!r} as asked"
    losses = {stem: val_loss_of(path, budget) for stem, path in have.items()}
    scored = {stem: v for stem, v in losses.items() if v is not None}
    if scored:
        best = min(scored, key=scored.__getitem__)
        unit = "robot-seconds" if benchmarked_in(model) == "seconds" else "labeled samples"
        at = "mean over budgets" if budget is None else f"at <= {budget:g} {unit}"
        return have[best], (f"lowest validation-unit loss of the run, {at} ({scored[best]:.3g} standardised "
                            "MSE; " + ", ".join(f"{k}: {v:.3g}" for k, v in sorted(scored.items())) + ")")
    fallback = str(config.get("options", {}).get("sweep_adapter", "input_affine+film"))
    stem = f"shared_{fallback.replace('+', '-')}_seed{seed}"
    if stem not in have:
        raise AnytipError(f"{model}: no shared model of seed {seed} with a recorded validation loss, "
                          f"and none for the run's sweep adapter {fallback!r}; the run holds: "
                          f"{', '.join(have) or 'none'}")
    return have[stem], f"the run's sweep adapter {fallback!r} (the run recorded no validation loss)"


def val_loss_of(path: Path, budget: float | None) -> float | None:
    """A shared model file's recorded validation-unit loss (`val_loss_table`)."""
    meta = read_header(model_paths(path)[1], SHARED_FORMAT).get("meta", {})
    return val_loss_table(meta if isinstance(meta, dict) else {}, budget)


def val_loss_table(meta: dict[str, Any], budget: float | None) -> float | None:
    """The validation-unit loss a shared model's metadata records (`val_loss_by_budget`) at the
    largest budget <= `budget`, or its mean over budgets for None; None if it has none."""
    table = {b: float(v) for b, v in budget_table(meta, "val_loss_by_budget").items()
             if isinstance(v, (int, float)) and math.isfinite(v)}
    if budget is None:
        return float(np.mean(list(table.values()))) if table else None
    return at_budget(table, budget)


def own_check_table(meta: dict[str, Any], budget: float) -> list[float] | None:
    """The validation units' own-check losses the metadata records (`own_check_by_budget`) at
    the largest budget <= `budget`; None if it records none."""
    def finite(v: Any) -> bool:
        return isinstance(v, (int, float)) and math.isfinite(v)
    table = {b: [float(x) for x in v] for b, v in budget_table(meta, "own_check_by_budget").items()
             if isinstance(v, list) and v and all(finite(x) for x in v)}
    return at_budget(table, budget)


def budget_table(meta: dict[str, Any], key: str) -> dict[float, Any]:
    values = meta.get(key)
    return {float(b): v for b, v in values.items() if is_amount(b)} if isinstance(values, dict) else {}


def at_budget(table: dict[float, Any], budget: float) -> Any:
    below = [b for b in table if b <= budget]
    return table[max(below)] if below else None


def is_amount(text: Any) -> bool:
    try:
        return math.isfinite(float(text)) and float(text) >= 0
    except (TypeError, ValueError):
        return False


def prior_for(meta: dict[str, Any], n: float) -> float:
    """The validation-chosen prior of the largest benchmarked budget <= n (labeled samples, or
    robot seconds for a model benchmarked in seconds), else the default."""
    table = {float(b): float(p) for b, p in meta.get("priors_by_budget", {}).items() if is_amount(b)}
    below = [b for b in table if b <= n]
    return table[max(below)] if below else float(meta.get("default_prior", 10.0))


def benchmarked_in(model: str | Path) -> str:
    """'seconds' or 'samples': how the benchmark behind `model` (a run directory or a shared
    model file) budgeted calibrations."""
    model = Path(model)
    if model.suffix in (".safetensors", ".json"):
        meta = read_header(model_paths(model.with_suffix(".safetensors"))[1], SHARED_FORMAT).get("meta", {})
        unit = meta.get("budget_unit", "samples") if isinstance(meta, dict) else "samples"
    else:
        unit = run_config(model).get("options", {}).get("budget_unit", "samples")
    if unit not in ("samples", "seconds"):
        raise AnytipError(f"{model}: budget_unit {unit!r} is neither 'samples' nor 'seconds'")
    return unit


def strategy_table(meta: dict[str, Any], key: str, strategy: str) -> dict[float, Any]:
    """A response model's per-budget record for plans of `strategy` (`<key>_by_strategy`); a model
    saved before that key holds `val_loss_by_budget` keyed by budget labels ("120 s cover")."""
    table = meta.get(f"{key}_by_strategy")
    if isinstance(table, dict) and isinstance(table.get(strategy), dict):
        return {float(b): v for b, v in table[strategy].items() if is_amount(b)}
    old = meta.get(f"{key}_by_budget") if key == "val_loss" else None
    out: dict[float, Any] = {}
    for label, v in (old.items() if isinstance(old, dict) else []):
        parts = str(label).split()
        if len(parts) == 3 and parts[1] == "s" and parts[2] == strategy and is_amount(parts[0]):
            out[float(parts[0])] = v
    return out


def response_record(path: Path) -> dict[str, Any]:
    """The metadata a response model file's header records (empty where it records none)."""
    recorded = read_header(model_paths(path)[1], RESPONSE_FORMAT).get("meta", {})
    return recorded if isinstance(recorded, dict) else {}


def response_models(run: Path) -> dict[int, Path]:
    """{seed: model file} of the response models a run directory holds
    (`models/response_seed<seed>.safetensors`; not their start networks, `..._start`, nor the
    cached responses, `..._source`)."""
    found = {}
    for path in sorted((run / "models").glob("response_seed*.safetensors")):
        seed = path.stem.removeprefix("response_seed")
        if seed.isdigit():
            found[int(seed)] = path
    return found
