"""Research log entry 126's reading: other16's designed plan with its second orientation pressed 600 s
after power-up (`data/other16s`), against entry 121's cold plan. Rule 1: every reference's rows,
`cover_informative`'s plans and RMSEs, and the designed plans' robot seconds and row counts equal entry 121's.
Rules 2-3: split over cold per unit for every method, each unit's draws averaged, and the validation units'
means per draw. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry126/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
COLD = HERE.parent / "entry121"
BEFORE = runpy.run_path(str(COLD / "analyse.py"))
PAIRED = runpy.run_path(str(HERE.parent / "entry123" / "analyse.py"))
DESIGNED = ("response@designed", "response+use@designed")


# The designed plans' robot seconds are sums of time stamps' differences; the warm run's stamps lie 600 s
# later, where float64 rounds each to 1.1e-13 s, so the sums may differ in the 13th digit (rule 1 as amended).
# This bound is the rounding of a few hundred stamps with ample room, and far under one 5 ms sample.
SECONDS_BOUND = 1e-9


def designed_plans(rows: list[dict]) -> list[tuple]:
    return sorted((r["method"], r["unit"], r["seed"], r["calib_samples"])
                  for r in rows if r["method"] in DESIGNED)


def designed_seconds(rows: list[dict]) -> list[float]:
    return [r["calib_seconds"] for r in sorted(rows, key=lambda r: (r["method"], r["unit"], r["seed"]))
            if r["method"] in DESIGNED]


def gate(d: int, k: int) -> bool:
    """Rule 1 for draw d, fold k."""
    new, old = BEFORE["rows"](HERE, d, k), BEFORE["rows"](COLD, d, k)
    shared_equal, n, moved = BEFORE["data_check"](new, old, BEFORE["SHARED"])
    plans_equal = designed_plans(new) == designed_plans(old)
    seconds = np.abs(np.array(designed_seconds(new)) - designed_seconds(old)).max()
    plans_equal = plans_equal and seconds <= SECONDS_BOUND
    ok = shared_equal and plans_equal and moved == 0.0
    print(f"rule 1, draw {d}, fold {k}: references and cover_informative's plans "
          f"{'equal' if shared_equal else 'DIFFER'}, its {n} RMSEs move by up to {moved:.2g}; "
          f"designed plans' rows {'equal' if plans_equal else 'DIFFER'} (seconds within {seconds:.1g} s): "
          f"{'passed' if ok else 'FAILED'}")
    return ok


def main() -> None:
    ran = [(d, k) for d in (0, 1, 2) for k in BEFORE["FOLDS"]
           if (BEFORE["run_dir"](HERE, d, k) / "metrics.json").is_file()]
    if not all([gate(d, k) for d, k in ran]):
        print("rule 1 failed: no designed row is read")
        return
    PAIRED["paired_arms"]({"split": HERE, "cold": COLD}, "split over cold")
    draws = sorted({d for d, _ in ran if all((d, k) in ran for k in BEFORE["FOLDS"])})
    for m in DESIGNED:
        means = [np.mean([BEFORE["record"](root, d, k)["val_loss"][m]["120"] for d in draws
                          for k in BEFORE["FOLDS"]]) for root in (HERE, COLD)]
        print(f"rule 2, {m}: validation mean over draws {draws} and four folds, split {means[0]:.5f}, "
              f"cold {means[1]:.5f} ({means[0] / means[1] - 1:+.1%})")


if __name__ == "__main__":
    main()
