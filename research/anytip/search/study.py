"""An Optuna study over MLP architectures under the microcontroller's budget.

A trial picks hidden widths, activation, input features (and, for shared cross-sensor models,
the adapter kind), learning rate and batch size; the budget (search/budget.py) becomes Optuna
constraints before any training, and an infeasible trial is pruned without training. A
feasible one is trained and scored on the search units' held-out patches by the family's
`fit_and_score` (per-unit: search/fit.py; shared: search/shared.py): objectives (force RMSE,
angle RMSE, MACs).
The study lives in a storage URL (SQLite in the run directory by default), so a killed
study resumes where it stopped: trials whose heartbeat stopped are marked failed and retried.
"""

from __future__ import annotations

import importlib.util
import warnings
from collections.abc import Callable
from dataclasses import dataclass
from typing import Annotated, Any, Literal

import numpy as np
import optuna
from pydantic import BaseModel, ConfigDict, Field, field_validator

from anytip.data.seeds import SEARCH_WORKER, stream_seed
from anytip.errors import AnytipError
from anytip.models.adapted import parse_kind
from anytip.models.features import FEATURES
from anytip.models.mlp import MAX_LAYERS, MAX_WIDTH
from anytip.search.budget import ACTIVATION_INSTRUCTIONS, Budget, constraints, cost
from anytip.train.adapt import ADAPTER_DECAY, AdapterRecipe
from anytip.train.recipe import TrainRecipe
from anytip.validation import mask_secrets

CONSTRAINT_NAMES = ("flash", "ram", "time")
PAPER_HIDDEN = (12, 64, 64)


@dataclass(frozen=True)
class Candidate:
    """What a trial trains: deployed layer widths (channels -> hidden -> outputs), the activation, the input
    features (folded into the first layer before scoring) and, for shared models, the adapter."""

    sizes: tuple[int, ...]
    activation: str = "relu"
    features: str = "raw"
    adapter: str | None = None


class SearchOptions(BaseModel):
    """`options:` of a search spec."""

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    n_trials: int = Field(default=24, ge=1, le=100_000)
    widths: list[Annotated[int, Field(ge=1, le=MAX_WIDTH)]] = [8, 12, 16, 24, 32, 48, 64, 96, 128]
    min_hidden: int = Field(default=1, ge=1)
    max_hidden: int = Field(default=3, ge=1, le=MAX_LAYERS)
    lr: tuple[float, float] = (3e-3, 3e-2)
    batch_sizes: list[Annotated[int, Field(ge=1, le=2**20)]] = [128, 256, 512]
    budget: str = "stm32f334"
    measure: bool = True  # compile and emulate where the toolchain is present
    storage: str | None = None  # an Optuna storage URL; default sqlite in the run directory
    study_name: str = "search"
    workers: int = Field(default=1, ge=1, le=256)  # processes sharing the study on this machine
    n_search_units: int = Field(default=4, ge=1, le=10_000)
    n_test_units: int = Field(default=4, ge=1, le=10_000)
    heartbeat_s: int = Field(default=30, ge=1, le=3600)
    seed: int = 0
    activations: list[str] = Field(default=["relu", "leaky_relu", "hardswish"], min_length=1)
    features: list[str] = Field(default=["raw", "neighbour_diffs"], min_length=1)
    family: Literal["per_unit", "shared"] = "per_unit"
    # shared family only: the first adapter kind is the one the paper's MLP is scored with
    adapters: list[str] = Field(default=["input_affine+film", "input_diag", "input_affine+embedding+film"],
                                min_length=1)
    n_train_units: int | None = Field(default=None, ge=1)  # shared: None takes every other unit
    max_train_rows: int | None = Field(default=None, ge=1)  # shared: rows per training unit, at random
    calib_samples: int = Field(default=1000, ge=1)  # labeled rows per search or test unit's adapter
    calibration_protocol: str = "short"
    prior: float = Field(default=100.0, ge=0)  # pull of a new unit's adapter toward the identity
    adapter_steps: int = Field(default=AdapterRecipe.steps, ge=1)
    adapter_lr: float = Field(default=AdapterRecipe.lr, gt=0)
    adapter_decay: float = Field(default=ADAPTER_DECAY, ge=0)

    @field_validator("activations")
    @classmethod
    def _exportable(cls, names: list[str]) -> list[str]:
        bad = [a for a in names if a not in ACTIVATION_INSTRUCTIONS]
        if bad:
            raise ValueError(f"{bad} cannot be searched: the microcontroller export computes only "
                             f"{list(ACTIVATION_INSTRUCTIONS)} (tanh, gelu and silu need libm)")
        return names

    @field_validator("features")
    @classmethod
    def _known_features(cls, names: list[str]) -> list[str]:
        bad = [f for f in names if f not in FEATURES]
        if bad:
            raise ValueError(f"unknown input features {bad}; known: {list(FEATURES)}")
        return names

    @field_validator("adapters")
    @classmethod
    def _known_adapters(cls, kinds: list[str]) -> list[str]:
        for kind in kinds:
            try:
                parse_kind(kind)
            except AnytipError as e:
                raise ValueError(str(e)) from None
        return kinds


@dataclass(frozen=True)
class Shape:
    """What the sensor model fixes of every candidate: its input width (pressure channels), its
    output width (label columns) and the result keys of its targets, the objectives."""

    channels: int = 8
    outputs: int = 5
    keys: tuple[str, ...] = ("force_rmse_n", "angle_rmse_rad")


FINGERTIP = Shape()


def suggest(trial: optuna.Trial, opts: SearchOptions,
            shape: Shape = FINGERTIP) -> tuple[Candidate, float, int]:
    """(candidate, lr, batch) of a trial; sizes run channels -> hidden widths -> outputs."""
    n = trial.suggest_int("n_hidden", opts.min_hidden, opts.max_hidden)
    choices = sorted(set(opts.widths) | set(PAPER_HIDDEN))  # the paper's MLP is always a candidate
    hidden = [trial.suggest_categorical(f"width{k}", choices) for k in range(opts.max_hidden)][:n]
    activation = trial.suggest_categorical("activation", opts.activations)
    features = trial.suggest_categorical("features", opts.features)
    adapter = trial.suggest_categorical("adapter", opts.adapters) if opts.family == "shared" else None
    lr = trial.suggest_float("lr", *opts.lr, log=True)
    batch = trial.suggest_categorical("batch_size", opts.batch_sizes)
    return Candidate((shape.channels, *hidden, shape.outputs), activation, features, adapter), lr, batch


def paper_params(opts: SearchOptions, recipe: TrainRecipe) -> dict[str, Any] | None:
    """The paper's 8-12-64-64-5 (ReLU, raw inputs, the first adapter kind) as a trial to enqueue
    first (widths beyond its depth unused); None when the space excludes it."""
    depth_ok = opts.min_hidden <= len(PAPER_HIDDEN) <= opts.max_hidden
    if not depth_ok or "relu" not in opts.activations or "raw" not in opts.features:
        return None
    widths = [*PAPER_HIDDEN] + [min(opts.widths)] * (opts.max_hidden - len(PAPER_HIDDEN))
    lr = min(max(recipe.lr, opts.lr[0]), opts.lr[1])
    batch = recipe.batch_size if recipe.batch_size in opts.batch_sizes else opts.batch_sizes[0]
    shared = {"adapter": opts.adapters[0]} if opts.family == "shared" else {}
    return {"n_hidden": 3, **{f"width{k}": w for k, w in enumerate(widths[: opts.max_hidden])},
            "activation": "relu", "features": "raw", **shared, "lr": lr, "batch_size": batch}


def is_paper(c: Candidate, opts: SearchOptions, shape: Shape = FINGERTIP) -> bool:
    """Whether `c` is the paper's MLP (its hidden widths on this sensor model) as the study
    enqueues it."""
    adapter = opts.adapters[0] if opts.family == "shared" else None
    return c == Candidate((shape.channels, *PAPER_HIDDEN, shape.outputs), "relu", "raw", adapter)


def make_objective(fit_and_score: Callable[[Candidate, TrainRecipe], list[dict[str, Any]]],
                   opts: SearchOptions, budget: Budget, recipe: TrainRecipe, shape: Shape = FINGERTIP
                   ) -> Callable[[optuna.Trial], tuple[float, ...]]:
    """objective(trial) -> each target's mean held-out RMSE over the units `fit_and_score` scored
    (the fingertip's force [N] and angle [rad]; one row per unit, with its `unit`, kept as the
    trial's `units`), then MACs."""

    def objective(trial: optuna.Trial) -> tuple[float, ...]:
        cand, lr, batch = suggest(trial, opts, shape)
        sizes = cand.sizes
        c = cost(sizes, budget, measure_if_possible=opts.measure, activation=cand.activation)
        with warnings.catch_warnings():  # a retried trial carries its constraints over already
            warnings.simplefilter("ignore", UserWarning)
            for name, value in zip(CONSTRAINT_NAMES, constraints(c, budget), strict=True):
                trial.set_constraint(name, value)
        for key, value in c.to_json().items():
            trial.set_user_attr(key, list(value) if isinstance(value, tuple) else value)
        if any(v > 0 for v in constraints(c, budget)):
            raise optuna.TrialPruned(f"{sizes} exceeds the {budget.name} budget")
        rows = fit_and_score(cand, recipe.model_copy(update={"lr": lr, "batch_size": batch}))
        trial.set_user_attr("units", [r["unit"] for r in rows])
        return (*mean_scores(rows, shape.keys), float(c.macs))

    return objective


def rdb_storage(url: str, opts: SearchOptions) -> optuna.storages.RDBStorage:
    """The study's storage: an SQLAlchemy database URL (sqlite:///file, postgresql://user@host/db,
    mysql://...), with heartbeats so that a killed worker's trials are failed and retried. A URL
    that names no database SQLAlchemy can open, or one that cannot be reached, stops the run
    with the URL (password hidden) and the reason."""
    import sqlalchemy.exc
    from sqlalchemy.engine import make_url

    try:
        parsed = make_url(url)
    except sqlalchemy.exc.ArgumentError:
        raise AnytipError(f"options.storage: {mask_secrets(url)!r} is not a database URL; use "
                          "sqlite:///FILE or "
                          "postgresql://USER@HOST/DB (journal files are not supported: resuming a "
                          "killed study needs heartbeats)") from None
    if parsed.drivername == "postgresql" and importlib.util.find_spec("psycopg") is None:
        # SQLAlchemy's default PostgreSQL driver is psycopg 3; the installed one is psycopg2
        url = parsed.set(drivername="postgresql+psycopg2").render_as_string(hide_password=False)
    shown = parsed.render_as_string(hide_password=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", optuna.exceptions.ExperimentalWarning)
        # SQLite serialises writers: let concurrent workers wait for the lock instead of failing
        engine = {"connect_args": {"timeout": 60}} if url.startswith("sqlite") else None
        try:
            return optuna.storages.RDBStorage(
                url, engine_kwargs=engine, heartbeat_interval=opts.heartbeat_s,
                grace_period=2 * opts.heartbeat_s,
                heartbeat_stale_trial_callback=optuna.storages.RetryHeartbeatStaleTrialCallback(max_retry=1))
        except (sqlalchemy.exc.NoSuchModuleError, ImportError) as e:
            reason = mask_secrets(str(e))
            raise AnytipError(f"options.storage {shown}: no database driver for it ({reason}); use "
                              "sqlite:///FILE or postgresql://USER@HOST/DB") from None
        except sqlalchemy.exc.OperationalError as e:
            reason = mask_secrets(" ".join(str(e.orig).split()))
            raise AnytipError(f"options.storage {shown}: cannot open the database ({reason})") from None


def open_study(url: str, name: str, opts: SearchOptions, worker: int = 0,
               n_objectives: int = 3) -> optuna.Study:
    """Create or load the study; stale running trials (no heartbeat) are failed and retried.
    Each worker samples from its own seed, so parallel workers do not propose the same trial."""
    storage = rdb_storage(url, opts)
    sampler = optuna.samplers.TPESampler(seed=stream_seed(SEARCH_WORKER, opts.seed, worker),
                                         n_startup_trials=min(8, opts.n_trials))
    return optuna.create_study(study_name=name, storage=storage, load_if_exists=True, sampler=sampler,
                               directions=["minimize"] * n_objectives)


def remaining(study: optuna.Study, n_trials: int) -> int:
    """Trials still to run for the study to hold n_trials finished (complete or pruned) ones."""
    done = [t for t in study.trials
            if t.state in (optuna.trial.TrialState.COMPLETE, optuna.trial.TrialState.PRUNED)]
    return max(0, n_trials - len(done))


def pareto_numbers(study: optuna.Study) -> set[int]:
    """Trial numbers on the feasible Pareto front."""
    return {t.number for t in study.best_trials}


def front_table(study: optuna.Study, keys: tuple[str, ...] = FINGERTIP.keys) -> list[dict[str, Any]]:
    """Complete trials as plain dicts (each target's RMSE under its key), sorted by MACs."""
    front = pareto_numbers(study)
    out = []
    for t in study.trials:
        if t.state != optuna.trial.TrialState.COMPLETE:
            continue
        out.append({"number": t.number, "sizes": tuple(t.user_attrs["sizes"]),
                    **dict(zip(keys, t.values[:-1], strict=True)), "macs": int(t.values[-1]),
                    "params": t.user_attrs["params"], "flash_bytes": t.user_attrs["flash_bytes"],
                    "ram_bytes": t.user_attrs["ram_bytes"], "cycles": t.user_attrs["cycles"],
                    "measured": bool(t.user_attrs["measured_sizes"]),
                    "measured_instructions": bool(t.user_attrs.get("measured_instructions")),
                    "pareto": t.number in front, "lr": t.params["lr"], "batch_size": t.params["batch_size"],
                    "activation": t.params.get("activation", "relu"),
                    "features": t.params.get("features", "raw"), "adapter": t.params.get("adapter")})
    return sorted(out, key=lambda r: (r["macs"], r[keys[0]]))


def mean_scores(scores: list[dict[str, Any]], keys: tuple[str, ...] = FINGERTIP.keys) -> tuple[float, ...]:
    """Each key's mean over the units' score rows."""
    return tuple(float(np.mean([s[k] for s in scores])) for k in keys)


def candidate_of(row: dict[str, Any]) -> Candidate:
    """The candidate of a `front_table` row."""
    return Candidate(tuple(row["sizes"]), row["activation"], row["features"], row["adapter"])
