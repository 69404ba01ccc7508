"""Research log entry 195's reading: rule 1 (F and X read the same rows), then log(X / F) per fresh unit of
the other elastomer, force and angle (entry 191's functions), each network scored on its unit's three full
runs.

    python reports/cross_sensor_response_gpu/entry195/score.py > \\
        reports/cross_sensor_response_gpu/entry195/logs/score.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

E191 = runpy.run_path(str(Path(__file__).parent.parent / "entry191" / "score.py"))

if __name__ == "__main__":
    pairs = [(f, u) for f, u in E191["PAIRS"] if f[0] == "o"]
    roots = dict.fromkeys("FX", Path("build/entry195"))
    print(E191["same_rows"](roots, pairs))
    print("\nrule 2: X (weighed as 2,400 s) over F (as 600 s), the designed plan of 60 s, per fresh unit")
    E191["ratio_table"](E191["scored"](roots, pairs), "X", "F", groups=E191["GROUPS"][2:])
