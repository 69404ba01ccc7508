"""Research log entry 109's reading: the validation units' losses with the correction's kernel over the query
rows in float32 against float64 (`run_fleet88w.sh`, each fold's 4 validation units and the 64 SIM42-* units):
the rule written down (the mean loss over the validation unit-folds within 0.5%), and, deciding nothing, the
paired per-unit ratio (geometric mean, 95% bootstrap interval over unit-folds). From the repository root:

    python reports/cross_sensor_response_gpu/entry109/analyse.py
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

HERE = Path("reports/cross_sensor_response_gpu/entry109")
METHOD, BUDGET = "response@cover_informative", "120"
TOLERANCE = 0.005  # entry 103's rule 1


def losses(arm: str) -> dict[tuple[int, str], float]:
    """{(fold, unit): validation loss} of an arm's two folds."""
    out = {}
    for fold in (0, 1):
        got = json.loads((HERE / arm / f"fleet88_seed{fold}" / "val_loss_units.json").read_text())
        out |= {(fold, u): v for u, v in got["val_loss_units"][METHOD][BUDGET].items()}
    return out


def main(draws: int = 10000, seed: int = 0) -> None:
    f64, f32 = losses("float64"), losses("float32")
    if set(f64) != set(f32):
        raise SystemExit("the arms scored different validation unit-folds")
    keys = sorted(f64)
    a, b = np.array([f64[k] for k in keys]), np.array([f32[k] for k in keys])
    change = b.mean() / a.mean() - 1
    print(f"{len(keys)} validation unit-folds ({sum(k[1].startswith('SIM42-') for k in keys)} of SIM42-*); "
          f"mean loss float64 {a.mean():.5f}, float32 {b.mean():.5f}: {change * 100:+.2f}%")
    verdict = "holds, the float32 kernel is taken" if abs(change) <= TOLERANCE else "fails, it stays float64"
    print(f"rule: within {TOLERANCE:.1%}: {verdict}")
    logs = np.log(b / a)
    rng = np.random.default_rng(seed)
    boot = np.exp(rng.choice(logs, (draws, len(logs))).mean(1))
    lo, hi = np.quantile(boot, [0.025, 0.975])
    print(f"also read: per unit-fold x{np.exp(logs.mean()):.4f} [{lo:.4f}, {hi:.4f}]; float32 lower in "
          f"{int((logs < 0).sum())}, higher in {int((logs > 0).sum())}, equal in {int((logs == 0).sum())}")
    for fold in (0, 1):
        mine = [i for i, k in enumerate(keys) if k[0] == fold]
        print(f"  fold {fold}: {len(mine)} units, mean {a[mine].mean():.5f} / {b[mine].mean():.5f} "
              f"({(b[mine].mean() / a[mine].mean() - 1) * 100:+.2f}%)")


if __name__ == "__main__":
    main()
