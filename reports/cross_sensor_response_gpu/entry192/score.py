"""Research log entry 192's reading: rule 1 (F and Q read the same rows), then log(Q / F) per fresh validation
unit, force and angle, over all 64 and per elastomer, each network of build/entry192/ARM-FOLD/UNIT scored on
its unit's three full runs (entry 191's functions).

    python reports/cross_sensor_response_gpu/entry192/score.py > \\
        reports/cross_sensor_response_gpu/entry192/logs/score.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

E191 = runpy.run_path(str(Path(__file__).parent.parent / "entry191" / "score.py"))

if __name__ == "__main__":
    roots = dict.fromkeys("FQ", Path("build/entry192"))
    print(E191["same_rows"](roots))
    print("\nrule 2, Q (weighed as 150 s) over F (as 600 s), the designed plan of 30 s, per fresh unit")
    E191["ratio_table"](E191["scored"](roots), "Q", "F")
