"""Research log entry 125's reading: entry 123's other16 rescorings (the correction off, at most 2,048 plan
rows in the joint fit with ordinary use) against the same with at most 128: 128 over 2,048 per unit for every
method, each unit's draws averaged, and the validation units' means per draw. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry125/analyse.py
"""

import runpy
from pathlib import Path

HERE = Path(__file__).parent
PAIRING = runpy.run_path(str(HERE.parent / "entry123" / "analyse.py"))  # its paired_arms
ARMS = {"128": HERE, "2048": HERE.parent / "entry123"}


def main() -> None:
    PAIRING["paired_arms"](ARMS, "128 over 2048 plan rows in the joint fit")


if __name__ == "__main__":
    main()
