"""Research log entry 199, read after its rule: the ceiling of any one factor per output on the shipped path's
widths (`uncertainty.fleet_margin.factor_ceiling`, chosen on the units it scores: a diagnostic), per set of
entry 198's units: the best share in [0.85, 0.95], and the best where none falls below 0.80.

    python reports/cross_sensor_response_gpu/entry199/ceiling.py > \\
        reports/cross_sensor_response_gpu/entry199/logs/ceiling.log
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np

from anytip.data.registry import Registry
from anytip.uncertainty.conformal import needed_halfwidths
from anytip.uncertainty.fleet_margin import factor_ceiling

HERE = Path(__file__).parent
E198 = runpy.run_path(str(HERE.parent / "entry198" / "analyse.py"))
EDGES = (0.80, 0.85, 0.95)  # the floor and the band's edges


def widths(calibration: Path, registry: Registry) -> tuple[np.ndarray, np.ndarray]:
    """The calibration's own half-widths (D,) and those at which its unit's full runs are covered at the
    floor and the band's edges (3, D)."""
    read = E198["on_full_runs"](calibration, registry)
    return read.own, needed_halfwidths(read.pred - read.target, EDGES)


def main() -> None:
    for name, pattern, root, role in E198["SETS"]:
        registry = Registry(root)
        got = [widths(c, registry) for c in sorted(p for p in Path().glob(pattern) if p.is_dir())]
        own, need = np.array([g[0] for g in got]), np.array([g[1] for g in got])
        c = factor_ceiling(own, need[:, 0], need[:, 1], need[:, 2])
        print(f"{name} [{role}]: best {100 * c.free_in_band:.1f}% in band; "
              f"{100 * c.safe_in_band:.1f}% where none falls below {EDGES[0]}")


if __name__ == "__main__":
    main()
