"""Research log entry 122's reading: fleet88's designed plan with ordinary use under today's recipe,
`cover_informative` beside it in the same runs. Rule 1: the references' rows and `cover_informative`'s
plans equal entry 105's run of the same fold; the shared methods' RMSEs move by the code's drift since,
which is reported. Rule 2: the designed plan's ratios at 120 s with ordinary use (and alone, beside entry
102's). Rule 3: designed over `cover_informative`, paired per unit. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry122/analyse.py
"""

import runpy
from pathlib import Path
from typing import Any

import numpy as np

from anytip.rundir import read_json

HERE = Path(__file__).parent
# entry 121's data_check, at_120, line and rule 3
READING = runpy.run_path(str(HERE.parent / "entry121" / "analyse.py"))
BEFORE = {"use": HERE.parent / "entry105" / "fleet88_cpu_use_on",
          "alone": HERE.parent / "entry102" / "fleet88_cpu_on"}
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}
FOLDS = (0, 1)
METHODS = tuple(f"{use}@{plan}" for use in ("response+use", "response")
                for plan in ("designed", "cover_informative"))


def rows(root: Path, k: int) -> list[dict[str, Any]]:
    return read_json(root / f"fleet88_seed{k}" / "metrics.json")["results"]


def record(root: Path, k: int) -> dict[str, Any]:
    return read_json(root / f"fleet88_seed{k}" / "provenance.json")["cross_sensor"][f"seed{k}"]


def same_data(k: int) -> None:
    """Rule 1 against entry 105's run, and the code's drift in the methods both runs hold."""
    old = rows(BEFORE["use"], k)
    shared = sorted({r["method"] for r in old} & set(METHODS))
    equal, n, drift = READING["data_check"](rows(HERE, k), old, shared)
    print(f"rule 1, fold {k}: references and plans of {', '.join(shared)} {'equal' if equal else 'DIFFER'}; "
          f"their {n} RMSEs move by up to {drift:.3f} relative")


def unit_figure(root: Path, method: str) -> dict[str, dict[str, float]]:
    return READING["at_120"]([r for k in FOLDS for r in rows(root, k)], method)


line = READING["line"]


def main() -> None:
    for k in FOLDS:
        same_data(k)
    print("rule 2, 120 s:")
    per = {m: unit_figure(HERE, m) for m in METHODS}
    for m in METHODS:
        print(f"  {m}: {line(per[m])}")
    print(f"  entry 105's response+use@cover_informative: {line(unit_figure(BEFORE['use'], METHODS[1]))}")
    print(f"  entry 102's response@designed: {line(unit_figure(BEFORE['alone'], METHODS[2]))}")
    READING["designed_over_informative"](per)
    val = {m: np.mean([record(HERE, k)["val_loss"][m]["120"] for k in FOLDS]) for m in METHODS}
    print("validation, mean over the folds: " + ", ".join(f"{m} {v:.5f}" for m, v in val.items()))


if __name__ == "__main__":
    main()
