"""Research log entry 167's reading: are three starts enough? Folds 0 and 1's fresh units, each reference
kept over five starts (entry 164's three and this entry's two) over the one kept over three, per unit. Usage,
from the repository root:

    python reports/cross_sensor_response_gpu/entry167/analyse.py
"""

import runpy
from pathlib import Path

from anytip.report.cross_sensor import paired_interval, paired_text
from anytip.rundir import read_json

HERE = Path(__file__).parent
E164 = runpy.run_path(str(HERE.parent / "entry164" / "analyse.py"))
KEYS = E164["KEYS"]


def main() -> None:
    got = E164["starts"]()
    for k in (0, 1):
        rows = read_json(HERE / f"other16f_seed{k}" / "references.json")["rows"]
        got |= {(r["unit"], r["start"]): r for r in rows}
    units = sorted({u for u, _ in got})
    tested = [u for u in units if len({got[u, j]["test_rows"] for j in range(5)}) != 1]
    print(f"rule 1: {len(units)} units, each with five starts on one test set"
          + (f"; DIFFER: {tested}" if tested else ""))
    three, five = E164["kept"](got, units, range(3)), E164["kept"](got, units, range(5))
    print("rule 2: the reference kept over five starts over the one kept over three, per unit: "
          + "; ".join(f"{n} x{paired_text([five[u][k] / three[u][k] for u in units])}"
                      for n, k in KEYS.items()))
    _, lo, hi = paired_interval([five[u][KEYS["force"]] / three[u][KEYS["force"]] for u in units])
    print("rule 3: " + ("three starts are not enough (upper bound below 0.99)" if hi < 0.99 else
                        "three starts stand (lower bound at or above 0.99)" if lo >= 0.99 else "between"))
    moved = sum(five[u]["start"] >= 3 for u in units)
    print(f"{moved} of {len(units)} units keep start 3 or 4")


if __name__ == "__main__":
    main()
