"""Research log entry 180's reading: the `--use-log` networks (build/entry178/L, `run.sh`) scored on the
units' full runs as entry 178's arms are, against entry 178's A and B and entry 179's C2, per unit, geometric
means with 95% t-intervals over units.

    python reports/cross_sensor_response_gpu/entry180/score.py > \\
        reports/cross_sensor_response_gpu/entry180/logs/score.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

HERE = Path(__file__).parent
table = runpy.run_path(str(HERE.parent / "entry179" / "score.py"))["table"]


if __name__ == "__main__":
    table("L", ("A", "B", "C2"))
