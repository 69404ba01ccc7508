"""Research log entry 204's accuracy reading: rule 1 (C and entry 196's N read the same rows), then log(C / N)
per fresh validation unit, force and angle, over all 64 and per elastomer (entry 191's functions), each
network scored on its unit's three full runs.

    python reports/cross_sensor_response_gpu/entry204/score.py > \\
        reports/cross_sensor_response_gpu/entry204/logs/score.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

E191 = runpy.run_path(str(Path(__file__).parent.parent / "entry191" / "score.py"))
ROOTS = {"N": Path("build/entry196"), "C": Path("build/entry204")}

if __name__ == "__main__":
    print(E191["same_rows"](ROOTS))
    print("\nrule 2, C (compiled step) over N (entry 196, numpy step), per fresh validation unit")
    E191["ratio_table"](E191["scored"](ROOTS), "C", "N", dump=False)
