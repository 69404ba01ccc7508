"""Research log entry 185's reading: rule 1 (U1's seconds read against entry 182's L60's), then each arm of
build/entry185/ARM/UNIT (`run.sh`) scored on the unit's three full runs of data/fleet88p as entry 182 scored
them, over entry 182's A60 and over U3, and U3 over entry 182's A120: per unit, geometric means with 95%
t-intervals over the 16 units.

    python reports/cross_sensor_response_gpu/entry185/score.py > \\
        reports/cross_sensor_response_gpu/entry185/logs/score.log
"""

from __future__ import annotations

import json
import runpy
from pathlib import Path

from anytip.data.registry import Registry

HERE = Path(__file__).parent
E178 = runpy.run_path(str(HERE.parent / "entry178" / "score.py"))
UNITS, ARMS = E178["UNITS"], ("U60", "U120", "U1", "U3")
ROOTS = {**{a: Path("build/entry185") for a in ARMS}, **{a: Path("build/entry182") for a in ("A60", "A120")}}


def read(root: Path, arm: str, unit: str) -> float:
    return float(json.loads((root / arm / unit / "calibration.json").read_text())["unlabeled_seconds"])


def main() -> None:
    same = sum(abs(read(ROOTS["U1"], "U1", u) - read(Path("build/entry182"), "L60", u)) < 1e-9 for u in UNITS)
    print(f"rule 1: U1 reads entry 182's L60's seconds for {same} of {len(UNITS)} units")
    for arm in ARMS:
        seconds = [read(ROOTS[arm], arm, u) for u in UNITS]
        print(f"{arm}: {min(seconds):.1f}-{max(seconds):.1f} contact-s read")
    registry = Registry("data/fleet88p")
    rmse = {(a, u): E178["scored"](registry, u, a, root) for a, root in ROOTS.items() for u in UNITS}
    print("\nrule 2, per unit (geometric mean [95% t-interval] over units)")
    E178["ratio_table"](rmse, (*((a, "A60") for a in ARMS), *((a, "U3") for a in ARMS[:3]), ("U3", "A120")))
    print("\n" + json.dumps({f"{a} {u}": rmse[a, u] for a in ARMS for u in UNITS}))


if __name__ == "__main__":
    main()
