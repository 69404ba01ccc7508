"""Calibration by response transfer: the unit's codes fitted on its plan (and its ordinary use), the
training units' rows carried over to it, and its own network trained on them; its own check is the plan's
pressures about its fitted response."""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
import torch
from torch import Tensor

from anytip.calibrate.intervals import response_intervals
from anytip.calibrate.plan_choice import PlanRequest, response_strategy
from anytip.calibrate.records import at_budget, response_record, strategy_table, val_loss_table
from anytip.calibrate.result import OWN_CHECK_ALARM, Calibrated, check_on_other_runs
from anytip.data.arrays import FleetArrays, load_arrays
from anytip.data.calibration import CalibrationStream
from anytip.data.plans import Plan, stream_ordinary_use, stream_presses
from anytip.data.registry import Registry
from anytip.data.use_log import UseLog, use_rows
from anytip.errors import AnytipError
from anytip.models.io import (
    LoadedModels,
    LoadedResponse,
    ModelFileError,
    load_models,
    load_response,
    load_source_response,
    model_paths,
    save_models,
    save_source_response,
)
from anytip.models.mlp import MLPConfig
from anytip.train.data import FleetBatchData, UnitTensors
from anytip.train.fleet import start_mismatch
from anytip.train.label_free import (
    FleetUse,
    Labeled,
    LabelFreeRecipe,
    distilled_rows,
    encoder_codes,
    fleet_force_scale,
    search_draws,
    unit_codes_with_use,
    use_inputs,
    with_use_method,
)
from anytip.train.metrics import predict
from anytip.train.response import (
    ResponseFit,
    ResponseRecipe,
    SourceRows,
    calibrate_by_response,
    draw_source_rows,
    own_response,
    plan_residual,
    source_digest,
    source_response_path,
    start_network_path,
)
from anytip.train.shared_split import main_rows, unit_main_rows


@dataclass(frozen=True)
class UseRequest:
    """A calibration's ordinary use (`--ordinary-use`): contact seconds of whole presses of the unit's
    stream read without their labels, and how the stream is read (the shared model's protocol,
    interleaving and rig's effective_hz, the defaults of a response model that records none); `stream`:
    the stream it is drawn from where that is not the plan's (a designed plan's runs are a stream of
    their own; None: the plan's)."""

    seconds: float
    protocol: str | None
    interleave: bool
    effective_hz: float
    stream: CalibrationStream | None = None
    logs: tuple[UseLog, ...] = ()  # ordinary-use logs (`--use-log`): read instead of any stream


class UseRead(NamedTuple):
    """What a calibration read as ordinary use: its rows among the loaded runs' (none for a log), how many
    rows, their contact seconds, and whether the stream or logs held less contact than asked (`ran_out`;
    otherwise reading whole presses, or whole samples of a log, stops short of the seconds asked by less than
    one press or one sample)."""

    rows: np.ndarray
    samples: int
    contact_seconds: float
    ran_out: bool = False


def choose_response(model: str | Path, seed: int | None, meta: dict[str, Any], budget: float, method: str,
                    adapter: str | None, use_seconds: float = 0.0, strategy: str | None = None
                    ) -> tuple[Path | None, str]:
    """The response model file to calibrate by (None: the shared model's adapter) and a note why.
    With ordinary use (`use_seconds` > 0) it is response transfer or an error: nothing else reads it.
    `strategy`: the plan's, where it is fixed (`designed`), whose validation loss `auto` compares; else
    the one response transfer would choose (`response_strategy`)."""
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
    strategy = strategy or response_strategy(recorded, str(meta.get("plan_strategy", "spread")), budget,
                                             path=path)
    table = strategy_table(recorded, "val_loss", strategy)
    theirs = at_budget({b: float(v) for b, v in table.items() if isinstance(v, (int, float))}, budget)
    ours = val_loss_table(meta, budget)
    if theirs is None and ours is not None:
        return None, (f"the shared model's adapter: the run's benchmark scored response transfer on no "
                      f"{strategy} plan at this budget (--method response calibrates by it all the same)")
    if theirs is None or ours is None or theirs >= ours:
        return None, ""
    return path, (f"calibration by response transfer: its validation-unit loss {theirs:.3g} is below the "
                  f"shared model's {ours:.3g} at this budget")


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
    return path, (f"calibration by response transfer: the codes from up to {use_seconds:g} s of the unit's "
                  f"ordinary use {what} (research log entries 44-46)")


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
    given, used, distilled = None, UseRead(np.zeros(0, np.int64), 0, 0.0), None
    use_weight = None  # (seconds the use read weighs, the benchmark's): which factor the intervals take
    if use is not None:
        fleet = _fleet_use(path, meta, fit, use, (training_arrays, units), seed, notes)
        asked = replace(fleet, free=replace(fleet.free, seconds=use.seconds))
        given, used, distilled = _codes_from_use(path, fit, recipe, asked, (source, start), arrays,
                                                 (use.stream or stream, use.logs),
                                                 Labeled(X, Y, plan.n_effective), seed)
        if used.ran_out:
            held = "all the logs hold" if use.logs else "all the stream holds"
            notes.append(f"ordinary use: {used.contact_seconds:.1f} s of contact read of the {use.seconds:g} "
                         f"s asked ({held}), weighed as what was read")
        # the seconds asked where the use held them: whole presses or samples stop short by less than one
        use_weight = (used.contact_seconds if used.ran_out else use.seconds, fleet.free.seconds)
    nets, codes = calibrate_by_response(fit, source, [X], [Y], [plan.n_effective], shape, recipe, seed,
                                        [stream.unit], arrays.output_names, start=start, codes=given,
                                        extra=[distilled])
    wall_s = time.perf_counter() - tick + plan_s
    own = _response_own_check(loaded, fit, plan, (X, Y, codes[0]), at_budget(
        strategy_table(meta, "residual", strategy), budget), notes)
    check, on_other = check_on_other_runs((nets.model, nets.in_scaler, nets.out_scaler), arrays, stream,
                                          used.rows)
    bands = None
    if interval_level is not None and len(plan.rows):
        fitted = predict(nets.model, nets.in_scaler, nets.out_scaler, X[None])[0].numpy()
        residuals = fitted - arrays.targets[plan.rows]
        pool = (pooled, stream.unit) if pooled else None
        bands = response_intervals(meta, residuals, budget, strategy, interval_level, arrays.output_names,
                                   on_other, notes, use_weight, pool)
    method = ("response" if use is None else with_use_method(fleet.free) if len(plan.rows)
              else "response:label_free")
    result = Calibrated(out, stream.unit, int(len(plan.rows)), plan.calib_seconds, used.samples, 0.0, check,
                        notes, None, wall_s, bands, 0.0, own, used.contact_seconds)
    save_models(out / "model.safetensors", nets.model, nets.in_scaler, nets.out_scaler, {
        "unit_ids": [stream.unit], "output_names": list(arrays.output_names), "response_model": str(path),
        "method": method, "codes": codes[0].tolist(),
        "calib_samples": result.calib_samples, "calib_seconds": plan.calib_seconds,
        "calib_presses": plan.presses, "n_effective": plan.n_effective, "unlabeled_samples": used.samples,
        "unlabeled_seconds": used.contact_seconds, "calibration_runs": list(stream.runs),
        "check_on_other_runs": check, "response_check": own, "intervals": bands})
    return result


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


def _fleet_use(path: Path, meta: dict[str, Any], fit: ResponseFit, use: UseRequest,
               training: tuple[FleetArrays, list[str]], seed: int, notes: list[str]) -> FleetUse:
    """How the unit's ordinary use is read: as the response model's benchmark recorded it (metadata
    `label_free`), or, for a model benchmarked without it, the default recipe with the force scale of
    the training units' own ordinary use and no code encoder; its seconds the benchmark's (the
    default recipe's)."""
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
    return fleet


def _codes_from_use(path: Path, fit: ResponseFit, recipe: ResponseRecipe, fleet: FleetUse,
                    fleet_rows: tuple[SourceRows, LoadedModels | None], arrays: FleetArrays,
                    where: tuple[CalibrationStream, tuple[UseLog, ...]], plan: Labeled, seed: int
                    ) -> tuple[Tensor, UseRead, tuple[Tensor, Tensor] | None]:
    """The unit's codes (1, C, k) from its ordinary use and its plan's labeled rows `plan` (none:
    label-free), the ordinary use read, and the rows it adds to the unit's network (`distilled_rows`; None
    unless the benchmark distilled with a plan). `where`: the stream whose whole presses are read, labels
    unread, or the unit's ordinary-use logs, whose contacts are found from their pressures (`use_rows`).
    The rows weigh in the joint fit as the contact seconds read where those fall short of `fleet`'s."""
    stream, logs = where
    source, start = fleet_rows
    if fleet.free.distil == "oracle":
        raise AnytipError(f"{model_paths(path)[1]}: meta.label_free.recipe.distil: 'oracle' reads the true "
                          "contacts of the unit's ordinary use, a benchmark's research ceiling; a unit in "
                          "use has none (benchmark with distil: fitted or none)")
    if start is None:
        raise AnytipError(f"{path}: its recipe trains a unit's network from scratch; reading ordinary use "
                          "pulls each unlabeled row's contact towards the pooled start network's "
                          "(benchmark with options.response.inverse_start: pooled)")
    if logs:
        P, read = _logged_use(logs, fleet.free.seconds)
    else:
        presses = stream_presses(arrays, stream.unit, stream)
        used = stream_ordinary_use(arrays, stream.unit, stream, fleet.free.seconds, seed, presses)
        P = arrays.pressure[used.rows]
        ran_out = used.presses == len(presses) and used.contact_seconds < fleet.free.seconds
        read = UseRead(used.rows, len(used.rows), used.contact_seconds, ran_out)
    if len(P) < 2:
        where_from = "ordinary-use logs hold" if logs else "calibration stream holds"
        raise AnytipError(f"unit {stream.unit}: its {where_from} no contacts to read as ordinary use")
    # the rows weigh as the contact seconds they hold, where fewer than asked (research log entry 184)
    fleet = replace(fleet, free=replace(fleet.free, seconds=min(fleet.free.seconds, read.contact_seconds)))
    coder = fleet.coder if fleet.free.start == "encoder" else None
    X, Y0, _ = use_inputs(P, fleet.free, start, None, "cpu")
    try:
        first = encoder_codes(P, coder, "cpu")
    except ValueError as e:
        raise AnytipError(f"{model_paths(path)[1]}: meta.label_free.encoder: {e}") from None
    draws = search_draws(source.Y, fleet.free, seed)
    codes, fitted = unit_codes_with_use(fit, recipe, fleet, X, Y0, draws, seed, plan, first)
    distilled = distilled_rows(fleet.free, X, fitted) if len(plan.X) else None
    return codes[None], read, distilled


def _logged_use(logs: tuple[UseLog, ...], seconds: float) -> tuple[np.ndarray, UseRead]:
    """The tared pressures (n, C) Pa of the contacts the logs hold, in order, up to `seconds` of contact
    (`use_rows`), and what was read: the logs ran out where a sample or more of the seconds asked is left
    after the last of them (a log that holds enough is read to within one sample)."""
    parts, left, rate = [], seconds, np.inf
    for log in logs:
        if left <= 0:
            break
        P, got = use_rows(log, left)
        parts.append(P)
        left, rate = left - got, log.sample_rate_hz
    P = np.concatenate(parts) if parts else np.zeros((0, 0), np.float32)
    return P, UseRead(np.zeros(0, np.int64), len(P), seconds - left, left * rate >= 1)
