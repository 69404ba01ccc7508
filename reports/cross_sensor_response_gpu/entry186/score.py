"""Research log entry 186's reading: rule 1 (D1's seconds read against entry 183's Ld's), then the arms of
build/entry186/ARM/UNIT (`run.sh`) scored on each unit's three full runs of data/other16 as entry 183 scored
its arms, against entry 183's A, Ad and Ld (build/entry183/): per unit, geometric means with 95% t-intervals
over the 16 units.

    python reports/cross_sensor_response_gpu/entry186/score.py > \\
        reports/cross_sensor_response_gpu/entry186/logs/score.log
"""

from __future__ import annotations

import json
import runpy
from pathlib import Path

import numpy as np

from anytip.data.registry import Registry

HERE = Path(__file__).parent
E178 = runpy.run_path(str(HERE.parent / "entry178" / "score.py"))
E181 = runpy.run_path(str(HERE.parent / "entry181" / "score.py"))
interval = runpy.run_path(str(HERE.parent / "entry183" / "score.py"))["interval"]
UNITS, OUTPUTS = E181["UNITS"], E181["OUTPUTS"]
ROOTS = {"D1": Path("build/entry186"), "D3": Path("build/entry186"),
         **{a: Path("build/entry183") for a in ("A", "Ad", "Ld")}}


def read(arm: str, unit: str) -> float:
    return float(json.loads((ROOTS[arm] / arm / unit / "calibration.json").read_text())["unlabeled_seconds"])


def main() -> None:
    same = sum(abs(read("D1", u) - read("Ld", u)) < 1e-9 for u in UNITS)
    print(f"rule 1: D1 reads entry 183's Ld's seconds for {same} of {len(UNITS)} units")
    for arm in ("D1", "D3"):
        seconds = [read(arm, u) for u in UNITS]
        print(f"{arm}: {min(seconds):.1f}-{max(seconds):.1f} contact-s read")
    registry = Registry("data/other16")
    rmse = {(a, u): E178["scored"](registry, u, a, root) for a, root in ROOTS.items() for u in UNITS}
    print("\nrule 2, per unit (geometric mean [95% t-interval] over units)")
    print("| ratio | force | angle |")
    print("|---|---|---|")
    for top, bottom in (("D3", "D1"), ("D3", "Ad"), ("D3", "A"), ("D1", "Ld")):
        cells = [interval([np.log(rmse[top, u][k] / rmse[bottom, u][k]) for u in UNITS]) for k in OUTPUTS]
        print(f"| {top} over {bottom} | " + " | ".join(cells) + " |")
    print("\n" + json.dumps({f"{a} {u}": rmse[a, u] for a in ("D1", "D3") for u in UNITS}))


if __name__ == "__main__":
    main()
