"""Research log entry 180's reading: the `--use-log` networks (build/entry178/L, `run.sh`) scored on the
units' full runs as entry 178's arms are, against entry 178's A and B and entry 179's C2, per unit, geometric
means with 95% t-intervals over units.

    python reports/cross_sensor_response_gpu/entry180/score.py > \\
        reports/cross_sensor_response_gpu/entry180/logs/score.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np

from anytip.data.registry import Registry

HERE = Path(__file__).parent
E178 = runpy.run_path(str(HERE.parent / "entry178" / "score.py"))
UNITS, OUTPUTS, t_interval = E178["UNITS"], E178["OUTPUTS"], E178["t_interval"]


def main() -> None:
    registry = Registry("data/fleet88g")
    rmse = {(arm, u): E178["scored"](registry, u, arm) for arm in ("A", "B", "C2", "L") for u in UNITS}
    print("per unit, 16 units (geometric mean [95% t-interval] over units)")
    print("| ratio | force | angle |")
    print("|---|---|---|")
    for bottom in ("A", "B", "C2"):
        cells = []
        for k in OUTPUTS:
            logs = np.log([rmse["L", u][k] / rmse[bottom, u][k] for u in UNITS])
            m, lo, hi = np.exp(t_interval(logs))
            cells.append(f"x{m:.3f} [{lo:.3f}, {hi:.3f}]")
        print(f"| L over {bottom} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
