"""A new unit's codes without labels: what its unlabeled stream tells response transfer (research
log entry 27).

Zero-shot calibration may read a new unit's pressures in ordinary use (the first `--seconds` of its
stream, labels unread). Response transfer needs the unit's codes. Without labels, each unlabeled
row's contact is unknown too, so the codes and every row's contact are fitted together: the MAP of

    sum_i w |x_i - G(c_i; z)|^2_W / 2 + w lam |c_i - c0_i|^2 / 2 + |z|^2_{1/code_var} / 2

(W the training units' residual precision per barometer, w = n_eff / n, c0_i the start network's
contact in standardised labels, lam a weak pull towards it), by Levenberg-Marquardt on the codes'
Schur complement (each row's contact eliminated), as bundle adjustment solves cameras and points.
Arms, each scored by a network trained on the transferred rows alone (no labeled row of the unit)
from the run's pooled start network:

- `pooled`: the start network itself (the training units' rows as measured): no transfer;
- `zero`: codes zero (the fleet's typical unit);
- `joint`: the label-free fit above;
- `stream_labels`: codes fitted on the same rows with their labels (no label-free method has them):
  the most those seconds of pressures could tell the codes;
- `plan`: codes fitted on the labeled rows of the run's plan of `--plan-seconds` robot-seconds (the
  run's own strategy), for comparison: the labeled method without the unit's rows in its network.

    python scripts/label_free_codes.py reports/cross_sensor_response_start/fleet24_seed1 \\
        --registry data/fleet24 --out reports/cross_sensor_label_free_codes/fleet24_seed1.json

Per unit and arm: the test-patch pressure residual about the arm's response (Pa) and, for held-out
units, the force and angle ratio to the run's reference; per unit, the joint objective's data term
per row at the joint fit and at the truth (stream_labels codes, true contacts), which separates
an optimiser that stops short (truth lower) from data that do not pin the codes down (fit lower).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np
import torch
from torch import Tensor

from anytip.config import load_spec
from anytip.data.plans import Budget
from anytip.data.registry import Registry
from anytip.errors import AnytipError
from anytip.models.io import load_models, load_response
from anytip.models.response import ResponseModel
from anytip.pipelines.common import Context, load
from anytip.pipelines.cross_sensor import min_units, prepare
from anytip.pipelines.cross_sensor_jobs import plan_of
from anytip.pipelines.cross_sensor_options import parse_options
from anytip.rundir import read_json
from anytip.train.metrics import scores
from anytip.train.response import (
    ResponseFit,
    ResponseRecipe,
    code_jacobian,
    evenly_spaced,
    fit_codes,
    residual_rms,
    source_rows,
    start_network_path,
    transfer,
    unit_networks,
)
from anytip.train.shared_split import predict_rows

ARMS = ("pooled", "zero", "joint", "stream_labels", "plan")


def jacobians(model: ResponseModel, c: Tensor, codes: Tensor) -> tuple[Tensor, Tensor, Tensor]:
    """At standardised contacts c (n, D) and codes (C, k): the pressures (n, C) Pa, their Jacobian
    in c (n, C, D) and in each barometer's own code (n, C, k)."""
    mean, std = model.label_mean, model.label_std
    Jc = torch.func.vmap(torch.func.jacfwd(lambda ci: model(ci * std + mean, codes)))(c)
    pred, Jz = code_jacobian(model, c * std + mean, codes)
    return pred, Jc.detach(), Jz


def joint_fit(fit: ResponseFit, X: Tensor, Y0: Tensor, n_eff: float, iterations: int = 30,
              lam: float = 1.0) -> tuple[Tensor, Tensor, list[float]]:
    """Codes (C, k) and contacts (n, D) of unlabeled pressures X (n, C) Pa from contacts Y0 (n, D),
    by damped Gauss-Newton on the joint MAP (module docstring); the objective after each step."""
    model = fit.model
    for p in model.parameters():
        p.requires_grad_(False)
    mean, std = model.label_mean, model.label_std
    (n, C), k, D = X.shape, fit.code_var.shape[0], Y0.shape[1]
    w = n_eff / n
    Wc, inv_spread = w / fit.noise_var, 1 / fit.code_var
    c0 = (Y0 - mean) / std
    c, z = c0.clone(), torch.zeros(C, k)

    def objective(cc: Tensor, zz: Tensor) -> float:
        with torch.no_grad():
            r = X - model(cc * std + mean, zz)
        data, pull = (r**2 * Wc).sum() / 2, w * lam * ((cc - c0) ** 2).sum() / 2
        return float(data + pull + (zz**2 * inv_spread).sum() / 2)

    obj, damping, trace = objective(c, z), 1e-2, []
    for _ in range(iterations):
        pred, Jc, Jz = jacobians(model, c, z)
        r = X - pred
        Hcc = torch.einsum("ncd,nce,c->nde", Jc, Jc, Wc) + w * lam * torch.eye(D)
        gc = torch.einsum("ncd,nc,c->nd", Jc, r, Wc) - w * lam * (c - c0)
        Hzz = torch.einsum("nck,ncj,c->ckj", Jz, Jz, Wc) + torch.diag_embed(inv_spread.expand(C, k))
        gz = torch.einsum("nck,nc,c->ck", Jz, r, Wc) - z * inv_spread
        A = torch.einsum("nck,ncd,c->nckd", Jz, Jc, Wc).reshape(n, C * k, D)  # codes-contact coupling
        Hzz = Hzz + damping * torch.diag_embed(torch.diagonal(Hzz, dim1=-2, dim2=-1))
        Hinv = torch.linalg.inv(Hcc + damping * torch.diag_embed(torch.diagonal(Hcc, dim1=-2, dim2=-1)))
        AH = A @ Hinv
        S = torch.block_diag(*Hzz) - torch.einsum("nad,nbd->ab", AH, A)  # contacts eliminated
        dz = torch.linalg.solve(S, gz.reshape(-1) - torch.einsum("nad,nd->a", AH, gc))
        dc = torch.einsum("nde,ne->nd", Hinv, gc - torch.einsum("nad,a->nd", A, dz))
        trial = objective(c + dc, z + dz.reshape(C, k))
        if trial < obj:
            c, z, obj, damping = c + dc, z + dz.reshape(C, k), trial, max(damping / 3, 1e-6)
        else:
            damping = min(damping * 4, 1e6)
        trace.append(obj)
    return z, c * std + mean, trace


def data_term(fit: ResponseFit, X: Tensor, Y: Tensor, codes: Tensor) -> float:
    """Mean over rows of sum_c (x_c - G_c(y; codes))^2 / noise_var_c."""
    with torch.no_grad():
        return float(((X - fit.model(Y, codes)) ** 2 / fit.noise_var).sum(-1).mean())


def run(run_dir: Path, registry: Path, seconds: float, rows: int, iterations: int,
        plan_seconds: float = 120.0) -> list[dict]:
    spec = load_spec(run_dir / "config.yaml", ["options.adapters=[]"])
    ctx = Context(spec, Registry(registry, create=False), run_dir, torch.device("cpu"), False, {})
    opts = parse_options(ctx)
    if opts.response is None:
        raise AnytipError(f"{run_dir}: its spec has no options.response")
    arrays = load(ctx, min_units(ctx))
    refs = {(r["seed"], r["unit"]): r for r in read_json(run_dir / "metrics.json")["results"]
            if r["method"] == "per_unit"}
    out = []
    for seed in spec.all_seeds:
        sd = prepare(ctx, arrays, opts, seed)  # the run's split; its extra units are not needed here
        recorded = read_json(run_dir / "provenance.json")["cross_sensor"][f"seed{seed}"]["units"]
        if sd.split.to_json() != recorded:
            raise AnytipError(f"seed {seed}: the split differs from the run's")
        path = run_dir / "models" / f"response_seed{seed}.safetensors"
        saved = load_response(path)
        fit, recipe = ResponseFit.from_loaded(saved), ResponseRecipe.from_saved(saved.meta["recipe"])
        start = load_models(start_network_path(path))
        n_eff = seconds * opts.rig.effective_hz
        units = [*sd.split.val, *sd.split.test]
        codes: dict[tuple[str, str], Tensor] = {}
        found: dict[str, dict] = {}
        for u in units:
            ev = sd.evals[u]
            stream = ev.stream.unlabeled(seconds)
            stream = stream[evenly_spaced(len(stream), rows).numpy()]
            X, Y = torch.from_numpy(arrays.pressure[stream]), torch.from_numpy(arrays.targets[stream])
            Y0 = torch.from_numpy(predict_rows(start.model, start.in_scaler, start.out_scaler, arrays,
                                               [stream])[0])
            zero = torch.zeros(fit.model.n_channels, fit.model.config.code_dim)
            labelled = fit_codes(fit, [X], [Y], [n_eff], recipe, seed)[0]
            joint, contacts, trace = joint_fit(fit, X, Y0, n_eff, iterations)
            plan = plan_of(sd, u, Budget(plan_seconds, "seconds", opts.plan_strategies[0]), opts, seed)
            Xp, Yp = torch.from_numpy(arrays.pressure[plan.rows]), torch.from_numpy(arrays.targets[plan.rows])
            planned = fit_codes(fit, [Xp], [Yp], [plan.n_effective], recipe, seed)[0]
            codes |= {(u, "zero"): zero, (u, "joint"): joint, (u, "stream_labels"): labelled,
                      (u, "plan"): planned}
            std = fit.model.label_std
            found[u] = {"unlabeled_rows": int(len(stream)), "data_term_truth": data_term(fit, X, Y, labelled),
                        "data_term_joint": data_term(fit, X, contacts, joint),
                        "data_term_start": data_term(fit, X, Y0, zero), "objective": trace,
                        "code_rms_truth": float(labelled.pow(2).mean().sqrt()),
                        "code_rms_joint_off_truth": float((joint - labelled).pow(2).mean().sqrt()),
                        "contact_error_start": float(((Y0 - Y) / std).pow(2).mean().sqrt()),
                        "contact_error_joint": float(((contacts - Y) / std).pow(2).mean().sqrt())}
            said = ", ".join(f"{k} {v:.3g}" for k, v in found[u].items() if k != "objective")
            print(f"seed {seed} {u}: {said}", flush=True)
        ids = [str(u) for u in saved.meta.get("source_unit_ids", [])]
        if not ids or not set(ids) <= set(sd.train.unit_ids):
            raise AnytipError(f"{path}: its source units are not the registry's training units of seed "
                              f"{seed} (a model that transfers extra units' rows)")
        source = source_rows(fit, sd.train.subset([sd.train.unit_ids.index(u) for u in ids]),
                             recipe.source_rows, seed)
        jobs = list(codes)
        nets = unit_networks(((transfer(fit, source, codes[j]), source.Y) for j in jobs), spec.model, recipe,
                             seed, [f"{u}/{a}" for u, a in jobs], arrays.output_names, start=start)
        preds = dict(zip(jobs, predict_rows(nets.model, nets.in_scaler, nets.out_scaler, arrays,
                                            [sd.evals[u].test_rows for u, _ in jobs]), strict=True))
        preds |= {(u, "pooled"): predict_rows(start.model, start.in_scaler, start.out_scaler, arrays,
                                              [sd.evals[u].test_rows])[0] for u in units}
        for u in units:
            test = sd.evals[u].test_rows
            Xt, Yt = torch.from_numpy(arrays.pressure[test]), torch.from_numpy(arrays.targets[test])
            for arm in ARMS:
                row = {"seed": seed, "unit": u, "arm": arm, "role": "val" if u in sd.split.val else "test",
                       **scores(preds[u, arm], Yt.numpy(), arrays.layout), **found[u]}
                if arm != "pooled":
                    rms = residual_rms(fit, Xt, Yt, codes[u, arm])
                    row["test_residual_pa"] = float((rms**2).mean() ** 0.5)
                if (seed, u) in refs:
                    row["force_ratio"] = row["force_rmse_n"] / refs[seed, u]["force_rmse_n"]
                    row["angle_ratio"] = row["angle_rmse_rad"] / refs[seed, u]["angle_rmse_rad"]
                out.append(row)
        for arm in ARMS:
            print(f"seed {seed} {arm:>14}: {summary(out, arm)}", flush=True)
    return out


def summary(rows: list[dict], arm: str) -> str:
    """The held-out units' mean force / angle ratio and every unit's mean test-patch residual."""
    mine = [r for r in rows if r["arm"] == arm]
    held = [r for r in mine if "force_ratio" in r]
    text = "no held-out unit"
    if held:
        text = (f"held-out force {np.mean([r['force_ratio'] for r in held]):.2f}x / angle "
                f"{np.mean([r['angle_ratio'] for r in held]):.2f}x ({len(held)} units)")
    if "test_residual_pa" in mine[0]:
        text += f"; test-patch residual {np.mean([r['test_residual_pa'] for r in mine]):.0f} Pa"
    return text


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path, help="a cross_sensor run with a pooled start")
    parser.add_argument("--registry", type=Path, required=True, help="the registry the run read")
    parser.add_argument("--out", type=Path, required=True, help="JSON file for the rows")
    parser.add_argument("--seconds", type=float, default=600.0, help="seconds of unlabeled stream read")
    parser.add_argument("--rows", type=int, default=4096, help="evenly spaced rows of them fitted")
    parser.add_argument("--iterations", type=int, default=30, help="damped Gauss-Newton steps")
    parser.add_argument("--plan-seconds", type=float, default=120.0, help="robot-seconds of the `plan` arm")
    args = parser.parse_args(argv)
    torch.set_num_threads(1)
    try:
        rows = run(args.run, args.registry, args.seconds, args.rows, args.iterations, args.plan_seconds)
    except AnytipError as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps({"run": str(args.run), "seconds": args.seconds, "rows": rows}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
