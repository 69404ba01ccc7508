"""Research log entry 119: the oracle codes' ceiling at severity 0.5, 1 and 2, read as pre-registered.

Per run in entry119/ (`rescore.sh NAME`): the plan alone's force and angle ratio over the 6 held-out
units with codes fitted on each unit's whole calibration, beside entry 118's same rows with the plan's
codes, and the paired per-unit force ratio of the two (geometric mean [95% bootstrap interval over
units]).

    python reports/cross_sensor_response_gpu/entry119/analyse.py
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np

G = Path("reports/cross_sensor_response_gpu")
E118 = runpy.run_path(str(G / "entry118/analyse.py"))  # rows_of, line_of, bootstrap_gmean
METHOD = "response@cover_informative"


def main() -> None:
    for name in ("severity0.5", "fleet24_seed1", "severity2"):
        out = G / "entry119" / name
        if not (out / "metrics.json").is_file():
            print(f"{name}: not run")
            continue
        oracle, plan = E118["rows_of"](out), E118["rows_of"](G / "entry118" / name)
        g, lo, hi = E118["paired_force"](oracle, plan, METHOD, 120.0)
        print(f"== {name}, 120 s, the plan alone\n   oracle codes: {E118['line_of'](oracle, METHOD, 120.0)}\n"
              f"   the plan's codes (entry 118): {E118['line_of'](plan, METHOD, 120.0)}\n"
              f"   paired, force: x{g:.3f} [{lo:.3f}, {hi:.3f}] (log {np.log(g):+.3f})")


if __name__ == "__main__":
    main()
