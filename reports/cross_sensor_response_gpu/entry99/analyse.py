"""Research log entry 99's reading: entry 97's rescorings again with the codes fitted to convergence, each
paired with entry 97's run of the same fold and draw (the control). Per registry: the validation units'
mean loss per plan (rule 1), each validation unit's loss paired against the control (a unit's draws
averaged first), and the held-out units' ratios against their references with the per-unit factor
against the control. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry99/analyse.py
"""

from pathlib import Path
from typing import Any

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
CONTROL = HERE.parent / "entry97"
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}
PLANS = ("cover", "cover_informative")
REGISTRIES = {  # name: (runs as (arm directory, fold), methods, the plan its recipe uses)
    "other16": ([(f"other16_severe_d{d}", k) for d in (0, 1, 2) for k in range(4)],
                [f"{m}@{p}" for m in ("response", "response+use") for p in PLANS], "cover_informative"),
    "fleet88": ([("fleet88_cpu", k) for k in (0, 1)], [f"response@{p}" for p in PLANS], "cover"),
}


def run_dir(root: Path, arm: str, k: int) -> Path:
    return root / arm / f"{arm.split('_')[0]}_seed{k}"


def record(root: Path, arm: str, k: int) -> dict[str, Any]:
    return read_json(run_dir(root, arm, k) / "provenance.json")["cross_sensor"][f"seed{k}"]


def rows(root: Path, runs: list[tuple[str, int]]) -> list[dict[str, Any]]:
    """Every result row of the runs under root (entry 97's or this entry's)."""
    return [r for a, k in runs for r in read_json(run_dir(root, a, k) / "metrics.json")["results"]]


def validation(runs: list[tuple[str, int]], method: str) -> None:
    """The validation units' mean loss, new and control, and the per-unit ratio (draws averaged first)."""
    means, logs = [], {}
    for root in (HERE, CONTROL):
        got = [record(root, a, k)["val_loss"][method]["120"] for a, k in runs]
        means.append(np.mean(got))
    for a, k in runs:
        new = record(HERE, a, k)["val_loss_units"][method]["120"]
        old = record(CONTROL, a, k)["val_loss_units"][method]["120"]
        for u in new:
            logs.setdefault(u, []).append(np.log(new[u] / old[u]))
    per = [float(np.exp(np.mean(v))) for v in logs.values()]
    change = 100 * (means[0] / means[1] - 1)
    print(f"  {method}: validation mean {means[0]:.5f} against {means[1]:.5f} ({change:+.2f}%);"
          f" per unit x{paired_text(per)} over {len(per)} units, {sum(r < 1 for r in per)} lower")


def held_out(runs: list[tuple[str, int]], method: str) -> None:
    """Each held-out unit's ratio to its reference (draws averaged), new and control, and their factor."""
    both = [rows(root, runs) for root in (HERE, CONTROL)]
    for label, key in KEYS.items():
        per = [unit_ratios(got, key)[(method, 120.0)] for got in both]
        (m, lo, hi), (c, clo, chi) = (mean_interval(list(p.values())) for p in per)
        factor = paired_text([per[0][u] / per[1][u] for u in per[1]])
        print(f"  held out {label}: {m:.3f}x [{lo:.2f}, {hi:.2f}] against {c:.3f}x [{clo:.2f}, {chi:.2f}]; "
              f"per unit x{factor} over {len(per[1])} units")


def main() -> None:
    for name, (runs, methods, plan) in REGISTRIES.items():
        runs = [(a, k) for a, k in runs if (run_dir(HERE, a, k) / "metrics.json").is_file()]
        if not runs:
            continue
        print(f"{name} ({len(runs)} runs; the recipe's plan: {plan})")
        for method in methods:
            validation(runs, method)
            held_out(runs, method)


if __name__ == "__main__":
    main()
