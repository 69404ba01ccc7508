"""Research log entry 125's reading: entry 123's other16 rescorings (the correction off, at most 2,048 plan
rows in the joint fit with ordinary use) against the same with at most 128: 128 over 2,048 per unit for every
method, each unit's draws averaged, and the validation units' means per draw. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry125/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
READING = runpy.run_path(str(HERE.parent / "entry121" / "analyse.py"))
PAIRING = runpy.run_path(str(HERE.parent / "entry123" / "analyse.py"))  # its off_over_on
FOLDS, METHODS = READING["FOLDS"], READING["METHODS"]
ARMS = {"128": HERE, "2048": HERE.parent / "entry123"}


def main() -> None:
    ran = [(root, k) for root in ARMS.values() for k in FOLDS]
    draws = [d for d in (0, 1, 2)
             if all((READING["run_dir"](root, d, k) / "metrics.json").is_file() for root, k in ran)]
    print(f"draws {draws}, 120 s, 128 over 2048 plan rows in the joint fit, per unit (the figure: 128's):")
    for m in METHODS:
        few, many = (READING["unit_figure"](root, draws, m) for root in ARMS.values())
        print(f"  {m}: {PAIRING['off_over_on'](few, many)}")
    for d in draws:
        means = {arm: {m: np.mean([READING["record"](root, d, k)["val_loss"][m]["120"] for k in FOLDS])
                       for m in METHODS} for arm, root in ARMS.items()}
        text = ", ".join(f"{m} {means['128'][m]:.5f} / {means['2048'][m]:.5f}" for m in METHODS)
        print(f"validation, draw {d}, 128 / 2048: {text}")


if __name__ == "__main__":
    main()
