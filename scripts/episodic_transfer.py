"""Does what episodic training learnt on its training units carry over to new units?

For a finished cross_sensor run with `shared_training: [joint, episodic]` (budgets in robot
seconds), each shared model (joint and episodic) calibrates, at one budget, both

- the run's training units (the registry's own, not `extra_units`): a plan of whole presses
  selected from all their runs as for a new unit, scored on 20,000 of their other rows drawn at
  random (rows the shared weights trained on, so an in-sample figure for the shared weights);
- the held-out units: the benchmark's plans, scored on their test patches,

with each of the run's fits of that model (the prior the run chose for it, or the inner fit),
as the mean standardised MSE over units. Beside them, each training unit's own adapter (fitted
with the shared weights on all its rows) on the same rows: what the shared model can do for a
unit whose adapter is known, so the gap from it to a 120 s calibration is the cost of
estimating the adapter from that plan alone; and that adapter projected onto the mean and top-k
principal directions of the other training units' adapters (k = 4, 8; leave one out): whether
a unit's adapter lies in a few directions the fleet already knows, so that a few numbers fitted
from a short plan could find it. If episodic training lowers the training units'
figure much more than the held-out units', what it learnt does not transfer to new units
(too few training units to meta-learn from); if it lowers neither, the episodic objective
itself was not met.

    python scripts/episodic_transfer.py RUN_DIR --registry data/fleet24 [--budget 120] [--seeds 0]
"""

from __future__ import annotations

import copy
import json
from pathlib import Path
from typing import Any

import numpy as np
import torch

from anytip.config import load_spec
from anytip.data.calibration import calibration_stream
from anytip.data.plans import Budget, find_presses, select_presses
from anytip.data.registry import Registry
from anytip.models.adapted import AdaptedMLP
from anytip.models.io import load_shared
from anytip.pipelines.common import Context, load
from anytip.pipelines.cross_sensor import adapted_method, fit_methods, min_units, plan_of, prepare
from anytip.pipelines.cross_sensor_options import parse_options, training_tag
from anytip.pipelines.run_diagnostic import diagnose, diagnostic_parser
from anytip.report.cross_sensor import mean_interval
from anytip.train.adapter_prior import flat_adapters
from anytip.train.shared_split import calibrate_many, predict_rows

QUERY_ROWS = 20_000
SUBSPACE_RANKS = (4, 8)


def seed_losses(run: Path, registry: str, seed: int, amount: float, adapter: str) -> list[dict]:
    """One line per (training, fit, unit role): each unit's standardised MSE after calibration."""
    spec = load_spec(run / "config.yaml")
    prov = json.loads((run / "provenance.json").read_text())["cross_sensor"][f"seed{seed}"]
    ctx = Context(spec, Registry(Path(registry), create=False), run, torch.device("cpu"), False)
    opts = parse_options(ctx)
    arrays = load(ctx, min_units(ctx))
    sd = prepare(ctx, arrays, opts, seed)
    budget = Budget(amount, "seconds", "spread")
    rng = np.random.default_rng(seed)
    jobs = {}  # unit -> (plan, query rows, unlabeled rows)
    for unit in sd.split.train:
        presses = find_presses(arrays, unit)
        plan = select_presses(presses, amount, opts.rig.timing(), "spread", seed)
        rest = np.setdiff1d(np.flatnonzero(arrays.unit == arrays.units.index(unit)), plan.rows)
        query = np.sort(rng.choice(rest, min(QUERY_ROWS, len(rest)), replace=False))
        stream = calibration_stream(arrays, unit, opts.calibration_protocol)
        jobs[unit] = (plan, query, stream.unlabeled(opts.unlabeled_s))
    for unit in sd.split.test:
        ev = sd.evals[unit]
        plan = plan_of(sd, unit, budget, opts, seed)
        jobs[unit] = (plan, ev.test_rows, ev.stream.unlabeled(opts.unlabeled_s))
    units = list(jobs)
    out = []
    for training in opts.shared_training:
        tag = training_tag(training)
        shared = load_shared(run / "models" / f"shared_{adapter.replace('+', '-')}{tag.replace('~', '_')}"
                                              f"_seed{seed}.safetensors")
        own = [shared.meta["unit_ids"].index(u) for u in sd.split.train]
        preds = predict_rows(shared.model.fold(own), shared.in_scaler.take(own), shared.out_scaler, arrays,
                             [jobs[u][1] for u in sd.split.train])
        out += _losses(f"{adapter}{tag}: own adapter, all rows", seed, list(sd.split.train), preds, jobs,
                       arrays, shared, sd)
        for k in SUBSPACE_RANKS:
            model = projected(shared.model, own, k)
            preds = predict_rows(model.fold(own), shared.in_scaler.take(own), shared.out_scaler, arrays,
                                 [jobs[u][1] for u in sd.split.train])
            out += _losses(f"{adapter}{tag}: own adapter in the others' top-{k} subspace", seed,
                           list(sd.split.train), preds, jobs, arrays, shared, sd)
        rates = shared.meta.get("inner_lr")
        for family, fit in fit_methods(adapter, opts, training):
            if fit.inner and rates is None:
                continue  # a run saved before models recorded their step sizes
            method = (adapted_method(fit.kind(adapter), family) + tag + fit.suffix()).removeprefix("adapted:")
            prior = prov["priors_chosen"][method][budget.label]
            folded, stats = calibrate_many(shared, arrays, [jobs[u][2] for u in units],
                                           [jobs[u][0] for u in units], [prior] * len(units),
                                           fit.recipe(opts, rates), seed, None, None)
            preds = predict_rows(folded, stats, shared.out_scaler, arrays, [jobs[u][1] for u in units])
            out += _losses(method, seed, units, preds, jobs, arrays, shared, sd)
    return out


def projected(model: AdaptedMLP, units: list[int], k: int) -> AdaptedMLP:
    """A copy of a trained shared model whose adapter of each unit in `units` is replaced by its
    projection onto the mean and top-k principal directions of every other training unit's
    adapter (leave one out): how much of a unit lies where the fleet varies."""
    theta = flat_adapters(model).detach().double()
    out = copy.deepcopy(model)
    flat = theta.clone()
    for u in units:
        others = torch.cat([theta[:u], theta[u + 1:]])
        mean = others.mean(0)
        _, _, vt = torch.linalg.svd(others - mean, full_matrices=False)
        basis = vt[:k]
        flat[u] = mean + ((theta[u] - mean) @ basis.T) @ basis
    offset = 0
    with torch.no_grad():
        for p in out.adapter.values():
            n = p[0].numel()
            p.copy_(flat[:, offset:offset + n].reshape(p.shape).to(p.dtype))
            offset += n
    return out


def _losses(method: str, seed: int, units: list[str], preds: list[np.ndarray], jobs: dict, arrays: Any,
            shared: Any, sd: Any) -> list[dict]:
    std = shared.out_scaler.std.reshape(-1).cpu().numpy()
    out = []
    for u, pred in zip(units, preds, strict=True):
        err = (pred - arrays.targets[jobs[u][1]]) / std
        role = "training" if u in sd.split.train else "held-out"
        out.append({"method": method, "seed": seed, "unit": u, "role": role, "loss": float((err**2).mean())})
    return out


def table(lines: list[dict]) -> str:
    """Markdown: per method, the mean loss [95% interval over units] of each role, and their ratio."""
    head = "| method | training units (other rows) | held-out units (test patches) | held-out / training |"
    body = [head, "|---|---|---|---|"]
    for method in dict.fromkeys(r["method"] for r in lines):
        cells, means = [], []
        for role in ("training", "held-out"):
            mine = [r["loss"] for r in lines if r["method"] == method and r["role"] == role]
            m, lo, hi = mean_interval(mine) if mine else (float("nan"),) * 3
            cells.append(f"{m:.4f} [{lo:.4f}, {hi:.4f}]" if mine else "")
            means.append(m)
        ratio = f"{means[1] / means[0]:.2f}x" if np.isfinite(means[1]) else ""
        body.append(f"| `{method}` | {cells[0]} | {cells[1]} | {ratio} |")
    return "\n".join(body)


def main() -> None:
    a = diagnostic_parser(__doc__).parse_args()

    def render(seeds: list[int], lines: list[dict]) -> str:
        return (f"# Episodic training on training and held-out units: `{a.run.name}`, {a.adapter}, "
                f"{a.budget:g} s\n\nStandardised MSE after calibration, mean over units "
                f"[95% interval]; seeds {seeds}.\n\n{table(lines)}\n")

    diagnose(a, lambda s: seed_losses(a.run, a.registry, s, a.budget, a.adapter), render)

if __name__ == "__main__":
    main()
