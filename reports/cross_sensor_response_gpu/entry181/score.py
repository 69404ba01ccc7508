"""Research log entry 181's reading: arms A and L (build/entry181, `run.sh`) scored on each unit's three full
runs of data/other16, force and angle RMSE; L over A per unit, geometric mean with a 95% t-interval.

    python reports/cross_sensor_response_gpu/entry181/score.py > \\
        reports/cross_sensor_response_gpu/entry181/logs/score.log
"""

from __future__ import annotations

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
UNITS = [f"SIM23-{i:03d}" for i in range(16)]
OUTPUTS = ("force_rmse_n", "angle_rmse_rad")


def scored(registry: Registry, unit: str, arm: str) -> dict[str, float]:
    """The arm's network for `unit` on the unit's full runs: {force_rmse_n, angle_rmse_rad}."""
    arrays = load_arrays(registry, [r for r in registry.list_runs(unit=unit) if r.protocol == "full"])
    net = load_models(Path("build/entry181") / arm / unit / "model.safetensors")
    pred = predict(net.model, net.in_scaler, net.out_scaler, torch.from_numpy(arrays.pressure)[None])[0]
    got = scores(pred.numpy(), arrays.targets, arrays.layout)
    return {k: float(got[k]) for k in OUTPUTS}


def main() -> None:
    registry = Registry("data/other16")
    arms = ("A", "L", "B") if (Path("build/entry181") / "B").is_dir() else ("A", "L")
    rmse = {(arm, u): scored(registry, u, arm) for arm in arms for u in UNITS}
    print("| unit | A force / angle | L force / angle |")
    print("|---|---|---|")
    for u in UNITS:
        print(f"| {u} | " + " | ".join(f"{rmse[a, u][OUTPUTS[0]]:.3f} / {rmse[a, u][OUTPUTS[1]]:.4f}"
                                       for a in "AL") + " |")
    pairs = [("L", "A")] + ([("B", "A"), ("L", "B")] if "B" in arms else [])
    for top, bottom in pairs:  # B (flag_arm.py, after the entry's rule) where it was run
        cells = []
        for k in OUTPUTS:
            m, lo, hi = np.exp(t_interval(np.log([rmse[top, u][k] / rmse[bottom, u][k] for u in UNITS])))
            cells.append(f"x{m:.3f} [{lo:.3f}, {hi:.3f}]")
        print(f"\n{top} over {bottom}, per unit (16 units): force {cells[0]}, angle {cells[1]}")


if __name__ == "__main__":
    main()
