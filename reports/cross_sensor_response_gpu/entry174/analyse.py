"""Research log entry 174's reading: fleet88's designed plan at 30 and 60 s over a second draw of the start
network, read as entry 173 reads 120 s (rule 1: references and plans equal entry 154's, the start network
differs; rule 2: each cell for draw 0, draw 1 and both, against entry 165's references of three starts).
Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry174/analyse.py > \\
        reports/cross_sensor_response_gpu/entry174/logs/analyse.log
"""

import runpy
from pathlib import Path

HERE = Path(__file__).parent
E173 = runpy.run_path(str(HERE.parent / "entry173" / "analyse.py"))

if __name__ == "__main__":
    E173["read"]({0: HERE.parent / "entry154", 1: HERE / "fleet88_d1"}, (30.0, 60.0), "entry 154")
