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


def gate() -> bool:
    ok = True
    for k in FLEET88["FOLDS"]:
        new, old = (FLEET88["rows"](root, k) for root in (HERE, GPU / "entry122"))
        equal, n, moved = BASE["data_check"](new, old, ALONE)
        ok &= equal and moved == 0.0
        print(f"gate, fold {k}: references and plans {'equal' if equal else 'DIFFER'}, the plans alone's {n} "
              f"RMSEs move by up to {moved:.2g}")
    return ok


def main() -> None:
    if not gate():
        print("gate failed: no row with ordinary use is read")
        return
    taken = OFF["choice"](HERE, GPU / "entry130", "centred", by=0.02)
    cover = [np.mean(list(OFF["fleet88_losses"](root, "response+use@cover_informative").values()))
             for root in (HERE, GPU / "entry122")]
    higher = cover[0] > cover[1]
    print(f"rule 1a, response+use@cover_informative: centred {cover[0]:.5f}, on {cover[1]:.5f}: "
          f"{'higher' if higher else 'not higher'}; "
          f"the choice with it: {'taken' if taken and not higher else 'not taken'}")
    OFF["held_out"](HERE, "centred")


if __name__ == "__main__":
    main()
