"""Research log entry 195: entry 191's 32 fresh units of the other elastomer pressed through the designed 60 s
plan too (`plan60`, added to `data/val191o`; their other runs are simulated again and found unchanged).

    python reports/cross_sensor_response_gpu/entry195/make_data.py > \\
        reports/cross_sensor_response_gpu/entry195/logs/data.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

E192 = runpy.run_path(str(Path(__file__).parent.parent / "entry192" / "make_data.py"))
E191 = runpy.run_path(str(Path(__file__).parent.parent / "entry191" / "make_data.py"))

if __name__ == "__main__":
    E192["main"](("full", "plan120", "plan30", "plan60"), E191["REGISTRIES"][1:])
