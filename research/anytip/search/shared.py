"""Shared cross-sensor candidates: one network over the training units with per-unit adapters,
scored on other units after fitting their adapters on a calibration budget.

Units are dealt by the seed into training, search and test units (train/shared_split.py's
`prepare_seed`): every search or test unit loses whole patches to testing, and its calibration
budget is the first `calib_samples` rows of its calibration stream (the short protocol), with
those patches removed. A candidate's shared network and the training units' adapters are
trained together (train/adapt.py); a new unit's input statistics come from its whole stream's
pressures (no labels), its adapter from the budget. The adapted network is folded (adapter,
then input features) into a plain 8 -> ... -> 5 MLP, and that is what is scored on the unit's
held-out patches.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Any

import numpy as np
import torch

from anytip.data.arrays import FleetArrays
from anytip.data.calibration import calibration_stream
from anytip.models.features import fold_features
from anytip.models.mlp import MLPConfig
from anytip.search.fit import feature_tensor, map_fleet
from anytip.search.study import Candidate, SearchOptions
from anytip.train.adapt import AdapterRecipe, calibrate_and_fold, input_stats, train_shared
from anytip.train.data import FleetBatchData
from anytip.train.metrics import scores
from anytip.train.recipe import TrainRecipe
from anytip.train.shared_split import Roles, SeedData, predict_rows, prepare_seed


@dataclass
class SharedData:
    """The units' roles and tensors: `seed` data of cross_sensor, training rows capped, and
    the training units' unlabeled calibration pressures [(n_u, 8), ...] Pa."""

    sd: SeedData
    train_unlabeled: list[torch.Tensor]

    @property
    def train_units(self) -> list[str]:
        return list(self.sd.split.train)

    @property
    def search_units(self) -> list[str]:
        return list(self.sd.split.val)

    @property
    def test_units(self) -> list[str]:
        return list(self.sd.split.test)


def prepare_shared(arrays: FleetArrays, opts: SearchOptions, splits: Any, seed: int,
                   device: torch.device) -> SharedData:
    """Deal units (n_search_units as validation units, n_test_units held out) and build tensors;
    `splits` gives the row fractions (the spec's `splits`)."""
    roles = Roles(opts.n_search_units, opts.n_test_units, opts.n_train_units, splits.patch_test_fraction,
                  splits.val_fraction, test_rows=splits.test_rows)
    sd = prepare_seed(arrays, roles, opts.calibration_protocol, False, seed, device)
    if opts.max_train_rows is not None:
        sd.train = cap_rows(sd.train, opts.max_train_rows, seed)
    streams = [calibration_stream(arrays, u, opts.calibration_protocol) for u in sd.split.train]
    unlabeled = [torch.from_numpy(arrays.pressure[s.rows]) for s in streams]
    return SharedData(sd, unlabeled)


def cap_rows(data: FleetBatchData, max_rows: int, seed: int) -> FleetBatchData:
    """At most `max_rows` training rows per unit, drawn at random (seeded); validation rows
    are capped to the same fraction."""
    rng = np.random.default_rng(seed)
    units = []
    for u in range(data.n_units):
        t = data.unit(u)
        keep = rng.permutation(len(t.X_train))[:max_rows]
        n_val = max(1, int(round(len(t.X_val) * min(1.0, max_rows / len(t.X_train)))))
        val = rng.permutation(len(t.X_val))[:n_val]
        units.append(dataclasses.replace(t, X_train=t.X_train[keep], Y_train=t.Y_train[keep],
                                         X_val=t.X_val[val], Y_val=t.Y_val[val]))
    return FleetBatchData.from_units(units, data.device, data.output_names)


def shared_scorer(arrays: FleetArrays, data: SharedData, opts: SearchOptions, units: list[str], seed: int,
                  device: torch.device):
    """fit_and_score(candidate, recipe) -> one score row per unit of `units` (search units in
    the study, test units afterwards): held-out-patch RMSE of its folded, calibrated network."""
    adapter_recipe = AdapterRecipe(opts.adapter_steps, opts.adapter_lr)

    def fit_and_score(cand: Candidate, recipe: TrainRecipe) -> list[dict[str, Any]]:
        F = feature_tensor(cand.features, cand.sizes[0])
        stats = input_stats([p @ F for p in data.train_unlabeled], device)
        config = MLPConfig(sizes=(F.shape[1], *cand.sizes[1:]), activation=cand.activation)
        shared = train_shared(map_fleet(data.sd.train, F), stats, config, cand.adapter or "none", recipe,
                              seed, device, False, opts.adapter_decay)
        streams = [data.sd.evals[u].stream for u in units]
        budget_rows = [s.first(opts.calib_samples) for s in streams]
        raw_unlabeled = [torch.from_numpy(arrays.pressure[s.rows]) for s in streams]
        X = [torch.from_numpy(arrays.pressure[r]) @ F for r in budget_rows]
        Y = [torch.from_numpy(arrays.targets[r]) for r in budget_rows]
        folded, unit_stats = calibrate_and_fold(shared, [p @ F for p in raw_unlabeled], X, Y,
                                                [len(r) for r in budget_rows], [opts.prior] * len(units),
                                                adapter_recipe, seed)
        if cand.features != "raw":
            folded, unit_stats = fold_features(folded, unit_stats, F, input_stats(raw_unlabeled, device))
        test_rows = [data.sd.evals[u].test_rows for u in units]
        preds = predict_rows(folded, unit_stats, shared.out_scaler, arrays, test_rows)
        return [{"unit": u, "calib_samples": len(r), **scores(p, arrays.targets[t], arrays.layout)}
                for u, r, p, t in zip(units, budget_rows, preds, test_rows, strict=True)]

    return fit_and_score
