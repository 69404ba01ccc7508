"""Research log entry 183's reading: rule 1, the gate (A and L's hashes in logs/run.log against entry
181's); each network of build/entry183/ARM/UNIT (`run.sh`) scored on the unit's three full runs of
data/other16 as entry 181 scored them; rule 2, per unit, geometric means with 95% t-intervals over the 16
units, and the contrast (Ld / Ad) / (L / A).

    python reports/cross_sensor_response_gpu/entry183/score.py > \\
        reports/cross_sensor_response_gpu/entry183/logs/score.log
"""

from __future__ import annotations

import json
import runpy
from pathlib import Path

import numpy as np

from anytip.data.registry import Registry

HERE = Path(__file__).parent
E178 = runpy.run_path(str(HERE.parent / "entry178" / "score.py"))
E181 = runpy.run_path(str(HERE.parent / "entry181" / "score.py"))
hashes = runpy.run_path(str(HERE.parent / "entry182" / "score.py"))["hashes"]
UNITS, OUTPUTS, ARMS = E181["UNITS"], E181["OUTPUTS"], ("A", "L", "Ad", "Ld")


def interval(logs: list[float]) -> str:
    """The geometric mean of exp(logs) with its 95% t-interval, as the tables print it."""
    m, lo, hi = np.exp(E181["t_interval"](np.array(logs)))
    return f"x{m:.3f} [{lo:.3f}, {hi:.3f}]"


def main() -> None:
    ours, before = hashes(HERE / "logs" / "run.log"), hashes(HERE.parent / "entry181" / "logs" / "run.log")
    for arm in ("A", "L"):
        equal = sum(ours[arm, u] == before[arm, u] for u in UNITS)
        print(f"rule 1: {arm}: {equal} of {len(UNITS)} networks equal entry 181's byte for byte")
    registry = Registry("data/other16")
    rmse = {(a, u): E178["scored"](registry, u, a, Path("build/entry183")) for a in ARMS for u in UNITS}
    print("\nrule 2, per unit (geometric mean [95% t-interval] over units)")
    print("| ratio | force | angle |")
    print("|---|---|---|")
    for top, bottom in (("Ld", "Ad"), ("Ad", "A"), ("Ld", "A"), ("L", "A")):
        cells = [interval([np.log(rmse[top, u][k] / rmse[bottom, u][k]) for u in UNITS]) for k in OUTPUTS]
        print(f"| {top} over {bottom} | " + " | ".join(cells) + " |")
    cells = [interval([np.log(rmse["Ld", u][k] / rmse["Ad", u][k] * rmse["A", u][k] / rmse["L", u][k])
                       for u in UNITS]) for k in OUTPUTS]
    print("| (Ld / Ad) / (L / A) | " + " | ".join(cells) + " |")
    print("\n" + json.dumps({f"{a} {u}": rmse[a, u] for a in ARMS for u in UNITS}))


if __name__ == "__main__":
    main()
