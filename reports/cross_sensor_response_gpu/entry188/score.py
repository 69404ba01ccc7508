"""Research log entry 188's reading: rule 1 (P1's networks against entry 183's Ad and entry 182's A120), then
P0.25 and P4 over P1 per unit, force and angle (geometric means with 95% t-intervals over the 16 units), each
network of build/entry188/PART/ARM/UNIT scored on its unit's three full runs as entry 187 scored its arms.

    python reports/cross_sensor_response_gpu/entry188/score.py > \\
        reports/cross_sensor_response_gpu/entry188/logs/score.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

HERE = Path(__file__).parent
E187 = runpy.run_path(str(HERE.parent / "entry187" / "score.py"))
GATES = {"A": ("entry183", "Ad"), "B": ("entry182", "A120")}


if __name__ == "__main__":
    E187["main"](HERE, ("P1", "P0.25", "P4"), GATES)
