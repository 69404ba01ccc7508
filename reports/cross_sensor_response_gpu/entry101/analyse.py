"""Research log entry 101: the table of `residual_probe.py`'s runs (the validation units of other16's
four folds and fleet88's two). Per unit, the test rows' RMS residual about its response with its plan's
codes, with those codes and the plan's residuals regressed on the contact (the one grid point whose
geometric mean ratio over every unit of both registries is lowest, as the rescoring takes it, and each
unit's own best, which chooses on the test rows: a diagnostic bound), and with its codes fitted on its
whole calibration (entry 87's oracle); then each grid point's geometric mean ratio per registry. Usage,
from the repository root:

    python reports/cross_sensor_response_gpu/entry101/analyse.py
"""

import json
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).parent
RUNS = {"other16": range(4), "fleet88": range(2)}


def units_of(name: str) -> dict[str, dict[str, Any]]:
    """unit (fold) -> its probe record, over the registry's folds."""
    units = {}
    for k in RUNS[name]:
        got = json.loads((HERE / f"{name}_seed{k}.json").read_text())
        units |= {f"{u} (fold {k})": r for u, r in got["units"].items()}
    return units


def geo(units: dict[str, dict[str, Any]], value) -> float:
    """The geometric mean over units of value(record) over the record's test RMS."""
    return float(np.exp(np.mean([np.log(value(r) / r["test_rms"]) for r in units.values()])))


def main() -> None:
    by_registry = {name: units_of(name) for name in RUNS}
    every = {f"{name} {u}": r for name, units in by_registry.items() for u, r in units.items()}
    grid = list(next(iter(every.values()))["corrected"])
    fixed = min(grid, key=lambda g: geo(every, lambda r: r["corrected"][g]))
    print(f"grid point (length/ratio) lowest over all {len(every)} units: {fixed}")
    print("| registry, unit | plan codes [Pa] | + correction, that point | + correction, own best "
          "| oracle codes |")
    print("|---|---|---|---|---|")
    for u, r in every.items():
        t, best = r["test_rms"], min(r["corrected"].values())
        print(f"| {u} | {t:.0f} | x{r['corrected'][fixed] / t:.3f} | x{best / t:.3f} | "
              f"x{r['oracle_test_rms'] / t:.3f} |")
    for name, units in {**by_registry, "both": every}.items():
        print(f"{name}: that point x{geo(units, lambda r: r['corrected'][fixed]):.3f}, own best "
              f"x{geo(units, lambda r: min(r['corrected'].values())):.3f}, oracle codes "
              f"x{geo(units, lambda r: r['oracle_test_rms']):.3f}")
    lengths = sorted({float(g.split("/")[0]) for g in grid})
    ratios = sorted({float(g.split("/")[1]) for g in grid})
    for name, units in {**by_registry, "both": every}.items():
        print(f"\n{name}, geometric mean ratio per grid point (rows: length; columns: ratio {ratios})")
        for length in lengths:
            cells = [geo(units, lambda r, g=f"{length:g}/{q:g}": r["corrected"][g]) for q in ratios]
            print(f"  {length:g}: " + " ".join(f"{c:.3f}" for c in cells))


if __name__ == "__main__":
    main()
