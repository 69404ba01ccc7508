"""Research log entry 187's reading: rule 1 (U1P1's networks against entry 186's D1 and entry 185's U1, the
gate as amended; entry 184's W60, as first written, asked for 0.001 s more than its logs hold), then U4P1,
U1P4 and U4P4 over U1P1 per unit, force and angle (geometric means with 95% t-intervals over the 16 units),
each network of build/entry187/PART/ARM/UNIT scored on its unit's three full runs as entries 184 and 186
scored theirs (part A on data/other16, part B on data/fleet88p).

    python reports/cross_sensor_response_gpu/entry187/score.py > \\
        reports/cross_sensor_response_gpu/entry187/logs/score.log
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
PARTS = {"A": (E181["UNITS"], "data/other16"), "B": (E178["UNITS"], "data/fleet88p")}
GATES = {"A": ("entry186", "D1"), "B": ("entry185", "U1")}
ARMS = ("U1P1", "U4P1", "U1P4", "U4P4")


def hashes(path: Path, width: int) -> dict[tuple[str, ...], str]:
    """{(fields...): hash} of a run.log's lines of `width` fields, the last a network's hash prefix."""
    rows = (line.split() for line in path.read_text().splitlines())
    return {tuple(r[:-1]): r[-1] for r in rows if len(r) == width}


def main(here: Path = HERE, arms: tuple[str, ...] = ARMS, gates: dict[str, tuple[str, str]] = GATES) -> None:
    """Rule 1 (each part's first arm against its gate's networks) and rule 2 (the other arms over the
    first) of the entry whose scripts are in `here`, its networks in build/<here's name>/PART/ARM/UNIT."""
    ours, first = hashes(here / "logs" / "run.log", 4), arms[0]
    scores = {}
    for part, (units, registry) in PARTS.items():
        entry, arm = gates[part]
        before = hashes(HERE.parent / entry / "logs" / "run.log", 3)
        equal = sum(ours[part, first, u] == before[arm, u] for u in units)
        print(f"rule 1, part {part}: {first} equals {entry}'s {arm} for {equal} of {len(units)} units")
        reg, root = Registry(registry), Path("build") / here.name / part
        rmse = {(a, u): E178["scored"](reg, u, a, root) for a in arms for u in units}
        print(f"\nrule 2, part {part}, per unit (geometric mean [95% t-interval] over units)")
        print("| ratio | force | angle |")
        print("|---|---|---|")
        for top in arms[1:]:
            cells = [interval([np.log(rmse[top, u][k] / rmse[first, u][k]) for u in units])
                     for k in E178["OUTPUTS"]]
            print(f"| {top} over {first} | " + " | ".join(cells) + " |")
        print()
        scores |= {f"{part} {a} {u}": v for (a, u), v in rmse.items()}
    print(json.dumps(scores))


if __name__ == "__main__":
    main()
