"""Research log entry 127's reading: entry 121's other16 rescorings with every job with ordinary use given
its unit's other plan's joint codes (designed <-> `cover_informative`). Gate: the references' rows and every
plan-alone row equal entry 121's. Reading: swapped over entry 121's per unit for every method, each unit's
draws averaged, and the validation units' means per draw. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry127/analyse.py
"""

import runpy
from pathlib import Path

HERE = Path(__file__).parent
SPLIT = runpy.run_path(str(HERE.parent / "entry126" / "analyse.py"))  # entries 121 and 123's readings, loaded
BEFORE, BASE, PAIRED = SPLIT["COLD"], SPLIT["BEFORE"], SPLIT["PAIRED"]
ALONE = ("response@designed", "response@cover_informative")


def gate(root: Path, d: int, k: int, recipe: Path = BEFORE, label: str = "") -> bool:
    """The references' rows and the plan-alone rows of draw d, fold k under root equal the recipe's run under
    `recipe` (entry 121's here; entry 132 gives entry 130's, and a label for the printed line)."""
    equal, n, moved = BASE["data_check"](BASE["rows"](root, d, k), BASE["rows"](recipe, d, k), ALONE)
    ok = equal and moved == 0.0
    print(f"gate, {label}draw {d}, fold {k}: references and plans {'equal' if equal else 'DIFFER'}, "
          f"the plans alone's {n} RMSEs move by up to {moved:.2g}: {'passed' if ok else 'FAILED'}")
    return ok


def read(root: Path, label: str, what: str, recipe: Path = BEFORE, versus: str = "121", gate_label: str = ""
         ) -> None:
    """The gate on every run under root, then, if it passed, root's arm (`label`) over the recipe's run under
    `recipe` (entry 121's, `versus`) per unit (entries 128, 130 and 132 read it too)."""
    ran = [(d, k) for d in (0, 1, 2) for k in BASE["FOLDS"]
           if (BASE["run_dir"](root, d, k) / "metrics.json").is_file()]
    if all([gate(root, d, k, recipe, gate_label) for d, k in ran]):
        PAIRED["paired_arms"]({label: root, versus: recipe}, what)
    else:
        print("gate failed: no row with ordinary use is read")


def main() -> None:
    read(HERE, "swapped", "swapped codes over their own")


if __name__ == "__main__":
    main()
