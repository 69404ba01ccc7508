"""Research log entry 120: severity 2's response model at a code of 32 per barometer, read as pre-registered.

The rescoring `entry120/severity2_extra2_code32` against entry 118's `severity2_extra2` (code 16, the run's
own model): the gate (its references scored again), per budget and method the force and angle ratio over
the 6 held-out units, the paired per-unit force ratio (geometric mean [95% bootstrap interval over units])
and the intervals.

    python reports/cross_sensor_response_gpu/entry120/analyse.py
"""

from __future__ import annotations

import runpy
from pathlib import Path

G = Path("reports/cross_sensor_response_gpu")
E118 = runpy.run_path(str(G / "entry118/analyse.py"))  # rows_of, gate, line_of, bootstrap_gmean, intervals


def main() -> None:
    wide, control = G / "entry120/severity2_extra2_code32", G / "entry118/severity2_extra2"
    new, old = E118["rows_of"](wide), E118["rows_of"](control)
    print(f"gate: {E118['gate'](new, old, True)}")
    for budget in (120.0, 600.0):
        for method in E118["METHODS"]:
            got = [r for r in new if r["method"] == method and r["budget_s"] == budget]
            g, lo, hi = E118["paired_force"](new, old, method, budget)
            print(f"{budget:g} s {method}\n   code 32: {E118['line_of'](new, method, budget)}; "
                  f"intervals {E118['intervals'](got)}\n   code 16: {E118['line_of'](old, method, budget)}\n"
                  f"   paired, force: x{g:.3f} [{lo:.3f}, {hi:.3f}]")


if __name__ == "__main__":
    main()
