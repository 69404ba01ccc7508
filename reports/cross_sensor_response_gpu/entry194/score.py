"""Research log entry 194's reading: rule 1 (D reads the rows entry 191's S read), then log(D / S) per fresh
validation unit, force and angle, over all 64 and per elastomer (entry 191's functions), each network scored
on its unit's three full runs.

    python reports/cross_sensor_response_gpu/entry194/score.py > \\
        reports/cross_sensor_response_gpu/entry194/logs/score.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

E191 = runpy.run_path(str(Path(__file__).parent.parent / "entry191" / "score.py"))

if __name__ == "__main__":
    roots = {"S": Path("build/entry191"), "D": Path("build/entry194")}
    print(E191["same_rows"](roots))
    print("\nrule 2: D (weighed as 1,200 s) over S (as 600 s), the designed plan of 120 s, per unit")
    E191["ratio_table"](E191["scored"](roots), "D", "S")
