"""Fleet vs one-at-a-time training speed on synthetic data.

    python -m anytip.train.bench --units 20 --rows 30000 --seq-units 2 --fleet-paper --threads 1

Fits the first `--seq-units` units one at a time with the paper recipe (the reference:
each unit's validation force RMSE and its training seconds, extrapolated to the fleet),
then the whole fleet at once with `--recipe`, and reports steps/s and the training
seconds until every reference unit is within 5% of its paper RMSE. With --fleet-paper
the fleet is also fit with the paper recipe batched (the same algorithm as the reference,
one step for all units), which gives a paper RMSE for every unit of the fleet.
"""

from __future__ import annotations

import argparse
import statistics
from pathlib import Path

import torch

from anytip.rundir import dumps_json, write_json
from anytip.train.fleet import FitResult, train_fleet
from anytip.train.recipe import PAPER, get_recipe
from anytip.train.sequential import train_sequential
from anytip.train.synthetic import synthetic_fleet
from anytip.train.timing import select_units, time_to_target


def kept_force_rmse(fit: FitResult, u: int) -> float:
    """Val force RMSE (N) of the weights unit u ended with (its lowest val loss)."""
    return min(fit.unit_history(u), key=lambda r: r["val_loss"])["val_force_rmse"]


def summary(fit: FitResult) -> dict:
    last = fit.history[-1]
    return {"train_s": last["elapsed_s"], "wall_s": fit.wall_s,
            "steps": last["step"], "steps_per_s": last["step"] / last["elapsed_s"],
            "val_force_rmse_n": statistics.mean(kept_force_rmse(fit, u)
                                                for u in range(len(fit.unit_ids)))}


def main(argv: list[str] | None = None) -> dict:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--units", type=int, default=20)
    p.add_argument("--rows", type=int, default=30_000)
    p.add_argument("--seq-units", type=int, default=2)
    p.add_argument("--recipe", default="fast")
    p.add_argument("--fleet-paper", action="store_true", help="also fit the fleet with `paper`")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--device", default="cpu")
    p.add_argument("--threads", type=int, help="torch CPU threads (1 suits a busy or small CPU)")
    p.add_argument("--json", help="write the summary here")
    args = p.parse_args(argv)
    if args.threads:
        torch.set_num_threads(args.threads)

    data = synthetic_fleet(args.units, args.rows, seed=args.seed, device=args.device)
    k = args.seq_units
    seq = train_sequential(data.subset(range(k)), recipe=PAPER, seed=args.seed)
    targets = [kept_force_rmse(seq, u) for u in range(k)]
    seq_steps = sum(seq.unit_history(u)[-1]["step"] for u in range(k))
    out: dict = {"units": args.units, "rows": args.rows, "threads": torch.get_num_threads(),
                 "sequential_paper": {
                     "units": k, "val_force_rmse_n": targets,
                     "train_s_per_unit": statistics.mean(seq.unit_train_s),
                     "steps_per_s": seq_steps / sum(seq.unit_train_s),
                     "fleet_estimate_s": statistics.mean(seq.unit_train_s) * args.units}}

    fleet = train_fleet(data, recipe=get_recipe(args.recipe), seed=args.seed, device=args.device)
    out[f"fleet_{args.recipe}"] = summary(fleet) | {
        "to_reference_units_s": time_to_target(select_units(fleet.history, range(k)), targets)}
    if args.fleet_paper:
        paper = train_fleet(data, recipe=PAPER, seed=args.seed, device=args.device)
        every = [kept_force_rmse(paper, u) for u in range(args.units)]
        out["fleet_paper"] = summary(paper)
        out[f"fleet_{args.recipe}"]["to_paper_all_units_s"] = time_to_target(fleet.history, every)
        out[f"fleet_{args.recipe}"]["to_paper_mean_s"] = time_to_target(
            fleet.history, statistics.mean(every))
    print(dumps_json(out), end="")
    if args.json:
        write_json(Path(args.json), out)
    return out


if __name__ == "__main__":
    main()
