"""Research log entry 138's reading: every joint fit with ordinary use with each barometer's level of its
plan's rows left free inside the fit, on today's recipe, against entry 130's run of it. Gate: the references'
rows and every plan-alone row equal entry 130's. Reading: the free level over entry 130 per unit for every
method, each unit's draws averaged, and the validation units' means per draw. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry138/analyse.py
"""

import runpy
from pathlib import Path

HERE = Path(__file__).parent
START = runpy.run_path(str(HERE.parent / "entry132" / "analyse.py"))  # its reading against entry 130

if __name__ == "__main__":
    START["read_arm"](HERE, "level free")
