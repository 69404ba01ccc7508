"""Research log entry 131's reading: fleet88's rescoring with entry 130's centred correction for the jobs
with ordinary use, against entry 122, read as entry 124's: the gate (references and plan-alone rows equal
entry 122's), the choice on validation units ((a) at least 2% lower for the designed plan with ordinary use
and `cover_informative`'s not higher; (b) both registries' 16 validation unit-folds, other16's from entry
130), then the held-out units per unit. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry131/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
GPU = HERE.parent
OFF = runpy.run_path(str(GPU / "entry124" / "analyse.py"))
FLEET88, BASE = OFF["FLEET88"], OFF["OTHER16"]  # entries 122 and 121's readings, as entry 124 loaded them
ALONE = ("response@designed", "response@cover_informative")

RECIPE = (GPU / "entry122", GPU / "entry121")  # the recipe in place before: its fleet88 and other16 runs


def gate(root: Path = HERE, recipe: Path = RECIPE[0]) -> bool:
    """The references' rows and every plan-alone row of both folds under root equal the recipe's run."""
    ok = True
    for k in FLEET88["FOLDS"]:
        new, old = (FLEET88["rows"](r, k) for r in (root, recipe))
        equal, n, moved = BASE["data_check"](new, old, ALONE)
        ok &= equal and moved == 0.0
        print(f"gate, fold {k}: references and plans {'equal' if equal else 'DIFFER'}, the plans alone's {n} "
              f"RMSEs move by up to {moved:.2g}")
    return ok


def main(root: Path = HERE, other16: Path = GPU / "entry130", arm: str = "centred",
         recipe: tuple[Path, Path] = RECIPE) -> None:
    """The gate, the choice (fleet88's run under root, other16's arm under other16, against `recipe`) and the
    held-out units (entry 133 reads it too)."""
    if not gate(root, recipe[0]):
        print("gate failed: no row with ordinary use is read")
        return
    taken = OFF["choice"](root, other16, arm, by=0.02, recipe=recipe)
    cover = [np.mean(list(OFF["fleet88_losses"](r, "response+use@cover_informative").values()))
             for r in (root, recipe[0])]
    higher = cover[0] > cover[1]
    print(f"rule 1a, response+use@cover_informative: {arm} {cover[0]:.5f}, on {cover[1]:.5f}: "
          f"{'higher' if higher else 'not higher'}; "
          f"the choice with it: {'taken' if taken and not higher else 'not taken'}")
    OFF["held_out"](root, arm, recipe[0])


if __name__ == "__main__":
    main()
