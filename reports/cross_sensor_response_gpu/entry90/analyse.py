"""Research log entry 90's tables: other16's plans chosen for what they tell the codes
(`{d,v}/other16_seed{K}`, `response@informative`) against entry 83's `e60_d0` (`response@cover`): the
validation units' loss per fold, and the 16 held-out units paired per unit, plan alone and with
ordinary use. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry90/analyse.py
"""

from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
CONTROL = HERE.parent / "entry83" / "e60_d0"
FOLDS, BUDGET = (0, 1, 2, 3), 120.0
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}
ARMS = {"cover (control)": (CONTROL, "cover"), "informative, d": (HERE / "d", "informative"),
        "informative, v": (HERE / "v", "informative")}


def done(root: Path) -> bool:
    return all((root / f"other16_seed{k}" / "metrics.json").is_file() for k in FOLDS)


def val_losses(root: Path, method: str) -> list[float]:
    """The validation units' loss of `method` at 120 s, fold by fold."""
    return [read_json(root / f"other16_seed{k}" / "provenance.json")["cross_sensor"][f"seed{k}"]["val_loss"]
            [method]["120"] for k in FOLDS]


def per_unit(root: Path, method: str, key: str) -> dict[str, float]:
    """{held-out unit: ratio to its reference} of `method` at 120 s over the four folds under root."""
    rows = [r for k in FOLDS for r in read_json(root / f"other16_seed{k}" / "metrics.json")["results"]]
    return unit_ratios(rows, key)[(method, BUDGET)]


def main() -> None:
    arms = {name: arm for name, arm in ARMS.items() if done(arm[0])}
    print("validation units' loss at 120 s, folds 0-3 and mean (alone | with use):")
    for name, (root, strategy) in arms.items():
        alone, use = val_losses(root, f"response@{strategy}"), val_losses(root, f"response+use@{strategy}")
        print(f"  {name:16s} {' '.join(f'{v:.5f}' for v in alone)} mean {np.mean(alone):.5f} | "
              f"{' '.join(f'{v:.5f}' for v in use)} mean {np.mean(use):.5f}")
    for kind in ("", "+use"):
        for label, key in KEYS.items():
            base = per_unit(CONTROL, f"response{kind}@cover", key)
            for name, (root, strategy) in arms.items():
                per = per_unit(root, f"response{kind}@{strategy}", key)
                m, lo, hi = mean_interval(list(per.values()))
                ratios = [per[u] / base[u] for u in base]
                paired = "" if root == CONTROL else f" paired x{paired_text(ratios)}"
                print(f"response{kind} {label} {name:16s} {m:.3f}x [{lo:.2f}, {hi:.2f}]{paired}")


if __name__ == "__main__":
    main()
