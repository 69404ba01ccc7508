"""Unit roles and tensors for a shared model across units: training units' rows, and each
validation and held-out unit's test patches and calibration stream.

Per seed, units are dealt into training, validation and held-out roles. Every validation and
held-out unit loses whole patches of its main runs (runs other than the calibration protocol's)
to testing; its calibration stream never contains a row of those patches. Training units
contribute their main rows (a random `val_fraction` for model selection) and their calibration
stream's pressures (its first `unlabeled_s` seconds, as for a new unit) as label-free input
statistics. Used by the cross_sensor pipeline, the shared
architecture search and `anytip calibrate`'s benchmark twin alike.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import torch

from anytip.data.arrays import FleetArrays, has_patch_grid
from anytip.data.calibration import CalibrationStream, calibration_stream
from anytip.data.plans import Plan, Presses, designed_rows, find_presses, test_session_rows
from anytip.data.seeds import FACTOR_TEST_PATCHES, TEST_PATCHES, VALIDATION_ROWS, stream_seed
from anytip.data.splits import UnitSplit, held_out_patches, split_units
from anytip.errors import AnytipError
from anytip.models.io import LoadedShared
from anytip.models.mlp import BatchedMLP
from anytip.models.scaler import Scaler
from anytip.train.adapt import AdapterRecipe, SharedFit, calibrate_and_fold, input_stats
from anytip.train.adapter_prior import AdapterPrior
from anytip.train.data import FleetBatchData, UnitTensors, pad_rows, split_validation, unit_tensors
from anytip.train.episodic import PressIndex
from anytip.train.metrics import predict


@dataclass
class EvalUnit:
    """A validation, held-out or factor unit: its test rows, its calibration stream, the whole
    presses of the stream's runs outside its test patches (what a plan may select) and those of
    its designed calibrations' runs (what the `designed` strategy's plan takes). `test_cells`:
    the global patch ids of its test patches, which no calibration or reference of it reads in any
    run; its test rows are its main rows there, or, where it has a test session (`retest`), that
    session's rows there alone (`Roles.test_rows`: or both sessions' rows there)."""

    unit: str
    test_rows: np.ndarray
    stream: CalibrationStream
    presses: Presses
    designed: Presses
    test_cells: np.ndarray

    def presses_for(self, strategy: str) -> Presses:
        """The presses a plan of `strategy` selects from."""
        return self.designed if strategy == "designed" else self.presses


@dataclass
class SeedData:
    split: UnitSplit
    train: FleetBatchData  # training units' rows, 10% random rows for model selection
    train_stats: Scaler  # (U_train, 1, C) label-free input statistics
    evals: dict[str, EvalUnit]  # validation, held-out and factor units
    n_extra: int = 0  # training units from another registry, after the split's own in `train`
    train_presses: list[np.ndarray] | None = None  # each training unit's press of every fitting row

    def press_index(self) -> PressIndex:
        """The training units' fitting rows grouped by press (episodic training)."""
        if self.train_presses is None:
            raise AnytipError("these training tensors were prepared without their presses")
        return PressIndex.from_ids(self.train_presses, self.train.X_train.shape[1], self.train.device)


@dataclass(frozen=True)
class Roles:
    """How many units of each role, and the row fractions: what `prepare_seed` needs of a spec."""

    n_val_units: int
    n_test_units: int
    n_train_units: int | None
    patch_test_fraction: float
    val_fraction: float
    unit_folds: int | None = None  # held-out units as rotating folds (data.splits.split_units)
    unlabeled_s: float | None = None  # seconds of each stream whose pressures set input statistics
    n_factor_units: int = 0  # units that learn intervals' width alone (data.splits.split_units)
    test_rows: str = "test_session"  # or "all_sessions" (config.SplitConfig.test_rows, `unit_test_rows`)


def prepare_seed(arrays: FleetArrays, roles: Roles, calibration_protocol: str | None,
                 interleave: bool, seed: int, device: torch.device | str = "cpu",
                 extra: FleetArrays | None = None) -> SeedData:
    """Unit roles, test patches of validation, held-out and factor units, training tensors.

    Validation and held-out units draw their test patches by their place in that order; factor units
    by their place among the factor units (`seeds.FACTOR_TEST_PATCHES`), so what they learn does not
    change with how many units a fold holds out.

    `extra`: units of another registry that only train (same channels and targets, no unit
    in common); their tensors follow the split's training units in `train`."""
    split = split_units(arrays.units, seed, max(roles.n_val_units, 1), max(roles.n_test_units, 1),
                        roles.n_train_units, roles.unit_folds, roles.n_factor_units)
    main, designed, session = (main_rows(arrays, calibration_protocol), designed_rows(arrays),
                               test_session_rows(arrays))
    # The fingertip's test patches are places, which a designed plan leaves out too; a design without
    # that grid holds out blocks of time within its main runs, and a designed run's block k is not near them.
    places = has_patch_grid(arrays.layout)
    evals = {}
    draws = [*(stream_seed(TEST_PATCHES, seed, k) for k in range(len(split.val) + len(split.test))),
             *(stream_seed(FACTOR_TEST_PATCHES, seed, i) for i in range(len(split.factor)))]
    for unit, draw in zip([*split.val, *split.test, *split.factor], draws, strict=True):
        mine = np.flatnonzero(arrays.unit == arrays.units.index(unit))
        own = unit_main_rows(arrays, unit, main)
        held = held_out_patches(arrays.patch[own], roles.patch_test_fraction, draw)
        test_cells = np.unique(arrays.patch[own][held])
        exclude = np.zeros(arrays.n_rows, bool)
        exclude[mine] = np.isin(arrays.patch[mine], test_cells)
        stream = calibration_stream(arrays, unit, calibration_protocol, exclude, interleave)
        test = unit_test_rows(own, mine[session[mine]], exclude, roles.test_rows)
        selectable = find_presses(arrays, unit, exclude | stream.outside(arrays))
        own_designed = find_presses(arrays, unit, (exclude if places else np.zeros_like(exclude)) | ~designed)
        evals[unit] = EvalUnit(unit, test, stream, selectable, own_designed, test_cells)
    members, stats, presses = training_units(arrays, split.train, roles, calibration_protocol, interleave,
                                             seed)
    if extra is not None:
        more = training_units(extra, extra.units, roles, calibration_protocol, interleave, seed,
                              first_index=len(split.train))
        members, stats, presses = members + more[0], stats + more[1], presses + more[2]
    train = FleetBatchData.from_units(members, device, arrays.output_names)
    return SeedData(split, train, input_stats(stats, device), evals, 0 if extra is None else len(extra.units),
                    presses if len(presses) == len(members) else None)


def unit_test_rows(own: np.ndarray, session: np.ndarray, at: np.ndarray, which: str) -> np.ndarray:
    """A unit's test rows: of its main rows `own` and its test session's rows `session` (row indices),
    those at its test patches (`at`, (N,) bool over every row): the session's where it has one, else
    the main rows' (`which` "test_session"); or both, main rows first ("all_sessions")."""
    main, retest = own[at[own]], session[at[session]]
    if which == "all_sessions":
        return np.concatenate([main, retest])
    if which != "test_session":
        raise ValueError(f"test rows {which!r}: test_session or all_sessions")
    return retest if len(retest) else main


def training_units(arrays: FleetArrays, units: Sequence[str], roles: Roles, calibration_protocol: str | None,
                   interleave: bool, seed: int, first_index: int = 0
                   ) -> tuple[list[UnitTensors], list[torch.Tensor], list[np.ndarray]]:
    """Each training unit's tensors (main rows, a random `val_fraction` for model selection),
    its unlabeled pressures for input statistics, (n, C), and the press of each fitting row
    (n_fit,) (an index into its `find_presses`; none where the rows have no times)."""
    main = main_rows(arrays, calibration_protocol)
    members, stats, presses = [], [], []
    press_of = np.full(arrays.n_rows, -1, np.int64)
    for u, unit in enumerate(units, start=first_index):
        mine = unit_main_rows(arrays, unit, main)
        rng = np.random.default_rng(stream_seed(VALIDATION_ROWS, seed, u))
        fit, val = split_validation(mine, roles.val_fraction, rng)
        members.append(unit_tensors(arrays, fit, val, unit))
        stream = calibration_stream(arrays, unit, calibration_protocol, interleave=interleave)
        stats.append(torch.from_numpy(arrays.pressure[stream.unlabeled(roles.unlabeled_s)]))
        if arrays.time is not None:  # rows without times have no presses (and no episodes)
            found = find_presses(arrays, unit)
            press_of[found.rows] = np.repeat(np.arange(len(found)), np.diff(found.start))
            presses.append(press_of[fit].copy())
    return members, stats, presses


def main_rows(arrays: FleetArrays, calibration_protocol: str | None) -> np.ndarray:
    """(N,) bool: rows of runs other than the calibration protocol's, a designed calibration's and
    a test session's (what units are trained and tested on; a unit with a test session is tested on
    that alone)."""
    calib_runs = [k for k, r in enumerate(arrays.runs)
                  if calibration_protocol is not None and r.protocol == calibration_protocol]
    return ~np.isin(arrays.run, calib_runs) & ~designed_rows(arrays) & ~test_session_rows(arrays)


def unit_main_rows(arrays: FleetArrays, unit: str, main: np.ndarray) -> np.ndarray:
    """Row indices a unit is trained and tested on: its main rows, or all its rows when it
    has only calibration-protocol runs (test patches then come out of those runs)."""
    mine = np.flatnonzero(arrays.unit == arrays.units.index(unit))
    own = mine[main[mine]]
    return own if len(own) else mine


def predict_rows(model: BatchedMLP, in_scaler: Scaler, out_scaler: Scaler, arrays: FleetArrays,
                 rows: list[np.ndarray]) -> list[np.ndarray]:
    """Model m's physical predictions on arrays rows[m]: [(n_m, d), ...]."""
    device = in_scaler.mean.device
    X, n = pad_rows([arrays.pressure[r] for r in rows], device)
    pred = predict(model.to(device), in_scaler, out_scaler.to(device), X).cpu().numpy()
    return [pred[m, : int(n[m])] for m in range(len(rows))]


def calibrate_many(shared: SharedFit, arrays: FleetArrays, unlabeled_rows: list[np.ndarray],
                   plans: list[Plan], priors: list[float], recipe: AdapterRecipe,
                   seed: int, fit_kind: str | None = None,
                   adapter_prior: AdapterPrior | None = None) -> tuple[BatchedMLP, Scaler]:
    """Fit and fold one adapter per (unit, plan, prior) job: its input statistics from the
    unit's unlabeled rows (its whole stream's pressures), its adapter from the plan's rows, the
    prior scaled by the plan's effective sample count."""
    unlabeled = [torch.from_numpy(arrays.pressure[r]) for r in unlabeled_rows]
    X = [torch.from_numpy(arrays.pressure[p.rows]) for p in plans]
    Y = [torch.from_numpy(arrays.targets[p.rows]) for p in plans]
    return calibrate_and_fold(shared, unlabeled, X, Y, [len(p.rows) for p in plans], priors, recipe, seed,
                              fit_kind, [p.n_effective for p in plans], adapter_prior)


OWN_CHECK_FOLDS = 5  # a plan's presses are dealt into 5 folds for the calibration's own check


def own_check_losses(shared: SharedFit | LoadedShared, arrays: FleetArrays, unlabeled_rows: list[np.ndarray],
                     plans: list[Plan], priors: list[float], recipe: AdapterRecipe, seed: int,
                     fit_kind: str | None = None, adapter_prior: AdapterPrior | None = None,
                     folds: int = OWN_CHECK_FOLDS) -> list[float | None]:
    """Each job's calibration checked on its own data: every press of the plan predicted by the
    adapter refitted without its fold (`plan_residuals`; min(folds, presses) folds), scored as
    standardised MSE over all the plan's rows and outputs (the benchmark's validation loss).
    None for a plan of fewer than 2 presses. The same statistic on the benchmark's validation
    units is what a new unit's check is compared with (`anytip calibrate`)."""
    resid = plan_residuals(shared, arrays, unlabeled_rows, plans, priors, recipe, seed, fit_kind,
                           adapter_prior, folds, fewer=True)
    return [own_check_loss(r, shared.out_scaler) for r in resid]


def own_check_loss(residuals: np.ndarray | None, out_scaler: Scaler) -> float | None:
    """The own check of out-of-fold residuals (n, D): their standardised MSE (None for None)."""
    if residuals is None:
        return None
    return float(((residuals / out_scaler.std.reshape(-1).cpu().numpy()) ** 2).mean())


def plan_residuals(shared: SharedFit | LoadedShared, arrays: FleetArrays, unlabeled_rows: list[np.ndarray],
                   plans: list[Plan], priors: list[float], recipe: AdapterRecipe, seed: int,
                   fit_kind: str | None = None, adapter_prior: AdapterPrior | None = None,
                   folds: int = OWN_CHECK_FOLDS, fewer: bool = False) -> list[np.ndarray | None]:
    """Out-of-fold residuals of each job's plan, cross-fitted by whole presses: the presses are
    dealt into `folds` folds (press k to fold k mod folds), each fold predicted by the adapter
    refitted without it (all folds of all jobs fitted as one batch). (n_j, D) target minus
    prediction in physical units over the plan's rows. A plan with fewer presses than `folds`
    gets None, or with `fewer` one fold per press (None below 2 presses)."""
    def n_folds(p: Plan) -> int:
        k = min(folds, p.presses) if fewer else folds
        return k if p.presses >= max(k, 2) else 0
    jobs = [(j, f) for j, p in enumerate(plans) for f in range(n_folds(p))]
    splits = [plans[j].split_presses(n_folds(plans[j]), f) for j, f in jobs]
    preds = refit_without(shared, arrays, [unlabeled_rows[j] for j, _ in jobs], [plans[j] for j, _ in jobs],
                          splits, [priors[j] for j, _ in jobs], recipe, seed, fit_kind, adapter_prior)
    parts: dict[int, list[np.ndarray]] = {}
    for (j, _), pred, (_, check) in zip(jobs, preds, splits, strict=True):
        parts.setdefault(j, []).append(arrays.targets[check] - pred)
    return [np.concatenate(parts[j]) if j in parts else None for j in range(len(plans))]


def refit_without(shared: SharedFit | LoadedShared, arrays: FleetArrays, unlabeled_rows: list[np.ndarray],
                  plans: list[Plan], splits: list[tuple[np.ndarray, np.ndarray]], priors: list[float],
                  recipe: AdapterRecipe, seed: int, fit_kind: str | None = None,
                  adapter_prior: AdapterPrior | None = None) -> list[np.ndarray | None]:
    """Each job's adapter fitted on its split's fitting rows only (the prior scaled by the
    share of the plan's rows kept), its physical predictions (n_check, D) on the check rows;
    None where a split has no check rows. One batch for all jobs."""
    live = [k for k, (_, check) in enumerate(splits) if len(check)]
    out: list[np.ndarray | None] = [None] * len(plans)
    if not live:
        return out
    X = [torch.from_numpy(arrays.pressure[splits[k][0]]) for k in live]
    Y = [torch.from_numpy(arrays.targets[splits[k][0]]) for k in live]
    folded, stats = calibrate_and_fold(
        shared, [torch.from_numpy(arrays.pressure[unlabeled_rows[k]]) for k in live], X, Y,
        [len(x) for x in X], [priors[k] for k in live], recipe, seed, fit_kind,
        [plans[k].n_effective * len(splits[k][0]) / len(plans[k].rows) for k in live], adapter_prior)
    preds = predict_rows(folded, stats, shared.out_scaler, arrays, [splits[k][1] for k in live])
    for k, pred in zip(live, preds, strict=True):
        out[k] = pred
    return out
