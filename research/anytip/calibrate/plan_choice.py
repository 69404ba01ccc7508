"""Which of a new unit's rows its calibration labels: a budget in samples or robot seconds, turned into
a plan as the shared model's benchmark chose plans (or the unit's designed calibration runs), and the
press selection response transfer takes (decided by the run's spec, asked for, or the response model's
best on its validation units)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any, get_args

import numpy as np

from anytip.calibrate.records import at_budget, response_record, strategy_table
from anytip.data.arrays import FleetArrays
from anytip.data.calibration import CalibrationStream, calibration_stream
from anytip.data.plans import (
    INFORMED,
    Budget,
    Plan,
    RigTiming,
    Strategy,
    designed_name,
    find_presses,
    plan_for,
    select_presses,
    stream_plan,
)
from anytip.errors import AnytipError
from anytip.models.io import model_paths
from anytip.sensor.protocols import is_designed
from anytip.train.response import ResponseFit, press_information

DEFAULT_SECONDS = 120.0  # a budget in seconds when none is given: the 2-minute calibration


# the selections from a unit's presses a spec may decide beforehand (a designed plan is its own run)
ASKABLE: tuple[str, ...] = tuple(s for s in get_args(Strategy) if s != "designed")
DESIGNED = "designed"  # `--plan-strategy designed`: the unit's designed calibration runs (`designed_plan`)


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


def rig_of(meta: dict[str, Any]) -> RigTiming:
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
        rig = rig_of(meta)
        plan = select_presses(presses, seconds, rig, meta.get("plan_strategy", "spread"),
                              int(meta.get("seed", 0)))
        total = float(presses.duration_s.sum() + rig.move_s * len(presses))
        note = (f"--budget-seconds {seconds:g}: the unit's runs hold {len(presses)} presses, all of them "
                f"used ({plan.calib_seconds:.1f} robot-s)") if plan.presses == len(presses) and \
            seconds > total else ""
        return plan, seconds, note
    n, note = budget_rows(stream, budget_samples, budget_seconds)
    return stream_plan(stream, n), float(n), note


def is_designed_stream(arrays: FleetArrays, stream: CalibrationStream) -> bool:
    """Whether a unit's calibration stream is its designed calibration: every run it reads is of a
    designed protocol (`plan<seconds>`), as `calibration_stream` leaves them where the unit has no
    other runs (a new unit calibrated on the rig's designed plan alone)."""
    protocols = [r.protocol for r in arrays.runs if r.run_id in stream.runs]
    return bool(protocols) and all(is_designed(p) for p in protocols)


def designed_plan(meta: dict[str, Any], arrays: FleetArrays, unit: str, budget_samples: int | None,
                  budget_seconds: float | None) -> tuple[CalibrationStream, Plan, float, str]:
    """A unit's designed calibration (`--plan-strategy designed`, or a unit whose runs are that alone):
    its runs of the design of the budget's robot seconds (`plan<seconds>`, what `anytip calibrate --plan
    SECONDS` writes for the rig) as its stream; their presses in recorded order up to the budget, each
    paying its recorded lead as its move, as the benchmark's `designed` rows read them (`plan_for`);
    the budget; and a note naming the runs. AnytipError naming the designs the unit holds where it
    holds none of this budget's, or the runs where they hold no press within it."""
    if meta.get("budget_unit", "samples") != "seconds" or budget_samples is not None:
        raise AnytipError("a designed calibration is budgeted in robot seconds: give --budget-seconds, with "
                          "a shared model benchmarked in seconds (options.budget_unit: seconds)")
    seconds = DEFAULT_SECONDS if budget_seconds is None else budget_seconds
    if not math.isfinite(seconds) or seconds <= 0:
        raise AnytipError(f"--budget-seconds must be a finite number > 0 for a designed calibration, "
                          f"got {seconds}")
    name = designed_name(seconds)
    stream = calibration_stream(arrays, unit, name)
    if stream.protocol != name:
        held = sorted({str(r.protocol) for r in arrays.runs if r.unit == unit and is_designed(r.protocol)})
        raise AnytipError(f"unit {unit} holds no runs of the designed calibration of {seconds:g} robot-s "
                          f"({name}); its designed runs: {', '.join(held) or 'none'} (give --budget-seconds "
                          f"of one of them, or mark the rig's runs with `anytip data protocol RUN {name}`)")
    presses = find_presses(arrays, unit, stream.outside(arrays))
    plan = plan_for(Budget(seconds, "seconds", DESIGNED), stream, presses, rig_of(meta),
                    int(meta.get("seed", 0)))
    if not plan.presses:
        raise AnytipError(f"unit {unit}: its {name} runs ({', '.join(stream.runs)}) hold no whole press "
                          f"within {seconds:g} robot-s")
    note = (f"plan: designed, the unit's {name} runs ({plan.presses} of their {len(presses)} presses, "
            f"{plan.calib_seconds:.1f} robot-s)")
    return stream, plan, seconds, note


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
        rig = rig_of(self.meta)
        information = (press_information(fit, self.arrays, presses, rig.effective_hz, criterion)
                       if self.strategy in INFORMED else None)
        return select_presses(presses, self.seconds, rig, self.strategy,  # type: ignore[arg-type]
                              int(self.meta.get("seed", 0)), information)


def response_plan(path: Path, meta: dict[str, Any], unit: tuple[FleetArrays, CalibrationStream], plan: Plan,
                  budget: float, with_use: bool, notes: list[str], asked: str | None = None
                  ) -> tuple[str, Plan | PlanRequest]:
    """(strategy, plan) of a calibration by the response model `path`: the shared model's plan
    `plan`, or a `PlanRequest` where the response model scored another strategy best
    (`response_strategy`; budgets in robot seconds), or where another was `asked`; `plan` itself as
    `designed` where that was asked (the unit's designed runs, `designed_plan`)."""
    shared = str(meta.get("plan_strategy", "spread"))
    if asked == DESIGNED:  # the unit's designed runs (`designed_plan`): nothing to choose
        if not strategy_table(response_record(path), "val_loss", DESIGNED):
            notes.append("the response model's benchmark scored no designed plans (options.plan_strategies "
                         "without designed): the own check and the intervals have no fleet reference "
                         "for them")
        return DESIGNED, plan
    if asked is not None and asked not in ASKABLE:
        raise AnytipError(f"--plan-strategy {asked!r}: expected one of {', '.join((*ASKABLE, DESIGNED))}")
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
            v = at_budget(strategy_table(recorded, key, strategy), budget)
            if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v):
                losses[strategy] = float(v)
        if any(s in INFORMED for s in losses):
            best = min(losses, key=losses.__getitem__)
            return shared if losses.get(shared, math.inf) <= losses[best] else best
    return shared
