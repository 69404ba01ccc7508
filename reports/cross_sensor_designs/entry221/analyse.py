"""Research log entry 221: the label-free search over every source row (arm A) against entry 219's four draws.

    python reports/cross_sensor_designs/entry221/analyse.py

Reads `entry221/all_seedK` and `entry219/drawD_seedK` (K, D = 0-3) with entry 220's readers, and prints the
gate, the decision on the validation units and the held-out reading, as the entry wrote them down.
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
_spec = importlib.util.spec_from_file_location("entry220", HERE.parent / "entry220" / "analyse.py")
assert _spec is not None and _spec.loader is not None
e220 = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(e220)
DRAWN, FOLDS, DRAWS = e220.DRAWN, e220.FOLDS, e220.DRAWS


def wall_s(run: Path) -> float:
    """A run's recorded wall time, s."""
    return float(json.loads((run / "provenance.json").read_text())["wall_s"])


def main() -> None:
    refs_equal, logged, val, test, lower, times = 0, 0, {}, {}, 0, []
    for k in FOLDS:
        run = HERE / f"all_seed{k}"
        obj = e220.objectives(HERE / "logs" / f"all_seed{k}.log")
        drawn_obj = [e220.objectives(DRAWN / "logs" / f"draw{d}_seed{k}.log") for d in DRAWS]
        logged += len(obj) == 8
        lower += sum(obj[u][0] < min(drawn_obj[d][u][0] for d in DRAWS) for u in obj)
        refs_equal += e220.rows(run, "per_unit") == e220.read_arm(run, k, val, test)
        times.append((wall_s(run), np.mean([wall_s(DRAWN / f"draw{d}_seed{k}") for d in DRAWS])))
    print("Rule 1 (gate):")
    print(f"  references equal the fold run's in {refs_equal} of {len(FOLDS)} runs; "
          f"8 objectives logged in {logged} of {len(FOLDS)}")
    e220.decide(val, "every row", "every source row a candidate")
    e220.held_out(test, "every row")
    print(f"  final objective below every draw's on {lower} of {len(val) + len(test)} units")
    print("  wall time per run, s (every row / the draws' mean): "
          + ", ".join(f"{a:.0f} / {b:.0f}" for a, b in times))


if __name__ == "__main__":
    main()
