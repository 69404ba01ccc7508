"""Research log entry 135's reading: entry 127's swap of joint codes (designed <-> `cover_informative`, every
job with ordinary use) on today's recipe, against entry 130's run of it. Gate: the references' rows and every
plan-alone row equal entry 130's. Reading: swapped over entry 130 per unit for every method, each unit's draws
averaged, and the validation units' means per draw. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry135/analyse.py
"""

import runpy
from pathlib import Path

HERE = Path(__file__).parent
START = runpy.run_path(str(HERE.parent / "entry132" / "analyse.py"))  # its gate against entry 130


def read(root: Path, label: str) -> None:
    """The gate on every run under root, then, if it passed, root's arm (`label`) over entry 130's per unit
    (entry 136 reads it too)."""
    ran = [(d, k) for d in (0, 1, 2) for k in START["BASE"]["FOLDS"]
           if (START["BASE"]["run_dir"](root, d, k) / "metrics.json").is_file()]
    if all([START["gate"](root, d, k) for d, k in ran]):
        START["PAIRED"]["paired_arms"]({label: root, "130": START["RECIPE"]}, f"{label} over entry 130")
    else:
        print("gate failed: no row with ordinary use is read")


if __name__ == "__main__":
    read(HERE, "swapped")
