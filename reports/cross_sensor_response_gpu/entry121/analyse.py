"""Research log entry 121's reading: other16's designed plan with today's recipe, `cover_informative` beside
it in the same runs. Rule 1 (each run's `cover_informative` rows and references equal entry 101's run of the
same fold and draw), rule 2 (the designed plan's ratios at 120 s, each unit's draws averaged, with and
without ordinary use) and rule 3 (designed over `cover_informative`, paired per unit). Reads the draws whose
four folds ran. Usage, from the repository root:

    python reports/cross_sensor_response_gpu/entry121/analyse.py
"""

from pathlib import Path
from typing import Any

import numpy as np

from anytip.report.cross_sensor import mean_interval, paired_text, unit_ratios
from anytip.rundir import read_json

HERE = Path(__file__).parent
BEFORE = HERE.parent / "entry101"
KEYS = {"force": "force_rmse_n", "angle": "angle_rmse_rad"}
FOLDS = (0, 1, 2, 3)
SHARED = ("response@cover_informative", "response+use@cover_informative", "per_unit")


def run_dir(root: Path, d: int, k: int) -> Path:
    return root / f"other16_severe_d{d}" / f"other16_seed{k}"


def rows(root: Path, d: int, k: int) -> list[dict[str, Any]]:
    return read_json(run_dir(root, d, k) / "metrics.json")["results"]


def record(root: Path, d: int, k: int) -> dict[str, Any]:
    return read_json(run_dir(root, d, k) / "provenance.json")["cross_sensor"][f"seed{k}"]


def largest_difference(new: list[float], old: list[float]) -> float:
    a, b = np.asarray(new, float), np.asarray(old, float)
    return float(np.max(np.abs(a - b) / np.maximum(np.abs(b), 1e-300))) if len(a) else 0.0


def same_as_before(d: int, k: int) -> None:
    """Rule 1: the shared methods' held-out rows and validation losses against entry 101's run."""
    def held(root: Path) -> list[tuple[Any, ...]]:
        return sorted((r["method"], budget, r["unit"], r["seed"], key, r[key])
                      for r in rows(root, d, k) if r["method"] in SHARED
                      for budget in [r.get("calib_seconds")] for key in KEYS.values())

    def losses(root: Path) -> list[tuple[str, str, str, float]]:
        got = record(root, d, k)["val_loss_units"]
        return sorted((m, b, u, v) for m in SHARED if m in got for b, per in got[m].items() for u, v in per.items())

    new, old = held(HERE), held(BEFORE)
    vnew, vold = losses(HERE), losses(BEFORE)
    same_keys = [r[:5] for r in new] == [r[:5] for r in old] and [r[:3] for r in vnew] == [r[:3] for r in vold]
    if not same_keys:
        print(f"rule 1, draw {d}, fold {k}: the shared rows DIFFER in which rows they hold")
        return
    diff = max(largest_difference([r[5] for r in new], [r[5] for r in old]),
               largest_difference([r[3] for r in vnew], [r[3] for r in vold]))
    verdict = "equal" if diff == 0 else f"largest relative difference {diff:.2g}"
    print(f"rule 1, draw {d}, fold {k}: {len(new)} held-out values and {len(vnew)} validation losses {verdict}")


def figure(draws: list[int], method: str) -> dict[str, dict[str, float]]:
    """Rule 2: per unit, the ratio at 120 s with its draws averaged; prints mean and interval."""
    got = [r for d in draws for k in FOLDS for r in rows(HERE, d, k)]
    per = {}
    for label, key in KEYS.items():
        per[label] = unit_ratios(got, key)[(method, 120.0)]
        m, lo, hi = mean_interval(list(per[label].values()))
        print(f"  {method} {label}: {m:.3f}x [{lo:.2f}, {hi:.2f}] over {len(per[label])} units")
    return per


def main() -> None:
    draws = [d for d in (0, 1, 2) if all((run_dir(HERE, d, k) / "metrics.json").is_file() for k in FOLDS)]
    for d in draws:
        for k in FOLDS:
            same_as_before(d, k)
    print(f"rule 2, draws {draws}, 120 s:")
    per = {m: figure(draws, m) for use in ("response+use", "response")
           for m in (f"{use}@designed", f"{use}@cover_informative")}
    print("rule 3, designed over cover_informative, paired per unit:")
    for use in ("response+use", "response"):
        for label in KEYS:
            d, c = per[f"{use}@designed"][label], per[f"{use}@cover_informative"][label]
            print(f"  {use} {label}: x{paired_text([d[u] / c[u] for u in c])}")
    for d in draws:
        val = {m: np.mean([record(HERE, d, k)["val_loss"][m]["120"] for k in FOLDS])
               for m in ("response@designed", "response@cover_informative", "response+use@designed",
                         "response+use@cover_informative")}
        print(f"validation, draw {d}: " + ", ".join(f"{m} {v:.5f}" for m, v in val.items()))


if __name__ == "__main__":
    main()
