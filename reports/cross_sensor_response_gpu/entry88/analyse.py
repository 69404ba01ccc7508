"""Research log entry 88's table: other16's four folds with the plan's rows weighing W times their
effective count in the fit of its codes (`w{W}/other16_seed{K}`) against entry 83's `e60_d0` (W = 1).
Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry88/analyse.py
"""

from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
CONTROL = HERE.parent / "entry83" / "e60_d0"
WEIGHTS, FOLDS, BUDGET = ("0.25", "4", "16"), (0, 1, 2, 3), 120.0
METHODS = ("response@cover", "response+use@cover")
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}


def runs(root: Path) -> list[Path]:
    return [root / f"other16_seed{k}" for k in FOLDS]


def val_loss(root: Path, method: str) -> float:
    """The validation units' loss of `method` at 120 s, mean over the four folds."""
    losses = [read_json(p / "provenance.json")["cross_sensor"][f"seed{k}"]["val_loss"][method]["120"]
              for k, p in zip(FOLDS, runs(root), strict=True)]
    return float(np.mean(losses))


def per_unit(root: Path, method: str, key: str) -> dict[str, float]:
    rows = [r for p in runs(root) for r in read_json(p / "metrics.json")["results"]]
    return unit_ratios(rows, key)[(method, BUDGET)]


def main() -> None:
    arms = {"1 (control)": CONTROL} | {w: HERE / f"w{w}" for w in WEIGHTS
                                       if all((p / "metrics.json").is_file() for p in runs(HERE / f"w{w}"))}
    for m in METHODS:
        base = val_loss(CONTROL, m)
        for w, root in arms.items():
            loss = val_loss(root, m)
            line = f"weight {w:12s} {m:20s} val {loss:.5f} ({100 * (loss / base - 1):+.1f}%)"
            for n, key in KEYS.items():
                per, ref = per_unit(root, m, key), per_unit(CONTROL, m, key)
                mean, lo, hi = mean_interval(list(per.values()))
                paired = paired_text([per[u] / ref[u] for u in ref])
                line += f" | {n} {mean:.3f}x [{lo:.2f}, {hi:.2f}] paired x{paired}"
            print(line)


if __name__ == "__main__":
    main()
