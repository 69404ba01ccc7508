"""Research log entry 220: the mean of four draws' codes (M4) against entry 219's four draws, pad folds 0-3.

    python reports/cross_sensor_designs/entry220/analyse.py

Reads `entry220/mean4_seedK` and `entry219/drawD_seedK` (K, D = 0-3) with entry 219's readers: the
held-out units' `response:label_free` rows, each validation unit's standardised loss (provenance) and
each unit's objectives (the runs' logs). Prints the gate, the decision on the validation units and the
held-out reading, as the entry wrote them down.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
DRAWN = HERE.parent / "entry219"
_spec = importlib.util.spec_from_file_location("entry219", DRAWN / "analyse.py")
assert _spec is not None and _spec.loader is not None
e219 = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(e219)
FOLDS, DRAWS, METHOD = e219.FOLDS, e219.DRAWS, e219.METHOD
rows, objectives, val_losses, geo = e219.rows, e219.objectives, e219.val_losses, e219.geo


def read_arm(run: Path, k: int, val: dict, test: dict) -> dict[str, dict]:
    """Fold k of an arm's run beside entry 219's draws, into `val` ({(k, unit): (loss, [loss per draw])})
    and `test` ({(k, unit): {"m": the arm's (force, position) RMSE, "d": each draw's, "ref": the
    reference's}}); the fold's references."""
    refs = rows(HERE.parent / f"pad_plans_seed{k}", "per_unit")
    drawn_val = [val_losses(DRAWN / f"draw{d}_seed{k}", k) for d in DRAWS]
    for u, loss in val_losses(run, k).items():
        val[(k, u)] = (loss, [drawn_val[d][u] for d in DRAWS])
    drawn_rows = [rows(DRAWN / f"draw{d}_seed{k}", METHOD) for d in DRAWS]
    for u, r in rows(run, METHOD).items():
        test[(k, u)] = {"m": (r["force_rmse_n"], r["position_rmse"]),
                        "d": [(x[u]["force_rmse_n"], x[u]["position_rmse"]) for x in drawn_rows],
                        "ref": (refs[u]["force_rmse_n"], refs[u]["position_rmse"])}
    return refs


def decide(val: dict, arm: str, what: str) -> None:
    """Rule 2: the arm is taken where its validation units' mean loss lies 2% below the draws' mean
    and draw 0's."""
    print("\nRule 2 (decision, 8 validation units):")
    mean = float(np.mean([v[0] for v in val.values()]))
    by_draw = [float(np.mean([v[1][d] for v in val.values()])) for d in DRAWS]
    draws_mean = float(np.mean(by_draw))
    for key in sorted(val):
        draws = " ".join(f"{x:.5f}" for x in val[key][1])
        print(f"  fold {key[0]} {key[1]}: {arm} {val[key][0]:.5f}, draws {draws}")
    print(f"  {arm} {mean:.5f}: {100 * (mean / draws_mean - 1):+.1f}% against the draws' mean "
          f"{draws_mean:.5f}, {100 * (mean / by_draw[0] - 1):+.1f}% against draw 0's {by_draw[0]:.5f}")
    taken = mean <= 0.98 * draws_mean and mean <= 0.98 * by_draw[0]
    print(f"  -> {what} {'TAKEN' if taken else 'not taken'}")


def held_out(test: dict, arm: str) -> None:
    """Rule 3: the arm over draw 0 and over the draws' geometric mean per unit, and to the references."""
    print("\nRule 3 (read after, 24 held-out units):")
    for name, col in (("force", 0), ("position", 1)):
        over_0 = [v["m"][col] / v["d"][0][col] for v in test.values()]
        over_mean = [v["m"][col] / np.exp(np.mean(np.log([x[col] for x in v["d"]]))) for v in test.values()]
        below_best = sum(v["m"][col] < min(x[col] for x in v["d"]) for v in test.values())
        ours, refs = ([v[key][col] for v in test.values()] for key in ("m", "ref"))
        print(f"  {name}: {arm} over draw 0 {geo(over_0)}; over the draws' geometric mean {geo(over_mean)}; "
              f"below the unit's best draw on {below_best} of {len(test)}; against the references "
              f"{np.mean(ours) / np.mean(refs):.3f}x")


def main() -> None:
    same, refs_equal, val, test = 0, 0, {}, {}
    for k in FOLDS:
        run = HERE / f"mean4_seed{k}"
        mean_obj = objectives(HERE / "logs" / f"mean4_seed{k}.log")
        drawn_obj = [objectives(DRAWN / "logs" / f"draw{d}_seed{k}.log") for d in DRAWS]
        same += sum(mean_obj[u] == [drawn_obj[d][u][0] for d in DRAWS] for u in mean_obj)
        refs_equal += rows(run, "per_unit") == read_arm(run, k, val, test)
    print("Rule 1 (gate):")
    print(f"  units whose four objectives equal entry 219's draws: {same} of {len(val) + len(test)}; "
          f"references equal the fold run's in {refs_equal} of {len(FOLDS)} runs")
    decide(val, "M4", "starts: 4")
    held_out(test, "M4")


if __name__ == "__main__":
    main()
