"""Research log entry 191's reading: rule 1 (S and H read the same rows), then log(S / H) per fresh validation
unit, force and angle, over all 64 and per elastomer (geometric means with 95% t-intervals), each network of
build/entry191/ARM-FOLD/UNIT scored on its unit's three full runs as entries 183-190 scored theirs.

    python reports/cross_sensor_response_gpu/entry191/score.py > \\
        reports/cross_sensor_response_gpu/entry191/logs/score.log
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
PAIRS = runpy.run_path(str(HERE / "units.py"))["PAIRS"]
ROOT = Path("build/entry191")


def record(arm: str, fold: str, unit: str) -> dict:
    return json.loads((ROOT / f"{arm}-{fold}" / unit / "calibration.json").read_text())


def main() -> None:
    rows = {a: [record(a, f, u)["unlabeled_samples"] for f, u in PAIRS] for a in "SH"}
    same = sum(s == h for s, h in zip(rows["S"], rows["H"], strict=True))
    held = [record("H", f, u)["unlabeled_seconds"] for f, u in PAIRS]
    print(f"rule 1: S and H read the same rows for {same} of {len(PAIRS)} units "
          f"({min(held):.1f}-{max(held):.1f} contact-s)")
    registries = {"f": Registry("data/val191d"), "o": Registry("data/val191o")}
    rmse = {(a, f, u): E178["scored"](registries[f[0]], u, f"{a}-{f}", ROOT) for a in "SH" for f, u in PAIRS}
    print("\nrule 2, S (weighed as 600 s) over H (as held), per fresh validation unit")
    print("| units | force | angle |")
    print("|---|---|---|")
    for name, keep in (("all 64", "fo"), ("default fingertip's 32 (SIM41)", "f"),
                       ("other elastomer's 32 (SIM24)", "o")):
        chosen = [(f, u) for f, u in PAIRS if f[0] in keep]
        cells = [interval([np.log(rmse["S", f, u][k] / rmse["H", f, u][k]) for f, u in chosen])
                 for k in E178["OUTPUTS"]]
        print(f"| {name} | " + " | ".join(cells) + " |")
    print("\n" + json.dumps({f"{a} {f} {u}": v for (a, f, u), v in rmse.items()}))


if __name__ == "__main__":
    main()
