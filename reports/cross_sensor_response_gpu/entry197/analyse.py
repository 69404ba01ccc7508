"""Research log entry 197's reading: new over old `wall_s` with a busy neighbour core, paired per (unit, arm,
round), entry 172's table on this entry's log. From the repository root:

    python reports/cross_sensor_response_gpu/entry197/analyse.py > \\
        reports/cross_sensor_response_gpu/entry197/logs/analyse.log
"""

import runpy
from pathlib import Path

HERE = Path(__file__).parent
E172 = runpy.run_path(str(HERE.parent / "entry172" / "analyse.py"))

if __name__ == "__main__":
    print("(rule 1 below is entry 172's; the numpy step moves each network by rounding: no pair is equal)")
    E172["main"](HERE / "logs" / "time_calibrate.log", "rule 1 of entry 197")
