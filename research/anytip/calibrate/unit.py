"""`calibrate_unit`: the arguments checked, the unit's runs and the shared model read, its plan chosen, and
the calibration handed to the adapter or to response transfer."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from anytip.calibrate.adapter import calibrate_by_adapter_unit
from anytip.calibrate.intervals import interval_records
from anytip.calibrate.plan_choice import (
    DEFAULT_SECONDS,
    DESIGNED,
    choose_plan,
    designed_plan,
    is_designed_stream,
    response_plan,
    rig_of,
)
from anytip.calibrate.records import benchmarked_in, find_shared
from anytip.calibrate.response import UseRequest, calibrate_by_response_unit, choose_response
from anytip.calibrate.result import Calibrated, write_calibration
from anytip.data.arrays import FleetArrays, load_arrays
from anytip.data.calibration import CalibrationStream, calibration_stream
from anytip.data.plans import Plan
from anytip.data.registry import Registry
from anytip.data.use_log import UseLog, read_use_log
from anytip.errors import AnytipError
from anytip.models.io import load_shared
from anytip.train.core_speed import core_gflops

METHODS = ("auto", "adapter", "response")

MAX_USE_S = 600.0  # seconds of ordinary use after mounting a calibration may read (the allowance)


def calibrate_unit(model: str | Path, unit: str, registry: Registry, out: str | Path,
                   budget_samples: int | None = None, budget_seconds: float | None = None,
                   adapter: str | None = None, seed: int | None = None,
                   interval_level: float | None = 0.9, method: str = "auto",
                   use_seconds: float = 0.0, factor_from: Sequence[str | Path] = (),
                   plan_strategy: str | None = None, use_logs: Sequence[str | Path] = ()) -> Calibrated:
    """Fit, fold and save one unit's model; see the package docstring (`anytip.calibrate`).
    `interval_level`: the nominal coverage of the intervals from the plan (None: none). `method`:
    `adapter` (the shared model's adapter, folded), `response` (response transfer; a run with a response
    model) or `auto` (response where the run's validation units scored it below the chosen shared model at
    this budget). `use_seconds`: contact seconds of the unit's ordinary use read without labels (response
    transfer alone reads them: with the plan, or alone at budget 0). `factor_from`: more runs of the same
    benchmark (a registry's other unit folds) whose response models' learning units learn the intervals'
    fleet factor and margin with the run's own (`pooled_learners`). `plan_strategy`: the press selection
    response transfer calibrates by, as asked (a choice made on more validation units than the run's;
    research log entry 100), instead of `response_strategy`'s; `designed`, the unit's runs of the designed
    calibration of the budget's seconds (`designed_plan`), which a unit whose runs are that alone gets by
    default, its ordinary use then read from its other runs. `use_logs`: ordinary-use logs of the unit
    (`data.use_log`), whose contacts are found from their pressures, read as its ordinary use instead of
    any run (with `use_seconds`)."""
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
    logs = _use_logs(use_logs, unit, use_seconds, arrays)
    use_stream = stream  # where ordinary use is read: the calibration stream, a designed plan's or not
    stream, plan, budget, clipped, plan_strategy = _unit_plan(
        meta, arrays, stream, (budget_samples, budget_seconds), plan_strategy, 0.0 if logs else use_seconds)
    notes = [f"shared model {shared_path.name}: {choice}"] + ([clipped] if clipped else [])
    if unit in meta.get("unit_ids", []):
        notes.append(f"warning: unit {unit} was a training unit of the shared model; its "
                     "calibration check is not an unseen-unit result")
    response, why = choose_response(model, seed, meta, budget, method, adapter, use_seconds,
                                    DESIGNED if plan_strategy == DESIGNED else None)
    notes += [why] if why else []
    if response is not None:
        use = None
        if use_seconds > 0:
            rig = rig_of(meta)
            use = UseRequest(use_seconds, meta.get("calibration_protocol"),
                             bool(meta.get("calibration_interleave", False)), rig.effective_hz, use_stream,
                             logs)
        pooled = interval_records(factor_from, response)
        strategy, planned = response_plan(response, meta, (arrays, stream), plan, budget, use is not None,
                                          notes, plan_strategy)
        return _written(calibrate_by_response_unit(response, registry, arrays, stream, planned, budget,
                                                   Path(out), notes, interval_level, strategy, use, pooled,
                                                   meta.get("calibration_protocol")))
    if factor_from:
        raise AnytipError("--factor-from is read by response transfer alone: the adapter's intervals have "
                          "their own fleet factor")
    if plan_strategy not in (None, DESIGNED):
        raise AnytipError("--plan-strategy is read by response transfer alone: the adapter calibrates on the "
                          "plans its benchmark chose, or on the unit's designed runs (--plan-strategy "
                          "designed)")
    return _written(calibrate_by_adapter_unit((shared, shared_path), arrays, stream, plan, budget, Path(out),
                                              notes, interval_level))


def _unit_plan(meta: dict[str, Any], arrays: FleetArrays, stream: CalibrationStream,
               budgets: tuple[int | None, float | None], plan_strategy: str | None, use_seconds: float
               ) -> tuple[CalibrationStream, Plan, float, str, str | None]:
    """The unit's stream, plan, budget and a note (`choose_plan`), and the plan strategy asked for: for
    `designed`, or by default where a benchmark in robot seconds meets a unit whose runs are its designed
    calibration alone and a labeled budget, the designed runs' stream and plan (`designed_plan`)."""
    alone = is_designed_stream(arrays, stream)
    labeled = budgets[1] != 0 and meta.get("budget_unit") == "seconds"
    if plan_strategy != DESIGNED and not (alone and labeled):
        return stream, *choose_plan(meta, arrays, stream, *budgets), plan_strategy
    if use_seconds > 0 and alone:
        raise AnytipError(f"unit {stream.unit}: its runs are its designed calibration alone "
                          f"({', '.join(stream.runs)}); --ordinary-use reads whole presses of its other "
                          "runs, unlabeled, as the log of its ordinary use, and it has none")
    return *designed_plan(meta, arrays, stream.unit, *budgets), DESIGNED


def _use_logs(paths: Sequence[str | Path], unit: str, use_seconds: float, arrays: FleetArrays
              ) -> tuple[UseLog, ...]:
    """The unit's ordinary-use logs read and checked against it: its id, sensor model and barometer count;
    AnytipError naming the file where one is another unit's or sensor's, or where no seconds are asked."""
    if paths and use_seconds <= 0:
        raise AnytipError("--use-log is read as ordinary use: give --ordinary-use SECONDS as well")
    logs, model = [], arrays.runs[0].sensor_model  # every run of the unit's is of one sensor model
    for path in paths:
        log = read_use_log(path)
        if log.sensor_id != unit or log.sensor_model != model:
            raise AnytipError(f"{path}: a log of {log.sensor_id} ({log.sensor_model}), not of unit {unit} "
                              f"({model})")
        if log.pressure.shape[1] != arrays.pressure.shape[1]:
            raise AnytipError(f"{path}: {log.pressure.shape[1]} barometers, where the unit's runs have "
                              f"{arrays.pressure.shape[1]}")
        logs.append(log)
    return tuple(logs)


def _written(result: Calibrated) -> Calibrated:
    """`result` with this core's reference product rate (`core_gflops`, measured after the fit, outside
    its `wall_s`), written as `calibration.json`."""
    result.core_gflops = round(core_gflops(), 1)
    return write_calibration(result)
