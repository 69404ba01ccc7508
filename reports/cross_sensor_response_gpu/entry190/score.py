"""Research log entry 190's reading: rule 1 (S and H read the same rows), then log(S / H) per validation
unit-fold, force and angle, over all 12 and per registry (geometric means with 95% t-intervals), each network
of build/entry190/ARM-FOLD/UNIT scored on its unit's three full runs as entries 183-189 scored theirs.

    python reports/cross_sensor_response_gpu/entry190/score.py > \\
        reports/cross_sensor_response_gpu/entry190/logs/score.log
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
ROOT = Path("build/entry190")
PAIRS = [("0", "SIM23-004"), ("0", "SIM23-011"), ("1", "SIM23-010"), ("1", "SIM23-015"), ("2", "SIM23-000"),
         ("2", "SIM23-004"), ("3", "SIM23-008"), ("3", "SIM23-014"), ("f", "SIM40-007"), ("f", "SIM40-009"),
         ("f", "SIM40-034"), ("f", "SIM40-068")]


def record(arm: str, fold: str, unit: str) -> dict:
    return json.loads((ROOT / f"{arm}-{fold}" / unit / "calibration.json").read_text())


def main() -> None:
    rows = {a: [record(a, f, u)["unlabeled_samples"] for f, u in PAIRS] for a in "SH"}
    same = sum(s == h for s, h in zip(rows["S"], rows["H"], strict=True))
    held = [record("H", f, u)["unlabeled_seconds"] for f, u in PAIRS]
    print(f"rule 1: S and H read the same rows for {same} of {len(PAIRS)} unit-folds "
          f"({min(held):.1f}-{max(held):.1f} contact-s)")
    registries = {"other16": Registry("data/other16"), "fleet88": Registry("data/fleet88p")}
    rmse = {(a, f, u): E178["scored"](registries["fleet88" if f == "f" else "other16"], u, f"{a}-{f}", ROOT)
            for a in "SH" for f, u in PAIRS}
    print("\nrule 2, S (weighed as 600 s) over H (as held), per validation unit-fold")
    print("| unit-folds | force | angle |")
    print("|---|---|---|")
    for name, keep in (("all 12", lambda f: True), ("other16's 8", lambda f: f != "f"),
                       ("fleet88's 4", lambda f: f == "f")):
        chosen = [(f, u) for f, u in PAIRS if keep(f)]
        cells = [interval([np.log(rmse["S", f, u][k] / rmse["H", f, u][k]) for f, u in chosen])
                 for k in E178["OUTPUTS"]]
        print(f"| {name} | " + " | ".join(cells) + " |")
    print("\n" + json.dumps({f"{a} {f} {u}": v for (a, f, u), v in rmse.items()}))


if __name__ == "__main__":
    main()
