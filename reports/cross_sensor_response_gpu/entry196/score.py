"""Research log entry 196's accuracy reading: rule 1 (N and entry 191's H read the same rows), then
log(N / H) per fresh validation unit, force and angle, over all 64 and per elastomer (entry 191's functions),
each network scored on its unit's three full runs; the calibrations' `wall_s` beside (two at a time, deciding
nothing).

    python reports/cross_sensor_response_gpu/entry196/score.py > \\
        reports/cross_sensor_response_gpu/entry196/logs/score.log
"""

from __future__ import annotations

import json
import runpy
from pathlib import Path

import numpy as np

E191 = runpy.run_path(str(Path(__file__).parent.parent / "entry191" / "score.py"))
ROOTS = {"H": Path("build/entry191"), "N": Path("build/entry196")}


def wall_s(arm: str) -> np.ndarray:
    """Each of the arm's calibrations' recorded fit-and-fold seconds."""
    return np.array([json.loads((ROOTS[arm] / f"{arm}-{f}" / u / "calibration.json").read_text())["wall_s"]
                     for f, u in E191["PAIRS"]])


if __name__ == "__main__":
    print(E191["same_rows"](ROOTS))
    print("\nrule 2, N (numpy step) over H (entry 191, torch step), per fresh validation unit")
    E191["ratio_table"](E191["scored"](ROOTS), "N", "H", dump=False)
    old, new = wall_s("H"), wall_s("N")
    ratio = np.exp(np.mean(np.log(new / old)))
    print(f"\nbeside, wall_s two at a time: H {np.median(old):.2f} s ({old.min():.2f}-{old.max():.2f}), "
          f"N {np.median(new):.2f} s ({new.min():.2f}-{new.max():.2f}); N / H paired x{ratio:.3f}")
