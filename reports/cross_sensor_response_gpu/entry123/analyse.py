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
ARMS = {"on": HERE.parent / "entry121", "off": HERE}


def off_over_on(off: dict[str, dict[str, float]], on: dict[str, dict[str, float]]) -> str:
    """Per output kind, off over on paired per unit, and off's mean with its interval, from two arms'
    per-unit ratios (entry 121's `at_120`; entry 124 reads it too)."""
    cells = []
    for label in KEYS:
        mean, lo, hi = mean_interval(list(off[label].values()))
        paired = paired_text([off[label][u] / on[label][u] for u in on[label]])
        cells.append(f"{label} x{paired} (off {mean:.3f}x [{lo:.2f}, {hi:.2f}])")
    return "; ".join(cells)


def main() -> None:
    ran = [(root, k) for root in ARMS.values() for k in FOLDS]
    draws = [d for d in (0, 1, 2)
             if all((ON["run_dir"](root, d, k) / "metrics.json").is_file() for root, k in ran)]
    print(f"draws {draws}, 120 s, off over on per unit:")
    for m in METHODS:
        per = {arm: ON["unit_figure"](root, draws, m) for arm, root in ARMS.items()}
        print(f"  {m}: {off_over_on(per['off'], per['on'])}")
    for d in draws:
        means = {arm: {m: np.mean([ON["record"](root, d, k)["val_loss"][m]["120"] for k in FOLDS])
                       for m in METHODS} for arm, root in ARMS.items()}
        text = ", ".join(f"{m} {means['off'][m]:.5f} / {means['on'][m]:.5f}" for m in METHODS)
        print(f"validation, draw {d}, off / on: {text}")


if __name__ == "__main__":
    main()
