"""Where a calibrated unit errs: on the presses it was calibrated on, or elsewhere.

For a finished cross_sensor run (budgets in robot seconds), each held-out unit of a seed is
calibrated again exactly as the benchmark did it (same shared model, plan, prior, prior family
and fit: the run's first method of that shared model), and
its force RMSE is split three ways, each over the unit's own per-unit reference on the same
rows:

- the plan's own rows (what the adapter was fitted on; the reference trained on them too);
- test patches in orientations the plan visited;
- test patches in orientations it did not visit (a re-mount the budget could not pay for),
  and these again split by where they lie: inside the box the plan's own rows span in every
  target but force (the fingertip's contact angles: the same places on the dome, reached from
  another run and orientation), or outside it.

A low ratio on the plan's rows and a high one on the test patches means the calibration does
not generalise from its presses; a high ratio only in unvisited orientations means coverage.

With `--priors`, the same calibration is also refitted at each prior strength and scored on the
test patches: the best strength per unit (chosen on held-out units, so never a method) bounds
what tuning the prior's strength could gain over the validation units' choice.

With `--remount-s`, the plans are chosen as if a change of orientation cost that many seconds
(100000: a plan that never re-mounts, so its presses stay in one orientation and the budget
buys more of them); everything else is the run's.

    python scripts/where_calibration_errs.py RUN_DIR --registry data/fleet24 --budget 120 \
        [--seeds 0 1] [--adapter input_affine+film] [--priors 0.1 1 10 100 1000] \
        [--remount-s 100000] [--out FILE.md]
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import torch

from anytip.config import load_spec
from anytip.data.arrays import FleetArrays
from anytip.data.plans import Budget
from anytip.data.registry import Registry
from anytip.models.io import load_models, load_shared
from anytip.pipelines.common import Context, load
from anytip.pipelines.cross_sensor import adapted_method, fit_methods, min_units, plan_of, prepare
from anytip.pipelines.cross_sensor_options import parse_options
from anytip.pipelines.run_diagnostic import diagnose, diagnostic_parser
from anytip.report.cross_sensor import mean_interval
from anytip.train.adapter_prior import make_prior
from anytip.train.metrics import scores
from anytip.train.shared_split import calibrate_many, predict_rows

KEY = "force_rmse_n"  # the benchmark's force RMSE [N] (anytip.train.metrics.scores)


def seed_ratios(run: Path, registry: str, seed: int, amount: float, adapter: str,
                priors: list[float], remount_s: float | None = None) -> list[dict]:
    """Per held-out unit of `seed`: force-RMSE ratios to the reference on plan rows and on the
    test patches of visited and unvisited orientations (at the prior the run chose), and on all
    test patches at each of `priors` (`by_prior`)."""
    spec = load_spec(run / "config.yaml")
    prov = json.loads((run / "provenance.json").read_text())
    ctx = Context(spec, Registry(Path(registry), create=False), run, torch.device("cpu"), False)
    opts = parse_options(ctx)
    if remount_s is not None:
        opts = opts.model_copy(update={"rig": opts.rig.model_copy(update={"remount_s": remount_s})})
    arrays = load(ctx, min_units(ctx))
    sd = prepare(ctx, arrays, opts, seed)
    units = list(sd.split.test)
    if units != prov["cross_sensor"][f"seed{seed}"]["units"]["test"]:
        raise SystemExit(f"{run}: seed {seed}'s held-out units differ from the run's record")
    family, fit = fit_methods(adapter, opts)[0]  # the run's first method of this shared model
    kind = fit.kind(adapter)
    method = (adapted_method(kind, family) + fit.suffix()).removeprefix("adapted:")
    budget = Budget(amount, "seconds", "spread")
    prior = prov["cross_sensor"][f"seed{seed}"]["priors_chosen"][method][budget.label]
    shared = load_shared(run / "models" / f"shared_{adapter.replace('+', '-')}_seed{seed}.safetensors")
    learnt = make_prior(family, shared.model, opts.prior_rank) if kind == adapter else None
    plans = [plan_of(sd, u, budget, opts, seed) for u in units]
    recipe = fit.recipe(opts, None)  # joint shared models: no inner fit
    unlabeled = [sd.evals[u].stream.unlabeled(opts.unlabeled_s) for u in units]
    jobs = [(k, p) for p in [prior, *priors] for k in range(len(units))]
    folded, stats = calibrate_many(shared, arrays, [unlabeled[k] for k, _ in jobs],
                                   [plans[k] for k, _ in jobs], [p for _, p in jobs], recipe, seed,
                                   kind, learnt)
    rows = {"plan": [p.rows for p in plans], "test": [sd.evals[u].test_rows for u in units]}
    every = {key: predict_rows(folded, stats, shared.out_scaler, arrays, [r[k] for k, _ in jobs])
             for key, r in rows.items()}
    adapted = {key: pred[: len(units)] for key, pred in every.items()}
    results = json.loads((run / "metrics.json").read_text())["results"]
    lr_of = {r["unit"]: r.get("reference_lr") for r in results
             if r["seed"] == seed and r["method"] == "per_unit"}
    refs = {}
    for k, lr in enumerate(opts.reference_lrs or [None]):
        name = f"per_unit_seed{seed}" + (f"_lr{k}" if opts.reference_lrs else "")
        m = load_models(run / "models" / name)
        refs[lr] = {key: predict_rows(m.model, m.in_scaler, m.out_scaler, arrays, r)
                    for key, r in rows.items()}
    orientation = np.array([r.orientation_deg for r in arrays.runs])

    def ratio(pred: np.ndarray, ref_pred: np.ndarray, at: np.ndarray) -> float:
        y = arrays.targets[at]
        return scores(pred, y, arrays.layout)[KEY] / scores(ref_pred, y, arrays.layout)[KEY]

    out = []
    for i, u in enumerate(units):
        ref = refs[lr_of[u]]
        line = {"unit": u, "seed": seed, "orientations": list(plans[i].orientations),
                "plan": ratio(adapted["plan"][i], ref["plan"][i], rows["plan"][i])}
        test = rows["test"][i]
        visited = np.isin(orientation[arrays.run[test]], plans[i].orientations)
        inside = within_plan(arrays, rows["plan"][i], test)
        for key, sel in (("visited", visited), ("unvisited", ~visited),
                         ("unvisited_inside", ~visited & inside), ("unvisited_outside", ~visited & ~inside)):
            if sel.any():
                line[key] = ratio(adapted["test"][i][sel], ref["test"][i][sel], test[sel])
        line["by_prior"] = {p: ratio(every["test"][j], ref["test"][i], test)
                            for j, (k, p) in enumerate(jobs) if k == i and j >= len(units)}
        out.append(line)
    return out


def within_plan(arrays: FleetArrays, plan_rows: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """(n,) bool: rows whose targets other than force lie within the range the plan's rows span
    in each component (all True where force is the only target)."""
    inside = np.ones(len(rows), bool)
    for name, cols in arrays.slices.items():
        if name != "force":
            own = arrays.targets[plan_rows][:, cols]
            y = arrays.targets[rows][:, cols]
            inside &= np.all((y >= own.min(0)) & (y <= own.max(0)), axis=1)
    return inside


def table(lines: list[dict]) -> str:
    """Markdown: one row per (unit, seed), then the mean over rows with a 95% bootstrap interval."""
    head = ("| unit | seed | orientations visited | plan rows | test, visited | test, unvisited | "
            "unvisited, inside the plan's places | unvisited, outside |\n|---|---|---|---|---|---|---|---|")

    def cell(v: float | None) -> str:
        return "" if v is None else f"{v:.2f}x"

    body = [f"| {r['unit']} | {r['seed']} | {', '.join(f'{o:g}' for o in r['orientations'])} | "
            f"{cell(r['plan'])} | {cell(r.get('visited'))} | {cell(r.get('unvisited'))} | "
            f"{cell(r.get('unvisited_inside'))} | {cell(r.get('unvisited_outside'))} |" for r in lines]
    summary = []
    for key in ("plan", "visited", "unvisited", "unvisited_inside", "unvisited_outside"):
        v = [r[key] for r in lines if key in r]
        if v:
            m, lo, hi = mean_interval(v)
            summary.append(f"{key}: {m:.2f}x [{lo:.2f}, {hi:.2f}] over {len(v)} unit-seeds")
    text = "\n".join([head, *body, "", "Mean force-RMSE ratio to the reference: " + "; ".join(summary)])
    priors = sorted({p for r in lines for p in r["by_prior"]})
    if not priors:
        return text
    grid = np.array([[r["by_prior"][p] for p in priors] for r in lines])  # (unit-seeds, priors)
    cells = [f"{p:g}: {mean_interval(list(grid[:, j]))[0]:.2f}x" for j, p in enumerate(priors)]
    best, lo, hi = mean_interval(list(grid.min(1)))
    return (f"{text}\n\nAll test patches, by prior strength (mean over unit-seeds): {'; '.join(cells)}. "
            f"The best strength of each unit, chosen on its own test patches (a bound, not a method): "
            f"{best:.2f}x [{lo:.2f}, {hi:.2f}].\n")


def main() -> None:
    ap = diagnostic_parser(__doc__)
    ap.add_argument("--priors", type=float, nargs="*", default=[], help="prior strengths to refit at")
    ap.add_argument("--remount-s", type=float, default=None,
                    help="choose the plans as if a re-mount cost this many seconds (default: the run's)")
    a = ap.parse_args()
    remount = "" if a.remount_s is None else f", plans priced at {a.remount_s:g} s per re-mount"

    def render(seeds: list[int], lines: list) -> str:
        return (f"# Where a {a.budget:g} s calibration errs: `{a.run.name}`, {a.adapter} "
                f"(first fit of the run{remount})\n\n{table(lines)}\n")

    diagnose(a, lambda s: seed_ratios(a.run, a.registry, s, a.budget, a.adapter, a.priors, a.remount_s),
             render)

if __name__ == "__main__":
    main()
