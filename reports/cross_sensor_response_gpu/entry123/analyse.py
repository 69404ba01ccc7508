"""Research log entry 123's reading: entry 121's other16 rescorings with the plan's residual correction off,
paired per unit with entry 121's (on): off over on per method, force and angle, each unit's draws averaged,
and the validation units' means per draw. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry123/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text

HERE = Path(__file__).parent
ON = runpy.run_path(str(HERE.parent / "entry121" / "analyse.py"))
KEYS, FOLDS, METHODS = ON["KEYS"], ON["FOLDS"], ON["METHODS"]
ARMS = {"off": HERE, "on": HERE.parent / "entry121"}  # the first over the second


def off_over_on(off: dict[str, dict[str, float]], on: dict[str, dict[str, float]], label: str = "off") -> str:
    """Per output kind, the first arm over the second paired per unit, and the first arm's mean with its
    interval (`label`), from two arms' per-unit ratios (entry 121's `at_120`; entries 124-125 read it too)."""
    cells = []
    for kind in KEYS:
        mean, lo, hi = mean_interval(list(off[kind].values()))
        paired = paired_text([off[kind][u] / on[kind][u] for u in on[kind]])
        cells.append(f"{kind} x{paired} ({label} {mean:.3f}x [{lo:.2f}, {hi:.2f}])")
    return "; ".join(cells)


def paired_arms(arms: dict[str, Path], what: str) -> None:
    """The first of two arms (entry 121's layout of runs) over the second, per unit for every method, each
    unit's draws averaged, over the draws both ran in full, and the validation units' means per draw (entry
    125 reads it too)."""
    (a, _), (b, _) = arms.items()
    ran = [(root, k) for root in arms.values() for k in FOLDS]
    draws = [d for d in (0, 1, 2)
             if all((ON["run_dir"](root, d, k) / "metrics.json").is_file() for root, k in ran)]
    print(f"draws {draws}, 120 s, {what} per unit:")
    for m in METHODS:
        per = {arm: ON["unit_figure"](root, draws, m) for arm, root in arms.items()}
        print(f"  {m}: {off_over_on(per[a], per[b], a)}")
    for d in draws:
        means = {arm: {m: np.mean([ON["record"](root, d, k)["val_loss"][m]["120"] for k in FOLDS])
                       for m in METHODS} for arm, root in arms.items()}
        text = ", ".join(f"{m} {means[a][m]:.5f} / {means[b][m]:.5f}" for m in METHODS)
        print(f"validation, draw {d}, {a} / {b}: {text}")


def main() -> None:
    paired_arms(ARMS, "off over on")


if __name__ == "__main__":
    main()
