"""Research log entry 193's reading: rule 1 (D and X read the rows entry 192's F read), then log(D / F) and
log(X / F) per fresh validation unit, force and angle, over all 64 and per elastomer (entry 191's functions),
each network scored on its unit's three full runs.

    python reports/cross_sensor_response_gpu/entry193/score.py > \\
        reports/cross_sensor_response_gpu/entry193/logs/score.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

E191 = runpy.run_path(str(Path(__file__).parent.parent / "entry191" / "score.py"))

if __name__ == "__main__":
    roots = {"F": Path("build/entry192"), "D": Path("build/entry193"), "X": Path("build/entry193")}
    for arm in "DX":
        print(E191["same_rows"]({a: roots[a] for a in ("F", arm)}))
    rmse = E191["scored"](roots)
    for arm, seconds in (("D", "1,200"), ("X", "2,400")):
        which = "rule 2" if arm == "D" else "beside rule 2"
        print(f"\n{which}: {arm} (weighed as {seconds} s) over F (as 600 s), the designed plan of 30 s, "
              "per fresh unit")
        E191["ratio_table"](rmse, arm, "F", dump=arm == "X")
