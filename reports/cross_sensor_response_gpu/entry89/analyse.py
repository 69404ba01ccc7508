"""Research log entry 89's table: other16's plan alone with codes from F times its press count of random
presses (`f{F}/other16_seed{K}`), beside entry 87's oracle and entry 83's `e60_d0`, paired per unit.
Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry89/analyse.py
"""

import importlib.util
from pathlib import Path

from anytip.report.cross_sensor import mean_interval, paired_text

HERE = Path(__file__).parent
_spec = importlib.util.spec_from_file_location("entry87_analyse", HERE.parent / "entry87" / "analyse.py")
entry87 = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(entry87)  # its per_unit reads a root's four folds


def main() -> None:
    arms = {"control": entry87.CONTROL, "F = 1": HERE / "f1", "F = 4": HERE / "f4", "oracle": entry87.ORACLE}
    for name, key in entry87.KEYS.items():
        base = entry87.per_unit(entry87.CONTROL, "response@cover", key)
        for label, root in arms.items():
            if not all((root / f"other16_seed{k}" / "metrics.json").is_file() for k in entry87.FOLDS):
                continue
            per = entry87.per_unit(root, "response@cover", key)
            m, lo, hi = mean_interval(list(per.values()))
            paired = paired_text([per[u] / base[u] for u in base])
            print(f"{name} {label:8s} {m:.3f}x [{lo:.2f}, {hi:.2f}] paired x{paired}")


if __name__ == "__main__":
    main()
