"""Research log entry 152's reading: entry 151's, for the design exchanged within each press's force level
(`entry152/at120`): rule 1 (gate), rule 2 (other16's validation units, with the paired interval) and rule 3
(held out, L or P). From the repository root:

    python reports/cross_sensor_response_gpu/entry152/analyse.py
"""

import runpy
from pathlib import Path

HERE = Path(__file__).parent
E151 = runpy.run_path(str(HERE.parent / "entry151" / "analyse.py"))
NEW = HERE / "at120"


def main() -> None:
    draws = E151["draws_done"](NEW)
    print(f"draws with all four folds: {draws}")
    ok = all(E151["gate"](d, k, NEW) for d in draws for k in E151["FOLDS"])
    print(f"rule 1: {'holds' if ok else 'FAILS'}")
    change, upper = E151["validation"](draws, NEW)
    worth = change["response@designed"] <= -0.03 and change["response+use@designed"] <= 0 and upper < 1
    print(f"rule 2: {'worth scoring on fleet88' if worth else 'not taken'}")
    print("rule 3, the within-level design over entry 146's, per unit, draws averaged:")
    lo, hi = E151["held_out"](draws, NEW, "within level")
    print(f"  reading (force, the plan alone): {'L' if hi <= 1.02 else 'P' if lo >= 1.02 else 'between'}")


if __name__ == "__main__":
    main()
