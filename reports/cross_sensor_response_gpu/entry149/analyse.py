"""Research log entry 149: the designed plan's intervals at 600 s on fleet88's 88 held-out units, tested on
both sessions (entry 147's reading at 600 s). Prints rule 1 (each held-out unit's plan against entry 146's at
600 s), rule 2 (the target per method with its verdict, and the ceiling of one factor per output chosen on the
held-out units, beside entry 147's at 120 s) and the figures rule 3 asks for. From the repository root:

    python reports/cross_sensor_response_gpu/entry149/analyse.py
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np

G = Path("reports/cross_sensor_response_gpu")
RUNS = [G / f"entry149/at600/fleet88_seed{k}" for k in (0, 1)]
PLANS_146 = [G / f"entry146/at600/fleet88_seed{k}" for k in (0, 1)]
AT_120 = [G / f"entry147/at120/fleet88_seed{k}" for k in (0, 1)]
METHODS = ("response@designed", "response+use@designed")
ANALYSE_106 = runpy.run_path(str(G / "entry106/analyse.py"))  # rows_by_unit, same
ANALYSE_108 = runpy.run_path(str(G / "entry108/analyse.py"))  # intervals, OUTPUTS
ANALYSE_110 = runpy.run_path(str(G / "entry110/analyse.py"))  # met
ANALYSE_147 = runpy.run_path(str(G / "entry147/analyse.py"))  # ceiling, factors
rows_by_unit, same, OUTPUTS = ANALYSE_106["rows_by_unit"], ANALYSE_106["same"], ANALYSE_108["OUTPUTS"]
ceiling = ANALYSE_147["ceiling"]


def spread(runs: list[Path], method: str) -> np.ndarray:
    """(D,) the spread over the held-out units of log(needed80 / own)."""
    rows = rows_by_unit(runs, method)
    return np.array([[np.log(r[f"{o}_needed80_halfwidth"] / r[f"{o}_halfwidth"]) for o in OUTPUTS]
                     for r in rows.values()]).std(axis=0, ddof=1)


def main() -> None:
    print("rule 1:\n" + "\n".join(
        f"  {m} plans (seconds, presses) against entry 146 at 600 s: "
        f"{same(rows_by_unit(RUNS, m), rows_by_unit(PLANS_146, m), ['calib_seconds', 'presses'])}"
        for m in METHODS))
    print("\nrule 2, the target on both sessions' rows (440 unit-outputs a method):")
    for m in METHODS:
        print(f"{ANALYSE_108['intervals'](RUNS, m)}\n    verdict: "
              f"{'met' if ANALYSE_110['met'](rows_by_unit(RUNS, m)) else 'missed'}")
        print(f"    one factor per output chosen on the held-out units: {ceiling(RUNS, m)} "
              f"(at 120 s, entry 147: {ceiling(AT_120, m)})")
    print("\nrule 3: each fold's factor and margin")
    for seed, run in enumerate(RUNS):
        print(ANALYSE_147["factors"](run, seed, budget="600"))
    print("the spread over the held-out units of log(needed80 / own), 600 s / 120 s:")
    for m in METHODS:
        print(f"  {m}: " + ", ".join(f"{o} {a:.3f} / {b:.3f}" for o, a, b in
                                      zip(OUTPUTS, spread(RUNS, m), spread(AT_120, m), strict=True)))


if __name__ == "__main__":
    main()
