"""Research log entry 179's reading: the trimmed detector's networks (build/entry178/C2, `run.sh`) scored on
the units' full runs as entry 178's arms are (its `scored`), against entry 178's A, B and C, per unit,
geometric means with 95% t-intervals over units.

    python reports/cross_sensor_response_gpu/entry179/score.py > \\
        reports/cross_sensor_response_gpu/entry179/logs/score.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

from anytip.data.registry import Registry

HERE = Path(__file__).parent
E178 = runpy.run_path(str(HERE.parent / "entry178" / "score.py"))
UNITS = E178["UNITS"]


def table(top: str, bottoms: tuple[str, ...]) -> None:
    """Arm `top` over each of `bottoms` (build/entry178/ARM), per unit, force and angle: a markdown table."""
    registry = Registry("data/fleet88g")
    rmse = {(arm, u): E178["scored"](registry, u, arm) for arm in (*bottoms, top) for u in UNITS}
    print("per unit, 16 units (geometric mean [95% t-interval] over units)")
    E178["ratio_table"](rmse, tuple((top, bottom) for bottom in bottoms))


def main() -> None:
    table("C2", ("A", "B", "C"))


if __name__ == "__main__":
    main()
