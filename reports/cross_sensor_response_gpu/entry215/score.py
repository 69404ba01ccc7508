"""Research log entry 215's reading: rule 1 (each unit's two plans take the same robot time), then log(R / H)
per fresh validation unit, force and angle, over all 64 and per elastomer (geometric means with 95%
t-intervals), each network of build/entry215/ARM-FOLD/UNIT scored on its unit's three full runs (the same runs
in both arms' registries, make_data.py's gate) with entry 191's functions. Entry 216 (`score.py C`): C over H,
then C over R.

    python reports/cross_sensor_response_gpu/entry215/score.py > \\
        reports/cross_sensor_response_gpu/entry215/logs/score.log
    python reports/cross_sensor_response_gpu/entry215/score.py C > \\
        reports/cross_sensor_response_gpu/entry215/logs/score216.log
"""

from __future__ import annotations

import json
import runpy
import sys
from pathlib import Path

HERE = Path(__file__).parent
E191 = runpy.run_path(str(HERE.parent / "entry191" / "score.py"))
ROOT = Path("build/entry215")


def robot_seconds(arm: str) -> list[float]:
    """Each unit's calibration robot seconds in `arm`, in entry 191's unit order."""
    return [json.loads((ROOT / f"{arm}-{f}" / u / "calibration.json").read_text())["calib_seconds"]
            for f, u in E191["PAIRS"]]


NAMES = {"R": "random cells and loads", "C": "random cells, loads in turn"}


def main(arm: str = "R") -> None:
    """Rule 1, then `arm` over H (and entry 216's C over R), per fresh validation unit."""
    h, other = robot_seconds("H"), robot_seconds(arm)
    same = sum(abs(a - b) < 1e-6 for a, b in zip(h, other, strict=True))
    print(f"rule 1: the two plans take the same robot time for {same} of {len(h)} units "
          f"({min(h):.2f}-{max(h):.2f} s)")
    rmse = E191["scored"](dict.fromkeys("HRC" if arm == "C" else "HR", ROOT))
    print(f"\nrule 2, {arm} ({NAMES[arm]}) over H (Halton points), the plan alone, per fresh validation unit")
    E191["ratio_table"](rmse, arm, "H", dump=arm == "R")
    if arm == "C":
        print("\nrule 3, C over R, the plan alone, per fresh validation unit")
        E191["ratio_table"](rmse, "C", "R", dump=False)


if __name__ == "__main__":
    main(*sys.argv[1:])
