"""Research log entry 135's reading: entry 127's swap of joint codes (designed <-> `cover_informative`, every
job with ordinary use) on today's recipe, against entry 130's run of it. Gate: the references' rows and every
plan-alone row equal entry 130's. Reading: swapped over entry 130 per unit for every method, each unit's draws
averaged, and the validation units' means per draw. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry135/analyse.py
"""

import runpy
from pathlib import Path

HERE = Path(__file__).parent
START = runpy.run_path(str(HERE.parent / "entry132" / "analyse.py"))  # its reading against entry 130

if __name__ == "__main__":
    START["read_arm"](HERE, "swapped")
