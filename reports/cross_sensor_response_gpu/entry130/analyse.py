"""Research log entry 130's reading: entry 121's other16 rescorings with every job with ordinary use learning
its correction from its plan's residuals less each barometer's mean, read as entry 127's: the gate (references
and plan-alone rows equal entry 121's), then centred over entry 121's per unit for every method and the
validation units' means per draw. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry130/analyse.py
"""

import runpy
from pathlib import Path

HERE = Path(__file__).parent
SWAP = runpy.run_path(str(HERE.parent / "entry127" / "analyse.py"))

if __name__ == "__main__":
    SWAP["read"](HERE, "centred", "centred over entry 121's correction")
