"""Research log entry 184's reading: rule 1 (W's rows read against L's, L's hashes against entry 182's log),
and W over L per budget, per unit, force and angle (geometric means with 95% t-intervals over the 16 units),
each network of build/entry182/ARM/UNIT scored on the unit's three full runs of data/fleet88p as entry 182
scored them.

    python reports/cross_sensor_response_gpu/entry184/score.py > \\
        reports/cross_sensor_response_gpu/entry184/logs/score.log
"""

from __future__ import annotations

import hashlib
import json
import runpy
from pathlib import Path

from anytip.data.registry import Registry

HERE = Path(__file__).parent
E178 = runpy.run_path(str(HERE.parent / "entry178" / "score.py"))
E182 = runpy.run_path(str(HERE.parent / "entry182" / "score.py"))
UNITS, ROOT, BUDGETS = E178["UNITS"], Path("build/entry182"), ("120", "60", "30")


def read_seconds(arm: str, unit: str) -> float:
    return float(json.loads((ROOT / arm / unit / "calibration.json").read_text())["unlabeled_seconds"])


def main() -> None:
    logged = E182["hashes"](HERE.parent / "entry182" / "logs" / "run.log")
    for b in BUDGETS:
        same = sum(abs(read_seconds(f"W{b}", u) - read_seconds(f"L{b}", u)) <= 1e-3 for u in UNITS)
        equal = sum(hashlib.sha256((ROOT / f"L{b}" / u / "model.safetensors").read_bytes()).hexdigest()[:16]
                    == logged[f"L{b}", u] for u in UNITS)
        print(f"rule 1, {b} s: W reads L's seconds for {same} of {len(UNITS)} units; L's networks equal "
              f"entry 182's log for {equal}")
    registry = Registry("data/fleet88p")
    rmse = {(f"{a}{b}", u): E178["scored"](registry, u, f"{a}{b}", ROOT) for a in "LW" for b in BUDGETS
            for u in UNITS}
    print("\nrule 2, per unit (geometric mean [95% t-interval] over units)")
    E178["ratio_table"](rmse, tuple((f"W{b}", f"L{b}") for b in BUDGETS))
    print("\n" + json.dumps({f"{a} {u}": v for (a, u), v in rmse.items() if a.startswith("W")}))


if __name__ == "__main__":
    main()
