"""Research log entry 141's table: each validation unit's margin of the variant 600 s design over the
design in place, log(loss with fleet88w6f's plan / loss with fleet88w6's), a unit's folds averaged, with a
95% t-interval over units. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry141/analyse.py
    python reports/cross_sensor_response_gpu/entry141/analyse.py entry145 fleet88w3 300   # entry 145's

A later entry gives its directory, the design in place's registry (the variant's is its name and f) and the
budget in seconds.
"""

import importlib.util
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path("reports/cross_sensor_response_gpu/entry141")
_spec = importlib.util.spec_from_file_location("entry98_analyse", HERE.parent / "entry98" / "analyse.py")
_entry98 = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_entry98)
line = _entry98.line  # one table row: the margin's mean, its t-interval, the units favouring each side
ENTRY, PLACE, BUDGET = (sys.argv[1:4] if len(sys.argv) > 3 else ("entry141", "fleet88w6", "600"))
HERE = HERE.parent / ENTRY
METHOD, PREFIX = "response@designed", "SIM42-"


def losses(registry: str) -> dict[int, dict[str, float]]:
    """{fold: {unit: validation loss}} of the runs on `registry`."""
    out = {}
    for f in sorted(HERE.glob(f"{registry}_seed*/val_loss_units.json")):
        got = json.loads(f.read_text())
        out[got["seed"]] = got["val_loss_units"][METHOD][BUDGET]
    return out


def main() -> None:
    place, variant = losses(PLACE), losses(f"{PLACE}f")
    folds = sorted(set(place) & set(variant))
    per_unit: dict[str, list[float]] = {}
    for k in folds:
        means = [np.mean(list(run[k].values())) for run in (place, variant)]
        print(f"fold {k}: {len(place[k])} units; mean loss, the design in place {means[0]:.5f}, "
              f"the variant {means[1]:.5f}")
        for u, loss in place[k].items():
            per_unit.setdefault(u, []).append(float(np.log(variant[k][u] / loss)))
    units = sorted(per_unit)
    logs = np.array([np.mean(per_unit[u]) for u in units])
    new = np.array([u.startswith(PREFIX) for u in units])
    print("\n| validation units | n | margin of the variant over the design in place (mean) | 95% interval "
          "| favour the variant / the design in place | |\n|---|---|---|---|---|---|")
    print(line(f"added ({PREFIX}*): rule 1", logs[new]))
    print(line("the folds' own", logs[~new]))
    print(line("all", logs))


if __name__ == "__main__":
    main()
