"""Research log entry 182's reading: rule 1, the gate (A120 and L120's hashes in logs/run.log against entries
178 and 180's); each network of build/entry182/ARM/UNIT (`run.sh`) scored on the unit's three full runs in
data/fleet88p as entry 178 scored its arms; rules 2 and 4, per unit, geometric means with 95% t-intervals over
the 16 units.

    python reports/cross_sensor_response_gpu/entry182/score.py > \\
        reports/cross_sensor_response_gpu/entry182/logs/score.log
"""

from __future__ import annotations

import json
import runpy
from pathlib import Path

from anytip.data.registry import Registry

HERE = Path(__file__).parent
E178 = runpy.run_path(str(HERE.parent / "entry178" / "score.py"))
UNITS = E178["UNITS"]
ARMS = ("A120", "L120", "A60", "B60", "L60", "A30", "B30", "L30")


def hashes(path: Path) -> dict[tuple[str, str], str]:
    """{(arm, unit): the network's hash prefix} of a run.log's `ARM UNIT HASH` lines."""
    return {(a, u): h for a, u, h in (line.split() for line in path.read_text().splitlines())}


def gate() -> None:
    """Rule 1: A120 and L120 against entry 178's A and entry 180's L, unit by unit."""
    ours = hashes(HERE / "logs" / "run.log")
    for arm, entry, theirs in (("A120", "entry178", "A"), ("L120", "entry180", "L")):
        before = hashes(HERE.parent / entry / "logs" / "run.log")
        equal = sum(ours[arm, u] == before[theirs, u] for u in UNITS)
        print(f"rule 1: {arm}: {equal} of {len(UNITS)} networks equal {entry}'s arm {theirs} byte for byte")


def main() -> None:
    gate()
    registry = Registry("data/fleet88p")
    rmse = {(a, u): E178["scored"](registry, u, a, Path("build/entry182")) for a in ARMS for u in UNITS}
    for b in ("60", "30"):
        print(f"\nrule 2, {b} s, per unit (geometric mean [95% t-interval] over units)")
        E178["ratio_table"](rmse, ((f"B{b}", f"A{b}"), (f"L{b}", f"A{b}"), (f"L{b}", f"B{b}")))
    print("\nrule 4, against 120 s, per unit")
    E178["ratio_table"](rmse, tuple((f"L{b}", f"{a}120") for b in ("60", "30") for a in "AL"))
    print("\n" + json.dumps({f"{a} {u}": rmse[a, u] for a in ARMS for u in UNITS}))


if __name__ == "__main__":
    main()
