"""Research log entry 178's reading: each calibration's network (build/entry178/ARM/UNIT, `run.sh`) scored on
the unit's three full runs in data/fleet88g (never read by the calibrations); rule 1, the plan alone's
networks equal in both registries (logs/run.log's hashes); rule 2, B over A, C over A and C over B per unit,
force and angle RMSE, geometric means with 95% t-intervals over units.

    python reports/cross_sensor_response_gpu/entry178/score.py > \
        reports/cross_sensor_response_gpu/entry178/logs/score.log
"""

from __future__ import annotations

import json
import runpy
from pathlib import Path

import numpy as np
import torch

from anytip.data.arrays import load_arrays
from anytip.data.registry import Registry
from anytip.models.io import load_models
from anytip.train.metrics import predict, scores

HERE = Path(__file__).parent
t_interval = runpy.run_path(str(HERE.parent / "entry162" / "analyse.py"))["t_interval"]
UNITS = runpy.run_path(str(HERE / "make_registries.py"))["UNITS"]
OUTPUTS = ("force_rmse_n", "angle_rmse_rad")


def scored(registry: Registry, unit: str, arm: str, root: Path = Path("build/entry178")) -> dict[str, float]:
    """The arm's network for `unit` (under `root`) on the unit's full runs: {force_rmse_n, angle_rmse_rad}."""
    arrays = load_arrays(registry, [r for r in registry.list_runs(unit=unit) if r.protocol == "full"])
    net = load_models(root / arm / unit / "model.safetensors")
    X = torch.from_numpy(arrays.pressure)[None]
    pred = predict(net.model, net.in_scaler, net.out_scaler, X)[0].numpy()
    got = scores(pred, arrays.targets, arrays.layout)
    return {k: float(got[k]) for k in OUTPUTS}


def ratio_table(rmse: dict[tuple[str, str], dict[str, float]], pairs: tuple[tuple[str, str], ...]) -> None:
    """Per (top, bottom) arm pair, top over bottom per unit, force and angle, the geometric mean with its 95%
    t-interval over UNITS: a markdown table (entries 178-180)."""
    print("| ratio | force | angle |")
    print("|---|---|---|")
    for top, bottom in pairs:
        cells = []
        for k in OUTPUTS:
            logs = np.log([rmse[top, u][k] / rmse[bottom, u][k] for u in UNITS])
            m, lo, hi = np.exp(t_interval(logs))
            cells.append(f"x{m:.3f} [{lo:.3f}, {hi:.3f}]")
        print(f"| {top} over {bottom} | " + " | ".join(cells) + " |")


def main() -> None:
    hashes = {}
    for line in (HERE / "logs" / "run.log").read_text().splitlines():
        arm, unit, digest = line.split()
        hashes[arm, unit] = digest
    equal = sum(hashes["A", u] == hashes["A2", u] for u in UNITS)
    print(f"rule 1: {equal} of {len(UNITS)} units' plan-alone networks equal in both registries")
    registry = Registry("data/fleet88g")
    rmse = {(arm, u): scored(registry, u, arm) for arm in ("A", "B", "C") for u in UNITS}
    print("\n| unit | " + " | ".join(f"{a} force / angle" for a in "ABC") + " |")
    print("|---|---|---|---|")
    for u in UNITS:
        cells = [f"{rmse[a, u][OUTPUTS[0]]:.3f} / {rmse[a, u][OUTPUTS[1]]:.4f}" for a in "ABC"]
        print(f"| {u} | " + " | ".join(cells) + " |")
    print("\nrule 2, per unit (geometric mean [95% t-interval] over units)")
    ratio_table(rmse, (("B", "A"), ("C", "A"), ("C", "B")))
    print("\n" + json.dumps({f"{a} {u}": rmse[a, u] for a in "ABC" for u in UNITS}))


if __name__ == "__main__":
    main()
