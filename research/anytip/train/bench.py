"""Fleet vs one-at-a-time training speed on synthetic data.

    python -m anytip.train.bench --units 20 --rows 30000 --seq-units 2

Fits `--seq-units` units one at a time with the paper recipe (the reference accuracy and
the per-unit time, extrapolated to the fleet), then the whole fleet at once with the
fleet recipe, and reports steps/s and the training seconds to reach the reference's
validation force RMSE (within 5%).
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

import torch

from anytip.train.fleet import FitResult, train_fleet
from anytip.train.recipe import PAPER, get_recipe
from anytip.train.sequential import train_sequential
from anytip.train.synthetic import synthetic_fleet
from anytip.train.timing import time_to_target


def final_force_rmse(fit: FitResult, u: int) -> float:
    """Val force RMSE (N) of the weights unit u ended with (its lowest val loss)."""
    return min(fit.unit_history(u), key=lambda r: r["val_loss"])["val_force_rmse"]


def main(argv: list[str] | None = None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--units", type=int, default=20)
    p.add_argument("--rows", type=int, default=30_000)
    p.add_argument("--seq-units", type=int, default=2)
    p.add_argument("--recipe", default="fast")
    p.add_argument("--fleet-paper", action="store_true", help="also fit the fleet with `paper`")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--device", default="cpu")
    p.add_argument("--json", help="write the summary here")
    args = p.parse_args(argv)

    data = synthetic_fleet(args.units, args.rows, seed=args.seed, device=args.device)
    seq = train_sequential(data.subset(range(args.seq_units)), recipe=PAPER, seed=args.seed)
    targets = [final_force_rmse(seq, u) for u in range(args.seq_units)]
    target = statistics.mean(targets)
    seq_steps = sum(r["step"] for r in (seq.unit_history(u)[-1] for u in range(args.seq_units)))
    seq_to_target = [time_to_target(seq.unit_history(u), targets[u]) for u in range(args.seq_units)]
    out = {"units": args.units, "rows": args.rows, "threads": torch.get_num_threads(),
           "paper_val_force_rmse_n": target,
           "sequential": {"train_s_per_unit": statistics.mean(seq.unit_train_s),
                          "steps_per_s": seq_steps / sum(seq.unit_train_s),
                          "to_own_final_s_per_unit": statistics.mean(seq_to_target),
                          "fleet_estimate_s": statistics.mean(seq.unit_train_s) * args.units}}
    recipes = [get_recipe(args.recipe)] + ([PAPER] if args.fleet_paper else [])
    for recipe in recipes:
        t = time.perf_counter()
        fit = train_fleet(data, recipe=recipe, seed=args.seed, device=args.device)
        last = fit.history[-1]
        out[f"fleet_{recipe.name}"] = {
            "train_s": last["elapsed_s"], "wall_s": time.perf_counter() - t,
            "steps_per_s": last["step"] / last["elapsed_s"],
            "to_target_mean_s": time_to_target(fit.history, target),
            "to_target_all_units_s": time_to_target(fit.history, target, reduce="max"),
            "val_force_rmse_n": statistics.mean(final_force_rmse(fit, u) for u in range(args.units)),
            "val_angle_rmse_rad": statistics.mean(last["val_angle_rmse"])}
    print(json.dumps(out, indent=2))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f, indent=2)
    return out


if __name__ == "__main__":
    main()
