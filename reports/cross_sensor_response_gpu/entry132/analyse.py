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
SWAP = runpy.run_path(str(HERE.parent / "entry127" / "analyse.py"))  # its gate; entries 121, 123 loaded
BASE, PAIRED = SWAP["BASE"], SWAP["PAIRED"]


def gate(root: Path, d: int, k: int) -> bool:
    """The references' rows and the plan-alone rows of draw d, fold k under root equal entry 130's."""
    return SWAP["gate"](root, d, k, RECIPE, f"{root.name}, ")


def main() -> None:
    for arm in ("rounds", "free"):
        root = HERE / arm
        ran = [(d, k) for d in (0, 1, 2) for k in BASE["FOLDS"]
               if (BASE["run_dir"](root, d, k) / "metrics.json").is_file()]
        if not ran:
            continue
        if all([gate(root, d, k) for d, k in ran]):
            PAIRED["paired_arms"]({arm: root, "130": RECIPE}, f"{arm} over entry 130")
        else:
            print(f"gate failed: no row of arm {arm} with ordinary use is read")


if __name__ == "__main__":
    main()
