"""Research log entry 101 (exploratory, validation units only): how much of a new unit's response
misfit away from its plan could a smooth correction learnt on the plan's own residuals predict?

For every validation unit of a finished run's fold, its `cover_informative` plan at 120 s gives its
codes as `scripts/rescore_response.py` fits them; the plan's residuals about that response (Pa) are
regressed on the contact (targets standardised over the training units' rows) by a Gaussian
process's posterior mean (squared-exponential kernel of length LENGTH, noise-to-signal ratio RATIO,
on at most ROWS plan rows evenly spaced), and the RMS residual on the unit's test rows is printed
with and without that correction, per grid point, and with the codes fitted on the unit's whole
calibration instead (entry 87's oracle: how much of the test misfit better codes remove). No network
is trained. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry101/residual_probe.py RUN --registry REG \\
        --response-model FILE --out OUT.json [--set KEY=VALUE ...]
"""

from __future__ import annotations

import argparse
import itertools
import json
from dataclasses import replace
from pathlib import Path

import torch

from anytip.config import load_spec
from anytip.data.registry import Registry
from anytip.models.io import load_response
from anytip.pipelines.common import Context, load
from anytip.pipelines.cross_sensor import min_units, prepare
from anytip.pipelines.cross_sensor_options import parse_options
from anytip.pipelines.cross_sensor_response import labeled_jobs, registry_units
from anytip.train.adapt import pooled_scaler
from anytip.train.response import ResponseFit, evenly_spaced, fit_codes, respond

LENGTHS = (0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 1000.0)  # 1000: the kernel is constant, the correction an offset
RATIOS = (0.03, 0.1, 0.3, 1.0, 3.0, 10.0, 30.0)
ROWS = 1024
ORACLE_ROWS = 8192  # entry 87's rows of the whole calibration


def gp_mean(Yp: torch.Tensor, R: torch.Tensor, Yq: torch.Tensor, length: float, ratio: float) -> torch.Tensor:
    """(q, C): the posterior mean at Yq (q, D) of a zero-mean GP through residuals R (p, C) at Yp (p, D)."""
    K = torch.exp(-torch.cdist(Yp, Yp).pow(2) / (2 * length**2))
    alpha = torch.linalg.solve(K + ratio * torch.eye(len(Yp), dtype=K.dtype), R)
    return torch.exp(-torch.cdist(Yq, Yp).pow(2) / (2 * length**2)) @ alpha


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", type=Path)
    parser.add_argument("--registry", type=Path, required=True)
    parser.add_argument("--response-model", required=True)
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--set", dest="overrides", action="append", default=[])
    args = parser.parse_args()
    torch.set_num_threads(1)
    spec = load_spec(args.run / "config.yaml", [*args.overrides, "options.adapters=[]",
                                                  "options.extra_units=null", "options.budgets=[120]",
                                                  "options.plan_strategies=[cover_informative]"])
    registry = Registry(args.registry, create=False)
    ctx = Context(spec, registry, args.out.parent, torch.device("cpu"), False, {})
    opts = parse_options(ctx)
    arrays = load(ctx, min_units(ctx))
    (seed,) = spec.all_seeds
    sd = prepare(ctx, arrays, opts, seed)
    assert opts.response is not None
    recipe = opts.response.recipe()
    fit = ResponseFit.from_loaded(load_response(args.response_model.format(seed=seed)))
    fit = fit.with_code_prior(recipe.code_prior, registry_units(sd))
    jobs = labeled_jobs(sd, list(sd.split.val), opts, seed, fit, arrays)
    X = [torch.from_numpy(arrays.pressure[p.rows]) for _, _, p in jobs]
    Y = [torch.from_numpy(arrays.targets[p.rows]) for _, _, p in jobs]
    codes = fit_codes(fit, X, Y, [p.n_effective for _, _, p in jobs], recipe, seed)
    whole = [sd.evals[u].presses.rows for u, _, _ in jobs]  # entry 87's oracle: every calibration press
    oracle = fit_codes(fit, [torch.from_numpy(arrays.pressure[r]) for r in whole],
                       [torch.from_numpy(arrays.targets[r]) for r in whole],
                       [p.n_effective * len(r) / len(p.rows)
                        for (_, _, p), r in zip(jobs, whole, strict=True)],
                       replace(recipe, code_rows=ORACLE_ROWS), seed)
    scaler = pooled_scaler(sd.train.Y_train, sd.train.n_train)
    mu, sigma = scaler.mean.reshape(-1).double().cpu(), scaler.std.reshape(-1).double().cpu()
    out = {"run": str(args.run), "seed": seed, "output_names": list(arrays.output_names), "units": {}}
    for m, (u, _, _) in enumerate(jobs):
        test = sd.evals[u].test_rows
        Xt, Yt = torch.from_numpy(arrays.pressure[test]), torch.from_numpy(arrays.targets[test])
        Rp = (X[m] - respond(fit.model, Y[m], codes[m])).double()
        Rt = (Xt - respond(fit.model, Yt, codes[m])).double()
        take = evenly_spaced(len(Rp), ROWS)
        Yp, Yq = (Y[m][take].double() - mu) / sigma, (Yt.double() - mu) / sigma
        Ro = (Xt - respond(fit.model, Yt, oracle[m])).double()
        row = {"plan_rows": len(Rp), "plan_rms": Rp.pow(2).mean().sqrt().item(),
               "test_rms": Rt.pow(2).mean().sqrt().item(), "corrected": {},
               "oracle_test_rms": Ro.pow(2).mean().sqrt().item()}
        for length, ratio in itertools.product(LENGTHS, RATIOS):
            got = Rt - gp_mean(Yp, Rp[take], Yq, length, ratio)
            row["corrected"][f"{length:g}/{ratio:g}"] = got.pow(2).mean().sqrt().item()
        out["units"][u] = row
        best = min(row["corrected"].items(), key=lambda kv: kv[1])
        print(f"{u}: plan {row['plan_rms']:.1f} Pa, test {row['test_rms']:.1f} Pa, "
              f"oracle codes {row['oracle_test_rms']:.1f} Pa, "
              f"best {best[0]} {best[1]:.1f} Pa", flush=True)
    args.out.write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
