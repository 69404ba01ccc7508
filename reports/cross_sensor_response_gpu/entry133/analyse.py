"""Research log entry 133's reading: entry 122's fleet88 rescorings with entry 132's `rounds` start, against
entry 131's run of today's recipe, read as entry 131's: the gate (references and plan-alone rows equal entry
131's), the choice on validation units (entry 124's rule 1 against entries 131 and 130, other16's arm entry
132's `rounds`), then the held-out units per method. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry133/analyse.py
"""

import runpy
from pathlib import Path

HERE = Path(__file__).parent
GPU = HERE.parent
CENTRED = runpy.run_path(str(GPU / "entry131" / "analyse.py"))

if __name__ == "__main__":
    CENTRED["main"](HERE, GPU / "entry132" / "rounds", "rounds", (GPU / "entry131", GPU / "entry130"))
