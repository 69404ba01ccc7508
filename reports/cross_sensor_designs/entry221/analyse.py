"""Research log entry 221: the label-free search over every source row (arm A) against entry 219's four draws.

    python reports/cross_sensor_designs/entry221/analyse.py

Reads `entry221/all_seedK` and `entry219/drawD_seedK` (K, D = 0-3) with entry 220's readers, and prints the
gate, the decision on the validation units and the held-out reading, as the entry wrote them down.
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
_spec = importlib.util.spec_from_file_location("entry220", HERE.parent / "entry220" / "analyse.py")
assert _spec is not None and _spec.loader is not None
e220 = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(e220)
DRAWN, FOLDS, DRAWS, METHOD = e220.DRAWN, e220.FOLDS, e220.DRAWS, e220.METHOD


def wall_s(run: Path) -> float:
    """A run's recorded wall time, s."""
    return float(json.loads((run / "provenance.json").read_text())["wall_s"])


def main() -> None:
    refs_equal, logged, val, test, lower, times = 0, 0, {}, {}, 0, []
    for k in FOLDS:
        run = HERE / f"all_seed{k}"
        obj = e220.objectives(HERE / "logs" / f"all_seed{k}.log")
        drawn_obj = [e220.objectives(DRAWN / "logs" / f"draw{d}_seed{k}.log") for d in DRAWS]
        logged += len(obj) == 8
        lower += sum(obj[u][0] < min(drawn_obj[d][u][0] for d in DRAWS) for u in obj)
        refs = e220.rows(HERE.parent / f"pad_plans_seed{k}", "per_unit")
        refs_equal += e220.rows(run, "per_unit") == refs
        times.append((wall_s(run), np.mean([wall_s(DRAWN / f"draw{d}_seed{k}") for d in DRAWS])))
        drawn_val = [e220.val_losses(DRAWN / f"draw{d}_seed{k}", k) for d in DRAWS]
        for u, loss in e220.val_losses(run, k).items():
            val[(k, u)] = (loss, [drawn_val[d][u] for d in DRAWS])
        drawn_rows = [e220.rows(DRAWN / f"draw{d}_seed{k}", METHOD) for d in DRAWS]
        for u, r in e220.rows(run, METHOD).items():
            test[(k, u)] = {"m": (r["force_rmse_n"], r["position_rmse"]),
                            "d": [(x[u]["force_rmse_n"], x[u]["position_rmse"]) for x in drawn_rows],
                            "ref": (refs[u]["force_rmse_n"], refs[u]["position_rmse"])}
    print("Rule 1 (gate):")
    print(f"  references equal the fold run's in {refs_equal} of {len(FOLDS)} runs; "
          f"8 objectives logged in {logged} of {len(FOLDS)}")

    print("\nRule 2 (decision, 8 validation units):")
    arm = float(np.mean([v[0] for v in val.values()]))
    by_draw = [float(np.mean([v[1][d] for v in val.values()])) for d in DRAWS]
    draws_mean = float(np.mean(by_draw))
    for key in sorted(val):
        draws = " ".join(f"{x:.5f}" for x in val[key][1])
        print(f"  fold {key[0]} {key[1]}: every row {val[key][0]:.5f}, draws {draws}")
    print(f"  every row {arm:.5f}: {100 * (arm / draws_mean - 1):+.1f}% against the draws' mean "
          f"{draws_mean:.5f}, {100 * (arm / by_draw[0] - 1):+.1f}% against draw 0's {by_draw[0]:.5f}")
    taken = arm <= 0.98 * draws_mean and arm <= 0.98 * by_draw[0]
    print(f"  -> every source row a candidate {'TAKEN' if taken else 'not taken'}")

    print("\nRule 3 (read after, 24 held-out units):")
    for name, col in (("force", 0), ("position", 1)):
        over_0 = [v["m"][col] / v["d"][0][col] for v in test.values()]
        over_mean = [v["m"][col] / np.exp(np.mean(np.log([x[col] for x in v["d"]]))) for v in test.values()]
        ours, refs = ([v[key][col] for v in test.values()] for key in ("m", "ref"))
        print(f"  {name}: over draw 0 {e220.geo(over_0)}; over the draws' geometric mean "
              f"{e220.geo(over_mean)}; against the references {np.mean(ours) / np.mean(refs):.3f}x")
    print(f"  final objective below every draw's on {lower} of {len(val) + len(test)} units")
    print("  wall time per run, s (every row / the draws' mean): "
          + ", ".join(f"{a:.0f} / {b:.0f}" for a, b in times))


if __name__ == "__main__":
    main()
