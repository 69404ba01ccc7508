"""Research log entry 128's reading: entry 121's other16 rescorings with every job with ordinary use
trained on its transferred rows alone (its plan's labeled rows left out of its network), read as entry 127's:
the gate (references and plan-alone rows equal entry 121's), then rows out over entry 121's per unit for every
method and the validation units' means per draw. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry128/analyse.py
"""

import runpy
from pathlib import Path

HERE = Path(__file__).parent
SWAP = runpy.run_path(str(HERE.parent / "entry127" / "analyse.py"))

if __name__ == "__main__":
    SWAP["read"](HERE, "rows out", "rows out over rows in")
