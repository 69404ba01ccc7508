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
import re
from pathlib import Path
from typing import Annotated, Any, Literal

from pydantic import BaseModel, ConfigDict, Field

from anytip.errors import AnytipError
from anytip.models.mlp import MLPConfig
from anytip.rundir import builtin
from anytip.sensor.fleet import FleetConfig
from anytip.sensor.protocols import TEST_SESSION
from anytip.train.recipe import FAST, TrainRecipe
from anytip.validation import NAME_PATTERN, load_yaml, mask_secrets, read_yaml, validate_strict

BLOCK_DIRS = {"fleet": "fleets", "model": "models", "training": "training"}
Pipeline = Literal["baseline", "cross_sensor", "deploy", "fleet_speed", "impulse_ratio", "realism",
                   "search", "sensor_models", "uncertainty"]


MAX_SEED = 2**32 - 1
Seed = Annotated[int, Field(ge=0, le=MAX_SEED)]


class Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)


class DataConfig(Strict):
    """Which runs of the registry an experiment reads."""

    sensor_model: str | None = None  # None: the model with the most units
    # catalog protocol(s) of the runs to read (plus measured runs that record none); None: all
    protocol: str | list[str] | None = "full"

    @property
    def protocols(self) -> list[str] | None:
        return [self.protocol] if isinstance(self.protocol, str) else self.protocol
    max_units: int | None = Field(default=None, ge=1, le=100_000)  # cap on units used, chosen by seed


class SimulateIfEmpty(Strict):
    """Fill an empty registry with a simulated fleet before running (the quickstart)."""

    units: int = Field(default=8, ge=1, le=10_000)
    seed: Seed = 0
    protocols: list[str] = ["full", "short"]


class SplitConfig(Strict):
    """Unit roles and row splits."""

    n_val_units: int = Field(default=0, ge=0, le=100_000)
    n_test_units: int = Field(default=0, ge=0, le=100_000)
    n_train_units: int | None = Field(default=None, ge=1, le=100_000)
    # held-out units as rotating folds: seed s holds out fold s % K (n_test_units then unused)
    unit_folds: int | None = Field(default=None, ge=2, le=100_000)
    random_test_fraction: float = Field(default=0.1, gt=0, lt=1)  # the paper's 90/10 rows
    patch_test_fraction: float = Field(default=0.2, gt=0, lt=1)  # whole held-out patches
    val_fraction: float = Field(default=0.1, gt=0, lt=1)  # of training rows, for early stopping
    # a validation or held-out unit's test rows at its test patches: its test session's (`retest`) where it
    # has one, else its main rows' (`test_session`); or both sessions' rows (`all_sessions`), so that a
    # unit-output's coverage carries less of one session's draw
    test_rows: Literal["test_session", "all_sessions"] = "test_session"


class ExperimentSpec(Strict):
    """One experiment: what runs, on what data, with which model and recipe."""

    name: str = Field(pattern=NAME_PATTERN, description="a directory name under runs/")
    pipeline: Pipeline
    description: str = ""
    seed: Seed = 0
    seeds: list[Seed] | None = Field(None, min_length=1, max_length=1000)  # one result row per seed
    device: Literal["auto", "cpu", "cuda"] = "auto"
    # torch CPU threads; tiny per-unit nets run fastest on one (None: torch's default)
    threads: int | None = Field(default=1, ge=1, le=1024)
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


def configs_dirs(spec_path: Path) -> list[Path]:
    """Where a spec's blocks are looked up, in order: a `configs/` beside the spec's project
    (searched upward from the spec, so a lab keeps its own blocks), then the built-in ones."""
    dirs = [parent / "configs" for parent in [spec_path.resolve().parent, *spec_path.resolve().parents]
            if (parent / "configs").is_dir()][:1]
    shipped = builtin("configs")
    return dirs + [shipped] if not dirs or dirs[0].resolve() != shipped.resolve() else dirs


def _resolve_block(kind: str, value: Any, configs: list[Path], spec_path: Path) -> dict[str, Any]:
    if isinstance(value, str):
        value = {"use": value}
    if not isinstance(value, dict):
        raise AnytipError(f"{spec_path}: key '{kind}' must be a name or a mapping, got {value!r}")
    value = dict(value)
    name = value.pop("use", None)
    if name is None:
        return value
    if not isinstance(name, str) or not re.fullmatch(NAME_PATTERN, name):
        raise AnytipError(f"{spec_path}: key '{kind}.use' must name a block in configs/{BLOCK_DIRS[kind]}/ "
                          f"(letters, digits, '_', '-', '.'; no path), got {name!r}")
    for folder in configs:
        block_file = folder / BLOCK_DIRS[kind] / f"{name}.yaml"
        if block_file.is_file():
            return {**read_yaml(block_file), **value}
    known = sorted({p.stem for folder in configs for p in (folder / BLOCK_DIRS[kind]).glob("*.yaml")})
    raise AnytipError(f"{spec_path}: key '{kind}': no block {name!r}; allowed: {', '.join(known)}")


def apply_override(data: dict[str, Any], assignment: str) -> None:
    """Apply one `a.b.c=value` override in place; the value is parsed as YAML."""
    if "=" not in assignment:
        raise AnytipError(f"--set {assignment!r}: expected key=value")
    key, raw = assignment.split("=", 1)
    parts = key.strip().split(".")
    if not all(parts):
        raise AnytipError(f"--set {assignment!r}: {key!r} is not a dotted key like training.epochs")
    node = data
    for part in parts[:-1]:
        node = node.setdefault(part, {})
        if not isinstance(node, dict):
            raise AnytipError(f"--set {assignment!r}: {part!r} is not a mapping")
    node[parts[-1]] = load_yaml(raw, f"--set {assignment!r}")


def public_config(spec: ExperimentSpec) -> dict[str, Any]:
    """The resolved spec as written to a run's config.yaml: plain values, URL passwords masked."""
    return mask_secrets(spec.model_dump(mode="json"))


def load_spec(path: str | Path, overrides: list[str] | None = None) -> ExperimentSpec:
    """Read, compose, override and validate an experiment spec."""
    path = Path(path)
    raw = read_yaml(path)
    configs = configs_dirs(path)
    data = copy.deepcopy(raw)
    data.setdefault("name", path.stem)
    for kind in BLOCK_DIRS:
        if kind in data:
            data[kind] = _resolve_block(kind, data[kind], configs, path)
    for assignment in overrides or []:
        apply_override(data, assignment)
    source = f"{path}" + (f" (with --set {' '.join(overrides)})" if overrides else "")
    spec = validate_strict(ExperimentSpec, data, source)
    _check_sessions(spec, source)
    return spec


def _check_sessions(spec: ExperimentSpec, source: str) -> None:
    """`splits.test_rows: all_sessions` asks for a unit's test session's rows, so `data.protocol` must
    read its runs (`retest`): a list without it would silently test every unit on its main rows alone."""
    protocols = spec.data.protocols
    if spec.splits.test_rows == "all_sessions" and protocols is not None and TEST_SESSION not in protocols:
        raise AnytipError(f"{source}: key 'splits.test_rows' is all_sessions, but key 'data.protocol' "
                          f"({', '.join(protocols)}) leaves out the test sessions' runs ({TEST_SESSION}); "
                          f"add {TEST_SESSION} to data.protocol or set it to null (every protocol)")
