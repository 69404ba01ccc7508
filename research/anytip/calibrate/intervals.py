"""A new unit's intervals from its own plan: the plan's residual half-widths times the fleet factor (and
margin) the benchmark's learning units learnt, pooled over other unit folds' response models where asked
(`--factor-from`)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from anytip.calibrate.records import at_budget, budget_table, response_models, strategy_table
from anytip.errors import AnytipError
from anytip.models.io import RESPONSE_FORMAT, model_paths, read_header
from anytip.train.shared_split import OWN_CHECK_FOLDS
from anytip.uncertainty.conformal import coverage, interval, residual_halfwidth
from anytip.uncertainty.fleet_margin import Learner, MarginChoice, pooled_factor

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
    return _usable_factor(rec, budget_table(rec, "fleet_factor_by_budget"), budget, level, names)


def _usable_factor(rec: dict[str, Any], table: dict[float, Any], budget: float, level: float,
                   names: tuple[str, ...]) -> tuple[dict[str, float] | None, str]:
    """The factor of a benchmark's intervals record `rec` from its per-budget `table` at the
    largest budget <= `budget`, or None and why: another level, or not a finite positive number
    for every output."""
    if rec.get("level") != level:
        return None, (f"the benchmark's fleet factor for intervals was learnt at level "
                      f"{rec.get('level')}, not {level:g}: intervals from the plan alone")
    factor = at_budget(table, budget)
    ok = isinstance(factor, dict) and all(isinstance(factor.get(n), (int, float)) and
                                          math.isfinite(factor[n]) and factor[n] > 0 for n in names)
    if not ok:
        return None, (f"the benchmark records no usable fleet factor for intervals at {budget:g} robot-s "
                      "or less: intervals from the plan alone")
    return {n: float(factor[n]) for n in names}, ""


def use_factor_fits(weighed: float, benchmark: float, notes: list[str]) -> bool:
    """Whether a unit's intervals take the fleet factor the benchmark learnt for codes fitted with its
    `benchmark` seconds of ordinary use: where the use the unit's codes read weighs as much (`weighed`
    seconds: those asked, or those read where the logs or stream ran out). A lighter use leaves the codes
    nearer the plan's alone, and the plan alone's factor serves: on 64 fresh validation units with logs
    of 160-235 contact-seconds it put 88.8% of their unit-outputs in band and 11 below 0.80, where the
    use factor put 78.4% and 21 (research log entry 198). A note says which."""
    if weighed >= benchmark:
        return True
    notes.append(f"intervals: the plan alone's fleet factor, as the ordinary use read weighs {weighed:.1f} "
                 f"s, less than the {benchmark:g} s the benchmark's factor for codes fitted with use was "
                 "learnt on (research log entry 198)")
    return False


def response_intervals(meta: dict[str, Any], residuals: np.ndarray, budget: float, strategy: str,
                       level: float, names: tuple[str, ...], other: tuple[np.ndarray, np.ndarray] | None,
                       notes: list[str], use: tuple[float, float] | None = None,
                       pooled: tuple[list[tuple[Path, dict[str, Any]]], str] | None = None
                       ) -> dict[str, Any] | None:
    """A response-transferred unit's intervals: its network's residuals on the plan's rows (n, D),
    which also trained it, times the fleet factor the benchmark's validation units learnt for
    plans of `strategy` (`intervals.fleet_factor_by_strategy`; `use_fleet_factor_by_strategy` for
    codes fitted with ordinary use that weighs as much as the benchmark's, `use`: (seconds weighed,
    the benchmark's), see `use_factor_fits`); a note where there is none. `pooled`: (other models'
    intervals records, the unit calibrated): the factor and margin learnt by the learners of this
    model's record and theirs but that unit's own (`pooled_learners`, research log entry 53)."""
    rec = meta.get("intervals")
    factor, why = None, ("the response model's benchmark learnt no fleet factor for intervals: intervals "
                         "from the plan's rows alone, which also trained the network (too narrow)")
    if isinstance(rec, dict):
        table = strategy_table(rec, "use_fleet_factor", strategy) if use else None
        if use and not table:
            notes.append("the response model's benchmark learnt no fleet factor for codes fitted with "
                         "ordinary use: the one learnt for codes from the plan alone is applied")
        elif use and not use_factor_fits(*use, notes):
            table = None
        prefix = "use_" if table else ""
        table = table or strategy_table(rec, "fleet_factor", strategy)
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
    got = at_budget(strategy_table(rec, key, strategy), budget)
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
        by_unit = at_budget(strategy_table(rec, key, strategy), budget)
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
