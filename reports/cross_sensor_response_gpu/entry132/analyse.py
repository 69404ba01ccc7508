"""Research log entry 132's reading: entry 121's other16 rescorings, every job with ordinary use starting its
joint fit elsewhere (arm `rounds`: the search's rounds from the plan's own codes; arm `free`: the label-free
search from the encoder's codes), against entry 130's run of today's recipe. Gate: the references' rows and
every plan-alone row equal entry 130's. Reading: each arm over entry 130 per unit for every method, each
unit's draws averaged, and the validation units' means per draw. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry132/analyse.py
"""

import runpy
from pathlib import Path

HERE = Path(__file__).parent
RECIPE = HERE.parent / "entry130"  # today's recipe: entry 121's driver gives its runs back bit for bit
SWAP = runpy.run_path(str(HERE.parent / "entry127" / "analyse.py"))  # its gate and reading


def read_arm(root: Path, label: str) -> None:
    """The gate against entry 130 on every run under root, then root's arm (`label`) over entry 130 per unit
    (entries 135 and 136 read it too)."""
    SWAP["read"](root, label, f"{label} over entry 130", RECIPE, "130", f"{root.name}, ")


def main() -> None:
    for arm in ("rounds", "free"):
        read_arm(HERE / arm, arm)


if __name__ == "__main__":
    main()
