"""Research log entry 103's reading: the float32 kernel's rescorings (`cover_informative` alone) paired with
entry 101's fleet88 runs of the same folds: the validation units' mean loss (rule 1) and the held-out ratios
with the per-unit factor against entry 101 (rule 2). Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry103/analyse.py
"""

from pathlib import Path

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
ROOTS = {"float32": HERE / "fleet88_cpu", "entry 101": HERE.parent / "entry101" / "fleet88_cpu"}
METHOD = "response@cover_informative"
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}
FOLDS = (0, 1)


def val_losses(root: Path) -> dict[str, float]:
    return {u: v for k in FOLDS for u, v in read_json(root / f"fleet88_seed{k}" / "provenance.json")
            ["cross_sensor"][f"seed{k}"]["val_loss_units"][METHOD]["120"].items()}


def main() -> None:
    new, old = (val_losses(r) for r in ROOTS.values())
    a, b = np.mean(list(new.values())), np.mean(list(old.values()))
    change = 100 * (a / b - 1)
    print(f"rule 1, validation: mean {a:.5f} against {b:.5f}"
          f" ({change:+.2f}%); per unit x{paired_text([new[u] / old[u] for u in old])} over {len(old)} units")
    rows = {name: [r for k in FOLDS for r in read_json(root / f"fleet88_seed{k}" / "metrics.json")["results"]]
            for name, root in ROOTS.items()}
    for label, key in KEYS.items():
        per = [unit_ratios(got, key)[(METHOD, 120.0)] for got in rows.values()]
        (m, lo, hi), (c, clo, chi) = (mean_interval(list(p.values())) for p in per)
        factor = paired_text([per[0][u] / per[1][u] for u in per[1]])
        print(f"rule 2, {label}, held out: {m:.3f}x [{lo:.2f}, {hi:.2f}] vs {c:.3f}x [{clo:.2f}, {chi:.2f}];"
              f" per unit x{factor} over {len(per[1])} units")


if __name__ == "__main__":
    main()
