"""Research log entry 192's reading: rule 1 (F and Q read the same rows), then log(Q / F) per fresh validation
unit, force and angle, over all 64 and per elastomer, each network of build/entry192/ARM-FOLD/UNIT scored on
its unit's three full runs (entry 191's scoring).

    python reports/cross_sensor_response_gpu/entry192/score.py > \\
        reports/cross_sensor_response_gpu/entry192/logs/score.log
"""

from __future__ import annotations

import json
import runpy
from pathlib import Path

import numpy as np

from anytip.data.registry import Registry

HERE = Path(__file__).parent
E178 = runpy.run_path(str(HERE.parent / "entry178" / "score.py"))
interval = runpy.run_path(str(HERE.parent / "entry183" / "score.py"))["interval"]
PAIRS = runpy.run_path(str(HERE.parent / "entry191" / "units.py"))["PAIRS"]
ROOT = Path("build/entry192")
GROUPS = (("all 64", "fo"), ("default fingertip's 32 (SIM41)", "f"), ("other elastomer's 32 (SIM24)", "o"))


def main() -> None:
    rows = {a: [json.loads((ROOT / f"{a}-{f}" / u / "calibration.json").read_text())["unlabeled_samples"]
                for f, u in PAIRS] for a in "FQ"}
    same = sum(x == y for x, y in zip(rows["F"], rows["Q"], strict=True))
    print(f"rule 1: F and Q read the same rows for {same} of {len(PAIRS)} units")
    registries = {"f": Registry("data/val191d"), "o": Registry("data/val191o")}
    rmse = {(a, f, u): E178["scored"](registries[f[0]], u, f"{a}-{f}", ROOT) for a in "FQ" for f, u in PAIRS}
    print("\nrule 2, Q (weighed as 150 s) over F (as 600 s), the designed plan of 30 s, per fresh unit")
    print("| units | force | angle |")
    print("|---|---|---|")
    for name, keep in GROUPS:
        chosen = [(f, u) for f, u in PAIRS if f[0] in keep]
        cells = [interval([np.log(rmse["Q", f, u][k] / rmse["F", f, u][k]) for f, u in chosen])
                 for k in E178["OUTPUTS"]]
        print(f"| {name} | " + " | ".join(cells) + " |")
    print("\n" + json.dumps({f"{a} {f} {u}": v for (a, f, u), v in rmse.items()}))


if __name__ == "__main__":
    main()
