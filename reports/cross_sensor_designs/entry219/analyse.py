"""Research log entry 219: the label-free fit's draw of search contacts, read from the rescored pad folds.

    python reports/cross_sensor_designs/entry219/analyse.py

Reads `entry219/drawD_seedK` (D = 0-3, K = 0-3): the held-out units' `response:label_free` rows (force and
position RMSE, the fit's final objective), each validation unit's standardised loss (provenance) and objective
(the run's log). S takes, per unit, the draw of lowest final objective. Prints the gate, the decision on the
validation units and the held-out reading, as the entry wrote them down.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
from scipy import stats

HERE = Path(__file__).resolve().parent
FOLDS, DRAWS = range(4), range(4)
METHOD = "response:label_free"


def rows(path: Path, method: str) -> dict[str, dict]:
    """{unit: row} of one method in a run's metrics.json."""
    results = json.loads((path / "metrics.json").read_text())["results"]
    return {r["unit"]: r for r in results if r["method"] == method}


def objectives(log: Path) -> dict[str, list[float]]:
    """{unit: [final objective per draw]} from a run's log line (validation and held-out units), as
    printed (six digits); one per unit where the run read one draw."""
    line = next(x for x in log.read_text().splitlines() if "the fit's objective" in x)
    return {u: [float(v) for v in vs.split()]
            for u, vs in re.findall(r"(PAD\S+) ([-+0-9.e ]+?)(?:,|$)", line.split(":", 2)[2])}


def val_losses(run: Path, k: int) -> dict[str, float]:
    """Each validation unit's standardised loss of fold k's label-free row."""
    return json.loads((run / "provenance.json").read_text())["cross_sensor"][f"seed{k}"]["val_loss_units"][
        METHOD]["0"]


def geo(values: list[float]) -> str:
    """Geometric mean of ratios with a 95% t-interval over units."""
    logs = np.log(values)
    m, half = logs.mean(), stats.t.ppf(0.975, len(logs) - 1) * logs.std(ddof=1) / np.sqrt(len(logs))
    return f"x{np.exp(m):.3f} [{np.exp(m - half):.3f}, {np.exp(m + half):.3f}]"


def main() -> None:
    gate, val, test = [], {}, {}
    for k in FOLDS:
        base = HERE.parent / f"pad_plans_seed{k}"
        refs = rows(base, "per_unit")
        for d in DRAWS:
            run = HERE / f"draw{d}_seed{k}"
            objective = {u: v[0] for u, v in objectives(HERE / "logs" / f"draw{d}_seed{k}.log").items()}
            same_refs = rows(run, "per_unit") == refs
            losses = val_losses(run, k)
            gate.append((k, d, same_refs, len(objective) == 8))
            for u, loss in losses.items():
                val.setdefault((k, u), {})[d] = (loss, objective[u])
            for u, r in rows(run, METHOD).items():
                assert abs(r["label_free_objective"] / objective[u] - 1) < 1e-5  # the log's 6 digits
                test.setdefault((k, u), {})[d] = (r["force_rmse_n"], r["position_rmse"], objective[u],
                                                  refs[u]["force_rmse_n"], refs[u]["position_rmse"])
    print("Rule 1 (gate):")
    print(f"  references equal the fold run's in {sum(g[2] for g in gate)} of {len(gate)} runs; "
          f"8 objectives logged in {sum(g[3] for g in gate)} of {len(gate)}")
    moved = sum(test[key][1][0] != test[key][0][0] for key in test)
    print(f"  draw 1's force RMSE differs from draw 0's on {moved} of {len(test)} held-out units")

    print("\nRule 2 (decision, 8 validation units):")
    pick = {key: min(DRAWS, key=lambda d: v[d][1]) for key, v in val.items()}
    by_draw = [np.mean([v[d][0] for v in val.values()]) for d in DRAWS]
    s = np.mean([val[key][pick[key]][0] for key in val])
    draws_mean = float(np.mean(by_draw))
    for key in sorted(val):
        v = val[key]
        print(f"  fold {key[0]} {key[1]}: losses " + " ".join(f"{v[d][0]:.5f}" for d in DRAWS)
              + "  objectives " + " ".join(f"{v[d][1]:.6g}" for d in DRAWS) + f"  S takes draw {pick[key]}")
    print("  mean loss per draw: " + " ".join(f"{x:.5f}" for x in by_draw) + f"; their mean {draws_mean:.5f}")
    print(f"  S: {s:.5f} ({100 * (s / draws_mean - 1):+.1f}% against the draws' mean, "
          f"{100 * (s / by_draw[0] - 1):+.1f}% against draw 0)")
    taken = s <= 0.98 * draws_mean and s <= 0.98 * by_draw[0]
    print(f"  -> `starts` {'TAKEN' if taken else 'not taken'}")

    print("\nRule 3 (read after, 24 held-out units):")
    spread_f = [max(v[d][0] for d in DRAWS) / min(v[d][0] for d in DRAWS) for v in test.values()]
    spread_p = [max(v[d][1] for d in DRAWS) / min(v[d][1] for d in DRAWS) for v in test.values()]
    print(f"  spread over draws, max/min per unit: force median x{np.median(spread_f):.3f}, largest "
          f"x{max(spread_f):.3f}; position median x{np.median(spread_p):.3f}, largest x{max(spread_p):.3f}")
    for name, col in (("force", 0), ("position", 1)):
        s_over_0, s_over_mean = [], []
        for v in test.values():
            chosen = v[min(DRAWS, key=lambda d: v[d][2])][col]
            s_over_0.append(chosen / v[0][col])
            s_over_mean.append(chosen / np.exp(np.mean([np.log(v[d][col]) for d in DRAWS])))
        print(f"  {name}: S over draw 0 {geo(s_over_0)}; S over the draws' geometric mean {geo(s_over_mean)}")
    hits = sum(min(DRAWS, key=lambda d: v[d][2]) == min(DRAWS, key=lambda d: v[d][0]) for v in test.values())
    print(f"  the lowest objective picks the draw of lowest force RMSE on {hits} of {len(test)} units "
          "(chance 6)")
    for d in DRAWS:
        f = np.mean([v[d][0] for v in test.values()]) / np.mean([v[d][3] for v in test.values()])
        p = np.mean([v[d][1] for v in test.values()]) / np.mean([v[d][4] for v in test.values()])
        print(f"  draw {d} against the references (ratio of means): {f:.3f}x / {p:.3f}x")
    f = np.mean([v[min(DRAWS, key=lambda d: v[d][2])][0] for v in test.values()]) / np.mean(
        [v[0][3] for v in test.values()])
    print(f"  S against the references: {f:.3f}x in force")
    for key in sorted(test):
        v = test[key]
        print(f"  fold {key[0]} {key[1]}: force " + " ".join(f"{v[d][0]:.4f}" for d in DRAWS)
              + "  objectives " + " ".join(f"{v[d][2]:.6g}" for d in DRAWS))


if __name__ == "__main__":
    main()
