"""What bounds response transfer: the response model's misfit of the training units, of the new
unit, or neither (research log entry 25).

A transferred row is x_t + G(y; z_u) - G(y; z_t). Where the response model G misfits, the row
errs by r_u(y) - r_t(y): the new unit's misfit, shared by every row it gets, less the training
unit's. This script re-runs a finished run's response transfer at one budget with each misfit
removed in turn by a per-unit residual network (contact labels -> the unit's pressure residual
about G, fitted on the unit's rows), on the run's own response model, plans and references:

- `plan`: the method as it is (codes from the plan);
- `source`: the training units' misfit removed (their residual networks, fitted on their own
  fitting rows, added to G(y; z_t));
- `oracle`: the new unit's misfit removed, with knowledge no calibration has: codes and a residual
  network fitted on the unit's whole calibration outside its test patches;
- `both`: `source` and `oracle` together;
- `plan_residual`: the new unit's misfit estimated from its plan alone (a residual network fitted
  on the plan's presses, early-stopped on held-out presses), with `source`.

    python scripts/transfer_bounds.py reports/cross_sensor_response/seed0 --registry data/fleet24 \\
        --budget 120 --out reports/transfer_bounds/fleet24_seed0.json

Prints and writes, per arm, the validation units' mean standardised MSE and the held-out units'
force / angle ratio to their references, with each unit's test-patch pressure residual (Pa).
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
from torch import Tensor

from anytip.config import load_spec
from anytip.data.arrays import FleetArrays
from anytip.data.plans import Budget, Plan
from anytip.data.registry import Registry
from anytip.errors import AnytipError
from anytip.models.io import load_response
from anytip.models.mlp import MLPConfig
from anytip.models.scaler import Scaler
from anytip.pipelines.common import Context, load
from anytip.pipelines.cross_sensor import min_units, prepare
from anytip.pipelines.cross_sensor_jobs import mean_loss, plan_of, validation_losses
from anytip.pipelines.cross_sensor_options import Options, parse_options
from anytip.rundir import read_json
from anytip.train.data import FleetBatchData, UnitTensors
from anytip.train.fleet import FitResult, train_fleet
from anytip.train.metrics import predict, ratio_fields, scores
from anytip.train.recipe import FAST
from anytip.train.response import ResponseFit, SourceRows, fit_codes, respond, source_rows, unit_networks
from anytip.train.shared_split import SeedData, predict_rows

ARMS = ("plan", "source", "oracle", "both", "plan_residual")
RESIDUAL_SHAPE = (64, 64)
RESIDUAL_RECIPE = FAST.model_copy(update={"epochs": 10, "batch_size": 1024, "lr": 3e-3})


def residual_nets(fit: ResponseFit, rows: list[tuple[Tensor, Tensor, Tensor, Tensor]], codes: Tensor,
                  seed: int, epochs: int = 10, patience: int | None = None) -> FitResult:
    """One residual network per unit k: labels (n, D) -> its pressure residual (n, C) Pa about
    G(y; codes[k]), trained on rows[k] = (X_fit, Y_fit, X_val, Y_val), kept at its best
    validation loss."""
    members = []
    for k, (xf, yf, xv, yv) in enumerate(rows):
        rf = xf - respond(fit.model, yf, codes[k])
        rv = xv - respond(fit.model, yv, codes[k])
        members.append(UnitTensors(yf, rf, yv, rv, str(k)))
    data = FleetBatchData.from_units(members, fit.device, [f"c{c}" for c in range(rows[0][0].shape[1])])
    D, C = rows[0][1].shape[1], rows[0][0].shape[1]
    shape = MLPConfig(sizes=(D, *RESIDUAL_SHAPE, C), activation="silu")
    recipe = RESIDUAL_RECIPE.model_copy(update={"patience": patience, "epochs": epochs})
    return train_fleet(data, shape, recipe, seed=seed, device=fit.device)


def residual_of(nets: FitResult, k: int, labels: Tensor) -> Tensor:
    """(n, C) Pa: residual network k's output for labels (n, D)."""
    in_scaler, out_scaler = nets.in_scaler.slice(k), nets.out_scaler.slice(k)
    return predict(nets.model.model_slice(k), in_scaler, out_scaler, labels[None])[0]


def split_rows(X: Tensor, Y: Tensor, val: np.ndarray) -> tuple[Tensor, Tensor, Tensor, Tensor]:
    fit = ~val
    return X[fit], Y[fit], X[val], Y[val]


@dataclass
class NewUnits:
    """The validation and held-out units of a seed: their plans' rows and whole calibrations' rows
    (tensors), and their codes fitted on each."""

    units: list[str]
    plans: list[Plan]
    plan_rows: list[tuple[Tensor, Tensor]]
    whole_rows: list[tuple[Tensor, Tensor]]
    codes_plan: Tensor
    codes_whole: Tensor


def new_units(fit: ResponseFit, sd: SeedData, arrays: FleetArrays, opts: Options, budget: Budget,
              seed: int) -> NewUnits:
    recipe = opts.response.recipe()
    units = [*sd.split.val, *sd.split.test]
    plans = [plan_of(sd, u, budget, opts, seed) for u in units]
    plan_rows = [rows_of(arrays, p.rows) for p in plans]
    whole = [sd.evals[u].presses.rows for u in units]
    whole_rows = [rows_of(arrays, r) for r in whole]
    codes_plan = fit_codes(fit, *zip(*plan_rows, strict=True), [p.n_effective for p in plans], recipe, seed)
    # the whole calibration counts its rows at the benchmark's effective rate (10 Hz of 200 Hz rows)
    codes_whole = fit_codes(fit, *zip(*whole_rows, strict=True), [len(r) / 20.0 for r in whole], recipe, seed)
    return NewUnits(units, plans, plan_rows, whole_rows, codes_plan, codes_whole)


def rows_of(arrays: FleetArrays, rows: np.ndarray) -> tuple[Tensor, Tensor]:
    return torch.from_numpy(arrays.pressure[rows]), torch.from_numpy(arrays.targets[rows])


class Responses:
    """Each arm's view of a new unit's response and of the training units' own responses."""

    def __init__(self, fit: ResponseFit, sd: SeedData, arrays: FleetArrays, new: NewUnits, source: SourceRows,
                 arms: list[str], seed: int):
        self.fit, self.new, self.source = fit, new, source
        self.source_fitted = {False: source.fitted}
        if {"source", "both", "plan_residual"} & set(arms):
            train = [sd.train.unit(k) for k in range(sd.train.n_units)]
            index = [fit.unit_ids.index(r.unit_id) for r in train]  # the model's unit of each
            nets = residual_nets(fit, [(r.X_train, r.Y_train, r.X_val, r.Y_val) for r in train],
                                 fit.model.codes.detach()[index], seed)
            per_unit = [residual_of(nets, index.index(u), source.Y[source.unit == u])
                        for u in source.unit.unique(sorted=True).tolist()]
            self.source_fitted[True] = source.fitted + torch.cat(per_unit)
        if {"oracle", "both"} & set(arms):
            g = np.random.default_rng(seed)
            rows = [split_rows(x, y, g.random(len(x)) < 0.1) for x, y in new.whole_rows]
            self.whole_nets = residual_nets(fit, rows, new.codes_whole, seed)
        if "plan_residual" in arms:  # early-stopped on every 5th press of the plan, from its 3rd
            rows = [(*rows_of(arrays, fit_rows), *rows_of(arrays, check_rows))
                    for fit_rows, check_rows in (p.split_presses(5, 2) for p in new.plans)]
            self.plan_nets = residual_nets(fit, rows, new.codes_plan, seed, epochs=300, patience=20)

    def unit(self, arm: str, m: int, labels: Tensor) -> Tensor:
        """(n, C) Pa: new unit m's response to labels (n, D) as `arm` knows it."""
        whole = arm in ("oracle", "both")
        out = respond(self.fit.model, labels, (self.new.codes_whole if whole else self.new.codes_plan)[m])
        if whole:
            out = out + residual_of(self.whole_nets, m, labels)
        if arm == "plan_residual":
            out = out + residual_of(self.plan_nets, m, labels)
        return out

    def transferred(self, arm: str, m: int) -> Tensor:
        """(S, C) Pa: the source rows carried over to new unit m as `arm` does it."""
        fitted = self.source_fitted[arm in ("source", "both", "plan_residual")]
        return self.source.X + self.unit(arm, m, self.source.Y) - fitted


def run_seed(ctx: Context, arrays: FleetArrays, opts: Options, run: Path, seed: int, budget: Budget,
             arms: list[str], response: str | None = None) -> list[dict]:
    """Rows (unit, arm) of one seed: scores on the unit's test patches, its force and angle ratio to
    its reference (held-out units), its test-patch pressure residual about the arm's response."""
    sd = prepare(ctx, arrays, opts, seed)
    saved = load_response(Path(response.format(seed=seed)) if response else
                          run / "models" / f"response_seed{seed}.safetensors")
    fit, recipe = ResponseFit.from_loaded(saved), opts.response.recipe()
    new = new_units(fit, sd, arrays, opts, budget, seed)
    views = Responses(fit, sd, arrays, new, source_rows(fit, sd.train, recipe.source_rows, seed), arms, seed)
    jobs = [(u, arm, m) for m, u in enumerate(new.units) for arm in arms]
    rows = ((torch.cat([views.transferred(arm, m), new.plan_rows[m][0]]),
             torch.cat([views.source.Y, new.plan_rows[m][1]])) for _, arm, m in jobs)
    nets = unit_networks(rows, ctx.spec.model, recipe, seed, [f"{u}/{a}" for u, a, _ in jobs],
                         arrays.output_names)
    preds = predict_rows(nets.model, nets.in_scaler, nets.out_scaler, arrays,
                         [sd.evals[u].test_rows for u, _, _ in jobs])
    refs = {r["unit"]: r for r in read_json(run / "metrics.json")["results"]
            if r["method"] == "per_unit" and r["seed"] == seed}
    val = validation_losses([(u, budget, float(ARMS.index(a))) for u, a, _ in jobs], preds, sd, arrays,
                            set(sd.split.val), Scaler.pooled(sd.train.Y_train, sd.train.n_train))
    out = []
    for (u, arm, m), pred in zip(jobs, preds, strict=True):
        Xt, Yt = rows_of(arrays, sd.evals[u].test_rows)
        row = {"seed": seed, "unit": u, "arm": arm, "role": "val" if u in sd.split.val else "test",
               "test_residual_pa": float((Xt - views.unit(arm, m, Yt)).pow(2).mean().sqrt()),
               **scores(pred, Yt.numpy(), arrays.layout)}
        if u in refs:
            row |= ratio_fields(row, refs[u], arrays.layout)
        else:
            row["val_loss_mean"] = mean_loss(val[(budget, float(ARMS.index(arm)))])
        out.append(row)
    for arm in arms:
        print(f"seed {seed} {arm:>14}: {summary(out, arm)}", flush=True)
    return out


def summary(rows: list[dict], arm: str) -> str:
    """One line of an arm's figures: validation loss, held-out ratios, test-patch residual."""
    mine = [r for r in rows if r["arm"] == arm]
    held = [r for r in mine if r["role"] == "test"]
    val = [r["val_loss_mean"] for r in mine if r["role"] == "val"]
    ratios = [k for k in held[0] if k.endswith("_ratio")] if held else []
    said = "  ".join(f"{k.removesuffix('_ratio')} {np.mean([r[k] for r in held]):.2f}x" for k in ratios)
    return (f"val loss {np.mean(val):.4f}  held-out {said}  test residual "
            f"{np.mean([r['test_residual_pa'] for r in mine]):.0f} Pa")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="a finished cross_sensor run with options.response")
    parser.add_argument("--registry", type=Path, required=True)
    parser.add_argument("--budget", type=float, default=120.0, help="robot seconds")
    parser.add_argument("--arms", default=",".join(ARMS))
    parser.add_argument("--out", type=Path, required=True, help="a JSON file for the rows")
    parser.add_argument("--response-model", help="another response model file of the run's training units "
                        "({seed} is replaced by the seed)")
    args = parser.parse_args(argv)
    torch.set_num_threads(1)
    try:
        spec = load_spec(args.run / "config.yaml", ["options.adapters=[]"])
        ctx = Context(spec, Registry(args.registry, create=False), args.out.parent, torch.device("cpu"),
                      False, {"spec_file": str(args.run / "config.yaml")})
        opts = parse_options(ctx)
        arrays = load(ctx, min_units(ctx))
        budget = Budget(args.budget, "seconds", opts.plan_strategies[0])
        rows = []
        for seed in spec.all_seeds:
            rows += run_seed(ctx, arrays, opts, args.run, seed, budget, args.arms.split(","),
                             args.response_model)
    except AnytipError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps({"run": str(args.run), "budget_s": args.budget, "rows": rows}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
