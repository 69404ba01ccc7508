"""Experiment specs: YAML files that name a pipeline and compose blocks from `configs/`.

A spec holds only what differs from the defaults. A block (`fleet`, `model`,
`training`) is either the name of a file `configs/<kind>/<name>.yaml` or a mapping
whose optional `use:` names such a file and whose other keys override it. `--set
a.b=value` overrides any key after composition (the value is parsed as YAML).
Every mistake stops the run before any work with an error that names the file, the
key and what is allowed.
"""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any, Literal

import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from anytip.errors import AnytipError
from anytip.models.mlp import MLPConfig
from anytip.sensor.fleet import FleetConfig
from anytip.train.recipe import FAST, TrainRecipe
from anytip.validation import format_validation_error

BLOCK_DIRS = {"fleet": "fleets", "model": "models", "training": "training"}
Pipeline = Literal["baseline", "cross_sensor", "deploy", "fleet_speed", "impulse_ratio", "realism",
                   "search", "uncertainty"]


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class DataConfig(Strict):
    """Which runs of the registry an experiment reads."""

    sensor_model: str | None = None  # None: the model with the most units
    # catalog protocol(s) of the runs to read (plus measured runs that record none); None: all
    protocol: str | list[str] | None = "full"

    @property
    def protocols(self) -> list[str] | None:
        return [self.protocol] if isinstance(self.protocol, str) else self.protocol
    max_units: int | None = Field(default=None, ge=1)  # cap on units used, chosen by seed


class SimulateIfEmpty(Strict):
    """Fill an empty registry with a simulated fleet before running (the quickstart)."""

    units: int = Field(default=8, ge=1)
    seed: int = 0
    protocols: list[str] = ["full", "short"]


class SplitConfig(Strict):
    """Unit roles and row splits."""

    n_val_units: int = Field(default=0, ge=0)
    n_test_units: int = Field(default=0, ge=0)
    n_train_units: int | None = Field(default=None, ge=1)
    random_test_fraction: float = Field(default=0.1, gt=0, lt=1)  # the paper's 90/10 rows
    patch_test_fraction: float = Field(default=0.2, gt=0, lt=1)  # whole held-out patches
    val_fraction: float = Field(default=0.1, gt=0, lt=1)  # of training rows, for early stopping


class ExperimentSpec(Strict):
    """One experiment: what runs, on what data, with which model and recipe."""

    name: str
    pipeline: Pipeline
    description: str = ""
    seed: int = 0
    seeds: list[int] | None = None  # several seeds: one result row per seed
    device: Literal["auto", "cpu", "cuda"] = "auto"
    # torch CPU threads; tiny per-unit nets run fastest on one (None: torch's default)
    threads: int | None = Field(default=1, ge=1)
    data: DataConfig = DataConfig()
    simulate_if_empty: SimulateIfEmpty | None = None
    fleet: FleetConfig = FleetConfig()
    model: MLPConfig = MLPConfig()
    training: TrainRecipe = FAST
    splits: SplitConfig = SplitConfig()
    recipes: list[str] = []  # pipelines that compare recipes name them here
    options: dict[str, Any] = {}  # pipeline-specific knobs, validated by the pipeline

    @property
    def all_seeds(self) -> list[int]:
        return self.seeds if self.seeds else [self.seed]


def find_configs_dir(spec_path: Path) -> Path | None:
    """The `configs/` directory beside the spec's project: searched upward from the spec."""
    for parent in [spec_path.resolve().parent, *spec_path.resolve().parents]:
        if (parent / "configs").is_dir():
            return parent / "configs"
    return None


def read_yaml(path: Path) -> dict[str, Any]:
    """A YAML mapping from `path`, or an AnytipError naming the file."""
    try:
        data = yaml.safe_load(path.read_text())
    except FileNotFoundError:
        raise AnytipError(f"{path}: no such file") from None
    except yaml.YAMLError as e:
        raise AnytipError(f"{path}: not valid YAML: {e}") from None
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise AnytipError(f"{path}: expected a mapping of keys to values, got {type(data).__name__}")
    return data


def _resolve_block(kind: str, value: Any, configs: Path | None, spec_path: Path) -> dict[str, Any]:
    if isinstance(value, str):
        value = {"use": value}
    if not isinstance(value, dict):
        raise AnytipError(f"{spec_path}: key '{kind}' must be a name or a mapping, got {value!r}")
    value = dict(value)
    name = value.pop("use", None)
    if name is None:
        return value
    if configs is None:
        raise AnytipError(f"{spec_path}: key '{kind}' names {name!r} but no configs/ directory was found")
    block_file = configs / BLOCK_DIRS[kind] / f"{name}.yaml"
    if not block_file.is_file():
        known = sorted(p.stem for p in (configs / BLOCK_DIRS[kind]).glob("*.yaml"))
        raise AnytipError(f"{spec_path}: key '{kind}': no block {name!r}; allowed: {', '.join(known)}")
    return {**read_yaml(block_file), **value}


def apply_override(data: dict[str, Any], assignment: str) -> None:
    """Apply one `a.b.c=value` override in place; the value is parsed as YAML."""
    if "=" not in assignment:
        raise AnytipError(f"--set {assignment!r}: expected key=value")
    key, raw = assignment.split("=", 1)
    parts = key.strip().split(".")
    node = data
    for part in parts[:-1]:
        node = node.setdefault(part, {})
        if not isinstance(node, dict):
            raise AnytipError(f"--set {assignment!r}: {part!r} is not a mapping")
    node[parts[-1]] = yaml.safe_load(raw)


def load_spec(path: str | Path, overrides: list[str] | None = None) -> ExperimentSpec:
    """Read, compose, override and validate an experiment spec."""
    path = Path(path)
    raw = read_yaml(path)
    configs = find_configs_dir(path)
    data = copy.deepcopy(raw)
    data.setdefault("name", path.stem)
    for kind in BLOCK_DIRS:
        if kind in data:
            data[kind] = _resolve_block(kind, data[kind], configs, path)
    for assignment in overrides or []:
        apply_override(data, assignment)
    try:
        return ExperimentSpec.model_validate(data)
    except ValidationError as e:
        source = f"{path}" + (f" (with --set {' '.join(overrides)})" if overrides else "")
        raise AnytipError(format_validation_error(e, source, ExperimentSpec)) from None
