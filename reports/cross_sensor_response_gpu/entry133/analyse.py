"""Research log entry 133's reading: entry 122's fleet88 rescorings with entry 132's `rounds` start, against
entry 131's run of today's recipe. Gate: the references' rows and every plan-alone row equal entry 131's. The
choice on validation units (entry 124's rule 1 against entries 131 and 130, other16's arm entry 132's
`rounds`), then the held-out units per method. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry133/analyse.py
"""

import runpy
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
GPU = HERE.parent
OFF = runpy.run_path(str(GPU / "entry124" / "analyse.py"))
FLEET88, BASE = OFF["FLEET88"], OFF["OTHER16"]  # entries 122 and 121's readings, as entry 124 loaded them
ALONE = ("response@designed", "response@cover_informative")
RECIPE = (GPU / "entry131", GPU / "entry130")  # today's recipe on fleet88 and other16


def gate() -> bool:
    ok = True
    for k in FLEET88["FOLDS"]:
        new, old = (FLEET88["rows"](root, k) for root in (HERE, RECIPE[0]))
        equal, n, moved = BASE["data_check"](new, old, ALONE)
        ok &= equal and moved == 0.0
        print(f"gate, fold {k}: references and plans {'equal' if equal else 'DIFFER'}, the plans alone's {n} "
              f"RMSEs move by up to {moved:.2g}")
    return ok


def main() -> None:
    if not gate():
        print("gate failed: no row with ordinary use is read")
        return
    taken = OFF["choice"](HERE, GPU / "entry132" / "rounds", "rounds", by=0.02, recipe=RECIPE)
    cover = [np.mean(list(OFF["fleet88_losses"](root, "response+use@cover_informative").values()))
             for root in (HERE, RECIPE[0])]
    higher = cover[0] > cover[1]
    print(f"rule 1a, response+use@cover_informative: rounds {cover[0]:.5f}, on {cover[1]:.5f}: "
          f"{'higher' if higher else 'not higher'}; "
          f"the choice with it: {'taken' if taken and not higher else 'not taken'}")
    OFF["held_out"](HERE, "rounds", RECIPE[0])


if __name__ == "__main__":
    main()
