"""Exploratory, after entry 108 (decides nothing): does a unit's own check, the RMS of its plan's pressures
about its fitted response (`response_residual_pa`, entry 101's fleet88 CPU rows: the same plans and codes as
entry 106's), say how much wider than its plan's own half-width its test rows needed the interval? Spearman
and Pearson correlation over the 88 held-out units of log(residual) against log(needed80 / own), per output
and method (entry 106's rows). From the repository root:

    python reports/cross_sensor_response_gpu/entry110/residual_width.py
"""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np
from scipy.stats import pearsonr, spearmanr

G = Path("reports/cross_sensor_response_gpu")
ANALYSE_106 = runpy.run_path(str(G / "entry106/analyse.py"))
rows_by_unit, METHODS, OUTPUTS = ANALYSE_106["rows_by_unit"], ANALYSE_106["METHODS"], ANALYSE_106["OUTPUTS"]
CHECKS = [G / f"entry101/fleet88_cpu/fleet88_seed{k}" for k in (0, 1)]


def main() -> None:
    residual = {u: r["response_residual_pa"] for u, r in rows_by_unit(CHECKS, METHODS[0]).items()}
    units = sorted(residual)
    x = np.log([residual[u] for u in units])
    print(f"{len(units)} held-out units; response_residual_pa {min(residual.values()):.0f}-"
          f"{max(residual.values()):.0f} Pa")
    for method in METHODS:
        rows = rows_by_unit(ANALYSE_106["RUNS"], method)
        cells = []
        for o in OUTPUTS:
            y = np.log([rows[u][f"{o}_needed80_halfwidth"] / rows[u][f"{o}_halfwidth"] for u in units])
            cells.append(f"{o} {spearmanr(x, y)[0]:+.2f} / {pearsonr(x, y)[0]:+.2f}")
        print(f"  {method}, Spearman / Pearson: " + ", ".join(cells))


if __name__ == "__main__":
    main()
