"""Research log entry 129's reading: entry 121's other16 rescorings with 40 steps of the joint fit with
ordinary use, read as entry 127's: the gate (references and plan-alone rows equal entry 121's), then 40 over
10 steps per unit for every method and the validation units' means per draw. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry129/analyse.py
"""

import runpy
from pathlib import Path

HERE = Path(__file__).parent
SWAP = runpy.run_path(str(HERE.parent / "entry127" / "analyse.py"))

if __name__ == "__main__":
    SWAP["read"](HERE, "40 steps", "40 steps over 10")
