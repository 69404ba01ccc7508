"""`anytip calibrate`: a new unit's per-unit model from a shared model and minutes of data.

Takes the unit's calibration stream from the registry (its runs of the shared model's
calibration protocol, in recorded order), sets its input statistics from the stream's
pressures (no labels), fits its adapter on a budget of labeled rows, folds it into a plain
MLP of the deployed shape and saves it in the per-unit model format (models/io.py), which
is what export reads. The budget is chosen as the shared model's benchmark chose it: whole
presses up to a number of robot seconds (data/plans.py, for models benchmarked in seconds),
or the first N rows of the stream. Rows of the unit's other runs, which calibration never
touched, score the result when there are any.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, get_args

import numpy as np
import torch
from torch import Tensor

from anytip.data.arrays import FleetArrays, load_arrays
from anytip.data.calibration import CalibrationStream, calibration_stream
from anytip.data.plans import (
    INFORMED,
    Plan,
    RigTiming,
    Strategy,
    find_presses,
    select_presses,
    stream_ordinary_use,
    stream_plan,
)
from anytip.data.registry import Registry
from anytip.errors import AnytipError
from anytip.models.io import (
    RESPONSE_FORMAT,
    SHARED_FORMAT,
    LoadedModels,
    LoadedResponse,
    LoadedShared,
    ModelFileError,
    load_models,
    load_response,
    load_shared,
    load_source_response,
    model_paths,
    read_header,
    save_models,
    save_source_response,
)
from anytip.models.mlp import BatchedMLP, MLPConfig
from anytip.models.scaler import Scaler
from anytip.rundir import write_json
from anytip.train.adapt import AdapterRecipe, calibrate_and_fold
from anytip.train.adapter_prior import make_prior
from anytip.train.data import FleetBatchData, UnitTensors
from anytip.train.fleet import start_mismatch
from anytip.train.label_free import (
    FleetUse,
    Labeled,
    LabelFreeRecipe,
    distilled_rows,
    encoder_codes,
    fleet_force_scale,
    search_candidates,
    unit_codes_with_use,
    use_inputs,
    with_use_method,
)
from anytip.train.metrics import predict, scores, target_key
from anytip.train.response import (
    ResponseFit,
    ResponseRecipe,
    SourceRows,
    calibrate_by_response,
    draw_source_rows,
    own_response,
    plan_residual,
    press_information,
    source_digest,
    source_response_path,
    start_network_path,
)
from anytip.train.shared_split import (
    OWN_CHECK_FOLDS,
    main_rows,
    own_check_loss,
    plan_residuals,
    unit_main_rows,
)
from anytip.uncertainty.conformal import coverage, interval, residual_halfwidth
from anytip.uncertainty.fleet_margin import Learner, MarginChoice, pooled_factor
from anytip.validation import read_yaml

METHODS = ("auto", "adapter", "response")
MAX_USE_S = 600.0  # seconds of ordinary use after mounting a calibration may read (the allowance)
# what `--plan-strategy` may ask for: every selection from a unit's presses (a designed plan is its own run)
ASKABLE: tuple[str, ...] = tuple(s for s in get_args(Strategy) if s != "designed")

# A new unit whose own check exceeds the worst validation unit's by more than this is flagged.
# Every cross_sensor report shows how often it fires on held-out units, which are ordinary units
# (section "The calibration's own check on ordinary units").
OWN_CHECK_ALARM = 2.0


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
    notes: list[str]  # which shared model and why, clipped budgets, warnings
    own_check: dict[str, float] | None = None  # the plan's held-out presses against the fleet's
    wall_s: float = 0.0  # fitting and folding the adapter on the whole plan
    intervals: dict[str, Any] | None = None  # from the plan's residuals (`plan_intervals`)
    check_s: float = 0.0  # the fold fits behind the own check and the intervals
    response_check: dict[str, Any] | None = None  # response transfer: the plan about its fitted response
    unlabeled_seconds: float = 0.0  # contact seconds of ordinary use read (response transfer)


@dataclass(frozen=True)
class UseRequest:
    """A calibration's ordinary use (`--ordinary-use`): contact seconds of whole presses of the unit's
    stream read without their labels, and how the stream is read (the shared model's protocol,
    interleaving and rig's effective_hz, the defaults of a response model that records none)."""

    seconds: float
    protocol: str | None
    interleave: bool
    effective_hz: float


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
    config = _run_config(model)
    seeds = config.get("seeds") or [config.get("seed", 0)]
    seed = seeds[0] if seed is None else seed
    have = {p.stem: p for p in sorted((model / "models").glob(f"shared_*_seed{seed}.safetensors"))}
    if adapter is not None:
        path = model / "models" / f"shared_{adapter.replace('+', '-')}_seed{seed}.safetensors"
        if not path.is_file():
            raise AnytipError(f"{path}: no shared model for adapter {adapter!r}, seed {seed}; "
                              f"the run holds: {', '.join(have) or 'none'}")
        return path, f"adapter {adapter!r} as asked"
    losses = {stem: _val_loss(path, budget) for stem, path in have.items()}
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


def _run_config(run_dir: Path) -> dict[str, Any]:
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


def _val_loss(path: Path, budget: float | None) -> float | None:
    """A shared model file's recorded validation-unit loss (`_val_loss_table`)."""
    meta = read_header(model_paths(path)[1], SHARED_FORMAT).get("meta", {})
    return _val_loss_table(meta if isinstance(meta, dict) else {}, budget)


def _val_loss_table(meta: dict[str, Any], budget: float | None) -> float | None:
    """The validation-unit loss a shared model's metadata records (`val_loss_by_budget`) at the
    largest budget <= `budget`, or its mean over budgets for None; None if it has none."""
    table = {b: float(v) for b, v in _budget_table(meta, "val_loss_by_budget").items()
             if isinstance(v, (int, float)) and math.isfinite(v)}
    if budget is None:
        return float(np.mean(list(table.values()))) if table else None
    return _at_budget(table, budget)


def _own_check_table(meta: dict[str, Any], budget: float) -> list[float] | None:
    """The validation units' own-check losses the metadata records (`own_check_by_budget`) at
    the largest budget <= `budget`; None if it records none."""
    def finite(v: Any) -> bool:
        return isinstance(v, (int, float)) and math.isfinite(v)
    table = {b: [float(x) for x in v] for b, v in _budget_table(meta, "own_check_by_budget").items()
             if isinstance(v, list) and v and all(finite(x) for x in v)}
    return _at_budget(table, budget)


def _budget_table(meta: dict[str, Any], key: str) -> dict[float, Any]:
    values = meta.get(key)
    return {float(b): v for b, v in values.items() if _is_amount(b)} if isinstance(values, dict) else {}


def _at_budget(table: dict[float, Any], budget: float) -> Any:
    below = [b for b in table if b <= budget]
    return table[max(below)] if below else None


def budget_rows(stream: CalibrationStream, samples: int | None, seconds: float | None) -> tuple[int, str]:
    """Labeled rows a budget grants, and a note when the budget was clipped to the stream: a
    sample count, or all rows within `seconds` of robot time (at most one is given)."""
    if seconds is not None:
        if not math.isfinite(seconds) or seconds < 0:
            raise AnytipError(f"--budget-seconds must be a finite number >= 0, got {seconds}")
        n = int(np.searchsorted(stream.seconds, seconds, side="right"))
        total = float(stream.seconds[-1]) if len(stream.seconds) else 0.0
        clipped = seconds > total
        note = f"--budget-seconds {seconds:g} clipped to the stream's {total:.1f} robot-s" if clipped else ""
        return n, note
    n = 1000 if samples is None else samples
    if n < 0:
        raise AnytipError(f"--budget-samples must be >= 0, got {n}")
    if n > len(stream.rows):
        return len(stream.rows), (f"--budget-samples {n} clipped to the {len(stream.rows)} labeled rows "
                                  "of the unit's calibration stream")
    return n, ""


def _is_amount(text: Any) -> bool:
    try:
        return math.isfinite(float(text)) and float(text) >= 0
    except (TypeError, ValueError):
        return False


def prior_for(meta: dict[str, Any], n: float) -> float:
    """The validation-chosen prior of the largest benchmarked budget <= n (labeled samples, or
    robot seconds for a model benchmarked in seconds), else the default."""
    table = {float(b): float(p) for b, p in meta.get("priors_by_budget", {}).items() if _is_amount(b)}
    below = [b for b in table if b <= n]
    return table[max(below)] if below else float(meta.get("default_prior", 10.0))


DEFAULT_SECONDS = 120.0  # a budget in seconds when none is given: the 2-minute calibration


def benchmarked_in(model: str | Path) -> str:
    """'seconds' or 'samples': how the benchmark behind `model` (a run directory or a shared
    model file) budgeted calibrations."""
    model = Path(model)
    if model.suffix in (".safetensors", ".json"):
        meta = read_header(model_paths(model.with_suffix(".safetensors"))[1], SHARED_FORMAT).get("meta", {})
        unit = meta.get("budget_unit", "samples") if isinstance(meta, dict) else "samples"
    else:
        unit = _run_config(model).get("options", {}).get("budget_unit", "samples")
    if unit not in ("samples", "seconds"):
        raise AnytipError(f"{model}: budget_unit {unit!r} is neither 'samples' nor 'seconds'")
    return unit


def _rig_of(meta: dict[str, Any]) -> RigTiming:
    """The rig timing a shared model's benchmark priced its plans with (`rig` in its metadata)."""
    return RigTiming(**{k: float(v) for k, v in meta.get("rig", {}).items()})


def choose_plan(meta: dict[str, Any], arrays: FleetArrays, stream: CalibrationStream,
                budget_samples: int | None, budget_seconds: float | None) -> tuple[Plan, float, str]:
    """The labeled rows of a new unit's calibration, the budget they were chosen for (the key
    of the prior) and a note when a budget was clipped to what the unit recorded."""
    if meta.get("budget_unit", "samples") == "seconds":
        if budget_samples is not None:
            raise AnytipError("the shared model was benchmarked with budgets in robot seconds; "
                              "give --budget-seconds, not --budget-samples")
        seconds = DEFAULT_SECONDS if budget_seconds is None else budget_seconds
        if not math.isfinite(seconds) or seconds < 0:
            raise AnytipError(f"--budget-seconds must be a finite number >= 0, got {seconds}")
        presses = find_presses(arrays, stream.unit, stream.outside(arrays))
        rig = _rig_of(meta)
        plan = select_presses(presses, seconds, rig, meta.get("plan_strategy", "spread"),
                              int(meta.get("seed", 0)))
        total = float(presses.duration_s.sum() + rig.move_s * len(presses))
        note = (f"--budget-seconds {seconds:g}: the unit's runs hold {len(presses)} presses, all of them "
                f"used ({plan.calib_seconds:.1f} robot-s)") if plan.presses == len(presses) and \
            seconds > total else ""
        return plan, seconds, note
    n, note = budget_rows(stream, budget_samples, budget_seconds)
    return stream_plan(stream, n), float(n), note


@dataclass(frozen=True)
class PlanRequest:
    """A plan response transfer makes once its model is loaded: `seconds` of robot time of
    `strategy` over the unit's presses, priced by the shared model's rig (`meta`); strategies that
    choose presses for what they tell the codes (`INFORMED`) read the response model."""

    meta: dict[str, Any]
    arrays: FleetArrays
    stream: CalibrationStream
    seconds: float
    strategy: str

    def plan(self, fit: ResponseFit, criterion: str) -> Plan:
        presses = find_presses(self.arrays, self.stream.unit, self.stream.outside(self.arrays))
        rig = _rig_of(self.meta)
        information = (press_information(fit, self.arrays, presses, rig.effective_hz, criterion)
                       if self.strategy in INFORMED else None)
        return select_presses(presses, self.seconds, rig, self.strategy,  # type: ignore[arg-type]
                              int(self.meta.get("seed", 0)), information)


Fit = Callable[[np.ndarray, float], tuple[BatchedMLP, Scaler]]


@dataclass
class Fitter:
    """How a new unit's adapter is fitted, as the shared model's benchmark fitted adapters.

    fit(rows, n_effective) -> (folded MLP, input scaler): fitted on `rows`; residuals(plan,
    folds): the plan's out-of-fold residuals (n, D) over that many press folds (one per press
    for a shorter plan; `train.shared_split.plan_residuals`), which give the calibration's own
    check over OWN_CHECK_FOLDS folds, as the benchmark measured it on its validation units, and
    the unit's intervals over the folds its benchmark used for them."""

    fit: Fit
    residuals: Callable[[Plan, int], np.ndarray | None]


def _fitter(shared: LoadedShared, meta: dict[str, Any], arrays: FleetArrays, unlabeled_rows: np.ndarray,
            prior: float) -> Fitter:
    """The unit's `Fitter`: the benchmark's recipe, prior family and strength."""
    recipe = AdapterRecipe(**meta.get("adapter_recipe", {}))
    seed = int(meta.get("seed", 0))
    family = None
    if shared.model.adapter_parameters():
        family = make_prior(meta.get("adapter_prior", "identity"), shared.model,
                            int(meta.get("prior_rank", 4)))
    unlabeled = [torch.from_numpy(arrays.pressure[unlabeled_rows])]

    def fit(rows: np.ndarray, n_effective: float) -> tuple[BatchedMLP, Scaler]:
        X, Y = [torch.from_numpy(arrays.pressure[rows])], [torch.from_numpy(arrays.targets[rows])]
        return calibrate_and_fold(shared, unlabeled, X, Y, [len(rows)], [prior], recipe,
                                  seed=seed, n_effective=[n_effective], adapter_prior=family)

    def residuals(plan: Plan, folds: int) -> np.ndarray | None:
        return plan_residuals(shared, arrays, [unlabeled_rows], [plan], [prior], recipe, seed,
                              adapter_prior=family, folds=folds, fewer=True)[0]
    return Fitter(fit, residuals)


INTERVAL_FOLDS = OWN_CHECK_FOLDS  # press folds of a new unit's intervals where its benchmark records none


def interval_folds(meta: dict[str, Any]) -> int:
    """Press folds of a new unit's interval residuals: those the shared model's benchmark used
    for its intervals (`intervals.folds`), else INTERVAL_FOLDS."""
    rec = meta.get("intervals")
    folds = rec.get("folds") if isinstance(rec, dict) else None
    usable = isinstance(folds, int) and not isinstance(folds, bool) and 2 <= folds <= 100
    return folds if usable else INTERVAL_FOLDS


def plan_intervals(residuals: np.ndarray | None, level: float, names: tuple[str, ...],
                   other: tuple[np.ndarray, np.ndarray] | None,
                   factor: dict[str, float] | None = None,
                   folds: int | None = INTERVAL_FOLDS) -> dict[str, Any] | None:
    """A new unit's intervals: the half-width per output (names; the output's unit) at nominal
    `level` from its plan's residuals (n, D), times the benchmark's fleet factor per output
    where given (`fleet_factor`; `own_halfwidth` keeps the plan's own), and, given the unit's
    other runs as (prediction, target) (m, D), the share of their rows inside. None without
    residuals. `folds`: the press folds behind out-of-fold residuals, as recorded; None for
    residuals on the plan's own rows (response transfer)."""
    if residuals is None:
        return None
    own = residual_halfwidth(residuals, level)
    half = own if factor is None else own * np.array([factor[n] for n in names])
    out: dict[str, Any] = {"level": level, "folds": folds, "rows": int(len(residuals)),
                           "halfwidth": dict(zip(names, map(float, half), strict=True))}
    if factor is not None:
        out |= {"own_halfwidth": dict(zip(names, map(float, own), strict=True)), "fleet_factor": dict(factor)}
    if other is not None:
        lo, hi = interval(other[0], half)
        out["coverage_on_other_runs"] = dict(zip(names, map(float, coverage(lo, hi, other[1])), strict=True))
    return out


def fleet_factor_for(meta: dict[str, Any], budget: float, level: float,
                     names: tuple[str, ...]) -> tuple[dict[str, float] | None, str]:
    """The intervals' fleet factor per output a shared model's benchmark learnt on its validation
    units (`intervals.fleet_factor_by_budget`) at the largest budget <= `budget`, and a note when
    there is none to apply: the benchmark recorded none, at another level, or not for every
    output as a finite positive number."""
    rec = meta.get("intervals")
    if not isinstance(rec, dict) or not isinstance(rec.get("fleet_factor_by_budget"), dict):
        return None, ""
    return _usable_factor(rec, _budget_table(rec, "fleet_factor_by_budget"), budget, level, names)


def _usable_factor(rec: dict[str, Any], table: dict[float, Any], budget: float, level: float,
                   names: tuple[str, ...]) -> tuple[dict[str, float] | None, str]:
    """The factor of a benchmark's intervals record `rec` from its per-budget `table` at the
    largest budget <= `budget`, or None and why: another level, or not a finite positive number
    for every output."""
    if rec.get("level") != level:
        return None, (f"the benchmark's fleet factor for intervals was learnt at level "
                      f"{rec.get('level')}, not {level:g}: intervals from the plan alone")
    factor = _at_budget(table, budget)
    ok = isinstance(factor, dict) and all(isinstance(factor.get(n), (int, float)) and
                                          math.isfinite(factor[n]) and factor[n] > 0 for n in names)
    if not ok:
        return None, (f"the benchmark records no usable fleet factor for intervals at {budget:g} robot-s "
                      "or less: intervals from the plan alone")
    return {n: float(factor[n]) for n in names}, ""


def own_check(loss: float | None, plan: Plan, fleet_loss: float | None,
              validation: list[float] | None) -> dict[str, Any] | None:
    """The calibration's own check (the plan's presses in OWN_CHECK_FOLDS folds, each predicted
    by the adapter refitted without it, standardised MSE over all of them) beside what the
    shared model's benchmark measured:
    the same statistic on its validation units at this budget (`validation`; `over_validation`
    is the ratio to the worst of them, and `alarm` is set above OWN_CHECK_ALARM), and the
    validation units' loss on their test patches (`over_fleet`: other rows, a guide only).
    None for a plan of fewer than 2 presses."""
    if loss is None:
        return None
    out: dict[str, Any] = {"presses": plan.presses, "folds": min(OWN_CHECK_FOLDS, plan.presses),
                           "rows": int(len(plan.rows)), "standardised_mse": loss}
    if fleet_loss is not None:
        out |= {"fleet_validation_mse": fleet_loss, "over_fleet": loss / fleet_loss}
    if validation:
        over = loss / max(validation)
        out |= {"validation_units_mse": validation, "over_validation": over, "alarm": over > OWN_CHECK_ALARM}
    return out


def calibrate_unit(model: str | Path, unit: str, registry: Registry, out: str | Path,
                   budget_samples: int | None = None, budget_seconds: float | None = None,
                   adapter: str | None = None, seed: int | None = None,
                   interval_level: float | None = 0.9, method: str = "auto",
                   use_seconds: float = 0.0, factor_from: Sequence[str | Path] = (),
                   plan_strategy: str | None = None) -> Calibrated:
    """Fit, fold and save one unit's model; see the module docstring. `interval_level`: the
    nominal coverage of the intervals from the plan (None: none). `method`: `adapter` (the shared
    model's adapter, folded), `response` (response transfer; a run with a response model) or
    `auto` (response where the run's validation units scored it below the chosen shared model at
    this budget). `use_seconds`: contact seconds of the unit's ordinary use read without labels
    (response transfer alone reads them: with the plan, or alone at budget 0). `factor_from`: more
    runs of the same benchmark (a registry's other unit folds) whose response models' learning units
    learn the intervals' fleet factor and margin with the run's own (`pooled_learners`).
    `plan_strategy`: the press selection response transfer calibrates by, as asked (a choice made on
    more validation units than the run's; research log entry 100), instead of `response_strategy`'s."""
    if method not in METHODS:
        raise AnytipError(f"--method must be one of {', '.join(METHODS)}, got {method!r}")
    if not 0 <= use_seconds <= MAX_USE_S:
        raise AnytipError(f"--ordinary-use must lie in [0, {MAX_USE_S:g}] seconds, got {use_seconds}")
    if interval_level is not None and not 0 < interval_level < 1:
        raise AnytipError(f"--interval-level must lie strictly between 0 and 1, got {interval_level}")
    if budget_samples is not None and budget_seconds is not None:
        raise AnytipError("give --budget-samples or --budget-seconds, not both")
    if benchmarked_in(model) == "seconds":
        wanted = DEFAULT_SECONDS if budget_seconds is None else budget_seconds
    else:
        wanted = (1000 if budget_samples is None else budget_samples) if budget_seconds is None else None
    shared_path, choice = find_shared(model, adapter, seed, wanted)
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
    plan, budget, clipped = choose_plan(meta, arrays, stream, budget_samples, budget_seconds)
    n = len(plan.rows)
    notes = [f"shared model {shared_path.name}: {choice}"] + ([clipped] if clipped else [])
    if unit in meta.get("unit_ids", []):
        notes.append(f"warning: unit {unit} was a training unit of the shared model; its "
                     "calibration check is not an unseen-unit result")
    response, why = choose_response(model, seed, meta, budget, method, adapter, use_seconds)
    notes += [why] if why else []
    if response is not None:
        use = None
        if use_seconds > 0:
            rig = _rig_of(meta)
            use = UseRequest(use_seconds, meta.get("calibration_protocol"),
                             bool(meta.get("calibration_interleave", False)), rig.effective_hz)
        pooled = interval_records(factor_from, response)
        strategy, planned = _response_plan(response, meta, (arrays, stream), plan, budget, use is not None,
                                           notes, plan_strategy)
        return calibrate_by_response_unit(response, registry, arrays, stream, planned, budget, Path(out),
                                          notes, interval_level, strategy, use, pooled,
                                          meta.get("calibration_protocol"))
    if factor_from:
        raise AnytipError("--factor-from is read by response transfer alone: the adapter's intervals have "
                          "their own fleet factor")
    if plan_strategy is not None:
        raise AnytipError("--plan-strategy is read by response transfer alone: the adapter calibrates on the "
                          "plans its benchmark chose")
    prior = prior_for(meta, budget)
    unlabeled_rows = stream.unlabeled(meta.get("unlabeled_s"))
    tick = time.perf_counter()
    fitter = _fitter(shared, meta, arrays, unlabeled_rows, prior)
    folded, stats = fitter.fit(plan.rows, plan.n_effective)
    wall_s = time.perf_counter() - tick
    tick = time.perf_counter()
    resid = fitter.residuals(plan, OWN_CHECK_FOLDS) if n else None
    own = own_check(own_check_loss(resid, shared.out_scaler), plan, _val_loss_table(meta, budget),
                    _own_check_table(meta, budget))
    check_s = time.perf_counter() - tick
    if own is not None and "validation_units_mse" in own and "own_check_folds" not in meta:
        notes.append("the shared model's validation units were checked on one held-out fold of every 5th "
                     "press (a benchmark from before the press-fold check): the same expected value, "
                     "noisier, so the comparison below is rougher")
    if own is not None and own.get("alarm"):
        notes.append(f"warning: the calibration's own check is {own['over_validation']:.1f}x the worst of "
                     "the shared model's validation units checked the same way (alarm above "
                     f"{OWN_CHECK_ALARM:g}x): check the unit's barometers, mounting and labels before "
                     "deploying it")
    out_scaler = Scaler(shared.out_scaler.mean.clone(), shared.out_scaler.std.clone())
    check, on_other = _check_on_other_runs((folded, stats, out_scaler), arrays, stream)
    bands = None
    folds = interval_folds(meta)
    if interval_level is not None and plan.presses >= folds:
        factor, why = fleet_factor_for(meta, budget, interval_level, arrays.output_names)
        notes += [why] if why else []
        tick = time.perf_counter()
        band_resid = resid if folds == OWN_CHECK_FOLDS else fitter.residuals(plan, folds)
        check_s += time.perf_counter() - tick
        bands = plan_intervals(band_resid, interval_level, arrays.output_names, on_other, factor, folds)
    result = Calibrated(Path(out), unit, n, plan.calib_seconds, len(unlabeled_rows), prior, check, notes,
                        own, wall_s, bands, check_s)
    save_models(Path(out) / "model.safetensors", folded, stats, out_scaler, {
        "unit_ids": [unit], "output_names": meta.get("output_names"), "shared_model": str(shared_path),
        "adapter": shared.model.kind, "calib_samples": n, "calib_seconds": result.calib_seconds,
        "calib_presses": plan.presses, "n_effective": plan.n_effective,
        "unlabeled_samples": result.unlabeled_samples, "prior": prior,
        "calibration_runs": list(stream.runs), "check_on_other_runs": check, "own_check": own,
        "intervals": bands,
    })
    return _write_calibration(result)


def _write_calibration(result: Calibrated) -> Calibrated:
    """`calibration.json` in the result's directory: every field of `result`, paths as text."""
    write_json(Path(result.path) / "calibration.json",
               {k: (str(v) if isinstance(v, Path) else v) for k, v in result.__dict__.items()})
    return result


def _strategy_table(meta: dict[str, Any], key: str, strategy: str) -> dict[float, Any]:
    """A response model's per-budget record for plans of `strategy` (`<key>_by_strategy`); a model
    saved before that key holds `val_loss_by_budget` keyed by budget labels ("120 s cover")."""
    table = meta.get(f"{key}_by_strategy")
    if isinstance(table, dict) and isinstance(table.get(strategy), dict):
        return {float(b): v for b, v in table[strategy].items() if _is_amount(b)}
    old = meta.get(f"{key}_by_budget") if key == "val_loss" else None
    out: dict[float, Any] = {}
    for label, v in (old.items() if isinstance(old, dict) else []):
        parts = str(label).split()
        if len(parts) == 3 and parts[1] == "s" and parts[2] == strategy and _is_amount(parts[0]):
            out[float(parts[0])] = v
    return out


def choose_response(model: str | Path, seed: int | None, meta: dict[str, Any], budget: float, method: str,
                    adapter: str | None, use_seconds: float = 0.0) -> tuple[Path | None, str]:
    """The response model file to calibrate by (None: the shared model's adapter) and a note why.
    With ordinary use (`use_seconds` > 0) it is response transfer or an error: nothing else reads it."""
    model = Path(model)
    if use_seconds > 0:
        return _response_for_use(model, seed, meta, budget, method, adapter, use_seconds)
    if method == "adapter" or model.suffix in (".safetensors", ".json"):
        if method == "response":
            raise AnytipError(f"--method response needs a cross_sensor run directory with a response model, "
                              f"not the model file {model}")
        return None, ""
    path = model / "models" / f"response_seed{int(meta.get('seed', 0) if seed is None else seed)}.safetensors"
    if not path.is_file():
        if method == "response":
            raise AnytipError(f"{path}: the run holds no response model (its spec had no options.response)")
        return None, ""
    if budget <= 0:
        if method == "response":
            raise AnytipError("--method response needs labeled presses: it fits the unit's response on its "
                              "plan, and this budget is label-free (0); give a budget, or use --method auto "
                              "or adapter for the label-free calibration")
        return None, "label-free budget: the shared model's adapter (response transfer needs labels)"
    if method == "response":
        return path, "calibration by response transfer, as asked"
    if adapter is not None:
        return None, ""
    recorded = response_record(path)
    strategy = response_strategy(recorded, str(meta.get("plan_strategy", "spread")), budget, path=path)
    table = _strategy_table(recorded, "val_loss", strategy)
    theirs = _at_budget({b: float(v) for b, v in table.items() if isinstance(v, (int, float))}, budget)
    ours = _val_loss_table(meta, budget)
    if theirs is None or ours is None or theirs >= ours:
        return None, ""
    return path, (f"calibration by response transfer: its validation-unit loss {theirs:.3g} is below the "
                  f"shared model's {ours:.3g} at this budget")


def _response_plan(path: Path, meta: dict[str, Any], unit: tuple[FleetArrays, CalibrationStream], plan: Plan,
                   budget: float, with_use: bool, notes: list[str], asked: str | None = None
                   ) -> tuple[str, Plan | PlanRequest]:
    """(strategy, plan) of a calibration by the response model `path`: the shared model's plan
    `plan`, or a `PlanRequest` where the response model scored another strategy best
    (`response_strategy`; budgets in robot seconds), or where another was `asked`."""
    shared = str(meta.get("plan_strategy", "spread"))
    if asked is not None and asked not in ASKABLE:
        raise AnytipError(f"--plan-strategy {asked!r}: expected one of {', '.join(ASKABLE)}")
    if meta.get("budget_unit") != "seconds" or not len(plan.rows):
        if asked is not None and asked != shared:
            raise AnytipError("--plan-strategy needs a run benchmarked in robot seconds and a labeled budget")
        return shared, plan
    recorded = response_record(path)
    decided = decided_strategy(recorded, path)
    strategy = asked or response_strategy(recorded, shared, budget, with_use, path)
    why = ("as asked (--plan-strategy)" if asked else
           "decided beforehand by the run's spec (options.response.plan_strategy)" if decided
           else "the response model's best on its validation units at this budget")
    if strategy == shared:
        notes += [f"plan: {strategy}, {why}"] if asked or decided else []
        return shared, plan
    notes.append(f"plan: {strategy}, {why}")
    return strategy, PlanRequest(meta, *unit, budget, strategy)


def response_record(path: Path) -> dict[str, Any]:
    """The metadata a response model file's header records (empty where it records none)."""
    recorded = read_header(model_paths(path)[1], RESPONSE_FORMAT).get("meta", {})
    return recorded if isinstance(recorded, dict) else {}


def decided_strategy(recorded: dict[str, Any], path: Path | None = None) -> str | None:
    """The press selection a response model's run decided beforehand (`decided_plan_strategy`, from its
    spec's `options.response.plan_strategy`), or None where its validation units choose. A value that
    is no selection calibrate can make is refused naming the file (`path`) and key."""
    got = recorded.get("decided_plan_strategy")
    if got is None:
        return None
    if got not in ASKABLE:
        where = f"{model_paths(path)[1]}: " if path is not None else ""
        raise AnytipError(f"{where}meta.decided_plan_strategy: {got!r} is not one of {', '.join(ASKABLE)}")
    return str(got)


def response_strategy(recorded: dict[str, Any], shared: str, budget: float, with_use: bool = False,
                      path: Path | None = None) -> str:
    """The press selection response transfer calibrates by: the one the run's spec decided beforehand
    (`decided_strategy`) where it decided one; else the shared model's (`shared`, what its adapters
    chose on their validation units), unless a selection made with the response model (`INFORMED`,
    which adapters never use) has a lower validation-unit loss at `budget` in the response model's
    record (`val_loss_by_strategy`; with ordinary use, `use_val_loss_by_strategy` where it holds one);
    then the lowest of those. `path`: the response model's file, named where its decision is refused."""
    decided = decided_strategy(recorded, path)
    if decided is not None:
        return decided
    for key in (["use_val_loss"] if with_use else []) + ["val_loss"]:
        losses = {}
        for strategy in [shared, *INFORMED]:
            v = _at_budget(_strategy_table(recorded, key, strategy), budget)
            if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v):
                losses[strategy] = float(v)
        if any(s in INFORMED for s in losses):
            best = min(losses, key=losses.__getitem__)
            return shared if losses.get(shared, math.inf) <= losses[best] else best
    return shared


def _response_for_use(model: Path, seed: int | None, meta: dict[str, Any], budget: float, method: str,
                      adapter: str | None, use_seconds: float) -> tuple[Path, str]:
    """`choose_response` where the calibration reads `use_seconds` of ordinary use."""
    if method == "adapter" or adapter is not None or model.suffix in (".safetensors", ".json"):
        raise AnytipError("--ordinary-use is read by response transfer alone: give a cross_sensor run "
                          "directory with a response model, without --adapter or --method adapter")
    path = model / "models" / f"response_seed{int(meta.get('seed', 0) if seed is None else seed)}.safetensors"
    if not path.is_file():
        raise AnytipError(f"{path}: the run holds no response model (its spec had no options.response), "
                          "and --ordinary-use needs one")
    what = "alone (no labels)" if budget <= 0 else "with the plan's labeled presses"
    return path, (f"calibration by response transfer: the codes from {use_seconds:g} s of the unit's "
                  f"ordinary use {what} (research log entries 44-46)")


def _response_intervals(meta: dict[str, Any], residuals: np.ndarray, budget: float, strategy: str,
                        level: float, names: tuple[str, ...], other: tuple[np.ndarray, np.ndarray] | None,
                        notes: list[str], with_use: bool = False,
                        pooled: tuple[list[tuple[Path, dict[str, Any]]], str] | None = None
                        ) -> dict[str, Any] | None:
    """A response-transferred unit's intervals: its network's residuals on the plan's rows (n, D),
    which also trained it, times the fleet factor the benchmark's validation units learnt for
    plans of `strategy` (`intervals.fleet_factor_by_strategy`; `use_fleet_factor_by_strategy` for
    codes fitted `with_use` of ordinary use); a note where there is none. `pooled`: (other models'
    intervals records, the unit calibrated): the factor and margin learnt by the learners of this
    model's record and theirs but that unit's own (`pooled_learners`, research log entry 53)."""
    rec = meta.get("intervals")
    factor, why = None, ("the response model's benchmark learnt no fleet factor for intervals: intervals "
                         "from the plan's rows alone, which also trained the network (too narrow)")
    if isinstance(rec, dict):
        table = _strategy_table(rec, "use_fleet_factor", strategy) if with_use else None
        if with_use and not table:
            notes.append("the response model's benchmark learnt no fleet factor for codes fitted with "
                         "ordinary use: the one learnt for codes from the plan alone is applied")
        prefix = "use_" if table else ""
        table = table or _strategy_table(rec, "fleet_factor", strategy)
        factor, why = _usable_factor(rec, table, budget, level, names)
        choice = _margin(rec, f"{prefix}margin", strategy, budget)
        if pooled is not None and factor is not None:
            learners = pooled_learners([(Path("."), rec), *pooled[0]], f"{prefix}units", strategy, budget,
                                       level, names, pooled[1])
            got, choice = pooled_factor(learners)
            factor = dict(zip(names, map(float, got), strict=True))
            notes.append(f"the fleet factor learnt by {len(learners)} learning units of this run and "
                         f"{len(pooled[0])} other response model(s) (--factor-from, research log entry 53)")
        if factor is not None and choice.margin != 1:
            factor = {n: f * choice.margin for n, f in factor.items()}
            notes.append(f"the fleet factor times {choice.margin:g}: the margin its learning units chose, "
                         "each left out in turn (research log entry 50)")
        short = choice.shortfall() if factor is not None else None
        if short:
            notes.append(f"the fleet factor without a margin: its learning units, each left out in turn, "
                         f"found none that keeps their outputs' coverage at the floor ({short}); a new "
                         "unit's coverage may fall below it too (research log entries 50, 104)")
    notes += [why] if why else []
    return plan_intervals(residuals, level, names, other, factor, folds=None)


def _margin(rec: dict[str, Any], key: str, strategy: str, budget: float) -> MarginChoice:
    """The margin on the fleet factor a benchmark recorded (`<key>_by_strategy`) at the largest
    budget <= `budget`, with its grid's counts below the floor and shares in the band where
    recorded; margin 1 where it recorded none or no finite positive one (a grid entry that is not a
    number is left out)."""
    got = _at_budget(_strategy_table(rec, key, strategy), budget)
    got = got if isinstance(got, dict) else {}
    margin = got.get("margin")
    ok = isinstance(margin, (int, float)) and math.isfinite(margin) and margin > 0
    below, in_band = (_grid(got.get(k)) for k in ("below_floor", "in_band"))
    return MarginChoice(float(margin) if ok else 1.0, {m: int(v) for m, v in below.items()}, in_band)


def _grid(table: object) -> dict[float, float]:
    """{margin: value} of a recorded grid ({"1.02": value, ...}), its finite numeric entries only."""
    out = {}
    for key, v in (table.items() if isinstance(table, dict) else ()):
        try:
            m = float(key)
        except ValueError:
            continue
        if isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(m) and math.isfinite(v):
            out[m] = float(v)
    return out


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


def interval_records(runs: Sequence[str | Path], own: Path) -> list[tuple[Path, dict[str, Any]]]:
    """(model file, intervals record) of every response model (`response_models`) in the run
    directories `runs` but `own`; AnytipError for a run that holds none, a model whose benchmark
    recorded no intervals, or runs that hold `own` alone (nothing to pool)."""
    out = []
    for run in map(Path, runs):
        found = response_models(run)
        if not found:
            raise AnytipError(f"--factor-from {run}: holds no response model (models/response_seed<n>)")
        for model in found.values():
            if model.resolve() == own.resolve():
                continue
            rec = read_header(model_paths(model)[1], RESPONSE_FORMAT).get("meta", {}).get("intervals")
            if not isinstance(rec, dict):
                raise AnytipError(f"--factor-from {model}: its benchmark recorded no intervals")
            out.append((model, rec))
    if runs and not out:
        raise AnytipError(f"--factor-from {' '.join(map(str, runs))}: holds no response model but the run's "
                          f"own ({own}), so there is nothing to pool; list the registry's other unit folds")
    return out


def pooled_learners(records: list[tuple[Path, dict[str, Any]]], key: str, strategy: str, budget: float,
                    level: float, names: tuple[str, ...], unit: str) -> list[Learner]:
    """The learning units the intervals `records` hold under `<key>_by_strategy` for `strategy` at
    their largest budget <= `budget`, but `unit` (its own test rows never set its width); AnytipError
    naming the file and key of a record at another level or a malformed learner, or for fewer than 2."""
    learners = []
    for path, rec in records:
        if rec.get("level") != level:
            raise AnytipError(f"{path}: intervals learnt at level {rec.get('level')!r}, not {level:g}")
        by_unit = _at_budget(_strategy_table(rec, key, strategy), budget)
        for u, learned in (by_unit.items() if isinstance(by_unit, dict) else []):
            try:
                learner = Learner.from_record(learned, names)
            except ValueError as e:
                raise AnytipError(f"{path}: key 'intervals.{key}_by_strategy.{strategy}' unit {u!r}: "
                                  f"{e}") from None
            if u != unit:
                learners.append(learner)
    if len(learners) < 2:
        raise AnytipError(f"--factor-from: {len(learners)} learning unit(s) at {budget:g} robot-s or less "
                          f"for {strategy} plans, where a pooled factor needs 2 or more")
    return learners


def _training_rows(registry: Registry, units: list[str], sensor_model: str, calibration_protocol: str | None
                   ) -> tuple[FleetArrays, FleetBatchData]:
    """The response model's training units' runs from the registry, and the rows the benchmark
    trained them on in its order (source rows): their main rows (`shared_split.main_rows`), so
    neither a designed calibration's runs, a test session's nor the calibration protocol's runs that
    a registry may hold beside them are carried over to the new unit."""
    runs = {u: registry.list_runs(unit=u, sensor_model=sensor_model) for u in units}
    missing = [u for u, records in runs.items() if not records]
    if missing:
        raise AnytipError(f"registry {registry.root} lacks the response model's training units "
                          f"{', '.join(missing[:4])}{' ...' if len(missing) > 4 else ''}: response transfer "
                          "carries their rows over to the new unit, so calibrate on the benchmark's registry")
    records = [r for u in units for r in runs[u]]
    arrays = load_arrays(registry, records)
    main = main_rows(arrays, calibration_protocol)
    members = []
    for u in units:
        rows = unit_main_rows(arrays, u, main)
        x, y = torch.from_numpy(arrays.pressure[rows]), torch.from_numpy(arrays.targets[rows])
        members.append(UnitTensors(x, y, x[:1], y[:1], u))
    return arrays, FleetBatchData.from_units(members, "cpu", arrays.output_names)


def _source_rows(path: Path, fit: ResponseFit, training: FleetBatchData, per_unit: int, seed: int,
                 notes: list[str]) -> SourceRows:
    """The training units' source rows with their own responses, read from the response model's
    cache (`source_response_path`) where it holds them for these rows and this model (the same
    digest), else computed and cached for the next calibration (a note where the cache cannot be
    read or written; the calibration goes on either way)."""
    source = draw_source_rows(fit, training, per_unit, seed)
    cache, digest = source_response_path(path), source_digest(fit, source)
    try:
        fitted = load_source_response(cache, digest, (len(source.X), fit.model.n_channels))
    except ModelFileError as e:
        notes.append(f"{e}; computed again")
        fitted = None
    if fitted is not None:
        source.fitted = fitted.to(fit.device)
        return source
    source.fitted = own_response(fit, source)
    try:
        save_source_response(cache, digest, source.fitted)
    except OSError as e:
        notes.append(f"the source rows' own responses could not be cached in {cache} ({e.strerror or e})")
    return source


def _registry_units(meta: dict[str, Any], sources: list[str]) -> list[str]:
    """The registry's own units a response model learnt (`registry_unit_ids`; a model saved before
    the record existed: the units whose rows it carries over)."""
    recorded = meta.get("registry_unit_ids", sources)
    if not isinstance(recorded, list) or not all(isinstance(u, str) for u in recorded):
        raise ValueError(f"registry_unit_ids: {recorded!r} is not a list of unit ids")
    return recorded


def calibrate_by_response_unit(path: Path, registry: Registry, arrays: FleetArrays,
                               stream: CalibrationStream, plan: Plan | PlanRequest, budget: float, out: Path,
                               notes: list[str], interval_level: float | None = 0.9,
                               strategy: str = "spread", use: UseRequest | None = None,
                               pooled: list[tuple[Path, dict[str, Any]]] | None = None,
                               calibration_protocol: str | None = None) -> Calibrated:
    """A new unit's own network by response transfer (train/response.py) on its plan, saved in the
    per-unit format; its own check is the RMS of the plan's pressures about its fitted response
    beside the benchmark's validation units' (alarm above OWN_CHECK_ALARM times the worst).
    `strategy`: how the plan was chosen (`response_strategy`), the key of what the response model
    recorded for such plans; `plan` is a `PlanRequest` where it is chosen with the response model,
    its choice counted in the calibration's time. `use`: the codes also (or, for an empty plan, only)
    from the unit's ordinary use (`unit_codes_with_use`). `pooled`: other response models'
    intervals records (`interval_records`), whose learners join the model's own (`pooled_learners`).
    `calibration_protocol`: the benchmark's (the shared model's), whose runs of the training units
    are no source rows (`_training_rows`)."""
    loaded = load_response(path)
    meta = loaded.meta
    # the units whose rows are carried over (every training unit of a model saved before the choice)
    units = [str(u) for u in meta.get("source_unit_ids", meta.get("unit_ids", []))]
    saved = meta.get("recipe", {})
    try:
        recipe = ResponseRecipe.from_saved(saved if isinstance(saved, dict) else {})
        fit = ResponseFit.from_loaded(loaded).with_code_prior(recipe.code_prior, _registry_units(meta, units))
    except (TypeError, ValueError) as e:
        raise AnytipError(f"{path}: {e}") from None
    seed = int(meta.get("seed", 0))
    tick = time.perf_counter()
    if isinstance(plan, PlanRequest):  # chosen with the response model: part of the calibration's time
        plan = plan.plan(fit, recipe.plan_criterion)
    plan_s = time.perf_counter() - tick
    training_arrays, training = _training_rows(registry, units, arrays.runs[0].sensor_model,
                                               calibration_protocol)
    X, Y = torch.from_numpy(arrays.pressure[plan.rows]), torch.from_numpy(arrays.targets[plan.rows])
    shape = MLPConfig(**meta["shape"]) if isinstance(meta.get("shape"), dict) else MLPConfig()
    # where the unit's network starts: one the benchmark trained once on the same source rows
    start = load_models(start_network_path(path)) if recipe.inverse_start == "pooled" else None
    if start is not None:
        problem = start_mismatch(start, shape)
        if problem is None and start.model.n_models != 1:
            problem = f"{start.model.n_models} networks, where one starts every unit"
        if problem:
            raise AnytipError(f"{start_network_path(path)}: {problem}")
    tick = time.perf_counter()
    source = _source_rows(path, fit, training, recipe.source_rows, seed, notes)
    given, used, distilled = None, Plan.empty(), None
    if use is not None:
        fleet = _fleet_use(path, meta, fit, use, (training_arrays, units), seed, notes)
        given, used, distilled = _codes_from_use(path, fit, recipe, fleet, (source, start), arrays, stream,
                                                 Labeled(X, Y, plan.n_effective), seed)
    nets, codes = calibrate_by_response(fit, source, [X], [Y], [plan.n_effective], shape, recipe, seed,
                                        [stream.unit], arrays.output_names, start=start, codes=given,
                                        extra=[distilled])
    wall_s = time.perf_counter() - tick + plan_s
    own = _response_own_check(loaded, fit, plan, (X, Y, codes[0]), _at_budget(
        _strategy_table(meta, "residual", strategy), budget), notes)
    check, on_other = _check_on_other_runs((nets.model, nets.in_scaler, nets.out_scaler), arrays, stream)
    bands = None
    if interval_level is not None and len(plan.rows):
        fitted = predict(nets.model, nets.in_scaler, nets.out_scaler, X[None])[0].numpy()
        residuals = fitted - arrays.targets[plan.rows]
        pool = (pooled, stream.unit) if pooled else None
        bands = _response_intervals(meta, residuals, budget, strategy, interval_level, arrays.output_names,
                                    on_other, notes, use is not None, pool)
    method = ("response" if use is None else with_use_method(fleet.free) if len(plan.rows)
              else "response:label_free")
    result = Calibrated(out, stream.unit, int(len(plan.rows)), plan.calib_seconds, len(used.rows), 0.0, check,
                        notes, None, wall_s, bands, 0.0, own, used.contact_seconds)
    save_models(out / "model.safetensors", nets.model, nets.in_scaler, nets.out_scaler, {
        "unit_ids": [stream.unit], "output_names": list(arrays.output_names), "response_model": str(path),
        "method": method, "codes": codes[0].tolist(),
        "calib_samples": result.calib_samples, "calib_seconds": plan.calib_seconds,
        "calib_presses": plan.presses, "n_effective": plan.n_effective, "unlabeled_samples": len(used.rows),
        "unlabeled_seconds": used.contact_seconds, "calibration_runs": list(stream.runs),
        "check_on_other_runs": check, "response_check": own, "intervals": bands})
    return _write_calibration(result)


def _response_own_check(loaded: LoadedResponse, fit: ResponseFit, plan: Plan,
                        rows: tuple[Tensor, Tensor, Tensor], validation: Any, notes: list[str]
                        ) -> dict[str, Any]:
    """A response-transferred unit's own check: the RMS of its plan's pressures X (n, C) Pa about
    its fitted response at contacts Y (n, D) and codes (C, k) (`rows`), beside the benchmark's
    validation units' (`validation`, Pa; alarm above OWN_CHECK_ALARM times the worst). A plan
    without rows (ordinary use alone) has none, and a note says so."""
    own: dict[str, Any] = {"presses": plan.presses, "rows": int(len(plan.rows)),
                           "fleet_noise_pa": float(loaded.noise_var.mean().sqrt())}
    if not len(plan.rows):
        notes.append("no labels: no own check of the plan and no intervals")
        return own
    residual = own["residual_pa"] = plan_residual(fit, *rows)
    if isinstance(validation, list) and validation:
        own |= {"validation_units_pa": validation, "over_validation": residual / max(validation),
                "alarm": residual / max(validation) > OWN_CHECK_ALARM}
        if own["alarm"]:
            notes.append(f"warning: the plan's pressures lie {own['over_validation']:.1f}x further from the "
                         "unit's fitted response than the worst validation unit's (alarm above "
                         f"{OWN_CHECK_ALARM:g}x): check the unit's barometers, mounting and labels")
    return own


def _check_on_other_runs(net: tuple[Callable[[Tensor], Tensor], Scaler, Scaler], arrays: FleetArrays,
                         stream: CalibrationStream
                         ) -> tuple[dict[str, Any] | None, tuple[np.ndarray, np.ndarray] | None]:
    """A unit's network (with its input and output scalers) scored on its runs outside the
    calibration stream (None where it has none), and its predictions and targets there (n, D)."""
    other = stream.outside(arrays)
    if not other.any():
        return None, None
    pred = predict(*net, torch.from_numpy(arrays.pressure[other])[None])[0].numpy()
    on_other = (pred, arrays.targets[other])
    return {"rows": int(other.sum()), **scores(*on_other, arrays.layout),
            "units": {target_key(n): t.unit for n, t in arrays.layout.items()}}, on_other


def _fleet_use(path: Path, meta: dict[str, Any], fit: ResponseFit, use: UseRequest,
               training: tuple[FleetArrays, list[str]], seed: int, notes: list[str]) -> FleetUse:
    """How the unit's ordinary use is read: as the response model's benchmark recorded it (metadata
    `label_free`), or, for a model benchmarked without it, the default recipe with the force scale of
    the training units' own ordinary use and no code encoder; `use.seconds` of it either way."""
    saved = meta.get("label_free")
    if saved is not None:
        try:
            fleet = FleetUse.from_json(saved, int(fit.model.label_mean.shape[0]))
        except ValueError as e:
            raise AnytipError(f"{model_paths(path)[1]}: meta.label_free: {e}") from None
    else:
        free = LabelFreeRecipe()
        try:
            scale = fleet_force_scale(training[0], training[1], use.protocol, use.interleave, free, seed)
        except ValueError as e:
            raise AnytipError(f"the response model's training units in the registry: {e}") from None
        fleet = FleetUse(free, use.effective_hz, scale, None)
        notes.append("the response model records no ordinary-use reading (benchmarked without "
                     "options.response.label_free): the default recipe, the training units' force scale, "
                     "and without labels a search from codes zero (research log entry 40)")
    return replace(fleet, free=replace(fleet.free, seconds=use.seconds))


def _codes_from_use(path: Path, fit: ResponseFit, recipe: ResponseRecipe, fleet: FleetUse,
                    fleet_rows: tuple[SourceRows, LoadedModels | None], arrays: FleetArrays,
                    stream: CalibrationStream, plan: Labeled, seed: int
                    ) -> tuple[Tensor, Plan, tuple[Tensor, Tensor] | None]:
    """The unit's codes (1, C, k) from its ordinary use (whole presses of its stream, labels unread)
    and its plan's labeled rows `plan` (none: label-free), the ordinary use read, and the rows it adds
    to the unit's network (`distilled_rows`; None unless the benchmark distilled with a plan)."""
    source, start = fleet_rows
    if fleet.free.distil == "oracle":
        raise AnytipError(f"{model_paths(path)[1]}: meta.label_free.recipe.distil: 'oracle' reads the true "
                          "contacts of the unit's ordinary use, a benchmark's research ceiling; a unit in "
                          "use has none (benchmark with distil: fitted or none)")
    if start is None:
        raise AnytipError(f"{path}: its recipe trains a unit's network from scratch; reading ordinary use "
                          "pulls each unlabeled row's contact towards the pooled start network's "
                          "(benchmark with options.response.inverse_start: pooled)")
    used = stream_ordinary_use(arrays, stream.unit, stream, fleet.free.seconds, seed)
    if len(used.rows) < 2:
        raise AnytipError(f"unit {stream.unit}: its calibration stream holds no whole presses to read as "
                          "ordinary use")
    coder = fleet.coder if fleet.free.start == "encoder" else None
    P = arrays.pressure[used.rows]
    X, Y0, _ = use_inputs(P, fleet.free, start, None, "cpu")
    try:
        first = encoder_codes(P, coder, "cpu")
    except ValueError as e:
        raise AnytipError(f"{model_paths(path)[1]}: meta.label_free.encoder: {e}") from None
    candidates = search_candidates(source.Y, fleet.free.candidates, seed)
    codes, fitted = unit_codes_with_use(fit, recipe, fleet, X, Y0, candidates, seed, plan, first)
    distilled = distilled_rows(fleet.free, X, fitted) if len(plan.X) else None
    return codes[None], used, distilled
