"""What every cross_sensor method shares about its calibration jobs: the plan a budget grants a
unit, what a row says of it, the validation units' loss that chooses between methods, and the
intervals a held-out unit gets from its plan's residuals and what the validation units taught."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, NamedTuple, TypeVar

import numpy as np
from scipy.stats import gmean

from anytip.data.arrays import FleetArrays
from anytip.data.plans import Budget, CodeInformation, Plan, designed_name, plan_for
from anytip.models.scaler import Scaler
from anytip.pipelines.cross_sensor_options import Options
from anytip.report.cross_sensor import COVERAGE_BAND
from anytip.train.shared_split import SeedData
from anytip.uncertainty.conformal import (
    coverage,
    interval,
    needed_halfwidths,
    residual_halfwidth,
)
from anytip.uncertainty.coverage_bootstrap import bootstrap_test_patches, exact_method_band
from anytip.uncertainty.fleet_margin import Learner, MarginChoice, pooled_factor

Job = tuple[str, Budget, float]  # (unit, budget, prior strength)


def band_edges(level: float) -> tuple[float, float, float]:
    """Coverages a unit's test rows record half-widths at: the floor no unit-output may fall
    below (two band widths under `level`) and the band's edges (`level` +- COVERAGE_BAND)."""
    return level - 2 * COVERAGE_BAND, level - COVERAGE_BAND, level + COVERAGE_BAND


def needed_key(output: str, coverage: float) -> str:
    """A held-out row's field for the half-width at which its test rows' coverage of `output` is
    `coverage` (one of `band_edges`): `<output>_needed80_halfwidth` for 0.80."""
    return f"{output}_needed{round(100 * coverage)}_halfwidth"


def missing_designs(arrays: FleetArrays, opts: Options) -> list[str]:
    """The designed calibrations (`plan<seconds>`) strategy `designed` reads at the spec's budgets
    (`options.designed_scale` times each) that no run read from the registry holds: those budgets
    get no designed rows."""
    if opts.budget_unit != "seconds" or "designed" not in opts.plan_strategies:
        return []
    held = {r.protocol for r in arrays.runs}
    wanted = dict.fromkeys(designed_name(design_seconds(b, opts)) for b in opts.budgets if b > 0)
    return [name for name in wanted if name not in held]


def design_seconds(budget_s: float, opts: Options) -> float:
    """Robot seconds of the design whose runs strategy `designed` reads at a budget of `budget_s`."""
    return budget_s * opts.designed_scale


def plan_of(sd: SeedData, unit: str, budget: Budget, opts: Options, seed: int,
            information: CodeInformation | None = None) -> Plan:
    """The labeled rows `budget` grants `unit` (a stream prefix or whole presses); `information`:
    what its presses tell a response model's codes (`informative` plans)."""
    ev = sd.evals[unit]
    return plan_for(budget, ev.stream, ev.presses_for(budget.strategy), opts.rig.timing(), seed, information,
                    designed_s=design_seconds(budget.amount, opts))


def budget_fields(budget: Budget, plan: Plan) -> dict[str, Any]:
    """What a row says of its calibration: labeled samples and robot seconds, and for a
    budget in seconds the budget, the press selection and the plan's presses."""
    out: dict[str, Any] = {"calib_samples": int(len(plan.rows)), "calib_seconds": plan.calib_seconds}
    if budget.unit == "seconds":
        out |= {"budget_s": budget.amount, "plan": budget.strategy, "presses": plan.presses,
                "n_effective": plan.n_effective, "orientations": len(plan.orientations)}
    return out


def plan_suffix(budget: Budget) -> str:
    """What a method name says of a budget in robot seconds: `@strategy` (nothing at 0 s)."""
    return f"@{budget.strategy}" if budget.unit == "seconds" and budget.amount > 0 else ""


UnitLosses = dict[str, float]  # validation unit -> its standardised MSE on its test patches
V = TypeVar("V")


def validation_by_method(method: str, val_loss: dict[Budget, V]) -> dict[str, dict[str, V]]:
    """{row method: {budget: validation-unit loss}} of one shared model and prior (the mean, or each
    unit's, `UnitLosses`), keyed as the report keys rows (method with its plan suffix; budget in
    samples or seconds)."""
    out: dict[str, dict[str, V]] = {}
    for b, v in val_loss.items():
        out.setdefault(method + plan_suffix(b), {})[f"{b.amount:g}"] = v
    return out


def validation_losses(jobs: list[tuple[str, Budget, float]], preds: list[np.ndarray], sd: SeedData,
                      arrays: FleetArrays, val_units: set[str],
                      out_scaler: Scaler) -> dict[tuple[Budget, float], UnitLosses]:
    """(budget, prior) -> each validation unit's standardised MSE on its test patches."""
    std = out_scaler.std.reshape(-1).cpu().numpy()
    loss: dict[tuple[Budget, float], UnitLosses] = {}
    for (u, b, p), pred in zip(jobs, preds, strict=True):
        if u in val_units:
            err = (pred - arrays.targets[sd.evals[u].test_rows]) / std
            loss.setdefault((b, p), {})[u] = float((err**2).mean())
    return loss


def mean_loss(units: UnitLosses) -> float:
    """The validation units' mean loss."""
    return float(np.mean(list(units.values())))


class FleetWidths(NamedTuple):
    """What the validation (and factor) units say about intervals at one budget, per output (D,):
    the fleet factor (`uncertainty.conformal.fleet_factor`), the typical half-width their test
    rows needed (geometric mean; a new unit's plan unused), in the output's unit, and the spread
    over them of log(needed / own half-width) (how far one unit's own half-width, times the
    factor, misses what its test rows need; NaN with one validation unit). `learners`: each unit's
    half-widths by id; `margin`: the factor's leave-one-unit-out margin over them
    (`uncertainty.fleet_margin`)."""

    factor: np.ndarray
    typical: np.ndarray
    spread: np.ndarray
    learners: dict[str, Learner] = {}  # noqa: RUF012  (a NamedTuple's default, never mutated)
    margin: MarginChoice = MarginChoice(1.0, {}, {})


def validation_factors(at_chosen: list[tuple[Job, np.ndarray]],
                       residuals: dict[int, np.ndarray | None], sd: SeedData, arrays: FleetArrays,
                       level: float) -> dict[Budget, FleetWidths]:
    """Budget -> `FleetWidths` over the validation and factor units whose plan gave a finite
    half-width at `level`: the half-width their test rows needed against their plan's own."""
    learners: dict[Budget, dict[str, Learner]] = {}
    learn = {*sd.split.val, *sd.split.factor}
    for k, r in residuals.items():
        (u, b, _), pred = at_chosen[k]
        if u not in learn or r is None:
            continue
        half = residual_halfwidth(r, level)
        miss = pred - arrays.targets[sd.evals[u].test_rows]
        test = residual_halfwidth(miss, level)
        if np.isfinite(half).all() and (half > 0).all() and np.isfinite(test).all() and (test > 0).all():
            learners.setdefault(b, {})[u] = Learner(half, test, *needed_halfwidths(miss, band_edges(level)))
    return {b: fleet_widths(by_unit) for b, by_unit in learners.items()}


def fleet_widths(learners: dict[str, Learner]) -> FleetWidths:
    """What the learning units (validation and factor units, by id) say at one budget."""
    units = list(learners.values())
    own, needed = np.stack([u.own for u in units]), np.stack([u.needed for u in units])
    factor, margin = pooled_factor(units)
    return FleetWidths(factor, gmean(needed, axis=0), log_ratio_spread(own, needed), learners, margin)


def log_ratio_spread(own: np.ndarray, needed: np.ndarray) -> np.ndarray:
    """(D,): the sample standard deviation over units of log(needed / own), both (U, D); NaN for U < 2."""
    if len(own) < 2:
        return np.full(own.shape[1], np.nan)
    return np.log(needed / own).std(0, ddof=1)


EXACT_DRAWS = 200  # test-patch draws behind the spread of a unit's coverage (interval_fields)


def interval_fields(residuals: np.ndarray | None, pred: np.ndarray, target: np.ndarray,
                    names: Sequence[str], level: float, fleet: FleetWidths | None = None,
                    patch: np.ndarray | None = None, seed: int = 0) -> dict[str, Any]:
    """A held-out unit's intervals from its own plan, scored on its test rows: the conformal half-width of
    each output (in its target's unit: the fingertip's N or rad) from the plan's out-of-fold residuals
    (n, D), and the share of test rows (pred, target (m, D)) inside pred +- half-width. Given what the
    validation units say (`fleet`), the same for the half-width times the fleet factor
    (`<output>_fleet_halfwidth`, `<output>_fleet_coverage`), for their typical half-width, the plan unused
    (`<output>_typical_...`), and for the geometric mean of the two, the unit's plan shrunk halfway to the
    fleet (`<output>_shrunk_...`), for the fleet factor times its margin (`<output>_margin_...`), and the
    half-widths at which the test rows' coverage is each of `band_edges` (`<output>_needed80_halfwidth`,
    ...: where any other width lands as to the band and its floor, without the test rows); given the test
    rows' patches (m,) as well, how well the unit's test set decides its coverage (`test_set_fields`).
    Empty for a plan too short to cross-fit."""
    if residuals is None:
        return {}
    half = residual_halfwidth(residuals, level)
    edges = band_edges(level)
    out = {"interval_level": level, "interval_rows": int(len(residuals)),
           "interval_test_rows": int(len(target)), **_band(pred, target, names, half, ""),
           **{needed_key(n, c): float(v)
              for c, h in zip(edges, needed_halfwidths(pred - target, edges), strict=True)
              for n, v in zip(names, h, strict=True)}}
    if fleet is not None:
        out |= _band(pred, target, names, half * fleet.factor, "fleet_")
        out |= _band(pred, target, names, half * fleet.factor * fleet.margin.margin, "margin_")
        out |= _band(pred, target, names, fleet.typical, "typical_")
        out |= _band(pred, target, names, np.sqrt(half * fleet.factor * fleet.typical), "shrunk_")
        if patch is not None:
            out |= test_set_fields(pred, target, half * fleet.factor, patch, names, level, seed)
    return out


def test_set_fields(pred: np.ndarray, target: np.ndarray, half: np.ndarray, patch: np.ndarray,
                    names: Sequence[str], level: float, seed: int) -> dict[str, Any]:
    """How well one unit's test set decides the coverage of its interval pred +- half (D,): with its
    test patches (m,) drawn again EXACT_DRAWS times, the spread of the coverage per output
    (`<output>_fleet_coverage_sd`) and the chance that a method whose coverage is exactly `level`
    for this unit lands outside level +- COVERAGE_BAND on such a test set (`<output>_exact_p_outside`;
    `uncertainty.coverage_bootstrap.exact_method_band`)."""
    lo, hi = interval(pred, half)
    covered = (target >= lo) & (target <= hi)
    draws = bootstrap_test_patches(covered, patch, EXACT_DRAWS, np.random.default_rng(seed))
    band = exact_method_band(draws, covered.mean(0), level, (level - COVERAGE_BAND, level + COVERAGE_BAND))
    return {"interval_test_patches": int(len(np.unique(patch))),
            **{f"{n}_fleet_coverage_sd": float(v) for n, v in zip(names, band["sd"], strict=True)},
            **{f"{n}_exact_p_outside": float(v) for n, v in zip(names, band["p_outside"], strict=True)}}


def scaled_fields(residuals: np.ndarray, pred: np.ndarray, target: np.ndarray, names: Sequence[str],
                  level: float, fleet: FleetWidths, prefix: str) -> dict[str, float]:
    """`<output>_<prefix>halfwidth` and `<output>_<prefix>coverage`: the conformal half-width of
    residuals (n, D) times the fleet factor, scored on the test rows (pred, target (m, D))."""
    return _band(pred, target, names, residual_halfwidth(residuals, level) * fleet.factor, prefix)


def _band(pred: np.ndarray, target: np.ndarray, names: Sequence[str], half: np.ndarray,
          prefix: str) -> dict[str, float]:
    lo, hi = interval(pred, half)
    cover = coverage(lo, hi, target)
    return {**{f"{n}_{prefix}halfwidth": float(h) for n, h in zip(names, half, strict=True)},
            **{f"{n}_{prefix}coverage": float(c) for n, c in zip(names, cover, strict=True)}}
